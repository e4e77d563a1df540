"""The grid of a BEM unit cell chosen by a stated accuracy, with its error estimate.

The real-to-ridge area ratio A_re/A_fr of a texture converges with the cell's grid at about first
order (the contact perimeter is resolved to a pixel): on the default cell (caps R 100 um,
h 20 um, hexagonal spacing 175 um) it is 3 %, 1.2 % and 0.4 % high at grids 32, 64 and 128
against grid 256. So the difference between a grid and its half, ``|r_N / r_{N/2} - 1|``, is a
(slightly conservative) estimate of the error of ``r_N``. :func:`choose_grid` doubles the grid
from its start until that estimate is below the target, or uses a given grid and only reports
the estimate. The coarse half-grid cell costs about a quarter of the fine one.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import FingerpadError, ResolutionWarning
from .bem import BEMUnitCell

if TYPE_CHECKING:
    from ..textures import Texture

__all__ = ["DEFAULT_ACCURACY", "MAX_AUTO_GRID", "GridChoice", "choose_grid", "halve"]

#: Target of the estimated relative error of A_re/A_fr when the grid is chosen automatically. The
#: estimate is conservative: on the default cell it is 2.8 % at grid 64 and 1.2 % at 128 where the
#: error against grid 256 is 1.2 % and 0.4 %; 2 % therefore takes the default cell to grid 128.
DEFAULT_ACCURACY = 0.02
#: The automatic choice stops at this many points along x (cost grows like the square).
MAX_AUTO_GRID = 512
#: Grids below this many points along x have no coarser companion for the estimate.
MIN_COMPANION_GRID = 16


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
        without a companion).
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

    @property
    def met(self) -> bool | None:
        """Whether the estimate is within the target (``None`` without a target or an estimate)."""
        if self.target is None or math.isnan(self.error):
            return None
        return self.error <= self.target

    def state_pressure_errors(self) -> dict[str, float]:
        """Relative change of the transition and full-contact pressures from the half grid (at
        least the brackets' relative width: below it the change is not resolved)."""
        out = {}
        if self.coarse is None:
            return {"transition": math.nan, "full": math.nan}
        for name, attr in (("transition", "transition_pressure"), ("full", "full_contact_pressure")):
            fine, coarse = getattr(self.cell, attr), getattr(self.coarse, attr)
            ok = math.isfinite(fine) and math.isfinite(coarse) and fine > 0 and coarse > 0
            out[name] = max(abs(fine / coarse - 1.0), self.cell.rtol) if ok else math.nan
        return out


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
        range follows the pixel, so the estimate measures both together).
    """
    opts = dict(cell_options or {})

    cells: list[BEMUnitCell] = []

    def prepared(tex: "Texture", report: bool) -> BEMUnitCell:
        cells.append(cell_type(tex, modulus, **opts).prepare(*p_range, progress=progress if report else None))
        return cells[-1]

    def companion(tex: "Texture") -> "Texture | None":
        nx = tex.shape[0]
        if make_texture is not None and nx // 2 >= MIN_COMPANION_GRID and nx % 2 == 0:
            try:
                with warnings.catch_warnings():  # coarse on purpose: it only measures the convergence
                    warnings.simplefilter("ignore", ResolutionWarning)
                    return make_texture(nx // 2)
            except FingerpadError:
                return halve(tex)
        return halve(tex)

    fine_tex = texture
    coarse_tex = companion(fine_tex)
    coarse = prepared(coarse_tex, False) if coarse_tex is not None else None
    fine = prepared(fine_tex, True)
    history: list[tuple[int, float]] = []
    while True:
        error = math.nan
        if coarse is not None:
            with np.errstate(divide="ignore", invalid="ignore"):
                rel = np.asarray(ratio(fine), float) / np.asarray(ratio(coarse), float) - 1.0
            rel = rel[np.isfinite(rel)]
            error = float(np.max(np.abs(rel))) if rel.size else math.nan
        history.append((fine_tex.shape[0], error))
        grow = (target is not None and make_texture is not None and not math.isnan(error)
                and error > target and 2 * fine_tex.shape[0] <= max_grid)
        if not grow:
            return GridChoice(fine, coarse, error, target, history, sum(c.solves for c in cells))
        try:
            next_tex = make_texture(2 * fine_tex.shape[0])  # type: ignore[misc]
        except FingerpadError:
            return GridChoice(fine, coarse, error, target, history, sum(c.solves for c in cells))
        coarse, fine_tex = fine, next_tex
        fine = prepared(fine_tex, True)
