"""The members' full-contact loads (fingerpad.population.members): those of the per-member search
of a plain prediction, to the bit."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad import textures
from fingerpad.finger import get_finger
from fingerpad.meso import ConstantFractionRidges
from fingerpad.micro.bem import BEMUnitCell
from fingerpad.population.members import member_full_contact_loads
from fingerpad.study.run import load_at_centre_pressure


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


def test_full_contact_loads_equal_the_per_member_search(cell):
    fingers = _fingers(5, seed=2)
    pressures = [cell.at_modulus(f.micro_modulus(None)).full_contact_pressure for f in fingers]
    want = [load_at_centre_pressure(f, p) for f, p in zip(fingers, pressures, strict=True)]
    np.testing.assert_array_equal(member_full_contact_loads(fingers, pressures), want)
    assert math.isinf(member_full_contact_loads(fingers[:1], [math.inf])[0])
