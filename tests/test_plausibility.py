"""A value far outside its role's range warns once (a unit probably forgotten); inside, silence."""

from __future__ import annotations

import math
import warnings

import pytest

from fingerpad.errors import FingerpadError
from fingerpad.plausibility import RANGES, PlausibilityWarning, check_plausible


@pytest.mark.parametrize("role", sorted(RANGES))
def test_inside_the_range_is_silent(role):
    low, high, _, _ = RANGES[role]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for value in (low, high, math.sqrt(low * high), -math.sqrt(low * high), math.nan, math.inf):
            check_plausible(value, role, "--x")


def test_a_forgotten_unit_warns_with_a_hint():
    with pytest.warns(PlausibilityWarning, match=r"--radius = 50 m is very large for a texture length: .*"
                                                 r"did you forget a unit suffix"):
        check_plausible(50.0, "texture length", "--radius")
    with pytest.warns(PlausibilityWarning, match=r"very small for a load"):
        check_plausible(1e-4, "load", "--loads")


def test_dimensionless_roles_have_no_unit_hint():
    with pytest.warns(PlausibilityWarning) as record:
        check_plausible(20.0, "friction coefficient", "mu")
    assert len(record) == 1 and "unit suffix" not in str(record[0].message)
    assert "mu = 20 is very large" in str(record[0].message)


def test_unknown_role():
    with pytest.raises(FingerpadError, match="unknown plausibility role 'speed'"):
        check_plausible(1.0, "speed", "--v")


def test_every_range_is_ordered_and_positive():
    for role, (low, high, dimension, typical) in RANGES.items():
        assert 0 < low < high, role
        assert dimension in ("length", "force", "pressure", "none") and typical


def test_layered_skin_moduli_without_unit_warn():
    """`--skin-layer-modulus 0.4` (MPa meant) is 0.4 Pa: warned like `--skin-modulus 0.3`, while
    the layer's published range (1 MPa - 1 GPa in vitro) and the tissue's (kPa) stay silent."""
    from fingerpad.finger import FINGER_PARAMS

    params = {p.name: p for p in FINGER_PARAMS}
    with pytest.warns(PlausibilityWarning, match=r"--skin-layer-modulus = 400 mPa is very small .*unit suffix"):
        params["skin_layer_modulus"].parse("0.4", "--skin-layer-modulus")
    with pytest.warns(PlausibilityWarning, match=r"--skin-substrate-modulus = 40 Pa is very small"):
        params["skin_substrate_modulus"].parse("40", "--skin-substrate-modulus")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for text in ("0.4MPa", "1GPa", "5.7kPa"):
            params["skin_layer_modulus"].parse(text, "--skin-layer-modulus")
        for text in ("5.7kPa", "40kPa"):
            params["skin_substrate_modulus"].parse(text, "--skin-substrate-modulus")
