"""The forced-choice model on ln(mu) (docs/perception.md, Eqs. P.1-P.3): its invariants."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad.errors import FingerpadError
from fingerpad.perception.discrimination import (
    THRESHOLD,
    WEBER_FRACTION,
    Z75,
    discriminates,
    noise_sd,
    p_correct,
    summarise,
)


def test_identical_surfaces_give_chance_and_nobody_tells_them_apart():
    mu = np.array([[0.3, 0.5, 0.9], [0.41, 0.62, 1.3]])
    w = np.array([[0.05], [0.3]])
    p = p_correct(mu, mu, w)
    assert np.all(p == 0.5)
    assert not discriminates(p).any()
    assert np.all(summarise(p)["fraction"] == 0.0)


def test_swapping_a_and_b_changes_nothing():
    rng = np.random.default_rng(3)
    a, b = rng.uniform(0.2, 1.2, (50, 4)), rng.uniform(0.2, 1.2, (50, 4))
    w = rng.uniform(0.05, 0.3, (50, 1))
    assert np.array_equal(p_correct(a, b, w), p_correct(b, a, w))


def test_p_grows_monotonically_with_the_log_ratio():
    ratio = np.linspace(1.0, 3.0, 400)
    p = p_correct(0.5, 0.5 * ratio, 0.11)
    assert p[0] == 0.5 and np.all(np.diff(p) > 0) and p[-1] > 0.999


def test_weber_fraction_is_the_75_percent_point():
    """A relative difference W gives P = 0.75 (Eq. P.3); sigma = ln(1 + W) / 0.9539."""
    for w in (0.05, 0.11, 0.2, 1.0):
        assert p_correct(1.0, 1.0 + w, w) == pytest.approx(THRESHOLD, abs=1e-12)
        assert noise_sd(w) == pytest.approx(math.log1p(w) / 0.9539, rel=1e-4)
    assert Z75 == pytest.approx(0.6744898, abs=1e-7)


def test_small_weber_fraction_makes_any_difference_felt():
    for w in (1e-3, 1e-6, 0.0):
        assert p_correct(0.5, 0.5 * 1.01, w) >= 0.9999 if w else p_correct(0.5, 0.505, w) == 1.0
    assert p_correct(0.5, 0.5, 0.0) == 0.5


def test_summary_is_the_fraction_and_median_of_the_members():
    p = np.array([[0.5, 0.8], [0.74, 0.75], [0.9, 0.6]])
    s = summarise(p)
    assert s["fraction"].tolist() == [1 / 3, 2 / 3]
    assert s["p_correct_median"].tolist() == [0.74, 0.75]


def test_weber_fraction_is_declared_with_its_bounds():
    assert WEBER_FRACTION.default == 0.11 and WEBER_FRACTION.unit == "1"
    assert WEBER_FRACTION.check(0.2, "W") == 0.2
    for bad in (0.0, -0.1, 3.0):
        with pytest.raises(FingerpadError):
            WEBER_FRACTION.check(bad, "--weber-fraction")
