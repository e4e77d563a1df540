"""Load curves of a texture cell: contact fraction psi(p), contact state, critical pressure.

The *contact state* of a cell (asperity / transition / full, docs/model.md, micro scale) is defined in
:func:`fingerpad.contact.contact_state`: *transition* starts when the skin touches the lowest
level of the texture (the base between bumps, the bottom of a dimple or a ridge valley), *full*
contact when at most 1 % of the cell is out of contact (:data:`fingerpad.contact.FULL_CONTACT_TOL`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..contact import ContactResult, HalfSpaceSolver
from ..errors import FingerpadError

__all__ = ["CriticalPressure", "LoadCurve", "Progress", "bisect_state", "critical_pressure", "full_contact_pressure",
           "load_curve"]

Progress = Callable[[int, int], None]


@dataclass
class LoadCurve:
    """Results of a sweep of mean nominal pressures on one cell (SI units), in the order asked."""

    mean_pressure: np.ndarray
    contact_fraction: np.ndarray
    mean_gap: np.ndarray
    max_pressure: np.ndarray
    contact_state: list[str]
    iterations: np.ndarray
    converged: np.ndarray
    seconds: np.ndarray
    results: list[ContactResult] = field(repr=False, default_factory=list)

    @property
    def real_contact_area(self) -> np.ndarray:
        """Real contact area of the whole cell, m^2."""
        if not self.results:
            raise FingerpadError("load curve holds no results")
        return self.contact_fraction * self.results[0].texture.area


def load_curve(
    solver: HalfSpaceSolver,
    pressures: "list[float] | np.ndarray",
    *,
    progress: Progress | None = None,
    keep_fields: bool = True,
) -> LoadCurve:
    """Solve the cell at each mean pressure (Pa), warm-starting each solve from the previous one.

    Pressures are solved in increasing order (each solution starts the next) and returned in the
    order given. ``progress(i, n)`` is called after each solve.
    """
    p = np.asarray(pressures, dtype=float).ravel()
    if p.size == 0:
        raise FingerpadError("no pressures given")
    if not np.all(np.isfinite(p)) or np.any(p <= 0):
        raise FingerpadError("pressures must be positive and finite")
    order = np.argsort(p, kind="stable")
    results: list[ContactResult | None] = [None] * p.size
    previous: ContactResult | None = None
    for k, i in enumerate(order):
        res = solver.solve_pressure(float(p[i]), initial=previous)
        results[i] = res
        previous = res
        if progress is not None:
            progress(k + 1, p.size)
    done = [r for r in results if r is not None]
    curve = LoadCurve(
        mean_pressure=np.array([r.mean_pressure for r in done]),
        contact_fraction=np.array([r.contact_fraction for r in done]),
        mean_gap=np.array([r.mean_gap for r in done]),
        max_pressure=np.array([r.max_pressure for r in done]),
        contact_state=[r.contact_state for r in done],
        iterations=np.array([r.iterations for r in done]),
        converged=np.array([r.converged for r in done]),
        seconds=np.array([r.seconds for r in done]),
        results=done if keep_fields else [],
    )
    return curve


@dataclass
class CriticalPressure:
    """A bracket [lower, upper] (Pa) of the mean pressure at which a contact state begins."""

    lower: float
    upper: float
    solves: int
    state: str

    @property
    def estimate(self) -> float:
        """Geometric mid-point of the bracket, Pa."""
        return math.sqrt(self.lower * self.upper)

    @property
    def relative_width(self) -> float:
        return (self.upper - self.lower) / self.upper


def _initial_pressure(solver: HalfSpaceSolver) -> float:
    # The pressure scale of a texture: E* times a height-to-length ratio (Westergaard's p* for a
    # sinusoid). Transitions of practical textures lie within a few decades of it.
    tex = solver.texture
    return solver.modulus * max(tex.peak_to_valley, 1e-12) / max(tex.size)


def _bracket(
    solver: HalfSpaceSolver, reached_state: Callable[[str], bool], state: str, rtol: float,
    progress: Progress | None, max_solves: int,
) -> CriticalPressure:
    if not (0 < rtol < 1):
        raise FingerpadError(f"rtol must lie in (0, 1), got {rtol!r}")
    if not solver.texture.periodic:
        raise FingerpadError("contact-state pressures are defined for periodic cells only")
    p = _initial_pressure(solver) * 1e-3
    solves = 0
    lo_res: ContactResult | None = None
    res = solver.solve_pressure(p)
    solves += 1
    # Go down until the state is not reached, then up until it is (factor 4 steps).
    while reached_state(res.contact_state):
        p /= 4.0
        if p < 1e-12 * _initial_pressure(solver):
            raise FingerpadError(f"the {state} state is reached at any load (flat texture?)")
        res = solver.solve_pressure(p)
        solves += 1
    lo, lo_res = p, res
    hi = p
    while True:
        hi *= 4.0
        res = solver.solve_pressure(hi, initial=lo_res)
        solves += 1
        if reached_state(res.contact_state):
            break
        lo, lo_res = hi, res
        if solves > max_solves:
            raise FingerpadError(f"no {state} state found below {hi:.3g} Pa")

    def solve(p: float, initial: ContactResult | None) -> ContactResult:
        nonlocal solves
        solves += 1
        if progress is not None:
            progress(solves, solves + int(math.ceil(math.log2(max(math.log(hi / lo) / rtol, 1.0)))))
        return solver.solve_pressure(p, initial=initial)

    lo, hi = bisect_state(solve, lo, hi, lo_res, reached_state, rtol, max_solves - solves)
    return CriticalPressure(lower=lo, upper=hi, solves=solves, state=state)


def bisect_state(
    solve: Callable[[float, "ContactResult | None"], ContactResult], lo: float, hi: float,
    lo_res: "ContactResult | None", reached: Callable[[str], bool], rtol: float, max_solves: int,
) -> tuple[float, float]:
    """Narrow [lo, hi] (state not reached at lo, reached at hi) geometrically to ``rtol``,
    each solve warm-started from the highest solution below the state."""
    n = 0
    while (hi - lo) / hi > rtol and n < max_solves:
        mid = math.sqrt(lo * hi)
        res = solve(mid, lo_res)
        n += 1
        if reached(res.contact_state):
            hi = mid
        else:
            lo, lo_res = mid, res
    return lo, hi


def critical_pressure(
    solver: HalfSpaceSolver, *, rtol: float = 1e-3, progress: Progress | None = None, max_solves: int = 200
) -> CriticalPressure:
    """Bracket the critical (transition) mean pressure of a periodic cell to relative width ``rtol``.

    The critical pressure is the lowest mean nominal pressure at which the skin touches the lowest
    level of the texture (end of the asperity-contact state). The micro-scale analogue of
    Eq. 3.3-3.6, including the neighbouring asperities that Hertz ignores.
    """
    return _bracket(solver, lambda st: st != "asperity", "transition", rtol, progress, max_solves)


def full_contact_pressure(
    solver: HalfSpaceSolver, *, rtol: float = 1e-3, progress: Progress | None = None, max_solves: int = 200
) -> CriticalPressure:
    """Bracket the mean pressure at which the cell reaches full contact (at most 1 % open)."""
    return _bracket(solver, lambda st: st == "full", "full", rtol, progress, max_solves)

