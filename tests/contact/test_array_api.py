"""GPU readiness without a GPU: the solver's numerics run through the array namespace.

``array_api_strict`` is a pure-CPU namespace that implements the Array API standard and nothing
else: any NumPy function applied to its arrays, any implicit conversion, any non-standard
method raises. Solving with it and getting the iterates of the NumPy path (same iteration
counts, same contact set, same fields to rounding) shows that a CuPy or PyTorch array would run
the same code. The optional GPU test runs only where CuPy finds a device.
"""

from __future__ import annotations

import contextlib

import numpy as np
import pytest

from fingerpad.contact import HalfSpaceSolver
from fingerpad.textures import Texture

from .test_solver import E, caps, paraboloid, random_rough

xps = pytest.importorskip("array_api_strict")


def _pair(tex: Texture, **kw):
    ref = HalfSpaceSolver(tex, E, kernels="array", **kw)
    strict = HalfSpaceSolver(tex, E, xp=xps, **kw)
    return ref, strict


def _same(a, b) -> None:
    # The preconditioner runs in float32 and the two paths use different FFT libraries
    # (SciPy's for NumPy, the namespace's own otherwise), so the iterates agree to single
    # precision rounding, far inside the solver tolerance; the iteration counts and the
    # contact sets are identical.
    assert a.converged and b.converged
    assert a.iterations == b.iterations
    assert a.formulation == b.formulation
    assert np.array_equal(a.contact, b.contact)
    np.testing.assert_allclose(b.pressure, a.pressure, rtol=0, atol=1e-6 * a.max_pressure)
    np.testing.assert_allclose(b.gap, a.gap, rtol=0, atol=1e-7 * a.texture.peak_to_valley)
    assert abs(b.approach - a.approach) <= 1e-7 * a.texture.peak_to_valley


@pytest.mark.parametrize("formulation", ["primal", "dual"])
@pytest.mark.parametrize("precondition", [True, False])
def test_strict_namespace_periodic(formulation: str, precondition: bool) -> None:
    tex = random_rough(64, 1e-4, 1e-6, seed=5)
    pbar = 0.3 * E * tex.peak_to_valley / tex.size[0]
    ref, strict = _pair(tex, formulation=formulation, precondition=precondition)
    _same(ref.solve_pressure(pbar), strict.solve_pressure(pbar))


def test_strict_namespace_approach_and_warm_start() -> None:
    tex = caps(64, 100e-6, 50e-6, 10e-6)
    ref, strict = _pair(tex)
    a, b = ref.solve_pressure(2e4), strict.solve_pressure(2e4)
    _same(a, b)
    _same(ref.solve_pressure(2.5e4, initial=a), strict.solve_pressure(2.5e4, initial=b))
    _same(ref.solve_approach(a.approach), strict.solve_approach(b.approach))


def test_strict_namespace_finite_body() -> None:
    tex = paraboloid(48, 0.6e-3, 1e-3, periodic=False)
    ref, strict = _pair(tex)
    _same(ref.solve_pressure(20.0), strict.solve_pressure(20.0))


def _device_namespace(name: str):
    """CuPy on a CUDA device, or PyTorch (through array_api_compat) on CUDA if it has one, else
    on its CPU tensors; skipped where the library is not installed (CI) or CuPy finds no device."""
    if name == "cupy":
        cp = pytest.importorskip("cupy")
        try:
            if cp.cuda.runtime.getDeviceCount() < 1:
                pytest.skip("no CUDA device")
        except Exception as exc:  # noqa: BLE001 - no driver: skip cleanly
            pytest.skip(f"no CUDA device ({exc})")
        return cp, contextlib.nullcontext()
    torch = pytest.importorskip("torch")
    # torch itself is taken as array_api_compat's wrapper of it (its own namespace is not the
    # Array API); new tensors go to the device inside the context (not for the whole session)
    xp = torch if name == "torch" else pytest.importorskip("array_api_compat.torch")
    return xp, torch.device("cuda" if torch.cuda.is_available() else "cpu")


@pytest.mark.parametrize("name", ["cupy", "torch", "array_api_compat.torch"])
def test_gpu_namespace_if_present(name: str) -> None:
    """The solver on CuPy or PyTorch arrays: the NumPy solution (PyTorch's tensors differ from
    the standard, e.g. ``size`` is a method, and its default dtype is float32)."""
    xp, device = _device_namespace(name)
    tex = random_rough(128, 1e-4, 1e-6, seed=2)
    pbar = 0.3 * E * tex.peak_to_valley / tex.size[0]
    a = HalfSpaceSolver(tex, E, kernels="array").solve_pressure(pbar)
    with device:
        solver = HalfSpaceSolver(tex, E, xp=xp)
        b = solver.solve_pressure(pbar)
        c = solver.solve_pressure(1.2 * pbar, initial=b)
        d = solver.solve_approach(b.approach)
    assert b.converged and abs(a.contact_fraction - b.contact_fraction) <= 2 / tex.heights.size
    np.testing.assert_allclose(b.pressure, a.pressure, rtol=0, atol=1e-7 * a.max_pressure)
    # a warm-started second solve and an approach-controlled one, as in a load curve
    c_ref = HalfSpaceSolver(tex, E, kernels="array").solve_pressure(1.2 * pbar)
    assert c.converged and abs(c.contact_fraction - c_ref.contact_fraction) <= 2 / tex.heights.size
    assert d.converged and abs(d.mean_pressure - pbar) <= 1e-5 * pbar
