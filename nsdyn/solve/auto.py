"""``method = "auto"``: the integration method chosen from the model, with its reason.

The rule (``docs/guide/full-models-and-scale.md``), for a model of ``n`` coordinates with
friction law ``law`` under the contact assumption ``contact``:

1. unilateral contact: ``event`` for the switch law, else ``radau`` (the two methods that
   integrate lift-off and landing);
2. the switch law: ``radau`` (``event``, with true stick phases, only when asked for);
3. a full-order model (sparse operators, :mod:`nsdyn.models.isolated.fullorder`) or
   ``n >= AUTO_LARGE_N`` coordinates with a smooth law (arctan, none): ``genalpha-lowrank`` at
   ``AUTO_DT`` (factored once; sparse for full-order models, whose cost per step grows
   linearly with the model, unless every mode is damped: then on the dense copies);
4. otherwise ``radau`` (adaptive, L-stable: the default run).

An explicit method always wins; the reason is one line, printed by ``nsdyn run`` and stored in
a run's summary (``method_reason``).
"""

from __future__ import annotations

from nsdyn.solve.sparse import METHOD

__all__ = ["AUTO", "AUTO_DT", "AUTO_LARGE_N", "choose_for_system", "choose_method", "sparse_path"]

AUTO = "auto"
AUTO_DT = 0.005  # s, the step "auto" gives the factor-once generalized-alpha (200 Hz records)
AUTO_LARGE_N = 200  # coordinates from which a smooth-law model goes to the factor-once method


def choose_method(
    n: int, law: str, contact: str, *, full_order: bool = False, dense: str = ""
) -> tuple[str, str]:
    """The method ``"auto"`` runs and the reason, one line (``docs/guide/full-models-and-
    scale.md``): for ``n`` coordinates, friction ``law`` and ``contact`` assumption,

    1. unilateral contact: ``event`` for the switch law, else ``radau`` (the methods that
       integrate lift-off and landing);
    2. the switch law: ``radau`` (``event``, the true stick phases, only when asked);
    3. a full-order model (sparse operators) or ``n >= AUTO_LARGE_N`` coordinates with a
       smooth law (arctan, none): ``genalpha-lowrank`` at ``AUTO_DT`` (factor once, sparse);
    4. otherwise ``radau`` (adaptive, L-stable: the default run).

    ``dense``: why a full-order model steps on its dense copies instead
    (:func:`nsdyn.solve.fullorder.dense_step`), in the reason's words; empty: sparse.
    """
    if contact == "unilateral":
        if law == "switch":
            return "event", "auto: unilateral contact with the switch law -> event"
        return "radau", f"auto: unilateral contact ({law} law) -> radau"
    if law == "switch":
        return "radau", "auto: switch law -> radau (method 'event' for true stick phases)"
    if full_order or n >= AUTO_LARGE_N:
        what = (
            f"full-order model ({n} dofs, {dense or 'sparse'})"
            if full_order
            else f"{n} coordinates"
        )
        return (
            METHOD,
            f"auto: {what}, {law} law -> {METHOD} (dt {AUTO_DT:g} s, factored once)",
        )
    return "radau", f"auto: {n} coordinates, {law} law -> radau (adaptive)"


def step_reason(reason: str, dt: float) -> str:
    """``reason`` naming the step ``dt`` that runs (a given one, or a record's finer sampling
    step) in place of :data:`AUTO_DT` (it said 0.005 s of a 2.5 ms run)."""
    return reason.replace(f"(dt {AUTO_DT:g} s", f"(dt {dt:g} s")


def choose_for_system(system, contact: str | None = None) -> tuple[str, str]:
    """:func:`choose_method` for an ``IsolatedSystem`` (contact default: its isolation's)."""
    iso = system.isolation
    law = iso.law if iso is not None else "none"
    contact = contact or getattr(iso, "contact", "detect")
    full = getattr(system, "sparse", None) is not None
    dense = ""
    if full:
        from nsdyn.solve.fullorder import dense_step

        dense = dense_step(system)
    return choose_method(system.n, law, contact, full_order=full, dense=dense)


def sparse_path(system, method: str, contact: str | None = None) -> bool:
    """True when ``method`` runs the full-order ``system`` on its sparse operators
    (:mod:`nsdyn.solve.fullorder`): ``genalpha-lowrank`` without unilateral contacts (default:
    the system's contact assumption), unless the model steps on its dense copies
    (:func:`nsdyn.solve.fullorder.dense_step`)."""
    if getattr(system, "sparse", None) is None or method != METHOD:
        return False
    if (contact or getattr(system.isolation, "contact", "detect")) == "unilateral":
        return False
    from nsdyn.solve.fullorder import dense_step

    return not dense_step(system)


def given_reason(system, method: str, contact: str | None = None) -> str:
    """``"given: 'radau'"``, the reason of a method given by name; for a full-order model with
    which operators it steps (``"given: 'genalpha-lowrank' (full-order model, 435 dofs,
    sparse)"``, or its dense copies and why), as ``auto``'s reason says."""
    if getattr(system, "sparse", None) is None:
        return f"given: {method!r}"
    from nsdyn.solve.fullorder import dense_step

    how = "sparse" if sparse_path(system, method, contact) else "dense"
    how = (method == METHOD and how == "dense" and dense_step(system)) or how
    return f"given: {method!r} (full-order model, {system.n} dofs, {how})"
