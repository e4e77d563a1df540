"""Fused element-wise kernels compiled with Numba (``kernels="numba"``).

The same interface as :class:`fingerpad.contact.kernels.ArrayKernels`, for NumPy arrays, in place
where the algorithm allows: one pass over the fields where NumPy needs several.

The loops are serial, on purpose. Parallel ones (``prange`` on OpenMP threads) measured no
faster than NumPy: after each loop the OpenMP threads spin-wait, and they took the cores from the
FFT's own threads, which then ran 2x slower (1024^2 cap cell, 2 cores: r2c 148 ms against 77 ms
per solve). ``OMP_WAIT_POLICY=PASSIVE`` cured that, but must be set before the process starts.
Serial, a solve takes ~20 % less time than with the NumPy kernels, and the reductions do not
depend on the number of threads.

Importing Numba and loading the compiled loops from its cache costs ~0.5 s per process (~1 s
when they must be compiled first), which is why the solver's ``kernels="auto"`` starts on
:class:`fingerpad.contact.kernels.NumpyKernels` and turns to these only once the work done
makes that load pay back, or from the first solve on very large grids
(:class:`fingerpad.contact.HalfSpaceSolver`).
"""

from __future__ import annotations

import threading
from typing import Any

import numpy as np

from .kernels import ArrayKernels

__all__ = ["NumbaKernels"]


def _build_numba() -> Any:
    import numba as nb  # noqa: PLC0415

    # serial (see the module docstring); fastmath off: the reductions keep IEEE order
    opts = dict(fastmath=False, cache=True, nogil=True)

    @nb.njit(**opts)
    def free_stats(ax, b, x, shift):  # pragma: no cover - compiled
        n = 0
        s1 = 0.0
        s2 = 0.0
        for i in range(x.size):
            if x[i] > 0:
                d = ax[i] - b[i] - shift
                n += 1
                s1 += d
                s2 += d * d
        return n, s1, s2

    @nb.njit(**opts)
    def direction(ax, b, x, lam, t, beta):  # pragma: no cover - compiled
        v = 0.0
        st = 0.0
        rt = 0.0
        for i in range(x.size):
            r = ax[i] - b[i] - lam
            if x[i] > 0:
                tn = r + beta * t[i]
                t[i] = tn
                st += tn
                rt += r * tn
            else:
                t[i] = 0.0
                if r < 0:
                    v += r * r
        return v, st, rt

    @nb.njit(**opts)
    def centre(t, x, c):  # pragma: no cover - compiled
        for i in range(x.size):
            if x[i] > 0:
                t[i] -= c

    @nb.njit(**opts)
    def step(x, t, tau, ax, b, lam):  # pragma: no cover - compiled
        nclip = 0
        nenter = 0
        total = 0.0
        for i in range(x.size):
            xi = x[i]
            if xi > 0:
                s = xi - tau * t[i]
                if s < 0:
                    s = 0.0
                    nclip += 1
            else:
                r = ax[i] - b[i] - lam
                if r < 0:
                    s = -tau * r
                    nenter += 1
                else:
                    s = 0.0
            x[i] = s
            total += s
        return nclip, nenter, total

    @nb.njit(**opts)
    def quad(w, th):  # pragma: no cover - compiled
        q = 0.0
        for i in range(th.size):
            z = th[i]
            q += w[i] * (z.real * z.real + z.imag * z.imag)
        return q

    @nb.njit(**opts)
    def axpy(xh, tau, th):  # pragma: no cover - compiled
        for i in range(xh.size):
            xh[i] -= tau * th[i]

    @nb.njit(**opts)
    def scale(x, f):  # pragma: no cover - compiled
        for i in range(x.size):
            x[i] *= f

    @nb.njit(**opts)
    def work_residual(ax, b, x, lam, rw, w):  # pragma: no cover - compiled
        nw = 0
        ne = 0
        srw = 0.0
        v = 0.0
        for i in range(x.size):
            r = ax[i] - b[i] - lam
            if x[i] > 0:
                rw[i] = r
                w[i] = 1
                nw += 1
                srw += r
            elif r < 0:
                rw[i] = r
                w[i] = 1
                nw += 1
                ne += 1
                srw += r
                v += r * r
            else:
                rw[i] = 0.0
                w[i] = 0
        return nw, srw, v, ne

    @nb.njit(**opts)
    def shift_on(a, w, c):  # pragma: no cover - compiled
        for i in range(a.size):
            if w[i]:
                a[i] -= c

    @nb.njit(**opts)
    def pre_stats(rw, z, w, t):  # pragma: no cover - compiled
        rz = 0.0
        sz = 0.0
        st = 0.0
        for i in range(z.size):
            if w[i]:
                rz += rw[i] * z[i]
                sz += z[i]
                st += t[i]
        return rz, sz, st

    @nb.njit(**opts)
    def pre_direction(z, w, t, beta, c, rw):  # pragma: no cover - compiled
        rt = 0.0
        for i in range(z.size):
            if w[i]:
                tn = z[i] + beta * t[i] - c
                t[i] = tn
                rt += rw[i] * tn
            else:
                t[i] = 0.0
        return rt

    @nb.njit(**opts)
    def pstep(x, t, tau):  # pragma: no cover - compiled
        nclip = 0
        total = 0.0
        for i in range(x.size):
            s = x[i] - tau * t[i]
            if s < 0:
                s = 0.0
                nclip += 1
            x[i] = s
            total += s
        return nclip, total

    # Compile (or load from the cache) now the loops of the default, preconditioned iteration,
    # on the types the solver passes, so that a failure shows here, where the caller falls back
    # to NumPy, and not in the middle of a solve (a cache directory that cannot be written fails
    # already at the decorators above). The plain iteration's loops load on first use (~35 ms
    # each).
    # (z, the preconditioned gradient, is float32: greens.FFTOperator.apply_low)
    f, z, m = np.ones(4), np.ones(4, dtype=np.float32), np.ones(4, dtype=np.uint8)
    free_stats(f, f, f, 0.0)
    work_residual(f, f, f, 0.0, f.copy(), m.copy())
    shift_on(f.copy(), m, 0.0)
    pre_stats(f, z, m, f)
    pre_direction(z, m, f.copy(), 0.0, 0.0, f)
    pstep(f.copy(), f, 0.0)
    scale(f.copy(), 1.0)
    return (free_stats, direction, centre, step, quad, axpy, scale,
            work_residual, shift_on, pre_stats, pre_direction, pstep)


_NUMBA: Any = None
_BUILD = threading.Lock()  # solvers in threads (the explorer's jobs, threaded Dask workers) build once


class NumbaKernels(ArrayKernels):
    """Fused, serial loops for NumPy arrays (in place where the algorithm allows)."""

    def __init__(self) -> None:
        global _NUMBA
        with _BUILD:
            if _NUMBA is None:
                _NUMBA = _build_numba()
        (self._free_stats, self._direction, self._centre, self._step, self._quad,
         self._axpy, self._scale, self._work_residual, self._shift_on, self._pre_stats,
         self._pre_direction, self._pstep) = _NUMBA
        super().__init__(np)

    @staticmethod
    def _flat(a: np.ndarray) -> np.ndarray:
        return a.reshape(-1)

    def free_stats(self, ax, b, x, shift):
        n, s1, s2 = self._free_stats(self._flat(ax), self._flat(b), self._flat(x), float(shift))
        return int(n), float(s1), float(s2)

    def direction(self, ax, b, x, lam, t, beta):
        t = np.array(t, copy=True) if not t.flags.writeable else t
        v, st, rt = self._direction(self._flat(ax), self._flat(b), self._flat(x), float(lam), self._flat(t), float(beta))
        return t, v, st, rt

    def centre(self, t, x, c):
        self._centre(self._flat(t), self._flat(x), float(c))
        return t

    def step(self, x, t, tau, ax, b, lam):
        # in place: the solver owns its iterate and does not need the old one
        nclip, nenter, total = self._step(self._flat(x), self._flat(t), float(tau), self._flat(ax), self._flat(b), float(lam))
        return x, nclip > 0, nenter > 0, float(total)

    def quad(self, weights, th):
        return float(self._quad(self._flat(weights), self._flat(th)))

    def axpy_spectrum(self, xh, tau, th):
        self._axpy(self._flat(xh), float(tau), self._flat(th))
        return xh

    def scale(self, x, factor):
        self._scale(self._flat(x), float(factor))
        return x

    def mask_like(self, x):
        return np.zeros(x.shape, dtype=np.uint8)

    def work_residual(self, ax, b, x, lam, rw, w):
        f = self._flat
        nw, srw, v, ne = self._work_residual(f(ax), f(b), f(x), float(lam), f(rw), f(w))
        return rw, w, int(nw), float(srw), float(v), int(ne)

    def shift_on(self, a, w, c):
        self._shift_on(self._flat(a), self._flat(w), float(c))
        return a

    def pre_stats(self, rw, z, w, t):
        f = self._flat
        rz, sz, st = self._pre_stats(f(rw), f(z), f(w), f(t))
        return float(rz), float(sz), float(st)

    def pre_direction(self, z, w, t, beta, c, rw):
        f = self._flat
        rt = self._pre_direction(f(z), f(w), f(t), float(beta), float(c), f(rw))
        return t, float(rt)

    def pstep(self, x, t, tau, need_total=True):
        nclip, total = self._pstep(self._flat(x), self._flat(t), float(tau))
        return x, int(nclip), float(total)
