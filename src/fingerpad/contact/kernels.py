"""Element-wise building blocks of the constrained conjugate gradient.

An iteration is a few FFTs plus a dozen element-wise operations and reductions. Three
implementations share one interface:

* :class:`ArrayKernels` - the reference, one array-API call per operation, for any namespace
  (``array_api_strict`` in the tests, CuPy or PyTorch on a GPU);
* :class:`NumpyKernels` - NumPy in place, into buffers owned by the kernels (no allocation per
  iteration, as few passes as NumPy allows); the default for NumPy arrays, run on two row
  halves in two threads for fields of 512 rows or more
  (:class:`~fingerpad.contact.kernels_blocked.BlockedNumpyKernels`);
* :class:`~fingerpad.contact.kernels_numba.NumbaKernels` - fused serial loops compiled with
  Numba (``kernels="numba"``, module :mod:`fingerpad.contact.kernels_numba`): ~20 % faster
  solves, but ~0.5 s to load per process, so ``kernels="auto"`` takes them once a solver's
  work makes that pay (long load curves; the first solve on very large grids).

Notation: ``x`` the iterate (pressure or gap), ``ax`` = A x, ``b`` the linear term, ``lam``
the multiplier of the mean constraint, ``free`` = ``x > 0``, ``r = ax - b - lam`` the gradient,
``W`` the working set of the preconditioned iteration (free points and bound points with
``r < 0``).
"""

from __future__ import annotations

from typing import Any

import numpy as np


class ArrayKernels:
    """Reference implementation on an array namespace ``xp``."""

    def __init__(self, xp: Any) -> None:
        self.xp = xp

    def free_stats(self, ax: Any, b: Any, x: Any, shift: float) -> tuple[int, float, float]:
        """Number of free points and the first two moments of ``ax - b - shift`` over them.

        The shift (the previous multiplier) keeps the variance free of cancellation.
        """
        xp = self.xp
        free = x > 0
        d = xp.where(free, ax - b - shift, 0.0)
        return int(xp.count_nonzero(free)), float(xp.sum(d)), float(xp.sum(d * d))

    def direction(self, ax: Any, b: Any, x: Any, lam: float, t: Any, beta: float) -> tuple[Any, float, float, float, float]:
        """New direction ``t = free ? r + beta t : 0`` and (|KKT violation|^2 off the free set,
        sum of t, r_free . t). Updates ``t`` in place where the implementation can."""
        xp = self.xp
        free = x > 0
        r = ax - b - lam
        rf = xp.where(free, r, 0.0)
        viol = xp.where(free, 0.0, xp.minimum(r, 0.0))
        t_new = xp.where(free, rf + beta * t, 0.0) if beta else rf
        return (
            t_new,
            float(xp.sum(viol * viol)),
            float(xp.sum(t_new)),
            float(xp.sum(rf * t_new)),
        )

    def centre(self, t: Any, x: Any, c: float) -> Any:
        """Subtract ``c`` from t on the free set (t stays zero elsewhere)."""
        xp = self.xp
        return xp.where(x > 0, t - c, 0.0)

    def step(self, x: Any, t: Any, tau: float, ax: Any, b: Any, lam: float) -> tuple[Any, bool, bool, float]:
        """Projected step: ``x - tau t`` clipped at 0, bound points with a descent gradient
        released to ``-tau r``. Returns (new x, clipped?, entering?, sum of new x)."""
        xp = self.xp
        free = x > 0
        r = ax - b - lam
        s = x - tau * t
        clipped = bool(xp.any(s < 0))
        enter = (~free) & (r < 0)
        entering = bool(xp.any(enter))
        if clipped:
            s = xp.maximum(s, 0.0)
        if entering:
            s = xp.where(enter, -tau * r, s)
        return s, clipped, entering, float(xp.sum(s))

    def quad(self, weights: Any, th: Any) -> float:
        """sum(weights |th|^2) over the half spectrum (Parseval)."""
        xp = self.xp
        return float(xp.sum(weights * (xp.real(th) ** 2 + xp.imag(th) ** 2)))

    def axpy_spectrum(self, xh: Any, tau: float, th: Any) -> Any:
        """``xh - tau th``."""
        return xh - tau * th

    def scale(self, x: Any, factor: float) -> Any:
        return x * factor

    def release(self) -> None:
        """Drop scratch buffers between solves (none here)."""

    # ---- preconditioned path (working set W = free points and bound points with a descent gradient)

    def mask_like(self, x: Any) -> Any:
        """A boolean mask buffer of the shape of ``x``."""
        return self.xp.zeros(x.shape, dtype=self.xp.bool)

    def gradient(self, ax: Any, b: Any, x: Any, lam: float, constrained: bool, rw: Any, w: Any) -> tuple:
        """The gradient of the preconditioned iteration in one call: the multiplier updated from
        the free points (``constrained``: the mean of x is fixed), the free-set variance ``g``,
        then :meth:`work_residual` with the new multiplier. Returns (rw, w, lam, g, viol2,
        |W|, sum of rw, number of released points)."""
        nfree, s1, s2 = self.free_stats(ax, b, x, lam if constrained else 0.0)
        if constrained and nfree > 0:
            lam += s1 / nfree
            g = max(s2 - s1 * s1 / nfree, 0.0)
        else:
            g = s2
        rw, w, nwork, srw, viol2, nenter = self.work_residual(ax, b, x, lam, rw, w)
        return rw, w, lam, g, viol2, nwork, srw, nenter

    def work_residual(self, ax: Any, b: Any, x: Any, lam: float, rw: Any, w: Any) -> tuple[Any, Any, int, float, float, int]:
        """Gradient on the working set: ``w = (x > 0) | (r < 0)``, ``rw = w ? r : 0`` with
        ``r = ax - b - lam``. Returns (rw, w, |W|, sum of rw, |KKT violation|^2 off the free set,
        number of bound points in W)."""
        xp = self.xp
        r = ax - b - lam
        free = x > 0
        enter = (~free) & (r < 0)
        w_new = free | enter
        rw_new = xp.where(w_new, r, 0.0)
        viol = xp.where(enter, r, 0.0)
        return (
            rw_new,
            w_new,
            int(xp.count_nonzero(w_new)),
            float(xp.sum(rw_new)),
            float(xp.sum(viol * viol)),
            int(xp.count_nonzero(enter)),
        )

    def shift_on(self, a: Any, w: Any, c: float) -> Any:
        """``a - c`` on the mask ``w`` (``a`` is zero off it)."""
        return self.xp.where(w, a - c, 0.0)

    def pre_stats(self, rw: Any, z: Any, w: Any, t: Any) -> tuple[float, float, float]:
        """(rw . z, sum of z on W, sum of t on W)."""
        xp = self.xp
        return float(xp.sum(rw * z)), float(xp.sum(xp.where(w, z, 0.0))), float(xp.sum(xp.where(w, t, 0.0)))

    def pre_direction(self, z: Any, w: Any, t: Any, beta: float, c: float, rw: Any) -> tuple[Any, float]:
        """``t = w ? z + beta t - c : 0`` and ``rw . t``."""
        xp = self.xp
        t_new = xp.where(w, z + beta * t - c, 0.0)
        return t_new, float(xp.sum(rw * t_new))

    def pstep(self, x: Any, t: Any, tau: float, need_total: bool = True) -> tuple[Any, int, float]:
        """``x - tau t`` clipped at 0: (new x, number of clipped points, sum of new x). The sum
        may be skipped (NaN) when ``need_total`` is false and nothing was clipped."""
        xp = self.xp
        s = x - tau * t
        nclip = int(xp.count_nonzero(s < 0))
        if nclip:
            s = xp.maximum(s, 0.0)
        return s, nclip, float(xp.sum(s))



class NumpyKernels(ArrayKernels):
    """NumPy, in place: each operation writes into a buffer the solver owns, so that an
    iteration allocates nothing (memory at 4096^2) and makes as few passes over the fields as
    NumPy allows. A solver starts on these (no load time; see :mod:`.kernels_numba`).
    """

    def __init__(self) -> None:
        super().__init__(np)
        self._buf: dict[tuple[str, tuple[int, ...]], np.ndarray] = {}

    def _scratch(self, name: str, shape: tuple[int, ...], dtype: Any = np.float64) -> np.ndarray:
        # "d" (a difference) and "z" (the preconditioned gradient) are never live together
        name = "d" if name == "z" else name
        key = (name, shape)
        a = self._buf.get(key)
        if a is None:
            a = self._buf[key] = np.empty(shape, dtype=dtype)
        return a

    @staticmethod
    def _dot(a: np.ndarray, b: np.ndarray) -> float:
        # einsum: single-threaded SIMD; BLAS dot spawns threads whose wake-up on a loaded
        # 2-core machine measured up to 8x slower (16 ms against 2 ms at 2048^2)
        return float(np.einsum("i,i->", a.reshape(-1), b.reshape(-1)))

    def mask_like(self, x):
        return np.zeros(x.shape, dtype=bool)

    def release(self) -> None:
        self._buf.clear()
        # the projected step's count decides when its sum is taken (every eighth step, for the
        # mean's drift): counted within a solve, so that a solve does not depend on how many
        # steps the solver's earlier solves took
        self._steps = 0

    def free_stats(self, ax, b, x, shift):
        d = self._scratch("d", x.shape)
        free = self._scratch("free", x.shape, bool)
        np.subtract(ax, b, out=d)
        if shift:
            d -= shift
        np.greater(x, 0.0, out=free)
        d *= free
        return int(np.count_nonzero(free)), float(d.sum()), self._dot(d, d)

    def gradient(self, ax, b, x, lam, constrained, rw, w):
        # Same results as the reference, in fewer passes: r0 = ax - b - lam_old once; the
        # multiplier's change dl and the free-set statistics from r0 on the free set; the
        # released points are those with r0 < dl off it.
        d = self._scratch("d", x.shape)
        enter = self._scratch("enter", x.shape, bool)
        np.subtract(ax, b, out=rw)
        if constrained and lam:
            rw -= lam
        np.greater(x, 0.0, out=w)
        np.multiply(rw, w, out=d)
        nfree = int(np.count_nonzero(w))
        s1 = float(d.sum())
        s2 = self._dot(d, d)
        dl = s1 / nfree if constrained and nfree > 0 else 0.0
        g = max(s2 - s1 * dl, 0.0) if dl else s2
        np.less(rw, dl, out=enter)
        np.greater(enter, w, out=enter)  # r < 0 and not free
        ne = int(np.count_nonzero(enter))
        if ne == 0:
            # rw = r on the free set: r0 - dl there, 0 elsewhere (d holds r0 on it)
            if dl:
                np.subtract(d, dl, out=d, where=w)
            np.copyto(rw, d)
            return rw, w, lam + dl, g, 0.0, nfree, 0.0, 0
        if dl:
            rw -= dl
        np.logical_or(w, enter, out=w)
        rw *= w
        np.multiply(rw, enter, out=d)
        return rw, w, lam + dl, g, self._dot(d, d), nfree + ne, float(rw.sum()), ne

    def work_residual(self, ax, b, x, lam, rw, w):
        free = self._scratch("free", x.shape, bool)
        enter = self._scratch("enter", x.shape, bool)
        np.subtract(ax, b, out=rw)
        if lam:
            rw -= lam
        np.greater(x, 0.0, out=free)
        np.less(rw, 0.0, out=enter)
        np.greater(enter, free, out=enter)  # r < 0 and not free
        ne = int(np.count_nonzero(enter))
        if ne:
            np.logical_or(free, enter, out=w)
            rw *= w
            d = self._scratch("d", x.shape)
            np.multiply(rw, enter, out=d)
            viol = self._dot(d, d)
        else:
            np.copyto(w, free)
            rw *= w
            viol = 0.0
        return rw, w, int(np.count_nonzero(w)), float(rw.sum()), viol, ne

    def shift_on(self, a, w, c):
        np.subtract(a, c, out=a, where=w)
        return a

    def pre_stats(self, rw, z, w, t):
        # t is already zero off W: pstep zeroes it where it clips, the only points that leave W
        # while t is still used (a release restarts with beta = 0)
        z64 = self._scratch("z", rw.shape)
        np.multiply(z, w, out=z64)  # z on W, in double precision
        return self._dot(rw, z64), float(z64.sum()), float(t.sum())

    def pre_direction(self, z, w, t, beta, c, rw):
        z64 = self._buf[("d", rw.shape)]
        if beta:
            t *= beta
            t += z64
        else:
            np.copyto(t, z64)
        if c:
            np.subtract(t, c, out=t, where=w)
        return t, self._dot(rw, t)

    def pstep(self, x, t, tau, need_total=True):
        d = self._scratch("d", x.shape)
        np.multiply(t, tau, out=d)
        x -= d
        nclip = 0
        if float(x.min()) < 0.0:
            neg = self._scratch("enter", x.shape, bool)
            np.less(x, 0.0, out=neg)
            nclip = int(np.count_nonzero(neg))
            np.maximum(x, 0.0, out=x)
            np.copyto(t, 0.0, where=neg)  # clipped points leave the working set
        self._steps = getattr(self, "_steps", 0) + 1
        if nclip or need_total and self._steps % 8 == 0:
            return x, nclip, float(x.sum())
        return x, nclip, float("nan")

    def scale(self, x, factor):
        x *= factor
        return x
