"""Sweep specs: the [sweep] table read into axes and points, every mistake named before any work."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad.design.spec import read_sweep_file, sweep_from_dict
from fingerpad.errors import FingerpadError

BASE = {
    "texture": {"name": "caps", "radius": "50um", "height": "10um", "spacing": "150um"},
    "model": {"kind": "hertz"},
}


def sweep(**table):
    return sweep_from_dict({**BASE, "sweep": table})


def test_grid_of_two_axes():
    s = sweep(axes={"spacing": "100um:400um:3", "height": {"values": ["5um", "10um"]}})
    assert s.design == "grid" and s.dims == ("spacing", "height") and s.shape == (3, 2) and s.size == 6
    spacing, height = s.axes
    np.testing.assert_allclose(spacing.values, [100e-6, 200e-6, 400e-6], rtol=1e-12)  # log-spaced range
    assert spacing.log is True
    assert height.values == (5e-6, 10e-6) and height.log is True  # a list with a constant ratio is log
    np.testing.assert_allclose(s.loads, np.geomspace(0.1, 4.0, 40), rtol=1e-12)
    assert s.assignment((2, 1)) == {"spacing": 400e-6, "height": 10e-6}


def test_linear_range_and_uneven_list():
    s = sweep(axes={"radius": {"range": "20um:60um:3", "log": False}, "height": ["5um", "6um", "10um"]})
    radius, height = s.axes
    np.testing.assert_allclose(radius.values, [20e-6, 40e-6, 60e-6], rtol=1e-12)
    assert radius.log is False and height.log is False


def test_study_data_writes_the_point_into_the_base():
    s = sweep(axes={"spacing": ["100um", "200um"], "material_modulus": ["1MPa"]}, loads="1N:2N:2")
    data = s.study_data(s.assignment((1, 0)))
    assert data["texture"]["spacing"] == 200e-6 and data["texture"]["radius"] == "50um"
    assert data["material"]["modulus"] == 1e6
    assert BASE["texture"]["spacing"] == "150um", "the base is not changed"
    np.testing.assert_allclose(s.loads, [1.0, 2.0])
    # the study's loads rule: a comma list, or a TOML list, as [loads] and --loads take them
    listed = sweep(axes={"spacing": ["100um", "200um"]}, loads="0.5N,1N:4N:3").loads
    np.testing.assert_allclose(listed, [0.5, 1.0, 2.0, 4.0], rtol=1e-12)
    np.testing.assert_allclose(sweep(axes={"spacing": ["100um"]}, loads=["1N", 3]).loads, [1.0, 3.0])


def test_sweeping_the_family_clears_its_parameters():
    s = sweep_from_dict({"texture": {"name": "flat", "size": "100um"},
                         "sweep": {"axes": {"texture": ["flat", "sinusoid"]}}})
    data = s.study_data({"texture": "sinusoid"})
    assert data["texture"] == {"name": "sinusoid"}


def test_latin_hypercube_points_within_bounds_and_reproducible():
    table = dict(design="lhs", points=20, seed=3, axes={"spacing": "100um:400um", "height": {"range": "5um:10um",
                                                                                               "log": False}})
    a, b = sweep(**table), sweep(**table)
    assert a.shape == (20,) and a.dims == ("point",)
    sp = np.asarray(a.point_values["spacing"])
    ht = np.asarray(a.point_values["height"])
    assert np.all((sp >= 100e-6) & (sp <= 400e-6)) and np.all((ht >= 5e-6) & (ht <= 10e-6))
    # Latin hypercube: one point in each of the 20 equal strata (log strata for the log axis)
    strata = np.floor((np.log(sp) - np.log(100e-6)) / (np.log(4) / 20)).astype(int)
    assert sorted(strata) == list(range(20))
    strata = np.floor((ht - 5e-6) / (5e-6 / 20)).astype(int)
    assert sorted(strata) == list(range(20))
    assert a.point_values == b.point_values
    assert sweep(**{**table, "seed": 4}).point_values != a.point_values


def test_points_design():
    s = sweep(design="points", point=[{"spacing": "150um", "height": "10um"}, {"spacing": "200um", "height": "5um"}])
    assert s.shape == (2,)
    assert s.assignment((1,)) == {"spacing": 200e-6, "height": 5e-6}


def test_signature_follows_the_inputs():
    a = sweep(axes={"spacing": ["100um", "200um"]})
    assert a.signature() == sweep(axes={"spacing": ["100um", "200um"]}).signature()
    assert a.signature() != sweep(axes={"spacing": ["100um", "300um"]}).signature()
    assert len(a.signature()) == 64


def test_angle_range_in_degrees():
    s = sweep_from_dict({"texture": {"name": "ridges", "width": "50um", "height": "10um", "spacing": "100um"},
                         "model": {"kind": "bem"},
                         "sweep": {"axes": {"direction": {"range": "0:90:3", "log": False}}}})
    np.testing.assert_allclose(s.axes[0].values, [0.0, math.pi / 4, math.pi / 2], atol=1e-15)


@pytest.mark.parametrize("table, message", [
    ({"axes": {}}, r"\[sweep.axes\] is empty"),
    ({"axes": {"spacing": "1um:2um:2"}, "desing": "grid"}, r"\[sweep\]: unknown key\(s\) desing"),
    ({"axes": {"spacing": "1um:2um:2"}, "design": "random"}, r"\[sweep\] design: must be one of grid, lhs, points"),
    ({"axes": {"spacing": "1um:2um:2"}, "chunk": 0}, r"\[sweep\] chunk: must be at least 1"),
    ({"axes": {"spacing": []}}, r"\[sweep.axes\] spacing: empty list of values"),
    ({"axes": {"spacing": ["1um", "1um"]}}, r"\[sweep.axes\] spacing: a value is given twice"),
    ({"axes": {"spacing": {"values": ["1um"], "range": "1um:2um:2"}}}, r"give values = \[...\] or range"),
    ({"axes": {"spacing": {"values": ["1um"], "step": 1}}}, r"unknown key\(s\) step"),
    ({"axes": {"spacing": {"range": "1um:2um:2", "log": "yes"}}}, r"spacing log: expected true or false"),
    ({"axes": {"spacing": "1um:2um"}}, r"expected START:STOP:COUNT, a list, or one value"),
    ({"axes": {"lattice": "a:b:2"}}, r"lattice takes a list of names"),
    ({"axes": {"spacing": "1um:2um:2"}, "design": "lhs"}, r"a Latin-hypercube axis takes bounds LOW:HIGH"),
    ({"axes": {"spacing": "2um:1um"}, "design": "lhs", "points": 4}, r"the bounds must satisfy LOW < HIGH"),
    ({"axes": {"spacing": "1um:2um"}, "design": "lhs"}, r"needs points = N"),
    ({"axes": {"spacing": "1um:2um"}, "design": "lhs", "points": 4, "seed": 1.5}, r"\[sweep\] seed: expected an integer"),
    ({"design": "points"}, r"needs \[\[sweep.point\]\] tables"),
    ({"design": "points", "point": [{"spacing": "1um"}, {"height": "1um"}]}, r"every point must give the same axes"),
    ({"axes": {"spacing": "1um:1mm:1000", "height": "1um:10um:1001"}}, r"1001000 points is more than the 1000000"),
    ({"axes": {"spacing": "1um:2um:2"}, "loads": "1N:2N:10001"}, r"\[sweep\] loads: 10001 loads asked for; at most 10000"),
    ({"axes": {"spacing": "1um:2um:2"}, "loads": "1N,-2N"}, r"\[sweep\] loads: loads must be positive"),
])
def test_bad_sweeps_named(table, message):
    with pytest.raises(FingerpadError, match=message):
        sweep(**table)


def test_the_base_study_is_checked():
    with pytest.raises(FingerpadError, match=r"\[model\] kind"):
        sweep_from_dict({**BASE, "model": {"kind": "fem"}, "sweep": {"axes": {"spacing": ["1um"]}}})


def test_sweep_file(tmp_path):
    path = tmp_path / "sweep.toml"
    path.write_text('[texture]\nname = "caps"\nradius = "50um"\nheight = "10um"\nspacing = "150um"\n'
                    '[sweep]\nloads = "1N:4N:3"\n[sweep.axes]\nspacing = ["100um", "200um"]\n')
    s = sweep_from_dict(read_sweep_file(str(path)))
    assert s.source == str(path) and s.shape == (2,)
    np.testing.assert_allclose(s.loads, [1.0, 2.0, 4.0], rtol=1e-12)
