"""The overturning spectrum's search finds the narrow safe band of one-sine pulses and says what
a NaN means.

Physics (Zhang & Makris 2001, Fig. 3): under a one-sine pulse a slender block overturns just
above its minimum after one impact (mode 1), is safe in a band above, and overturns without an
impact above that band (mode 2). Checked here by direct simulation at the reported edges, not
against the search itself: inside the band the block survives, just below it overturns after
an impact, just above it overturns without one.
"""

from __future__ import annotations

import json
import math
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

from nsdyn.models.rocking import RockingBlock
from nsdyn.models.rocking.spectra import STATUS, _overturns, overturning_spectrum

BLOCK = RockingBlock(width=0.3, height=1.2)


@pytest.mark.parametrize("x", [1.5, 3.0])
def test_default_scan_finds_the_narrow_safe_band(x):
    # the band is 0.5 % (x = 1.5) and 3 % (x = 3) wide: narrower than one scan factor (10 %),
    # so a plain scan steps over it
    with ThreadPoolExecutor(1) as ex:
        sp = overturning_spectrum(BLOCK, [x], executor=ex)
    lo, hi = sp.safe_lo_ratio[0], sp.safe_hi_ratio[0]
    assert sp.status == ["safe band"] and sp.mode[0] == 1
    assert sp.a_min_ratio[0] < lo < hi < lo * sp.scan
    a_ref, w = BLOCK.uplift_accel, x * BLOCK.p
    edge = 4 * sp.rtol  # outside the bisected edges by a few times their width
    below = _overturns(BLOCK, "sine", w, lo * (1 - edge) * a_ref, 1e-10)
    inside = _overturns(BLOCK, "sine", w, math.sqrt(lo * hi) * a_ref, 1e-10)
    above = _overturns(BLOCK, "sine", w, hi * (1 + edge) * a_ref, 1e-10)
    assert below[0] and below[1] > 0
    assert not inside[0]
    assert above[0] and above[1] == 0


def test_status_words_say_what_a_nan_means():
    # up to a_max = 1.05 g tan(alpha) the block (minimum 1.13 at x = 1) does not overturn: the
    # status says "up to a_max", the minimum is NaN; at a high frequency the minimum exists
    with ThreadPoolExecutor(1) as ex:
        none = overturning_spectrum(BLOCK, [1.0], executor=ex, a_max=1.05)
        some = overturning_spectrum(BLOCK, [1.0, 0.5], executor=ex, rtol=1e-3)
    assert np.isnan(none.a_min_ratio[0]) and none.status == [STATUS[0]]
    assert STATUS[0] == "no overturning up to a_max"
    assert all(s in STATUS for s in some.status)
    assert all((s == STATUS[1]) == (np.isfinite(a) and np.isnan(lo))
               for s, a, lo in zip(some.status, some.a_min_ratio, some.safe_lo_ratio,
                                   strict=True))  # fmt: skip
    # the summary says the NaN as None (JSON), the table keeps the arrays as they are
    assert none.summary()["a_min_ratio"] == [None]
    assert none.summary()["status"] == [STATUS[0]]
    pytest.importorskip("pandas")
    df = some.to_dataframe()
    assert list(df.index) == list(some.omega_ratio) and df.index.name == "omega_ratio"
    np.testing.assert_array_equal(df["a_min_ratio"].to_numpy(), some.a_min_ratio)
    assert list(df["status"]) == some.status and df.attrs["p_per_s"] == BLOCK.p
    assert "array(" not in repr(some)  # (brief: its arrays were printed in full)


def test_spectrum_command_reports_the_status(tmp_path, capsys):
    from nsdyn.cli import main

    scene = Path(__file__).resolve().parents[3] / "examples" / "scenes"
    argv = ["spectrum", str(scene / "rocking-seed003-column.toml"), "--n", "2", "--wmin", "1.5",
            "--wmax", "3", "--rtol", "1e-3", "--workers", "1", "--out", str(tmp_path),
            "--json", "--no-figures"]  # fmt: skip
    assert main(argv) == 0
    rep = json.loads(capsys.readouterr().out)
    words = rep["frequency_status"]  # (the command's "status" is its exit status)
    assert rep["status"] == 0 and len(words) == 2 and all(s in STATUS for s in words)
    assert rep["search"]["scan"] > 1.0
    # p = sqrt(3 g / (4 R)) of the 0.3 x 1.2 m column, named as every summary names it
    assert rep["p_per_s"] == pytest.approx(math.sqrt(3 * 9.81 / (4 * math.hypot(0.15, 0.6))))
    header = Path(rep["csv"]).read_text().splitlines()[0]
    assert header.endswith(",status")


def test_a_bisection_width_below_round_off_is_refused():
    # while a_hi - a_lo > rtol a_hi never ends once the width stops shrinking: at rtol 1e-17
    # (below double precision's epsilon) the spectrum ran on; the floor is 100 x epsilon

    with pytest.raises(ValueError, match=r"rtol: expected a relative width 2\.2e-14 <= rtol"):
        overturning_spectrum(BLOCK, [1.0], rtol=1e-17)


def test_an_unknown_pulse_shape_is_refused_before_any_worker_starts():
    # "sien" was refused inside each worker task, the pool already started (11 frames deep)
    class Counting(ThreadPoolExecutor):
        submitted = 0

        def submit(self, *a, **k):
            Counting.submitted += 1
            return super().submit(*a, **k)

    for shape in ("sien", ["sine"]):  # (a list was "unhashable type")
        with Counting(1) as ex, pytest.raises(ValueError, match=r"^shape: expected one of"):
            overturning_spectrum(RockingBlock(width=0.5, height=2.0), [1.5], shape=shape,
                                 executor=ex)  # fmt: skip
    assert Counting.submitted == 0
    from nsdyn.ground.pulses import Pulse

    with pytest.raises(ValueError, match=r"^shape: expected one of"):  # (the pulse's own)
        Pulse(["sine"], 1.0, 1.0)
