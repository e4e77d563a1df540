"""Validation of the half-space contact solver against exact solutions and invariants."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from fingerpad.contact import HalfSpaceSolver
from fingerpad.errors import FingerpadError
from fingerpad.micro.loadcurve import critical_pressure, full_contact_pressure, load_curve
from fingerpad.textures import Texture

E = 1.0e6  # reduced modulus, Pa


def paraboloid(n: int, length: float, radius: float, periodic: bool) -> Texture:
    """z = -r^2/(2R) about the cell centre (the Hertz geometry)."""
    x = (np.arange(n) + 0.5) * length / n - length / 2 if not periodic else np.arange(n) * length / n - length / 2
    X, Y = np.meshgrid(x, x, indexing="ij")
    return Texture(-(X**2 + Y**2) / (2 * radius), (length, length), periodic=periodic)


def caps(n: int, lam: float, radius: float, height: float) -> Texture:
    """One spherical cap of height h on a flat base, centred on a pixel of a periodic cell."""
    x = np.arange(n) * lam / n - lam / 2
    X, Y = np.meshgrid(x, x, indexing="ij")
    z = np.sqrt(np.maximum(radius**2 - X**2 - Y**2, 0.0)) - (radius - height)
    return Texture(np.maximum(z, 0.0), (lam, lam))


def hertz(force: float, radius: float) -> tuple[float, float, float]:
    """Contact radius, peak pressure and approach of a Hertz contact."""
    a = (3 * force * radius / (4 * E)) ** (1 / 3)
    return a, 3 * force / (2 * math.pi * a**2), a**2 / radius


# ------------------------------------------------------------------------------------ Hertz


@pytest.mark.parametrize("n", [64, 128])
def test_hertz_nonperiodic(n: int) -> None:
    R, L, a_target = 1e-3, 0.6e-3, 0.15e-3
    force = 4 * E * a_target**3 / (3 * R)
    res = HalfSpaceSolver(paraboloid(n, L, R, periodic=False), E).solve_pressure(force / L**2)
    a, p0, d = hertz(force, R)
    assert res.converged
    assert abs(math.sqrt(res.real_contact_area / math.pi) / a - 1) < 0.01
    assert abs(res.max_pressure / p0 - 1) < 0.01
    assert abs(res.approach / d - 1) < 0.01
    assert abs(res.mean_pressure * L**2 / force - 1) < 1e-12  # load balance


def test_hertz_grid_convergence() -> None:
    """Peak pressure and approach errors fall at second order with the grid spacing."""
    R, L, a_target = 1e-3, 0.6e-3, 0.15e-3
    force = 4 * E * a_target**3 / (3 * R)
    _, p0, d = hertz(force, R)
    errs = []
    for n in (32, 64, 128):
        res = HalfSpaceSolver(paraboloid(n, L, R, periodic=False), E).solve_pressure(force / L**2)
        errs.append((abs(res.max_pressure / p0 - 1), abs(res.approach / d - 1)))
    for coarse, fine in zip(errs, errs[1:]):
        assert fine[0] < coarse[0] / 2.5
        assert fine[1] < coarse[1] / 2.5


def test_hertz_approach_control_matches_load_control() -> None:
    R, L = 1e-3, 0.6e-3
    _, _, d = hertz(1e-3, R)
    force = 1e-3
    solver = HalfSpaceSolver(paraboloid(96, L, R, periodic=False), E)
    res = solver.solve_approach(d)
    assert res.converged
    assert abs(res.mean_pressure * L**2 / force - 1) < 0.01


def test_hertz_large_periodic_cell() -> None:
    """An isolated sphere in a periodic cell 10 contact radii wide is Hertzian to 1 %."""
    R, L, n = 1e-3, 1.0e-3, 256
    a_target = L / 10
    force = 4 * E * a_target**3 / (3 * R)
    res = HalfSpaceSolver(paraboloid(n, L, R, periodic=True), E).solve_pressure(force / L**2)
    a, p0, _ = hertz(force, R)
    assert res.converged
    assert abs(math.sqrt(res.real_contact_area / math.pi) / a - 1) < 0.01
    assert abs(res.max_pressure / p0 - 1) < 0.01


# ------------------------------------------------------------------------------ Westergaard


def sinusoid(n: int, lam: float, h: float) -> Texture:
    x = np.arange(n) * lam / n
    z = h * np.cos(2 * np.pi * x / lam)
    return Texture(np.repeat(z[:, None], 4, axis=1), (lam, 4 * lam / n))


@pytest.mark.parametrize("formulation", ["auto", "primal", "dual"])
def test_westergaard_whole_range(formulation: str) -> None:
    n, lam, h = 512, 1e-4, 1e-6
    p_star = math.pi * E * h / lam
    solver = HalfSpaceSolver(sinusoid(n, lam, h), E, formulation=formulation)
    fractions = [0.001, 0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99, 0.999]
    curve = load_curve(solver, [f * p_star for f in fractions])
    exact = (2 / math.pi) * np.arcsin(np.sqrt(fractions))
    assert np.all(curve.converged)
    # the discrete contact set is exact to about a pixel on each of the two contact edges
    assert np.max(np.abs(curve.contact_fraction - exact)) < 2.5 / n
    # full contact starts at p*: just above it every pixel touches
    assert solver.solve_pressure(1.001 * p_star).contact_state == "full"
    assert solver.solve_pressure(0.99 * p_star).contact_state != "full"


def test_westergaard_full_contact_pressure_bracket() -> None:
    n, lam, h = 256, 1e-4, 1e-6
    p_star = math.pi * E * h / lam
    br = full_contact_pressure(HalfSpaceSolver(sinusoid(n, lam, h), E), rtol=1e-3)
    assert br.relative_width <= 1e-3
    # on a grid the last gap (one pixel at the valley) closes a little before p*
    assert 0.99 * p_star < br.estimate <= 1.001 * p_star


# ------------------------------------------------------------ bisinusoid (JGH asymptotics)


def bisinusoid(n: int, lam: float, delta: float) -> Texture:
    """Johnson-Greenwood-Higginson egg-box z = Delta cos(2 pi x/lam) cos(2 pi y/lam)."""
    x = np.arange(n) * lam / n
    X, Y = np.meshgrid(x, x, indexing="ij")
    return Texture(delta * np.cos(2 * np.pi * X / lam) * np.cos(2 * np.pi * Y / lam), (lam, lam))


def test_bisinusoid_light_load_is_hertz() -> None:
    """Light load: each of the two peaks per cell is a Hertz contact with 1/R = Delta q^2."""
    n, lam, delta = 512, 1e-4, 1e-6  # contact radius ~18 px
    q = 2 * math.pi / lam
    p_star = math.sqrt(2) * math.pi * E * delta / lam
    pbar = 1e-3 * p_star
    res = HalfSpaceSolver(bisinusoid(n, lam, delta), E).solve_pressure(pbar)
    a, _, _ = hertz(pbar * lam**2 / 2, 1 / (delta * q**2))
    assert res.converged
    assert abs(res.contact_fraction / (2 * math.pi * a**2 / lam**2) - 1) < 0.03


def test_bisinusoid_near_full_contact_asymptote() -> None:
    """Near full contact JGH: A_gap / lam^2 = (3 / 2 pi) (1 - p/p*), p* = sqrt(2) pi E* Delta / lam."""
    n, lam, delta = 256, 1e-4, 1e-6
    p_star = math.sqrt(2) * math.pi * E * delta / lam
    solver = HalfSpaceSolver(bisinusoid(n, lam, delta), E)
    for ratio in (0.97, 0.985):
        res = solver.solve_pressure(ratio * p_star)
        assert res.converged
        gap_fraction = 1 - res.contact_fraction
        expected = 3 / (2 * math.pi) * (1 - ratio)
        assert abs(gap_fraction / expected - 1) < 0.12
    assert solver.solve_pressure(1.001 * p_star).contact_state == "full"


# --------------------------------------------------------------------------- invariants


def random_rough(n: int, length: float, rms: float, seed: int = 1) -> Texture:
    rng = np.random.default_rng(seed)
    q = np.sqrt(np.fft.fftfreq(n)[:, None] ** 2 + np.fft.rfftfreq(n)[None, :] ** 2) * n
    spec = np.where((q >= 2) & (q <= n / 8), np.maximum(q, 1.0) ** (-1.8), 0.0)
    noise = rng.standard_normal((n, n // 2 + 1)) + 1j * rng.standard_normal((n, n // 2 + 1))
    z = np.fft.irfft2(spec * noise, s=(n, n))
    return Texture(z * rms / z.std(), (length, length))


@pytest.mark.parametrize("texture_kind", ["rough", "caps"])
@pytest.mark.parametrize("load", [0.02, 0.5])
def test_invariants(texture_kind: str, load: float) -> None:
    if texture_kind == "rough":
        tex = random_rough(128, 1e-4, 1e-6)
    else:
        tex = caps(128, 100e-6, 50e-6, 10e-6)
    scale = E * tex.peak_to_valley / tex.size[0]
    res = HalfSpaceSolver(tex, E, tol=1e-10).solve_pressure(load * scale)
    assert res.converged and res.residual < 1e-10
    assert abs(res.pressure.mean() / res.mean_pressure - 1) < 1e-12
    assert abs(res.mean_pressure / (load * scale) - 1) < 1e-9  # load balance
    assert res.pressure.min() >= 0
    pv = tex.peak_to_valley
    assert res.gap.min() > -1e-7 * pv
    assert np.max(np.abs(res.gap[res.pressure > 0])) < 1e-7 * pv
    # displacement and gap are consistent: g = u + h_max - h - d
    g = res.displacement + tex.heights.max() - tex.heights - res.approach
    np.testing.assert_allclose(g, res.gap, atol=1e-9 * pv)


@pytest.mark.parametrize("precondition", [True, False])
def test_primal_and_dual_agree(precondition: bool) -> None:
    tex = random_rough(128, 1e-4, 1e-6, seed=3)
    pbar = 0.3 * E * tex.peak_to_valley / tex.size[0]
    a = HalfSpaceSolver(tex, E, formulation="primal", tol=1e-10, precondition=precondition).solve_pressure(pbar)
    b = HalfSpaceSolver(tex, E, formulation="dual", tol=1e-10, precondition=precondition).solve_pressure(pbar)
    assert a.converged and b.converged
    assert np.array_equal(a.contact, b.contact)
    np.testing.assert_allclose(a.pressure, b.pressure, atol=1e-6 * a.max_pressure)
    assert abs(a.approach - b.approach) < 1e-8 * tex.peak_to_valley


def test_approach_control_inverts_pressure_control_periodic() -> None:
    tex = caps(128, 100e-6, 50e-6, 10e-6)
    solver = HalfSpaceSolver(tex, E)
    res = solver.solve_pressure(5e3)
    back = solver.solve_approach(res.approach)
    assert back.converged
    assert abs(back.mean_pressure / 5e3 - 1) < 1e-5


def test_symmetric_texture_gives_symmetric_fields() -> None:
    n = 128
    tex = caps(n, 100e-6, 50e-6, 10e-6)  # cap centred on pixel n/2: mirror i -> n - i
    res = HalfSpaceSolver(tex, E, tol=1e-10).solve_pressure(2e4)
    p = res.pressure
    mirror_x = np.roll(p[::-1, :], 1, axis=0)
    mirror_y = np.roll(p[:, ::-1], 1, axis=1)
    scale = p.max()
    np.testing.assert_allclose(mirror_x, p, atol=1e-7 * scale)
    np.testing.assert_allclose(mirror_y, p, atol=1e-7 * scale)
    np.testing.assert_allclose(p.T, p, atol=1e-7 * scale)


def test_warm_start_saves_iterations() -> None:
    tex = caps(128, 100e-6, 50e-6, 10e-6)
    solver = HalfSpaceSolver(tex, E, coarse_to_fine=False)
    first = solver.solve_pressure(1.0e4)
    cold = solver.solve_pressure(1.05e4)
    warm = solver.solve_pressure(1.05e4, initial=first)
    assert warm.iterations < cold.iterations
    assert warm.contact_fraction == cold.contact_fraction


def test_progress_reports_every_level_and_the_final_residual() -> None:
    tex = caps(256, 100e-6, 50e-6, 10e-6)
    calls: list[tuple[tuple[int, int], int, float]] = []
    solver = HalfSpaceSolver(tex, E, progress=lambda shape, it, r: calls.append((shape, it, r)))
    res = solver.solve_pressure(1.5e4)
    shapes = [c[0] for c in calls]
    # the nested start reports its coarse levels first, coarsest first, then the cell itself
    assert shapes[0] == (64, 64) and shapes[-1] == (256, 256)
    assert sorted(set(shapes)) == [(64, 64), (128, 128), (256, 256)]
    assert shapes == sorted(shapes)
    fine = [c for c in calls if c[0] == (256, 256)]
    assert [c[1] for c in fine] == list(range(len(fine)))  # one call per iteration, in order
    assert fine[-1][1] == res.iterations and fine[-1][2] == pytest.approx(res.residual)
    assert res.converged and fine[-1][2] < solver.tol <= fine[-2][2]  # stops at the first residual below tol
    with pytest.raises(FingerpadError, match="progress"):
        HalfSpaceSolver(tex, E, progress="yes")  # type: ignore[arg-type]


# --------------------------------------------------------------- contact states, critical p


def test_states_and_critical_pressure_bracket() -> None:
    tex = caps(128, 100e-6, 50e-6, 10e-6)
    solver = HalfSpaceSolver(tex, E)
    crit = critical_pressure(solver, rtol=1e-3)
    assert crit.relative_width <= 1e-3
    assert solver.solve_pressure(crit.lower).contact_state == "asperity"
    assert solver.solve_pressure(crit.upper).contact_state == "transition"
    huge = solver.solve_pressure(1e3 * crit.upper)
    assert huge.contact_state in ("transition", "full")


def test_unconverged_is_reported_not_hidden() -> None:
    tex = random_rough(64, 1e-4, 1e-6)
    solver = HalfSpaceSolver(tex, E, max_iter=2, formulation="primal", coarse_to_fine=False)
    with pytest.warns(RuntimeWarning, match="did not converge"):
        res = solver.solve_pressure(1e4)
    assert not res.converged and res.residual > solver.tol
    assert res.summary()["converged"] is False


# --------------------------------------------------------------------------- bad input


@pytest.mark.parametrize("modulus", [0.0, -1.0, float("nan")])
def test_bad_modulus(modulus: float) -> None:
    with pytest.raises(FingerpadError, match="modulus"):
        HalfSpaceSolver(caps(32, 1e-4, 5e-5, 1e-5), modulus)


def test_bad_numerics() -> None:
    tex = caps(32, 1e-4, 5e-5, 1e-5)
    with pytest.raises(FingerpadError, match="tolerance"):
        HalfSpaceSolver(tex, E, tol=0)
    with pytest.raises(FingerpadError, match="too small"):
        HalfSpaceSolver(Texture(np.zeros((2, 2)), (1e-4, 1e-4)), E)
    with pytest.raises(FingerpadError, match="pressure"):
        HalfSpaceSolver(tex, E).solve_pressure(-1.0)
    with pytest.raises(FingerpadError, match="full contact"):
        HalfSpaceSolver(tex, E).solve_approach(1.0)
    with pytest.raises(FingerpadError, match="periodic"):
        HalfSpaceSolver(paraboloid(32, 1e-4, 1e-3, periodic=False), E, formulation="dual")


@pytest.mark.parametrize("precondition", [True, False])
@pytest.mark.parametrize("kernels", ["numpy", "numba"])
@pytest.mark.parametrize("formulation", ["primal", "dual"])
def test_fast_kernels_match_array_kernels(formulation: str, kernels: str, precondition: bool) -> None:
    if kernels == "numba":
        pytest.importorskip("numba")
    tex = random_rough(64, 1e-4, 1e-6, seed=5)
    pbar = 0.3 * E * tex.peak_to_valley / tex.size[0]
    kw = dict(formulation=formulation, precondition=precondition)
    a = HalfSpaceSolver(tex, E, kernels="array", **kw).solve_pressure(pbar)
    b = HalfSpaceSolver(tex, E, kernels=kernels, **kw).solve_pressure(pbar)
    assert a.iterations == b.iterations
    assert np.array_equal(a.contact, b.contact)
    np.testing.assert_allclose(a.pressure, b.pressure, rtol=0, atol=1e-9 * a.max_pressure)


def test_auto_kernels_are_the_grid_s_choice_not_the_history_s(monkeypatch) -> None:
    """``kernels="auto"``: below COMPILED_FIRST_POINTS NumPy loops however much the solver has
    solved (the compiled loops differ in the last bits, so a switch would make a solve depend on
    the solves before it), bit for bit ``kernels="numpy"``; from that grid size the compiled
    loops from the first solve, coarse levels included, with the same solution to the solver's
    tolerance and on the types they were warmed up on (no compile mid-solve)."""
    pytest.importorskip("numba")
    import fingerpad.contact.solver as solver_mod
    from fingerpad.contact import kernels_numba
    from fingerpad.contact.kernels import NumpyKernels
    from fingerpad.contact.kernels_numba import NumbaKernels

    tex = random_rough(128, 1e-4, 1e-6, seed=5)
    pbar = 0.3 * E * tex.peak_to_valley / tex.size[0]
    solver = HalfSpaceSolver(tex, E)
    ref = HalfSpaceSolver(tex, E, kernels="numpy").solve_pressure(pbar)
    for p in np.geomspace(0.1, 3.0, 6) * pbar:  # work: any threshold of it would pass
        solver.solve_pressure(p)
    late = solver.solve_pressure(pbar)
    assert type(solver._kern) is NumpyKernels
    assert np.array_equal(late.pressure, ref.pressure)

    monkeypatch.setattr(solver_mod, "COMPILED_FIRST_POINTS", 128 * 128)  # this grid is "large"
    big = HalfSpaceSolver(tex, E)
    first = big.solve_pressure(pbar)
    assert isinstance(big._kern, NumbaKernels)
    assert isinstance(big._coarse["half"]._kern, NumbaKernels)
    assert first.converged and first.iterations == ref.iterations
    assert np.array_equal(first.contact, ref.contact)
    np.testing.assert_allclose(first.pressure, ref.pressure, rtol=0, atol=1e-9 * ref.max_pressure)
    loops = kernels_numba._NUMBA
    assert all(len(f.signatures) == 1 for f in loops if f.signatures), [f.signatures for f in loops]


def test_compiled_kernels_for_a_caller_of_many_solves_from_the_first_solve() -> None:
    """``kernels="compiled"`` (a unit cell's curve): the compiled loops from the first solve on
    any grid, coarse levels included, the same solution to the solver's tolerance as NumPy's
    loops; ``arithmetic`` names them before the first solve (a cell's cache key)."""
    pytest.importorskip("numba")
    from fingerpad.contact.kernels import NumpyKernels
    from fingerpad.contact.kernels_numba import NumbaKernels

    tex = random_rough(128, 1e-4, 1e-6, seed=5)
    pbar = 0.3 * E * tex.peak_to_valley / tex.size[0]
    ref = HalfSpaceSolver(tex, E, kernels="numpy").solve_pressure(pbar)
    solver = HalfSpaceSolver(tex, E, kernels="compiled")
    assert solver.arithmetic.endswith("/numba") and type(solver._kern) is NumpyKernels  # not loaded yet
    res = solver.solve_pressure(pbar)
    assert isinstance(solver._kern, NumbaKernels)
    assert isinstance(solver._coarse["half"]._kern, NumbaKernels)
    assert res.converged and res.iterations == ref.iterations and np.array_equal(res.contact, ref.contact)
    np.testing.assert_allclose(res.pressure, ref.pressure, rtol=0, atol=1e-9 * ref.max_pressure)
    assert HalfSpaceSolver(tex, E).arithmetic.endswith("/numpy")  # "auto" on this grid


def test_auto_kernels_compiled_from_the_first_solve_on_very_large_grids(monkeypatch) -> None:
    pytest.importorskip("numba")
    import fingerpad.contact.solver as solver_mod
    from fingerpad.contact.kernels_numba import NumbaKernels

    tex = random_rough(128, 1e-4, 1e-6, seed=5)
    monkeypatch.setattr(solver_mod, "COMPILED_FIRST_POINTS", 128 * 128)  # "very large" = this grid
    solver = HalfSpaceSolver(tex, E)
    solver.solve_pressure(0.3 * E * tex.peak_to_valley / tex.size[0])
    assert isinstance(solver._kern, NumbaKernels)
    assert isinstance(solver._coarse["half"]._kern, NumbaKernels)  # its levels too, once loaded


def test_auto_kernels_stay_numpy_where_numba_jit_is_disabled(monkeypatch) -> None:
    import fingerpad.contact.solver as solver_mod
    from fingerpad.contact.kernels import NumpyKernels

    monkeypatch.setenv("NUMBA_DISABLE_JIT", "1")  # the loops would run as plain Python
    monkeypatch.setattr(solver_mod, "COMPILED_FIRST_POINTS", 1)
    tex = random_rough(64, 1e-4, 1e-6, seed=5)
    solver = HalfSpaceSolver(tex, E)
    solver.solve_pressure(0.3 * E * tex.peak_to_valley / tex.size[0])
    assert type(solver._kern) is NumpyKernels


def test_compiled_kernels_that_cannot_load_fall_back_to_numpy(monkeypatch) -> None:
    """Where Numba cannot build its loops (no writable cache directory, say), the solve that
    turns to them warns once and runs on the NumPy kernels, with the same solution."""
    import fingerpad.contact.solver as solver_mod
    from fingerpad.contact import kernels_numba
    from fingerpad.contact.kernels import NumpyKernels

    def broken() -> None:
        raise RuntimeError("cannot cache function 'free_stats': no locator available")

    monkeypatch.setattr(kernels_numba, "_NUMBA", None)
    monkeypatch.setattr(kernels_numba, "_build_numba", broken)
    monkeypatch.setattr(solver_mod, "_COMPILED_UNAVAILABLE", False)
    tex = random_rough(64, 1e-4, 1e-6, seed=5)
    pbar = 0.3 * E * tex.peak_to_valley / tex.size[0]
    a = HalfSpaceSolver(tex, E).solve_pressure(pbar)
    monkeypatch.setattr(solver_mod, "COMPILED_FIRST_POINTS", 64 * 64)  # this grid turns to them
    solver = HalfSpaceSolver(tex, E)
    with pytest.warns(RuntimeWarning, match="compiled kernels unavailable.*no locator"):
        b = solver.solve_pressure(pbar)
    assert type(solver._kern) is NumpyKernels and b.converged
    np.testing.assert_allclose(b.pressure, a.pressure, rtol=0, atol=1e-9 * a.max_pressure)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # not again in this process
        HalfSpaceSolver(tex, E, kernels="numba").solve_pressure(pbar)


def test_preconditioned_matches_plain_polonsky_keer() -> None:
    """Both iterations solve the same problem: same contact set and fields at tol 1e-10; the
    preconditioned one in fewer iterations (an invariant of the method, not a timing)."""
    tex = random_rough(128, 1e-4, 1e-6, seed=4)
    pbar = 0.5 * E * tex.peak_to_valley / tex.size[0]
    a = HalfSpaceSolver(tex, E, tol=1e-10, precondition=False, formulation="primal").solve_pressure(pbar)
    b = HalfSpaceSolver(tex, E, tol=1e-10, coarse_to_fine=False).solve_pressure(pbar)
    assert a.converged and b.converged
    assert np.array_equal(a.contact, b.contact)
    np.testing.assert_allclose(b.pressure, a.pressure, rtol=0, atol=1e-6 * a.max_pressure)
    assert b.iterations < a.iterations


def test_two_grid_warm_start_matches_cold_solves() -> None:
    """Along a load curve each solve starts from the previous fine solution plus the coarse
    level's change; the answers are those of cold solves (same contact sets, same fields)."""
    tex = caps(128, 100e-6, 50e-6, 10e-6)
    pressures = [2e3, 5e3, 1.2e4, 3e4, 8e4]
    solver = HalfSpaceSolver(tex, E, tol=1e-10)
    curve = load_curve(solver, pressures)
    assert np.all(curve.converged)
    for p, warm in zip(pressures, curve.results):
        cold = HalfSpaceSolver(tex, E, tol=1e-10).solve_pressure(p)
        assert np.array_equal(warm.contact, cold.contact)
        np.testing.assert_allclose(warm.pressure, cold.pressure, rtol=0, atol=1e-6 * cold.max_pressure)
    # the warm path was taken: the solver keeps its last solution's coarse companion
    assert solver._warm is not None and solver._warm[0]() is curve.results[-1].pressure
