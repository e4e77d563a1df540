"""The two-block NumPy kernels (issue 23): every kernel gives the one-block kernel's fields bit
for bit and its sums and counts exactly (NumPy's pairwise sum splits at the middle anyway), its
dot products to rounding; one thread or two give the same bits; a whole solve keeps its
iterations, contact set and reported numbers."""

from __future__ import annotations

import numpy as np
import pytest

from fingerpad.contact import HalfSpaceSolver
from fingerpad.contact.kernels import NumpyKernels
from fingerpad.contact.kernels_blocked import BLOCKED_MIN_ROWS, BlockedNumpyKernels, blocked_applies
from fingerpad.textures.caps import spherical_caps

SHAPE = (BLOCKED_MIN_ROWS, 96)


def _fields(seed: int = 0) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(seed)
    x = np.maximum(rng.standard_normal(SHAPE), 0.0)  # ~half the points free
    return {
        "ax": rng.standard_normal(SHAPE), "b": rng.standard_normal(SHAPE) * 0.1, "x": x,
        "t": rng.standard_normal(SHAPE) * (x > 0), "z": rng.standard_normal(SHAPE).astype(np.float32),
    }


def _run(kern, f: dict[str, np.ndarray], lam: float, dl_zero: bool = False):
    """The preconditioned iteration's kernel calls in their order, on copies; every output."""
    f = {k: v.copy() for k, v in f.items()}
    rw, w = np.zeros(SHAPE), kern.mask_like(f["x"])
    b = f["b"]
    if dl_zero:  # the multiplier already right: no change dl, and no released points
        b = f["ax"] - lam
    rw, w, lam2, g, viol, nwork, srw, ne = kern.gradient(f["ax"], b, f["x"], lam, True, rw, w)
    out = {"rw": rw.copy(), "w": w.copy(), "numbers": (lam2, nwork, srw, ne), "close": (g, viol)}
    if ne:
        rw = kern.shift_on(rw, w, srw / nwork)
    rz, sz, st = kern.pre_stats(rw, f["z"], w, f["t"])
    t, rt = kern.pre_direction(f["z"], w, f["t"], 0.7, 1e-3, rw)
    out["t"] = t.copy()
    x, nclip, total = kern.pstep(f["x"], t, 0.3, True)
    x = kern.scale(x, 1.01)
    out.update(x=x.copy(), t_after=t.copy(), steps=(nclip,), sums=(sz, st, total), dots=(rz, rt))
    return out


@pytest.mark.parametrize("lam", [0.0, 0.05])
@pytest.mark.parametrize("dl_zero", [False, True])
def test_blocked_kernels_equal_the_one_block_kernels(lam, dl_zero):
    f = _fields()
    ref = _run(NumpyKernels(), f, lam, dl_zero)
    for threads in (1, 2):
        got = _run(BlockedNumpyKernels(threads), f, lam, dl_zero)
        for name in ("rw", "w", "t", "x", "t_after"):
            np.testing.assert_array_equal(got[name], ref[name], err_msg=name)
        assert got["numbers"][1:] == ref["numbers"][1:] and got["steps"] == ref["steps"]
        assert got["sums"] == ref["sums"]  # pairwise sums: exact
        np.testing.assert_allclose(got["numbers"][0], ref["numbers"][0], rtol=1e-13)
        np.testing.assert_allclose(got["dots"], ref["dots"], rtol=1e-13)
        np.testing.assert_allclose(got["close"], ref["close"], rtol=1e-12)
    assert ref["numbers"][3] > 0 or dl_zero  # released points happen (both branches run)


def test_threads_do_not_change_the_bits():
    f = _fields(1)
    one, two = _run(BlockedNumpyKernels(1), f, 0.02), _run(BlockedNumpyKernels(2), f, 0.02)
    for name in one:
        if isinstance(one[name], np.ndarray):
            np.testing.assert_array_equal(one[name], two[name])
        else:
            assert one[name] == two[name]


def test_blocked_by_shape_only():
    assert blocked_applies((512, 512)) and blocked_applies((1024, 1024))
    assert not blocked_applies((256, 256)) and not blocked_applies((513, 512)) and not blocked_applies((4096,))


def test_a_blocked_solve_matches_the_one_block_solve(monkeypatch):
    """A 512^2 cap cell (two blocks at the fine level) against the same solve on one block:
    same iterations and contact set, pressure to 1e-9 of its peak, load balance exact."""
    import fingerpad.contact.solver as solver_module

    tex = spherical_caps(radius=50e-6, height=10e-6, spacing=100e-6, grid=512)
    blocked = HalfSpaceSolver(tex, 0.3e6, tol=1e-8)
    assert isinstance(blocked._kern, BlockedNumpyKernels)
    got = blocked.solve_pressure(15e3)
    monkeypatch.setattr(solver_module, "blocked_applies", lambda shape: False)
    plain = HalfSpaceSolver(tex, 0.3e6, tol=1e-8)
    assert type(plain._kern) is NumpyKernels
    ref = plain.solve_pressure(15e3)
    assert got.converged and got.iterations == ref.iterations
    np.testing.assert_array_equal(got.pressure > 0, ref.pressure > 0)
    assert np.max(np.abs(got.pressure - ref.pressure)) <= 1e-9 * ref.pressure.max()
    assert got.pressure.mean() == pytest.approx(15e3, rel=1e-12)


@pytest.mark.parametrize("kernels", [NumpyKernels, lambda: BlockedNumpyKernels(2)])
def test_the_projected_step_counts_its_steps_within_a_solve(kernels):
    """The projected step returns the field's sum (for the mean's drift check) on every eighth
    step of a solve: counted from the solve's start, not across the solver's earlier solves,
    whose step counts would otherwise decide when a later solve rescales its iterate."""
    kern = kernels()
    rows = BLOCKED_MIN_ROWS
    x = np.ones((rows, 8))
    t = np.zeros_like(x)  # a zero step: nothing clips, only the count decides
    for _ in range(5):  # an earlier solve of five steps
        kern.pstep(x, t, 0.0)
    kern.release()
    totals = [not np.isnan(kern.pstep(x, t, 0.0)[2]) for _ in range(16)]
    assert totals == [k % 8 == 7 for k in range(16)]
