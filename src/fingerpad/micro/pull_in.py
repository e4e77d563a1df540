"""The transition of a pulled-in adhesive cell, extrapolated to a vanishing pixel.

With strong adhesion the skin sagging between a texture's asperities is pulled onto the base
from a distance (:attr:`~fingerpad.micro.adhesive_cell.AdhesiveUnitCell.pulled_in`), at a
pressure that converges slowly with the grid (docs/model.md 6.6, "Why the jump at w 0.3
converges slowly, and what is reported", and 6.6.1). Such a cell reports its transition
Richardson-extrapolated from its grid, the half and the quarter grid, with an estimate from the
eighth (:func:`extrapolated_states`); the grids' cells adopt it (:func:`adopt_extrapolated`), a
prediction prepares the companions it needs (:func:`pulled_in_companions`), and the error
estimate of A_re/A_fr charges the grid with its own jump (:func:`adopted_ratio_error`). The grid
choice that uses them is :mod:`fingerpad.micro.resolution`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any

import numpy as np

from .companions import companion, halve

if TYPE_CHECKING:
    from ..textures import Texture

__all__ = ["ADOPTED_RATIO_METHOD", "FADE_RATIO", "FOLD_RATIO", "PULL_IN_METHOD", "PULL_IN_NEXT_ORDER", "PULL_IN_ORDERS",
           "adopt_extrapolated", "adopted_ratio_error", "eighth_of", "extrapolated_states", "pulled_in_companions",
           "richardson"]


#: Orders in the pixel of the error of a pulled-in transition (an adhesive cell's
#: :attr:`~fingerpad.micro.adhesive_cell.AdhesiveUnitCell.pulled_in`), removed one after the
#: other by :func:`extrapolated_states`. The skin is pulled onto the base when the caps' contact
#: edges come within ``c`` pixels of their feet, so the pressure misses the edges' arrival by
#: ``c dx``: first order. ``c`` itself drifts with the cohesive zone's Maugis parameter, which
#: grows as ``dx^(-1/2)`` (the range follows the pixel as ``dx^(1/2)``): 2.4 to 3.0 pixels on
#: grids 64 to 512, a term of order 3/2. Measured on the default cell at ``w`` 0.3 J/m^2, grids 64
#: to 512: ``p* - a dx + b dx^(3/2)`` fits the grid's own transitions within 6 Pa (0.03 %), every
#: other pair of orders from {1/2, 1, 3/2, 2, 3} 6-30 times worse (docs/model.md 6.6).
PULL_IN_ORDERS = (1.0, 1.5)
#: Order of what the two extrapolations leave (the next power of ``dx^(1/2)``): the change of the
#: twice-extrapolated transition from the half grid is divided by ``2^q - 1`` for its estimate.
PULL_IN_NEXT_ORDER = 2.0
#: How :func:`extrapolated_states` makes a pulled-in transition's pressure and estimate, in words
#: (a state report's ``method``).
PULL_IN_METHOD = ("the skin was pulled onto the base from more than a range (docs/model.md 6.6): the pressure "
                  "extrapolated to a vanishing pixel with the orders 1 and 3/2 removed (Richardson on the grid, "
                  "its half and its quarter; p_N + (p_N - p_{N/2}) where only the half grid was pulled in); its "
                  "estimate |p / p' - 1|, p' the limit one order further with the eighth grid too (else the "
                  "farther of the extrapolation of one order less and the grid's own), at least the bracket's "
                  "width; where the grid's own changes shrink faster than those orders allow (a fold of the "
                  "branch, 6.6.1), the grid's own, compared with the farther of the half grid's and the "
                  "extrapolation; where the base's gap before the jump (in ranges) falls below 3/4 of the half "
                  "grid's, compared with the grid's own where that is farther; the load's: the same carried "
                  "through the pad, |F(p) / F(p') - 1|")
#: The grid's own transitions converge *faster* than the orders 1 and 3/2 allow where their change
#: from the half grid is at most this fraction of the half grid's change from the quarter grid
#: (``2^(-3/2)``: what an error of orders 1 and 3/2 of one sign shrinks by at most): the jump is
#: then a fold of the loading branch, which converges with the branch (Johnson's adhesive
#: sinusoid: changes shrinking by 0.11-0.27 per doubling, docs/model.md 6.6.1), not the pixel-bound
#: pull-in (the default cell: 0.6-0.9), and extrapolating at order 1 only amplifies the coarse
#: grids' error.
FOLD_RATIO = 2.0**-1.5
#: The pull-in *fades* where the base's gap before the jump, in ranges
#: (:attr:`~fingerpad.micro.adhesive_cell.AdhesiveUnitCell.pull_in_ranges`), falls below this
#: fraction of the half grid's: finer grids may touch the base instead, at a pressure below the
#: extrapolation (measured, docs/model.md 6.6.1: 0.55 and 0.72 at 128 on the taller caps and on the
#: default cell at ``w`` 0.15 J/m^2, both touched from 256 on, their limits 14 % and a few per
#: cent below the extrapolation; 0.93-0.97 on the default cell, 0.80-0.84 on the square lattice,
#: whose extrapolations hold to 0.1 %).
FADE_RATIO = 0.75


def richardson(values: "list[float]", orders: "tuple[float, ...]" = PULL_IN_ORDERS) -> float:
    """The value at a vanishing pixel of ``values`` (a quantity on grids ``N, N/2, N/4, ...``,
    finest first) whose error is a sum of terms ``c_i dx^(q_i)``: Richardson's extrapolation,
    the term of order ``orders[0]`` removed from each pair of neighbours, then ``orders[1]`` from
    each pair of those, ... as far as the values go (``len(values) - 1`` orders; one value: itself).
    Exact for ``values`` of that form."""
    level = [float(v) for v in values]
    for q in orders[: len(level) - 1]:
        factor = 1.0 / (2.0**q - 1.0)
        level = [fine + (fine - coarse) * factor for fine, coarse in zip(level[:-1], level[1:], strict=False)]
    return level[0]


def extrapolated_states(fine: Any, coarse: Any, quarter: Any = None,
                        eighth: Any = None) -> dict[str, tuple[float, float, float]]:
    """The state pressures of an adhesive cell whose transition was pulled in, extrapolated to a
    vanishing pixel (Richardson, :func:`richardson`, orders :data:`PULL_IN_ORDERS`).

    ``fine``, ``coarse``, ``quarter``, ``eighth``: prepared adhesive cells of the same texture at
    ``N``, ``N/2``, ``N/4`` and ``N/8`` points along x (``quarter``, ``eighth`` may be ``None``;
    ``eighth`` is then made from ``quarter``'s texture block-averaged 2 x 2, :func:`eighth_of`, a
    sixty-fourth of ``fine``'s work). Only where ``fine`` and ``coarse`` were both pulled in; the
    full contact with it where it came with the transition on ``fine`` (the same bracket: the jump
    into full contact) or where ``fine``'s own lies below the extrapolated transition (full
    contact cannot precede it). Returns per state ``(pressure, compared, error)`` (Pa, Pa, -), the error
    ``|pressure / compared - 1|`` (at least the bracket's relative width):

    * the grid's own changes shrinking faster than the orders 1 and 3/2 allow (by at most
      :data:`FOLD_RATIO` from the quarter's to the half grid's, :func:`_converges_faster`): a fold
      of the branch (docs/model.md 6.6.1), the pressure is the grid's own ``p_N``, compared with
      the farther of ``p_{N/2}`` (the change undivided) and the extrapolation below;
    * ``quarter`` and ``eighth`` pulled in: the pressure :func:`richardson` of ``p_N, p_{N/2},
      p_{N/4}`` (orders 1 and 3/2 removed); compared with the limit the next order
      (:data:`PULL_IN_NEXT_ORDER`) gives with ``p_{N/8}`` as well, which moves it by the change
      from the half grid's value over ``2^2 - 1`` (exact for an error of that order). Where the
      four grids do not take the assumed form (:func:`_asymptotic`), compared instead with the
      farther of the half grid's value (the change undivided) and the limit at the order the
      three finest grids' own changes show (:func:`_own_order_limit`, where they show one);
    * ``quarter`` only: the same pressure, compared with the farther of the first-order
      extrapolation ``p1 = p_N + (p_N - p_{N/2})`` (the last correction) and the grid's own
      ``p_N``: three grids cannot tell the assumed form from a fold (6.6.1), whose limit is near
      ``p_N``;
    * ``fine`` and ``coarse`` only: ``p1``, compared with the grid's own ``p_N``;
    * and wherever the pull-in fades from the half grid to the grid (:func:`_fading`: the base's
      gap before the jump, in ranges, below :data:`FADE_RATIO` of the half grid's), compared with
      the farther of the above and ``p_N``: finer grids may touch the base at a pressure below
      the extrapolation (docs/model.md 6.6.1).

    Empty where nothing is extrapolated."""
    if coarse is None or not (getattr(fine, "pulled_in", False) and getattr(coarse, "pulled_in", False)):
        return {}
    chain = [fine, coarse]
    if quarter is not None and getattr(quarter, "pulled_in", False):
        chain.append(quarter)
        if eighth is None:
            eighth = eighth_of(quarter)
        if eighth is not None and getattr(eighth, "pulled_in", False):
            chain.append(eighth)
    own = [c.own_state_pressure("transition") for c in chain]
    if not all(math.isfinite(v) and v > 0 for v in own):
        return {}
    p = richardson(own[:3])
    if len(own) >= 3 and _converges_faster(own[:3]):
        # a fold of the branch: the grid's own is the answer, the extrapolation only bounds it
        p, candidates = own[0], [own[1], richardson(own[:3])]
        compared = max((c for c in candidates if c > 0), key=lambda c: abs(p / c - 1.0), default=math.nan)
    elif len(own) == 4:
        if _asymptotic(own):
            compared = richardson(own, PULL_IN_ORDERS + (PULL_IN_NEXT_ORDER,))
        else:
            candidates = [richardson(own[1:4]), _own_order_limit(own[:3])]
            compared = max((c for c in candidates if c > 0), key=lambda c: abs(p / c - 1.0), default=math.nan)
    elif len(own) == 3:
        # three grids cannot check the form: the estimate reaches back to the grid's own
        compared = max((richardson(own[:2]), own[0]), key=lambda c: abs(p / c - 1.0))
    else:
        compared = own[0]  # p1 = p_N + (p_N - p_{N/2}), compared with p_N
    if _fading(fine, coarse) and math.isfinite(compared):
        # a finer grid may touch the base below the extrapolation: the estimate reaches to the own
        compared = max((compared, own[0]), key=lambda c: abs(p / c - 1.0))
    if not (math.isfinite(p) and p > 0 and math.isfinite(compared) and compared > 0):
        return {}
    error = max(abs(p / compared - 1.0), fine.rtol)
    out = {"transition": (p, compared, error)}
    # the full contact with it where it came at the transition on the grid reported (the jump
    # into full contact), or where the grid's own comes below it: it cannot precede the transition
    if (fine.full is not None and fine.full == fine.transition) or fine.own_state_pressure("full") < p:
        out["full"] = (p, compared, error)
    return out


def adopt_extrapolated(cells: dict[int, Any], grid: int) -> dict[str, tuple[float, float, float]]:
    """The one place an adhesive cell reports its pulled-in transition extrapolated (docs/model.md
    6.6): the cell at ``grid`` points along x adopts :func:`extrapolated_states` from itself and
    the cells at ``grid / 2``, ``grid / 4`` and ``grid / 8`` (``cells``: prepared adhesive cells of
    one texture by grid points along x; those missing count as ``None``), so that its zones, critical load
    and ``psi(p)`` all jump there
    (:meth:`~fingerpad.micro.adhesive_cell.AdhesiveUnitCell.adopt_pressure`); the half grid's
    cell adopts its own (from ``grid / 2`` to ``/ 16``) where it has one, so that it too reports
    one transition (the grid's estimate moves the half grid's jump to the grid's for the
    comparison, :func:`adopted_ratio_error`). Returns the cell's
    ``{state: (pressure, coarse pressure, error)}`` (empty: nothing extrapolated)."""
    fine = cells.get(grid)
    if fine is None:
        return {}
    out = extrapolated_states(fine, cells.get(grid // 2), cells.get(grid // 4), cells.get(grid // 8))
    for name, (p, _, _) in out.items():
        fine.adopt_pressure(name, p)
    coarse = cells.get(grid // 2)
    if out and coarse is not None:
        for name, (p, _, _) in extrapolated_states(coarse, cells.get(grid // 4), cells.get(grid // 8),
                                                   cells.get(grid // 16)).items():
            coarse.adopt_pressure(name, p)
    return out


#: How the A_re/A_fr estimate of a cell reporting an extrapolated transition is made, in words
#: (a resolution report's ``method``; :func:`adopted_ratio_error`).
ADOPTED_RATIO_METHOD = ("per load, the change from the half grid with the half grid's jump moved to the grid's "
                        "reported transition, |r_N / r~_{N/2} - 1| / (2^q - 1) (the branch and what lies past the "
                        "jump, order q = 1/2), plus the change of r_N when the jump moves by the transition's own "
                        "estimate, max |r_N(p_t (1 +- e_t)) / r_N - 1| (where the jump comes); the largest over the "
                        "loads")


@contextmanager
def _adopting(cell: Any, pressures: dict[str, float]) -> Iterator[None]:
    """``cell`` reporting ``pressures`` (Pa, by state) for the block, its reported states as
    before afterwards (:meth:`~fingerpad.micro.adhesive_cell.AdhesiveUnitCell.adopt_pressure`)."""
    before = {name: cell.reported_state_pressure(name) for name in pressures}
    own = {name: cell.own_state_pressure(name) for name in pressures}
    try:
        for name, p in pressures.items():
            cell.adopt_pressure(name, p)
        yield
    finally:
        for name, p in before.items():
            cell.adopt_pressure(name, None if p == own[name] else p)


def adopted_ratio_error(fine: Any, coarse: Any, ratio: Callable[[Any], np.ndarray],
                        settled: dict[str, tuple[float, float, float]], factor: float) -> np.ndarray:
    """Per load, the estimated relative error of ``ratio(fine)`` (A_re/A_fr) for a cell that
    reports its transition extrapolated (``settled``: :func:`adopt_extrapolated`'s
    ``{state: (pressure, compared, error)}``; docs/model.md 6.6, "The error of A_re/A_fr with a
    reported transition").

    Its error has two parts, estimated each from what is uncertain on the grid itself:

    * the branch (below the jump, its continuation, what lies past the jump): the change from
      the half grid's curve with *its* jump moved to where the grid reports it (``coarse``
      adopting ``settled``'s pressures), ``|r_N / r~_{N/2} - 1|``, scaled to the error left by
      ``factor`` (``1 / (2^q - 1)``, :func:`~fingerpad.micro.resolution.order_factor`);
    * where the jump comes: the change of ``r_N`` when the reported states move by the
      transition's own estimate ``e_t`` (both ways), ``max |r_N(p (1 +- e_t)) / r_N - 1|``.

    Comparing the curves each grid reports instead would charge the grid with the half grid's
    error of the jump's position (on the default cell at ``w`` 0.3 J/m^2, grid 256: 3.3 % of the
    3.8 % change at 1 N comes from grid 128's transition lying 3.9 % lower; its own estimate of
    that, 3.7 %, is carried by the half grid, not the grid). The sum is returned (NaN where a
    ratio is not finite); both cells report as before afterwards."""
    r = np.asarray(ratio(fine), float)
    with _adopting(coarse, {name: p for name, (p, _, _) in settled.items()}):
        aligned = np.asarray(ratio(coarse), float)
    branch = np.abs(r / aligned - 1.0) * factor
    e = float(settled["transition"][2])
    jump = np.zeros_like(r)
    for scale in (1.0 - e, 1.0 + e):
        with _adopting(fine, {name: p * scale for name, (p, _, _) in settled.items()}):
            jump = np.maximum(jump, np.abs(np.asarray(ratio(fine), float) / r - 1.0))
    return branch + jump


def pulled_in_companions(cell: Any, make_texture: Callable[[int], "Texture"] | None,
                         make_cell: Callable[["Texture"], Any], cells: dict[int, Any]) -> int:
    """Add to ``cells`` (by grid points along x) the companions :func:`adopt_extrapolated` needs
    for ``cell``: where ``cell`` was pulled in, its half grid's, and where that was pulled in
    too, the quarter grid's, and so the eighth's (1/4, 1/16 and 1/64 of the work of the grid; the
    eighth feeds the estimate only), each made by
    ``make_cell(texture)`` (prepared) on :func:`~fingerpad.micro.companions.companion`'s texture, unless ``cells`` holds it.
    Returns the solves added."""
    solves = 0
    current = cell
    for _ in range(3):
        if current.flat or not current.pulled_in:
            break
        n = int(current.texture.shape[0]) // 2
        if n not in cells:
            tex = companion(make_texture, current.texture)
            if tex is None:
                break
            made = make_cell(tex)
            cells[int(tex.shape[0])] = made
            solves += made.solves
        current = cells[n]
    return solves


def _asymptotic(own: "list[float]") -> bool:
    """Whether four grids' transitions (finest first) take the form the extrapolations assume, an
    error with no term below first order: what the first-order extrapolation leaves shrinks
    faster than an error of order 1/2 (by less than ``2^(-1/2)`` per doubling; ``2^(-3/2)`` once
    only the order 3/2 is left; measured on the default cell at ``w`` 0.3 J/m^2: 0.48 on grids 32
    to 256, 0.34 on 64 to 512), and the second extrapolation moves less than the first."""
    e = [richardson(own[i:i + 2]) for i in range(3)]
    d_fine, d_coarse = e[0] - e[1], e[1] - e[2]
    d_second = richardson(own[:3]) - richardson(own[1:4])
    return abs(d_fine) < 2.0**-0.5 * abs(d_coarse) and abs(d_second) < abs(d_fine)


def _fading(fine: Any, coarse: Any) -> bool:
    """Whether the pull-in fades from ``coarse`` to ``fine`` (the half grid to the grid): the
    base's gap before the jump, in ranges, falls below :data:`FADE_RATIO` of the half grid's
    (False where a cell does not say)."""
    g, gc = (float(getattr(c, "pull_in_ranges", math.nan)) for c in (fine, coarse))
    return math.isfinite(g) and math.isfinite(gc) and g < FADE_RATIO * gc


def _converges_faster(own: "list[float]") -> bool:
    """Whether three grids' transitions (finest first) converge faster than an error of orders 1
    and 3/2 of one sign can: the change from the half grid at most :data:`FOLD_RATIO` of the
    half grid's change from the quarter (both changes zero included: the same bracket)."""
    return abs(own[0] - own[1]) <= FOLD_RATIO * abs(own[1] - own[2])


def _own_order_limit(own: "list[float]") -> float:
    """The limit of three grids' values (finest first) at the order their own changes show,
    ``p_N + (p_N - p_{N/2}) r / (1 - r)`` with ``r = (p_N - p_{N/2}) / (p_{N/2} - p_{N/4})``
    (Aitken's); NaN where the changes do not shrink monotonically (no order to read)."""
    d_fine, d_coarse = own[0] - own[1], own[1] - own[2]
    r = d_fine / d_coarse if d_coarse != 0 else math.nan
    return own[0] + d_fine * r / (1.0 - r) if 0.0 < r < 1.0 else math.nan


def eighth_of(quarter: Any) -> Any:
    """The adhesive cell of ``quarter``'s texture block-averaged 2 x 2 (:func:`~fingerpad.micro.companions.halve`), with its
    settings and cache, prepared; ``None`` where the texture cannot be halved (as a measured
    map's companion is made: the cell does not know its texture's generator). On the default
    caps at ``w`` 0.3 J/m^2 its transition bracket is the generated grid 32's."""
    tex = halve(quarter.texture)
    if tex is None:
        return None
    return quarter.sibling(tex).prepare()
