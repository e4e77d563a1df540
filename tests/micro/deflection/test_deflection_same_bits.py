"""The deflection solver's shortcuts give the numbers of the long way, to the bit (issue 31: a
speed-up never buys a different answer).

Each shortcut skips work whose result the caller does not use (the fold contact's Hessians in a
line search's merit, einsum's general loop for an outer product, a stiffness assembled again at
a converged state); what it does return must be the same floats, so these compare with
``np.array_equal``, not a tolerance."""

from __future__ import annotations

import numpy as np

from fingerpad.micro.deflection.contact import normal_gap, segment_gap, tile_jacobian
from fingerpad.micro.deflection.hyperelastic import Solid, _outer, _outer_swapped, isochoric, volumetric
from fingerpad.micro.deflection.mesh import SectionGeometry, build_mesh
from fingerpad.micro.deflection.solve import SectionSolver


def _folded():
    """A section whose right flank is laid flat on (and slightly into) the base, so that many
    fold-contact points are active, some past their segment's ends."""
    mesh = build_mesh(SectionGeometry("ellipse", 2.0, 5.0, 2.0), resolution=3)
    solver = SectionSolver(mesh, 0.45, 1.0, fold_penalty=20.0)
    x = mesh.nodes.copy()
    flank = mesh.surface[mesh.on_asperity][::-1]
    xf = x[flank]
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(xf, axis=0).T))])
    right = s < 0.5 * s[-1]
    foot = x[flank[0]]
    x[flank[right], 0] = foot[0] + s[right]
    x[flank[right], 1] = -0.004 * (1.0 + 0.5 * np.sin(7.0 * s[right]))
    return mesh, solver, x


def test_gaps_without_hessian_are_the_same_bits():
    rng = np.random.default_rng(5)
    s, p, q = (rng.standard_normal((200, 2)) for _ in range(3))
    for fn in (normal_gap, segment_gap):
        g, grad, hess = fn(s, p, q)
        g2, grad2, none = fn(s, p, q, hessian=False)
        assert none is None and hess.shape == (200, 6, 6)
        assert np.array_equal(g, g2) and np.array_equal(grad, grad2)
    # points past both ends of their segments took the end-point branch
    t = np.einsum("ni,ni->n", s - p, q - p) / np.einsum("ni,ni->n", q - p, q - p)
    assert np.any(t < 0) and np.any(t > 1)


def test_fold_force_without_tangent_is_the_same_bits():
    _, solver, x = _folded()
    pairs = solver.fold.pair(x)
    gaps, terms, n_act, min_gap = solver.fold.evaluate(x, pairs)
    gaps2, terms2, n_act2, min_gap2 = solver.fold.evaluate(x, pairs, tangent=False)
    assert n_act == n_act2 > 10 and min_gap == min_gap2 and np.array_equal(gaps, gaps2)
    for (d, gr, g, he, w), (d2, gr2, g2, he2, w2) in zip(terms, terms2, strict=True):
        assert he is not None and he2 is None
        assert all(np.array_equal(a, b) for a, b in ((d, d2), (gr, gr2), (g, g2), (w, w2)))
    force, stiff, _ = solver._fold(x, pairs)
    force2, none, _ = solver._fold(x, pairs, tangent=False)
    assert none is None and stiff.nnz > 0 and np.array_equal(force, force2)


def test_outer_products_are_einsums_bits():
    rng = np.random.default_rng(7)
    f, h = rng.standard_normal((2, 40, 9, 2, 2))
    assert np.array_equal(_outer(f, h), np.einsum("...ij,...kl->...ijkl", f, h))
    assert np.array_equal(_outer_swapped(h), np.einsum("...il,...kj->...ijkl", h, h))
    # and the material tangents built from them are still the derivative of the stress
    fm = np.eye(2) + 0.2 * rng.standard_normal((5, 2, 2))
    for law, modulus in ((isochoric, 1.0), (volumetric, 30.0)):
        _, a = law(fm, modulus)
        d = 1e-7 * rng.standard_normal((5, 2, 2))
        fd = (law(fm + d, modulus, tangent=False)[0] - law(fm - d, modulus, tangent=False)[0]) / 2
        assert np.allclose(np.einsum("nijkl,nkl->nij", a, d), fd, rtol=1e-6, atol=1e-12)


def test_tile_jacobian_weights_once_per_count():
    _, solver, x = _folded()
    xs = x[solver.surface]
    tj = tile_jacobian(xs)
    assert np.array_equal(tj, tile_jacobian(xs.copy()))  # the cached weights are not modified
    d = 1e-7 * np.random.default_rng(2).standard_normal(xs.shape)
    from fingerpad.micro.deflection.contact import tile_lengths

    fd = (tile_lengths(xs + d) - tile_lengths(xs - d)) / 2
    assert np.allclose(np.einsum("inc,nc->i", tj, d), fd, rtol=1e-6, atol=1e-13)


def test_stiffness_memo_is_the_assembled_one():
    mesh, _, _ = _folded()
    solid = Solid(mesh, 0.35, 3.0)
    u = 0.002 * np.random.default_rng(4).standard_normal(solid.ndof)
    assert solid.min_jacobian(u) > 0
    f1, k1 = solid.assemble(u)
    f2, k2 = solid.assemble(u)  # from the memo
    fresh = Solid(mesh, 0.35, 3.0)
    f3, k3 = fresh.assemble(u)
    assert np.array_equal(f1, f2) and np.array_equal(f1, f3)
    assert np.array_equal(k1.data, k2.data) and np.array_equal(k2.data, k3.data)
    k2.data[:] = 0.0  # a caller's change does not reach the memo
    assert np.array_equal(solid.assemble(u)[1].data, k1.data)


def _bits(a: np.ndarray) -> np.ndarray:
    """The float64 words as integers: -0.0 and 0.0 differ, NaNs compare by payload."""
    return np.ascontiguousarray(a, dtype=np.float64).view(np.int64)


def _one_expression_tangents(f: np.ndarray, mu: float, kappa: float) -> tuple[np.ndarray, np.ndarray]:
    """The material tangents as the single expressions they were before the in-place
    arithmetic (the reference the solver's numbers were made with)."""
    det = f[..., 0, 0] * f[..., 1, 1] - f[..., 0, 1] * f[..., 1, 0]
    h = np.empty_like(f)
    h[..., 0, 0], h[..., 1, 1] = f[..., 1, 1] / det, f[..., 0, 0] / det
    h[..., 0, 1], h[..., 1, 0] = -f[..., 1, 0] / det, -f[..., 0, 1] / det
    i1 = np.einsum("...ij,...ij->...", f, f) + 1.0
    c = mu * det ** (-2.0 / 3.0)
    fh, hh, hs = _outer(f, h), _outer(h, h), _outer_swapped(h)
    i1_ = i1[..., None, None, None, None]
    delta = np.einsum("ik,jl->ijkl", np.eye(2), np.eye(2))
    iso = c[..., None, None, None, None] * (
        delta - 2.0 / 3.0 * (fh + np.swapaxes(np.swapaxes(fh, -4, -2), -3, -1))
        + 2.0 / 9.0 * i1_ * hh + i1_ / 3.0 * hs
    )
    d1 = 0.5 * kappa * (det - 1.0 / det)
    d2 = 0.5 * kappa * (1.0 + 1.0 / det**2)
    vol = (d2 * det**2 + d1 * det)[..., None, None, None, None] * hh - (d1 * det)[..., None, None, None, None] * hs
    return iso, vol


def test_in_place_tangents_are_the_expressions_bits():
    rng = np.random.default_rng(11)
    for shape in ((348, 9), (60, 4), (3,)):
        f = np.eye(2) + 0.15 * rng.standard_normal(shape + (2, 2))
        assert np.all(np.linalg.det(f) > 0.2)  # no inverted point
        iso, vol = _one_expression_tangents(f, 0.7, 40.0)
        for law, modulus, ref in ((isochoric, 0.7, iso), (volumetric, 40.0, vol)):
            p, a = law(f, modulus)
            none, a2 = law(f, modulus, stress=False)
            assert none is None and np.array_equal(_bits(a), _bits(ref)) and np.array_equal(_bits(a2), _bits(ref))
            assert a.flags.c_contiguous  # the stacked matmul then takes the path it took
            assert np.array_equal(_bits(p), _bits(law(f, modulus, tangent=False)[0]))


def test_stiffness_after_a_merit_is_the_fresh_one():
    """A line search's merit leaves the internal force in the memo; the tangent assembled next
    (stress skipped) is the one a fresh solid assembles."""
    mesh, _, _ = _folded()
    u = 0.002 * np.random.default_rng(6).standard_normal(2 * mesh.n_nodes)
    solid = Solid(mesh, 0.35, 3.0)
    f1, none = solid.assemble(u, tangent=False)
    f2, k2 = solid.assemble(u)
    f3, k3 = Solid(mesh, 0.35, 3.0).assemble(u)
    assert none is None and np.array_equal(_bits(f1), _bits(f3)) and np.array_equal(_bits(f2), _bits(f3))
    assert np.array_equal(_bits(k2.data), _bits(k3.data)) and np.array_equal(k2.indices, k3.indices)


def test_summed_is_the_sparse_constructors_bits():
    """Repeated entries of widely different sizes (their sum's last bit depends on the order), in
    columns long enough that SciPy's sort is not an insertion sort: the same matrix to the bit."""
    import scipy.sparse as sp

    from fingerpad.micro.deflection.hyperelastic import summed

    rng = np.random.default_rng(12)
    n = 40
    rows = np.concatenate([rng.integers(0, n, 3000), np.full(200, 7), np.repeat(np.arange(n), 5)])
    cols = np.concatenate([rng.integers(0, 8, 3000), np.full(200, 3), np.repeat(np.arange(n), 5)])
    vals = rng.choice([-1.0, 1.0], rows.size) * 10.0 ** rng.uniform(-8, 8, rows.size)
    vals[::17] = -0.0
    for fmt, cls in (("csc", sp.csc_matrix), ("csr", sp.csr_matrix)):
        ref = cls((vals, (rows, cols)), shape=(n, n))
        got = summed(vals, rows, cols, (n, n), fmt)
        assert got.format == fmt and got.has_canonical_format
        assert np.array_equal(got.indptr, ref.indptr) and np.array_equal(got.indices, ref.indices)
        assert np.array_equal(_bits(got.data), _bits(ref.data))


def test_reduction_maps_are_the_sparse_products_bits():
    _, solver, _ = _folded()
    rng = np.random.default_rng(13)
    v = rng.standard_normal(solver.nred)
    v[::7] = -0.0  # SciPy's product turns -0.0 into 0.0 (0.0 + 1.0 * v)
    r = rng.standard_normal(solver.solid.ndof) * 10.0 ** rng.uniform(-8, 8, solver.solid.ndof)
    r[::5] = -0.0
    assert np.array_equal(_bits(solver.displacement(v)), _bits(solver.M @ v))
    assert np.array_equal(_bits(solver.reduce(r)), _bits(solver.MT @ r))


def test_fold_chain_rule_is_the_one_built_per_call():
    """The per-point map T onto (s, p, q), built once, holds the entries the per-call loop built."""
    _, solver, _ = _folded()
    fold = solver.fold
    na = fold.point_nodes.shape[1]
    pts = np.arange(fold.point_nodes.shape[0])
    t = np.zeros((pts.size, 6, 2 * (na + 2)))
    for j in range(na):
        t[:, 0:2, 2 * j:2 * j + 2] = fold.point_shape[pts, j][:, None, None] * np.eye(2)
    t[:, 2:4, 2 * na:2 * na + 2] = np.eye(2)
    t[:, 4:6, 2 * na + 2:2 * na + 4] = np.eye(2)
    assert np.array_equal(_bits(fold._chain_rule), _bits(t))
