"""The two FFT engines of NumPy arrays (ducc0 and SciPy) give the same transforms and solves.

ducc0 is optional (the ``fast`` extra): without it ``"auto"`` falls back to SciPy, which these
tests check by hiding the module (those run with or without ducc0; the comparisons need it).
The engine only changes rounding, so the transforms agree to double precision and solves
converge in the same iterations to the same contact set.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest

from fingerpad.contact import HalfSpaceSolver
from fingerpad.contact.greens import Backend, compliance_operator
from fingerpad.errors import FingerpadError

from .test_solver import E, caps, paraboloid, random_rough

try:
    import ducc0  # noqa: F401

    HAVE_DUCC0 = True
except ImportError:
    HAVE_DUCC0 = False
needs_ducc0 = pytest.mark.skipif(not HAVE_DUCC0, reason="ducc0 (the 'fast' extra) is not installed")


@needs_ducc0
@pytest.mark.parametrize("shape", [(32, 48), (33, 47), (64, 1), (256, 448), (300, 257)])
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_transforms_agree(shape: tuple[int, int], dtype: type) -> None:
    a = np.random.default_rng(1).standard_normal(shape).astype(dtype)
    d, s = Backend(fft="ducc0"), Backend(fft="scipy")
    ha, hb = d.rfft2(a), s.rfft2(a)
    assert ha.dtype == hb.dtype and ha.shape == hb.shape
    eps = np.finfo(dtype).eps
    np.testing.assert_allclose(ha, hb, rtol=0, atol=50 * eps * np.abs(hb).max())
    # inverse (ducc0 may overwrite its input: hand it a copy) and the zero-padded forward
    np.testing.assert_allclose(d.irfft2(ha.copy(), shape), a, rtol=0, atol=50 * eps * np.abs(a).max())
    big = (2 * shape[0], 2 * shape[1])
    np.testing.assert_allclose(d.rfft2(a, s=big), s.rfft2(a, s=big), rtol=0, atol=100 * eps * np.abs(a).sum())


@needs_ducc0
@pytest.mark.parametrize("periodic", [True, False])
def test_operators_agree(periodic: bool) -> None:
    tex = paraboloid(48, 1e-4, 1e-3, periodic=periodic)
    p = np.random.default_rng(2).random(tex.shape) * 1e4
    ud = compliance_operator(Backend(fft="ducc0"), tex, E)(p)
    us = compliance_operator(Backend(fft="scipy"), tex, E)(p)
    np.testing.assert_allclose(ud, us, rtol=0, atol=1e-12 * np.abs(us).max())


@needs_ducc0
@pytest.mark.parametrize("formulation", ["primal", "dual"])
def test_solves_agree(formulation: str) -> None:
    tex = random_rough(64, 1e-4, 1e-6, seed=5)
    pbar = 0.3 * E * tex.peak_to_valley / tex.size[0]
    a = HalfSpaceSolver(tex, E, formulation=formulation, fft="scipy").solve_pressure(pbar)
    b = HalfSpaceSolver(tex, E, formulation=formulation, fft="ducc0").solve_pressure(pbar)
    assert a.converged and b.converged
    assert a.iterations == b.iterations
    assert np.array_equal(a.contact, b.contact)
    np.testing.assert_allclose(b.pressure, a.pressure, rtol=0, atol=1e-7 * a.max_pressure)


@needs_ducc0
def test_finite_body_solve_agrees() -> None:
    tex = paraboloid(64, 1e-4, 1e-3, periodic=False)
    a = HalfSpaceSolver(tex, E, fft="scipy").solve_pressure(2e3)
    b = HalfSpaceSolver(tex, E, fft="ducc0").solve_pressure(2e3)
    assert a.iterations == b.iterations and np.array_equal(a.contact, b.contact)
    np.testing.assert_allclose(b.pressure, a.pressure, rtol=0, atol=1e-7 * a.max_pressure)


def test_auto_prefers_ducc0_and_falls_back_to_scipy(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("FINGERPAD_FFT", raising=False)
    assert Backend().fft == ("ducc0" if HAVE_DUCC0 else "scipy")
    monkeypatch.setenv("FINGERPAD_FFT", " SciPy ")  # any case, spaces ignored
    assert Backend().fft == "scipy"
    if HAVE_DUCC0:
        assert Backend(fft="ducc0").fft == "ducc0"  # the argument wins over the variable
    monkeypatch.delenv("FINGERPAD_FFT")
    # ducc0 not installed: a None entry in sys.modules makes its import fail
    monkeypatch.setitem(sys.modules, "ducc0", None)
    monkeypatch.setitem(sys.modules, "ducc0.fft", None)
    assert Backend().fft == "scipy"
    with pytest.raises(FingerpadError, match=r"FFT engine 'ducc0' .*: the 'fast' extra is not installed \(ducc0 missing\): pip install 'fingerpad\[fast\]'"):
        HalfSpaceSolver(caps(32, 1e-4, 5e-5, 1e-5), E, fft="ducc0")
    # the coarse levels of a nested solve use the engine of the fine one
    solver = HalfSpaceSolver(caps(256, 1e-4, 5e-5, 1e-5), E)
    assert solver.solve_pressure(1e4).converged
    coarse = [s for s in solver._coarse.values() if s is not None]
    assert coarse and {s.backend.fft for s in coarse} == {"scipy"}


def test_bad_settings_are_clear_errors(monkeypatch: pytest.MonkeyPatch) -> None:
    tex = caps(32, 1e-4, 5e-5, 1e-5)
    with pytest.raises(FingerpadError, match=r"unknown FFT engine 'fftw' \(fft\)"):
        HalfSpaceSolver(tex, E, fft="fftw")
    monkeypatch.setenv("FINGERPAD_FFT", "mkl")
    with pytest.raises(FingerpadError, match=r"unknown FFT engine 'mkl' \(FINGERPAD_FFT\)"):
        HalfSpaceSolver(tex, E)
    monkeypatch.delenv("FINGERPAD_FFT")
    monkeypatch.setenv("FINGERPAD_FFT_WORKERS", "two")
    with pytest.raises(FingerpadError, match="FINGERPAD_FFT_WORKERS must be a whole number"):
        HalfSpaceSolver(tex, E)
    monkeypatch.setenv("FINGERPAD_FFT_WORKERS", "1")
    assert HalfSpaceSolver(tex, E).backend.workers == 1
    with pytest.raises(FingerpadError, match="workers must be"):
        HalfSpaceSolver(tex, E, workers=-2)


def test_bad_setting_on_the_command_line(monkeypatch: pytest.MonkeyPatch) -> None:
    from typer.testing import CliRunner  # noqa: PLC0415

    from fingerpad.cli import app  # noqa: PLC0415

    monkeypatch.setenv("FINGERPAD_FFT", "bogus")
    res = CliRunner().invoke(app, ["solve", "--texture", "caps", "--radius", "50um", "--height", "10um",
                                   "--spacing", "100um", "--grid", "32", "--pressure", "10kPa"])
    assert res.exit_code == 2
    assert "error: unknown FFT engine 'bogus' (FINGERPAD_FFT)" in res.output
    assert "Traceback" not in res.output


@pytest.fixture
def ducc0_pool_of_two():
    """ducc0's FFT thread pool running with two threads (as on a 2-core machine), restored after."""
    import ducc0.fft
    import ducc0.misc as dm

    ducc0.fft.r2c(np.ones((8, 8)), nthreads=1)  # the pool exists
    before = dm.thread_pool_size()
    dm.resize_thread_pool(2)
    yield dm
    dm.resize_thread_pool(before)


@needs_ducc0
def test_every_fork_of_the_process_parks_the_fft_threads(ducc0_pool_of_two, monkeypatch):
    """A fork once hung for good in ducc0's fork handler (joining its pool's threads): the pool
    holds only the calling thread wherever this process forks workers (the analysis's pools, a
    local sweep cluster's start, the deflection's ramps), and gets its size back after."""
    from fingerpad.contact.greens import fft_threads_parked
    from fingerpad.micro.deflection import ramps

    dm = ducc0_pool_of_two
    with fft_threads_parked():
        assert dm.thread_pool_size() == 1
    assert dm.thread_pool_size() == 2
    with pytest.raises(RuntimeError), fft_threads_parked():  # restored after an error too
        raise RuntimeError
    assert dm.thread_pool_size() == 2
    if sys.platform.startswith("linux"):
        pytest.importorskip("distributed")
        from fingerpad.design.engine import _worker_start

        monkeypatch.delenv("FINGERPAD_DEVICE", raising=False)
        with _worker_start():
            assert dm.thread_pool_size() == 1
        assert dm.thread_pool_size() == 2

    seen = []

    class Pool:  # records the pool size where the executor would fork its workers
        def __init__(self, *args, **kwargs):
            seen.append(dm.thread_pool_size())

        def __enter__(self):
            raise RuntimeError("stop here")

        def __exit__(self, *exc):
            return False

    monkeypatch.setattr(ramps, "ProcessPoolExecutor", Pool)
    with pytest.raises(RuntimeError, match="stop here"):
        ramps._pooled([], 2, None)
    assert seen == [1] and dm.thread_pool_size() == 2


@needs_ducc0
@pytest.mark.parametrize("fft", ["ducc0", "scipy"])
def test_the_same_bits_on_any_number_of_cores(fft: str) -> None:
    """A transform and a solve have the same bits with 1, 2 or 3 FFT threads: the machine's
    cores decide nothing (ducc0 left to thread a 256 x 448 transform itself gives other last bits
    with 2 threads than with 1; contact.transforms cuts it into blocks fixed by the shape)."""
    x = np.random.default_rng(3).random((256, 448))
    spectra = [Backend(workers=w, fft=fft).rfft2(x) for w in (1, 2, 3)]
    fields = [Backend(workers=w, fft=fft).irfft2(spectra[0].copy(), x.shape) for w in (1, 2, 3)]
    assert all(np.array_equal(spectra[0], s) for s in spectra[1:])
    assert all(np.array_equal(fields[0], f) for f in fields[1:])
    np.testing.assert_allclose(fields[0], x, rtol=0, atol=1e-14)
    tex = random_rough(256, 1e-4, 1e-6, seed=2)
    pbar = 0.3 * E * tex.peak_to_valley / tex.size[0]
    solves = [HalfSpaceSolver(tex, E, workers=w, fft=fft).solve_pressure(pbar) for w in (1, 2)]
    assert np.array_equal(solves[0].pressure, solves[1].pressure)
