"""The constrained conjugate gradient of the contact solver (Polonsky & Keer 1999 family).

One routine serves both forms of the contact problem: ``min 1/2 x.A x - b.x`` subject to
``x >= 0`` and, optionally, a fixed mean of ``x``. The primal form has the pressures as ``x`` and
the compliance as ``A``; the dual has the gaps as ``x`` and the stiffness as ``A``
(:mod:`fingerpad.contact.solver` sets them up).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from .greens import FFTOperator
from .kernels import ArrayKernels

__all__ = ["CCGResult", "constrained_cg"]

@dataclass
class CCGResult:
    """Outcome of :func:`constrained_cg`: the iterate and how the iteration ended."""

    x: Any
    iterations: int
    residual: float
    converged: bool
    multiplier: float  # Lagrange multiplier of the mean constraint (0 without one)
    ax: Any = None  # A x at the returned iterate when computed from x itself (else None)


def constrained_cg(
    kern: ArrayKernels,
    op: FFTOperator,
    b: Any,
    x0: Any,
    *,
    mean: float | None,
    scale: float,
    tol: float,
    max_iter: int,
    stall: int | None = None,
    precond: FFTOperator | None = None,
    own: bool = False,
    callback: Callable[[int, float], None] | None = None,
) -> CCGResult:
    """Minimise 1/2 x.Ax - b.x subject to x >= 0 (and mean(x) = ``mean`` if given).

    Polonsky-Keer constrained conjugate gradient: conjugate directions on the free set
    ``x > 0``, projection onto ``x >= 0``, bound points with a descent gradient released by a
    steepest-descent step (which restarts conjugacy). With the mean constraint the direction is
    centred on the free set, so the straight step keeps the mean and the multiplier is the mean
    gradient on the free set; after a projection the iterate is rescaled to the mean.

    Transforms per iteration: the forward FFT of the direction ``t`` gives ``t.A t`` by
    Parseval (exact line search); the spectrum of ``x`` follows by linearity and one inverse FFT
    gives ``A x``. Only when the projection moved ``x`` off the straight step is ``x``
    transformed afresh: one FFT pair per settled iteration, one and a half otherwise. The
    element-wise work is fused into a few passes (:mod:`fingerpad.contact.kernels`).

    With ``stall``, give up (not converged) once the residual has not halved for that many
    iterations: degenerate active sets (a flat base just touching) can make one formulation
    cycle while the other converges at once.

    With ``precond`` (an approximate inverse of ``A``, applied by FFT) the iteration is the
    preconditioned variant :func:`_preconditioned_cg`; ``own=True`` lets it update ``x0`` in
    place (the caller gives it up).

    ``callback(iteration, residual)``, if given, is called once per iteration (progress of long
    solves; it must be cheap).
    """
    if precond is not None:
        return _preconditioned_cg(kern, op, precond, b, x0, mean=mean, scale=scale, tol=tol, max_iter=max_iter,
                                  stall=stall, own=own, callback=callback)
    xp = kern.xp
    n = math.prod(x0.shape)  # PyTorch's .size is a method
    x = xp.asarray(x0, copy=True)  # updated in place by the kernels
    xh = op.forward(x)
    ax = op.apply_hat(xh)
    fresh = True  # ax computed from x itself (not by linear updates)
    t = xp.zeros_like(x)
    g_old = 1.0
    restart = True
    lam = 0.0
    residual = math.inf
    best, best_it = math.inf, 0
    it = 0
    while it <= max_iter:
        nfree, s1, s2 = kern.free_stats(ax, b, x, lam if mean is not None else 0.0)
        if mean is not None and nfree > 0:
            lam += s1 / nfree
            g = max(s2 - s1 * s1 / nfree, 0.0)
        else:
            g = s2
        beta = 0.0 if (restart or nfree == 0) else g / g_old
        t, viol2, sum_t, rf_t = kern.direction(ax, b, x, lam, t, beta)
        # KKT: zero gradient on the free set, non-negative gradient on the bound set.
        residual = math.sqrt((g + viol2) / n) / scale
        if callback is not None:
            callback(it, residual)
        if residual < tol:
            if fresh:
                return CCGResult(x, it, residual, True, lam, ax)
            # Confirm on A x recomputed from x: linear updates carry rounding drift.
            xh = op.forward(x)
            ax = op.apply_hat(xh)
            fresh = True
            restart = True
            continue
        it += 1
        if it > max_iter:
            break
        if residual < 0.5 * best:
            best, best_it = residual, it
        elif stall is not None and it - best_it > stall:
            return CCGResult(x, it, residual, False, lam)
        if nfree == 0:
            # Every point at its bound: release those with a descent gradient by a projected
            # steepest-descent step of exact length.
            r = ax - b - lam
            t = xp.minimum(r, 0.0)
            tat = op.quad(op.forward(t))
            if tat <= 0:
                return CCGResult(x, it, residual, False, lam)
            x = xp.maximum(x - (float(xp.sum(r * t)) / tat) * t, 0.0)
            if mean is not None:
                x = x * (mean / float(xp.mean(x)))
            xh = op.forward(x)
            ax = op.apply_hat(xh)
            fresh = True
            restart = True
            t = xp.zeros_like(x)
            continue
        if mean is not None:
            # Feasible directions keep the mean: centre t on the free set. r_free sums to zero
            # there, so r_free . t is unchanged.
            t = kern.centre(t, x, sum_t / nfree)
        g_old = g
        th = op.forward(t)
        tat = kern.quad(op.quad_weights, th)
        if tat <= 0:
            return CCGResult(x, it, residual, False, lam)
        tau = rf_t / tat
        x, clipped, entering, total = kern.step(x, t, tau, ax, b, lam)
        if clipped or entering:
            if mean is not None:
                x = kern.scale(x, mean * n / total)
            xh = op.forward(x)
            fresh = True
        else:
            xh = kern.axpy_spectrum(xh, tau, th)
            fresh = False
        ax = op.apply_hat(xh)
        # Restart conjugacy when bound points were released (Polonsky-Keer). Keeping it through
        # clipping measured fewer iterations (1024^2 caps, 31 % contact: 120 against 170).
        restart = entering
    return CCGResult(x, max_iter, residual, False, lam)


def _preconditioned_cg(
    kern: ArrayKernels,
    op: FFTOperator,
    precond: FFTOperator,
    b: Any,
    x0: Any,
    *,
    mean: float | None,
    scale: float,
    tol: float,
    max_iter: int,
    stall: int | None,
    own: bool = False,
    callback: Callable[[int, float], None] | None = None,
) -> CCGResult:
    """Preconditioned, projected conjugate gradient on the working set.

    The compliance of the half-space (primal) is a smoothing operator of order -1 in |q|: its
    condition number on an n x n grid grows like n, and the plain conjugate gradient needs
    O(sqrt n) iterations, most of them spent on the short wavelengths. The stiffness (its
    inverse, order +1) restricted to the contact set is spectrally close to the inverse of the
    compliance restricted to that set (opposite-order preconditioning of boundary-integral
    operators on a screen: the condition number then grows only like a power of log n), so the
    iterations hardly grow with the grid. The same holds for the dual with the roles swapped.

    One iteration: ``W`` = free points plus bound points whose gradient points into the
    feasible set (Polonsky-Keer release, restarting conjugacy); ``rw`` = the gradient on W
    (centred on W under the mean constraint); ``z = W * precond(rw)`` (centred on W);
    ``t = z + beta t``, ``beta = rw.z / rw_old.z_old`` (Fletcher-Reeves for PCG); exact line
    search ``tau = rw.t / t.A t``; projection onto ``x >= 0``.

    Transforms per iteration: ``A x`` afresh in double precision (one rfft2 + irfft2 pair, so
    no rounding drift accumulates and no final re-check is needed), the preconditioner and
    ``t.A t`` in single precision (one pair and one forward transform in float32, together
    about half a float64 pair with SciPy's FFT, 0.7-1x one with ducc0's).
    """
    xp = kern.xp
    n = math.prod(x0.shape)  # PyTorch's .size is a method
    x = x0 if own else xp.asarray(x0, copy=True)  # own: the caller hands x0 over
    del x0
    if mean is not None:
        m = float(xp.mean(x))
        if m > 0:
            x = kern.scale(x, mean / m)
    ax = op(x)
    t = xp.zeros_like(x)
    rw = xp.zeros_like(x)
    w = kern.mask_like(x)
    rz_old = 0.0
    restart = True
    lam = 0.0
    residual = math.inf
    best, best_it = math.inf, 0
    it = 0
    while True:
        rw, w, lam, g, viol2, nwork, srw, nenter = kern.gradient(ax, b, x, lam, mean is not None, rw, w)
        residual = math.sqrt((g + viol2) / n) / scale
        if callback is not None:
            callback(it, residual)
        if residual < tol:
            return CCGResult(x, it, residual, True, lam, ax)
        if it >= max_iter:
            return CCGResult(x, it, residual, False, lam)
        it += 1
        if residual < 0.5 * best:
            best, best_it = residual, it
        elif stall is not None and it - best_it > stall:
            return CCGResult(x, it, residual, False, lam)
        if nwork == 0:
            return CCGResult(x, it, residual, False, lam)
        if mean is not None and nenter:
            # feasible directions keep the mean: the gradient projected on sum(t) = 0 over W
            # (without released points it sums to zero on W already, by the multiplier)
            rw = kern.shift_on(rw, w, srw / nwork)
        z = precond.apply_low(rw)
        rz, sz, st = kern.pre_stats(rw, z, w, t)
        beta = 0.0 if (restart or nenter or rz_old <= 0) else rz / rz_old
        c = (sz + beta * st) / nwork if mean is not None else 0.0
        t, rt = kern.pre_direction(z, w, t, beta, c, rw)
        if rt <= 0 and beta != 0.0:
            # descent lost (projections, single-precision preconditioner): restart
            t, rt = kern.pre_direction(z, w, t, 0.0, sz / nwork if mean is not None else 0.0, rw)
        rz_old = rz
        restart = False
        tat = op.quad_low(t)
        if rt <= 0 or tat <= 0:
            return CCGResult(x, it, residual, False, lam)
        x, nclip, total = kern.pstep(x, t, rt / tat, mean is not None)
        if mean is not None and total > 0 and (nclip or abs(total - mean * n) > 1e-14 * mean * n):
            # back onto mean(x) = mean after clipping (or rounding drift of the centred steps)
            x = kern.scale(x, mean * n / total)
        ax = None  # release the old A x before the transform allocates the new one
        ax = op(x)


# --------------------------------------------------------------------------------------------
