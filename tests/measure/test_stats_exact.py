"""The random-intercept fits and cluster means behind every interval: exact cases and invariants."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats as sps

from fingerpad import measure as m
from fingerpad.errors import FingerpadError


def test_noiseless_line_is_recovered_exactly():
    x = np.tile(np.linspace(0.0, 1.0, 5), 4)
    clusters = np.repeat(["a", "b", "c", "d"], 5)
    offsets = np.repeat([0.0, 0.3, -0.2, 0.1], 5)  # a random intercept per recording
    y = 1.5 + 2.0 * x + offsets
    fit = m.random_intercept_fit(y, np.column_stack([np.ones_like(x), x]), clusters)
    # the slope is estimated within clusters: exact; the intercept is the mean level
    assert fit.coef[1] == pytest.approx(2.0, abs=1e-9)
    assert fit.coef[0] == pytest.approx(1.5 + offsets.mean(), abs=1e-9)
    assert fit.n == 20 and fit.n_clusters == 4
    assert fit.between == (True, False)
    assert fit.df_between == 3.0 and fit.df_within == 20 - 4 - 1


def test_without_clusters_it_is_least_squares():
    rng = np.random.default_rng(1)
    x = rng.uniform(0, 1, 30)
    y = 0.5 - x + 0.1 * rng.standard_normal(30)
    X = np.column_stack([np.ones_like(x), x])
    fit = m.random_intercept_fit(y, X, None)
    ref = sps.linregress(x, y)
    assert fit.coef[1] == pytest.approx(ref.slope, rel=1e-12)
    assert fit.coef[0] == pytest.approx(ref.intercept, rel=1e-12)
    assert math.sqrt(fit.cov[1, 1]) == pytest.approx(ref.stderr, rel=1e-10)
    # the interval is the Student-t interval with n - 2 df
    lo, hi = fit.interval([0, 1], 0.9)
    q = sps.t.ppf(0.95, 28)
    assert (lo, hi) == pytest.approx((ref.slope - q * ref.stderr, ref.slope + q * ref.stderr), rel=1e-10)
    assert fit.sigma2_between == 0.0 and fit.note == ""


def test_one_cluster_says_so():
    x = np.linspace(0, 1, 8)
    fit = m.random_intercept_fit(x + 1, np.column_stack([np.ones_like(x), x]), ["r1"] * 8)
    assert fit.n_clusters == 1 and "one recording" in fit.note


@pytest.mark.parametrize("y, X, clusters, message", [
    (np.ones(3), np.ones((4, 1)), None, "3 responses for 4 design rows"),
    (np.ones(2), np.ones((2, 2)), None, "need more than 2 points"),
    (np.arange(5.0), np.column_stack([np.ones(5), np.ones(5)]), None, "rank-deficient"),
    (np.arange(5.0), np.ones((5, 1)), ["a", "b"], "2 cluster labels for 5 points"),
])
def test_fit_refusals(y, X, clusters, message):
    with pytest.raises(FingerpadError, match=message):
        m.random_intercept_fit(y, X, clusters)


def test_cluster_mean_cr1_by_hand():
    values = [1.0, 2.0, 3.0, 5.0, 9.0]
    clusters = ["a", "a", "b", "b", "c"]
    mean, se, lo, hi = m.cluster_mean(values, clusters, level=0.95)
    assert mean == 4.0
    # cluster sums of deviations: (-3 - 2), (-1 + 1), (5): 25 + 0 + 25 = 50; G = 3
    expected = math.sqrt(3 / 2 * 50) / 5
    assert se == pytest.approx(expected, rel=1e-14)
    q = sps.t.ppf(0.975, 2)
    assert (lo, hi) == pytest.approx((mean - q * expected, mean + q * expected), rel=1e-12)


def test_cluster_mean_degenerate_cases():
    assert all(math.isnan(v) for v in m.cluster_mean([], None))
    mean, se, lo, hi = m.cluster_mean([1.0, 3.0], ["a", "a"])
    assert mean == 2.0 and math.isnan(se) and math.isnan(lo) and math.isnan(hi)
    # without labels each value is its own cluster: the CR1 error of independent points
    mean, se, _, _ = m.cluster_mean([1.0, 2.0, 3.0, 4.0], None)
    dev = np.array([1.0, 2.0, 3.0, 4.0]) - 2.5
    assert se == pytest.approx(math.sqrt(4 / 3 * np.sum(dev**2)) / 4, rel=1e-14)


# ---------------------------------------------------------------------------------------------
# the power law mu = k F^(n - 1)
# ---------------------------------------------------------------------------------------------


def test_power_law_exact_on_noiseless_data():
    loads = np.geomspace(0.1, 4.0, 12)
    mu = 0.6 * loads ** (0.75 - 1.0)
    fit = m.fit_power_law_clustered(loads, mu)
    assert fit.k == pytest.approx(0.6, rel=1e-12) and fit.n == pytest.approx(0.75, rel=1e-12)
    assert fit.k_stderr == pytest.approx(0.0, abs=1e-10) and fit.n_ci[0] <= 0.75 <= fit.n_ci[1]
    np.testing.assert_allclose(fit(loads), mu, rtol=1e-12)
    assert fit(1.0) == pytest.approx(fit.k, rel=1e-15), "k is mu at 1 N"
    value, se, df = fit.log_level(loads)
    assert value == pytest.approx(np.mean(np.log(mu)), rel=1e-12)


def test_power_law_per_recording_levels():
    loads = np.tile(np.geomspace(0.2, 3.0, 6), 3)
    rec = np.repeat(["r1", "r2", "r3"], 6)
    level = np.repeat([1.0, 1.2, 0.9], 6)
    fit = m.fit_power_law_clustered(loads, 0.5 * level * loads ** (-0.3), rec)
    assert fit.n == pytest.approx(0.7, abs=1e-9)  # the exponent is within-recording: exact
    assert fit.n_clusters == 3 and fit.df_level == 2.0
    assert fit.k == pytest.approx(0.5 * math.exp(np.mean(np.log([1.0, 1.2, 0.9]))), rel=1e-9)
    assert fit.sigma_between > 0


@pytest.mark.parametrize("loads, mu, message", [
    ([1.0, 2.0], [0.5, 0.4], "at least 3 points"),
    ([1.0, 2.0, 3.0], [0.5, 0.4], "differ in length"),
    ([1.0, 2.0, -3.0], [0.5, 0.4, 0.3], "positive and finite"),
    ([1.0, 1.0, 1.0], [0.5, 0.4, 0.3], "at least two different loads"),
])
def test_power_law_refusals(loads, mu, message):
    with pytest.raises(FingerpadError, match=message):
        m.fit_power_law_clustered(loads, mu)


def test_the_reml_grid_in_one_pass_is_the_same_bits_as_one_ratio_at_a_time():
    """random_intercept_fit's grid of variance ratios is evaluated in one pass of stacked
    products and solves (_Reml.log_likelihoods); each value is bit for bit the one solve(gamma)
    gives, on random designs of 1 and 2 columns, 2-30 clusters, balanced or not (the fit's
    reported numbers depend on which grid point is largest)."""
    from fingerpad.measure.stats import _Reml, _sums

    rng = np.random.default_rng(7)
    grid = np.r_[0.0, np.exp(np.linspace(-12.0, 9.0, 22))]
    for _ in range(300):
        n = int(rng.integers(8, 300))
        p = int(rng.integers(1, 3))
        g = int(rng.integers(2, min(30, n - 2)))
        X = np.column_stack([np.ones(n)] + [rng.normal(size=n) for _ in range(p - 1)])
        inv = np.sort(np.r_[np.arange(g), rng.integers(0, g, n - g)])
        y = rng.normal(size=n) + rng.normal(size=g)[inv]
        reml = _Reml(_sums(X, inv, g), _sums(y, inv, g), np.bincount(inv, minlength=g).astype(float), X.T @ X,
                     X.T @ y, float(y @ y), n, p)
        one_by_one = np.array([reml.solve(gamma)[0] for gamma in grid])
        assert np.array_equal(reml.log_likelihoods(grid), one_by_one)


def test_t_quantile_is_scipys_bit_for_bit():
    from fingerpad.measure.stats import t_quantile

    for df in (1e-3, 0.7, 1.0, 2.0, 3.5, 9.0, 41.0, 1e4):
        for level in (0.5, 0.9, 0.95, 0.99):
            assert t_quantile(level, df) == float(sps.t.ppf(0.5 + level / 2.0, df))
    assert t_quantile(0.95, math.inf) == float(sps.norm.ppf(0.975))
