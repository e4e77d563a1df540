"""Load curves and state pressures of a cell, on the Westergaard sinusoid (exact full contact)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import fingerpad as fp
from fingerpad.errors import FingerpadError

E = 1e6  # Pa
H = 2e-6  # amplitude, m: z = H (1 + cos(2 pi x / L))
L = 100e-6


@pytest.fixture(scope="module")
def solver():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tex = fp.make_texture("sinusoid", amplitude=H, wavelength=L, grid=32)
    return fp.HalfSpaceSolver(tex, E, tol=1e-10)


def test_curve_is_returned_in_the_order_asked(solver):
    pressures = [4e3, 1e3, 2e4]
    curve = fp.load_curve(solver, pressures)
    np.testing.assert_allclose(curve.mean_pressure, pressures, rtol=1e-9)
    order = np.argsort(pressures)
    assert np.all(np.diff(curve.contact_fraction[order]) >= 0)
    assert len(curve.results) == 3 and curve.results[1].mean_pressure == pytest.approx(1e3, rel=1e-9)
    assert curve.converged.all()
    np.testing.assert_allclose(curve.real_contact_area, curve.contact_fraction * solver.texture.area, rtol=1e-15)


def test_curve_without_fields(solver):
    calls = []
    curve = fp.load_curve(solver, [1e3, 2e3], keep_fields=False, progress=lambda i, n: calls.append((i, n)))
    assert curve.results == [] and calls == [(1, 2), (2, 2)]
    with pytest.raises(FingerpadError, match="holds no results"):
        curve.real_contact_area


@pytest.mark.parametrize("pressures, message", [([], "no pressures given"), ([1e3, -1.0], "positive and finite"),
                                                ([math.nan], "positive and finite")])
def test_bad_pressures(solver, pressures, message):
    with pytest.raises(FingerpadError, match=message):
        fp.load_curve(solver, pressures)


def test_full_contact_bracket_below_westergaard(solver):
    """Westergaard: full contact of a 1-D sinusoid of amplitude H at p* = pi E* H / L. "Full" here
    means at most 1 % open, reached just below p*."""
    p_star = math.pi * E * H / L
    br = fp.full_contact_pressure(solver, rtol=0.02)
    assert br.state == "full" and br.lower < br.upper and br.relative_width <= 0.02
    assert 0.8 * p_star < br.estimate <= p_star * 1.02
    assert br.estimate == pytest.approx(math.sqrt(br.lower * br.upper))
    assert solver.solve_pressure(br.upper).contact_state == "full"
    assert solver.solve_pressure(br.lower).contact_state != "full"


def test_transition_bracket_is_a_state_change(solver):
    br = fp.critical_pressure(solver, rtol=0.05)
    assert br.state == "transition"
    assert solver.solve_pressure(br.lower).contact_state == "asperity"
    assert solver.solve_pressure(br.upper).contact_state != "asperity"
    assert br.upper <= fp.full_contact_pressure(solver, rtol=0.05).upper


def test_state_search_refusals(solver):
    with pytest.raises(FingerpadError, match=r"rtol must lie in \(0, 1\)"):
        fp.critical_pressure(solver, rtol=0.0)
    patch = fp.Texture(np.zeros((8, 8)), (1e-4, 1e-4), periodic=False)
    with pytest.raises(FingerpadError, match="periodic cells only"):
        fp.critical_pressure(fp.HalfSpaceSolver(patch, E))
    flat = fp.make_texture("flat", size=1e-4, grid=8)
    with pytest.raises(FingerpadError, match="reached at any load"):
        fp.critical_pressure(fp.HalfSpaceSolver(flat, E))
