"""Sweep axes: what each name sets in the study, its kind and unit, and how its values are read."""

from __future__ import annotations

import math

import pytest

from fingerpad.design.axes import resolve_axis
from fingerpad.errors import FingerpadError


@pytest.mark.parametrize("name, family, where, kind", [
    ("spacing", "caps", ("texture", "spacing"), "length"),
    ("lattice", "caps", ("texture", "lattice"), "choice"),
    ("orientation", "ellipsoids", ("texture", "orientation"), "angle"),
    ("texture", "caps", ("texture", "name"), "choice"),
    ("material_modulus", "caps", ("material", "modulus"), "pressure"),
    ("material.poisson", "caps", ("material", "poisson"), "none"),
    ("direction", "ridges", ("model", "direction"), "angle"),
    ("finger", "caps", ("finger", "preset"), "choice"),
    ("finger.radius", "caps", ("finger", "radius"), "length"),
    ("finger.modulus", "caps", ("finger", "modulus"), "pressure"),
    ("skin_modulus", "caps", ("finger", "skin_modulus"), "pressure"),
    ("beta", "caps", ("finger", "beta"), "none"),
])
def test_axis_targets(name, family, where, kind):
    axis = resolve_axis(name, family)
    assert (axis.section, axis.key) == where
    assert axis.kind == kind
    assert axis.numeric == (kind != "choice")


def test_radius_alone_is_the_texture_s():
    axis = resolve_axis("radius", "caps")
    assert (axis.section, axis.key) == ("texture", "radius")


def test_parameter_of_some_family_when_the_family_is_swept():
    axis = resolve_axis("semi_axis_x", None)
    assert (axis.section, axis.key, axis.kind) == ("texture", "semi_axis_x", "length")


def test_unknown_axis_lists_what_can_be_swept():
    with pytest.raises(FingerpadError, match=r"\[sweep\] axis 'spasing' is not a parameter of texture 'caps' .*"
                                             r"\(axes: .*spacing.*\)"):
        resolve_axis("spasing", "caps")
    with pytest.raises(FingerpadError, match="is not a parameter"):
        resolve_axis("radius", "ridges")  # ridges have no radius, and the pad's is finger.radius


def test_units_labels_and_display():
    spacing = resolve_axis("spacing", "caps")
    assert spacing.unit == "m" and spacing.label() == "spacing (um)"
    assert spacing.display(150e-6) == pytest.approx(150.0)
    modulus = resolve_axis("material_modulus", "caps")
    assert modulus.unit == "Pa" and modulus.label() == "material_modulus (kPa)"
    assert modulus.display(2e6) == pytest.approx(2000.0)
    direction = resolve_axis("direction", "ridges")
    assert direction.unit == "rad" and direction.display(math.pi / 2) == pytest.approx(90.0)
    assert resolve_axis("beta", "caps").label() == "beta"


def test_parse_values():
    spacing = resolve_axis("spacing", "caps")
    assert spacing.parse("150um", "x") == pytest.approx(150e-6)
    assert spacing.parse(2e-4, "x") == 2e-4
    with pytest.raises(FingerpadError, match="x"):
        spacing.parse("2N", "x")
    with pytest.raises(FingerpadError, match="x: expected a length, got True"):
        spacing.parse(True, "x")
    lattice = resolve_axis("lattice", "caps")
    assert lattice.parse(" Hexagonal ", "x") == "hexagonal"
    with pytest.raises(FingerpadError, match="x: must be one of square, hexagonal, got 'round'"):
        lattice.parse("round", "x")
    # angles: degrees unless a unit says otherwise, kept in radians
    direction = resolve_axis("direction", "ridges")
    assert direction.parse(90, "x") == pytest.approx(math.pi / 2)
    assert direction.parse("0.5rad", "x") == pytest.approx(0.5)
    assert direction.study_value(0.5) == "0.5rad"
    assert spacing.study_value(1e-4) == 1e-4


def test_count_axis_takes_integers():
    ny = resolve_axis("ny", "ridges")
    assert ny.kind == "count" and ny.unit == ""
    assert ny.parse("16", "x") == 16 and isinstance(ny.parse(8.0, "x"), int)
    with pytest.raises(FingerpadError, match="x: expected an integer, got 2.5"):
        ny.parse(2.5, "x")
