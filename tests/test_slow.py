"""Long validations (``make test-slow``): fine-grid convergence and large cells."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad.contact import HalfSpaceSolver
from fingerpad.micro.loadcurve import critical_pressure
from fingerpad.textures import Texture, spherical_caps

pytestmark = pytest.mark.slow
E = 1.0e6


def test_hertz_fine_grids() -> None:
    R, L, a_t = 1e-3, 0.6e-3, 0.15e-3
    force = 4 * E * a_t**3 / (3 * R)
    a = (3 * force * R / (4 * E)) ** (1 / 3)
    p0 = 3 * force / (2 * math.pi * a**2)
    for n in (256, 512):
        x = (np.arange(n) + 0.5) * L / n - L / 2
        X, Y = np.meshgrid(x, x, indexing="ij")
        tex = Texture(-(X**2 + Y**2) / (2 * R), (L, L), periodic=False)
        res = HalfSpaceSolver(tex, E).solve_pressure(force / L**2)
        assert res.converged
        assert abs(math.sqrt(res.real_contact_area / math.pi) / a - 1) < 0.003
        assert abs(res.max_pressure / p0 - 1) < 0.001


def test_unit_cell_grid_convergence() -> None:
    """psi(p) of a cap cell converges as the grid is refined: against a 512^2 reference the
    error falls at every refinement (measured: 3.5e-3, 2.5e-3, 1.1e-3 at worst)."""
    pressures = (2e3, 2e4, 1e5)
    psi = {}
    for n in (64, 128, 256, 512):
        solver = HalfSpaceSolver(spherical_caps(radius=50e-6, height=10e-6, spacing=150e-6, grid=n), E)
        psi[n] = np.array([solver.solve_pressure(p).contact_fraction for p in pressures])
    err = [np.abs(psi[n] - psi[512]) for n in (64, 128, 256)]
    assert np.all(err[1] < err[0]) and np.all(err[2] < err[1])
    assert err[2].max() < 0.002


@pytest.mark.parametrize("spacing", [70e-6, 100e-6, 200e-6])
def test_bem_transition_above_hertz_for_close_asperities(spacing: float) -> None:
    """Neighbouring asperities hold the skin up: the cell's transition pressure exceeds the
    isolated-asperity Hertz estimate (Eq. 3.3 with F = p lambda^2), the more so the closer."""
    R, h = 50e-6, 10e-6
    tex = spherical_caps(radius=R, height=h, spacing=spacing, grid=256)
    crit = critical_pressure(HalfSpaceSolver(tex, E), rtol=1e-3)
    p_hertz = (4 / 3) * E * math.sqrt(R * h**3) / spacing**2
    ratio = crit.estimate / p_hertz
    assert ratio > 1.0
    if spacing <= 100e-6:
        assert ratio > 1.3


def test_large_cell_both_formulations_agree() -> None:
    tex = spherical_caps(radius=50e-6, height=10e-6, spacing=150e-6, grid=1024)
    a = HalfSpaceSolver(tex, E, formulation="primal").solve_pressure(3e4)
    b = HalfSpaceSolver(tex, E, formulation="dual").solve_pressure(3e4)
    assert a.converged and b.converged
    assert abs(a.contact_fraction - b.contact_fraction) < 1e-5
