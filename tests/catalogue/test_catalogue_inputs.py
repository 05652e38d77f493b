"""Catalogue of bad input files: every scene kind, frame files, ground-motion records, studies.

Each row writes one bad file (a valid example with one defect), reads it through the public
loader of its kind and asserts the error class and that the message names the file, the field
and the expected form (and, for a misspelt key, the nearest valid key). The contract is the
house rule for bad input: ``SceneError`` / ``FrameFileError`` / ``RecordFileError`` naming
file, field and expected form, never a traceback from deep inside the code.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import pytest

from nsdyn.ground import RecordFileError, UnitWarning, read_motion
from nsdyn.ground.library import bundled_records
from nsdyn.models.scenefile import SceneError, read_toml, scene_kind
from nsdyn.structure import FrameFileError, load_frame

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "examples" / "scenes"
FRAMES = ROOT / "frames"


def _edit(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


def _write(tmp_path: Path, name: str, text: str) -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def _load(kind: str, path: Path):
    """Read and validate (and build, without running) a scene of any kind."""
    if kind == "isolated":
        assert scene_kind(read_toml(path), str(path)) == kind
        from nsdyn.models.isolated.scene import build_scene_run, load_scene

        return build_scene_run(load_scene(path))
    cfg = read_toml(path)
    assert scene_kind(cfg, str(path)) == kind
    if kind == "rocking":
        from nsdyn.models.rocking.scene import build_model, build_motion, build_solver

        build_model(cfg, str(path))
        build_solver(cfg, str(path))
        return build_motion(cfg, str(path))
    if kind == "contact":
        from nsdyn.models.contact.scene import build

        return build(cfg, str(path))
    if kind == "cylinder":
        from nsdyn.models.cylinder.scene import build

        return build(cfg, str(path))
    if kind == "deck":
        from nsdyn.models.isolated.deck_scene import build_motion, build_solver, build_system

        build_system(cfg, str(path))
        build_solver(cfg, str(path))
        return build_motion(cfg, str(path))
    if kind == "building3d":
        from nsdyn.models.isolated import building3d_scene as b3

        b3.build_system(cfg, str(path))
        b3.build_solver(cfg, str(path))
        return b3.build_motion(cfg, str(path))
    raise AssertionError(kind)


def _expect(exc_type, fn, *needles):
    with pytest.raises(exc_type) as ei:
        fn()
    msg = str(ei.value)
    assert type(ei.value) is exc_type or isinstance(ei.value, exc_type), type(ei.value)
    for n in needles:
        assert re.search(n, msg), f"{n!r} not in {msg!r}"
    assert "\n" not in msg.strip() or len(msg) < 2000
    return msg


# ----------------------------------------------------------------------------- scenes
# (id, example file, old text, new text, needles the message must contain)
SHEAR = "isolated-shear-3storey.toml"
MATR = "isolated-coulomb-force.toml"
CASK = "rocking-seed001-cask.toml"
COMPL = "rocking-seed001-compliant.toml"
RFRAME = "rocking-seed003-frame.toml"
CONTACT = "contact-seed002-A5.toml"
CYL = "cylinder-uplift.toml"
DECK = "deck-fps4-3c.toml"
SDOF2 = "sdof-bidirectional-circular.toml"

SCENE_ROWS = [
    # --- TOML syntax, unknown kind (every kind shares read_toml / scene_kind)
    ("syntax-unclosed-table", SHEAR, "[structure]", "[structure", [r"not valid TOML", r"line"]),
    ("syntax-missing-value", CASK, "height = 4.0", "height = ", [r"not valid TOML"]),
    ("syntax-dup-key", CONTACT, "mass = 2500.0", "mass = 2500.0\nmass = 1.0", [r"TOML"]),
    ("kind-misspelt", CASK, 'kind = "rocking"', 'kind = "rockin"', [r"scene\.kind", "'rocking'"]),
    # --- isolated frame scene (default frame), shear and matrices structures
    ("iso-unknown-table", SHEAR, "[isolation]", "[isolator]", [r"\[isolator\]", "isolation"]),
    ("iso-misspelt-motion", SHEAR, "pga = 3.0", "pgaa = 3.0", [r"motion\.pgaa", "'pga'"]),
    (
        "iso-misspelt-solver",
        SHEAR,
        'method = "radau"',
        'methd = "radau"',
        [r"solver\.methd", "'method'"],
    ),
    ("iso-misspelt-isolation", SHEAR, "mu = 0.05", "muu = 0.05", [r"isolation\.muu", "'mu'"]),
    ("iso-wrong-type-pga", SHEAR, "pga = 3.0", 'pga = "3"', [r"motion\.pga", "number|float"]),
    ("iso-negative-pga", SHEAR, "pga = 3.0", "pga = -3.0", [r"motion\.pga", "positive"]),
    ("iso-pga-inf", SHEAR, "pga = 3.0", "pga = inf", [r"motion\.pga", "finite"]),
    ("iso-pga-nan", SHEAR, "pga = 3.0", "pga = nan", [r"motion\.pga", "finite"]),
    (
        "iso-tend-negative",
        SHEAR,
        "pga = 3.0",
        "pga = 3.0\nt_end = -5.0",
        [r"motion\.t_end", "positive"],
    ),
    ("iso-tend-inf", SHEAR, "pga = 3.0", "pga = 3.0\nt_end = inf", [r"motion\.t_end", "finite"]),
    (
        "iso-max-steps-zero",
        SHEAR,
        'method = "radau"',
        'method = "radau"\nmax_steps = 0',
        [r"solver\.max_steps", "positive integer"],
    ),
    (
        "iso-max-steps-fraction",
        SHEAR,
        'method = "radau"',
        'method = "radau"\nmax_steps = 2.5',
        [r"solver\.max_steps", "positive integer"],
    ),
    ("iso-mu-negative", SHEAR, "mu = 0.05", "mu = -0.05", [r"isolation\.mu", "non-negative"]),
    ("iso-eps-zero", SHEAR, "eps = 500.0", "eps = 0.0", [r"isolation\.eps", "positive"]),
    ("iso-eps-negative", SHEAR, "eps = 500.0", "eps = -1.0", [r"isolation\.eps", "positive"]),
    (
        "iso-klam-negative",
        SHEAR,
        "k_lam = 2.0e5",
        "k_lam = -2.0e5",
        [r"isolation\.k_lam", "non-negative"],
    ),
    ("iso-bad-law", SHEAR, 'law = "arctan"', 'law = "coulomb"', [r"law", "arctan"]),
    (
        "iso-rtol-zero",
        SHEAR,
        'method = "radau"',
        'method = "radau"\nrtol = 0',
        [r"solver\.rtol", "positive"],
    ),
    (
        "iso-atol-triple",
        SHEAR,
        'method = "radau"',
        'method = "radau"\natol = [1, 2, 3]',
        [r"solver\.atol", "pair"],
    ),
    (
        "iso-uplift-mode",
        SHEAR,
        'method = "radau"',
        'method = "radau"\nuplift = "ignore"',
        [r"solver\.uplift", "'raise'"],
    ),
    (
        "iso-unknown-record",
        SHEAR,
        '"synthetic-wn-40s"',
        '"synthetic-wn-4s"',
        [r"synthetic-wn-4s", "synthetic-wn-40s"],
    ),
    (
        "shear-mass-zero",
        SHEAR,
        "masses = [2.0e4,",
        "masses = [0.0,",
        [r"structure\.masses", "positive"],
    ),
    (
        "shear-mass-negative",
        SHEAR,
        "masses = [2.0e4,",
        "masses = [-2.0e4,",
        [r"structure\.masses", "positive"],
    ),
    (
        "shear-stiffness-zero",
        SHEAR,
        "stiffnesses = [2.0e7,",
        "stiffnesses = [0.0,",
        [r"structure\.stiffnesses", "positive"],
    ),
    (  # a percentage typed as the ratio: [0, 1) as every frame's zeta
        "shear-damping-percent",
        SHEAR,
        "damping_ratios = 0.05",
        "damping_ratios = 1.5",
        [r"structure\.damping_ratios", r"in \[0, 1\) \(0\.05 for 5 %\)"],
    ),
    (
        "shear-height-negative",
        SHEAR,
        "heights = 3.0",
        "heights = -3.0",
        [r"structure\.heights", "positive"],
    ),
    (
        "shear-length-mismatch",
        SHEAR,
        "stiffnesses = [2.0e7, 1.5e7, 1.0e7]",
        "stiffnesses = [2.0e7, 1.5e7]",
        [r"structure\.stiffnesses", r"3"],
    ),
    (
        "shear-missing-masses",
        SHEAR,
        "masses = [2.0e4, 1.0e4, 1.0e4, 1.0e4]",
        "",
        [r"structure\.masses", "required|missing"],
    ),
    (
        "shear-misspelt-key",
        SHEAR,
        "damping_ratios = 0.05",
        "damping_ratio = 0.05",
        [r"structure\.damping_ratio", "'damping_ratios'"],
    ),
    (
        "shear-wrong-type",
        SHEAR,
        "masses = [2.0e4,",
        'masses = ["a",',
        [r"structure\.masses", "number"],
    ),
    ("structure-kind", SHEAR, 'kind = "shear"', 'kind = "sheer"', [r"structure\.kind", "'shear'"]),
    (
        "matrices-mass-negative",
        MATR,
        "M = [[1000.0]]",
        "M = [[-1000.0]]",
        [r"structure\.M", "positive"],
    ),
    (
        "matrices-not-square",
        MATR,
        "K = [[0.0]]",
        "K = [[0.0, 1.0]]",
        [r"structure\.K", r"1 x 1|square|shape"],
    ),
    (
        "matrices-weight-zero",
        MATR,
        "weight = 9810.0",
        "weight = 0.0",
        [r"structure\.weight", "positive"],
    ),
    (
        "matrices-missing-isolation",
        MATR,
        "k_lam = 4.0e4",
        "",
        [r"isolation\.k_lam", "required|missing"],
    ),
    (
        "matrices-iso-dof-range",
        MATR,
        "iso_dofs = [0]",
        "iso_dofs = [3]",
        [r"structure\.iso_dofs", r"0"],
    ),
    (
        "force-frequency-zero",
        MATR,
        "frequency = 1.5",
        "frequency = 0.0",
        [r"force\.frequency", "positive"],
    ),
    (
        "force-misspelt",
        MATR,
        "amplitude = 1635.0",
        "amplitud = 1635.0",
        [r"force\.amplitud", "'amplitude'"],
    ),
    ("force-no-duration", MATR, "n_periods = 20", "", [r"force", "n_periods|t_end"]),
    (
        "force-dof-out-of-range",
        MATR,
        "\ndofs = [0]",
        "\ndofs = [1]",
        [r"force\.dofs", r"in 0\.\.0 \(the system has 1 dofs\), got \[1\]"],
    ),
    # --- rocking
    ("rock-misspelt-block", CASK, "height = 4.0", "hieght = 4.0", [r"block\.hieght", "'height'"]),
    ("rock-unknown-table", CASK, "[block]", "[blok]", [r"blok", "'block'"]),
    ("rock-width-zero", CASK, "width = 2.0", "width = 0.0", [r"block\.width", "positive"]),
    ("rock-height-negative", CASK, "height = 4.0", "height = -4.0", [r"block\.height", "positive"]),
    ("rock-mass-zero", CASK, "mass = 124800.0", "mass = 0.0", [r"block\.mass", "positive"]),
    ("rock-width-text", CASK, "width = 2.0", 'width = "2 m"', [r"block\.width", "number"]),
    ("rock-missing-height", CASK, "height = 4.0", "", [r"block\.height", "missing"]),
    ("rock-r-negative", CASK, "\nr = 0.82", "\nr = -0.2", [r"block\.r", r"0 <= r <= 1"]),
    ("rock-r-above-one", CASK, "\nr = 0.82", "\nr = 1.2", [r"block\.r", r"0 <= r <= 1"]),
    ("rock-bad-model", CASK, 'model = "block"', 'model = "blok"', [r"scene\.model", "'block'"]),
    ("rock-bad-pulse", CASK, 'pulse = "sine"', 'pulse = "sinus"', [r"motion\.pulse", "sine"]),
    ("rock-f-zero", CASK, "f_p = 0.81", "f_p = 0.0", [r"motion\.f_p", "positive"]),
    ("rock-cycles-zero", CASK, "n_cycles = 8", "n_cycles = 0", [r"motion\.n_cycles", ">= 1"]),
    ("rock-cycles-float", CASK, "n_cycles = 8", "n_cycles = 8.5", [r"motion\.n_cycles", "integer"]),
    ("rock-tend-negative", CASK, "t_end = 12.0", "t_end = -1.0", [r"motion\.t_end", "positive"]),
    ("rock-pga-inf", CASK, "a_p_g = 1.0", "a_p_g = 1.0\npga = inf", [r"motion\.pga", "finite"]),
    ("rock-tol-zero", CASK, "tol = 1e-9", "tol = 0.0", [r"solver\.tol", "positive"]),
    (
        "rock-record-missing",
        CASK,
        'pulse = "sine"',
        'record = "nosuch-record"\npulse = "sine"',
        [r"motion\.record", "synthetic-wn-40s"],
    ),
    (
        "rock-frame-gamma-negative",
        RFRAME,
        "gamma = 5.0",
        "gamma = -5.0",
        [r"block\.gamma", "non-negative"],
    ),
    (
        "rock-compliant-zeta-negative",
        COMPL,
        "zeta = 2.0",
        "zeta = -2.0",
        [r"block\.zeta", "non-negative"],
    ),
    (
        "rock-compliant-stiff-zero",
        COMPL,
        "omega_v_over_p = 300.0",
        "omega_v_over_p = 0.0",
        [r"block\.omega_v_over_p", "positive"],
    ),
    ("rock-compliant-r", COMPL, "zeta = 2.0", "zeta = 2.0\nr = 0.9", [r"block\.r", "compliant"]),
    # --- contact
    (
        "contact-misspelt-friction",
        CONTACT,
        "mu_s = 0.57",
        "mu_st = 0.57",
        [r"friction\.mu_st", "'mu_s'"],
    ),
    (
        "contact-mu-negative",
        CONTACT,
        "mu_s = 0.57",
        "mu_s = -0.57",
        [r"friction\.mu_s", "non-negative"],
    ),
    ("contact-mud-above-mus", CONTACT, "mu_d = 0.29", "mu_d = 0.9", [r"friction", r"mu_d"]),
    ("contact-mass-zero", CONTACT, "mass = 2500.0", "mass = 0.0", [r"body\.mass", "positive"]),
    (
        "contact-width-negative",
        CONTACT,
        "width = 1.1",
        "width = -1.1",
        [r"body\.width", "positive"],
    ),
    ("contact-en-above-one", CONTACT, "e_n = 0.0", "e_n = 1.5", [r"impact\.e_n", r"e_n <= 1"]),
    ("contact-en-negative", CONTACT, "e_n = 0.0", "e_n = -0.5", [r"impact\.e_n", "non-negative"]),
    ("contact-bad-law", CONTACT, 'law = "newton"', 'law = "poisson"', [r"impact\.law", "'newton'"]),
    (
        "contact-moreau-h-too-long",
        CONTACT,
        'method = "event"',
        'method = "moreau"\nh = 0.5',
        [r"solver\.h", r"expected at most 0\.0545 s"],  # T/40 of the A5 sine, T = 2.18 s
    ),
    (
        "contact-period-zero",
        CONTACT,
        "period = 2.18",
        "period = 0.0",
        [r"motion\.period", "positive"],
    ),
    (
        "contact-bad-method",
        CONTACT,
        'method = "event"',
        'method = "euler"',
        [r"solver\.method", "event"],
    ),
    ("contact-pga-inf", CONTACT, "pga = 1.6", "pga = inf", [r"motion\.pga", "finite"]),
    ("contact-pga-nan", CONTACT, "pga = 1.6", "pga = nan", [r"motion\.pga", "finite"]),
    ("contact-missing-mus", CONTACT, "mu_s = 0.57", "", [r"friction\.mu_s", "missing"]),
    # --- cylinder
    ("cyl-misspelt", CYL, "H = 4.0", "h = 4.0", [r"cylinder\.h", "'H'"]),
    ("cyl-radius-zero", CYL, "r = 1.0", "r = 0.0", [r"cylinder\.r", "positive"]),
    ("cyl-mass-negative", CYL, "m = 1.0", "m = -1.0", [r"cylinder\.m", "positive"]),
    ("cyl-frock-zero", CYL, "f_rock = 3.0", "f_rock = 0.0", [r"foundation\.f_rock", "positive"]),
    ("cyl-zeta-negative", CYL, "zeta = 0.10", "zeta = -0.1", [r"foundation\.zeta", "non-negative"]),
    (
        "cyl-case",
        CYL,
        'case = "tensionless"',
        'case = "tensionles"',
        [r"foundation\.case", "tensionless"],
    ),
    ("cyl-seed-negative", CYL, "seed = 1", "seed = -1", [r"motion\.seed", "non-negative integer"]),
    ("cyl-dt-text", CYL, "dt = 0.01", 'dt = "0.01"', [r"motion\.dt", "number"]),
    ("cyl-pga-inf", CYL, "seed = 1", "seed = 1\npga = inf", [r"motion\.pga", "finite"]),
    (
        "cyl-tend-negative",
        CYL,
        "seed = 1",
        "seed = 1\nt_end = -5.0",
        [r"motion\.t_end", "positive"],
    ),
    ("cyl-rtol-zero", CYL, "rtol = 1e-7", "rtol = 0.0", [r"solver\.rtol", "positive"]),
    (
        "cyl-k-negative",
        CYL,
        "f_rock = 3.0           # design targets -> k = 9814 N/m^3, c = 103.6 N s/m^3\nzeta = 0.10",
        "k = -1.0\nc = 1.0",
        [r"foundation\.k", "positive"],
    ),
    (
        "cyl-record-missing",
        CYL,
        "seed = 1",
        'record = "nosuch"',
        [r"motion\.record", "synthetic-wn-40s"],
    ),
    # --- deck on bidirectional isolators
    ("deck-radius-zero", DECK, "radius = 2.2 ", "radius = 0.0 ", [r"bearing\.radius", "positive"]),
    ("deck-radius-negative", DECK, "radius = 2.2 ", "radius = -2.2 ", [r"bearing\.radius"]),
    (
        "deck-static-below-kinetic",
        DECK,
        "mu_static = 0.075",
        "mu_static = 0.05",
        [r"bearing\.mu_static", "kinetic"],
    ),
    ("deck-dcap-small", DECK, "d_cap = 0.35 ", "d_cap = 0.1 ", [r"bearing\.d_cap", "mu_s R"]),
    ("deck-missing-m", DECK, "m = 2.0e6 ", "# m = 2.0e6 ", [r"deck\.m", "missing"]),
    ("deck-misspelt", DECK, "ecc = [", "ecx = [", [r"deck\.ecx", "'ecc'"]),
    ("deck-law", DECK, 'law = "switch"', 'law = "coulomb"', [r"solver\.law", "switch"]),
    (
        "deck-positions-line",
        DECK,
        "positions = [[-10.0, -6.0], [10.0, -6.0], [10.0, 6.0], [-10.0, 6.0]]",
        "positions = [[-10.0, 0.0], [0.0, 0.0], [10.0, 0.0]]",
        [r"deck\.positions", "one line"],
    ),
    ("deck-record-missing", DECK, '"synthetic-wn-40s"', '"nosuch"', [r"motion\.record"]),
    ("sdof-missing-mu", SDOF2, "mu = 0.03", "# mu = 0.03", [r"bearing\.mu", "missing"]),
    ("sdof-fps-no-radius", SDOF2, 'type = "flat"', 'type = "fps"', [r"bearing\.radius"]),
    (
        "sdof-frequency-negative",
        SDOF2,
        "frequency = 0.4 ",
        "frequency = -0.4 ",
        [r"motion\.frequency"],
    ),
]


def _kind(example: str) -> str:
    return "deck" if example.startswith("sdof-") else example.split("-")[0]


@pytest.mark.parametrize("row", [pytest.param(r, id=r[0]) for r in SCENE_ROWS])
def test_bad_scene_file(tmp_path, row):
    rid, example, old, new, needles = row
    p = _write(tmp_path, f"bad-{rid}.toml", _edit((SCENES / example).read_text(), old, new))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnitWarning)
        msg = _expect(SceneError, lambda: _load(_kind(example), p), *needles)
    assert str(p) in msg, f"file not named: {msg!r}"


# scenes of the isolated frame on the bundled office frame (no example file: the defaults)
FRAME_SCENE_ROWS = [
    ("frame-pga-inf", "[motion]\npga = inf\n", [r"motion\.pga", "finite"]),
    ("frame-pga-nan", "[motion]\npga = nan\n", [r"motion\.pga", "finite"]),
    ("frame-tend-negative", "[motion]\nt_end = -5.0\n", [r"motion\.t_end", "positive"]),
    ("frame-tend-zero", "[motion]\nt_end = 0.0\n", [r"motion\.t_end", "positive"]),
    ("frame-dt-out-inf", "[solver]\ndt_out = inf\n", [r"solver\.dt_out", "finite"]),
]


@pytest.mark.parametrize("row", [pytest.param(r, id=r[0]) for r in FRAME_SCENE_ROWS])
def test_bad_frame_scene(tmp_path, row):
    rid, text, needles = row
    p = _write(tmp_path, f"{rid}.toml", text)
    msg = _expect(SceneError, lambda: _load("isolated", p), *needles)
    assert str(p) in msg


def test_fmax_inf_is_the_full_model_not_an_error(tmp_path):
    # the one float field where inf is meaningful: a Craig-Bampton cut-off that keeps every
    # mode (the reduced model is the full one, nsdyn.structure.reduction)
    from nsdyn.models.isolated.scene import load_scene

    p = _write(tmp_path, "fmax.toml", "[scene]\nf_max = inf\n")
    assert load_scene(p)["scene"]["f_max"] == float("inf")


@pytest.mark.parametrize(
    "text", ["", "\n\n", "# a scene, some day\n"], ids=["empty", "blank", "comment"]
)
def test_empty_scene_file_is_refused(tmp_path, text):
    # an empty file would otherwise run the default scene as if it had been asked for
    p = _write(tmp_path, "empty.toml", text)
    msg = _expect(SceneError, lambda: read_toml(p), r"empty scene file", r"\[scene\]")
    assert str(p) in msg


def test_missing_scene_file(tmp_path):
    p = tmp_path / "nosuch.toml"
    msg = _expect(SceneError, lambda: read_toml(p), "no such scene file")
    assert str(p) in msg


def test_binary_scene_file(tmp_path):
    p = tmp_path / "b.toml"
    p.write_bytes(b"\xff\xfe\x00\x01")
    msg = _expect(SceneError, lambda: read_toml(p), "text|TOML")
    assert str(p) in msg


# ----------------------------------------------------------------------------- frame files
OFFICE = "office-11.toml"
PORTAL = "portal.toml"
FRAME_ROWS = [
    ("frame-syntax", OFFICE, "[frame.beams]", "[frame.beams", [r"TOML|line"]),
    ("frame-misspelt", OFFICE, "floor_mass =", "floor_mas =", [r"floor_mas", "'floor_mass'"]),
    (
        "frame-bays-negative",
        OFFICE,
        "bays = [15.0]",
        "bays = [-15.0]",
        [r"frame\.bays", "positive"],
    ),
    (
        "frame-height-zero",
        OFFICE,
        "storey_heights = [6.0,",
        "storey_heights = [0.0,",
        [r"frame\.storey_heights", "positive"],
    ),
    (
        "frame-mass-negative",
        OFFICE,
        "floor_mass = [57500.0,",
        "floor_mass = [-57500.0,",
        [r"frame\.floor_mass", ">= 0"],
    ),
    ("frame-E-zero", OFFICE, "E = 2.1e11", "E = 0.0", [r"frame\.columns\.E", "positive"]),
    ("frame-A-text", OFFICE, "A = 0.0493", 'A = "0.0493"', [r"frame\.beams\.A", "positive|number"]),
    ("frame-zeta-negative", OFFICE, "zeta = [0.03,", "zeta = [-0.03,", [r"frame\.zeta", ">= 0"]),
    ("frame-kind", OFFICE, 'kind = "regular"', 'kind = "regulr"', [r"frame\.kind", "regular"]),
    ("frame-nv-zero", OFFICE, "\nn_v = 5", "\nn_v = 0", [r"frame\.n_v", "integer|>= 1|positive"]),
    ("frame-explicit-missing", PORTAL, "base_nodes", "base_nodez", [r"base_node"]),
]


@pytest.mark.parametrize("row", FRAME_ROWS, ids=[r[0] for r in FRAME_ROWS])
def test_bad_frame_file(tmp_path, row):
    rid, example, old, new, needles = row
    p = _write(tmp_path, f"bad-{rid}.toml", _edit((FRAMES / example).read_text(), old, new))
    msg = _expect(FrameFileError, lambda: load_frame(p), *needles)
    assert msg.startswith(f"{p}: "), f"file not named: {msg!r}"


def test_unknown_frame_name_lists_bundled():
    _expect(FrameFileError, lambda: load_frame("office-12"), "office-11", "portal")


# 3D frame files (nsdyn.structure.load_frame3d): orientation vectors, diaphragms, sections
OFFICE3D = "office-11-3d.toml"
PORTAL3D = "portal-3d.toml"
FRAME3D_ROWS = [
    (
        "frame3d-no-vecxz",
        PORTAL3D,
        "vecxz = [1.0, 0.0, 0.0]\n",
        "",
        [r"frame3d\.members\[0\]\.vecxz", "orientation vector"],
    ),
    (
        "frame3d-parallel-vecxz",
        OFFICE3D,
        "vecxz = [1.0, 0.0, 0.0]",
        "vecxz = [0.0, 0.0, 1.0]",
        [r"frame3d\.columns\.vecxz", "not parallel"],
    ),
    (
        "frame3d-diaphragm-one-node",
        PORTAL3D,
        "nodes = [4, 5, 6, 7]",
        "nodes = [4]",
        [r"frame3d\.diaphragms\[0\]\.nodes", ">= 2"],
    ),
    ("frame3d-missing-I_y", OFFICE3D, "I_y = 0.00805\n", "", [r"frame3d\.beams_x\.I_y"]),
    ("frame3d-missing-J", PORTAL3D, "J = 1.852e-6\n", "", [r"frame3d\.sections\[0\]\.J"]),
]


@pytest.mark.parametrize("row", FRAME3D_ROWS, ids=[r[0] for r in FRAME3D_ROWS])
def test_bad_frame3d_file(tmp_path, row):
    from nsdyn.structure import load_frame3d

    rid, example, old, new, needles = row
    p = _write(tmp_path, f"bad-{rid}.toml", _edit((FRAMES / example).read_text(), old, new))
    msg = _expect(FrameFileError, lambda: load_frame3d(p), *needles)
    assert msg.startswith(f"{p}: ") and "\n" not in msg, f"file not named: {msg!r}"


# ----------------------------------------------------------------------------- records
RECORD_ROWS = [
    ("empty", "", RecordFileError, [r"numeric data"]),
    ("header-only", "t,a\n", RecordFileError, [r"numeric data"]),
    ("nan", "0,0.1\n0.01,nan\n0.02,0.3\n", RecordFileError, [r":2:", "finite"]),
    ("inf", "0,0.1\n0.01,inf\n0.02,0.3\n", RecordFileError, [r":2:", "finite"]),
    ("text", "0,0.1\n0.01,abc\n0.02,0.3\n", RecordFileError, [r":2:", "number"]),
    ("ragged", "0,0.1\n0.01\n0.02,0.3\n", RecordFileError, [r":2:", "2 numbers"]),
    ("non-uniform", "0,0.1\n0.01,0.2\n0.03,0.3\n0.04,0.1\n", RecordFileError, [r":3:", "uniform"]),
    (
        "decreasing-named",
        "t,a\n0,0.1\n0.02,0.2\n0.01,0.3\n0.03,0.1\n",
        RecordFileError,
        [r":4:", r"expected time >"],
    ),
    (
        "repeated-time",
        "t,a\n0,0.1\n0.01,0.2\n0.01,0.3\n0.02,0.1\n",
        RecordFileError,
        [r":4:", r"expected time >"],
    ),
    (  # unnamed and short: the glitch keeps it from looking like time, yet it is named
        "repeated-time-unnamed",
        "0,0.1\n0.01,0.2\n0.01,0.3\n0.02,0.1\n",
        RecordFileError,
        [r":3:", r"expected time > 0\.01 s, found 0\.01 s"],
    ),
    ("single-sample", "0,0.1\n", RecordFileError, [r"sample|step|dt|interval"]),
    (
        "at2-bad-npts",
        "PEER\nx\nx\nNPTS=  10, DT= .0100 SEC\n0.1 0.2 0.3\n",
        RecordFileError,
        [r"NPTS|10"],
    ),
]


@pytest.mark.parametrize("row", RECORD_ROWS, ids=[r[0] for r in RECORD_ROWS])
def test_bad_record_file(tmp_path, row):
    rid, text, exc, needles = row
    p = _write(tmp_path, f"rec-{rid}.csv" if not rid.startswith("at2") else f"{rid}.AT2", text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnitWarning)
        msg = _expect(exc, lambda: read_motion(p), *needles)
    assert str(p) in msg


@pytest.mark.parametrize("name", ["nosuch-record", "synthetic-wn-4s", "/nonexistent/dir/rec.AT2"])
def test_unknown_record_lists_bundled(name):
    with pytest.raises(FileNotFoundError) as ei:
        read_motion(name)
    msg = str(ei.value)
    assert name in msg
    for b in bundled_records():
        assert b in msg


@pytest.mark.parametrize(
    "values, needle",
    [("0,1.0\n0.01,900\n0.02,3\n", r"cm/s² \(gal\)"), ("0,0.0001\n0.01,0.002\n0.02,0\n", r"in g")],
    ids=["gal-as-mps2", "g-as-mps2"],
)
def test_implausible_units_warn(tmp_path, values, needle):
    # a PGA of 900 m/s² (a record in gal) or 0.002 m/s² (a record in g read as m/s²)
    p = _write(tmp_path, "units.csv", values)
    with pytest.warns(UnitWarning, match=needle) as rec:
        read_motion(p, units="m/s2")
    assert any(str(p) in str(w.message) and "units=" in str(w.message) for w in rec)


# ----------------------------------------------------------------------------- studies
STUDY = """
[study]
name = "cat"
batch = 2

[base.motion]
t_end = 2.0

[parameters]
"isolation.mu" = [0.02, 0.05]

[records]
names = ["synthetic-wn-40s"]
"""

STUDY_ROWS = [
    ("study-syntax", '"isolation.mu" = [0.02, 0.05]', '"isolation.mu" = [0.02, 0.05', [r"TOML"]),
    (
        "study-unknown-parameter",
        '"isolation.mu"',
        '"isolation.muu"',
        [r"isolation\.muu", "'isolation.mu'"],
    ),
    ("study-unknown-table-field", "batch = 2", "bach = 2", [r"study\.bach", "'batch'"]),
    ("study-unknown-table", "[records]", "[recrods]", [r"recrods", "'records'"]),
    ("study-batch-negative", "batch = 2", "batch = -2", [r"study\.batch", "non-negative|>= 0"]),
    ("study-batch-text", "batch = 2", 'batch = "2"', [r"study\.batch", "int"]),
    ("study-empty-grid", "[0.02, 0.05]", "[]", [r"isolation\.mu", "empty|at least"]),
    (
        "study-linspace-bad",
        "[0.02, 0.05]",
        "{ linspace = [0.02, 0.05] }",
        [r"isolation\.mu", "linspace"],
    ),
    (
        "study-random-bad-form",
        "[0.02, 0.05]",
        "{ uniformly = [0.0, 1.0] }",
        [r"isolation\.mu", "'uniform'"],
    ),
    (
        "study-unknown-record",
        '"synthetic-wn-40s"',
        '"nosuch-rec"',
        [r"records\.names", "synthetic-wn-40s"],
    ),
    (
        "study-record-set",
        'names = ["synthetic-wn-40s"]',
        'set = "kob"',
        [r"records\.set", "'kobe'"],
    ),
    (
        "study-simulated-n-zero",
        'names = ["synthetic-wn-40s"]',
        "simulated = { n = 0, seed = 1, duration = 5.0 }",
        [r"records\.simulated\.n", "positive|>= 1"],
    ),
    (
        "study-scene-missing",
        'name = "cat"',
        'name = "cat"\nscene = "nosuch.toml"',
        [r"study\.scene", "nosuch"],
    ),
    ("study-base-misspelt", "t_end = 2.0", "t_ned = 2.0", [r"motion\.t_ned", "'t_end'"]),
    # parameter values: every task's scene is checked before any task runs
    (
        "study-klam-negative",
        '"isolation.mu" = [0.02, 0.05]',
        '"isolation.k_lam" = [5e4, -1.0]',
        [r"task 1 \(isolation\.k_lam = -1, record synthetic-wn-40s\)", r"non-negative"],
    ),
    ("study-mu-nan", "[0.02, 0.05]", "[0.02, nan]", [r"task 1 ", r"isolation\.mu", "finite"]),
    (
        "study-pga-inf",
        '"isolation.mu" = [0.02, 0.05]',
        '"motion.pga" = [3.0, inf]',
        [r"task 1 ", r"motion\.pga", "finite"],
    ),
    (
        "study-tend-negative",
        '"isolation.mu" = [0.02, 0.05]',
        '"motion.t_end" = [2.0, -5.0]',
        [r"task 1 ", r"motion\.t_end", "positive"],
    ),
    (
        "study-dt-too-small",
        '"isolation.mu" = [0.02, 0.05]',
        '"solver.method" = ["genalpha"]\n"solver.dt" = [1e-7]',
        [r"task 0 ", r"solver\.dt", "too small", "max_steps"],
    ),
    (
        "study-unknown-method",
        '"isolation.mu" = [0.02, 0.05]',
        '"solver.method" = ["radau", "rk4"]',
        [r"task 1 ", r"solver\.method", "'radau'"],
    ),
]


@pytest.mark.parametrize("row", STUDY_ROWS, ids=[r[0] for r in STUDY_ROWS])
def test_bad_study_file(tmp_path, row):
    from nsdyn.studies.study import load_study

    rid, old, new, needles = row
    p = _write(tmp_path, f"{rid}.toml", _edit(STUDY, old, new))
    msg = _expect(SceneError, lambda: load_study(p), *needles)
    assert str(p) in msg, f"file not named: {msg!r}"


def test_empty_study_file_is_refused(tmp_path):
    # it would otherwise run one task of the default scene
    from nsdyn.studies.study import load_study

    p = _write(tmp_path, "empty.toml", "# a study, some day\n")
    msg = _expect(SceneError, lambda: load_study(p), r"empty study file", r"\[study\]")
    assert str(p) in msg


def test_garbage_record_in_a_study_is_refused(tmp_path):
    from nsdyn.studies.study import load_study

    _write(tmp_path, "garbage.csv", "0,0.1\n0.01,abc\n0.02,0.3\n")
    p = _write(tmp_path, "s.toml", _edit(STUDY, '"synthetic-wn-40s"', '"garbage.csv"'))
    msg = _expect(SceneError, lambda: load_study(p), r"task 0 ", r"motion\.record",
                  r"garbage\.csv:2")  # fmt: skip
    assert str(p) in msg


def test_bad_parameter_of_another_scene_kind_is_refused(tmp_path):
    # a rocking study: its tasks' scenes are checked by the rocking family's reader
    from nsdyn.studies.study import load_study

    text = f"""
[study]
scene = "{SCENES / CASK}"
[parameters]
"block.width" = [2.0, -2.0]
"""
    p = _write(tmp_path, "rock.toml", text)
    msg = _expect(SceneError, lambda: load_study(p), r"task 1 \(block\.width = -2\)",
                  r"block\.width", "positive")  # fmt: skip
    assert str(p) in msg


def test_bad_parameter_of_a_deck_study_is_refused(tmp_path):
    # a study of the deck on friction pendulums: its tasks' scenes are checked by the deck
    # reader (bearing tables, three-component motion)
    from nsdyn.studies.study import load_study

    text = f"""
[study]
scene = "{SCENES / "deck-fps4-3c.toml"}"
[parameters]
"bearing.radius" = [2.2, 0.0]
"""
    p = _write(tmp_path, "deck.toml", text)
    msg = _expect(SceneError, lambda: load_study(p), r"task 1 \(bearing\.radius = 0, record ",
                  r"radius", "positive")  # fmt: skip
    assert str(p) in msg


def test_good_study_loads(tmp_path):
    # the base of every study row is itself valid (each row fails for its one defect only)
    from nsdyn.studies.study import load_study

    assert load_study(_write(tmp_path, "ok.toml", STUDY)).n_tasks == 2


# ----------------------------------------------------------------------------- new scene tables
# three-component ground motion ([motion] kind = "record3" | "orbit") and bidirectional bearings
# ([isolation] of a plane isolator): the table readers a scene file goes through
REC3 = {"kind": "record3", "record": "synthetic-wn-40s"}
ORBIT = {"kind": "orbit", "orbit": "circular", "frequency": 1.0, "amplitude": 2.0, "n_periods": 5}
INF, NAN = float("inf"), float("nan")
TABLE_ROWS = [
    ("rec3-pga-inf", "motion3", REC3 | {"pga": INF}, [r"motion\.pga", "finite"]),
    ("rec3-pga-nan", "motion3", REC3 | {"pga": NAN}, [r"motion\.pga", "finite"]),
    ("rec3-tend-negative", "motion3", REC3 | {"t_end": -5.0}, [r"motion\.t_end", "positive"]),
    ("rec3-misspelt", "motion3", REC3 | {"pgaa": 3.0}, [r"motion\.pgaa", "unknown", "'pga'"]),
    ("rec3-record", "motion3", REC3 | {"record": "nosuch"}, [r"motion\.record", "synthetic"]),
    ("motion3-kind", "motion3", {"kind": "record4"}, [r"motion\.kind", "'record3'"]),
    ("orbit-f-zero", "motion3", ORBIT | {"frequency": 0.0}, [r"motion\.frequency", "positive"]),
    ("orbit-amp-inf", "motion3", ORBIT | {"amplitude": INF}, [r"motion\.amplitude", "finite"]),
    ("orbit-shape", "motion3", ORBIT | {"orbit": "square"}, [r"motion\.orbit", "'circular'"]),
    ("orbit-periods-neg", "motion3", ORBIT | {"n_periods": -2}, [r"motion\.n_periods", "posit"]),
    ("orbit-two-durations", "motion3", ORBIT | {"t_end": 3.0}, [r"t_end / motion\.n_periods"]),
    ("orbit-sense", "motion3", ORBIT | {"sense": 2}, [r"motion\.sense", r"\+1"]),
    ("bearing-mu-negative", "bearing", {"radius": 2.0, "mu": -0.05}, [r"\.mu", "non-negative"]),
    ("bearing-mu-nan", "bearing", {"radius": 2.0, "mu": NAN}, [r"\.mu", "finite"]),
    ("bearing-radius-zero", "bearing", {"radius": 0.0, "mu": 0.05}, [r"\.radius", "positive"]),
    ("bearing-no-radius", "bearing", {"type": "fps", "mu": 0.05}, [r"\.radius", "missing"]),
    ("bearing-type", "bearing", {"type": "roller", "mu": 0.05}, [r"\.type", "'fps'"]),
    ("bearing-no-mu", "bearing", {"type": "flat"}, [r"\.mu", "missing"]),
    ("bearing-dcap", "bearing", {"type": "flat", "mu": 0.05, "d_cap": -0.1}, [r"\.d_cap", "pos"]),
    (
        "bearing-static-below",
        "bearing",
        {"type": "flat", "mu": 0.05, "mu_static": 0.01},
        [r"\.mu_static", "kinetic"],
    ),
]


@pytest.mark.parametrize("row", [pytest.param(r, id=r[0]) for r in TABLE_ROWS])
def test_bad_new_scene_table(row):
    from nsdyn.ground import motion3_from_table
    from nsdyn.models.isolated.bearings import bearing_from_config

    rid, reader, table, needles = row
    source = "scene.toml"
    if reader == "motion3":
        msg = _expect(ValueError, lambda: motion3_from_table(table, source), *needles)
    else:
        msg = _expect(ValueError, lambda: bearing_from_config(table, f"{source}: isolation"),
                      *needles)  # fmt: skip
    assert msg.startswith(f"{source}: "), msg
    assert msg.count(source) == 1, msg  # the file named once, not once per layer


@pytest.mark.parametrize("example", sorted(p.name for p in SCENES.glob("*.toml")))
def test_examples_are_valid(example):
    # the base of every scene row loads without error
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnitWarning)
        _load(_kind(example), SCENES / example)


N_INPUT_CASES = (
    len(SCENE_ROWS)
    + len(FRAME_ROWS)
    + len(RECORD_ROWS)
    + len(STUDY_ROWS)
    + 2
    + 1
    + 3
    + 2
    + len(FRAME_SCENE_ROWS)
    + 3  # empty scene files
    + 4  # empty study, garbage record, another kind's parameter, a deck study's
    + 1  # f_max = inf accepted
    + len(TABLE_ROWS)
)
