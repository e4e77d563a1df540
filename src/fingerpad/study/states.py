"""The state pressures of a prediction's unit cell and the adhesive cell's grid (docs/model.md 6.6).

What :func:`~fingerpad.study.run.run_study` asks of the cell besides its curve: the grid of each
state pressure (:func:`state_choices`), the adhesive cell on its grid with its companions
(:func:`resolve_adhesive_cell`) and its state pressures, a pulled-in transition extrapolated to
a vanishing pixel (:func:`adhesive_states`, :data:`~fingerpad.micro.pull_in.PULL_IN_METHOD`), and the report of the
state brackets: their pressures, the loads they map to at the pad centre (:func:`centre_load`)
and their estimates (:func:`state_report`, :func:`state_brackets`). SI units.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from ..errors import FingerpadError
from ..finger import Finger
from ..micro.bem import STATE_SEARCH_CAP
from ..micro.pull_in import PULL_IN_METHOD
from ..textures import Texture
from .spec import Study

__all__ = ["FINGER_LOAD_LIMIT", "MAX_ADHESIVE_GRID", "adhesive_states", "centre_load",
           "load_at_centre_pressure", "load_notes", "pull_off_error", "resolve_adhesive_cell", "state_brackets",
           "state_choices", "state_report", "texture_maker"]


#: Loads above this (N) are beyond what a finger exerts in touch; reports say so.
FINGER_LOAD_LIMIT = 100.0


def load_at_centre_pressure(finger: Finger, pressure: float) -> float:
    """Load (N) at which the centre pressure ``1.5 F / A_fr(F)`` equals ``pressure`` (Pa);
    ``inf`` for an infinite pressure, NaN if none in the searched load range
    (:data:`~fingerpad.micro.response.DEFAULT_LOAD_RANGE`): the package's one search of this
    equation, :func:`~fingerpad.coupling.loads.centre_loads`, which a population's members take
    all at once (the same bits)."""
    from ..coupling.loads import FingerStack, centre_loads

    return float(centre_loads(FingerStack([finger]), [float(pressure)])[0])



def centre_load(finger: Finger, cell: Any) -> Callable[[float], float]:
    """``pressure -> load`` (N) at which the pad centre reaches ``pressure`` (Pa): the Hertz
    pad's ``1.5 F / A_fr`` (:func:`load_at_centre_pressure`), or with an adhesive cell the
    adhesive pad's centre pressure (Eq. 3.17)."""
    if not getattr(cell, "adhesive", False):
        return lambda p: load_at_centre_pressure(finger, p)
    from ..micro.adhesive_pad import adhesive_pad
    from ..micro.response import DEFAULT_LOAD_RANGE, solve_load

    pad = adhesive_pad(finger, cell)

    def centre(load: float) -> float:
        f = np.array([load])
        return float(pad.centre_pressure(f, pad.areas(f)[1])[0])

    def load_at(p: float) -> float:
        if math.isinf(p):
            return math.inf
        if not math.isfinite(p):
            return math.nan
        if p <= centre(0.0):
            return 0.0
        try:
            return solve_load(lambda f: centre(f) - p, DEFAULT_LOAD_RANGE, "load", lambda lo, hi: "")
        except FingerpadError:
            return math.nan

    return load_at



def texture_maker(study: Study) -> Callable[[int], Texture] | None:
    """``make(nx)``: the study's texture built at ``nx`` points along x (a generated texture);
    ``None`` for a height map, whose grid is its own."""
    from .texture import TextureSpec

    if isinstance(study.texture, TextureSpec) and study.texture.name is not None:
        return lambda nx: study.texture.build(nx)  # type: ignore[union-attr]
    return None


def state_choices(study: Study, tex: Texture, e1: float, choice: Any) -> tuple[dict[str, Any], int]:
    """The grid of each state pressure (:func:`~fingerpad.micro.resolution.choose_state_grids`):
    chosen by the study's accuracy from the starting grid where the curve's grid is chosen
    automatically, else the curve's own grid (given, or a measured map's). The loads asked for
    do not enter. Returns the choices and the solves they added."""
    from ..micro.resolution import choose_state_grids

    make = texture_maker(study)
    automatic = study.grid is None and make is not None
    start = tex if automatic else choice.cell.texture
    return choose_state_grids(
        make, start, e1, target=study.accuracy if automatic else None,
        cell_options={"tol": study.tol, "max_iter": study.max_iter, "cache": study.curve_cache(),
                      "layer": study.finger.layer},
        cells=choice.cells,
    )


def state_report(states: dict[str, Any], finger: Finger,
                  centre_load: Callable[[float], float] | None = None) -> dict[str, Any]:
    """Per state: its grid, the half grid's, the pressure's and the load's estimated errors
    (``centre_load``: pressure -> load at the pad centre, :func:`centre_load`; by default the
    Hertz pad's, :func:`load_at_centre_pressure`)."""
    if centre_load is None:
        centre_load = lambda p: load_at_centre_pressure(finger, p)  # noqa: E731
    out = {}
    for name, st in states.items():
        p, pc = st.pressure, st.coarse_pressure
        f, fc = centre_load(p), centre_load(pc)
        with np.errstate(all="ignore"):
            load_error = abs(f / fc - 1.0) if math.isfinite(f) and math.isfinite(fc) and fc > 0 else \
                (math.nan if math.isnan(st.error) else math.inf)
        if not math.isnan(st.error) and math.isfinite(load_error):
            load_error = max(load_error, _load_floor(centre_load, st))
        out[name] = {
            "grid": list(st.cell.texture.shape),
            "coarse_grid": list(st.coarse.texture.shape) if st.coarse is not None else None,
            "pressure_error": st.error,
            "load_error": load_error,
            "coarse_pressure": pc,
            "target": st.target,
            "met": st.met,
            "history": [{"grid": g, "pressure_error": e} for g, e in st.history],
            "method": "relative change from the half grid, |p_N / p_{N/2} - 1| (at least the bracket's width); "
                      "the load's: the same change carried through the pad, |F(p_N) / F(p_{N/2}) - 1|"
            if st.reported is None else PULL_IN_METHOD,
        }
        if st.reported is not None:
            out[name]["own_pressure"] = st.cell.own_state_pressure(name)
    return out


def _load_floor(centre_load: Callable[[float], float], st: Any) -> float:
    """The load change of a pressure change of the brackets' relative width, the wider of the
    cell's and its companion's (the estimate's floor, as the pressure's)."""
    from ..micro.resolution import state_width

    p = st.pressure
    width = max(state_width(c, st.state) for c in (st.cell, st.coarse) if c is not None)
    f, f2 = centre_load(p), centre_load(p * (1.0 + width))
    return abs(f2 / f - 1.0) if math.isfinite(f) and math.isfinite(f2) and f > 0 else 0.0


#: The automatic grid of an adhesive cell stops at this many points along x: each of its ~120
#: solves is a continuation step (grid 128: ~15 s on one core, 256: ~1.5 min; measured on the
#: default cell), and the estimate is reported where it stays above the accuracy.
MAX_ADHESIVE_GRID = 256


def resolve_adhesive_cell(study: Study, grid: int, e1: float, progress: Callable[[int, int], None] | None,
                          estimate: bool = True) -> Any:
    """The adhesive cell (:class:`~fingerpad.micro.adhesive_cell.AdhesiveUnitCell`) of the study's
    texture, from the grid ``grid`` the non-adhesive cell took, doubled while the estimate of its
    A_re/A_fr error (the adhesive pad's, the range following the pixel) exceeds the accuracy."""
    from ..coupling import predict_curve
    from ..micro.adhesive_cell import AdhesiveUnitCell
    from ..micro.pull_in import adopt_extrapolated, pulled_in_companions
    from ..micro.resolution import choose_grid

    finger = study.finger
    loads = np.append(study.loads, study.zone_load)
    make = texture_maker(study)
    tex = make(grid) if make is not None else study.build_texture()
    target = None if study.grid is not None or make is None else study.accuracy
    ratio = (lambda cell: predict_curve(loads, finger, cell, reference=False).area_ratio) \
        if estimate or target is not None else (lambda cell: np.full(loads.size, np.nan))
    options = {"tol": study.tol, "max_iter": study.max_iter, "cache": study.curve_cache(),
               "layer": finger.layer, "work_of_adhesion": finger.work_of_adhesion,
               "adhesion_range": finger.adhesion_range, "law": finger.adhesion_law}
    # a pulled-in transition is extrapolated from the grid, its half and its quarter, its estimate
    # taken with the eighth (1/16 and 1/64 of the work of the grid for the last two), and the cell
    # reports it, psi(p) included, before its A_re/A_fr is read for the estimate (docs/model.md 6.6)

    def settle(cell: Any, cells: dict[int, Any]) -> dict[str, Any]:
        pulled_in_companions(cell, make, lambda t: AdhesiveUnitCell(t, e1, **options).prepare(), cells)
        return adopt_extrapolated(cells, int(cell.texture.shape[0]))

    return choose_grid(make, tex, e1, (0.0, 0.0), ratio, target=target, max_grid=MAX_ADHESIVE_GRID,
                       cell_options=options, progress=progress, cell_type=AdhesiveUnitCell, settle=settle)


def adhesive_states(choice: Any, accuracy: float) -> dict[str, Any]:
    """The state pressures of an adhesive cell as state choices: its own brackets on its grid,
    the half grid's beside them, the estimate the change between them divided by ``2^q - 1``
    (:meth:`~fingerpad.micro.resolution.GridChoice.state_pressure_errors`; the grid is chosen by
    A_re/A_fr, not by the states, so ``accuracy`` is what the estimate is compared with)."""
    from ..micro.resolution import STATES, StateChoice

    errors = choice.state_pressure_errors()
    out = {name: StateChoice(name, choice.cell, choice.coarse, errors[name], accuracy) for name in STATES}
    # a transition the attraction pulled in: extrapolated to a vanishing pixel, which the cell
    # adopted in its grid's choice (:func:`resolve_adhesive_cell`; docs/model.md 6.6)
    for name, (p, pc, error) in choice.extrapolated.items():
        out[name] = StateChoice(name, choice.cell, choice.coarse, error, accuracy, reported=p, reported_coarse=pc)
    return out


def pull_off_error(choice: Any) -> float:
    """Estimated relative error of the finger's pull-off force (Eqs. 3.15-3.18: proportional to
    the cell's work of separation ``W``): ``|W_N / W_{N/2} - 1| / (2^q - 1)`` from the adhesive
    cell and its half-grid companion (NaN without one)."""
    from ..micro.resolution import order_factor

    if choice.coarse is None:
        return math.nan
    fine, coarse = choice.cell.work_of_separation, choice.coarse.work_of_separation
    if not (coarse > 0 and math.isfinite(fine)):
        return math.nan
    return abs(fine / coarse - 1.0) * order_factor(type(choice.cell))


def state_brackets(cell: Any, states: dict[str, Any], finger: Finger) -> tuple[float | None, dict[str, Any]]:
    """The full-contact load (N) and, per state (``transition``, ``full``), the bracket of the
    cell pressure (Pa), the loads (N) it maps to at the pad centre, its relative width and its
    estimate (:func:`state_report`). ``(None, {})`` without a cell, ``(0.0, {})`` for a flat."""
    if cell is None:
        return None, {}
    if cell.flat:
        return 0.0, {}
    brackets: dict[str, Any] = {}
    at_centre = centre_load(finger, cell)
    report = state_report(states, finger, at_centre)
    full = at_centre(cell.full_contact_pressure)
    for state, bracket in (("transition", cell.transition), ("full", cell.full)):
        lo, hi = (float(b) for b in bracket)
        brackets[state] = {
            "pressure": [lo, hi],
            "load": [at_centre(lo), at_centre(hi)],
            # none where the state is not reached, or reached at no load (adhesion alone: hi = 0)
            "relative_width": (hi - lo) / hi if math.isfinite(hi) and hi > 0 else None,
            **(report.get(state, {})),
        }
    return full, brackets


def load_notes(cell: Any, critical: float | None, full: float | None, notes: list[str]) -> None:
    """Notes for a critical or full-contact load beyond a finger's, and for a full contact the
    cell does not reach (added to ``notes``)."""
    for name, f in (("critical", critical), ("full-contact", full)):
        if f is not None and math.isfinite(f) and f > FINGER_LOAD_LIMIT:
            notes.append(f"BEM {name} load {f:.4g} N lies beyond the loads a finger exerts "
                         f"(above {FINGER_LOAD_LIMIT:g} N)")
    if math.isinf(cell.full_contact_pressure):
        notes.append(f"full contact not reached up to {cell.full[0] / 1e3:.4g} kPa (the last node below "
                     f"{STATE_SEARCH_CAP:g} E*, where linear elasticity ends)")
