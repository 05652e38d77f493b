"""A rocking, contact or cylinder scene's result columns are known only once a run has made
them: an analysis naming a misspelt one ran every task and then wrote a NaN table with a note.
Now the first successful row checks the analyses' columns: the study stops after one run with
a SceneError naming the field (status 2 on the command line), its row kept, and the study
resumes from it once the name is fixed; a table read back is checked before any run."""

from __future__ import annotations

from pathlib import Path

import pytest

from nsdyn.models.scenefile import SceneError
from nsdyn.studies.execute import run_study
from nsdyn.studies.study import load_study

SCENE = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "rocking-seed003-column.toml"
STUDY = f"""[study]
name = "rk"
batch = 1
scene = "{SCENE}"

[base.motion]
t_end = 0.5

[parameters]
"motion.a_p_g" = [0.6, 0.8, 1.0]

[analysis.percentiles]
quantities = ["QUANTITY"]
"""


def _study(tmp_path, quantity: str):
    path = tmp_path / "s.toml"
    path.write_text(STUDY.replace("QUANTITY", quantity))
    return load_study(path)


def test_a_misspelt_result_column_stops_the_study_after_its_first_run(tmp_path):
    out = tmp_path / "o"
    with pytest.raises(SceneError, match=r"analysis.percentiles.quantities: unknown column "
                       r"'max_theta_radd'; did you mean 'max_theta_rad'\? \(the columns of a "
                       r"rocking scene's first run"):  # fmt: skip
        run_study(_study(tmp_path, "max_theta_radd"), out, workers=1)
    # one process, batches of one: the first row arrived alone and stopped the rest
    run = run_study(_study(tmp_path, "max_theta_rad"), out, workers=1)
    assert run.n_skipped == 1 and run.n_run == 2 and run.n_failed == 0
    with pytest.raises(SceneError, match="'max_theta_radd'"):  # every row there: no run
        run_study(_study(tmp_path, "max_theta_radd"), out, workers=1)


def test_a_name_far_from_the_first_rows_columns_runs_on(tmp_path):
    # a rigid rung's summary lacks the corner drifts a flexible rung's has: a name the first
    # row lacks may be another task's column, and only a typo's distance stops the study
    run = run_study(_study(tmp_path, "peak_tilt_of_the_roof"), tmp_path / "o", workers=1)
    assert run.n_run == 3 and run.n_failed == 0


@pytest.mark.parametrize(("edp", "refused"), [("max_theta_rad", True), ("overturned", False)])
def test_a_fragility_of_a_number_without_limits_stops_after_the_first_run(tmp_path, edp, refused):
    # without limits the EDP must be a true/false outcome: a number ran every task and then
    # said so in the analysis alone (status 0)
    path = tmp_path / "s.toml"
    path.write_text(
        STUDY.replace(
            '[analysis.percentiles]\nquantities = ["QUANTITY"]',
            f'[analysis.fragility]\nim = "motion.a_p_g"\nedp = "{edp}"',
        )
    )
    study = load_study(path)
    if refused:
        with pytest.raises(SceneError, match=rf"analysis.fragility.limits: missing, and '{edp}' "
                           r"is a number, not a true/false outcome"):  # fmt: skip
            run_study(study, tmp_path / "o", workers=1)
    else:
        assert run_study(study, tmp_path / "o", workers=1).n_run == 3


def test_an_isolated_frames_fragility_of_a_number_without_limits_is_refused_at_load(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text('[study]\nname = "f"\n[base.scene]\nfidelity = "rigid"\n[parameters]\n'
                    '"motion.pga" = [1.0, 2.0]\n[analysis.fragility]\nim = "motion.pga"\n'
                    'edp = "idr_max"\n')  # fmt: skip
    with pytest.raises(SceneError, match=r"analysis.fragility.limits: missing, and 'idr_max'"):
        load_study(path)
