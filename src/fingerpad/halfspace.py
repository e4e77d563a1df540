"""Frictionless, non-adhesive normal contact of an elastic half-space (the skin) with a texture.

The skin is an ideal flat elastic half-space of reduced modulus E* (MODEL.md Eq. 3.4); the
texture is a rigid height map ``h`` (its own compliance is folded into E*). With the skin's
rest plane at ``h_max - d`` (``d`` the approach, measured from first touch), the gap is

    g = u + (h_max - h) - d >= 0,     p >= 0,     p g = 0,

where ``u`` is the surface displacement of the half-space under the pressure ``p``:

* periodic cells: ``u_q = 2 p_q / (E* |q|)`` for q != 0 (spectral Boussinesq kernel). The mean
  displacement of a periodic half-space is unbounded, so ``u`` is taken with zero mean and the
  approach is measured from that mean plane;
* finite bodies (``Texture.periodic = False``): the Boussinesq kernel integrated exactly over each
  pixel (Love's rectangle solution), applied as a linear convolution by zero padding to twice the
  size (no periodic images).

Algorithm
---------
Both contact problems are bound-constrained quadratic programmes solved by a constrained
conjugate gradient of the Polonsky-Keer (1999) family, written once for ``min 1/2 x.A x - b.x,
x >= 0`` with an optional fixed mean of ``x``:

* **primal** (``x = p``, ``A`` the compliance): the free variables are the contact pressures, so
  it is fastest while the contact fraction is small;
* **dual** (``x = g``, ``A`` the stiffness ``E*|q|/2``, gradient = pressure): the free variables
  are the gaps, so it is fastest and robust near full contact, exactly where the primal method
  stalls (its free set is almost the whole cell and the last gaps close slowly). At a fixed mean
  pressure the dual needs no equality constraint at all: the q = 0 mode of the pressure is the
  load.

``formulation="auto"`` picks the dual for periodic cells above 75 % contact (judged from the warm
start, or for a cold start from a solve of the cell block-averaged to ~128 points per axis), the
primal otherwise; a formulation that stalls hands over to the other. The dual starts from a
coarse-to-fine chain (the cell halved recursively, each solution repeated onto the next grid);
the primal starts from uniform pressure, which measured as fast as any coarse guess.

Each iteration transforms the search direction (its spectrum gives the exact line search by
Parseval) and inverse-transforms the iterate's spectrum, which follows by linearity; only when
the projection changed the active set is the iterate transformed afresh. A settled iteration
costs one FFT pair, an unsettled one one and a half. The element-wise work is fused into a few
parallel loops (:mod:`fingerpad._kernels`).

Convergence is measured by the relative KKT residual: the RMS over the cell of the projected
gradient (gap error where in contact and overlap elsewhere, for the primal; pressure error off
contact and tension in contact, for the dual) divided by the texture's peak-to-valley height
(primal) or by the mean pressure (dual).

The numerics are written against an array namespace (``array_api_compat``): a GPU array library
can run them; the default CPU path uses NumPy with SciPy's multi-threaded FFTs.
"""

from __future__ import annotations

import math
import os
import time
import warnings
from dataclasses import dataclass, field, replace
from typing import Any, Callable

import numpy as np

from ._kernels import ArrayKernels, kernels_for
from .errors import FingerpadError
from .materials import check_modulus
from .textures import Texture

__all__ = ["HalfSpaceSolver", "ContactResult", "contact_state", "FULL_CONTACT_TOL"]

#: A cell is in *full contact* when at most this fraction of its pixels is out of contact.
#: Zero: every pixel touches (discrete full contact).
FULL_CONTACT_TOL = 0.0
#: Pixels whose height is within this fraction of the peak-to-valley height of the lowest one form
#: the texture's base level; touching any of them starts the *transition* state.
BASE_LEVEL_RTOL = 1e-6

_COARSE_MIN = 64  # coarsest level of the dual's coarse-to-fine start
_PROBE_MIN = 128  # the cold-start probe of the contact fraction solves at about this size
#: In auto mode a formulation whose residual has not halved for this many iterations hands over
#: to the other one.
STALL_ITERATIONS = 150
#: Contact fraction above which auto mode solves the dual (gap) problem.
DUAL_ABOVE = 0.75
#: Grids from this many points on use the compiled kernels (their load time is ~2 s).
NUMBA_MIN_SIZE = 512 * 512  # do not coarsen below this many points along an axis


# --------------------------------------------------------------------------------------------
# Array backend
# --------------------------------------------------------------------------------------------


class _Backend:
    """Array namespace plus real FFTs; NumPy uses SciPy's threaded FFT."""

    def __init__(self, xp: Any = None, workers: int | None = None) -> None:
        if xp is None:
            import array_api_compat.numpy as xp_np  # noqa: PLC0415

            xp = xp_np
        self.xp = xp
        self.is_numpy = "numpy" in getattr(xp, "__name__", "")
        self.workers = workers or os.cpu_count() or 1
        if self.is_numpy:
            import scipy.fft as sfft  # noqa: PLC0415

            w = self.workers
            self.rfft2 = lambda a, s=None: sfft.rfft2(a, s=s, workers=w)
            self.irfft2 = lambda a, s: sfft.irfft2(a, s=s, workers=w)
        else:
            self.rfft2 = lambda a, s=None: xp.fft.rfftn(a, s=s, axes=(0, 1))
            self.irfft2 = lambda a, s: xp.fft.irfftn(a, s=s, axes=(0, 1))

    def asarray(self, a: Any) -> Any:
        return self.xp.asarray(a, dtype=self.xp.float64)

    def to_numpy(self, a: Any) -> np.ndarray:
        if self.is_numpy:
            return np.asarray(a)
        if hasattr(a, "get"):  # CuPy
            return a.get()
        return np.asarray(a)


# --------------------------------------------------------------------------------------------
# Elastic operators
# --------------------------------------------------------------------------------------------


def _wavenumbers(shape: tuple[int, int], spacing: tuple[float, float]) -> np.ndarray:
    """|q| (rad/m) on the half-spectrum grid of rfft2 for a periodic cell."""
    nx, ny = shape
    dx, dy = spacing
    qx = 2 * np.pi * np.fft.fftfreq(nx, d=dx)
    qy = 2 * np.pi * np.fft.rfftfreq(ny, d=dy)
    return np.sqrt(qx[:, None] ** 2 + qy[None, :] ** 2)


def _love_rectangle(x: np.ndarray, y: np.ndarray, a: float, b: float) -> np.ndarray:
    """Integral of 1/r over the rectangle |x'|<=a, |y'|<=b seen from (x, y) (Love 1929)."""

    def f(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
        # F(X, Y) = int_0^X int_0^Y ds dt / sqrt(s^2 + t^2), odd in X and in Y.
        ax, ay = np.abs(X), np.abs(Y)
        with np.errstate(divide="ignore", invalid="ignore"):
            t1 = np.where(ax > 0, ax * np.arcsinh(ay / np.where(ax > 0, ax, 1.0)), 0.0)
            t2 = np.where(ay > 0, ay * np.arcsinh(ax / np.where(ay > 0, ay, 1.0)), 0.0)
        return np.sign(X) * np.sign(Y) * (t1 + t2)

    return f(x + a, y + b) - f(x - a, y + b) - f(x + a, y - b) + f(x - a, y - b)


class _Operator:
    """A symmetric linear elastic operator applied by FFT (periodic or zero-padded).

    Besides ``A x`` it exposes the spectral pieces the solver combines to save transforms:
    ``forward`` (the real FFT of a field, zero-padded for finite bodies), ``apply_hat`` (``A x``
    from that spectrum) and ``quad`` (``t.A t`` from the spectrum of ``t`` by Parseval).
    """

    def __init__(self, backend: _Backend, shape: tuple[int, int], multiplier: np.ndarray, padded: bool):
        self.b = backend
        self.shape = shape
        self.padded = padded
        self.fshape = (2 * shape[0], 2 * shape[1]) if padded else shape
        xp = backend.xp
        self.multiplier = xp.asarray(multiplier)
        # Parseval on the half spectrum: interior columns stand for two conjugate modes.
        w = np.full(multiplier.shape, 2.0)
        w[:, 0] = 1.0
        if self.fshape[1] % 2 == 0:
            w[:, -1] = 1.0
        self.quad_weights = xp.asarray(w * np.real(multiplier) / (self.fshape[0] * self.fshape[1]))

    def forward(self, x: Any) -> Any:
        return self.b.rfft2(x, s=self.fshape) if self.padded else self.b.rfft2(x)

    def apply_hat(self, xh: Any) -> Any:
        out = self.b.irfft2(xh * self.multiplier, s=self.fshape)
        return out[: self.shape[0], : self.shape[1]] if self.padded else out

    def quad(self, th: Any) -> float:
        xp = self.b.xp
        return float(xp.sum(self.quad_weights * (xp.real(th) ** 2 + xp.imag(th) ** 2)))

    def __call__(self, x: Any) -> Any:
        return self.apply_hat(self.forward(x))


def _compliance(backend: _Backend, texture: Texture, modulus: float) -> _Operator:
    """Pressure -> displacement operator (Boussinesq), periodic or free-space."""
    shape = texture.shape
    if texture.periodic:
        q = _wavenumbers(shape, texture.spacing)
        with np.errstate(divide="ignore"):
            mult = np.where(q > 0, 2.0 / (modulus * np.where(q > 0, q, 1.0)), 0.0)
        return _Operator(backend, shape, mult, padded=False)
    nx, ny = shape
    dx, dy = texture.spacing
    # Offsets on the doubled grid in FFT order; the wrapped half never meets physical pixels.
    ix = np.fft.fftfreq(2 * nx, d=1.0 / (2 * nx))
    iy = np.fft.fftfreq(2 * ny, d=1.0 / (2 * ny))
    X, Y = np.meshgrid(ix * dx, iy * dy, indexing="ij")
    kernel = _love_rectangle(X, Y, dx / 2, dy / 2) / (np.pi * modulus)
    mult = np.fft.rfft2(kernel)
    return _Operator(backend, shape, mult, padded=True)


def _stiffness(backend: _Backend, texture: Texture, modulus: float) -> _Operator:
    """Displacement -> pressure operator of a periodic cell (inverse of the compliance)."""
    q = _wavenumbers(texture.shape, texture.spacing)
    return _Operator(backend, texture.shape, modulus * q / 2.0, padded=False)


# --------------------------------------------------------------------------------------------
# Results
# --------------------------------------------------------------------------------------------


def contact_state(contact: np.ndarray, base: np.ndarray) -> str:
    """Contact state of a cell from its contact mask and the texture's base-level mask.

    ``"asperity"``: the skin does not touch the lowest level of the texture;
    ``"full"``: every pixel is in contact (see :data:`FULL_CONTACT_TOL`);
    ``"transition"``: in between.
    """
    out_of_contact = 1.0 - float(np.count_nonzero(contact)) / contact.size
    if out_of_contact <= FULL_CONTACT_TOL:
        return "full"
    if np.any(contact & base):
        return "transition"
    return "asperity"


@dataclass
class ContactResult:
    """Solution of one contact problem on one cell (SI units).

    Fields are (nx, ny) arrays: ``pressure`` (Pa), ``gap`` (m, skin to texture), ``displacement``
    (m, skin surface displacement away from the texture, zero mean for periodic cells).
    """

    pressure: np.ndarray
    gap: np.ndarray
    displacement: np.ndarray
    mean_pressure: float
    approach: float
    contact_fraction: float
    real_contact_area: float
    max_pressure: float
    mean_gap: float
    iterations: int
    residual: float
    converged: bool
    seconds: float
    formulation: str
    contact_state: str
    texture: Texture = field(repr=False)
    modulus: float = 0.0
    tol: float = 0.0

    @property
    def contact(self) -> np.ndarray:
        """Boolean contact mask."""
        return self.pressure > 0

    def summary(self) -> dict[str, Any]:
        """JSON-ready scalar results (SI units)."""
        return {
            "mean_pressure": float(self.mean_pressure),
            "contact_fraction": float(self.contact_fraction),
            "real_contact_area": float(self.real_contact_area),
            "max_pressure": float(self.max_pressure),
            "mean_gap": float(self.mean_gap),
            "approach": float(self.approach),
            "contact_state": self.contact_state,
            "iterations": int(self.iterations),
            "residual": float(self.residual),
            "converged": bool(self.converged),
            "seconds": float(self.seconds),
            "formulation": self.formulation,
        }


@dataclass
class _Raw:
    x: Any
    iterations: int
    residual: float
    converged: bool
    multiplier: float  # Lagrange multiplier of the mean constraint (0 without one)


# --------------------------------------------------------------------------------------------
# Constrained conjugate gradient
# --------------------------------------------------------------------------------------------


def _ccg(
    kern: ArrayKernels,
    op: _Operator,
    b: Any,
    x0: Any,
    *,
    mean: float | None,
    scale: float,
    tol: float,
    max_iter: int,
    stall: int | None = None,
) -> _Raw:
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
    element-wise work is fused into a few passes (:mod:`fingerpad._kernels`).

    With ``stall``, give up (not converged) once the residual has not halved for that many
    iterations: degenerate active sets (a flat base just touching) can make one formulation
    cycle while the other converges at once.
    """
    xp = kern.xp
    n = x0.size
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
        if residual < tol:
            if fresh:
                return _Raw(x, it, residual, True, lam)
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
            return _Raw(x, it, residual, False, lam)
        if nfree == 0:
            # Every point at its bound: release those with a descent gradient by a projected
            # steepest-descent step of exact length.
            r = ax - b - lam
            t = xp.minimum(r, 0.0)
            tat = op.quad(op.forward(t))
            if tat <= 0:
                return _Raw(x, it, residual, False, lam)
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
            return _Raw(x, it, residual, False, lam)
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
    return _Raw(x, max_iter, residual, False, lam)


# --------------------------------------------------------------------------------------------
# Solver
# --------------------------------------------------------------------------------------------


class HalfSpaceSolver:
    """Normal contact of the skin (elastic half-space) on one texture cell.

    Parameters
    ----------
    texture
        The counter-surface height map (periodic unit cell or finite patch).
    modulus
        Reduced modulus E* (Pa), MODEL.md Eq. 3.4.
    tol
        Relative KKT residual at which a solve stops (see module docstring).
    max_iter
        Iteration cap per solve; a solve that hits it returns ``converged=False`` and warns.
    formulation
        ``"auto"``, ``"primal"`` (pressure unknowns) or ``"dual"`` (gap unknowns, periodic only).
    coarse_to_fine
        Start cold solves from a coarse-grid solution.
    xp
        Array namespace (default: NumPy). A GPU namespace runs the same code.
    workers
        FFT threads (default: all cores).
    kernels
        ``"auto"``: fused Numba loops for NumPy grids of at least :data:`NUMBA_MIN_SIZE` points
        when Numba is installed; ``"numba"``: always those; ``"array"``: plain array-namespace
        operations.
    """

    def __init__(
        self,
        texture: Texture,
        modulus: float,
        *,
        tol: float = 1e-8,
        max_iter: int = 5000,
        formulation: str = "auto",
        coarse_to_fine: bool = True,
        xp: Any = None,
        workers: int | None = None,
        kernels: str = "auto",
    ) -> None:
        if not isinstance(texture, Texture):
            raise FingerpadError("texture must be a fingerpad.Texture")
        self.texture = texture
        self.modulus = check_modulus(modulus, "reduced modulus")
        if not (isinstance(tol, (int, float)) and 0 < tol < 1):
            raise FingerpadError(f"tolerance must lie in (0, 1), got {tol!r}")
        if not (isinstance(max_iter, int) and max_iter >= 1):
            raise FingerpadError(f"max_iter must be a positive integer, got {max_iter!r}")
        if formulation not in ("auto", "primal", "dual"):
            raise FingerpadError(f"formulation must be auto, primal or dual, got {formulation!r}")
        if formulation == "dual" and not texture.periodic:
            raise FingerpadError("the dual (gap) formulation needs a periodic cell")
        nx, ny = texture.shape
        if nx < 4 or (ny < 4 and ny != 1):
            raise FingerpadError(f"grid {nx}x{ny} is too small: use at least 4 points per axis")
        self.tol = float(tol)
        self.max_iter = max_iter
        self.formulation = formulation
        self.coarse_to_fine = coarse_to_fine
        self.backend = _Backend(xp, workers)
        xp_ = self.backend.xp
        h = texture.heights
        self.h_max = float(h.max())
        self.h_mean = float(h.mean())
        self.pv = max(texture.peak_to_valley, 1e-300)
        self.h = self.backend.asarray(h)
        self.base = h <= h.min() + BASE_LEVEL_RTOL * texture.peak_to_valley
        self._K = _compliance(self.backend, texture, self.modulus)
        self._S = _stiffness(self.backend, texture, self.modulus) if texture.periodic else None
        self._Sh = self._S(self.h) if self._S is not None else None
        self._xp = xp_
        if kernels not in ("auto", "array", "numba"):
            raise FingerpadError(f"kernels must be auto, array or numba, got {kernels!r}")
        self._kernels_choice = kernels
        # Compiled kernels pay a one-off load (seconds) that small grids never earn back.
        use_numba = self.backend.is_numpy and (kernels == "numba" or (kernels == "auto" and h.size >= NUMBA_MIN_SIZE))
        self._kern = kernels_for(xp_, use_numba)
        self._coarse: dict[str, HalfSpaceSolver | None] = {}
        self._coarse_tol = min(max(self.tol, 1e-6) * 10, 1e-3)
        self._factors = (1, 1)

    # ---------------------------------------------------------------- public API

    def solve_pressure(self, mean_pressure: float, initial: ContactResult | None = None) -> ContactResult:
        """Solve at a given mean nominal pressure (Pa) over the cell."""
        p = float(mean_pressure)
        if not (math.isfinite(p) and p > 0):
            raise FingerpadError(f"mean pressure must be positive, got {mean_pressure!r}")
        return self._solve("pressure", p, initial)

    def solve_approach(self, approach: float, initial: ContactResult | None = None) -> ContactResult:
        """Solve at a given approach (rigid-body displacement, m, from first touch)."""
        d = float(approach)
        if not math.isfinite(d):
            raise FingerpadError(f"approach must be finite, got {approach!r}")
        if self.texture.periodic and d >= self.h_max - self.h_mean:
            raise FingerpadError(
                "approach reaches full contact of a periodic cell (pressure undetermined there): "
                f"keep it below {self.h_max - self.h_mean:.4g} m or solve at a given pressure"
            )
        return self._solve("approach", d, initial)

    # ---------------------------------------------------------------- internals

    def _choose(self, mode: str, value: float, initial: ContactResult | None) -> str:
        if self.formulation != "auto":
            return self.formulation
        if not self.texture.periodic:
            return "primal"
        if initial is None:
            probe = self._coarse_solver("probe")
            if probe is None:
                return "primal"  # small cell: the stall hand-over covers near-full contact
            initial = probe._solve(mode, value, None)
        return "dual" if initial.contact_fraction > DUAL_ABOVE else "primal"

    @staticmethod
    def _coarsening(n: int, limit: int, minimum: int) -> int:
        """Largest power-of-two factor f <= limit with n % f == 0 and n / f >= minimum."""
        f = 1
        while 2 * f <= limit and n % (2 * f) == 0 and n // (2 * f) >= minimum:
            f *= 2
        return f

    def _coarse_solver(self, kind: str) -> HalfSpaceSolver | None:
        """The cell block-averaged by 2 (``"half"``, a coarse-to-fine level) or to about
        _COARSE_MIN points per axis (``"probe"``, to judge the contact fraction); None if the
        cell is too small."""
        if not self.coarse_to_fine:
            return None
        if kind not in self._coarse:
            nx, ny = self.texture.shape
            limit, minimum = (2, _COARSE_MIN) if kind == "half" else (nx, _PROBE_MIN)
            fx, fy = self._coarsening(nx, limit, minimum), self._coarsening(ny, limit, minimum)
            if fx < 2:
                self._coarse[kind] = None
                return None
            h = self.texture.heights
            # Block averages keep the mean height; the features survive well enough to place
            # the contact spots and to judge the contact fraction.
            hc = h.reshape(nx // fx, fx, ny // fy, fy).mean(axis=(1, 3))
            # Coarse levels only place the contact set: one loose tolerance for the whole chain
            # (not compounded level by level).
            solver = HalfSpaceSolver(
                replace(self.texture, heights=hc), self.modulus, tol=self._coarse_tol,
                max_iter=self.max_iter, formulation=self.formulation, coarse_to_fine=kind == "half",
                xp=self.backend.xp, workers=self.backend.workers, kernels=self._kernels_choice,
            )
            solver._factors = (fx, fy)
            solver._coarse_tol = self._coarse_tol
            self._coarse[kind] = solver
        return self._coarse[kind]

    def _solve(
        self, mode: str, value: float, initial: ContactResult | None, form: str | None = None
    ) -> ContactResult:
        start = time.perf_counter()
        if initial is not None and initial.pressure.shape != self.texture.shape:
            raise FingerpadError("initial solution has a different grid")
        if form is None:
            form = self._choose(mode, value, initial)
        seed: Any = initial
        if seed is None and form == "dual":
            # The dual converges much faster from a coarse-to-fine start (recursive halving);
            # the primal's uniform-pressure cold start finds the contact set as fast as any guess.
            half = self._coarse_solver("half")
            if half is not None:
                coarse = half._solve(mode, value, None, form="dual")
                fx, fy = half._factors
                rep = lambda a: np.repeat(np.repeat(a, fx, axis=0), fy, axis=1)  # noqa: E731
                seed = _Seed(rep(coarse.pressure), rep(coarse.gap))
        auto = self.formulation == "auto" and self.texture.periodic
        raw = self._run(form, mode, value, seed, stall=STALL_ITERATIONS if auto else None)
        if not raw.converged and auto:
            # The other formulation is the fallback (e.g. near full contact for the primal).
            other = "dual" if form == "primal" else "primal"
            raw2 = self._run(other, mode, value, seed)
            raw2.iterations += raw.iterations
            if raw2.converged or raw2.residual < raw.residual:
                raw, form = raw2, other
        result = self._finish(form, mode, value, raw, time.perf_counter() - start)
        if not result.converged:
            warnings.warn(
                f"contact solve did not converge: residual {result.residual:.3g} > tol {self.tol:.3g} "
                f"after {result.iterations} iterations ({mode} = {value:.6g})",
                RuntimeWarning,
                stacklevel=3,
            )
        return result

    def _run(self, form: str, mode: str, value: float, seed: Any, stall: int | None = None) -> _Raw:
        xp = self._xp
        be = self.backend
        n = self.h.size
        if form == "primal":
            if mode == "pressure":
                b = self.h
                x0 = be.asarray(seed.pressure) if seed is not None else xp.full(self.h.shape, value)
                x0 = xp.maximum(x0, 0.0)
                m = float(xp.mean(x0))
                x0 = x0 * (value / m) if m > 0 else xp.full(self.h.shape, value)
                return _ccg(self._kern, self._K, b, x0, mean=value, scale=self.pv, tol=self.tol, max_iter=self.max_iter, stall=stall)
            b = self.h - (self.h_max - value)
            if seed is not None:
                x0 = xp.maximum(be.asarray(seed.pressure), 0.0)
            else:
                x0 = xp.where(b > 0, b, 0.0) * (self.modulus / max(self.texture.size) * 4)
            return _ccg(self._kern, self._K, b, x0, mean=None, scale=self.pv, tol=self.tol, max_iter=self.max_iter, stall=stall)
        # dual: unknown gap, gradient = pressure
        if mode == "pressure":
            b = -(self._Sh + value)
            x0 = xp.maximum(be.asarray(seed.gap), 0.0) if seed is not None else self._gap_guess()
            return _ccg(self._kern, self._S, b, x0, mean=None, scale=value, tol=self.tol, max_iter=self.max_iter, stall=stall)
        target = self.h_max - value - self.h_mean  # mean gap for a zero-mean displacement
        b = -self._Sh
        x0 = xp.maximum(be.asarray(seed.gap), 0.0) if seed is not None else xp.maximum(self.h_max - self.h, 0.0)
        mx = float(xp.mean(x0))
        x0 = x0 * (target / mx) if mx > 0 else xp.full(self.h.shape, target)
        scale = self.modulus * self.pv / max(self.texture.size)
        return _ccg(self._kern, self._S, b, x0, mean=target, scale=scale, tol=self.tol, max_iter=self.max_iter, stall=stall)

    def _gap_guess(self) -> Any:
        # Skin plane at the texture's mid-height, gaps where it does not reach: only a starting
        # point for the dual on cells too small for a coarse-to-fine start.
        xp = self._xp
        return xp.maximum(self.h_max - self.h - 0.5 * self.pv, 0.0)

    def _finish(self, form: str, mode: str, value: float, raw: _Raw, seconds: float) -> ContactResult:
        xp = self._xp
        be = self.backend
        tex = self.texture
        if form == "primal":
            p = raw.x
            u = self._K(p)
            if mode == "pressure":
                # g = u - h + c with c fixed by the multiplier (zero gap on the contact set).
                gap = u - self.h - raw.multiplier
            else:
                gap = u - self.h + self.h_max - value
        else:
            gap = raw.x
            if mode == "pressure":
                p = self._S(gap) + self._Sh + value
            else:
                p = self._S(gap) + self._Sh - raw.multiplier
            # Tension of the order of the residual can remain on contact points; it is part of
            # the reported residual, and the field itself is kept non-negative.
            p = xp.where(gap > 0, 0.0, xp.maximum(p, 0.0))
            u = None
        p_np = be.to_numpy(p)
        g_np = be.to_numpy(gap)
        if tex.periodic:
            mean_gap = float(g_np.mean())
            approach = self.h_max - self.h_mean - mean_gap
            disp = g_np + tex.heights - (self.h_max - approach)
        else:
            # gap = u - h - lambda = u + h_max - h - d  =>  d = h_max + lambda
            approach = value if mode == "approach" else self.h_max + raw.multiplier
            disp = be.to_numpy(u) if u is not None else g_np + tex.heights - (self.h_max - approach)
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
            contact_state=contact_state(contact, self.base),
            texture=tex,
            modulus=self.modulus,
            tol=self.tol,
        )


@dataclass
class _Seed:
    pressure: np.ndarray
    gap: np.ndarray
