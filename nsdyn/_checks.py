"""Argument checks shared by the public entry points: an object of the wrong kind is a
TypeError naming the argument, what was expected and how to make one (instead of an
AttributeError from deep inside a model)."""

from __future__ import annotations


def expect(name: str, value, ok: bool, what: str) -> None:
    """Raise ``TypeError("{name}: expected {what}, got {type}")`` unless ``ok``."""
    if not ok:
        raise TypeError(f"{name}: expected {what}, got {type(value).__name__}")
