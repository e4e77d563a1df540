"""The elastic operators against exact solutions: a cosine pressure on a periodic half-space, a
uniform pressure on a rectangle (Love 1929), stiffness as the inverse of compliance, Parseval."""

from __future__ import annotations

import math

import numpy as np
import pytest

import fingerpad as fp
from fingerpad.contact import greens

E = 2e6  # reduced modulus, Pa


def backend():
    return greens.Backend()


def periodic(nx=32, ny=16, lx=1e-4, ly=5e-5):
    return fp.Texture(np.zeros((nx, ny)), (lx, ly), periodic=True)


def test_cosine_pressure_gives_the_westergaard_displacement():
    """u = 2 p cos(q x) / (E* q) for p cos(q x) on a half-space (Johnson, Contact Mechanics 13.2)."""
    tex = periodic()
    x, y = tex.coordinates()
    X, _ = np.meshgrid(x, y, indexing="ij")
    for k in (1, 3):
        q = 2 * math.pi * k / tex.size[0]
        p = 1e3 * np.cos(q * X)
        u = greens.compliance_operator(backend(), tex, E)(p)
        np.testing.assert_allclose(u, 2 * p / (E * q), rtol=0, atol=1e-12 * 2e3 / (E * q))


def test_mean_pressure_gives_no_periodic_displacement():
    tex = periodic()
    u = greens.compliance_operator(backend(), tex, E)(np.full(tex.shape, 5e3))
    assert np.max(np.abs(u)) < 1e-20


def test_stiffness_inverts_compliance_without_the_mean():
    tex = periodic()
    rng = np.random.default_rng(0)
    p = rng.standard_normal(tex.shape)
    p -= p.mean()
    c = greens.compliance_operator(backend(), tex, E)
    s = greens.stiffness_operator(backend(), tex, E)
    np.testing.assert_allclose(s(c(p)), p, atol=1e-12 * np.abs(p).max())


def test_operator_is_symmetric_and_positive_and_parseval_holds():
    tex = periodic()
    rng = np.random.default_rng(1)
    a, b = rng.standard_normal(tex.shape), rng.standard_normal(tex.shape)
    c = greens.compliance_operator(backend(), tex, E)
    assert float(np.sum(a * c(b))) == pytest.approx(float(np.sum(b * c(a))), rel=1e-12)
    assert float(np.sum(a * c(a))) > 0
    # t.A t from the spectrum equals the direct sum
    assert c.quad(c.forward(a)) == pytest.approx(float(np.sum(a * c(a))), rel=1e-12)
    assert c.quad_low(a) == pytest.approx(float(np.sum(a * c(a))), rel=1e-4)


def test_wavenumbers():
    q = greens.wavenumbers((4, 6), (0.5, 0.25))
    assert q.shape == (4, 4)  # rfft half spectrum along y
    assert q[0, 0] == 0.0
    assert q[1, 0] == pytest.approx(2 * math.pi / 2.0)  # first x mode of a 2 m cell
    assert q[0, 1] == pytest.approx(2 * math.pi / 1.5)


def test_love_rectangle_centre_value():
    """Centre of a 2a x 2b rectangle: 2 [a asinh(b/a) + b asinh(a/b)]."""
    a, b = 1.0, 2.0
    got = greens.love_rectangle(np.array([0.0]), np.array([0.0]), a, b)[0]
    assert got == pytest.approx(4 * (a * math.asinh(b / a) + b * math.asinh(a / b)), rel=1e-14)
    # far away it is area / distance
    far = greens.love_rectangle(np.array([1e4]), np.array([0.0]), a, b)[0]
    assert far == pytest.approx(4 * a * b / 1e4, rel=1e-6)


def test_finite_body_uniform_square_is_love_s_solution():
    """Uniform pressure p on a square patch of a half-space: at every pixel centre the deflection
    is Love's closed form p / (pi E*) * I(x, y), I the integral of 1/r over the square. The pixel
    kernels are exact integrals over each pixel, so their sum is exact to round-off."""
    n, side, p = 16, 1e-4, 1e3
    tex = fp.Texture(np.zeros((n, n)), (side, side), periodic=False)
    u = greens.compliance_operator(backend(), tex, E)(np.full((n, n), p))
    a = side / 2
    centres = (np.arange(n) + 0.5) * side / n - a  # pixel centres about the square's centre
    X, Y = np.meshgrid(centres, centres, indexing="ij")
    exact = p / (math.pi * E) * greens.love_rectangle(X, Y, a, a)
    np.testing.assert_allclose(u, exact, rtol=1e-10)
    # and the centre of the square (Love): (8 / pi) asinh(1) p a / E*, the corner half of it
    centre = 8 / math.pi * math.asinh(1.0) * p * a / E
    assert p / (math.pi * E) * greens.love_rectangle(np.array([0.0]), np.array([0.0]), a, a)[0] == \
        pytest.approx(centre, rel=1e-14)
    corner = p / (math.pi * E) * greens.love_rectangle(np.array([a]), np.array([a]), a, a)[0]
    assert corner == pytest.approx(centre / 2, rel=1e-14)
    assert u.max() < centre and u.min() > corner


def test_preconditioners_are_positive():
    tex = periodic()
    for form in ("primal", "dual"):
        op = greens.preconditioner(backend(), tex, E, form)
        assert np.all(np.real(op._host_multiplier) > 0), form
