"""The unit-cell interface: the power-law test cell, the checks the coupling relies on, root finding."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad import micro
from fingerpad.errors import FingerpadError
from fingerpad.micro import response


def test_power_law_cell():
    cell = micro.PowerLawUnitCell(coefficient=1e-3, exponent=0.5)
    assert cell.full_contact_pressure == pytest.approx(1e6, rel=1e-12)  # c^(-1/m)
    assert cell.transition_pressure == cell.full_contact_pressure
    np.testing.assert_allclose(cell.contact_fraction(np.array([0.0, 1e4, 1e6, 4e6])), [0.0, 0.1, 1.0, 1.0])
    assert cell.contact_fraction(np.array([-5.0]))[0] == 0.0
    assert micro.PowerLawUnitCell(1e-3, 0.5, transition=1e4).transition_pressure == 1e4
    with pytest.raises(FingerpadError, match="must not exceed the full-contact pressure"):
        micro.PowerLawUnitCell(1e-3, 0.5, transition=2e6)
    with pytest.raises(FingerpadError, match="exponent m"):
        micro.PowerLawUnitCell(1e-3, 0.0)


def test_check_cell():
    pt, pf, kinks = response.check_cell(micro.PowerLawUnitCell(1e-3, 0.5, transition=1e4))
    assert (pt, pf) == (1e4, pytest.approx(1e6)) and kinks[:2] == (pt, pf)
    hertz = micro.HertzUnitCell(50e-6, 10e-6, 150e-6, 0.4e6)
    assert response.check_cell(hertz)[2][-1] == hertz.saturation_pressure
    with pytest.raises(FingerpadError, match="is not a unit-cell response"):
        response.check_cell(object())

    class Backwards:
        transition_pressure = 10.0
        full_contact_pressure = 1.0

        def contact_fraction(self, p):
            return p

    with pytest.raises(FingerpadError, match="is below its transition"):
        response.check_cell(Backwards())

    class Negative(Backwards):
        transition_pressure = -1.0

    with pytest.raises(FingerpadError, match="must not be negative"):
        response.check_cell(Negative())


def test_checked_psi_refuses_bad_arrays():
    class Cell:
        transition_pressure = 1.0
        full_contact_pressure = 2.0

        def __init__(self, f):
            self.f = f

        def contact_fraction(self, p):
            return self.f(p)

    p = np.array([1.0, 2.0])
    assert np.array_equal(response.checked_psi(Cell(lambda p: p / 2))(p), [0.5, 1.0])
    # round-off just outside [0, 1] is clipped, more is an error
    assert response.checked_psi(Cell(lambda p: p * 0 + 1 + 1e-12))(p).max() == 1.0
    with pytest.raises(FingerpadError, match="outside \\[0, 1\\]"):
        response.checked_psi(Cell(lambda p: p))(p)
    with pytest.raises(FingerpadError, match="returned a bad array"):
        response.checked_psi(Cell(lambda p: p[:1]))(p)
    with pytest.raises(FingerpadError, match="returned a bad array"):
        response.checked_psi(Cell(lambda p: p * np.nan))(p)


def test_solve_load_finds_the_root_to_round_off():
    root = response.solve_load(lambda f: f**3 - 2.0, (1e-3, 1e3), "test", lambda lo, hi: "")
    assert root == pytest.approx(2 ** (1 / 3), rel=1e-14)
    assert response.solve_load(lambda f: f - 1.0, (1.0, 2.0), "x", lambda lo, hi: "") == 1.0
    with pytest.raises(FingerpadError, match=r"no test between 1 N and 2 N: why"):
        response.solve_load(lambda f: f + 1.0, (1.0, 2.0), "test", lambda lo, hi: "why")
    with pytest.raises(FingerpadError, match="0 < low < high"):
        response.solve_load(lambda f: f, (2.0, 1.0), "x", lambda lo, hi: "")
    with pytest.raises(FingerpadError, match="0 < low < high"):
        response.solve_load(lambda f: f, (1.0, math.inf), "x", lambda lo, hi: "")


def test_area_function():
    assert response.area_function(2e-4)(5.0) == 2e-4
    assert response.area_function(lambda f: 1e-4 * f)(2.0) == pytest.approx(2e-4)
    with pytest.raises(FingerpadError, match="ridge area"):
        response.area_function(0.0)
    with pytest.raises(FingerpadError, match=r"A_fr\(1 N\) = nan is not a positive area"):
        response.area_function(lambda f: math.nan)(1.0)
