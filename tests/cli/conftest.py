"""Fixtures of the command-line tests."""

from __future__ import annotations

import pytest


@pytest.fixture
def one_line(capsys):
    """``check(*needles)``: stderr so far is one line, no traceback, holding every needle
    (the command-line convention of docs/reference/cli.md); returns the line."""

    def check(*needles) -> str:
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and "Traceback" not in err, err
        for n in needles:
            assert n in err, (n, err)
        return err

    return check
