"""Fixed figure margins, in inches.

matplotlib's layout engines (``layout="constrained"``, ``tight_layout``) measure the extent of
every tick label and title to place the axes: about a third of the time a figure of six
panels takes to draw and save. The figures of a run have a known grid and labels of a known
kind, so their margins are set once, in inches (independent of the figure's size).
"""

from __future__ import annotations


def fixed_margins(fig, nrows: int, ncols: int, *, left: float = 0.95, right: float = 0.2,
                  bottom: float = 0.55, top: float = 0.35, wspace: float = 0.95,
                  hspace: float = 0.6) -> None:  # fmt: skip
    """Place the ``nrows x ncols`` grid of ``fig``'s subplots with the given margins [in]:
    ``left`` / ``bottom`` hold the tick labels and axis labels, ``top`` the (sup)title,
    ``wspace`` / ``hspace`` the labels between panels."""
    w, h = fig.get_size_inches()
    axw = (w - left - right - (ncols - 1) * wspace) / ncols
    axh = (h - top - bottom - (nrows - 1) * hspace) / nrows
    if axw <= 0 or axh <= 0:
        raise ValueError(f"margins leave no room for a {nrows} x {ncols} grid in {w} x {h} in")
    fig.subplots_adjust(left=left / w, right=1 - right / w, bottom=bottom / h, top=1 - top / h,
                        wspace=wspace / axw, hspace=hspace / axh)  # fmt: skip
