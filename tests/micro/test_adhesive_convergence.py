"""Grid convergence of the adhesive unit cell past the transition (docs/model.md 6.6).

* the range of an adhesive cell follows the pixel, and what the cell gives past the transition
  (the skin's jump onto the texture's base) moves with the range, not with the pixel: at a
  fixed range the default cell's transition pressure converges with the grid, with the range
  following the pixel it does not, and it rises toward the non-adhesive one as the range
  shrinks;
* the grid's error estimate of an adhesive cell says so: the change from the half grid scaled to
  the error left at convergence order 1/4, while a non-adhesive cell's estimate is unchanged.
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


def transition(grid: int, work: float, range_: float | None) -> float:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        cell = AdhesiveUnitCell(default_cell(grid), E, work_of_adhesion=work, adhesion_range=range_, cache=False)
        return cell.prepare().transition_pressure


class SlowCell:
    """A stand-in cell converging with order 1/4 (the grid bookkeeping only, no solves)."""

    convergence_order = AdhesiveUnitCell.convergence_order
    solves = 0

    def __init__(self, texture, modulus, **options) -> None:
        self.texture = texture

    def prepare(self, *args, progress=None):
        return self

    def value(self) -> np.ndarray:
        # r_N = 1 + N^(-1/4): the change from the half grid is (2^(1/4) - 1) N^(-1/4), the error N^(-1/4)
        return np.array([1.0 + self.texture.shape[0] ** -0.25])


def test_adhesive_estimate_is_the_change_scaled_to_order_one_quarter() -> None:
    choice = choose_grid(default_cell, default_cell(32), E, (0.0, 0.0), SlowCell.value, target=0.02,
                         max_grid=64, cell_type=SlowCell)
    # at 64 the change alone, 4.7 %, understates the error left, 26 %; scaled it says 25 %
    change = abs(float(choice.cell.value()[0] / choice.coarse.value()[0] - 1.0))
    limit_error = float(choice.cell.value()[0] - 1.0) / float(choice.cell.value()[0])
    assert choice.error == pytest.approx(change / (2**0.25 - 1.0), rel=1e-12)
    assert choice.error >= 0.9 * limit_error > 5 * change / 1.1 and choice.met is False
    assert order_factor(AdhesiveUnitCell) == pytest.approx(5.2852, rel=1e-4)
    assert "q = 0.25" in estimate_method(AdhesiveUnitCell)
    # a non-adhesive cell's estimate and its report are today's, exactly
    assert order_factor(BEMUnitCell) == 1.0
    assert estimate_method(BEMUnitCell) == \
        "relative change from the half grid, |r_N / r_{N/2} - 1| (first-order convergence)"


@pytest.mark.slow
def test_transition_converges_at_a_fixed_range_not_with_the_range_following_the_pixel() -> None:
    # w 0.3 J/m2: the range the grid 64 resolves, 1.63 um, is used as given at 64 and 128
    fixed = [transition(g, 0.3, 1.627e-6) for g in (64, 128)]
    moving = [transition(g, 0.3, None) for g in (64, 128)]
    assert abs(fixed[1] / fixed[0] - 1) < 0.02  # measured 0.5 %
    assert moving[1] / moving[0] - 1 > 0.3  # measured 45 % (7.3 -> 10.6 kPa)
    # on one grid (128) the transition rises as the range shrinks: 2.3, 1.63 and 1.15 um (the
    # last the one the grid resolves) give 4.1, 7.3 and 10.6 kPa, toward the non-adhesive 32 kPa
    longer = transition(128, 0.3, 2.3e-6)
    assert longer < fixed[1] < moving[1] < 32e3
    assert math.isfinite(longer) and fixed[1] / longer > 1.3
