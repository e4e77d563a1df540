"""The vectorised coupling of many fingers (fingerpad.coupling.members), their areas as one
(fingerpad.coupling.loads.FingerStack) and the one search of their loads (centre_loads): every
member's numbers, its critical and full-contact loads included, are those of a predict_curve and
a load_at_centre_pressure of that member alone, to the bit; the search agrees with Brent's
method and with closed forms to LOAD_RTOL (issue 22, cost; issue 34, all members' loads at once)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad import textures
from fingerpad.coupling import predict_curve
from fingerpad.errors import FingerpadError
from fingerpad.finger import get_finger
from fingerpad.macro.pressure import disc_average
from fingerpad.meso import ConstantFractionRidges
from fingerpad.micro.bem import BEMUnitCell
from fingerpad.micro.response import PowerLawUnitCell
from fingerpad.coupling import critical_load
from fingerpad.coupling.loads import LOAD_RTOL, FingerStack, centre_loads
from fingerpad.coupling.members import predict_members
from fingerpad.macro import DzidekArea, HertzArea, PowerLawArea, TwoRegimePowerLawArea
from fingerpad.meso import PowerLawRidges, SinusoidalRidges
from fingerpad.population.members import member_full_contact_loads
from fingerpad.study.run import load_at_centre_pressure

LOADS = np.geomspace(0.1, 4.0, 9)


@pytest.fixture(scope="module")
def cell():
    tex = textures.spherical_caps(radius=50e-6, height=10e-6, spacing=100e-6, lattice="square", grid=32)
    return BEMUnitCell(tex, 0.3e6, cache=False).prepare(50.0, 2e6)


def _fingers(n: int, seed: int = 1) -> list:
    rng = np.random.default_rng(seed)
    base = get_finger("default")
    return [base.with_overrides(radius=float(r), modulus=float(m), skin_modulus=float(e), tau0=float(t),
                                ridges=ConstantFractionRidges(float(c)))
            for r, m, e, t, c in zip(rng.uniform(7e-3, 11e-3, n), rng.uniform(10e3, 100e3, n),
                                     rng.uniform(0.2e6, 0.5e6, n), rng.uniform(4e3, 12e3, n),
                                     rng.uniform(0.1, 0.7, n), strict=True)]


def test_members_equal_predict_curve_per_member_bit_for_bit(cell, monkeypatch):
    import fingerpad.coupling.members as members

    monkeypatch.setattr(members, "BLOCK", 4)
    fingers = _fingers(11)  # more than one block, and a last block that is not full
    moduli = [f.micro_modulus(None) for f in fingers]
    got = predict_members(LOADS, fingers, cell, moduli)
    for finger, e, curve in zip(fingers, moduli, got, strict=True):
        want = predict_curve(LOADS, finger, cell.at_modulus(e))
        for key, value in want.as_dict().items():
            other = getattr(curve, key)
            if value is None:
                assert other is None, key
            else:
                np.testing.assert_array_equal(np.asarray(other), np.asarray(value), err_msg=key)
        assert math.isfinite(curve.critical_load)
        # the one search against Brent's method per finger (coupling.critical_load)
        brent = critical_load(cell.at_modulus(e), finger.ridge_area_law())
        assert curve.critical_load == pytest.approx(brent, rel=LOAD_RTOL)
    # the members span asperity contact and the transition: discs over the transition bracket's
    # nodes (the interpolant's kinks) are exercised
    assert any(c.centre_past_transition.any() for c in got) and any(not c.centre_past_transition.all() for c in got)


def test_full_contact_loads_equal_the_per_member_search(cell):
    fingers = _fingers(5, seed=2)
    pressures = [cell.at_modulus(f.micro_modulus(None)).full_contact_pressure for f in fingers]
    want = [load_at_centre_pressure(f, p) for f, p in zip(fingers, pressures, strict=True)]
    np.testing.assert_array_equal(member_full_contact_loads(fingers, pressures), want)
    assert math.isinf(member_full_contact_loads(fingers[:1], [math.inf])[0])


def test_other_cells_run_per_member():
    fingers = _fingers(3)
    pl = PowerLawUnitCell(1e-4, 0.8)
    got = predict_members(LOADS, fingers, pl)
    for finger, curve in zip(fingers, got, strict=True):
        np.testing.assert_array_equal(curve.mu, predict_curve(LOADS, finger, pl).mu)
    with pytest.raises(FingerpadError, match="2 unit cells for 3 fingers"):
        predict_members(LOADS, fingers, [pl, pl])
    with pytest.raises(FingerpadError, match="moduli"):
        predict_members(LOADS, fingers, BEMUnitCell.__new__(BEMUnitCell), [1.0])


def test_disc_average_per_disc_breakpoints_equal_one_call_per_disc():
    """The 2-D breakpoints of disc_average (one row per disc) give each disc's own 1-D result, and
    the evaluation skips only nodes of zero weight (an exact closed form still holds)."""
    peaks = np.array([1e3, 5e3, 2e4, 8e4])
    kinks = np.array([[2e3, 3e4], [4e3, 6e4], [1e3, 1e5], [3e3, 4e4]])

    def psi(p):  # a kink-free element-wise function: the split alone differs between the discs
        return np.minimum(p / 1e5, 1.0) ** 0.7

    rows = disc_average(psi, peaks, kinks)
    for i, peak in enumerate(peaks):
        assert rows[i] == disc_average(psi, [peak], tuple(kinks[i]))[0]
    # psi = c p^m over the whole disc: 2 pi a^2 c (1.5 p_mean)^m / (m + 2) / (pi a^2)
    c, m = 1e-4, 0.8
    got = disc_average(lambda p: c * p**m, peaks, (5e3,))
    np.testing.assert_allclose(got, 2 * c * peaks**m / (m + 2), rtol=1e-13)


def _hertz_centre_load(finger, p):
    """Closed form of 1.5 F / (c pi (3 F R / 4 E)^(2/3)) = p (Hertz pad, constant ridge fraction)."""
    c = finger.ridges.fraction
    return (p * c * math.pi * (3.0 * finger.radius / (4.0 * finger.modulus)) ** (2.0 / 3.0) / 1.5) ** 3


def test_centre_loads_closed_form_and_independent_of_company():
    fingers = _fingers(40, seed=3)
    rng = np.random.default_rng(4)
    pressures = rng.uniform(1e3, 1e6, len(fingers))
    got = centre_loads(FingerStack(fingers), pressures)
    want = [_hertz_centre_load(f, p) for f, p in zip(fingers, pressures, strict=True)]
    np.testing.assert_allclose(got, want, rtol=1e-13, atol=0)
    # each finger's load does not depend on the others in the search (alone, or shuffled)
    order = rng.permutation(len(fingers))
    shuffled = centre_loads(FingerStack([fingers[i] for i in order]), pressures[order])
    np.testing.assert_array_equal(shuffled, got[order])
    alone = centre_loads(FingerStack(fingers[7:8]), pressures[7:8])
    assert alone[0] == got[7]


def test_centre_loads_edges():
    fingers = _fingers(5, seed=5)
    # inf: never reached; NaN: 0 Pa, NaN, and a pressure the centre never reaches in 1e-9..1e9 N
    # (Hertz: 1.5 F / A_fr grows as F^(1/3), ~1e-2 Pa at 1e-9 N for these pads)
    got = centre_loads(FingerStack(fingers), [math.inf, 0.0, math.nan, 1e-9, 2e4])
    assert math.isinf(got[0]) and np.isnan(got[1:4]).all()
    assert got[4] == pytest.approx(_hertz_centre_load(fingers[4], 2e4), rel=1e-13)
    with pytest.raises(FingerpadError, match="3 pressures for 5 fingers"):
        centre_loads(FingerStack(fingers), [1.0, 2.0, 3.0])


def _varied(model, n: int, rng, fields: dict[str, tuple[float, float]]) -> list:
    import dataclasses

    return [dataclasses.replace(model, **{k: float(rng.uniform(*v)) for k, v in fields.items()}) for _ in range(n)]


def test_finger_stack_rows_equal_each_finger_bit_for_bit():
    """Every model class that declares STACKS, with its fields varied between fingers: each row
    of the stack is that finger's areas_checked, to the bit; models that do not stack run per row."""
    rng = np.random.default_rng(6)
    base = get_finger("default")
    n = 64
    gross_sets = {
        "hertz": _varied(HertzArea(9e-3, 40e3), n, rng, {"radius": (7e-3, 11e-3), "modulus": (1e4, 1e5)}),
        "dzidek": _varied(DzidekArea(9e-3, 40e3, 5.0), n, rng, {"radius": (7e-3, 11e-3), "stiffening": (1.0, 5.0),
                                                                 "exponent": (2.0, 4.0)}),
        "power_law": _varied(PowerLawArea(1e-4, 0.6), n, rng, {"coefficient": (5e-5, 2e-4), "exponent": (0.4, 0.8)}),
        "two_regime": _varied(TwoRegimePowerLawArea(1e-4, 0.4, 0.2), n, rng,
                              {"coefficient": (5e-5, 2e-4), "exponent_low": (0.3, 0.5), "break_load": (1.0, 3.0)}),
    }
    ridge_sets = {
        "constant": [ConstantFractionRidges(float(c)) for c in rng.uniform(0.1, 0.7, n)],
        "power_law": _varied(PowerLawRidges(5e-5, 0.5), n, rng, {"coefficient": (2e-5, 8e-5), "exponent": (0.3, 0.7)}),
        "sinusoidal": [SinusoidalRidges(wavelength=float(w), modulus=100e3, amplitude=30e-6) for w in rng.uniform(0.4e-3, 0.5e-3, n)],
    }
    loads = np.tile(np.geomspace(0.05, 8.0, 13), (n, 1))
    for gname, gross in gross_sets.items():
        for rname, ridges in ridge_sets.items():
            fingers = [base.with_overrides(gross=g, ridges=r, radius=getattr(g, "radius", base.radius),
                                           modulus=getattr(g, "modulus", base.modulus))
                       for g, r in zip(gross, ridges, strict=True)]
            stacked_g, stacked_r = FingerStack(fingers).areas(loads)
            for i, finger in enumerate(fingers):
                g, r = finger.areas_checked(loads[i])
                np.testing.assert_array_equal(stacked_g[i], g, err_msg=f"{gname}/{rname} gross")
                np.testing.assert_array_equal(stacked_r[i], r, err_msg=f"{gname}/{rname} ridge")


class _PatchRidges:
    """Half the gross area, refused above 1e3 N (as a fingerprint patch too small for the load)."""

    def area(self, load, gross_area):
        if np.any(np.asarray(load) > 1e3):
            raise FingerpadError("the gross contact reaches the edge of the patch")
        return 0.5 * np.asarray(gross_area, float)


def test_centre_loads_of_a_finger_without_an_area_at_some_load():
    """A model that refuses a trial load (the bracket reaches 1e9 N) gives that finger no load, as
    a single finger's search reports it, and leaves the others' bits as they are alone."""
    fingers = _fingers(3, seed=8)
    patch = fingers[1].with_overrides(ridges=_PatchRidges())
    stack = FingerStack([fingers[0], patch, fingers[2]])
    got = centre_loads(stack, [2e4, 2e4, 2e4])
    assert np.isnan(got[1])
    assert math.isnan(centre_loads(FingerStack([patch]), [2e4])[0])
    for i in (0, 2):
        assert got[i] == centre_loads(FingerStack([fingers[i]]), [2e4])[0]
