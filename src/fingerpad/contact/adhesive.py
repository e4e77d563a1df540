"""Adhesive contact: the gap as the unknown, an attractive interaction added to the elastic energy.

With an :class:`~fingerpad.contact.interaction.Interaction` ``phi(g)`` (energy per unit area of
the gap ``g``; ``phi(0) = -w``) the contact problem is the minimisation of

    Pi(g) = 1/2 u.S u + sum_i phi(g_i) a_px (+ p_mean sum_i g_i a_px under load control),
    u = g - (h_max - h - d),   g >= 0,

over the gap (the approach of Rey, Anciaux & Molinari 2017: the gap is the primal variable, the
interaction is local in it, the elastic energy is a quadratic form applied by FFT). Its gradient
per pixel is ``r = p + phi'(g)``: the surface traction ``p = S u`` (Pa, compressive positive)
plus the attraction. At a minimum

    g > 0:  p = -phi'(g)  (the gap is held open by the attraction's tension),
    g = 0:  p >= -phi'(0) (contact, which may carry tension up to the peak attraction).

The energy is not convex (``phi'' < 0``): equilibria may be unstable and a load may have several
(jumps into and out of contact, adhesive hysteresis); the iteration finds a local minimum next
to its start, so a load curve continued from one solution to the next follows one branch.

**Periodic cells** (``S = E*|q|/2``, the layered factor with a layer): load control fixes the
mean traction (the q = 0 mode, no constraint needed); approach control fixes the mean gap, with
the mean traction as its multiplier, as the dual form of the non-adhesive solver does.

**Finite patches** (``Texture.periodic = False``): the free-space compliance of the patch, Love's
pixel kernel convolved linearly, is a circulant operator ``K`` on the doubled (zero-padded) grid
whose products with a pressure supported on the patch are exact there. The unknown lives on the
doubled grid: the gap on the patch (bound below by zero, with the interaction) and the free
surface displacement outside it (no bound, no interaction); the stiffness is ``S = K^-1`` on the
doubled grid and the gradient outside the patch is the traction there, which the minimum makes
zero. So the pressure is supported on the patch and the displacement is free space's, exactly.
Approach control; load control finds the approach by a bracketed secant on the mean pressure.

**Iteration.** A projected, preconditioned nonlinear conjugate gradient (Polak-Ribiere+): the
working set is the free points plus contact points whose gradient points into the gap; the
preconditioner is the compliance (the exact inverse of ``S``, as for the dual form); the line
search minimises the energy along the direction exactly enough (``|f'| <= 1e-2 |f'(0)|``) by a
safeguarded regula falsi on its slope, where the elastic part is a quadratic of known
coefficients (``d.S d`` by Parseval, one single-precision transform) and the interaction part is
element-wise, so a line search costs no further transform; the step is then projected onto
``g >= 0``. Convergence: the relative KKT residual, the RMS over the cell of the projected
gradient divided by ``max(|p_mean|, w / rho)`` (load control) or ``max(w / rho, E* PV / Lx)``
(approach control).

Under load control with a tension beyond what the contact can hold the skin lifts off: the
iteration stops once no pixel touches and the attraction has fallen below 1e-12 of its peak
everywhere, and the result says ``detached`` (not converged; no equilibrium exists there).
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import FingerpadError
from .greens import FFTOperator, preconditioner, stiffness_operator
from .interaction import Interaction, tip_zone
from .result import ContactResult, contact_state

__all__ = ["AdhesiveRun", "AdhesiveSetup", "adhesive_cg", "adhesive_energy", "solve_adhesive"]

#: Most evaluations of the slope in one line search.
_LINE_EVALS = 40
#: The line search stops at |f'(tau)| <= this fraction of |f'(0)|.
_LINE_TOL = 1e-2


@dataclass
class AdhesiveRun:
    """What one run of :func:`adhesive_cg` ends with (fields on the working grid)."""

    x: Any
    iterations: int
    residual: float
    converged: bool
    multiplier: float  # the mean traction (Pa) under a fixed mean gap; 0 otherwise
    detached: bool = False
    sx: Any = None  # S x at the returned iterate
    #: Where a regularised attraction acts at the returned iterate with the gap within its reach
    #: (the next solve's ``held``; ``None`` for an attraction acting everywhere).
    bonded: Any = None


def adhesive_cg(
    op: FFTOperator,
    precond: FFTOperator,
    e: Any,
    x0: Any,
    interaction: Interaction,
    *,
    patch: Any = None,
    mean: float | None = None,
    load: float | None = None,
    scale: float,
    tol: float,
    max_iter: int,
    callback: Callable[[int, float], None] | None = None,
    held: Any = None,
) -> AdhesiveRun:
    """Minimise ``1/2 x.S x + e.x + sum_patch phi(x)`` over ``x`` with ``x >= 0`` on the patch.

    Parameters
    ----------
    op, precond
        The stiffness ``S`` and its (approximate) inverse on the working grid.
    e
        The linear term: the gradient of the elastic energy is ``S x + e``, the traction.
    x0
        Start (a fresh array the run may update in place).
    interaction
        The attraction on the patch.
    patch
        Boolean mask of the points that carry the bound and the interaction (``None``: all).
    mean
        Fixed mean of ``x`` (approach control of a periodic cell), its multiplier returned as
        the mean traction.
    load
        The mean traction under load control (only to tell a lift-off when it is a tension).
    scale
        Pressure that makes the residual relative (Pa).
    tol, max_iter, callback
        As for :func:`fingerpad.contact.ccg.constrained_cg`.
    held
        Where a regularised attraction acted in the state the solve starts from (boolean, the
        working grid: the last solve's ``bonded``; ``None``: the points where ``x0`` is closed):
        it keeps acting there (:func:`_acting`).
    """
    xp = op.b.xp
    on = patch if patch is not None else xp.ones(x0.shape, dtype=xp.bool)
    if interaction.tip_pixels and held is None:
        # (a start rebuilt from a pressure field, a finite patch's, closes its contact to rounding)
        held = on & (x0 <= 1e-6 * interaction.range)
    run = _adhesive_cg(op, precond, e, x0, interaction, patch, on, held, mean, load, scale, tol, max_iter, callback)
    if interaction.tip_pixels:
        run.bonded = _acting(xp, interaction, run.x, on, held) & (run.x < interaction.reach * _FAR_REACHES)
    return run


def _adhesive_cg(op: FFTOperator, precond: FFTOperator, e: Any, x0: Any, interaction: Interaction, patch: Any,
                 on: Any, held: Any, mean: float | None, load: float | None, scale: float, tol: float,
                 max_iter: int, callback: Callable[[int, float], None] | None) -> AdhesiveRun:
    """The iteration of :func:`adhesive_cg` (``on``: the patch's mask, all points without one)."""
    xp = op.b.xp
    x = x0
    n_patch = int(xp.count_nonzero(patch)) if patch is not None else math.prod(x.shape)
    if mean is not None:
        m = float(xp.mean(x))
        x = x * (mean / m) if m > 0 else xp.full(x.shape, mean, dtype=xp.float64)
    far = interaction.reach * _FAR_REACHES  # the attraction beyond: below 1e-17 of its peak
    sx = op(x)
    d = xp.zeros_like(x)
    z_old = None
    rz_old = 0.0
    lam = 0.0
    residual = math.inf
    it = 0
    while True:
        acts = _acting(xp, interaction, x, on, held)  # where the attraction acts this iteration
        near = acts & (x < far)
        r = sx + e
        r += _masked(xp, near, interaction.traction, x)  # the gradient: traction plus attraction
        free = x > 0 if patch is None else (~on) | (x > 0)
        if mean is not None:
            nfree = int(xp.count_nonzero(free))
            lam = -float(xp.sum(xp.where(free, r, 0.0))) / max(nfree, 1)
            r += lam
        # KKT: zero gradient where free, none pointing into the gap where closed
        kkt = xp.where(free, r, xp.minimum(r, 0.0))
        residual = math.sqrt(float(xp.sum(kkt * kkt)) / n_patch) / scale
        del kkt
        if callback is not None:
            callback(it, residual)
        if residual < tol:
            return AdhesiveRun(x, it, residual, True, lam, sx=sx)
        if load is not None and load < 0 and mean is None and not bool(xp.any(near)):
            # no contact, no attraction left, a tension applied: the skin has lifted off
            return AdhesiveRun(x, it, residual, False, lam, detached=True, sx=sx)
        if it >= max_iter:
            return AdhesiveRun(x, it, residual, False, lam, sx=sx)
        it += 1
        work = free | (r < 0)  # free points and closed ones the gradient would open
        entering = bool(xp.any(work & ~free))
        nwork = int(xp.count_nonzero(work))
        if nwork == 0:
            return AdhesiveRun(x, it, residual, False, lam, sx=sx)
        rw = xp.where(work, r, 0.0)
        if mean is not None:
            rw = xp.where(work, rw - float(xp.sum(rw)) / nwork, 0.0)
        z = xp.astype(precond.apply_low(rw), xp.float64)
        z = xp.where(work, z, 0.0)
        if mean is not None:
            z = xp.where(work, z - float(xp.sum(z)) / nwork, 0.0)
        rz = float(xp.sum(rw * z))
        beta = 0.0
        if z_old is not None and not entering and rz_old > 0:
            beta = max(0.0, (rz - float(xp.sum(rw * z_old))) / rz_old)  # Polak-Ribiere+
        d = xp.where(work, -z + beta * d, 0.0)
        if mean is not None and beta:
            d = xp.where(work, d - float(xp.sum(d)) / nwork, 0.0)
        slope0 = float(xp.sum(r * d))
        if slope0 >= 0 and beta:
            d, beta = -z, 0.0  # descent lost: restart along the preconditioned gradient
            slope0 = float(xp.sum(r * d))
        if slope0 >= 0:
            return AdhesiveRun(x, it, residual, False, lam, sx=sx)
        z_old, rz_old = z, rz
        dsd = op.quad_low(d)
        if not dsd > 0:
            return AdhesiveRun(x, it, residual, False, lam, sx=sx)
        cap = _trust(xp, interaction, x, d, acts)
        # the pixels the interaction can act on within the capped step: the line search's own
        xa, da = _within_reach(xp, interaction, x, d, acts, cap)
        tau, capped = _line_search(interaction, xa, da, slope0, dsd, cap)
        if capped:
            z_old = None  # a step short of the line's minimum: conjugacy restarts
        x = x + tau * d
        x = xp.maximum(x, 0.0) if patch is None else xp.where(on, xp.maximum(x, 0.0), x)
        if mean is not None:
            total = float(xp.mean(x))
            if total > 0:
                x = x * (mean / total)
        sx = None  # release the old S x before the transform allocates the new one
        sx = op(x)


#: Beyond this many reaches a gap feels no attraction worth counting (exponential: 40 ranges,
#: exp(-40) ~ 4e-18 of the peak; Maugis-Dugdale: exactly none beyond one range).
_FAR_REACHES = 4.0


def _acting(xp: Any, law: Interaction, x: Any, on: Any, held: Any = None) -> Any:
    """Where the attraction acts at the gap ``x``: the patch ``on``, or with a regularised range
    (``law.tip_pixels``) its points within that many pixels of the current contact and the points
    ``held``, where it acted in the state the solve started from (docs/model.md 6.6: the JKR
    limit's attraction lives in the cohesive zone at the contact's edge, and a surface out of
    contact feels none until it touches; once it has acted on a point it keeps acting there
    while the gap is within its reach, as a cohesive bond does, so that the surfaces pulled
    apart release the whole ``w`` and one long step of the iteration cannot tear a contact off
    for good). Fixed along one iteration's line search."""
    if not law.tip_pixels:
        return on
    zone = tip_zone(on & (x <= 0), law.tip_pixels)
    return on & (zone if held is None else zone | held)


def _masked(xp: Any, mask: Any, f: Callable[[Any], Any], x: Any) -> Any:
    """``f(x)`` where ``mask``, 0 elsewhere, evaluating ``f`` on the masked points only (NumPy;
    other namespaces evaluate it everywhere)."""
    if isinstance(x, np.ndarray):
        out = np.zeros_like(x)
        out[mask] = f(x[mask])
        return out
    return xp.where(mask, f(x), 0.0)


def _within_reach(xp: Any, law: Interaction, x: Any, d: Any, on: Any, cap: float) -> tuple[Any, Any]:
    """The gaps and directions (1-D) of the patch's points that are, or can come, within the
    interaction's reach in a step of at most ``cap``: the only ones whose attraction changes
    along the step by more than ~1e-4 of its peak (the line search neglects the others' change)."""
    lowest = x + cap * xp.minimum(d, 0.0) if math.isfinite(cap) else xp.where(d < 0, -math.inf, x)
    sel = on & (lowest < law.reach) & (d != 0)
    if isinstance(x, np.ndarray):
        return x[sel], d[sel]
    idx = xp.nonzero(xp.reshape(sel, (-1,)))[0]
    return xp.take(xp.reshape(x, (-1,)), idx), xp.take(xp.reshape(d, (-1,)), idx)


def _trust(xp: Any, law: Interaction, x: Any, d: Any, on: Any) -> float:
    """The longest step along ``d`` that moves no gap by more than :data:`TRUST_RANGES` ranges
    inside the interaction's reach (a gap outside it may travel to its edge first).

    The energy is not convex: along a direction that closes many gaps at once it may fall all the
    way into a distant state (a whole cell snapped into contact) that the loading history does
    not reach. Bounding the motion where the attraction acts makes the iteration follow the
    nearest equilibrium, the branch a quasi-static load increment reaches."""
    reach = law.reach
    step = TRUST_RANGES * law.range
    inside = on & (x <= reach)
    # a closing gap outside the reach may first travel to its edge (an opening one is free)
    closing = on & (x > reach) & (d < 0)
    if isinstance(x, np.ndarray):
        moves = d[inside]
        fastest = float(np.max(np.abs(moves))) if moves.size else 0.0
        cap = step / fastest if fastest > 0 else math.inf
        far_x, far_d = x[closing], d[closing]
        if far_x.size:
            cap = min(cap, float(np.min((far_x - reach + step) / -far_d)))
        return cap
    fastest = float(xp.max(xp.where(inside, xp.abs(d), 0.0)))
    cap = step / fastest if fastest > 0 else math.inf
    if bool(xp.any(closing)):
        room = xp.where(closing, (x - reach + step) / xp.where(closing, -d, 1.0), math.inf)
        cap = min(cap, float(xp.min(room)))
    return cap


#: Gaps within the interaction's reach move by at most this many ranges per iteration (:func:`_trust`).
TRUST_RANGES = 4.0


def _line_search(law: Interaction, xa: Any, da: Any, slope0: float, dsd: float,
                 cap: float = math.inf) -> tuple[float, bool]:
    """A step ``tau > 0`` along the direction at which the energy's slope ``f'(tau)`` has risen to
    within :data:`_LINE_TOL` of ``|f'(0)|`` of zero from below, and the energy has fallen.

    ``f'(tau) = f'(0) + tau d.S d + sum d [phi'(x + tau d) - phi'(x)]`` (the elastic part is a
    quadratic of known coefficients; the sum runs over the points within the interaction's reach,
    ``xa``, ``da``: :func:`_within_reach`), ``f'(0) = slope0 < 0``. A Newton step starts it; a
    bracket ``f'(lo) < 0 <= f'(hi)`` is then narrowed by regula falsi with the Illinois
    modification (bisection where it stalls). The attraction is bounded, so ``f'`` rises without
    bound: a bracket always exists. The step is at most ``cap`` (:func:`_trust`); the second
    value returned says whether that bound was taken instead of the line's minimum.
    """
    t0 = law.traction(xa)
    e0 = law.energy(xa)

    def slope(tau: float) -> float:
        return slope0 + tau * dsd + float(np.sum(da * (law.traction(xa + tau * da) - t0)))

    def drop(tau: float) -> float:
        # f(tau) - f(0): the quadratic plus the interaction's change beyond its first order
        extra = law.energy(xa + tau * da) - e0 - tau * da * t0
        return tau * slope0 + 0.5 * tau * tau * dsd + float(np.sum(extra))

    curv = dsd + float(np.sum(da * da * law.curvature(xa)))
    tau = min(-slope0 / (curv if curv > 0.25 * dsd else dsd), cap)
    lo, f_lo = 0.0, slope0
    f_tau = slope(tau)
    evals = 1
    while f_tau < 0 and evals < _LINE_EVALS:  # still descending: expand
        if tau >= cap:
            if drop(tau) < 0:
                return tau, True
            break
        lo, f_lo = tau, f_tau
        tau = min(2.0 * tau, cap)
        f_tau = slope(tau)
        evals += 1
    hi, f_hi = tau, f_tau
    side = 0
    while evals < _LINE_EVALS and f_hi > -_LINE_TOL * slope0 and abs(f_lo) > _LINE_TOL * abs(slope0):
        t = hi - f_hi * (hi - lo) / (f_hi - f_lo) if f_hi != f_lo else 0.5 * (lo + hi)
        if not (lo < t < hi):
            t = 0.5 * (lo + hi)
        ft = slope(t)
        evals += 1
        if ft < 0:
            lo, f_lo = t, ft
            if side == -1:
                f_hi *= 0.5
            side = -1
        else:
            hi, f_hi = t, ft
            if side == 1:
                f_lo *= 0.5
            side = 1
        if hi - lo <= 1e-12 * hi:
            break
    best = lo if abs(f_lo) <= abs(f_hi) and lo > 0 else hi
    for _ in range(60):  # the energy must fall (a far root of a non-convex slope may not)
        if drop(best) < 0:
            return best, False
        best *= 0.5
    return best, False


# --------------------------------------------------------------------------------------------
# The solve: working grid, operators, start, result
# --------------------------------------------------------------------------------------------


class AdhesiveSetup:
    """The operators of an adhesive solve on one solver's texture (built once, on first use).

    Periodic: the working grid is the cell, ``S`` the periodic stiffness, the preconditioner the
    periodic compliance. Finite patch: the working grid is the doubled one, ``K`` the zero-padded
    Love compliance as a circulant there, ``S = 1/K`` in Fourier space, the preconditioner ``K``.
    """

    def __init__(self, solver: Any) -> None:
        tex = solver.texture
        be = solver.backend
        xp = be.xp
        self.periodic = tex.periodic
        nx, ny = tex.shape
        if self.periodic:
            self.op = stiffness_operator(be, tex, solver.modulus, solver.layer)
            self.pre = preconditioner(be, tex, solver.modulus, "dual", solver.layer)
            self.shape = (nx, ny)
            self.patch = None
        else:
            mult = np.asarray(solver._K._host_multiplier, dtype=np.float64)
            if not np.all(mult > 0):
                raise FingerpadError("the finite patch's compliance is not positive definite on the doubled grid")
            shape2 = (2 * nx, 2 * ny)
            self.op = FFTOperator(be, shape2, 1.0 / mult, padded=False)
            self.pre = FFTOperator(be, shape2, mult, padded=False)
            self.shape = shape2
            patch = np.zeros(shape2, dtype=bool)
            patch[:nx, :ny] = True
            self.patch = xp.asarray(patch)
            self._compliance = FFTOperator(be, shape2, mult, padded=False)
        self._sh: Any = None

    def sh(self, solver: Any) -> Any:
        """``S h`` of a periodic cell (built on first use)."""
        if self._sh is None:
            self._sh = self.op(solver.h)
        return self._sh

    def embed(self, solver: Any, field: Any) -> Any:
        """A patch field on the doubled grid, zero outside (finite patches)."""
        xp = solver.backend.xp
        nx, ny = solver.texture.shape
        out = xp.zeros(self.shape, dtype=xp.float64)
        if hasattr(out, "__setitem__") and solver.backend.is_numpy:
            out[:nx, :ny] = field
            return out
        pad = np.zeros(self.shape)
        pad[:nx, :ny] = solver.backend.to_numpy(field)
        return xp.asarray(pad)

    def rigid_gap(self, solver: Any, approach: float) -> Any:
        """``h_max - h - d`` on the patch, 0 outside (finite patches): the gap of the undeformed skin."""
        return self.embed(solver, solver.h_max - solver.h - approach)


def _scale_approach(solver: Any, law: Interaction) -> float:
    return max(law.peak_traction, solver.modulus * solver.pv / max(solver.texture.size))


def run_adhesive(solver: Any, mode: str, value: float, seed: Any) -> tuple[AdhesiveRun, float]:
    """One adhesive run on ``solver``'s texture at a mean pressure (``mode="pressure"``, Pa) or an
    approach (``"approach"``, m) from ``seed`` (a :class:`ContactResult` or a start field on the
    working grid, or ``None``). Returns the run and the approach (m) it is at."""
    setup = solver._adhesive_setup()
    law = solver.interaction
    xp = solver.backend.xp
    cb = solver._callback()
    if setup.periodic:
        x0 = _periodic_start(solver, seed, value if mode == "approach" else None)
        held = _held(solver, setup, seed)
        if mode == "pressure":
            e = setup.sh(solver) + value
            run = adhesive_cg(setup.op, setup.pre, e, x0, law, load=value,
                              scale=max(abs(value), law.peak_traction), tol=solver.tol, max_iter=solver.max_iter,
                              callback=cb, held=held)
        else:
            target = solver.h_max - value - solver.h_mean
            run = adhesive_cg(setup.op, setup.pre, setup.sh(solver), x0, law, mean=target,
                              scale=_scale_approach(solver, law), tol=solver.tol, max_iter=solver.max_iter,
                              callback=cb, held=held)
        mean_gap = float(xp.mean(run.x))
        return run, solver.h_max - solver.h_mean - mean_gap
    if mode == "approach":
        return _patch_run(solver, setup, value, seed), value
    return _patch_pressure(solver, setup, value, seed)


def _held(solver: Any, setup: "AdhesiveSetup", seed: Any) -> Any:
    """Where a regularised attraction acted in the result ``seed`` (its ``bonded`` points; a
    non-adhesive result's contact), on the working grid; ``None`` for other seeds (the start's
    closed points then) or an attraction acting everywhere."""
    if not (isinstance(seed, ContactResult) and solver.interaction.tip_pixels):
        return None
    bonded = (seed.adhesion or {}).get("_bonded")
    mask = solver.backend.asarray(np.asarray(seed.gap <= 0 if bonded is None else bonded, dtype=np.float64))
    return (mask if setup.periodic else setup.embed(solver, mask)) > 0


def _periodic_start(solver: Any, seed: Any, approach: float | None) -> Any:
    xp = solver.backend.xp
    if isinstance(seed, ContactResult):
        return xp.maximum(solver.backend.asarray(seed.gap), 0.0)
    if seed is not None:
        return xp.maximum(solver.backend.asarray(seed), 0.0)
    # the skin resting on the highest point, undeformed
    return xp.maximum(solver.h_max - solver.h, 0.0)


def _patch_start(solver: Any, setup: AdhesiveSetup, seed: Any, approach: float) -> Any:
    """The doubled grid's unknown from a seed: a result's pressure gives its displacement
    everywhere (one transform), hence the gap on the patch at this approach."""
    xp = solver.backend.xp
    c = setup.rigid_gap(solver, approach)
    if isinstance(seed, ContactResult):
        u = setup._compliance(setup.embed(solver, solver.backend.asarray(seed.pressure)))
        x = u + c
    elif seed is not None:
        return solver.backend.asarray(seed)
    else:
        x = c
    return xp.where(setup.patch, xp.maximum(x, 0.0), x)


def _patch_run(solver: Any, setup: AdhesiveSetup, approach: float, seed: Any, held: Any = None) -> AdhesiveRun:
    c = setup.rigid_gap(solver, approach)
    x0 = _patch_start(solver, setup, seed, approach)
    e = -setup.op(c)
    if held is None:
        held = _held(solver, setup, seed)  # a result's bonds (its start is moved to this approach)
    return adhesive_cg(setup.op, setup.pre, e, x0, solver.interaction, patch=setup.patch,
                       scale=_scale_approach(solver, solver.interaction), tol=solver.tol, max_iter=solver.max_iter,
                       callback=solver._callback(), held=held)


def _patch_pressure(solver: Any, setup: AdhesiveSetup, pressure: float, seed: Any) -> tuple[AdhesiveRun, float]:
    """Load control of a finite patch: the approach whose mean pressure over the patch is
    ``pressure`` (Pa), by a bracketed secant on the approach (each trial an approach-controlled
    solve warm-started from the last). The mean pressure rises with the approach on a stable
    branch; a tension no approach reaches is a lift-off (``detached``)."""
    xp = solver.backend.xp
    law = solver.interaction
    nx, ny = solver.texture.shape
    scale = max(abs(pressure), law.peak_traction)
    target_tol = solver.tol * scale
    total = 0

    def trial(approach: float, start: Any, held: Any = None) -> tuple[AdhesiveRun, float, float]:
        """A solve at ``approach``: the run, its mean pressure minus the target, its contact area."""
        nonlocal total
        run = _patch_run(solver, setup, approach, start, held)
        total += run.iterations
        p = run.sx + (-setup.op(setup.rigid_gap(solver, approach)))
        contact = float(xp.count_nonzero(setup.patch & (run.x <= 0))) / (nx * ny) * solver.texture.area
        return run, float(xp.mean(p[:nx, :ny])) - pressure, contact

    d = float(seed.approach) if isinstance(seed, ContactResult) else 0.0
    run, err, contact = trial(d, seed)
    lo: tuple[float, float, Any] | None = None  # (approach, error < 0, run)
    hi: tuple[float, float, Any] | None = None  # (approach, error > 0, run)
    side = 0
    for _ in range(_PATCH_TRIALS):
        if abs(err) <= target_tol:
            break
        if err < 0:
            lo = (d, err, run)
        else:
            hi = (d, err, run)
            if pressure < 0 and contact == 0 and lo is None:
                # pulled out of contact and the tension still short of the target: lift-off
                run.detached = True
                break
        if lo is not None and hi is not None:
            (d0, e0, r0), (d1, e1, r1) = lo, hi
            if abs(d1 - d0) <= 1e-15 * max(abs(d0), abs(d1), solver.pv):
                break
            nxt = d0 - e0 * (d1 - d0) / (e1 - e0)  # regula falsi, Illinois-weighted below
            if not (min(d0, d1) < nxt < max(d0, d1)):
                nxt = 0.5 * (d0 + d1)
            near_run = r0 if abs(nxt - d0) <= abs(nxt - d1) else r1
            start, bonds = near_run.x, near_run.bonded
        else:
            # the mean pressure's slope in the approach: 2 E* a / area for a contact of radius a
            radius = math.sqrt(max(contact, solver.texture.area / (nx * ny)) / math.pi)
            step = -err / (2.0 * solver.modulus * radius / solver.texture.area)
            nxt = d + max(min(step, solver.pv), -solver.pv)
            start, bonds = run.x, run.bonded
        d = nxt
        run, err, contact = trial(d, start, bonds)
        if lo is not None and hi is not None:
            # Illinois: halve the weight of an end kept twice in a row
            if err < 0:
                if side == -1:
                    hi = (hi[0], 0.5 * hi[1], hi[2])
                side = -1
            else:
                if side == 1:
                    lo = (lo[0], 0.5 * lo[1], lo[2])
                side = 1
    run.iterations = total
    run.converged = bool(run.converged and abs(err) <= target_tol and not run.detached)
    return run, d


#: Most approach-controlled solves of one load-controlled solve of a finite patch.
_PATCH_TRIALS = 100


def solve_adhesive(solver: Any, mode: str, value: float, initial: ContactResult | None) -> ContactResult:
    """The adhesive contact of ``solver``'s texture (its ``interaction`` set), from ``initial``
    (a warm start: the branch of that solution is followed) or cold.

    A cold solve starts from the non-adhesive solution at the same mean pressure (or approach;
    at zero or negative ones, the undeformed skin resting on the highest point): the contact
    formed without attraction, which the attraction then enlarges. That is the state reached by
    pressing the skin on and then letting the surfaces adhere, the loading branch; a start from
    a coarser grid, as the non-adhesive solves take, could land on another branch (a coarse
    grid does not resolve the attraction's range and holds a full contact the fine grid would
    not reach by loading)."""
    start = time.perf_counter()
    seed: Any = initial
    before = 0
    if seed is None:
        seed = _plain_start(solver, mode, value)
        before = seed.iterations if seed is not None else 0  # the start's iterations count too
    run, approach = run_adhesive(solver, mode, value, seed)
    run.iterations += before
    return _result(solver, run, mode, value, approach, time.perf_counter() - start)


def _plain_start(solver: Any, mode: str, value: float) -> ContactResult | None:
    """The non-adhesive solution of the same cell at ``value`` (``None``: the undeformed skin on
    the highest point, for a mean pressure or approach that is not positive)."""
    if value <= 0:
        return None
    plain = solver._plain_solver()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a start only: the adhesive solve reports
        return plain.solve_pressure(value) if mode == "pressure" else plain.solve_approach(value)


def _result(solver: Any, run: AdhesiveRun, mode: str, value: float, approach: float, seconds: float) -> ContactResult:
    be = solver.backend
    setup = solver._adhesive_setup()
    tex = solver.texture
    nx, ny = tex.shape
    sx = run.sx if run.sx is not None else setup.op(run.x)
    if setup.periodic:
        mean_p = value if mode == "pressure" else run.multiplier
        p = sx + setup.sh(solver) + mean_p
        gap = run.x
        g_np = be.to_numpy(gap)
        disp = g_np + tex.heights - (solver.h_max - approach)
    else:
        e = -setup.op(setup.rigid_gap(solver, approach))
        p_full = sx + e
        p = p_full[:nx, :ny]
        gap = run.x[:nx, :ny]
        g_np = be.to_numpy(gap)
        disp = g_np + tex.heights - (solver.h_max - approach)
    p_np = be.to_numpy(p)
    contact = g_np <= 0
    frac = float(np.count_nonzero(contact)) / contact.size
    law = solver.interaction
    adhesion = {
        **law.describe(),
        "detached": bool(run.detached),
        "tensile_fraction": float(np.count_nonzero(p_np < 0)) / p_np.size,
        "contact_tensile_fraction": float(np.count_nonzero(contact & (p_np < 0))) / p_np.size,
    }
    if run.bonded is not None:
        # where a regularised attraction acts: the next solve from this one keeps it there
        adhesion["_bonded"] = be.to_numpy(run.bonded if setup.periodic else run.bonded[:nx, :ny]).astype(bool)
    # a lifted-off skin has no equilibrium: no gap to report
    mean_gap = math.nan if run.detached else float(g_np.mean())
    # under load control of a periodic cell the mean pressure is the constraint itself (its
    # field's mean differs from it by rounding only)
    mean_pressure = value if (setup.periodic and mode == "pressure") else float(p_np.mean())
    return ContactResult(
        pressure=p_np,
        gap=g_np,
        displacement=disp,
        mean_pressure=mean_pressure,
        approach=math.nan if run.detached else float(approach),
        contact_fraction=frac,
        real_contact_area=frac * tex.area,
        max_pressure=math.nan if run.detached else float(p_np.max()),
        mean_gap=mean_gap,
        iterations=run.iterations,
        residual=run.residual,
        converged=run.converged,
        seconds=seconds,
        formulation="adhesive",
        contact_state="detached" if run.detached else contact_state(contact, solver.base),
        texture=tex,
        modulus=solver.modulus,
        tol=solver.tol,
        adhesion=adhesion,
    )


def adhesive_energy(solver: Any, gap: np.ndarray, mean_pressure: float) -> float:
    """The energy an adhesive load-controlled solve of a periodic cell minimises, per unit area
    (J/m^2, up to a constant): ``(1/n) [1/2 g.S g + (S h).g + p_mean sum g + sum phi(g)]``, the
    elastic energy of the skin, the work of the mean pressure and the interaction energy, at the
    gap ``gap`` (m, the cell's grid, ``>= 0``). Its gradient is ``p + phi'(g)`` (module docstring):
    a converged solution is a local minimum of it over gaps ``>= 0`` (checked by the tests)."""
    if not solver.texture.periodic or solver.interaction is None:
        raise FingerpadError("adhesive_energy needs a periodic cell and an interaction")
    setup = solver._adhesive_setup()
    be = solver.backend
    g = be.asarray(gap)
    sg = setup.op(g)
    xp = be.xp
    law = solver.interaction
    # a regularised attraction acts near the contact of this gap only (:func:`_acting`)
    phi = xp.where(_acting(xp, law, g, xp.ones(g.shape, dtype=xp.bool)), law.energy(g), 0.0)
    total = 0.5 * float(xp.sum(g * sg)) + float(xp.sum(setup.sh(solver) * g)) + mean_pressure * float(xp.sum(g)) \
        + float(xp.sum(phi))
    return total / math.prod(solver.texture.shape)
