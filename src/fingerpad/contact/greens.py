"""Elastic operators of the half-space, applied by FFT: the "Green's functions" of the solver.

The skin is an elastic half-space of reduced modulus E* (Eq. 3.4). Its surface displacement
under a pressure field is a convolution with the Boussinesq kernel; on a regular grid it is
applied by real FFTs:

* periodic cells: ``u_q = 2 p_q / (E* |q|)`` (q != 0), the compliance, and its inverse
  ``p_q = E* |q| u_q / 2``, the stiffness (used by the dual form of the solver);
* finite bodies: Love's (1929) solution for a uniformly loaded rectangle (one pixel), applied
  as a linear convolution by zero padding to twice the size, so no periodic images appear.

:class:`Backend` wraps the array namespace (NumPy by default, any Array-API library such as
CuPy or PyTorch for a GPU) and its real FFTs; :class:`FFTOperator` exposes the spectral pieces
the conjugate gradient combines to save transforms.
"""

from __future__ import annotations

import contextlib
import functools
import os
import sys
from collections.abc import Iterator
from typing import Any

import numpy as np

from ..errors import SetupError
from ..extras import require
from ..textures import Texture
from .device import choice_setting, device_namespace
from .layered import Layer, spectral_factor
from .transforms import ducc0_transforms, scipy_transforms

__all__ = ["FFT_ENGINES", "Backend", "FFTOperator", "check_setup", "fft_settings", "fft_threads_parked", "compliance_operator", "preconditioner", "stiffness_operator", "wavenumbers",
           "love_rectangle", "smoothed_rectangle"]

FFT_ENGINES = ("auto", "ducc0", "scipy")
#: Most FFT threads one process may be given (``FINGERPAD_FFT_WORKERS``): far above any machine's
#: cores (their number changes the speed, never a result), far below a typo's 100000 threads.
MAX_FFT_WORKERS = 1024


def fft_settings(fft: str | None = None, workers: int | None = None) -> tuple[str, int]:
    """The FFT engine asked for and the FFT threads, from the arguments or the environment.

    ``fft`` (``"auto"``, ``"ducc0"`` or ``"scipy"``, any case) wins over the environment variable
    ``FINGERPAD_FFT``, which replaces the default ``"auto"``; ``workers`` wins over
    ``FINGERPAD_FFT_WORKERS``, which replaces the default of all cores. Bad values raise
    :class:`~fingerpad.errors.SetupError` naming where they came from. Cheap (no FFT library
    is imported): commands call it before they start long work, so that a bad setting stops them
    at once instead of failing every solve.
    """
    engine, _ = choice_setting(fft, "fft", "FINGERPAD_FFT", FFT_ENGINES, "FFT engine")
    if workers is None:
        raw = os.environ.get("FINGERPAD_FFT_WORKERS", "").strip()
        if len(raw) > 30:
            raise SetupError(f"FINGERPAD_FFT_WORKERS must be a whole number of threads in 0..{MAX_FFT_WORKERS}, "
                             f"got a value of {len(raw)} characters")
        try:
            workers = int(raw) if raw else 0
        except ValueError:
            raise SetupError(f"FINGERPAD_FFT_WORKERS must be a whole number of threads, got {raw!r}") from None
        source = "FINGERPAD_FFT_WORKERS"
    else:
        source = "workers"
    if isinstance(workers, bool) or not isinstance(workers, int) or not 0 <= workers <= MAX_FFT_WORKERS:
        raise SetupError(f"{source} must be a whole number of threads in 0..{MAX_FFT_WORKERS} (0: all cores), "
                         f"got {workers!r}")
    return engine, workers or os.cpu_count() or 1


@contextlib.contextmanager
def fft_threads_parked() -> Iterator[None]:
    """ducc0's FFT thread pool shrunk to the calling thread until exit: wrap every fork of this
    process (worker pools, a local Dask cluster's start).

    ducc0 stops and joins its pool's threads in a handler that runs inside ``fork()``; the suite
    once hung there for good (native stack fork -> ducc0 -> std::thread::join, ducc0 0.42,
    2026-11-29), a race that a process with many threads makes likely. With no pool thread there
    is nothing to join. The pool's size is restored on exit. The results are the same: the
    FFTs choose their threads per call (``nthreads``), and meanwhile run on the calling thread.
    Does nothing where ducc0 is not loaded (importing it here would cost time)."""
    misc = sys.modules.get("ducc0.misc")
    size = misc.thread_pool_size() if misc is not None else None
    if size is not None and size > 1:
        misc.resize_thread_pool(1)
    try:
        yield
    finally:
        if size is not None and size > 1:
            misc.resize_thread_pool(size)


class Backend:
    """Array namespace plus real FFTs.

    On NumPy arrays the transforms are ducc0's (``fft="ducc0"``) or SciPy's (``"scipy"``);
    ``"auto"`` takes ducc0 when it imports (see :func:`fft_settings` for the environment
    variables). Both are threaded pocketfft descendants and agree to rounding; ducc0 measured
    20-35 % faster solves on 1024^2-2048^2 cells and imports in ~5 ms where ``scipy.fft`` takes
    ~0.15-0.25 s (benchmarks/bench_solver.py, bench_startup.py), which the whole
    ``fingerpad solve`` command pays on every start. Other namespaces use their own ``fft``;
    without ``xp``, the environment variable ``FINGERPAD_DEVICE`` chooses the namespace
    (:func:`fingerpad.contact.device.device_namespace`; NumPy by default).
    ``self.fft`` names the engine in use. The inverse transform may overwrite its input.
    """

    def __init__(self, xp: Any = None, workers: int | None = None, fft: str | None = None) -> None:
        if xp is None:
            # FINGERPAD_DEVICE (set by the commands' --device) may ask for a GPU namespace
            xp = device_namespace()
        if xp is None:
            # NumPy 2 implements the array API in its main namespace; the array_api_compat
            # wrapper (for CuPy, PyTorch, ...) is not needed on the CPU and costs ~0.1 s to import.
            import numpy as xp_np  # noqa: PLC0415

            xp = xp_np
        if getattr(xp, "__name__", "") == "torch":
            # PyTorch's own namespace is not the Array API (rfftn takes dim=, not axes=, ...);
            # array_api_compat's wrapper of it is
            from array_api_compat import torch as xp  # noqa: PLC0415
        self.xp = xp
        self.is_numpy = "numpy" in getattr(xp, "__name__", "")
        # FINGERPAD_FFT_WORKERS: sweep workers run one FFT thread each (their parallelism is theirs).
        engine, self.workers = fft_settings(fft if self.is_numpy else "auto", workers)
        if not self.is_numpy:
            self.fft = f"{getattr(xp, '__name__', 'xp')}.fft"
            self.rfft2 = lambda a, s=None: xp.fft.rfftn(a, s=s, axes=(0, 1))
            self.irfft2 = lambda a, s: xp.fft.irfftn(a, s=s, axes=(0, 1))
            return
        if engine in ("auto", "ducc0"):
            try:
                self.rfft2, self.irfft2 = ducc0_transforms(self.workers)
                self.fft = "ducc0"
                return
            except ImportError as exc:
                if engine == "ducc0":
                    require("fast", "FFT engine 'ducc0' (FINGERPAD_FFT=scipy needs none)", ("ducc0",))
                    raise SetupError(f"the FFT engine 'ducc0' could not load: {exc}") from None
        self.rfft2, self.irfft2 = scipy_transforms(self.workers)
        self.fft = "scipy"

    def asarray(self, a: Any) -> Any:
        return self.xp.asarray(a, dtype=self.xp.float64)

    def to_numpy(self, a: Any) -> np.ndarray:
        if self.is_numpy:
            return np.asarray(a)
        if hasattr(a, "get"):  # CuPy
            return a.get()
        if hasattr(a, "cpu"):  # PyTorch (its GPU tensors do not convert implicitly)
            return a.cpu().numpy()
        return np.asarray(a)


# --------------------------------------------------------------------------------------------
# Elastic operators
# --------------------------------------------------------------------------------------------


def check_setup() -> Backend:
    """The backend every solve of this process would use, made once to check the environment's
    compute settings (``FINGERPAD_DEVICE``, ``FINGERPAD_FFT``, ``FINGERPAD_FFT_WORKERS``).

    The one rule of every front door that runs many solves (``predict``, ``sweep``, ``design``,
    the explorer, their Python functions): a device or FFT engine that is absent or misspelt
    stops the work at once, in one line, instead of failing each solve, which a job that records
    its failures per point or candidate would report as NaN results.

    Raises
    ------
    SetupError
        An unknown device or engine, a GPU library or GPU that is missing, a bad thread count.
    """
    return Backend()


def wavenumbers(shape: tuple[int, int], spacing: tuple[float, float]) -> np.ndarray:
    """|q| (rad/m) on the half-spectrum grid of rfft2 for a periodic cell."""
    nx, ny = shape
    dx, dy = spacing
    qx = 2 * np.pi * np.fft.fftfreq(nx, d=dx)
    qy = 2 * np.pi * np.fft.rfftfreq(ny, d=dy)
    return np.sqrt(qx[:, None] ** 2 + qy[None, :] ** 2)


def love_rectangle(x: np.ndarray, y: np.ndarray, a: float, b: float) -> np.ndarray:
    """Integral of 1/r over the rectangle |x'|<=a, |y'|<=b seen from (x, y) (Love 1929)."""

    def f(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
        # F(X, Y) = int_0^X int_0^Y ds dt / sqrt(s^2 + t^2), odd in X and in Y.
        ax, ay = np.abs(X), np.abs(Y)
        with np.errstate(divide="ignore", invalid="ignore"):
            t1 = np.where(ax > 0, ax * np.arcsinh(ay / np.where(ax > 0, ax, 1.0)), 0.0)
            t2 = np.where(ay > 0, ay * np.arcsinh(ax / np.where(ay > 0, ay, 1.0)), 0.0)
        return np.sign(X) * np.sign(Y) * (t1 + t2)

    return f(x + a, y + b) - f(x - a, y + b) - f(x + a, y - b) + f(x - a, y - b)


class FFTOperator:
    """A symmetric linear elastic operator applied by FFT (periodic or zero-padded).

    Besides ``A x`` it exposes the spectral pieces the solver combines to save transforms:
    ``forward`` (the real FFT of a field, zero-padded for finite bodies), ``apply_hat`` (``A x``
    from that spectrum) and ``quad`` (``t.A t`` from the spectrum of ``t`` by Parseval).
    """

    def __init__(self, backend: Backend, shape: tuple[int, int], multiplier: np.ndarray, padded: bool):
        self.b = backend
        self.shape = shape
        self.padded = padded
        self.fshape = (2 * shape[0], 2 * shape[1]) if padded else shape
        xp = backend.xp
        self.multiplier = xp.asarray(multiplier)
        self._host_multiplier = multiplier
        self._quad_weights: Any = None
        self._low_mult: Any = None
        self._low_weights: Any = None

    def _weights(self, dtype: Any) -> Any:
        # Parseval on the half spectrum: interior columns stand for two conjugate modes.
        m = self._host_multiplier
        w = np.real(m) * (2.0 / (self.fshape[0] * self.fshape[1]))
        w[:, 0] *= 0.5
        if self.fshape[1] % 2 == 0:
            w[:, -1] *= 0.5
        return self.b.xp.asarray(w.astype(dtype, copy=False))

    @property
    def quad_weights(self) -> Any:
        """Weights of ``t.A t = sum(weights |t_q|^2)`` on the half spectrum (built on first use)."""
        if self._quad_weights is None:
            self._quad_weights = self._weights(np.float64)
        return self._quad_weights

    def forward(self, x: Any) -> Any:
        return self.b.rfft2(x, s=self.fshape) if self.padded else self.b.rfft2(x)

    # Single-precision helpers. The preconditioner and the line search's curvature t.A t need
    # only a few significant digits (the iterate, A x and the residual stay in double
    # precision), and with SciPy a float32 transform costs 1/2 to 1/5 of a float64 one (measured
    # 1024^2, 2048^2; with ducc0 0.7-1x, where double precision measured no faster). Since a
    # float32 preconditioner is not exactly symmetric, the conjugate gradient keeps its descent
    # safeguard (ccg.py).

    def _low(self) -> tuple[Any, Any]:
        if self._low_mult is None:
            xp = self.b.xp
            m = self.multiplier
            dt = xp.complex64 if xp.isdtype(m.dtype, "complex floating") else xp.float32
            self._low_mult = xp.astype(m, dt)
        if self._low_weights is None:
            self._low_weights = self._weights(np.float32)
        return self._low_mult, self._low_weights

    def apply_low(self, x: Any) -> Any:
        """``A x`` in single precision (float32 result, the field's shape)."""
        xp = self.b.xp
        mult, _ = self._low()
        xh = self.forward(xp.astype(x, xp.float32))
        xh *= mult
        out = self.b.irfft2(xh, self.fshape)
        return out[: self.shape[0], : self.shape[1]] if self.padded else out

    def quad_low(self, t: Any) -> float:
        """``t.A t`` from a single-precision transform of ``t`` (Parseval), summed in double."""
        xp = self.b.xp
        _, w = self._low()
        th = self.forward(xp.astype(t, xp.float32))
        re, im = xp.real(th), xp.imag(th)
        return float(xp.sum(w * (re * re + im * im), dtype=xp.float64))

    def apply_hat(self, xh: Any) -> Any:
        out = self.b.irfft2(xh * self.multiplier, s=self.fshape)
        return out[: self.shape[0], : self.shape[1]] if self.padded else out

    def quad(self, th: Any) -> float:
        xp = self.b.xp
        return float(xp.sum(self.quad_weights * (xp.real(th) ** 2 + xp.imag(th) ** 2)))

    def __call__(self, x: Any) -> Any:
        # the spectrum is a temporary here: multiply in place (one spectrum-sized array less)
        xh = self.forward(x)
        xh *= self.multiplier
        out = self.b.irfft2(xh, self.fshape)
        return out[: self.shape[0], : self.shape[1]] if self.padded else out


def smoothed_rectangle(x: np.ndarray, y: np.ndarray, a: float, b: float, c: float) -> np.ndarray:
    """Integral of 1/sqrt(r^2 + c^2) over the rectangle |x'|<=a, |y'|<=b seen from (x, y).

    The potential of a uniformly charged rectangle at height c: with R = sqrt(X^2 + Y^2 + c^2),
    ``F(X, Y) = X ln(Y + R) + Y ln(X + R) - c atan(X Y / (c R))`` has the mixed derivative
    ``d^2F/dXdY = 1/R``; c = 0 is Love's rectangle (:func:`love_rectangle`).
    """

    def f(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
        # odd in X and in Y: evaluate on |X|, |Y| (the logarithms' arguments stay >= c > 0)
        ax, ay = np.abs(X), np.abs(Y)
        R = np.sqrt(ax * ax + ay * ay + c * c)
        with np.errstate(divide="ignore", invalid="ignore"):
            t1 = np.where(ax > 0, ax * np.log((ay + R) / np.where(ax > 0, np.sqrt(ax * ax + c * c), 1.0)), 0.0)
            t2 = np.where(ay > 0, ay * np.log((ax + R) / np.where(ay > 0, np.sqrt(ay * ay + c * c), 1.0)), 0.0)
        # the ln terms are shifted by functions of one variable (X ln sqrt(X^2+c^2), ...),
        # which the double difference below removes
        t3 = c * np.arctan2(ax * ay, c * R)
        return np.sign(X) * np.sign(Y) * (t1 + t2 - t3)

    return f(x + a, y + b) - f(x - a, y + b) - f(x + a, y - b) + f(x - a, y - b)


def _layered_multiplier(texture: Texture, modulus: float, layer: Layer | None, shape: tuple[int, int],
                        spacing: tuple[float, float]) -> tuple[np.ndarray, np.ndarray | None]:
    """``|q|`` on a periodic grid and the layer's factor there (None for the homogeneous skin)."""
    q = wavenumbers(shape, spacing)
    return q, spectral_factor(layer, q, modulus)


def compliance_operator(backend: Backend, texture: Texture, modulus: float, layer: Layer | None = None) -> FFTOperator:
    """Pressure -> displacement operator (Boussinesq, or the layered skin's), periodic or free-space.

    With a ``layer`` the periodic compliance ``2 / (E* |q|)`` is multiplied by the layer's factor
    (:func:`fingerpad.contact.layered.spectral_factor`). For finite bodies the layered kernel is
    split in three (docs/model.md, "Layered skin"): Love's rectangle of E* (exact, as for the
    homogeneous skin), the long-range excess ``(F0 - 1)/(pi E* sqrt(r^2 + t^2))`` integrated
    exactly over the pixel (F0 the factor at q -> 0), both convolved linearly (zero padding), and
    the remainder ``2/(E*|q|) [F(q) - 1 - (F0 - 1) exp(-|q| t)]``, bounded and smooth, whose
    real-space kernel (:func:`remainder_kernel`) is sampled at the pixel offsets and added to the
    rest before the zero-padded transform; for a layer thinner than two pixels it is sampled in
    Fourier space on the padded grid instead (periodic images at twice the patch size).
    """
    shape = texture.shape
    if texture.periodic:
        q, factor = _layered_multiplier(texture, modulus, layer, shape, texture.spacing)
        with np.errstate(divide="ignore"):
            mult = np.where(q > 0, 2.0 / (modulus * np.where(q > 0, q, 1.0)), 0.0)
        if factor is not None:
            mult = mult * factor
        return FFTOperator(backend, shape, mult, padded=False)
    nx, ny = shape
    dx, dy = texture.spacing
    # Offsets on the doubled grid in FFT order; the wrapped half never meets physical pixels.
    # The kernel is even in both offsets: evaluate it on one quadrant (a quarter of the
    # transcendental work) and index it by |offset|. Its spectrum is then real.
    ix = np.abs(np.fft.fftfreq(2 * nx, d=1.0 / (2 * nx))).astype(np.intp)
    iy = np.abs(np.fft.fftfreq(2 * ny, d=1.0 / (2 * ny))).astype(np.intp)
    X, Y = np.meshgrid(np.arange(nx + 1) * dx, np.arange(ny + 1) * dy, indexing="ij")
    quadrant = love_rectangle(X, Y, dx / 2, dy / 2) / (np.pi * modulus)
    if layer is not None:
        t = layer.thickness
        f0 = float(spectral_factor(layer, np.zeros(1), modulus)[0])
        quadrant = quadrant + (f0 - 1.0) * smoothed_rectangle(X, Y, dx / 2, dy / 2, t) / (np.pi * modulus)
    spectral_rest = layer is not None and layer.thickness < 2 * max(dx, dy)
    if layer is not None and not spectral_rest:
        # the remainder in real space (a radial Hankel transform), sampled at the pixel offsets:
        # no periodic images at all, whatever the layer's thickness against the patch's size
        quadrant = quadrant + remainder_kernel(layer, modulus, np.hypot(X, Y), f0) * (dx * dy)
    kernel = quadrant[ix[:, None], iy[None, :]]
    mult = np.fft.rfft2(kernel).real
    if spectral_rest:
        # A layer thinner than two pixels: its remainder varies within a pixel and is sampled in
        # Fourier space on the padded grid instead (periodic images at twice the patch size,
        # negligible since t < 2 pixels is far below the patch; measured 0.08 % of the layer's
        # part at t = L/16, 1.1 % at L/4 against a periodic cell 32x the patch).
        q, _ = _layered_multiplier(texture, modulus, layer, (2 * nx, 2 * ny), (dx, dy))
        qs = np.where(q > 0, q, 1.0)
        mult = mult + np.where(q > 0, _remainder(layer, modulus, qs, f0), _remainder_at_zero(layer, modulus, f0))
    return FFTOperator(backend, shape, mult, padded=True)


#: The remainder's radial table reaches r = _RHO_TABLE t; beyond, its r^-3 tail is used (measured
#: for a layer 10x stiffer than its substrate: the tail is 2.8x off at r = 40 t, 23 % at 100 t,
#: 1 % at 200 t, where the remainder itself is 3e-4 of the half-space kernel).
_RHO_TABLE = 200.0


def remainder_kernel(layer: Layer, modulus: float, r: np.ndarray, f0: float) -> np.ndarray:
    """Real-space kernel (m/Pa per m^2 of load) of the bounded remainder of the layered compliance.

    ``d(r) = 1/(pi E* t) int_0^inf f(x) J0(x r/t) dx``, ``f(x) = F(x/t) - 1 - (F0 - 1) e^-x``
    (bounded, f(0) = 0, decaying like e^-x): Gauss-Legendre panels on x in [0, 40] (24 nodes per
    0.1, converged to 1e-10 at r/t = 200), tabulated on r/t in [0, 200] (steps of 0.02 to 20,
    then of 0.5 %) and interpolated; beyond, the asymptotic tail ``-f2 / (pi E* t (r/t)^3)``
    (f2 the x^2 coefficient of f: ``int x^2 J0(rho x) dx = -1/rho^3``). The table is computed
    once per layer and modulus (~0.3 s) and shared by the levels of a nested solve.
    """
    rho_table, table, f2 = _remainder_table(layer, float(modulus), float(f0))
    rho = np.asarray(r, dtype=np.float64) / layer.thickness
    with np.errstate(divide="ignore"):
        tail = -f2 / np.where(rho > 0, rho, 1.0) ** 3
    return np.where(rho <= rho_table[-1], np.interp(rho, rho_table, table), tail) / (np.pi * modulus * layer.thickness)


@functools.lru_cache(maxsize=8)
def _remainder_table(layer: Layer, modulus: float, f0: float) -> tuple[np.ndarray, np.ndarray, float]:
    """The radial table of :func:`remainder_kernel` (without its 1/(pi E* t)) and f2."""
    from scipy.special import j0  # noqa: PLC0415

    t = layer.thickness

    def f(x: np.ndarray) -> np.ndarray:
        return spectral_factor(layer, x / t, modulus) - 1.0 - (f0 - 1.0) * np.exp(-x)

    nodes, weights = np.polynomial.legendre.leggauss(24)
    edges = np.linspace(0.0, 40.0, 401)  # panels of 0.1: ~3 oscillations of J0 at rho = 200
    half = np.diff(edges)[:, None] / 2
    xs = ((edges[:-1, None] + edges[1:, None]) / 2 + half * nodes[None, :]).ravel()
    ws = (half * weights[None, :]).ravel()
    fw = f(xs) * ws
    rho_table = np.concatenate([np.linspace(0.0, 20.0, 1001), np.geomspace(20.0, _RHO_TABLE, 462)[1:]])
    table = np.array([np.dot(fw, j0(xs * rh)) for rh in rho_table])
    h = 1e-3
    f2 = float((f(np.array([2 * h]))[0] - 2 * f(np.array([h]))[0]) / (2 * h * h))
    rho_table.flags.writeable = False
    table.flags.writeable = False
    return rho_table, table, f2


def _remainder(layer: Layer, modulus: float, q: np.ndarray, f0: float) -> np.ndarray:
    """The bounded part ``2/(E*|q|) [F(q) - 1 - (F0 - 1) exp(-|q| t)]`` of the layered compliance."""
    factor = spectral_factor(layer, q, modulus)
    return 2.0 / (modulus * q) * (factor - 1.0 - (f0 - 1.0) * np.exp(-q * layer.thickness))


def _remainder_at_zero(layer: Layer, modulus: float, f0: float) -> float:
    """Its limit at q -> 0, ``2/E* (F'(0) + (F0 - 1) t)``: Richardson from ``|q| t`` = 1e-4 and 2e-4
    (truncation ~1e-8, rounding ~1e-12 of the value)."""
    d = np.array([1e-4, 2e-4]) / layer.thickness
    r = _remainder(layer, modulus, d, f0)
    return float(2.0 * r[0] - r[1])


def _stiffness(modulus: float, q: np.ndarray, factor: np.ndarray | None) -> np.ndarray:
    return modulus * q / 2.0 if factor is None else modulus * q / (2.0 * factor)


def _compliance(modulus: float, q: np.ndarray, factor: np.ndarray | None) -> np.ndarray:
    return 2.0 / (modulus * q) if factor is None else 2.0 * factor / (modulus * q)


def preconditioner(backend: Backend, texture: Texture, modulus: float, form: str,
                   layer: Layer | None = None) -> FFTOperator:
    """Approximate inverse of the solver's operator, for the preconditioned conjugate gradient.

    ``form="primal"``: the periodic stiffness ``E* |q| / 2`` on the texture's own grid (also for
    finite bodies, whose compliance it inverts up to the longest wavelengths); ``"dual"``: the
    periodic compliance ``2 / (E* |q|)``. The q = 0 mode, which the operators leave undefined,
    takes the value of the lowest non-zero wavenumber so that the preconditioner is positive
    definite (under a mean constraint the solver removes that mode anyway). With a ``layer``
    both carry its factor: the exact inverse of the layered periodic compliance.
    """
    q, factor = _layered_multiplier(texture, modulus, layer, texture.shape, texture.spacing)
    q0 = float(np.min(q[q > 0]))
    if factor is not None:
        factor = np.where(q > 0, factor, float(spectral_factor(layer, np.array([q0]), modulus)[0]))
    q = np.where(q > 0, q, q0)
    mult = _stiffness(modulus, q, factor) if form == "primal" else _compliance(modulus, q, factor)
    return FFTOperator(backend, texture.shape, mult, padded=False)


def stiffness_operator(backend: Backend, texture: Texture, modulus: float, layer: Layer | None = None) -> FFTOperator:
    """Displacement -> pressure operator of a periodic cell (inverse of the compliance)."""
    q, factor = _layered_multiplier(texture, modulus, layer, texture.shape, texture.spacing)
    if factor is not None:
        factor = np.where(q > 0, factor, 1.0)  # q = 0: E* q / 2 = 0 whatever the factor
    return FFTOperator(backend, texture.shape, _stiffness(modulus, q, factor), padded=False)


# --------------------------------------------------------------------------------------------
# Results
