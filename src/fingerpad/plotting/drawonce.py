"""What matplotlib works out twice in one draw, worked out once: the same image, pixel for pixel.

Tick labels: matplotlib's ``Axis.draw`` finds the ticks to draw and their labels' boxes, draws them, and then
places the axis label beside those boxes (``_update_label_position``), which finds the ticks and
lays out every tick label a second time: ~7 % of a QC figure. Nothing changes in between, so
:func:`lay_out_ticks_once` lets the second pass reuse the first one's results; the image is the
same, pixel for pixel.

Legends at ``loc="best"``: ``Legend.draw`` asks for the legend box's extent, which places it
(``_find_best_position``: every candidate position against every line's vertices), and then
draws the box, which places it again with the same size; :func:`place_legend_once` keeps the
first answer for the second.

Both rely on private methods of matplotlib (the same from 3.8 to 3.11); where they are missing
the artist is left as it is.
"""

from __future__ import annotations

from typing import Any

__all__ = ["lay_out_ticks_once", "place_legend_once"]

_NEEDED = ("_update_ticks", "_get_ticklabel_bboxes", "_update_label_position", "draw")


def _memo_per_draw(artist: Any) -> dict[Any, Any]:
    """Wrap ``artist.draw`` so that the returned dict is emptied and marked ``"on"`` for the
    duration of each draw (and emptied after it): what is remembered in it lasts one draw."""
    draw = artist.draw
    memo: dict[Any, Any] = {}

    def drawing(renderer: Any, *args: Any, **kwargs: Any) -> Any:
        memo.clear()
        memo["on"] = True
        try:
            return draw(renderer, *args, **kwargs)
        finally:
            memo.clear()

    artist.draw = drawing
    return memo


def lay_out_ticks_once(axis: Any) -> None:
    """Make ``axis`` (a ``matplotlib.axis.Axis``) reuse, while it draws, the ticks and tick-label
    boxes it found first: what it computes to place its label is then not computed again.
    Outside a draw the axis behaves as before."""
    if not all(hasattr(axis, name) for name in _NEEDED) or "draw" in vars(axis):
        return
    update_ticks, bboxes = axis._update_ticks, axis._get_ticklabel_bboxes
    memo = _memo_per_draw(axis)

    def ticks_once() -> Any:
        if not memo.get("on"):
            return update_ticks()
        if "ticks" not in memo:
            memo["ticks"] = update_ticks()
        return memo["ticks"]

    def boxes_once(ticks: Any, renderer: Any) -> Any:
        if not memo.get("on") or ticks is not memo.get("ticks"):
            return bboxes(ticks, renderer)
        key = ("boxes", id(renderer))
        if key not in memo:
            memo[key] = bboxes(ticks, renderer)
        return memo[key]

    axis._update_ticks = ticks_once
    axis._get_ticklabel_bboxes = boxes_once


def place_legend_once(legend: Any) -> None:
    """Make ``legend`` (a ``matplotlib.legend.Legend``) place itself once per draw: a second
    request for the best position of a box of the same size in the same draw gets the first
    answer. Outside a draw the legend behaves as before."""
    if legend is None or not hasattr(legend, "_find_best_position") or "draw" in vars(legend):
        return
    best = legend._find_best_position
    memo = _memo_per_draw(legend)

    def best_once(width: float, height: float, renderer: Any) -> Any:
        if not memo.get("on"):
            return best(width, height, renderer)
        key = (width, height, id(renderer))
        if key not in memo:
            memo[key] = best(width, height, renderer)
        return memo[key]

    legend._find_best_position = best_once
