"""The two formulations of one contact solve: what a run of the constrained conjugate gradient
is given and what its result becomes (the iteration itself is :mod:`.ccg`'s, the choice of
formulation, nested starts and fallbacks :class:`.solver.HalfSpaceSolver`'s).

* primal (``x = p``): minimise ``1/2 p.K p - h.p``, ``p >= 0``, with the compliance ``K`` (the
  layered one with a layer), mean pressure fixed under load control (its multiplier is the
  rigid-body level, hence the approach);
* dual (``x = g``, periodic cells): minimise ``1/2 g.S g + (S h + p_mean).g``, ``g >= 0``, with
  the stiffness ``S = K^-1``; the gradient is the pressure, the q = 0 mode of which is the load.

Split out of :mod:`.solver` (which passed 500 lines with the layered skin): these functions take
the solver (:class:`SolverFields`: operators, heights, tolerance, kernels), read it and never change it.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

import numpy as np

from .ccg import CCGResult, constrained_cg
from .greens import Backend
from .result import ContactResult, contact_state

__all__ = ["SolverFields", "finish", "gap_guess", "gap_scale", "run_formulation"]


class SolverFields(Protocol):
    """What these functions read of a :class:`fingerpad.contact.solver.HalfSpaceSolver` (named
    here so that this module does not import the solver back): the texture and its heights (m),
    the modulus E* (Pa), the operators, tolerance and kernels."""

    texture: Any
    modulus: float
    tol: float
    max_iter: int
    backend: Backend
    h: Any
    h_max: float
    h_mean: float
    pv: float
    base: Any
    _xp: Any
    _kern: Any
    _K: Any

    @property
    def _S(self) -> Any: ...

    @property
    def _Sh(self) -> Any: ...

    def _precond(self, form: str) -> Any: ...

    def _callback(self) -> Callable[[int, float], None] | None: ...


def run_formulation(s: SolverFields, form: str, mode: str, value: float, seed: Any,
                    stall: int | None = None) -> CCGResult:
    """One constrained conjugate-gradient run of ``form`` (``"primal"``: pressure unknowns,
    compliance operator; ``"dual"``: gap unknowns, stiffness operator) at a mean pressure
    (``mode="pressure"``, Pa) or an approach (``"approach"``, m): its right-hand side, starting
    point (from ``seed``, whose ``pressure``/``gap`` a nested or warm start supplies), the
    fixed mean of the unknown and the scale that makes its residual relative (module docstring of
    :mod:`.solver`)."""
    xp = s._xp
    be = s.backend
    pre = s._precond(form)
    if form == "primal":
        if mode == "pressure":
            b = s.h
            x0 = be.asarray(seed.pressure) if seed is not None else xp.full(s.h.shape, value, dtype=xp.float64)
            x0 = xp.maximum(x0, 0.0)  # a fresh array: the solve updates it in place
            del seed  # the caller's seed may be the only other full-size field alive
            m = float(xp.mean(x0))
            if m > 0:
                x0 *= value / m
            else:
                x0 = xp.full(s.h.shape, value, dtype=xp.float64)
            return constrained_cg(s._kern, s._K, b, x0, mean=value, scale=gap_scale(s, value), tol=s.tol,
                                  max_iter=s.max_iter, stall=stall, precond=pre, own=True,
                                  callback=s._callback())
        b = s.h - (s.h_max - value)
        if seed is not None:
            x0 = xp.maximum(be.asarray(seed.pressure), 0.0)
        else:
            x0 = xp.where(b > 0, b, 0.0) * (s.modulus / max(s.texture.size) * 4)
        return constrained_cg(s._kern, s._K, b, x0, mean=None, scale=max(s.pv, 1e-3 * abs(value)),
                              tol=s.tol, max_iter=s.max_iter, stall=stall, precond=pre, own=True, callback=s._callback())
    # dual: unknown gap, gradient = pressure
    if mode == "pressure":
        b = -(s._Sh + value)
        x0 = xp.maximum(be.asarray(seed.gap), 0.0) if seed is not None else gap_guess(s)
        return constrained_cg(s._kern, s._S, b, x0, mean=None, scale=value, tol=s.tol,
                              max_iter=s.max_iter, stall=stall, precond=pre, own=True,
                              callback=s._callback())
    target = s.h_max - value - s.h_mean  # mean gap for a zero-mean displacement
    b = -s._Sh
    x0 = xp.maximum(be.asarray(seed.gap), 0.0) if seed is not None else xp.maximum(s.h_max - s.h, 0.0)
    mx = float(xp.mean(x0))
    x0 = x0 * (target / mx) if mx > 0 else xp.full(s.h.shape, target, dtype=xp.float64)
    scale = s.modulus * s.pv / max(s.texture.size)
    return constrained_cg(s._kern, s._S, b, x0, mean=target, scale=scale, tol=s.tol,
                          max_iter=s.max_iter, stall=stall, precond=pre, own=True, callback=s._callback())


def gap_scale(s: SolverFields, pressure: float) -> float:
    """Length that makes the primal residual relative: the texture's peak-to-valley height,
    but at least 1e-3 of the displacement the mean pressure gives the patch, so that a flat
    (or nearly flat) map, a flat punch, converges instead of dividing by zero."""
    return max(s.pv, 1e-3 * pressure * max(s.texture.size) / s.modulus)


def gap_guess(s: SolverFields) -> Any:
    """The dual's starting gap (m) on cells too small for a coarse-to-fine start: the skin plane
    at the texture's mid-height, gaps where it does not reach."""
    xp = s._xp
    return xp.maximum(s.h_max - s.h - 0.5 * s.pv, 0.0)


def finish(s: SolverFields, form: str, mode: str, value: float, raw: CCGResult, seconds: float) -> ContactResult:
    """The :class:`ContactResult` of a run: pressure (Pa), gap and displacement (m) recovered from
    the formulation's unknown, the approach (m) from the multiplier of the fixed mean (load
    control) or as given, and the contact fraction and state."""
    xp = s._xp
    be = s.backend
    tex = s.texture
    if form == "primal":
        p = raw.x
        u = raw.ax if raw.ax is not None else s._K(p)
        if mode == "pressure":
            # g = u - h + c with c fixed by the multiplier (zero gap on the contact set).
            gap = u - s.h - raw.multiplier
        else:
            gap = u - s.h + s.h_max - value
    else:
        gap = raw.x
        if mode == "pressure":
            p = s._S(gap) + s._Sh + value
        else:
            p = s._S(gap) + s._Sh - raw.multiplier
        # Tension of the order of the residual can remain on contact points; it is part of
        # the reported residual, and the field itself is kept non-negative.
        p = xp.where(gap > 0, 0.0, xp.maximum(p, 0.0))
        u = None
    p_np = be.to_numpy(p)
    g_np = be.to_numpy(gap)
    if tex.periodic:
        mean_gap = float(g_np.mean())
        approach = s.h_max - s.h_mean - mean_gap
        disp = g_np + tex.heights - (s.h_max - approach)
    else:
        # gap = u - h - lambda = u + h_max - h - d  =>  d = h_max + lambda
        approach = value if mode == "approach" else s.h_max + raw.multiplier
        disp = be.to_numpy(u) if u is not None else g_np + tex.heights - (s.h_max - approach)
        mean_gap = float(g_np.mean())
    contact = p_np > 0
    frac = float(np.count_nonzero(contact)) / contact.size
    mean_p = float(p_np.mean())
    return ContactResult(
        pressure=p_np,
        gap=g_np,
        displacement=disp,
        mean_pressure=mean_p,
        approach=float(approach),
        contact_fraction=frac,
        real_contact_area=frac * tex.area,
        max_pressure=float(p_np.max()),
        mean_gap=mean_gap,
        iterations=raw.iterations,
        residual=raw.residual,
        converged=raw.converged,
        seconds=seconds,
        formulation=form,
        contact_state=contact_state(contact, s.base),
        texture=tex,
        modulus=s.modulus,
        tol=s.tol,
    )
