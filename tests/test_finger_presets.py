"""The finger presets hold the numbers their comments state, and overrides keep the pad consistent."""

from __future__ import annotations

import math

import numpy as np
import pytest

import fingerpad as fp
from fingerpad import macro, meso
from fingerpad.errors import FingerpadError


def test_default_finger_documented_inputs():
    f = fp.get_finger("default")
    assert (f.radius, f.modulus, f.skin_modulus, f.skin_poisson) == (9e-3, 40e3, 0.3e6, 0.49)
    # the comment's worked numbers at 1 N: a = 5.53 mm, A_g = 95.9 mm^2, A_fr = 48.0 mm^2
    assert macro.HertzArea(f.radius, f.modulus).contact_radius(1.0) == pytest.approx(5.53e-3, rel=1e-3)
    assert f.gross_area(1.0) == pytest.approx(95.9e-6, rel=1e-3)
    assert f.ridge_area(1.0) == pytest.approx(48.0e-6, rel=2e-3)
    assert f.ridge_radius(1.0) == pytest.approx(math.sqrt(f.ridge_area(1.0) / math.pi), rel=1e-14)
    assert f.beta * 3 / 16 * 5.53e-3 / f.radius == pytest.approx(0.0115, rel=0.01)


def test_stiffening_preset_phi():
    f = fp.get_finger("stiffening")
    assert isinstance(f.gross, macro.DzidekArea)
    assert f.gross.phi == pytest.approx(0.23, abs=0.005)  # "phi = 0.23 /N"
    # the strain estimate stays below 1/C whenever a < R_fp (why C = 5 was chosen)
    a = macro.HertzArea(f.radius, f.modulus).contact_radius(np.array([0.1, 4.0]))
    assert np.all(5.0 * 0.2 * a / f.radius < 1)


def test_ridged_preset_fraction_over_the_exploration_loads():
    f = fp.get_finger("ridged")
    assert isinstance(f.ridges, meso.SinusoidalRidges)
    frac = np.asarray(f.ridge_area([0.1, 4.0])) / np.asarray(f.gross_area([0.1, 4.0]))
    # "A_fr/A_g runs from ~30 % at 0.1 N to ~73 % at 4 N"
    assert frac[0] == pytest.approx(0.30, abs=0.03) and frac[1] == pytest.approx(0.73, abs=0.03)


@pytest.mark.parametrize("name, radius, modulus", [("soft", 11e-3, 10e3), ("stiff", 7e-3, 100e3)])
def test_soft_and_stiff_pads(name, radius, modulus):
    f = fp.get_finger(name)
    assert (f.radius, f.modulus) == (radius, modulus)
    assert (f.tau0, f.alpha, f.beta) == (8.1e3, 0.1, 0.1), "interface properties kept from default"


def test_presets_case_insensitive_and_unknown():
    assert fp.get_finger(" Default ") is fp.FINGER_PRESETS["default"]
    with pytest.raises(FingerpadError, match="unknown finger preset 'thumb'; choose one of: default, soft"):
        fp.get_finger("thumb")


def test_overrides_keep_a_hertz_type_gross_model_in_step():
    f = fp.get_finger("stiffening").with_overrides(radius="8mm", modulus="50kPa")
    assert f.gross.radius == pytest.approx(8e-3) and f.gross.modulus == pytest.approx(50e3)
    assert f.gross.stiffening == 5.0
    # a gross model without radius (power law) is left alone
    p = fp.get_finger("default").with_overrides(gross=macro.PowerLawArea(1e-4, 0.3)).with_overrides(radius=8e-3)
    assert p.gross == macro.PowerLawArea(1e-4, 0.3)


@pytest.mark.parametrize("kwargs, message", [
    (dict(thumb=1), r"unknown finger parameter\(s\) thumb"),
    (dict(beta=1.5), r"beta: must lie in \[0, 1\]"),
    (dict(skin_poisson=0.7), "skin Poisson ratio"),
    (dict(ridges="half"), "ridges must be a ridge-area model"),
    (dict(gross=3), "gross must be a gross-area model"),
    (dict(radius="2N"), "radius"),
])
def test_override_refusals(kwargs, message):
    with pytest.raises(FingerpadError, match=message):
        fp.get_finger("default").with_overrides(**kwargs)


def test_as_dict_names_every_parameter():
    d = fp.get_finger("ridged").as_dict()
    assert d["name"] == "ridged" and d["radius"] == 9e-3 and "SinusoidalRidges" in d["ridge_model"]
    assert "HertzArea" in d["gross_model"]
    assert set(d) == {"name", "radius", "modulus", "gross_model", "ridge_model", "beta", "tau0", "alpha",
                      "skin_modulus", "skin_poisson"}
