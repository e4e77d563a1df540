"""Frictionless, non-adhesive normal contact of an elastic half-space (the skin) with a texture.

The skin is an ideal flat elastic half-space of reduced modulus E* (docs/model.md Eq. 3.4); the
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
  are the gaps, so the plain iteration is fastest and robust near full contact, exactly where the
  plain primal stalls (its free set is almost the whole cell and the last gaps close slowly). At a fixed mean
  pressure the dual needs no equality constraint at all: the q = 0 mode of the pressure is the
  load.

Both are solved by a *preconditioned* projected conjugate gradient (:mod:`.ccg`): the inverse
operator (the stiffness ``E*|q|/2`` for the primal, the compliance for the dual) applied to the
gradient on the working set. Plain Polonsky-Keer iterations grow like sqrt(n) on an n x n grid
(55, 72, 92, 113-134 at 256^2 ... 2048^2 on a cap cell at 35 % contact); preconditioned they
barely grow (17, 20, 24 at 256^2, 512^2, 1024^2 from a cold start) across contact fractions
1-100 %, so
``formulation="auto"`` takes the primal everywhere and keeps the dual as the fallback of a
stalled solve. ``precondition=False`` restores the plain iteration (and, for periodic cells,
the former choice: the dual above 75 % contact judged from a ~128-point probe).

Cold solves start by nested iteration: the cell block-averaged by 2 recursively down to ~64
points per axis, each level solved to a loose tolerance and its solution repeated onto the next
grid. With the preconditioner the fine grid then needs ~10 iterations (1024^2 and 2048^2).

Each preconditioned iteration transforms the iterate afresh in double precision (one rfft2 +
irfft2 pair; no rounding drift, no re-check at the end) and runs the preconditioner and the
line search's curvature ``t.A t`` in single precision (half a double pair or less with
SciPy's FFT). The element-wise work runs in place on NumPy (:mod:`fingerpad.contact.kernels`)
at first, and in fused loops compiled with Numba once a solver has done enough work for their
load to pay back (a long load curve), or from the first solve on very large grids
(:mod:`fingerpad.contact.kernels_numba`: ~0.5 s to load once per process, ~20 % per solve).

Convergence is measured by the relative KKT residual: the RMS over the cell of the projected
gradient (gap error where in contact and overlap elsewhere, for the primal; pressure error off
contact and tension in contact, for the dual) divided by the texture's peak-to-valley height
(primal) or by the mean pressure (dual).

The numerics are written against the Array API standard: pass any compliant namespace as ``xp``
(CuPy, PyTorch through ``array_api_compat.array_namespace``, ...) and the same code runs on its
arrays; the tests run it on ``array_api_strict``. The default CPU path is NumPy 2 itself (no
wrapper) with SciPy's FFTs.
"""

from __future__ import annotations

import math
import os
import time
import warnings
import weakref
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..cancel import current as cancel_scope
from ..errors import FingerpadError, one_line
from ..extras import missing, require
from ..materials import check_modulus
from ..textures import Texture
from .formulations import finish, run_formulation
from .greens import Backend, compliance_operator, preconditioner, stiffness_operator
from .interaction import Interaction
from .layered import Layer
from .kernels import ArrayKernels, NumpyKernels
from .kernels_blocked import BlockedNumpyKernels, blocked_applies
from .result import FULL_CONTACT_TOL, ContactResult, contact_state

__all__ = ["HalfSpaceSolver", "ContactResult", "contact_state", "FULL_CONTACT_TOL", "solver_references"]  # re-exported

_COARSE_MIN = 64  # coarsest level of the dual's coarse-to-fine start
_PROBE_MIN = 128  # the cold-start probe of the contact fraction solves at about this size
#: In auto mode a formulation whose residual has not halved for this many iterations hands over
#: to the other one.
STALL_ITERATIONS = 150
#: Contact fraction above which auto mode solves the dual (gap) problem.
DUAL_ABOVE = 0.75


# Solver
# --------------------------------------------------------------------------------------------


_COMPILED_UNAVAILABLE = False  # set once the compiled kernels failed to load in this process
#: ``kernels="auto"`` runs on the compiled loops from the first solve on grids of this many
#: points and more, on NumPy below, whatever the solver has done before. The loops sum in
#: another order than NumPy's (the last bits of a solve differ, ~1e-11 relative), so the choice
#: is the grid's alone: a switch after so much work (before 2026-11-29) made a cell's node depend
#: on how many nodes the run solved before it, i.e. on what the cache held (at 512^2 after about
#: 25 solves of a cell). Their ~0.5 s load per process pays back on the solves of a cell or a
#: curve at 1024^2 (a 50-point curve: 11.5-12.7 s against 13.3-15.0 s on NumPy alone) and costs
#: ~0.2-0.3 s net on one lone solve there.
COMPILED_FIRST_POINTS = 2**20


def _kernels_for(xp: Any, choice: str, shape: tuple[int, ...] = (), threads: int = 1) -> ArrayKernels:
    """``"numpy"``: in-place NumPy kernels (on two row blocks, in ``threads`` > 1 threads, for
    fields of at least 512 rows); ``"numba"``: compiled loops (NumPy arrays; the NumPy kernels,
    with one warning per process, where they cannot load); ``"array"``: the array-namespace
    reference."""
    global _COMPILED_UNAVAILABLE
    if choice == "array":
        return ArrayKernels(xp)
    if choice == "numba" and not _COMPILED_UNAVAILABLE:
        try:
            from .kernels_numba import NumbaKernels  # noqa: PLC0415 - ~0.5 s to load

            return NumbaKernels()
        except Exception as exc:  # noqa: BLE001 - no Numba, no writable cache for its loops, ...
            # same results, ~20 % slower: say so once, do not fail the solve
            _COMPILED_UNAVAILABLE = True
            warnings.warn(f"compiled kernels unavailable, NumPy kernels used instead: {one_line(str(exc))}",
                          RuntimeWarning, stacklevel=2)
    if blocked_applies(shape):
        return BlockedNumpyKernels(threads)
    return NumpyKernels()


def preload_compiled_kernels() -> None:
    """Load the compiled loops now, where Numba is installed and may run: a process about to
    fork workers that solve unit cells (kernels="compiled") loads them once for all, instead of
    each worker for its first cell (~0.5-1 s of CPU each). A failure is the solvers' to report
    (the warning once, NumPy's loops), as it would be at their first solve."""
    if _COMPILED_UNAVAILABLE or _jit_disabled():
        return
    _kernels_for(np, "numba")


def _jit_disabled() -> bool:
    # NUMBA_DISABLE_JIT (coverage runs, debugging) makes the "compiled" loops plain Python,
    # ~40x slower than NumPy: "auto" then stays on NumPy. Without Numba (it comes with the
    # optional `fast` extra) "auto" stays on NumPy too, silently: same answers, ~20 % slower on
    # long curves.
    return os.environ.get("NUMBA_DISABLE_JIT", "").strip() not in ("", "0") or bool(missing("fast", ("numba",)))


def solver_references(periodic: bool = True, layered: bool = False) -> tuple[str, ...]:
    """The publications of the method a :class:`HalfSpaceSolver` runs (:mod:`fingerpad.references`
    keys): the constrained conjugate gradient (Polonsky-Keer), Love's pixel kernel on a
    non-periodic map, the layered skin's compliance (docs/model.md, 6.4)."""
    return ("polonsky1999",) + (() if periodic else ("love1929",)) + (("fingerpad-layered",) if layered else ())


#: Most iterations a solve may be given (``max_iter``): 20 times the default; solves converge in
#: 6-14 iterations from 1 % to 99 % contact (docs/solver.md), and a cap far above that only
#: hides a typo that would let an unconvergeable solve run for days.
MAX_ITER = 100_000


class HalfSpaceSolver:
    """Normal contact of the skin (elastic half-space) on one texture cell.

    Parameters
    ----------
    texture
        The counter-surface height map (periodic unit cell or finite patch).
    modulus
        Reduced modulus E* (Pa), docs/model.md Eq. 3.4. With a ``layer``: the pair's at short
        wavelengths, i.e. the layer's E1* combined with the counter-surface's (E1* itself for a
        rigid texture); it may not exceed E1*.
    layer
        A layered skin (:class:`fingerpad.contact.layered.Layer`: an elastic layer on an elastic
        half-space or a rigid base) instead of the homogeneous half-space (``None``, the
        default, bit-identical to the solver without this option). Its exact Fourier-space
        compliance multiplies the half-space kernel (docs/model.md, section 6.4); the
        preconditioner inverts it exactly.
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
    fft
        FFT engine for NumPy arrays: ``"auto"`` (ducc0 when installed, else SciPy), ``"ducc0"``
        or ``"scipy"``. Default: the environment variable ``FINGERPAD_FFT``, else ``"auto"``
        (:func:`fingerpad.contact.greens.fft_settings`).
    kernels
        Element-wise work: ``"numpy"`` (in place, NumPy), ``"numba"`` (fused loops compiled
        with Numba: ~20 % faster solves, but ~0.5 s to load once per process) or ``"array"``
        (the array-namespace reference). ``"auto"``: for NumPy arrays, ``"numba"`` on grids of
        :data:`COMPILED_FIRST_POINTS` points and more (where their load pays back), ``"numpy"``
        below, decided by the grid alone (the two differ in the last bits: a node's value must
        not depend on what the solver solved before it); ``"compiled"``: the compiled loops
        from the first solve wherever Numba is installed, NumPy otherwise (silently), for a
        caller of many solves whatever the grid (a unit cell's curve: 1.3-2x faster at grids
        16-128, where NumPy's per-call cost dominates); ``"array"`` for other namespaces.
    precondition
        Preconditioned conjugate gradient (the inverse operator as preconditioner, see
        :func:`fingerpad.contact.ccg.constrained_cg`); ``False`` gives the plain Polonsky-Keer
        iteration (a diagnostic: slower on every cell measured).
    progress
        ``progress(shape, iteration, residual)``, called once per iteration of every level of a
        solve (the coarse levels of the nested start report their own, smaller ``shape``): the
        progress of long solves (2048^2 and up take seconds). Must be cheap.
    interaction
        An attractive interaction (:class:`fingerpad.contact.interaction.Interaction`, SI: its
        work of adhesion and range) added to the energy: adhesive contact, solved with the gap
        as the unknown (:mod:`fingerpad.contact.adhesive`); mean pressures may then be zero or
        negative. ``None`` (the default): non-adhesive contact, bit-identical to the solver
        without this option.
    """

    def __init__(
        self,
        texture: Texture,
        modulus: float,
        *,
        layer: Layer | None = None,
        tol: float = 1e-8,
        max_iter: int = 5000,
        formulation: str = "auto",
        coarse_to_fine: bool = True,
        xp: Any = None,
        workers: int | None = None,
        fft: str | None = None,
        kernels: str = "auto",
        precondition: bool = True,
        progress: Callable[[tuple[int, int], int, float], None] | None = None,
        interaction: Interaction | None = None,
    ) -> None:
        if not isinstance(texture, Texture):
            raise FingerpadError("texture must be a fingerpad.Texture")
        self.texture = texture
        self.modulus = check_modulus(modulus, "reduced modulus")
        if layer is not None and not isinstance(layer, Layer):
            raise FingerpadError("layer must be a fingerpad.contact.layered.Layer or None")
        self.layer = layer
        if interaction is not None and not isinstance(interaction, Interaction):
            raise FingerpadError("interaction must be a fingerpad.contact.interaction.Interaction or None")
        self.interaction = interaction
        self._adhesive: Any = None  # the adhesive solve's operators, built on first use
        self._plain: HalfSpaceSolver | None = None  # the same cell without it (cold adhesive starts)
        if not (isinstance(tol, (int, float)) and 0 < tol < 1):
            raise FingerpadError(f"tolerance must lie in (0, 1), got {tol!r}")
        if not (isinstance(max_iter, int) and 1 <= max_iter <= MAX_ITER):
            raise FingerpadError(f"max_iter must be an integer in 1..{MAX_ITER}, got {max_iter!r}")
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
        self.backend = Backend(xp, workers, fft)
        xp_ = self.backend.xp
        h = texture.heights
        self.h_max = float(h.max())
        self.h_mean = float(h.mean())
        self.pv = max(texture.peak_to_valley, 1e-300)
        self.h = self.backend.asarray(h)
        self.base = texture.base_mask()
        self._K = compliance_operator(self.backend, texture, self.modulus, self.layer)
        self._S_op: Any = None  # the dual's stiffness and S h, built on first use (memory)
        self._Sh_field: Any = None
        self._xp = xp_
        if kernels not in ("auto", "compiled", "array", "numpy", "numba"):
            raise FingerpadError(f"kernels must be auto, compiled, array, numpy or numba, got {kernels!r}")
        self._kernels_choice = kernels
        if kernels in ("numpy", "numba") and not self.backend.is_numpy:
            raise FingerpadError(f"kernels={kernels!r} needs NumPy arrays")
        if kernels == "numba":
            require("fast", "kernels='numba'", ("numba",))
        # NumPy arrays: in-place NumPy kernels until the first solve decides (_turns_compiled:
        # by the grid or the caller, never the history); other namespaces: the array-API reference.
        choice = ("numpy" if self.backend.is_numpy else "array") if kernels in ("auto", "compiled") else kernels
        self._kern = _kernels_for(xp_, choice, texture.shape, self.backend.workers)
        self._compiled = False
        self._kernels_decided = False
        self.precondition = bool(precondition)
        self._pre: dict[str, Any] = {}
        self._coarse: dict[str, HalfSpaceSolver | None] = {}
        self._warm: tuple[Any, Any] | None = None  # (weakref to the last pressure field, its coarse pressure)
        self._coarse_tol = min(max(self.tol, 1e-6) * 10, 1e-3)
        self._factors = (1, 1)
        if progress is not None and not callable(progress):
            raise FingerpadError("progress must be a callable (shape, iteration, residual) or None")
        self.progress = progress

    # ---------------------------------------------------------------- public API

    def solve_pressure(self, mean_pressure: float, initial: ContactResult | None = None) -> ContactResult:
        """Solve at a given mean nominal pressure (Pa) over the cell (with an ``interaction``
        also zero or negative: a tension the adhesion holds, or a lift-off the result reports
        as ``contact_state == "detached"``)."""
        p = float(mean_pressure)
        if self.interaction is not None:
            if not math.isfinite(p):
                raise FingerpadError(f"mean pressure must be finite, got {mean_pressure!r}")
            return self._solve("pressure", p, initial)
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
        if self.precondition:
            # Preconditioned, the primal converges in a few tens of iterations from 1 % to full
            # contact (measured), so no probe is needed; the dual remains the stall fallback.
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
                replace(self.texture, heights=hc), self.modulus, layer=self.layer, tol=self._coarse_tol,
                max_iter=self.max_iter, formulation=self.formulation, coarse_to_fine=kind == "half",
                xp=self.backend.xp, workers=self.backend.workers, fft=self.backend.fft, kernels=self._kernels_choice,
                precondition=self.precondition, progress=self.progress,
            )
            solver._factors = (fx, fy)
            solver._coarse_tol = self._coarse_tol
            if self._compiled:
                solver._use_compiled()
            self._coarse[kind] = solver
        return self._coarse[kind]

    def _use_compiled(self) -> None:
        """Run this solver and its coarse levels on the compiled loops from now on."""
        self._compiled = True
        self._kern = _kernels_for(self._xp, "numba")
        for level in self._coarse.values():
            if level is not None and not level._compiled:
                level._use_compiled()

    def _solve(
        self, mode: str, value: float, initial: ContactResult | None, form: str | None = None
    ) -> ContactResult:
        start = time.perf_counter()
        if initial is not None and initial.pressure.shape != self.texture.shape:
            raise FingerpadError("initial solution has a different grid")
        if self.interaction is not None:
            # the interaction is a term of the energy the gap form minimises: its own iteration
            return self._solve_adhesive(mode, value, initial)
        if not self._kernels_decided:
            # once, at the first solve: a large grid, or a caller of many solves, turns to the
            # compiled loops, whose load then pays back (the grid's or the caller's rule, never
            # the history's: the loops' last bits differ from NumPy's)
            self._kernels_decided = True
            if not self._compiled and self._turns_compiled():
                self._use_compiled()
        if form is None:
            form = self._choose(mode, value, initial)
        seed: Any = initial
        nested = form == "dual" or self.precondition
        half = self._coarse_solver("half") if nested else None
        coarse_p = None  # this solve's coarse-level pressure, kept for the next warm start
        if half is not None:
            fx, fy = half._factors
            rep = lambda a: np.repeat(np.repeat(a, fx, axis=0), fy, axis=1)  # noqa: E731
        if half is not None and seed is None:
            # Nested iteration: start from the solution on the cell halved (recursively). The
            # plain primal gains nothing from it (the interpolation error is short-wavelength,
            # which it resolves last); the dual and the preconditioned primal do.
            coarse = half._solve(mode, value, None, form=form)
            # only the field the formulation starts from (memory at 4096^2)
            seed = _Seed(rep(coarse.pressure) if form == "primal" else None,
                         rep(coarse.gap) if form == "dual" else None)
            coarse_p = coarse.pressure if form == "primal" else None
            del coarse
        elif half is not None and form == "primal" and self._warm is not None and self._warm[0]() is initial.pressure:
            # Two-grid warm start from this solver's previous solution: that fine solution plus
            # the change of the coarse solution between the two loads (itself warm-started the
            # same way, level by level). The fine details carry over and the coarse level
            # supplies the long-wavelength change: ~35 % fewer fine iterations along a load
            # curve than the previous solution alone (measured, 50 loads, 512^2 cap cell).
            old = self._warm[1]
            coarse = half._solve(mode, value, _Seed(old, None), form="primal")
            seed = _Seed(np.maximum(initial.pressure + rep(coarse.pressure - old), 0.0), None)
            coarse_p = coarse.pressure
            del coarse
        auto = self.formulation == "auto" and self.texture.periodic
        # hand the seed over (memory: a nested start's seed is a full-size field of its own)
        holder = [seed]
        del seed
        raw = run_formulation(self, form, mode, value, holder.pop(), stall=STALL_ITERATIONS if auto else None)
        self._kern.release()
        if not raw.converged and auto:
            # The other formulation is the fallback (e.g. near full contact for the primal).
            other = "dual" if form == "primal" else "primal"
            raw2 = run_formulation(self, other, mode, value, initial)
            raw2.iterations += raw.iterations
            if raw2.converged or raw2.residual < raw.residual:
                raw, form = raw2, other
        result = finish(self, form, mode, value, raw, time.perf_counter() - start)
        self._warm = (weakref.ref(result.pressure), coarse_p) if coarse_p is not None and form == "primal" else None
        if not result.converged:
            warnings.warn(
                f"contact solve did not converge: residual {result.residual:.3g} > tol {self.tol:.3g} "
                f"after {result.iterations} iterations ({mode} = {value:.6g})",
                RuntimeWarning,
                stacklevel=3,
            )
        return result

    def _solve_adhesive(self, mode: str, value: float, initial: ContactResult | None) -> ContactResult:
        from .adhesive import solve_adhesive  # noqa: PLC0415 - only adhesive solves need it

        result = solve_adhesive(self, mode, value, initial)
        if not result.converged and result.contact_state != "detached":
            warnings.warn(
                f"contact solve did not converge: residual {result.residual:.3g} > tol {self.tol:.3g} "
                f"after {result.iterations} iterations ({mode} = {value:.6g})",
                RuntimeWarning,
                stacklevel=4,
            )
        return result

    def _plain_solver(self) -> "HalfSpaceSolver":
        """The same cell without the interaction: the start of a cold adhesive solve."""
        if self._plain is None:
            self._plain = HalfSpaceSolver(
                self.texture, self.modulus, layer=self.layer, tol=self.tol, max_iter=self.max_iter,
                formulation=self.formulation, coarse_to_fine=self.coarse_to_fine, xp=self.backend.xp,
                workers=self.backend.workers, fft=self.backend.fft, kernels=self._kernels_choice,
                precondition=self.precondition,
            )
        return self._plain

    def _adhesive_setup(self) -> Any:
        """The adhesive solve's operators on this solver's texture (built on first use)."""
        if self._adhesive is None:
            from .adhesive import AdhesiveSetup  # noqa: PLC0415

            self._adhesive = AdhesiveSetup(self)
        return self._adhesive

    @property
    def arithmetic(self) -> str:
        """What decides a solve's last bits besides its inputs: the FFT engine and the family of
        element-wise kernels this solver runs on its grid, e.g. ``"ducc0/numpy"``. Stored results
        are keyed by it, so that an entry one installation wrote (SciPy's FFTs, no Numba) is
        never read as another's (ducc0, the compiled loops): the same command then gives the same
        bits whatever the cache held."""
        if not self.backend.is_numpy:
            return f"{self.backend.fft}/array"
        compiled = self._compiled or (
            (self._kernels_choice == "numba" or self._turns_compiled()) and not _COMPILED_UNAVAILABLE)
        family = "numba" if compiled else "array" if self._kernels_choice == "array" else "numpy"
        return f"{self.backend.fft}/{family}"

    def _turns_compiled(self) -> bool:
        """Whether this solver runs on the compiled loops (from its first solve): ``"compiled"``
        wherever Numba is there, ``"auto"`` on grids of :data:`COMPILED_FIRST_POINTS` and more."""
        if not self.backend.is_numpy or self._kernels_choice not in ("auto", "compiled"):
            return False
        if self._kernels_choice == "auto" and math.prod(self.texture.shape) < COMPILED_FIRST_POINTS:
            return False
        # last: it asks the import system for Numba (~50 us)
        return not _jit_disabled()

    @property
    def _S(self) -> Any:
        if self._S_op is None and self.texture.periodic:
            self._S_op = stiffness_operator(self.backend, self.texture, self.modulus, self.layer)
        return self._S_op

    @property
    def _Sh(self) -> Any:
        if self._Sh_field is None and self.texture.periodic:
            self._Sh_field = self._S(self.h)
        return self._Sh_field

    def _callback(self) -> Callable[[int, float], None] | None:
        """The per-iteration callback of the conjugate gradient: ``progress`` with this grid, and
        the check of the caller's cancellation scope (:mod:`fingerpad.cancel`: a solve nobody
        waits for stops within one iteration, before it returns or stores anything)."""
        token = cancel_scope()
        if self.progress is None and token is None:
            return None
        report, shape = self.progress, self.texture.shape
        if token is None:
            return lambda it, residual: report(shape, it, residual)  # type: ignore[misc]

        def callback(it: int, residual: float) -> None:
            token.check()
            if report is not None:
                report(shape, it, residual)

        return callback

    def _precond(self, form: str) -> Any:
        if not self.precondition:
            return None
        if form not in self._pre:
            self._pre[form] = preconditioner(self.backend, self.texture, self.modulus, form, self.layer)
        return self._pre[form]


@dataclass
class _Seed:
    pressure: np.ndarray
    gap: np.ndarray
