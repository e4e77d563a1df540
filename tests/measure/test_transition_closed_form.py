"""The closed-form skin modulus from the transition load (Eqs. 3.4, 3.6) and its inverse."""

from __future__ import annotations

import math

import pytest

import fingerpad as fp
from fingerpad import measure as m
from fingerpad.errors import FingerpadError

R, H, LAM = 50e-6, 18e-6, 100e-6


def test_inverse_of_eq_3_6_on_a_rigid_texture():
    es, area = 0.3e6, 8e-5
    e1 = fp.reduced_modulus(es, 0.49)
    fcrit = fp.critical_load_hertz(area, radius=R, height=H, spacing=LAM, reduced_modulus=e1)
    assert m.modulus_from_transition(fcrit, R, H, LAM, area) == pytest.approx(es, rel=1e-12)
    assert m.transition_load(es, R, H, LAM, area) == pytest.approx(fcrit, rel=1e-9)


def test_with_an_elastic_material_and_a_load_dependent_area():
    finger = fp.get_finger("default")
    es = 0.4e6
    fcrit = m.transition_load(es, R, H, LAM, finger, material_modulus=2e6, material_poisson=0.4)
    # Eq. 3.6 holds at that load with the finger's own A_fr(F)
    e1 = fp.reduced_modulus(es, 0.49, 2e6, 0.4)
    expected = 8 / 9 * e1 * math.sqrt(H**3 * R) * finger.ridge_area(fcrit) / LAM**2
    assert fcrit == pytest.approx(expected, rel=1e-8)
    back = m.modulus_from_transition(fcrit, R, H, LAM, finger, material_modulus=2e6, material_poisson=0.4)
    assert back == pytest.approx(es, rel=1e-8)
    # a callable A_fr(F) gives the same as the finger
    assert m.modulus_from_transition(fcrit, R, H, LAM, finger.ridge_area, material_modulus=2e6,
                                     material_poisson=0.4) == pytest.approx(back, rel=1e-14)


def test_softer_skin_reaches_the_transition_earlier():
    loads = [m.transition_load(es, R, H, LAM, 8e-5) for es in (0.1e6, 0.2e6, 0.4e6)]
    assert loads == sorted(loads)
    # constant A_fr: F_crit is proportional to E1*, itself to E_s on a rigid texture
    assert loads[2] / loads[1] == pytest.approx(2.0, rel=1e-8)


def test_refusals():
    with pytest.raises(FingerpadError, match="critical load must be positive"):
        m.modulus_from_transition(0.0, R, H, LAM, 8e-5)
    with pytest.raises(FingerpadError, match="ridge area must be positive"):
        m.modulus_from_transition(1.0, R, H, LAM, lambda f: 0.0)
    with pytest.raises(FingerpadError, match="stiffer than the counter-surface allows"):
        # a transition at a huge load on a soft material: E1* above what the material alone gives
        m.modulus_from_transition(1e3, R, H, LAM, 8e-5, material_modulus=1e4)
    with pytest.raises(FingerpadError, match="no transition load within"):
        m.transition_load(0.3e6, R, H, LAM, 8e-5, bracket=(1e-6, 1e-5))
