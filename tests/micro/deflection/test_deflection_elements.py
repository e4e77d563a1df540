"""Mesh, hyperelastic element and contact operators of the deflection model: exact checks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad.errors import FingerpadError
from fingerpad.micro.deflection.contact import contact_length, normal_gap, skin_compliance, tile_lengths
from fingerpad.micro.deflection.hyperelastic import Solid, isochoric, volumetric
from fingerpad.micro.deflection.mesh import SectionGeometry, build_mesh


@pytest.fixture(scope="module")
def mesh():
    return build_mesh(SectionGeometry("ellipse", 1.5, 3.0, 2.0), resolution=3)


def test_mesh_is_valid_and_mirror_symmetric(mesh):
    solid = Solid(mesh, 1.0, 10.0)  # raises on a non-positive Jacobian
    assert solid.ndof == 2 * mesh.n_nodes
    x = mesh.nodes
    # every node has a mirror image x -> -x
    mirrored = np.column_stack([-x[:, 0], x[:, 1]])
    d = np.min(np.hypot(*(mirrored[:, None, :] - x[None, :, :]).transpose(2, 0, 1)), axis=1)
    assert d.max() < 1e-12
    # surface runs from -lambda/2 to +lambda/2, passes the apex, profile nodes lie on the ellipse
    s = mesh.surface
    assert s.size % 2 == 1
    assert x[s[0], 0] == pytest.approx(-1.5) and x[s[-1], 0] == pytest.approx(1.5)
    assert mesh.apex in s and x[mesh.apex] == pytest.approx([0.0, 1.5])
    prof = x[s[mesh.on_asperity]]
    assert np.allclose(prof[:, 0] ** 2 + (prof[:, 1] / 1.5) ** 2, 1.0, atol=1e-6)
    # periodic pairs share z
    assert np.allclose(x[mesh.periodic[:, 0], 1], x[mesh.periodic[:, 1], 1])


def test_mesh_rejects_bad_geometry():
    with pytest.raises(FingerpadError):
        SectionGeometry("ellipse", 1.0, 1.5, 1.0)  # wider than its period
    with pytest.raises(FingerpadError):
        SectionGeometry("circular", 1.5, 3.0, 1.0)  # arc higher than half its chord
    with pytest.raises(FingerpadError):
        SectionGeometry("square", 1.0, 3.0, 1.0)


def _energy(f: np.ndarray, mu: float, kappa: float) -> float:
    j = np.linalg.det(f)
    i1 = np.sum(f * f) + 1.0
    return mu / 2 * (j ** (-2 / 3) * i1 - 3) + kappa / 4 * (j * j - 1 - 2 * math.log(j))


def test_stress_is_the_energy_gradient_and_tangent_its_hessian():
    f = np.array([[1.2, 0.3], [-0.1, 0.9]])
    p = isochoric(f, 0.7)[0] + volumetric(f, 5.0)[0]
    a = isochoric(f, 0.7)[1] + volumetric(f, 5.0)[1]
    h = 1e-6
    for i in range(2):
        for j in range(2):
            e = np.zeros((2, 2))
            e[i, j] = h
            assert (_energy(f + e, 0.7, 5.0) - _energy(f - e, 0.7, 5.0)) / (2 * h) == pytest.approx(p[i, j], rel=1e-7)
            dp = (isochoric(f + e, 0.7)[0] + volumetric(f + e, 5.0)[0]
                  - isochoric(f - e, 0.7)[0] - volumetric(f - e, 5.0)[0]) / (2 * h)
            assert np.allclose(dp, a[:, :, i, j], rtol=1e-6, atol=1e-8)


def test_small_strain_limit_is_linear_elasticity():
    mu, kappa = 0.4, 3.0
    a = isochoric(np.eye(2), mu)[1] + volumetric(np.eye(2), kappa)[1]
    lam = kappa - 2 * mu / 3
    d = np.eye(2)
    c = lam * np.einsum("ij,kl->ijkl", d, d) + mu * (np.einsum("ik,jl->ijkl", d, d) + np.einsum("il,jk->ijkl", d, d))
    assert np.allclose(a, c)


def test_assembled_tangent_and_objectivity(mesh):
    solid = Solid(mesh, 1.0, 30.0)
    x0 = mesh.nodes
    u = np.column_stack([0.2 * np.sin(x0[:, 1]) * x0[:, 0], 0.1 * x0[:, 0] ** 2 - 0.05 * x0[:, 1]]).ravel()
    f, k = solid.assemble(u)
    du = 1e-6 * np.random.default_rng(1).standard_normal(u.size)
    fd = (solid.assemble(u + du, False)[0] - solid.assemble(u - du, False)[0]) / 2
    assert np.linalg.norm(fd - k @ du) < 1e-7 * np.linalg.norm(k @ du)
    assert abs(k - k.T).max() < 1e-10 * abs(k).max()
    th = 0.4  # a rigid rotation stores no energy: no force
    rot = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
    assert np.abs(solid.assemble((x0 @ rot.T - x0).ravel(), False)[0]).max() < 1e-12


def test_skin_compliance_matches_the_fourier_series():
    period, modulus = 4.0, 2.0
    x = np.array([-1.0, 0.3, 1.1])
    tiles = np.array([0.05, 0.08, 0.03])
    c = skin_compliance(x, tiles, period, modulus)
    # lift at x_i from a uniform load on tile j: sum over modes 2 p_k / (E* |k|), p_k of a box
    n = np.arange(1, 200000)
    k = 2 * math.pi * n / period
    for i in range(3):
        for j in range(3):
            if i == j:
                continue
            box = np.sinc(k * tiles[j] / 2 / math.pi)  # Fourier coefficient of a unit-area box
            series = np.sum(2 * (2 / period) * box * np.cos(k * (x[i] - x[j])) / (modulus * k))
            assert c[i, j] == pytest.approx(series, rel=1e-4)
    # derivative against finite differences
    _, dc = skin_compliance(x, tiles, period, modulus, derivative=True)
    h = 1e-6
    xp, xm = x.copy(), x.copy()
    xp[1] += h
    xm[1] -= h
    fd = (skin_compliance(xp, tiles, period, modulus) - skin_compliance(xm, tiles, period, modulus)) / (2 * h)
    assert np.allclose(fd[1, [0, 2]], dc[1, [0, 2]], rtol=1e-6)


def test_tiles_cover_the_surface_and_integrate_uniform_pressure():
    xs = np.column_stack([np.linspace(0, 2, 9), np.zeros(9)])
    t = tile_lengths(xs)
    assert t.sum() == pytest.approx(2.0)
    assert t[1] == pytest.approx(4 * t[0])  # Simpson: mid-side 2/3, corner 1/6 per face


def test_normal_gap_derivatives():
    v = np.array([0.3, 0.01, 0.1, 0.02, 0.6, -0.15])
    g, grad, hess = normal_gap(v[None, 0:2], v[None, 2:4], v[None, 4:6])
    d, r = v[4:6] - v[2:4], v[0:2] - v[2:4]
    assert g[0] == pytest.approx((d[0] * r[1] - d[1] * r[0]) / np.hypot(*d))
    h = 1e-6
    for i in range(6):
        e = np.zeros(6)
        e[i] = h
        gp = normal_gap((v + e)[None, 0:2], (v + e)[None, 2:4], (v + e)[None, 4:6])
        gm = normal_gap((v - e)[None, 0:2], (v - e)[None, 2:4], (v - e)[None, 4:6])
        assert (gp[0][0] - gm[0][0]) / (2 * h) == pytest.approx(grad[0, i], abs=1e-8)
        assert np.allclose((gp[1][0] - gm[1][0]) / (2 * h), hess[0, i], atol=1e-7)


def test_contact_length_recovers_a_hertz_edge_between_nodes():
    b = 0.437  # half-width, deliberately between nodes
    x = np.linspace(-1, 1, 41)
    xs = np.column_stack([x, np.zeros_like(x)])
    inside = np.abs(x) < b
    p = np.where(inside, np.sqrt(np.clip(1 - (x / b) ** 2, 0, None)), 0.0)
    u = np.abs(x) / b
    gap = np.where(inside, 0.0, u * np.sqrt(np.clip(u * u - 1, 0, None)) - np.arccosh(np.maximum(u, 1.0)))
    indicator = np.where(inside, p, -gap)
    arc, proj = contact_length(xs, indicator, p, gap)
    assert arc == pytest.approx(2 * b, rel=0.01)
    assert proj == pytest.approx(arc)
    lin, _ = contact_length(xs, indicator)
    assert abs(arc - 2 * b) < abs(lin - 2 * b)  # the edge asymptotics beat linear interpolation


def _folded_flat():
    """A section whose right flank is laid flat on the right base, slightly into it, and on past
    the period edge over the neighbouring cell's base (positions only, no equilibrium)."""
    from fingerpad.micro.deflection.solve import SectionSolver

    mesh = build_mesh(SectionGeometry("ellipse", 2.0, 5.0, 2.0), resolution=3)
    solver = SectionSolver(mesh, 0.45, 1.0, fold_penalty=20.0)
    x = mesh.nodes.copy()
    flank = mesh.surface[mesh.on_asperity][::-1]  # from the right foot up to the left foot
    xf = x[flank]
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(xf, axis=0).T))])
    right = s < 0.5 * s[-1]  # the right flank
    foot = x[flank[0]]
    x[flank[right], 0] = foot[0] + s[right]
    x[flank[right], 1] = -0.004 * (1.0 + 0.5 * np.sin(7.0 * s[right]))
    return mesh, solver, x


def test_fold_contact_gauss_points_derivatives():
    mesh, solver, x = _folded_flat()
    fold = solver.fold
    pairs = fold.pair(x)

    def energy(xx):
        _, terms, _, _ = fold.evaluate(xx, pairs)
        return sum(0.5 * fold.k * float(np.sum(w * g**2)) for _, _, g, _, w in terms)

    force, stiff, n_act = solver._fold(x, pairs)
    assert n_act > 10
    rng = np.random.default_rng(3)
    dx = rng.standard_normal(x.shape) * 1e-6
    assert (energy(x + dx) - energy(x - dx)) / 2 == pytest.approx(force @ dx.ravel(), rel=1e-6)
    fp, _, _ = solver._fold(x + dx, pairs)
    fm, _, _ = solver._fold(x - dx, pairs)
    assert np.linalg.norm((fp - fm) / 2 - stiff @ dx.ravel()) < 1e-6 * np.linalg.norm(stiff @ dx.ravel())
    # a face's three Gauss weights add up to its length over the node spacing (two nodes' worth)
    assert fold.weights.sum() == pytest.approx(2.0 * (fold.point_nodes.shape[0] // 3), rel=0.02)


def test_fold_contact_reaches_over_the_period_edge():
    mesh, solver, x = _folded_flat()
    fold = solver.fold
    edge = mesh.geometry.period / 2
    pts = fold.points(x)
    beyond = pts[:, 0] > edge + 0.05
    assert np.any(beyond)
    right_chain = fold.pair(x)[0]
    nodes, shift = fold.chains[0]
    # points past the edge lie on the left base's periodic image, and penetrate it
    assert np.all(right_chain[beyond] >= 0)
    seg_end = right_chain[beyond] + 1  # the segment's far end
    assert np.all(shift[seg_end] == pytest.approx(mesh.geometry.period))
    assert set(nodes[seg_end]) <= set(mesh.left_base)
    gaps, _, _, min_gap = fold.evaluate(x)
    assert min_gap < -0.003 and min_gap > -0.007
