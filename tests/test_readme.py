"""The README as the front door: short, the two commands CI runs verbatim, a figure that a
README command draws, and links that lead somewhere. (Its library example runs in
``tests/test_examples.py``.)

Sources: ``.ci/run`` (the commands it greps for and runs), the example scripts (which figure
each one writes) and the repository's files (where each link points).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
CI = (ROOT / ".ci" / "run").read_text(encoding="utf-8")


def _ci_var(name: str) -> str:
    return re.search(rf"^{name}='(.*)'$", CI, re.M).group(1)


def test_the_readme_is_a_front_door_of_at_most_250_lines():
    assert README.count("\n") <= 250


def test_the_first_two_code_blocks_are_the_commands_ci_runs():
    # .ci/run greps the test command verbatim and runs the first `pip install . && nsdyn ...`
    blocks = re.findall(r"^```[^\n]*\n(.*?)^```", README, re.S | re.M)
    main, tests = blocks[0].strip(), blocks[1].strip()
    assert main == "python3 -m venv .venv && . .venv/bin/activate && pip install . && nsdyn run"
    assert tests.endswith(f"{_ci_var('INSTALL_TEST')} && {_ci_var('TEST_CMD')}")
    assert tests.startswith("python3 -m venv .venv && . .venv/bin/activate && ")


def test_every_relative_link_and_image_points_to_a_file():
    links = re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", README)
    local = [u for u in links if not re.match(r"[a-z]+://", u)]
    assert local
    missing = [u for u in local if not (ROOT / u).exists()]
    assert not missing, missing


def test_the_figure_is_drawn_by_a_script_the_readme_names():
    sys.path.insert(0, str(ROOT / "docs" / "gen"))
    from gallery import figures_of

    images = re.findall(r"!\[[^\]]*\]\((examples/figures/[^)]+\.png)\)", README)
    assert len(images) == 1, "one figure: the README is the front door"
    fig = ROOT / images[0]
    scripts = re.findall(r"python (examples/\w+\.py)", README)
    drawn_by = [s for s in scripts if fig in figures_of((ROOT / s).read_text(), [fig])]
    assert drawn_by, f"{images[0]}: no script named in the README writes it"
