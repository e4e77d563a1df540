"""The pad's nominal pressure over the ridge contact (Eq. 3.7) and disc averages of it."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

from fingerpad import macro
from fingerpad.errors import FingerpadError

F = 1.5  # N
AREA = 80e-6  # m^2
A_RADIUS = math.sqrt(AREA / math.pi)


def test_pad_pressure_integrates_to_the_load():
    total, _ = integrate.quad(lambda r: 2 * math.pi * r * macro.pad_pressure(r, F, AREA), 0.0, A_RADIUS,
                              epsabs=0, epsrel=1e-12, limit=200)
    assert total == pytest.approx(F, rel=1e-9)


def test_pad_pressure_is_hertzian():
    r = np.linspace(0, A_RADIUS, 11)
    p = macro.pad_pressure(r, F, AREA)
    p0 = 1.5 * F / AREA
    np.testing.assert_allclose(p, p0 * np.sqrt(1 - (r / A_RADIUS) ** 2), rtol=1e-12, atol=1e-9 * p0)
    assert macro.pad_pressure(0.0, F, AREA) == pytest.approx(p0, rel=1e-14)
    # (p / p0)^2 + (r / a)^2 = 1: an ellipse
    np.testing.assert_allclose((p / p0) ** 2 + (r / A_RADIUS) ** 2, 1.0, atol=1e-12)


def test_pad_pressure_zero_outside_the_disc_and_without_load():
    assert macro.pad_pressure(1.0001 * A_RADIUS, F, AREA) == 0.0
    assert np.all(np.asarray(macro.pad_pressure([2 * A_RADIUS, 1.0], F, AREA)) == 0.0)
    assert np.all(np.asarray(macro.pad_pressure([0.0, 0.5 * A_RADIUS], 0.0, AREA)) == 0.0)


def test_pad_pressure_keeps_shape():
    r = np.full((3, 4), 0.5 * A_RADIUS)
    out = macro.pad_pressure(r, F, AREA)
    assert out.shape == (3, 4)
    assert isinstance(macro.pad_pressure(0.0, F, AREA), float)


@pytest.mark.parametrize("r, load, area, word", [(-1e-3, F, AREA, "radius"), (float("nan"), F, AREA, "radius"),
                                                 (0.0, -1.0, AREA, "load"), (0.0, F, 0.0, "ridge area")])
def test_pad_pressure_refuses_bad_input(r, load, area, word):
    with pytest.raises(FingerpadError, match=word):
        macro.pad_pressure(r, load, area)


# ---------------------------------------------------------------------------------------------
# disc averages
# ---------------------------------------------------------------------------------------------


def test_disc_average_of_pressure_is_mean_pressure():
    peaks = np.array([1e2, 1.5e4, 3e6])
    np.testing.assert_allclose(macro.disc_average(lambda p: p, peaks), peaks / 1.5, rtol=1e-13)


@pytest.mark.parametrize("m", [0.0, 0.5, 1.0, 2.0, 2 / 3, -0.5])
def test_disc_average_of_power_closed_form(m):
    """Mean of p^m over the Hertzian disc: 2 p0^m / (m + 2), also for the singular m < 0."""
    peaks = np.array([10.0, 1e4])
    with np.errstate(divide="ignore"):
        got = macro.disc_average(lambda p: p**m, peaks)
    np.testing.assert_allclose(got, 2 * peaks**m / (m + 2), rtol=1e-11)


def test_disc_average_of_indicator_with_breakpoint():
    """Share of the disc above p_c: s > p_c / p0, area fraction 1 - (p_c / p0)^2."""
    peaks = np.array([2.0, 4.0, 10.0])
    pc = 1.0
    got = macro.disc_average(lambda p: (p > pc).astype(float), peaks, breakpoints=[pc])
    np.testing.assert_allclose(got, 1 - (pc / peaks) ** 2, rtol=1e-13)


def test_disc_average_of_kinked_saturation():
    """mean of min(p, p_c) = p0 (2/3) - (2/3) p0 (1 - s0^2)^(3/2) + p_c (1 - s0^2), s0 = p_c / p0."""
    p0, pc = 3.0, 1.2
    s0 = pc / p0
    exact = 2 * (p0 * s0**3 / 3 + pc * (1 - s0**2) / 2)
    got = macro.disc_average(lambda p: np.minimum(p, pc), [p0], breakpoints=[pc])
    assert got[0] == pytest.approx(exact, rel=1e-13)


def test_breakpoints_outside_or_meaningless_are_ignored():
    peaks = np.array([1.0, 5.0])
    plain = macro.disc_average(lambda p: p**2, peaks)
    odd = macro.disc_average(lambda p: p**2, peaks, breakpoints=[100.0, -1.0, 0.0, float("nan"), float("inf")])
    np.testing.assert_allclose(odd, plain, rtol=1e-13)


def test_disc_average_zero_peak_and_constant():
    got = macro.disc_average(lambda p: np.ones_like(p), [0.0, 1.0, 1e9])
    np.testing.assert_allclose(got, 1.0, rtol=1e-14)
    # a function returning a scalar broadcast over the nodes
    assert macro.disc_average(lambda p: 3.0, 2.0)[0] == pytest.approx(3.0, rel=1e-14)


def test_disc_average_matches_direct_quadrature_of_pad_pressure():
    """The disc average of a non-linear function equals the area integral over pad_pressure."""
    func = lambda p: np.tanh(p / 2e4)  # noqa: E731
    p0 = 1.5 * F / AREA
    direct, _ = integrate.quad(lambda r: 2 * math.pi * r * func(macro.pad_pressure(r, F, AREA)), 0.0, A_RADIUS,
                               epsabs=0, epsrel=1e-11, limit=200)
    assert macro.disc_average(func, p0)[0] == pytest.approx(direct / AREA, rel=1e-9)
