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
