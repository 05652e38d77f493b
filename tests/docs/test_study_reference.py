"""The study-file reference against the study reader: the page names exactly the tables, keys
and parameter forms the reader checks files against (its own lists in nsdyn.studies.study and
nsdyn.studies.analyses), and a key the page does not list is refused by the reader."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from nsdyn.models.scenefile import SceneError
from nsdyn.studies import analyses, study

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "docs" / "gen"))
import study_reference as ref  # noqa: E402


def test_the_page_lists_the_readers_keys():
    assert set(ref.STUDY) == set(study.STUDY_FIELDS)
    assert set(ref.RECORDS) == set(study.RECORD_FIELDS)
    assert set(ref.SIMULATED) == set(study.SIMULATED_FIELDS)
    assert set(ref.PAIRS) == set(study.PAIR_FIELDS)
    assert {k: set(v) for k, v in ref.ANALYSES.items()} == {
        k: set(v) for k, v in analyses.FIELDS.items()
    }
    page = ref.page()
    for form in (*study.GRID_FORMS, *study.RANDOM_FORMS, *study.GENERATORS):
        assert f"`{form}" in page or f"{{ {form} =" in page, form
    for table in study.STUDY_TABLES:
        assert f"## `[{table}" in page, table


@pytest.mark.parametrize(
    "text, says",
    [
        ('[study]\nnmae = "x"\n', "study.nmae: unknown field; did you mean 'name'?"),
        ('[records]\nsimulated = { n = 2, seed = 1, lenght = 5.0 }\n',
         "records.simulated.lenght: unknown field"),
        ("[analysis.design]\nobjective = []\n", "analysis.design.objective: unknown field"),
    ],
)  # fmt: skip
def test_a_key_the_page_does_not_list_is_refused(tmp_path, text, says):
    path = tmp_path / "s.toml"
    path.write_text(text)
    with pytest.raises(SceneError, match=says.replace("[", r"\[").replace("?", r"\?")):
        study.load_study(path)
