"""The NumPy kernels of the preconditioned iteration on two row blocks at once.

An iteration of the constrained conjugate gradient is a few FFTs, which use every core, plus a
dozen memory-bound element-wise passes and reductions, which NumPy runs on one: at 1024^2 on
two cores those passes are about half of a solve's time (issue 23). NumPy releases the GIL in
its loops, so the passes can run on the two halves of the field in two threads; each kernel
below is :class:`~fingerpad.contact.kernels.NumpyKernels`'s, split where it needs a global
number (the multiplier's change needs the free set's sums over the whole field before the
working set can be formed, so the gradient takes three rounds).

Results do not depend on the number of threads: the field is always cut into the same two
halves, and the partial results are combined in the same order whether the halves run in
parallel or one after the other. Sums are NumPy's pairwise sums, which split an array at its
middle (to a multiple of 8 elements) anyway: the sum of the two halves' sums *is* the sum over
the field, bit for bit. The dot products (``einsum``) differ from one over the whole field in
the last bit or two, which moves nothing the solver reports beyond its tolerance.

Only the preconditioned primal path's kernels are blocked (the default's); the others are
the parent's.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np

from .kernels import NumpyKernels

__all__ = ["BLOCKED_MIN_ROWS", "BlockedNumpyKernels", "blocked_applies"]

#: Fields of at least this many rows are cut in two (an even count, so that both halves hold a
#: multiple of 8 elements for the row lengths the solver uses). Below it a pass takes well
#: under a millisecond and handing half of it to a thread does not pay.
BLOCKED_MIN_ROWS = 512

_POOL: ThreadPoolExecutor | None = None
_POOL_LOCK = threading.Lock()


def _pool() -> ThreadPoolExecutor:
    # One helper thread for the process: the calling thread runs the first half itself.
    global _POOL
    with _POOL_LOCK:
        if _POOL is None:
            _POOL = ThreadPoolExecutor(max_workers=1, thread_name_prefix="fingerpad-kernels")
        return _POOL


def blocked_applies(shape: tuple[int, ...]) -> bool:
    """Whether a field of ``shape`` is cut in two halves (by the shape alone, never by the
    machine, so that results are the same on any number of cores)."""
    return len(shape) == 2 and shape[0] >= BLOCKED_MIN_ROWS and shape[0] % 2 == 0 and (shape[0] // 2) * shape[1] % 8 == 0


class BlockedNumpyKernels(NumpyKernels):
    """:class:`~fingerpad.contact.kernels.NumpyKernels` on two row blocks.

    Parameters
    ----------
    threads
        1: the halves one after the other (same results, no thread); 2 or more: the second
        half in a helper thread while the calling thread does the first.
    """

    def __init__(self, threads: int) -> None:
        super().__init__()
        self.threads = int(threads)

    def _halves(self, x: np.ndarray) -> tuple[slice, slice]:
        m = x.shape[0] // 2
        return slice(0, m), slice(m, x.shape[0])

    def _both(self, x: np.ndarray, fn: Callable[[slice], Any]) -> tuple[Any, Any]:
        first, second = self._halves(x)
        if self.threads < 2:
            return fn(first), fn(second)
        later = _pool().submit(fn, second)
        try:
            a = fn(first)
        finally:
            b = later.result()  # the helper's half is done before anything reads it
        return a, b

    def gradient(self, ax, b, x, lam, constrained, rw, w):
        if not blocked_applies(x.shape):
            return super().gradient(ax, b, x, lam, constrained, rw, w)
        d = self._scratch("d", x.shape)
        enter = self._scratch("enter", x.shape, bool)
        shift = lam if constrained and lam else 0.0

        def stats(s: slice) -> tuple[int, float, float]:
            np.subtract(ax[s], b[s], out=rw[s])
            if shift:
                rw[s] -= shift
            np.greater(x[s], 0.0, out=w[s])
            np.multiply(rw[s], w[s], out=d[s])
            return int(np.count_nonzero(w[s])), float(d[s].sum()), self._dot(d[s], d[s])

        (n1, a1, q1), (n2, a2, q2) = self._both(x, stats)
        nfree, s1, s2 = n1 + n2, a1 + a2, q1 + q2
        dl = s1 / nfree if constrained and nfree > 0 else 0.0
        g = max(s2 - s1 * dl, 0.0) if dl else s2

        def released(s: slice) -> int:
            np.less(rw[s], dl, out=enter[s])
            np.greater(enter[s], w[s], out=enter[s])  # r < 0 and not free
            return int(np.count_nonzero(enter[s]))

        ne = sum(self._both(x, released))
        if ne == 0:
            def free_only(s: slice) -> None:
                if dl:
                    np.subtract(d[s], dl, out=d[s], where=w[s])
                np.copyto(rw[s], d[s])

            self._both(x, free_only)
            return rw, w, lam + dl, g, 0.0, nfree, 0.0, 0

        def working(s: slice) -> tuple[float, float]:
            if dl:
                rw[s] -= dl
            np.logical_or(w[s], enter[s], out=w[s])
            rw[s] *= w[s]
            np.multiply(rw[s], enter[s], out=d[s])
            return self._dot(d[s], d[s]), float(rw[s].sum())

        (v1, r1), (v2, r2) = self._both(x, working)
        return rw, w, lam + dl, g, v1 + v2, nfree + ne, r1 + r2, ne

    def shift_on(self, a, w, c):
        if not blocked_applies(a.shape):
            return super().shift_on(a, w, c)
        self._both(a, lambda s: np.subtract(a[s], c, out=a[s], where=w[s]))
        return a

    def pre_stats(self, rw, z, w, t):
        if not blocked_applies(rw.shape):
            return super().pre_stats(rw, z, w, t)
        z64 = self._scratch("z", rw.shape)

        def stats(s: slice) -> tuple[float, float, float]:
            np.multiply(z[s], w[s], out=z64[s])  # z on W, in double precision
            return self._dot(rw[s], z64[s]), float(z64[s].sum()), float(t[s].sum())

        (a1, b1, c1), (a2, b2, c2) = self._both(rw, stats)
        return a1 + a2, b1 + b2, c1 + c2

    def pre_direction(self, z, w, t, beta, c, rw):
        if not blocked_applies(rw.shape):
            return super().pre_direction(z, w, t, beta, c, rw)
        z64 = self._buf[("d", rw.shape)]

        def direction(s: slice) -> float:
            if beta:
                t[s] *= beta
                t[s] += z64[s]
            else:
                np.copyto(t[s], z64[s])
            if c:
                np.subtract(t[s], c, out=t[s], where=w[s])
            return self._dot(rw[s], t[s])

        d1, d2 = self._both(rw, direction)
        return t, d1 + d2

    def pstep(self, x, t, tau, need_total=True):
        if not blocked_applies(x.shape):
            return super().pstep(x, t, tau, need_total)
        d = self._scratch("d", x.shape)
        self._steps = getattr(self, "_steps", 0) + 1
        # the parent sums x every 8th step when asked (rounding drift of the mean); here the sum
        # rides along with the step's own pass, or with the clipping's when it clips
        want_total = need_total and self._steps % 8 == 0

        def step(s: slice) -> tuple[float, float]:
            np.multiply(t[s], tau, out=d[s])
            x[s] -= d[s]
            return float(x[s].min()), float(x[s].sum()) if want_total else 0.0

        (m1, t1), (m2, t2) = self._both(x, step)
        if min(m1, m2) >= 0.0:
            return x, 0, (t1 + t2) if want_total else float("nan")
        neg = self._scratch("enter", x.shape, bool)

        def clip(s: slice) -> tuple[int, float]:
            np.less(x[s], 0.0, out=neg[s])
            n = int(np.count_nonzero(neg[s]))
            np.maximum(x[s], 0.0, out=x[s])
            np.copyto(t[s], 0.0, where=neg[s])  # clipped points leave the working set
            return n, float(x[s].sum())

        (n1, c1), (n2, c2) = self._both(x, clip)
        return x, n1 + n2, c1 + c2

    def scale(self, x, factor):
        if not blocked_applies(x.shape):
            return super().scale(x, factor)

        def times(s: slice) -> None:
            x[s] *= factor

        self._both(x, times)
        return x
