"""Validation of the section model: Hertz, mesh convergence, mirror symmetry, the rigid limit,
the small-strain limit and force balance (issue 13's list)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad.micro.deflection.mesh import SectionGeometry, build_mesh
from fingerpad.micro.deflection.path import follow_load, follow_shear
from fingerpad.micro.deflection.solve import FrictionLaw, SectionSolver


def _solver(height=1.0, period=4.0, resolution=6, skin=1.0, nu=0.49, law=FrictionLaw("coulomb"), linear=False):
    mesh = build_mesh(SectionGeometry("ellipse", height, period, period), resolution=resolution)
    return SectionSolver(mesh, nu, skin, law, linear=linear, fold_penalty=20.0)


def test_zero_shear_matches_hertz_line_contact():
    """A semicircular asperity (R = r) pressed by the skin half-space: contact half-width
    b = sqrt(4 P R / (pi E*)) with the combined plane-strain modulus (Eq. 3.4 in 2-D)."""
    nu, skin = 0.49, 1.0
    solver = _solver(skin=skin, nu=nu, resolution=8)
    e_comb = 1.0 / (1.0 / skin + (1 - nu**2) / 1.0)
    loads = [0.02, 0.04]
    ramp = follow_load(solver, loads)
    assert ramp.stopped is None
    for st, p in zip(ramp.states, loads):
        b = math.sqrt(4 * p * 1.0 / (math.pi * e_comb))
        assert st.info["contact_length"] / 2 == pytest.approx(b, rel=0.04)
        assert st.info["friction_force"] == 0.0


def test_mirror_symmetry_of_the_shear_ramp():
    solver = _solver(height=1.5)
    start = follow_load(solver, [0.05]).states[-1]
    right = follow_shear(solver, start, 0.4, check_stability=False)
    left = follow_shear(solver, start, -0.4, check_stability=False)
    assert right.stopped is None and left.stopped is None
    for a, b in zip(right.states, left.states):
        assert a.shear == pytest.approx(-b.shear, abs=1e-9)
        assert a.info["contact_length"] == pytest.approx(b.info["contact_length"], rel=1e-6)
        assert a.info["tip_dx"] == pytest.approx(-b.info["tip_dx"], rel=1e-6, abs=1e-12)
        assert a.info["tip_dz"] == pytest.approx(b.info["tip_dz"], rel=1e-6)


def test_stiff_texture_tends_to_gain_one():
    """A texture 1000x stiffer than the skin hardly deflects: the contact length does not change
    with shear (with a linear half-space skin, tangential load does not lift it)."""
    solver = _solver(height=2.0, skin=1e-3)
    start = follow_load(solver, [2e-4]).states[-1]
    ramp = follow_shear(solver, start, 1.0, check_stability=False)
    assert ramp.stopped is None
    l0 = start.info["contact_length"]
    gains = np.array([s.info["contact_length"] / l0 for s in ramp.states])
    assert np.max(np.abs(gains - 1)) < 0.01
    assert max(abs(s.info["deflection_dx"]) for s in ramp.states) < 5e-3  # units of r, at mu = 1


def test_small_shear_agrees_with_the_small_strain_solution():
    nl = _solver(height=1.5)
    lin = _solver(height=1.5, linear=True)
    load, mu = 0.004, 0.05
    s_nl = follow_load(nl, [load]).states[-1]
    s_li = follow_load(lin, [load]).states[-1]
    a = nl.solve(load, mu, s_nl.copy(), lag=s_nl)
    b = lin.solve(load, mu, s_li.copy(), lag=s_li)
    assert a.info["deflection_dx"] == pytest.approx(b.info["deflection_dx"], rel=0.02)
    assert a.info["contact_length"] == pytest.approx(b.info["contact_length"], rel=0.02)
    # and the linear solid responds linearly to the shear (up to the small change of the contact)
    b2 = lin.solve(load, 2 * mu, b.copy(), lag=s_li)
    assert b2.info["deflection_dx"] == pytest.approx(2 * b.info["deflection_dx"], rel=1e-3)


@pytest.mark.parametrize("law", [FrictionLaw("coulomb"), FrictionLaw("package", tau0=0.02, alpha=0.1)])
def test_force_balance(law):
    """The clamped bottom carries exactly the friction force mu P and the load P, and the
    friction is the integral of the contact traction of the law."""
    solver = _solver(height=1.5, law=law)
    start = follow_load(solver, [0.05]).states[-1]
    ramp = follow_shear(solver, start, 0.6, check_stability=False)
    st = ramp.states[-1]
    u = solver.displacement(st.v)
    fint, _ = solver.solid.assemble(u)
    fold, _, _ = solver._fold(solver.positions(st.v), st.info.get("pairs"))
    bottom = solver.mesh.bottom
    # internal forces sum to zero (translation invariance), so the clamped nodes carry minus
    # the applied load: friction mu P along +x, the skin load P downward
    reaction = (fint + fold).reshape(-1, 2)[bottom].sum(axis=0)
    assert reaction[0] == pytest.approx(-st.shear * st.load, rel=1e-6)
    assert reaction[1] == pytest.approx(st.load, rel=1e-6)
    assert st.info["friction_force"] == pytest.approx(st.shear * st.load, rel=1e-9)
    assert st.f.sum() == pytest.approx(st.load, rel=1e-9)


@pytest.mark.slow
def test_mesh_convergence():
    out = {}
    for res in (6, 10):
        solver = _solver(height=1.5, resolution=res)
        start = follow_load(solver, [0.05]).states[-1]
        st = follow_shear(solver, start, 0.5, check_stability=False).states[-1]
        out[res] = (start.info["contact_length"], st.info["contact_length"], st.info["deflection_dx"])
    for a, b in zip(out[6], out[10]):
        assert a == pytest.approx(b, rel=0.04)


def test_stability_index_counts_negative_eigenvalues_and_flags_buckling():
    """A slender column (h = 3 r) is stable under a light skin load and unstable under a heavy
    one (Euler-type buckling under the normal load alone); the inertia count from one LDL^T
    equals the number of negative eigenvalues of the condensed tangent."""
    solver = _solver(height=3.0, resolution=3, skin=1.33)
    light, heavy = follow_load(solver, [0.02, 0.3]).states
    assert solver.min_eigenvalue(light) == 1.0
    index = solver.min_eigenvalue(heavy)
    assert index < 0
    eig = np.linalg.eigvalsh(solver.condensed_tangent(heavy).toarray())
    assert int(np.count_nonzero(eig < 0)) == -index
    assert np.all(np.linalg.eigvalsh(solver.condensed_tangent(light).toarray()) > 0)


def test_limit_cycle_of_the_newton_residuals():
    """A Newton iteration whose natural residuals come back every 1-4 iterations is caught (it
    fails at once instead of at max_iter); a converging or merely wandering one is not."""
    from fingerpad.micro.deflection.solve import CYCLE_RTOL, _limit_cycle

    two = [0.3, 0.1, 1.3e-3, 1.4e-4, 1.3e-3, 1.4e-4]
    assert _limit_cycle(two[:-1]) == 0  # one repeat is not yet a cycle
    assert _limit_cycle(two) == 2
    assert _limit_cycle([0.5, 2e-2, 3e-2, 4e-2, 2e-2, 3e-2, 4e-2]) == 3
    assert _limit_cycle([0.2, 7e-3, 7e-3 * (1 + 0.1 * CYCLE_RTOL), 7e-3]) == 1
    # the closest near-repeat seen in a solve that converged (1.6e-2) and a plain Newton descent
    assert _limit_cycle([0.2, 0.1, 0.2 * (1 + 1.6e-2), 0.1 * (1 - 1.6e-2)]) == 0
    assert _limit_cycle([1.0, 0.5, 0.2, 5e-2, 3e-3, 1e-5, 1e-10]) == 0


def test_stagnating_newton_residuals():
    """A late Newton iteration whose residual has not halved over STALL_WINDOW iterations is given
    up; an early one, or one still descending (even slowly, by halving), is not."""
    from fingerpad.micro.deflection.solve import STALL_AFTER, STALL_FACTOR, STALL_WINDOW, _stagnates

    wander = [0.14, 0.087, 0.077, 0.066] + [0.06 + 0.01 * (k % 3) for k in range(STALL_AFTER)]
    assert _stagnates(wander)
    assert not _stagnates(wander[:STALL_AFTER - 1])  # too early to judge
    halving = [0.5 * (0.99 * STALL_FACTOR ** (1 / STALL_WINDOW)) ** k for k in range(3 * STALL_AFTER)]
    assert not any(_stagnates(halving[:n]) for n in range(1, len(halving) + 1))
    # the first 14 residuals of a solve of issue 23's ramps that converged after 23 iterations
    late = [0.43, 0.52, 0.5, 0.38, 0.23, 0.22, 0.19, 0.18, 0.16, 0.14, 0.075, 0.064, 0.059, 0.057]
    assert not _stagnates(late)
