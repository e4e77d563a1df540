"""The vectorised coupling of many fingers (fingerpad.coupling.members) and the members' full-contact
loads (fingerpad.population.members): every member's numbers are those of a predict_curve and a
load search per member, to the bit (issue 22, cost)."""

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
from fingerpad.coupling.members import predict_members
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
