"""Validation of the layered skin (issue 24): the compliance factor, its operators and solves.

The independent check of the closed form is a plane-strain finite-element model of the layered
strip under a sinusoidal pressure ``p cos(k x)``, written here: for one Fourier mode the
displacements are exactly ``u_x = U(z) sin(k x)``, ``u_z = W(z) cos(k x)`` (the strip is
periodic, the load a single harmonic), so the finite elements discretise only the depth:
quadratic Lagrange elements in z for U and W, the strain energy of plane-strain Hooke's law
averaged over one wavelength, the substrate truncated at 40 wavelengths / 2 pi below the layer
(e^-40 of the field left) and clamped there. It shares nothing with the closed form but the
elasticity equations.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad.contact import HalfSpaceSolver, Layer
from fingerpad.contact.greens import Backend, compliance_operator, love_rectangle, preconditioner, remainder_kernel, \
    smoothed_rectangle, stiffness_operator, wavenumbers
from fingerpad.contact.layered import layer_factor, spectral_factor
from fingerpad.errors import FingerpadError
from fingerpad.textures import Texture

E1, NU1 = 1.0e6, 0.3
E2, NU2 = 0.1e6, 0.45
T = 20e-6


def reduced(e: float, nu: float) -> float:
    return e / (1 - nu**2)


# ------------------------------------------------------------------- finite elements in depth


def fe_compliance(k: float, layer: Layer, per_layer: int = 24, substrate: int = 60) -> float:
    """Surface deflection / pressure amplitude of the layered strip, by finite elements in z."""
    t = layer.thickness
    z_nodes = list(np.linspace(0.0, t, 2 * per_layer + 1))
    mats = [(layer.modulus, layer.poisson)] * per_layer
    if not layer.rigid_base:
        # geometric grading from a layer-sized first element to the truncation depth
        depth = 40.0 / k
        h0 = min(t / per_layer, 0.05 / k)
        edges = t + np.concatenate([[0.0], np.geomspace(h0, depth, substrate)])
        for a, b in zip(edges[:-1], edges[1:]):
            z_nodes += [0.5 * (a + b), b]
        mats += [(layer.substrate_modulus, layer.substrate_poisson)] * substrate
    z = np.array(z_nodes)
    n = len(z)
    K = np.zeros((2 * n, 2 * n))  # dofs: U_i at 2i, W_i at 2i + 1
    gp, gw = np.polynomial.legendre.leggauss(4)
    for e, (E, nu) in enumerate(mats):
        lam = E * nu / ((1 + nu) * (1 - 2 * nu))
        mu = E / (2 * (1 + nu))
        za, zb = z[2 * e], z[2 * e + 2]
        jac = (zb - za) / 2
        idx = np.array([[2 * (2 * e + a), 2 * (2 * e + a) + 1] for a in range(3)]).ravel()
        ke = np.zeros((6, 6))
        for s, w in zip(gp, gw):
            N = np.array([s * (s - 1) / 2, 1 - s * s, s * (s + 1) / 2])
            dN = np.array([s - 0.5, -2 * s, s + 0.5]) / jac
            # strain amplitudes as rows over (U1, W1, U2, W2, U3, W3):
            # eps_xx = k U, eps_zz = W', gamma_xz = U' - k W
            exx = np.zeros(6); ezz = np.zeros(6); gxz = np.zeros(6)
            exx[0::2] = k * N
            ezz[1::2] = dN
            gxz[0::2] = dN
            gxz[1::2] = -k * N
            ke += w * jac * ((lam + 2 * mu) * (np.outer(exx, exx) + np.outer(ezz, ezz))
                             + lam * (np.outer(exx, ezz) + np.outer(ezz, exx)) + mu * np.outer(gxz, gxz))
        K[np.ix_(idx, idx)] += ke
    f = np.zeros(2 * n)
    f[1] = 1.0  # unit pressure amplitude on W(0) (the 1/2 of the wavelength average cancels)
    if layer.rigid_base and layer.base == "frictionless":
        fixed = [2 * (n - 1) + 1]
    else:
        fixed = [2 * (n - 1), 2 * (n - 1) + 1]
    free = np.setdiff1d(np.arange(2 * n), fixed)
    u = np.linalg.solve(K[np.ix_(free, free)], f[free])
    return float(u[list(free).index(1)])


CASES = {
    "stiff on soft": Layer(T, E1, NU1, E2, NU2),
    "soft on stiff": Layer(T, E2, NU2, E1, NU1),
    "very stiff on soft": Layer(T, 100 * E1, 0.4, E2, 0.45),
    "rigid base, bonded": Layer(T, E1, 0.45),
    "rigid base, frictionless": Layer(T, E1, NU1, math.inf, NU1, base="frictionless"),
}


@pytest.mark.parametrize("case", list(CASES))
def test_compliance_matches_finite_elements(case: str) -> None:
    """The closed-form compliance agrees with the FE strip to < 0.01 % from |k|t = 0.05 to 5
    (measured: 2e-5 at most, the FE's own discretisation error)."""
    layer = CASES[case]
    for kt in (0.05, 0.3, 1.0, 5.0):
        k = kt / layer.thickness
        closed = float(layer.compliance(k))
        fe = fe_compliance(k, layer)
        assert abs(fe / closed - 1) < 1e-4, (kt, fe / closed)


def test_finite_elements_check_can_fail() -> None:
    """The FE strip tells layered bodies apart: a layer of half the thickness is off by > 5 %."""
    layer = CASES["stiff on soft"]
    k = 1.0 / T
    thinner = Layer(T / 2, E1, NU1, E2, NU2)
    assert abs(fe_compliance(k, thinner) / float(layer.compliance(k)) - 1) > 0.05


# ------------------------------------------------------------------------------------ limits


@pytest.mark.parametrize("case", ["stiff on soft", "soft on stiff", "very stiff on soft"])
def test_thick_layer_is_the_layers_half_space_thin_one_the_substrates(case: str) -> None:
    layer = CASES[case]
    e1s, e2s = reduced(layer.modulus, layer.poisson), reduced(layer.substrate_modulus, layer.substrate_poisson)
    k = 1e4
    for t, modulus in ((1e3, e1s), (1e-12, e2s)):
        thick = Layer(t, layer.modulus, layer.poisson, layer.substrate_modulus, layer.substrate_poisson)
        assert abs(float(thick.compliance(k)) * modulus * k / 2 - 1) < 1e-6
    # and monotonically in between (no spurious resonance of the closed form)
    K = layer_factor(np.logspace(-6, 1.2, 400), layer)  # beyond, K = 1 to rounding
    assert np.all(np.diff(K) < 0) if e1s > e2s else np.all(np.diff(K) > 0)


def test_rigid_base_thin_layer_limits() -> None:
    """A thin layer on a rigid base compresses in uniaxial strain (bonded) or with free lateral
    expansion (frictionless, plane strain); a thick one is the layer's half-space."""
    t, k = 1e-9, 1e3
    for nu in (0.3, 0.45, 0.5):
        bonded = Layer(t, E1, nu)
        uniaxial = t * (1 + nu) * (1 - 2 * nu) / (E1 * (1 - nu))
        if nu < 0.5:
            assert abs(float(bonded.compliance(k)) / uniaxial - 1) < 1e-5
        else:  # incompressible: the compliance vanishes like (k t)^3 / k (no cancellation)
            assert 0 < float(bonded.compliance(k)) < 1e-15 * t
        slid = Layer(t, E1, nu, math.inf, nu, base="frictionless")
        assert abs(float(slid.compliance(k)) / (t * (1 - nu**2) / E1) - 1) < 1e-5
        for lay in (bonded, slid):
            assert abs(float(lay.factor(60.0)) - 1) < 1e-12


def test_incompressible_layer_on_rigid_base_is_the_classical_formula() -> None:
    x = np.array([1e-3, 0.1, 1.0, 4.0])
    classical = (np.sinh(2 * x) - 2 * x) / (np.cosh(2 * x) + 1 + 2 * x**2)
    np.testing.assert_allclose(layer_factor(x, Layer(T, E1, 0.5)), classical, rtol=1e-9)


def test_stiff_plate_on_soft_foundation_bends() -> None:
    """Very stiff, thin layer: long waves see a plate of bending stiffness E1* t^3/12 on the
    soft half-space, k^4 D + E2* k / 2 in stiffness."""
    layer = Layer(T, 1e4 * E1, 0.3, E2, 0.45)
    e1s, e2s = reduced(layer.modulus, 0.3), reduced(E2, 0.45)
    for kt in (1e-3, 3e-3):
        k = kt / T
        plate = 1.0 / (e1s * T**3 * k**4 / 12 + e2s * k / 2)
        assert abs(float(layer.compliance(k)) / plate - 1) < 0.02


def test_equal_moduli_are_the_homogeneous_half_space_at_every_wavenumber() -> None:
    x = np.concatenate([[0.0], np.logspace(-8, 3, 200)])
    for nu in (-0.5, 0.0, 0.3, 0.49, 0.5):
        np.testing.assert_allclose(layer_factor(x, Layer(T, E1, nu, E1, nu)), 1.0, rtol=0, atol=1e-14)
    # and the operators then reproduce the homogeneous ones (periodic and padded)
    layer = Layer(T, E1, 0.3, E1, 0.3)
    e = reduced(E1, 0.3)
    be = Backend()
    for periodic in (True, False):
        tex = Texture(np.zeros((32, 24)), (1e-4, 0.8e-4), periodic=periodic)
        a = compliance_operator(be, tex, e)._host_multiplier
        b = compliance_operator(be, tex, e, layer)._host_multiplier
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-13 * np.max(np.abs(a)))


def test_no_layer_is_bit_identical_to_the_half_space_kernel() -> None:
    tex = Texture(np.zeros((16, 12)), (1e-4, 1e-4))
    q = wavenumbers(tex.shape, tex.spacing)
    be = Backend()
    with np.errstate(divide="ignore"):
        assert np.array_equal(compliance_operator(be, tex, E1)._host_multiplier, np.where(q > 0, 2.0 / (E1 * q), 0.0))
    assert np.array_equal(stiffness_operator(be, tex, E1)._host_multiplier, E1 * q / 2.0)
    assert spectral_factor(None, q, E1) is None


def test_smoothed_rectangle_is_the_pixel_integral() -> None:
    from scipy import integrate  # noqa: PLC0415

    for x, y, c in ((0.3, 0.1, 0.2), (2.0, -1.0, 0.5), (0.0, 0.0, 0.05), (-0.7, 0.45, 1.5)):
        quad = integrate.dblquad(lambda yy, xx: 1 / math.sqrt((x - xx) ** 2 + (y - yy) ** 2 + c * c),
                                 -0.5, 0.5, -0.4, 0.4, epsabs=1e-12, epsrel=1e-12)[0]
        assert abs(float(smoothed_rectangle(np.array(x), np.array(y), 0.5, 0.4, c)) / quad - 1) < 1e-9
    X, Y = np.meshgrid(np.linspace(-2, 2, 9), np.linspace(-2, 2, 7), indexing="ij")
    np.testing.assert_allclose(smoothed_rectangle(X, Y, 0.5, 0.4, 0.0), love_rectangle(X, Y, 0.5, 0.4), rtol=1e-13)


def test_layer_checks() -> None:
    with pytest.raises(FingerpadError, match="thickness"):
        Layer(0.0, E1)
    with pytest.raises(FingerpadError, match="substrate modulus"):
        Layer(T, E1, 0.3, -1.0)
    with pytest.raises(FingerpadError, match="frictionless"):
        Layer(T, E1, 0.3, E2, 0.3, base="frictionless")
    with pytest.raises(FingerpadError, match="base"):
        Layer(T, E1, base="glued")
    tex = Texture(np.zeros((8, 8)), (1e-4, 1e-4))
    with pytest.raises(FingerpadError, match="exceeds the layer"):
        HalfSpaceSolver(tex, 2 * E1, layer=Layer(T, E1, 0.3, E2, 0.45))
    with pytest.raises(FingerpadError, match="Layer"):
        HalfSpaceSolver(tex, E1, layer=(T, E1))  # type: ignore[arg-type]


# --------------------------------------------------------------------- Westergaard generalised


def sinusoid(n: int, lam: float, h: float) -> Texture:
    x = np.arange(n) * lam / n
    return Texture(np.repeat((h * np.cos(2 * np.pi * x / lam))[:, None], 4, axis=1), (lam, 4 * lam / n))


@pytest.mark.parametrize("case", list(CASES))
def test_westergaard_generalised(case: str) -> None:
    """A sinusoid h cos(kx) is in full contact from p* = h / C(k) on, with the pressure
    p_mean + p* cos(kx) there, for |k| t from 0.1 to 10 (C the layered compliance)."""
    base = CASES[case]
    n, lam, h = 64, 1e-4, 1e-6
    k = 2 * np.pi / lam
    tex = sinusoid(n, lam, h)
    for kt in (0.1, 1.0, 10.0):
        layer = Layer(kt / k, base.modulus, base.poisson, base.substrate_modulus, base.substrate_poisson, base.base)
        solver = HalfSpaceSolver(tex, layer.reduced_modulus, layer=layer)
        p_star = h / float(layer.compliance(k))
        full = solver.solve_pressure(1.3 * p_star)
        assert full.converged and full.contact_state == "full"
        wave = full.pressure[:, 0] - full.mean_pressure
        assert abs(wave.max() / p_star - 1) < 1e-8  # measured <= 3e-10
        assert solver.solve_pressure(0.9 * p_star).contact_state != "full"


def test_counter_surface_compliance_adds_to_the_layers() -> None:
    """With a deformable counter-surface (E* below E1*) the pair's compliance is the sum."""
    layer = CASES["stiff on soft"]
    e1s = layer.reduced_modulus
    ems = 2 * e1s
    pair = 1 / (1 / e1s + 1 / ems)
    n, lam, h = 64, 1e-4, 1e-6
    k = 2 * np.pi / lam
    p_star = h / (float(layer.compliance(k)) + 2 / (ems * k))
    res = HalfSpaceSolver(sinusoid(n, lam, h), pair, layer=layer).solve_pressure(1.3 * p_star)
    assert res.contact_state == "full"
    assert abs((res.pressure[:, 0].max() - res.mean_pressure) / p_star - 1) < 1e-6


# --------------------------------------------------------------- finite bodies (padded solver)


def paraboloid(n: int, length: float, radius: float) -> Texture:
    x = (np.arange(n) + 0.5) * length / n - length / 2
    X, Y = np.meshgrid(x, x, indexing="ij")
    return Texture(-(X**2 + Y**2) / (2 * radius), (length, length), periodic=False)


def hertz_radius(force: float, radius: float, modulus: float) -> float:
    return (3 * force * radius / (4 * modulus)) ** (1 / 3)


@pytest.mark.parametrize(("thickness", "which"), [(1e-1, "layer"), (1e-8, "substrate")])
def test_padded_hertz_limits(thickness: float, which: str) -> None:
    """A sphere on a layer much thicker than the contact is Hertz on the layer; on one much
    thinner, Hertz on the substrate (non-periodic, zero-padded solver)."""
    R, L, n = 1e-3, 0.6e-3, 64
    layer = Layer(thickness, E1, NU1, E2, NU2)
    e_expected = layer.reduced_modulus if which == "layer" else reduced(E2, NU2)
    a_target = 0.15e-3
    force = 4 * e_expected * a_target**3 / (3 * R)
    res = HalfSpaceSolver(paraboloid(n, L, R), layer.reduced_modulus, layer=layer).solve_pressure(force / L**2)
    a = hertz_radius(force, R, e_expected)
    assert res.converged
    assert abs(math.sqrt(res.real_contact_area / math.pi) / a - 1) < 0.02
    assert abs(res.approach / (a * a / R) - 1) < 0.02


@pytest.mark.parametrize("pixels", [1.5, 2.0, 8.0, 32.0])
def test_padded_kernel_matches_a_large_periodic_cell(pixels: float) -> None:
    """The padded layered operator against the periodic one on a cell 16x the patch, for layers
    of 1.5 pixels (the remainder sampled in Fourier space) to a patch's width (in real space):
    the layer's part of the displacement (layered minus homogeneous, so that both
    discretisations of the 1/r singularity drop out) agrees to 0.2 % of its range over the patch
    (after the periodic cell's undetermined mean is removed)."""
    n, L = 32, 1e-4
    layer = Layer(pixels * L / n, E1, NU1, E2, NU2)
    e = layer.reduced_modulus
    x = (np.arange(n) + 0.5) * L / n - L / 2
    X, Y = np.meshgrid(x, x, indexing="ij")
    p = np.maximum(1 - (X**2 + Y**2) / (0.3 * L) ** 2, 0.0) ** 0.5
    be = Backend()
    patch = Texture(np.zeros((n, n)), (L, L), periodic=False)
    d_pad = compliance_operator(be, patch, e, layer)(p) - compliance_operator(be, patch, e)(p)
    m = 16
    big = Texture(np.zeros((m * n, m * n)), (m * L, m * L))
    pb = np.zeros((m * n, m * n))
    pb[:n, :n] = p
    d_per = (compliance_operator(be, big, e, layer)(pb) - compliance_operator(be, big, e)(pb))[:n, :n]
    d_pad, d_per = d_pad - d_pad.mean(), d_per - d_per.mean()
    assert np.max(np.abs(d_pad - d_per)) < 2e-3 * np.ptp(d_pad)


def test_remainder_kernel_is_continuous_into_its_tail() -> None:
    layer = CASES["stiff on soft"]
    e = layer.reduced_modulus
    f0 = float(spectral_factor(layer, np.zeros(1), e)[0])
    d = remainder_kernel(layer, e, np.array([199.9, 200.1]) * layer.thickness, f0)
    assert abs(d[1] / d[0] - 1) < 0.02


def test_layered_grid_convergence() -> None:
    """Peak pressure and approach of a sphere on a layer as thick as the contact radius converge
    with the grid: successive differences fall by > 2.5 per halving of the spacing."""
    R, L = 1e-3, 0.6e-3
    layer = Layer(0.15e-3, E1, NU1, E2, NU2)
    force = 4 * reduced(E1, NU1) * (0.15e-3) ** 3 / (3 * R)
    vals = []
    for n in (32, 64, 128, 256):
        res = HalfSpaceSolver(paraboloid(n, L, R), layer.reduced_modulus, layer=layer).solve_pressure(force / L**2)
        vals.append((res.max_pressure, res.approach))
    vals = np.array(vals)
    diffs = np.abs(np.diff(vals, axis=0))
    assert np.all(diffs[1:] < diffs[:-1] / 2.5), diffs


def test_layered_unit_cell_grid_convergence() -> None:
    """psi(p) of a periodic cap cell on a stiff layer (t = spacing/5, E1 = 10 E2) converges as the
    homogeneous cell's does (tests/test_slow.py): against a 512^2 reference the error falls at
    every refinement from 64^2 (measured: 1.2e-3/8.3e-3/3.4e-3 at 64, 3.0e-4/2.0e-3/2.1e-3 at
    128, 1.3e-4/1.2e-3/4.3e-4 at 256, at 2/20/100 kPa)."""
    from fingerpad.textures import spherical_caps

    layer = Layer(30e-6, 1e6 * (1 - 0.49**2), 0.49, 1e5 * (1 - 0.49**2), 0.49)
    pressures = (2e3, 2e4, 1e5)
    psi = {}
    for n in (64, 128, 256, 512):
        tex = spherical_caps(radius=50e-6, height=10e-6, spacing=150e-6, grid=n)
        solver = HalfSpaceSolver(tex, layer.reduced_modulus, layer=layer)
        psi[n] = np.array([solver.solve_pressure(p).contact_fraction for p in pressures])
    err = [np.abs(psi[n] - psi[512]) for n in (64, 128, 256)]
    assert np.all(err[1] < err[0]) and np.all(err[2] < err[1]), err
    assert err[2].max() < 0.002
    # the layer matters at this scale: the homogeneous cell of the layer differs by far more
    homog = HalfSpaceSolver(spherical_caps(radius=50e-6, height=10e-6, spacing=150e-6, grid=256), layer.reduced_modulus)
    assert abs(homog.solve_pressure(2e4).contact_fraction - psi[256][1]) > 20 * err[2].max()


# --------------------------------------------------------------------------- preconditioner


def caps(n: int, lam: float, radius: float, height: float) -> Texture:
    x = np.arange(n) * lam / n - lam / 2
    X, Y = np.meshgrid(x, x, indexing="ij")
    z = np.sqrt(np.maximum(radius**2 - X**2 - Y**2, 0.0)) - (radius - height)
    return Texture(np.maximum(z, 0.0), (lam, lam))


def test_layered_preconditioner_is_the_exact_inverse_and_keeps_iterations_low() -> None:
    n, lam = 128, 1e-4
    layer = Layer(lam / 10, 10 * E1, NU1, E1, NU1)  # a stiff skin: a strongly varying factor
    e = layer.reduced_modulus
    tex = caps(n, lam, 0.4 * lam, 0.05 * lam)
    be = Backend()
    K = compliance_operator(be, tex, e, layer)._host_multiplier
    P = preconditioner(be, tex, e, "primal", layer)._host_multiplier
    np.testing.assert_allclose((K * P)[K > 0], 1.0, rtol=1e-12)
    D = preconditioner(be, tex, e, "dual", layer)._host_multiplier
    np.testing.assert_allclose(D[K > 0], K[K > 0], rtol=1e-12)
    load = 0.005 * e * 0.05
    layered = HalfSpaceSolver(tex, e, layer=layer).solve_pressure(load)
    plain = HalfSpaceSolver(tex, e, layer=layer, precondition=False, coarse_to_fine=False).solve_pressure(load)
    assert layered.converged and plain.converged
    assert abs(layered.mean_pressure / plain.mean_pressure - 1) < 1e-12
    assert abs(layered.contact_fraction - plain.contact_fraction) < 0.01  # the same solution, to a pixel
    assert layered.iterations < plain.iterations / 2


# ----------------------------------------------------- the derivation of docs/model.md, solved


def _mode_rows(z: float, k: float, mu: float, nu: float) -> np.ndarray:
    """Rows (u_x, u_z, sigma_xz, sigma_zz) of one Fourier mode against the Papkovich-Neuber
    constants (A, B, C, D) of docs/model.md ("Layered skin"), z into the body."""
    kap = 3 - 4 * nu
    em, ep = math.exp(-k * z), math.exp(k * z)
    kz = k * z
    return np.array([
        [kz * em / (2 * mu), em / (2 * mu), kz * ep / (2 * mu), ep / (2 * mu)],                     # u_x / sin
        [(kap + kz) * em / (2 * mu), em / (2 * mu), (kap - kz) * ep / (2 * mu), -ep / (2 * mu)],   # u_z / cos
        [k * (-(1 - 2 * nu) - kz) * em, -k * em, k * (-(1 - 2 * nu) + kz) * ep, k * ep],          # s_xz / sin
        [-k * (2 * (1 - nu) + kz) * em, -k * em, k * (2 * (1 - nu) - kz) * ep, -k * ep],           # s_zz / cos
    ])


def derivation_compliance(k: float, layer: Layer) -> float:
    """Surface deflection per unit pressure amplitude from the boundary-value problem of the
    docs, solved as a linear system (no closed form)."""
    t = layer.thickness
    mu1 = layer.modulus / (2 * (1 + layer.poisson))
    top, bottom = _mode_rows(0.0, k, mu1, layer.poisson), _mode_rows(t, k, mu1, layer.poisson)
    if layer.rigid_base:
        rows = [top[2], top[3], bottom[1]] + ([bottom[2]] if layer.base == "frictionless" else [bottom[0]])
        a = np.array(rows)
        c = np.linalg.solve(a, [0.0, -1.0, 0.0, 0.0])
        return float(top[1] @ c)
    mu2 = layer.substrate_modulus / (2 * (1 + layer.substrate_poisson))
    sub = _mode_rows(t, k, mu2, layer.substrate_poisson)[:, :2]  # decaying solutions only
    a = np.zeros((6, 6))
    a[0, :4], a[1, :4] = top[2], top[3]
    a[2:, :4] = bottom
    a[2:, 4:] = -sub
    c = np.linalg.solve(a, [0.0, -1.0, 0, 0, 0, 0])
    return float(top[1] @ c[:4])


@pytest.mark.parametrize("case", list(CASES))
def test_closed_form_solves_the_derivations_boundary_value_problem(case: str) -> None:
    layer = CASES[case]
    for kt in (0.05, 0.5, 2.0, 6.0):
        k = kt / layer.thickness
        assert abs(derivation_compliance(k, layer) / float(layer.compliance(k)) - 1) < 1e-9


# ------------------------------------------------------------------- any array namespace


def _paraboloid(n: int, periodic: bool) -> Texture:
    """A paraboloid of tip radius lam on an n x n grid of side lam = 100 um."""
    lam = 1e-4
    x = (np.arange(n) + 0.5) * lam / n - lam / 2
    X, Y = np.meshgrid(x, x, indexing="ij")
    return Texture(-(X**2 + Y**2) / (2 * lam), (lam, lam), periodic=periodic)


@pytest.mark.parametrize("periodic", [True, False])
def test_layered_solver_runs_on_the_strict_array_namespace(periodic: bool) -> None:
    """The layered kernel is one more host-built multiplier: a GPU namespace runs it unchanged."""
    xps = pytest.importorskip("array_api_strict")
    tex = _paraboloid(32, periodic)
    layer = CASES["stiff on soft"]
    e = layer.reduced_modulus
    ref = HalfSpaceSolver(tex, e, layer=layer, kernels="array").solve_pressure(1e-3 * e)
    strict = HalfSpaceSolver(tex, e, layer=layer, xp=xps).solve_pressure(1e-3 * e)
    assert ref.converged and strict.converged and ref.iterations == strict.iterations
    np.testing.assert_allclose(strict.pressure, ref.pressure, rtol=0, atol=1e-6 * ref.max_pressure)


@pytest.mark.parametrize("case", ["stiff on soft", "rigid base, bonded"])
def test_layered_primal_dual_and_approach_control_agree(case: str) -> None:
    """The dual (gap) form uses the layered stiffness, the exact inverse: same solution; and
    an approach-controlled solve inverts the pressure-controlled one."""
    layer = CASES[case]
    e = layer.reduced_modulus
    tex = caps(64, 1e-4, 0.4e-4, 0.05e-4)
    load = 2e-3 * e
    a = HalfSpaceSolver(tex, e, layer=layer, formulation="primal").solve_pressure(load)
    b = HalfSpaceSolver(tex, e, layer=layer, formulation="dual").solve_pressure(load)
    assert a.converged and b.converged
    np.testing.assert_allclose(b.pressure, a.pressure, rtol=0, atol=1e-5 * a.max_pressure)
    assert abs(b.approach / a.approach - 1) < 1e-6
    back = HalfSpaceSolver(tex, e, layer=layer).solve_approach(a.approach)
    assert back.converged and abs(back.mean_pressure / load - 1) < 1e-6


@pytest.mark.parametrize("name", ["cupy", "torch"])
@pytest.mark.parametrize("periodic", [True, False])
def test_layered_solver_on_a_gpu_namespace_if_present(name: str, periodic: bool) -> None:
    """The layered solver on CuPy or PyTorch arrays (a GPU where there is one; skipped where the
    library is missing, as in CI) gives the NumPy solution, in the same iterations."""
    if name == "cupy":
        xp = pytest.importorskip("cupy")
        device = xp.cuda.Device(0) if xp.cuda.is_available() else pytest.skip("no CUDA device")
    else:
        torch = pytest.importorskip("torch")
        xp = pytest.importorskip("array_api_compat.torch")
        device = torch.device("cuda" if torch.cuda.is_available() else "cpu")
    tex = _paraboloid(64, periodic)
    layer = CASES["stiff on soft"]
    e = layer.reduced_modulus
    ref = HalfSpaceSolver(tex, e, layer=layer, kernels="array").solve_pressure(1e-3 * e)
    with device:
        gpu = HalfSpaceSolver(tex, e, layer=layer, xp=xp).solve_pressure(1e-3 * e)
    assert ref.converged and gpu.converged and abs(ref.iterations - gpu.iterations) <= 1
    np.testing.assert_allclose(gpu.pressure, ref.pressure, rtol=0, atol=1e-6 * ref.max_pressure)
