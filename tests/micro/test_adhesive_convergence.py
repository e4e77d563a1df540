"""Grid convergence of the adhesive unit cell past the transition (docs/model.md 6.6).

* the range of an adhesive cell follows the pixel and its attraction acts at the contact's edge
  only: the default cell's transition pressure and A_re / A_fr up to it converge with the grid
  at w 0.05 J/m^2 (within 2 % between grids 128 and 256);
* the grid's error estimate of an adhesive cell is the change from the half grid scaled to the
  error left at convergence order 1/2 (Maugis's parameter grows as the pixel's -1/2 power),
  while a non-adhesive cell's estimate is unchanged.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from fingerpad.materials import reduced_modulus
from fingerpad.micro.adhesive_cell import AdhesiveUnitCell
from fingerpad.micro.bem import BEMUnitCell
from fingerpad.micro.resolution import choose_grid, estimate_method, order_factor
from fingerpad.textures import spherical_caps

E = reduced_modulus(0.3e6, 0.49, 0.5e9, 0.4)  # the default finger on PE: 0.3945 MPa


def default_cell(grid: int):
    return spherical_caps(radius=100e-6, height=20e-6, spacing=175e-6, lattice="hexagonal", grid=grid)


def prepared(grid: int, work: float) -> AdhesiveUnitCell:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return AdhesiveUnitCell(default_cell(grid), E, work_of_adhesion=work, cache=False).prepare()


class SlowCell:
    """A stand-in cell converging with order 1/2 (the grid bookkeeping only, no solves)."""

    convergence_order = AdhesiveUnitCell.convergence_order
    solves = 0

    def __init__(self, texture, modulus, **options) -> None:
        self.texture = texture

    def prepare(self, *args, progress=None):
        return self

    def value(self) -> np.ndarray:
        # r_N = 1 + N^(-1/2): the change from the half grid is (2^(1/2) - 1) N^(-1/2), the error N^(-1/2)
        return np.array([1.0 + self.texture.shape[0] ** -0.5])


def test_adhesive_estimate_is_the_change_scaled_to_order_one_half() -> None:
    choice = choose_grid(default_cell, default_cell(32), E, (0.0, 0.0), SlowCell.value, target=0.02,
                         max_grid=64, cell_type=SlowCell)
    # at 64 the change alone, 4.4 %, understates the error left, 11 %; scaled it says 10.6 %
    change = abs(float(choice.cell.value()[0] / choice.coarse.value()[0] - 1.0))
    limit_error = float(choice.cell.value()[0] - 1.0) / float(choice.cell.value()[0])
    assert choice.error == pytest.approx(change / (2**0.5 - 1.0), rel=1e-12)
    assert choice.error >= 0.9 * limit_error > 2.4 * change / 1.1 and choice.met is False
    assert order_factor(AdhesiveUnitCell) == pytest.approx(2.4142, rel=1e-4)
    assert "q = 0.5" in estimate_method(AdhesiveUnitCell)
    # a non-adhesive cell's estimate and its report are today's, exactly
    assert order_factor(BEMUnitCell) == 1.0
    assert estimate_method(BEMUnitCell) == \
        "relative change from the half grid, |r_N / r_{N/2} - 1| (first-order convergence)"


@pytest.mark.slow
def test_transition_converges_with_the_grid_at_the_defaults() -> None:
    # w 0.05 J/m2, the range following the pixel, the attraction at the contact's edge only: the
    # skin reaches the base where it touches it, at a pressure the grid resolves (measured: 26.0,
    # 30.64 and 30.96 kPa on 64, 128 and 256, the zone of 8 pixels reaching the base at 64;
    # with the attraction reaching out of contact 23.6, 25.1 and 26.3 kPa, the skin jumping onto
    # the base from a range's distance)
    cells = [prepared(g, 0.05) for g in (128, 256)]
    transition = [c.transition_pressure for c in cells]
    assert abs(transition[1] / transition[0] - 1) < 0.02
    assert 28e3 < transition[1] < 32e3  # below the non-adhesive 32 kPa, above the old 25 kPa
    # A_re / A_fr on the way there: within 2 % between the grids (measured 0.3-0.9 %)
    psi = [c.contact_fraction(np.array([10e3, 20e3, 30e3])) for c in cells]
    assert np.max(np.abs(psi[1] / psi[0] - 1)) < 0.02
