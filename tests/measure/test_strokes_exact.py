"""Strokes of a reciprocating recording with known numbers: count, senses, steady friction, bins."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from fingerpad import measure as m
from fingerpad.errors import FingerpadError

FS = 100.0  # Hz


def recording(n_strokes=6, mu=0.4, load=1.5, travel=0.02, source="P1_glass_1.csv"):
    """Triangle-wave position (constant speed), constant load, friction exactly opposing motion."""
    n = int(FS)  # samples per stroke
    up = np.linspace(0.0, travel, n, endpoint=False)
    x = np.concatenate([up if j % 2 == 0 else travel - up for j in range(n_strokes)])
    x = np.r_[x, x[-1]]
    t = np.arange(x.size) / FS
    v = np.gradient(x, t)
    fn = np.full(x.size, load)
    ft = -np.sign(v) * mu * load
    return m.Recording(source=source, normal=fn, friction=ft, time=t, position=x, participant="P1", sample="glass")


def test_strokes_counted_with_alternating_senses():
    strokes = m.detect_strokes(recording(n_strokes=6))
    assert len(strokes) == 6
    assert [s.sense for s in strokes] == [1, -1, 1, -1, 1, -1]
    for s in strokes:
        assert s.start <= s.steady_start < s.steady_stop <= s.stop
        assert s.travel == pytest.approx(0.02, rel=0.05)


def test_steady_friction_and_load_are_exact():
    table = m.measure_strokes(recording(mu=0.4, load=1.5))
    assert len(table) == 6
    np.testing.assert_allclose(table["mu"], 0.4, rtol=1e-12)
    np.testing.assert_allclose(table["load"], 1.5, rtol=1e-12)
    assert list(table["sense"]) == ["+", "-"] * 3
    assert (table["participant"] == "P1").all() and (table["sample"] == "glass").all()
    np.testing.assert_allclose(table["speed"], 0.02, rtol=0.05)  # 2 cm in 1 s
    assert (table["time_end"] > table["time_start"]).all()


def test_trim_keeps_the_middle():
    rec = recording()
    narrow = m.detect_strokes(rec, m.StrokeOptions(trim=0.4))
    wide = m.detect_strokes(rec, m.StrokeOptions(trim=0.0))
    for a, b in zip(narrow, wide, strict=True):
        assert (a.steady_stop - a.steady_start) < (b.steady_stop - b.steady_start)


def test_too_few_strokes_named():
    with pytest.raises(FingerpadError, match=r"P1_glass_1\.csv: found 1 usable stroke\(s\) .* need at least 3"):
        m.measure_strokes(recording(n_strokes=1), m.StrokeOptions(min_strokes=3))


@pytest.mark.parametrize("kwargs, message", [
    (dict(trim=0.5), r"trim must lie in \[0, 0.45\]"), (dict(deadband=0.0), r"deadband must lie in \(0, 1\)"),
    (dict(smooth=0), "smooth and min_strokes must be at least 1"),
    (dict(direction_source="eyes"), "unknown direction source"),
    (dict(min_load=-1.0), "min_load must be non-negative"), (dict(min_travel=float("inf")), "min_travel"),
    (dict(motion_threshold=0.0), "motion_threshold must be positive"),
])
def test_options_refusals(kwargs, message):
    with pytest.raises(FingerpadError, match=message):
        m.StrokeOptions(**kwargs)


def test_load_bin_edges():
    loads = np.array([0.1, 0.5, 1.0, 4.0])
    edges = m.load_bin_edges(loads, 4)
    assert edges.size == 5 and edges[0] <= 0.1 and edges[-1] >= 4.0
    np.testing.assert_allclose(np.diff(np.log(edges)), np.log(edges[1] / edges[0]), rtol=1e-12)  # log-spaced
    assert m.load_bin_edges(np.array([1.0, 1.0]), 3).tolist() == pytest.approx([0.9, 1.1])


def test_bin_strokes_means_per_bin():
    strokes = pd.DataFrame({
        "file": ["a", "a", "b", "b"], "participant": "P1", "sample": "glass", "direction": "", "repetition": "",
        "session": "", "sense": ["+", "-", "+", "-"], "load": [0.2, 0.2, 2.0, 2.0], "mu": [0.4, 0.6, 0.3, 0.5],
        "outlier": [False, False, False, True],
    })
    edges = np.array([0.1, 1.0, 10.0])
    bins = m.bin_strokes(strokes, edges)
    both = bins[bins["sense"] == "both"].set_index("bin")
    assert both.loc[0, "mu"] == pytest.approx(0.5) and both.loc[0, "n"] == 2
    assert both.loc[1, "mu"] == pytest.approx(0.3) and both.loc[1, "n"] == 1  # the outlier is left out
    assert np.isnan(both.loc[0, "mu_sem"]), "one recording: no between-recording error"
    assert (both["bin_low"].to_numpy() == edges[:2]).all()


def test_the_median_of_three_samples_is_numpys():
    """A stroke's travel reads the median of its first and last three positions by a shortcut
    (_median3): the same number as numpy's median, NaN included, for every order and ties."""
    import itertools

    import numpy as np

    from fingerpad.measure.strokes import _median3

    values = [-1.5, 0.0, 2e-3, 2e-3, 7.25, float("nan"), -0.0]
    for triple in itertools.product(values, repeat=3):
        a = np.array(triple)
        want = float(np.median(a))
        got = _median3(a)
        assert (got == want or (np.isnan(got) and np.isnan(want))), triple
    assert _median3(np.array([3.0, 1.0])) == 2.0  # other sizes: numpy's median itself
