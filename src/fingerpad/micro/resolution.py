"""The grid of a BEM unit cell chosen by a stated accuracy, with its error estimate.

The real-to-ridge area ratio A_re/A_fr of a texture converges with the cell's grid at about first
order (the contact perimeter is resolved to a pixel): on the default cell (caps R 100 um,
h 20 um, hexagonal spacing 175 um) it is 3 %, 1.2 % and 0.4 % high at grids 32, 64 and 128
against grid 256. So the difference between a grid and its half, ``|r_N / r_{N/2} - 1|``, is a
(slightly conservative) estimate of the error of ``r_N``. :func:`choose_grid` doubles the grid
from its start until that estimate is below the target, or uses a given grid and only reports
the estimate. The coarse half-grid cell costs about a quarter of the fine one.

The state pressures (transition, full contact) have grids of their own, chosen the same way by
their own convergence (:func:`choose_state_grids`): a state load is a property of the texture
and the finger, so its grid must not follow the loads asked for, as the curve's does (issue 31:
on the default cell the full-contact pressure is 160.7 kPa at grid 64 and 170.3 kPa at 128, and
the grid the curve took over 1-1000 N or 0.1-4 N decided which was reported).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import FingerpadError, ResolutionWarning
from .bem import BEMUnitCell

if TYPE_CHECKING:
    from ..textures import Texture

__all__ = ["DEFAULT_ACCURACY", "MAX_AUTO_GRID", "MAX_STATE_GRID", "PULL_IN_METHOD", "STATES", "GridChoice",
           "StateChoice", "adopt_extrapolated", "adopted_ratio_error", "choose_grid", "choose_state_grids", "companion", "eighth_of",
           "estimate_method", "extrapolated_states", "halve", "order_factor", "pulled_in_companions", "richardson",
           "state_width"]

#: Target of the estimated relative error of A_re/A_fr when the grid is chosen automatically. The
#: estimate is conservative: on the default cell it is 2.8 % at grid 64 and 1.2 % at 128 where the
#: error against grid 256 is 1.2 % and 0.4 %; 2 % therefore takes the default cell to grid 128.
DEFAULT_ACCURACY = 0.02
#: The automatic choice stops at this many points along x (cost grows like the square).
MAX_AUTO_GRID = 512
#: Grids below this many points along x have no coarser companion for the estimate.
MIN_COMPANION_GRID = 16
#: The automatic choice of a state pressure's grid stops at this many points along x. A state
#: bracket is ~13 cold solves near that state (~1 s of CPU at 256 x 448 on the default cell, ~7 s
#: at 512 x 882, measured on the shared 2-core machine); where a state converges slowly with the
#: grid (the default cell's full contact: 6.0, 4.3 and 3.4 % from 64 to 128, 256 and 512) 512
#: buys little for that cost, and the estimate reported beside the state says how far it is.
MAX_STATE_GRID = 256
#: How the half-grid companion of :func:`choose_grid`'s first grid is prepared (options of a
#: :class:`BEMUnitCell`): it only feeds the error estimates, so its curve is refined where psi
#: steps by more than 0.06 (the reported cell: 0.04) and its full-contact bracket is bisected to
#: a relative width of 1e-2 (the reported cell: 1e-3; a full-contact pressure's grid error is
#: some 4-35 %, the transition's 0.1-1.5 %, whose bracket keeps 1e-3). The full-contact width
#: joins the cache key (the companion's entry is its own). Measured (benchmarks/cell_change.py,
#: docs/solver.md "The companion of an estimate"): every reported number keeps its bits, the
#: estimates move by -5 to +8 % of themselves, the sweep cells' solves fall by 8 %.
COMPANION_OPTIONS: dict[str, Any] = {"psi_step": 0.06, "full_rtol": 1e-2}
#: The state pressures a cell brackets, and the attribute of each.
STATES = {"transition": "transition_pressure", "full": "full_contact_pressure"}


@dataclass
class GridChoice:
    """The prepared cell and what is known of its discretisation error.

    Attributes
    ----------
    cell
        The chosen, prepared BEM cell.
    coarse
        The companion cell at half the grid (``None`` if none could be made).
    error
        Estimated relative error of A_re/A_fr over the loads, ``|r_N / r_{N/2} - 1|`` (NaN
        without a companion), divided by ``2^q - 1`` for a cell of convergence order ``q``
        below 1 (:func:`order_factor`); for a cell reporting its transition extrapolated,
        :func:`adopted_ratio_error`.
    target
        The accuracy asked for (``None`` when the grid was given).
    history
        ``(grid points along x, estimated error)`` of each grid tried.
    """

    cell: BEMUnitCell
    coarse: BEMUnitCell | None
    error: float
    target: float | None
    history: list[tuple[int, float]] = field(default_factory=list)
    solves: int = 0
    #: Every cell prepared for the choice, by grid points along x (the state grids reuse them).
    cells: dict[int, BEMUnitCell] = field(default_factory=dict)
    #: What ``settle`` reported of the chosen cell (:func:`choose_grid`): an adhesive cell's
    #: extrapolated states, ``{state: (pressure, coarse pressure, error)}`` (empty: none).
    extrapolated: dict[str, Any] = field(default_factory=dict)

    @property
    def met(self) -> bool | None:
        """Whether the estimate is within the target (``None`` without a target or an estimate)."""
        if self.target is None or math.isnan(self.error):
            return None
        return self.error <= self.target

    def state_pressure_errors(self) -> dict[str, float]:
        """Relative change of the transition and full-contact pressures from the half grid (at
        least the brackets' relative width: below it the change is not resolved)."""
        if self.coarse is None:
            return dict.fromkeys(STATES, math.nan)
        factor = order_factor(type(self.cell))
        return {name: _state_error(self.cell, self.coarse, name) * factor for name in STATES}


def order_factor(cell_type: Any) -> float:
    """``1 / (2^q - 1)``: the error left after a grid whose change from the half grid is 1, for a
    cell converging with order ``q`` in the pixel (its ``convergence_order``; 1 when it declares
    none, the factor then exactly 1). An adhesive cell converges with order 1/2 (factor 2.4)."""
    order = float(getattr(cell_type, "convergence_order", 1.0))
    return 1.0 / (2.0**order - 1.0)


def estimate_method(cell_type: Any, extrapolated: bool = False) -> str:
    """How the error estimate of ``cell_type``'s grid is made, in words (the reports' ``method``);
    ``extrapolated``: the cell reports its transition extrapolated (:func:`adopted_ratio_error`)."""
    if extrapolated:
        return ADOPTED_RATIO_METHOD
    order = float(getattr(cell_type, "convergence_order", 1.0))
    if order == 1.0:
        return "relative change from the half grid, |r_N / r_{N/2} - 1| (first-order convergence)"
    return (f"relative change from the half grid divided by 2^q - 1, |r_N / r_{{N/2}} - 1| / (2^q - 1) "
            f"(convergence of order q = {order:g} in the pixel: the adhesion range follows it)")


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
      ``factor`` (``1 / (2^q - 1)``, :func:`order_factor`);
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
    ``make_cell(texture)`` (prepared) on :func:`companion`'s texture, unless ``cells`` holds it.
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
    """The adhesive cell of ``quarter``'s texture block-averaged 2 x 2 (:func:`halve`), with its
    settings and cache, prepared; ``None`` where the texture cannot be halved (as a measured
    map's companion is made: the cell does not know its texture's generator). On the default
    caps at ``w`` 0.3 J/m^2 its transition bracket is the generated grid 32's."""
    tex = halve(quarter.texture)
    if tex is None:
        return None
    return quarter.sibling(tex).prepare()


def _state_error(fine: BEMUnitCell, coarse: BEMUnitCell, name: str) -> float:
    """``|p_N / p_{N/2} - 1|`` of a state pressure (at least the brackets' relative widths, below
    which the change is not resolved: a first companion's full-contact width is 1e-2,
    :data:`COMPANION_OPTIONS`); NaN where neither grid reaches the state (beyond the search cap
    at both: nothing to refine), inf where one does and the other not."""
    f, c = fine.own_state_pressure(name), coarse.own_state_pressure(name)
    if math.isinf(f) and math.isinf(c):
        return math.nan
    if not (math.isfinite(f) and math.isfinite(c)):
        return math.inf
    if f <= 0 or c <= 0:
        return 0.0 if f == c else math.inf
    return max(abs(f / c - 1.0), state_width(fine, name), state_width(coarse, name))


def state_width(cell: Any, name: str) -> float:
    """The relative width of ``cell``'s bracket of state ``name`` (its ``state_rtol``, else its
    ``rtol``: an adhesive cell brackets both states to one width)."""
    width = getattr(cell, "state_rtol", None)
    return float(width(name)) if callable(width) else float(cell.rtol)


@dataclass
class StateChoice:
    """The grid of one state pressure, chosen by the state's own convergence, and its estimate.

    Attributes
    ----------
    state
        ``"transition"`` or ``"full"``.
    cell, coarse
        The cell whose bracket is reported and its half-grid companion (``None``: none).
    error
        Estimated relative error of the state pressure, ``|p_N / p_{N/2} - 1|`` (at least the
        bracket's relative width; NaN without a companion or with the state beyond the search cap
        on both grids; inf when one grid reaches it and the other not).
    target
        The accuracy asked for (``None``: the grid was not chosen, it is the curve's).
    history
        ``(grid points along x, estimated error)`` of each grid tried.
    """

    state: str
    cell: BEMUnitCell
    coarse: BEMUnitCell | None
    error: float
    target: float | None
    history: list[tuple[int, float]] = field(default_factory=list)

    @property
    def met(self) -> bool | None:
        """Whether the estimate is within the target (``None`` without a target or an estimate)."""
        if self.target is None or math.isnan(self.error):
            return None
        return self.error <= self.target

    #: The pressure reported instead of the grid's own (Pa; ``None``: the own), and what its
    #: estimate compares it with (:func:`extrapolated_states`).
    reported: float | None = None
    reported_coarse: float | None = None

    @property
    def pressure(self) -> float:
        """The state pressure (Pa) on the chosen grid (extrapolated where :attr:`reported`)."""
        return self.cell.own_state_pressure(self.state) if self.reported is None else self.reported

    @property
    def coarse_pressure(self) -> float:
        """The state pressure (Pa) on the half grid (NaN without one), or what an extrapolated
        pressure is compared with."""
        if self.reported_coarse is not None:
            return self.reported_coarse
        return math.nan if self.coarse is None else self.coarse.own_state_pressure(self.state)


def halve(texture: "Texture") -> "Texture | None":
    """The texture block-averaged 2 x 2 (``None`` if a side is odd or too short)."""
    nx, ny = texture.shape
    if nx % 2 or nx // 2 < MIN_COMPANION_GRID:
        return None
    h = texture.heights
    if ny == 1 or ny % 2:
        if ny % 2 and ny != 1:
            return None
        hc = h.reshape(nx // 2, 2, ny).mean(axis=1)
    else:
        hc = h.reshape(nx // 2, 2, ny // 2, 2).mean(axis=(1, 3))
    return replace(texture, heights=hc)


def choose_grid(
    make_texture: Callable[[int], "Texture"] | None,
    texture: "Texture",
    modulus: float,
    p_range: tuple[float, float],
    ratio: Callable[[BEMUnitCell], np.ndarray],
    *,
    target: float | None = DEFAULT_ACCURACY,
    max_grid: int = MAX_AUTO_GRID,
    cell_options: dict[str, Any] | None = None,
    progress: Callable[[int, int], None] | None = None,
    cell_type: Callable[..., Any] = BEMUnitCell,
    settle: Callable[[Any, dict[int, Any]], dict[str, Any]] | None = None,
) -> GridChoice:
    """Prepare the BEM cell of ``texture`` and estimate (or bound) its discretisation error.

    Parameters
    ----------
    make_texture
        ``make_texture(nx)`` builds the same texture on another grid (generated textures);
        ``None`` for a measured map, whose companion is the map block-averaged 2 x 2 and whose
        grid is never raised.
    texture
        The texture at the starting grid.
    modulus
        Reduced modulus E* (Pa), Eq. 3.4.
    p_range
        Local pressures (Pa) the cell is prepared over.
    ratio
        ``ratio(cell)``: the quantity whose error is estimated, A_re/A_fr at the study's loads.
    target
        Accuracy to reach by doubling the grid (relative error of ``ratio``); ``None`` to keep
        the starting grid and only report the estimate.
    max_grid
        Largest grid along x the doubling may reach.
    cell_options
        Keyword arguments of :class:`BEMUnitCell` (tolerance, cache, ...).
    progress
        ``progress(i, n)`` after each solve of the fine cells.
    cell_type
        The cell's class: :class:`BEMUnitCell`, or
        :class:`~fingerpad.micro.adhesive_cell.AdhesiveUnitCell` for an adhesive skin (whose
        range follows the pixel, so the estimate measures both together; its
        ``convergence_order``, 1/2, scales the change to the error left: :func:`order_factor`).
    settle
        ``settle(cell, cells)`` before each estimate, ``cells`` the prepared cells by grid points
        along x (it may add some): what the cell reports beyond its own curve, settled before
        its ``ratio`` is read (an adhesive cell's extrapolated transition,
        :func:`adopt_extrapolated`); its result is the choice's :attr:`GridChoice.extrapolated`.
    """
    opts = dict(cell_options or {})

    cells: list[BEMUnitCell] = []

    def prepared(tex: "Texture", report: bool, extra: dict[str, Any] | None = None) -> BEMUnitCell:
        cells.append(cell_type(tex, modulus, **{**opts, **(extra or {})}).prepare(
            *p_range, progress=progress if report else None))
        return cells[-1]

    # the change from the half grid is the error of first-order convergence; a cell that
    # converges slower (order q) declares it, and the change is scaled to the error left,
    # 1 / (2^q - 1) times the change (an adhesive cell: docs/model.md 6.6)
    factor = order_factor(cell_type)
    fine_tex = texture
    coarse_tex = companion(make_texture, fine_tex)
    # the first companion only feeds the estimate: a lighter curve (COMPANION_OPTIONS; an
    # adhesive cell keeps its own plan); a companion after a doubling is the grid before, as is
    lighter = dict(COMPANION_OPTIONS) if cell_type is BEMUnitCell else {}
    coarse = prepared(coarse_tex, False, lighter) if coarse_tex is not None else None
    fine = prepared(fine_tex, True)
    history: list[tuple[int, float]] = []
    settled: dict[str, Any] = {}
    while True:
        error = math.nan
        if settle is not None:
            held = _by_grid(cells)
            settled = settle(fine, held)
            cells.extend(c for c in held.values() if not any(c is d for d in cells))
        if coarse is not None:
            with np.errstate(divide="ignore", invalid="ignore"):
                if "transition" in settled:  # a transition reported extrapolated: its own rule
                    rel = adopted_ratio_error(fine, coarse, ratio, settled, factor)
                else:
                    rel = (np.asarray(ratio(fine), float) / np.asarray(ratio(coarse), float) - 1.0) * factor
            rel = rel[np.isfinite(rel)]
            error = float(np.max(np.abs(rel))) if rel.size else math.nan
        history.append((fine_tex.shape[0], error))
        grow = (target is not None and make_texture is not None and not math.isnan(error)
                and error > target and 2 * fine_tex.shape[0] <= max_grid)
        if not grow:
            return GridChoice(fine, coarse, error, target, history, sum(c.solves for c in cells), _by_grid(cells),
                              settled)
        try:
            next_tex = make_texture(2 * fine_tex.shape[0])  # type: ignore[misc]
        except FingerpadError:
            return GridChoice(fine, coarse, error, target, history, sum(c.solves for c in cells), _by_grid(cells),
                              settled)
        coarse, fine_tex = fine, next_tex
        fine = prepared(fine_tex, True)


def companion(make_texture: Callable[[int], "Texture"] | None, tex: "Texture") -> "Texture | None":
    """The half-grid companion of ``tex``: the generator at half the grid, else the map
    block-averaged 2 x 2 (``None`` if neither exists)."""
    nx = tex.shape[0]
    if make_texture is not None and nx // 2 >= MIN_COMPANION_GRID and nx % 2 == 0:
        try:
            with warnings.catch_warnings():  # coarse on purpose: it only measures the convergence
                warnings.simplefilter("ignore", ResolutionWarning)
                return make_texture(nx // 2)
        except FingerpadError:
            return halve(tex)
    return halve(tex)


def _by_grid(cells: list[BEMUnitCell]) -> dict[int, BEMUnitCell]:
    return {int(c.texture.shape[0]): c for c in cells}


def choose_state_grids(
    make_texture: Callable[[int], "Texture"] | None,
    texture: "Texture",
    modulus: float,
    *,
    target: float | None = DEFAULT_ACCURACY,
    max_grid: int = MAX_STATE_GRID,
    cell_options: dict[str, Any] | None = None,
    cells: dict[int, BEMUnitCell] | None = None,
) -> tuple[dict[str, StateChoice], int]:
    """The grid of each state pressure (transition, full contact), chosen by its own convergence.

    From the starting grid (``texture``, the curve's start) and its half-grid companion, the grid
    of each state is doubled until ``|p_N / p_{N/2} - 1|`` is within ``target`` or the next grid
    would pass ``max_grid``; a cell made for this brackets the states only
    (:meth:`BEMUnitCell.prepare_states`, no curve). Nothing here depends on the loads asked for.
    ``target=None`` (or a measured map, ``make_texture=None``) keeps the starting grid and only
    reports the estimate.

    Parameters
    ----------
    make_texture, texture, modulus, target, max_grid, cell_options
        As :func:`choose_grid`.
    cells
        Cells already prepared (grid points along x -> cell, e.g. :attr:`GridChoice.cells`):
        reused, their states are bracketed already.

    Returns
    -------
    choices, solves
        Per state its :class:`StateChoice`, and the unit-cell solves this call added.
    """
    opts = dict(cell_options or {})
    known: dict[int, BEMUnitCell] = dict(cells or {})
    solves = 0

    def cell_at(tex: "Texture") -> BEMUnitCell:
        nonlocal solves
        nx = int(tex.shape[0])
        cell = known.get(nx)
        if cell is None or cell.texture.shape != tex.shape:
            cell = known[nx] = BEMUnitCell(tex, modulus, **opts)
        before = cell.solves
        cell.prepare_states()
        solves += cell.solves - before
        return cell

    start_tex = texture
    coarse_tex = companion(make_texture, start_tex)
    out: dict[str, StateChoice] = {}
    for name in STATES:
        fine_tex = start_tex
        fine = cell_at(fine_tex)
        coarse = cell_at(coarse_tex) if coarse_tex is not None else None
        history: list[tuple[int, float]] = []
        while True:
            error = _state_error(fine, coarse, name) if coarse is not None else math.nan
            history.append((int(fine_tex.shape[0]), error))
            grow = (target is not None and make_texture is not None and not math.isnan(error)
                    and error > target and 2 * fine_tex.shape[0] <= max_grid)
            if grow:
                try:
                    next_tex = make_texture(2 * fine_tex.shape[0])  # type: ignore[misc]
                except FingerpadError:
                    grow = False
            if not grow:
                out[name] = StateChoice(name, fine, coarse, error, target if make_texture is not None else None,
                                        history)
                break
            coarse, fine_tex = fine, next_tex
            fine = cell_at(fine_tex)
    return out, solves
