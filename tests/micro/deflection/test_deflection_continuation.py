"""The ramps reach the shear the coupling needs, and inputs a little apart give the same ramps
(issue 31).

The README ellipsoids' along section (b = 135 um across a 300 um period: 30 um of base between
neighbours) at the 26.8 kPa level stopped at mu = 0.0625 whatever the step: a flank point near
the foot changed base segment, its gap jumped by the difference between the two segments' lines,
and the Newton iteration cycled. The fold gap is now the distance to the nearest closed segment,
continuous in the positions."""

from __future__ import annotations

import numpy as np
import pytest

from fingerpad.micro.deflection import DeflectionSettings, EllipsoidGeometry, needed_shear, section_for
from fingerpad.micro.deflection.contact import normal_gap, segment_gap
from fingerpad.micro.deflection.gain import SectionMaterials, level_pressures, solve_section

README = EllipsoidGeometry(45e-6, 135e-6, 90e-6, 300e-6, 300e-6)
MATS = SectionMaterials(0.3e6, 0.49, 0.3e6, 0.49)


def test_the_segment_gap_is_continuous_past_the_ends_and_exact():
    p, q = np.array([[0.0, 0.0]]), np.array([[1.0, 0.2]])
    # inside: the line's distance; past an end: the end point's distance, signed by the side
    s = np.array([[0.5, 0.5], [-0.3, -0.4], [1.3, 0.6]])
    g, _, _ = segment_gap(s, np.repeat(p, 3, 0), np.repeat(q, 3, 0))
    assert g[0] == pytest.approx(normal_gap(s[:1], p, q)[0][0])
    assert g[1] == pytest.approx(-0.5) and g[2] == pytest.approx(0.5)
    # continuous, with its gradient, across the end (t = 1): the end point's normal is the line's
    n = np.array([-0.2, 1.0]) / np.hypot(0.2, 1.0)
    for h in (0.3, -0.2):
        on = q + h * n
        t = np.array([1.0, 0.2]) / np.hypot(1.0, 0.2)
        pts = np.vstack([on - 1e-7 * t, on + 1e-7 * t])
        g2, gr2, _ = segment_gap(pts, np.repeat(p, 2, 0), np.repeat(q, 2, 0))
        assert g2[0] == pytest.approx(g2[1], abs=1e-9) and g2[0] == pytest.approx(h)
        assert np.allclose(gr2[0], gr2[1], atol=1e-6)
    # the gradient and the Hessian are those of the distance (finite differences), past the end
    rng = np.random.default_rng(1)
    for _ in range(5):
        y = np.concatenate([rng.uniform(1.1, 1.6, 1), rng.uniform(-0.8, 0.8, 1), [0.0, 0.0, 1.0, 0.2]])
        def gap(z):
            return segment_gap(z[None, 0:2], z[None, 2:4], z[None, 4:6])[0][0]
        _, grad, hess = segment_gap(y[None, 0:2], y[None, 2:4], y[None, 4:6])
        eps = 1e-6
        num = np.array([(gap(y + eps * e) - gap(y - eps * e)) / (2 * eps) for e in np.eye(6)])
        assert np.allclose(num, grad[0], atol=1e-6)
        num_h = np.array([(segment_gap((y + eps * e)[None, 0:2], (y + eps * e)[None, 2:4], (y + eps * e)[None, 4:6])[1][0]
                           - segment_gap((y - eps * e)[None, 0:2], (y - eps * e)[None, 2:4], (y - eps * e)[None, 4:6])[1][0])
                          / (2 * eps) for e in np.eye(6)])
        assert np.allclose(num_h, hess[0], atol=1e-5)


def test_levels_a_little_apart_are_the_same_levels():
    lo, hi = 14514.726639031436, 49639.66685066251  # the README command's pad-centre pressures
    levels = level_pressures(lo, hi, 3)
    assert levels.tolist() == [14500.0, 26800.0, 49600.0]
    for k in (1 + 1e-6, 1 - 1e-6, 1 + 1e-5):
        assert np.array_equal(level_pressures(lo * k, hi * k, 3), levels)
    assert np.all(np.abs(levels / np.geomspace(lo, hi, 3) - 1) < 5e-3)


def test_needed_shear_lies_above_every_fixed_point():
    from fingerpad.micro.deflection import GainCurve, solve_local_shear
    from fingerpad.micro.deflection.pressure_ramp import PressureRamp

    p = np.geomspace(1e4, 5e4, 9)
    psi = 0.08 * (p / 1e4) ** 0.6
    need = needed_shear(p, psi, tau0=8.1e3, alpha=0.1)
    assert need == pytest.approx(0.05 * np.ceil((3.0 * 8.1e3 * 0.08 / 1e4 + 0.1) / 0.05))
    mu = np.linspace(0, 5, 101)
    z = np.zeros_like(mu)
    steep = GainCurve(np.array([1e4, 5e4]), [PressureRamp(q, 1.0, mu, 1 + 0.4 * mu, np.minimum(1 + 0.4 * mu, 3.0),
                                                           z, z, z, z, z, z, np.nan, np.nan, False, None)
                                              for q in (1e4, 5e4)])
    fixed = solve_local_shear(p, psi, steep, 8.1e3, 0.1)
    assert np.all(fixed.converged) and np.all(fixed.mu <= need)


@pytest.fixture(scope="module")
def along():
    """The README's along section at its 26.8 kPa level and at a pressure 1e-6 above, to mu 0.3
    (the coupling needs ~0.2 there)."""
    sec = section_for(README, 90.0)
    return [solve_section(sec, MATS, np.array([p]), tau0=8.1e3, alpha=0.1,
                          settings=DeflectionSettings(mu_max=0.3, n_pressures=1))[0]
            for p in (26800.0, 26800.0 * (1 + 1e-6))]


def test_the_along_section_passes_the_shear_it_stopped_at(along):
    """MODEL_VERSION 7 stopped at mu = 0.0625 (lost convergence, at every step size)."""
    for ramp in along:
        assert ramp.stopped is None and ramp.mu_reached >= 0.3
        mu, gain = ramp.branch()
        assert np.all(np.abs(gain - 1) < 0.05)  # a squat section: no deflection gain to speak of


def test_a_pressure_a_little_apart_gives_the_same_ramp(along):
    """Insensitive to an input change far below the model's error: the ramps of two pressures
    1e-6 apart take the same steps and agree to the solver's tolerance (not only to the +-3 %
    noise of the gain)."""
    a, b = along
    assert a.mu.size == b.mu.size
    assert np.allclose(a.gain, b.gain, rtol=1e-4) and np.allclose(a.mu, b.mu, rtol=1e-4, atol=1e-6)
