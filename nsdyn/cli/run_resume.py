"""The checkpoint of ``nsdyn run`` on an isolated frame, in its output folder.

An interrupted run leaves its state (:data:`CHECKPOINT`) and what it was run with (the scene
after the command-line overrides, and the fidelity) beside it; ``--resume`` continues the
state only for the same settings, and says from which time; a rerun without it starts afresh
and says that it discards the checkpoint.
"""

from __future__ import annotations

import hashlib
import json
import sys
from pathlib import Path

import numpy as np

from nsdyn.atomic import differing
from nsdyn.cli.args import SAID

CHECKPOINT = ".run-checkpoint.npz"  # an interrupted run's state, in its output directory
IDENTITY = ".run-checkpoint.json"  # the settings of the run that wrote it


def run_identity(cfg: dict, fidelity, motion=None) -> dict:
    """What a run's checkpoint depends on: the whole scene (after the command-line overrides)
    and the ground motion's samples (a record edited since: a scene the same, the run not)."""
    scene = {k: v for k, v in cfg.items() if not k.startswith("_")}
    ident = {"scene": scene, "fidelity": fidelity}
    if motion is not None:
        ident["motion"] = samples_digest(motion)
    return json.loads(json.dumps(ident, default=str))


def samples_digest(motion) -> str:
    """A fingerprint of a motion's numbers (its arrays and scalars; not its name, source or
    header text), hashed as a run's checkpoint key hashes its inputs."""
    from nsdyn.solve.checkpoint import feed

    h = hashlib.sha256()
    for key, v in sorted(getattr(motion, "__dict__", {}).items()):
        if key not in ("name", "source", "meta"):
            feed(h, (key, v))
    return h.hexdigest()


def refuse_foreign_checkpoint(path: Path, ident: dict) -> None:
    """A checkpoint written for other settings is never continued (it would mix two runs);
    the refusal names the settings that differ (the motion's samples only when the scene's
    keys do not: a record edited since)."""
    from nsdyn.models.scenefile import SceneError

    try:
        old = json.loads(path.read_text())
    except (OSError, ValueError):  # (said as "other settings, an older nsdyn")
        raise SceneError(
            f"{path.parent}: the checkpoint there is unreadable ({path.name} missing, "
            "damaged or cut); run without --resume to start afresh"
        ) from None
    if isinstance(old, dict) and "motion" in ident and "motion" not in old:  # (written
        # before the samples counted: an older nsdyn's, not a record edited since)
        old = None
    if old != ident:
        keys = [] if old is None else differing(old, ident)
        if len(keys) > 1 and "motion" in keys:  # (the samples follow from the scene's keys)
            keys.remove("motion")
        names = dict.fromkeys(_field(k) for k in keys)  # (in order, once each)
        diff = "an older nsdyn" if old is None else "differing: " + ", ".join(names)
        raise SceneError(
            f"{path.parent}: the checkpoint there was written by a run with other settings "
            f"({diff}); rerun with the same scene and options to resume it, or without "
            "--resume to start afresh"
        )


def _field(key: str) -> str:
    """A differing identity key as the scene field it is (``scene.solver.method`` ->
    ``solver.method``, a command-line flag included: the scene is taken after them)."""
    if key == "fidelity":
        return "scene.fidelity"
    if key == "motion":
        return "the record's samples"
    return key.removeprefix("scene.")


def checkpoint_time(path: Path) -> float | None:
    """The last output time a checkpoint holds (None if it holds none or cannot be read: the
    run then says why when it loads it)."""
    try:
        with np.load(path) as d:
            t = d["t"]
            return float(t[-1]) if t.size else None
    except Exception:  # noqa: BLE001 -- a damaged file is reported by the run's own load
        return None


def open_checkpoint(out: Path, ident: dict, resume: bool, quiet: bool,
                    notes: list | None = None):  # fmt: skip
    """(checkpoint, identity file, the time resumed from or None) of a run into ``out``:
    without ``resume`` an earlier checkpoint is discarded (and said so); with it, one of other
    settings is refused, and the time it resumes from is said (on stderr, unless ``quiet``).
    A discarded checkpoint, or none to resume, is also one of ``notes`` (--json's)."""
    ckpt, identity = out / CHECKPOINT, out / IDENTITY

    def say(text, note=False):
        if note and notes is not None:  # (--json said nothing of either: the checkpoint
            notes.append(text)  # gone without a word; nor when the new run was interrupted)
            SAID.append(("note", text))
        if not quiet:
            print(f"nsdyn run: {text}", file=sys.stderr)

    if not resume:
        if ckpt.is_file():
            say(f"starting afresh; the checkpoint an interrupted run left in {out} is "
                "discarded (--resume continues it)", note=True)  # fmt: skip
        ckpt.unlink(missing_ok=True)
        identity.unlink(missing_ok=True)
        return ckpt, identity, None
    if not ckpt.is_file():
        say(f"--resume: no checkpoint in {out}; the run starts at the beginning", note=True)
        return ckpt, identity, None
    refuse_foreign_checkpoint(identity, ident)
    t = checkpoint_time(ckpt)
    if t is not None:
        say(f"resuming from t = {t:g} s (the checkpoint in {out}); wall_s counts this part "
            "only")  # fmt: skip
    return ckpt, identity, t
