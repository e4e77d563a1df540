"""Elastic constants and the reduced modulus E1* of skin and counter-surface (Eq. 3.4)."""

from __future__ import annotations

import math

import pytest

import fingerpad as fp
from fingerpad.errors import FingerpadError


def test_eq_3_4_rigid_and_elastic():
    assert fp.reduced_modulus(0.3e6, 0.49) == pytest.approx(0.3e6 / (1 - 0.49**2), rel=1e-15)
    e = fp.reduced_modulus(0.3e6, 0.49, 0.5e9, 0.4)
    assert 1 / e == pytest.approx((1 - 0.49**2) / 0.3e6 + (1 - 0.4**2) / 0.5e9, rel=1e-15)
    # two equal materials: half the plane-strain modulus of one
    same = fp.reduced_modulus(1e6, 0.3, 1e6, 0.3)
    assert same == pytest.approx(1e6 / (1 - 0.09) / 2, rel=1e-15)


def test_stiffer_material_tends_to_rigid():
    rigid = fp.reduced_modulus(0.3e6, 0.49)
    values = [fp.reduced_modulus(0.3e6, 0.49, em, 0.35) for em in (1e6, 1e8, 1e10, 1e14)]
    assert values == sorted(values) and values[-1] == pytest.approx(rigid, rel=1e-7)
    # the default 0.5 GPa PE foil differs from rigid by about 0.1 %
    foil = fp.reduced_modulus(0.3e6, 0.49, 0.5e9, 0.4)
    assert 0 < 1 - foil / rigid < 2e-3


def test_materials_dataclass():
    m = fp.Materials()
    assert m.skin_modulus == 0.3e6 and m.skin_poisson == 0.49 and m.material_modulus is None
    assert m.reduced_modulus == pytest.approx(fp.reduced_modulus(0.3e6, 0.49))
    d = fp.Materials(material_modulus=1e9).as_dict()
    assert d["reduced_modulus"] == pytest.approx(fp.reduced_modulus(0.3e6, 0.49, 1e9, 0.35))
    assert set(d) == {"skin_modulus", "skin_poisson", "material_modulus", "material_poisson", "reduced_modulus"}


@pytest.mark.parametrize("kwargs, message", [
    (dict(skin_modulus=0.0), "skin modulus must be a positive number of pascals"),
    (dict(skin_modulus=math.inf), "skin modulus"),
    (dict(skin_poisson=0.6), r"skin Poisson ratio must lie in \(-1, 0.5\]"),
    (dict(skin_poisson=-1.0), "skin Poisson ratio"),
    (dict(material_modulus=-5.0), "material modulus"),
    (dict(material_modulus=1e9, material_poisson=0.51), "material Poisson ratio"),
])
def test_refusals(kwargs, message):
    with pytest.raises(FingerpadError, match=message):
        fp.Materials(**kwargs)


def test_incompressible_skin_is_allowed():
    assert fp.reduced_modulus(0.3e6, 0.5) == pytest.approx(0.4e6, rel=1e-15)
