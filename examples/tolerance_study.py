"""How tight must an earthquake run be? Errors of tolerance settings against a much tighter run.

The office frame (Craig-Bampton 13 dofs, isolated, K_lam 5e4, c 1e4, mu 0.03), 40 s of the
bundled synthetic record and - when ``shared/records`` is found - of the four Kobe 1995
records at PGA 3 m/s^2. For each setting: steps, wall time after compilation, and the relative
errors of the x_iso history, the peak IDR, the peak floor acceleration above the isolators and
the peak base-level acceleration, against the same method at rtol 1e-8, atol 1e-10.

    python examples/tolerance_study.py [--quick] [--out DIR]

``--quick``: the bundled record only, 20 s. Writes ``tolerance_study.csv`` (atomically) and
prints the table docs/guide/transient.md quotes ("Tolerances and accuracy").
"""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path

import numpy as np

from nsdyn.atomic import atomic_open
from nsdyn.cli.args import out_dir
from nsdyn.ground import default_shared_dir, kobe_records, read_motion
from nsdyn.models.isolated.system import Isolation, build_system
from nsdyn.solve.transient import DEFAULT_RTOL, FAST_ATOL, default_atol, simulate
from nsdyn.structure import load_frame

REF = dict(rtol=1e-8, atol=1e-10)
SETTINGS = [  # (label, friction law, method, rtol, atol)
    ("default radau", "arctan", "radau", DEFAULT_RTOL, default_atol("radau")),
    ("fast radau", "arctan", "radau", DEFAULT_RTOL, FAST_ATOL),
    ("library default radau", "arctan", "radau", 1e-6, 1e-8),
    ("default event", "switch", "event", DEFAULT_RTOL, default_atol("event")),
]


def motions(quick: bool) -> dict:
    out = {"synthetic-wn-40s": read_motion("synthetic-wn-40s")}
    shared = None if quick else default_shared_dir()
    if shared is not None:
        out.update({k: m.scaled_to_pga(3.0) for k, m in kobe_records(shared, "000").items()})
    t_end = 20.0 if quick else 40.0
    return {k: m.window(m.t0, m.t0 + t_end) for k, m in out.items()}


def rel(a: float, b: float) -> float:
    return abs(a / b - 1.0)


def main(out: Path, quick: bool) -> list[dict]:
    frame = load_frame("office-11")
    rows = []
    systems = {
        law: build_system(frame, Isolation(law=law), fidelity="cb") for law in ("arctan", "switch")
    }
    for name, m in motions(quick).items():
        refs = {}
        for label, law, method, rtol, atol in SETTINGS:
            s = systems[law]
            if method not in refs:
                refs[method] = simulate(s, m, method=method, **REF)
            ref = refs[method].response
            walls = []
            for _ in range(3):
                res = simulate(s, m, method=method, rtol=rtol, atol=atol)
                walls.append(res.wall_s)
            r = res.response
            xr = ref.x_iso[:, 0]
            row = dict(
                record=name,
                setting=label,
                method=method,
                rtol=rtol,
                atol=str(atol),
                steps=res.n_steps,
                ref_steps=refs[method].n_steps,
                wall_s=float(np.median(walls)),
                err_x=float(np.max(np.abs(r.x_iso[:, 0] - xr)) / np.max(np.abs(xr))),
                err_idr=rel(r.idr_max, ref.idr_max),
                err_acc=rel(r.floor_acc_max, ref.floor_acc_max),
                err_acc_base=rel(r.floor_acc_by_level[0], ref.floor_acc_by_level[0]),
            )
            rows.append(row)
            print(
                f"{name:17s} {label:22s} steps {row['steps']:6d}  wall {row['wall_s']:.3f} s  "
                f"x {row['err_x']:.1e}  IDR {row['err_idr']:.1e}  a {row['err_acc']:.1e}  "
                f"a_base {row['err_acc_base']:.1e}",
                flush=True,
            )
    with atomic_open(out / "tolerance_study.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print("\n| setting | steps | median wall | x_iso history | peak IDR | peak floor acc. | "
          "base-level acc. |")  # fmt: skip
    print("|---|---|---|---|---|---|---|")
    for label, *_ in SETTINGS:
        sel = [r for r in rows if r["setting"] == label]
        st, wall = [r["steps"] for r in sel], [r["wall_s"] for r in sel]
        print(
            f"| {label} | {min(st)}–{max(st)} | {min(wall):.3f}–{max(wall):.3f} s | "
            f"≤ {max(r['err_x'] for r in sel):.1e} | "
            f"≤ {max(r['err_idr'] for r in sel):.1e} | ≤ {max(r['err_acc'] for r in sel):.1e} | "
            f"≤ {max(r['err_acc_base'] for r in sel):.1e} |"
        )
    return rows


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=out_dir, default="nsdyn-out/tolerance-study")
    ap.add_argument("--quick", action="store_true", help="bundled record only, 20 s")
    a = ap.parse_args()
    from nsdyn.atomic import caused_by_interrupt

    try:
        main(Path(a.out), a.quick)
    except BaseException as exc:  # Ctrl-C inside a kernel reaches Python as numba's SystemError
        if not caused_by_interrupt(exc):
            raise
        print("interrupted: no table written (the CSV is written once every run is done)",
              file=sys.stderr)  # fmt: skip
        sys.exit(130)
