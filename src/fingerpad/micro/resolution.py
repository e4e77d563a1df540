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
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import FingerpadError
from .bem import BEMUnitCell
from .companions import companion
from .pull_in import ADOPTED_RATIO_METHOD, adopted_ratio_error

if TYPE_CHECKING:
    from ..textures import Texture

__all__ = ["DEFAULT_ACCURACY", "MAX_AUTO_GRID", "MAX_STATE_GRID", "STATES", "GridChoice", "StateChoice",
           "choose_grid", "choose_state_grids", "estimate_method", "order_factor", "state_width"]

#: Target of the estimated relative error of A_re/A_fr when the grid is chosen automatically. The
#: estimate is conservative: on the default cell it is 2.8 % at grid 64 and 1.2 % at 128 where the
#: error against grid 256 is 1.2 % and 0.4 %; 2 % therefore takes the default cell to grid 128.
DEFAULT_ACCURACY = 0.02
#: The automatic choice stops at this many points along x (cost grows like the square).
MAX_AUTO_GRID = 512
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
        :func:`~fingerpad.micro.pull_in.adopted_ratio_error`.
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
    ``extrapolated``: the cell reports its transition extrapolated (:func:`~fingerpad.micro.pull_in.adopted_ratio_error`)."""
    if extrapolated:
        return ADOPTED_RATIO_METHOD
    order = float(getattr(cell_type, "convergence_order", 1.0))
    if order == 1.0:
        return "relative change from the half grid, |r_N / r_{N/2} - 1| (first-order convergence)"
    return (f"relative change from the half grid divided by 2^q - 1, |r_N / r_{{N/2}} - 1| / (2^q - 1) "
            f"(convergence of order q = {order:g} in the pixel: the adhesion range follows it)")


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
    #: estimate compares it with (:func:`~fingerpad.micro.pull_in.extrapolated_states`).
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
        :func:`~fingerpad.micro.pull_in.adopt_extrapolated`); its result is the choice's :attr:`GridChoice.extrapolated`.
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
