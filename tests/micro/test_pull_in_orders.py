"""A pulled-in transition on textures other than the default cell (docs/model.md 6.6.1;
benchmarks/pull_in_orders.py measures them).

* Johnson's adhesive sinusoid jumps into full contact at a fold of its loading branch, from a
  gap of 3-10 ranges (so ``pulled_in``), but its jump converges with the branch, faster than the
  orders 1 and 3/2 the extrapolation assumes: the changes of the grid's own transition shrink by
  0.11-0.27 per doubling. The rule reads that from the grids and reports the grid's own, whose
  estimate covers the converged value; extrapolating at order 1 only amplified the coarse
  grids' error (grid 128: 23.71 kPa where the own 24.59 and the converged 24.67 kPa);
* three grids cannot tell that form from the assumed one: the estimate reaches to the grid's own.
"""

from __future__ import annotations

import math
import warnings

import pytest
from scipy.optimize import minimize_scalar

from fingerpad.materials import reduced_modulus
from fingerpad.micro.adhesive_cell import AdhesiveUnitCell
from fingerpad.micro.pull_in import FADE_RATIO, FOLD_RATIO, extrapolated_states, richardson
from fingerpad.textures import sinusoid

E = reduced_modulus(0.3e6, 0.49, 0.5e9, 0.4)  # the default finger on PE: 0.3945 MPa
LAM, H, ALPHA = 200e-6, 10e-6, 0.3  # one wavelength, amplitude; Johnson's alpha
W = ALPHA**2 * math.pi**2 * H**2 * E / (2 * LAM)  # alpha = (sqrt 2 / pi)(lambda / h) sqrt(w / (E* lambda))


def johnson_jump() -> float:
    """Pa: the maximum of p* (sin^2 t - alpha sqrt(tan t)), where the sinusoid jumps into full contact."""
    res = minimize_scalar(lambda t: -(math.sin(t) ** 2 - ALPHA * math.sqrt(math.tan(t))),
                          bounds=(1e-9, math.pi / 2 - 1e-9), method="bounded", options={"xatol": 1e-12})
    return -float(res.fun) * math.pi * E * H / LAM


@pytest.fixture(scope="module")
def cells() -> dict[int, AdhesiveUnitCell]:
    # grids 16-256 of one wavelength, one point along y (the same brackets as 8): 2.8 s at a load of 3
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the coarse grids are coarse on purpose
        return {g: AdhesiveUnitCell(sinusoid(amplitude=H, wavelength=LAM, grid=g, ny=1), E, work_of_adhesion=W,
                                    cache=False).prepare() for g in (16, 32, 64, 128, 256)}


def test_sinusoid_fold_is_reported_as_the_grid_converges(cells) -> None:
    own = {g: c.own_state_pressure("transition") for g, c in cells.items()}
    assert all(c.pulled_in for c in cells.values())  # jumps from 3-9 ranges of gap
    # a fold: the gap before the jump is a length of its own (4.2-4.4 um on 64-256), so its number
    # of ranges grows as the range follows the pixel (on the default caps it stays near 3)
    gaps = [cells[g].pull_in_ranges * cells[g].adhesion_range for g in (64, 128, 256)]
    assert max(gaps) / min(gaps) < 1.1 and cells[256].pull_in_ranges > 1.5 * cells[64].pull_in_ranges
    # the grid's own converges (measured 24.29, 24.59, 24.67 kPa on 64, 128, 256, and the same
    # bracket of 1e-3 on 512, 1024, 2048): 256's is the converged value
    converged = own[256]
    # ... 2.7 % above Johnson's closed form, on every grid from 256 to 2048: the regularised
    # loading branch's own offset (about 1 % of p*, docs/model.md 6.6.1), not the grid's
    assert 0.0 < converged / johnson_jump() - 1.0 < 0.03
    for grid in (64, 128, 256):
        p, compared, error = extrapolated_states(cells[grid], cells[grid // 2], cells[grid // 4],
                                                 cells.get(grid // 8))["transition"]
        if grid < 256:
            # the estimate covers the distance to the converged value (64: 20 % off, estimated 22 %;
            # 128: 0.3 % off, estimated 3.7 %)
            assert abs(p / converged - 1.0) <= error
        if grid >= 128:
            # four grids show the fold: the grid's own is reported, nearer the converged value than
            # any extrapolation at order 1 (23.71 kPa at 128), its estimate reaching to the
            # extrapolation and the half grid's
            assert abs(own[grid] - own[grid // 2]) <= FOLD_RATIO * abs(own[grid // 2] - own[grid // 4])
            assert p == own[grid]
            assert error == pytest.approx(max(abs(p / own[grid // 2] - 1.0),
                                              abs(p / richardson([own[grid // g] for g in (1, 2, 4)]) - 1.0),
                                              cells[grid].rtol), rel=1e-12)


class Stand:
    """A stand-in pulled-in cell whose transition is ``p`` (Pa): the rule's bookkeeping only."""

    rtol = 1e-3
    pulled_in = True

    def __init__(self, p: float, gap: float = math.nan) -> None:
        self.p, self.pull_in_ranges = p, gap
        self.transition = self.full = (p, p)

    def own_state_pressure(self, name: str) -> float:
        return self.p

    @property
    def texture(self):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return sinusoid(amplitude=H, wavelength=LAM, grid=16, ny=1)  # too coarse to be halved: no eighth


def test_fold_and_three_grid_rules_cover_the_limit() -> None:
    # an error of order 3 (a fold converging with its branch): the grid's own, its estimate the
    # change from the half grid or the distance to the extrapolation at orders 1, 3/2 (2.7 % low here)
    def fold(n: int) -> float:
        return 20e3 - 2e3 * (32 / n) ** 3

    chain = [Stand(fold(128 // 2**i)) for i in range(4)]
    p, compared, error = extrapolated_states(*chain)["transition"]
    assert p == chain[0].p and abs(p / 20e3 - 1) <= error
    assert abs(richardson([c.p for c in chain[:3]]) / 20e3 - 1) > 0.02
    # the same fold on three grids (no eighth): not told from the assumed form by its changes
    # alone unless they shrink fast enough; the estimate reaches to the grid's own, which is
    # where the limit lies
    def slow_fold(n: int) -> float:
        return 20e3 - 4e3 * (32 / n) ** 0.4 if n < 64 else 20e3 - 400.0 * (64 / n) ** 3

    chain = [Stand(slow_fold(64 // 2**i)) for i in range(3)]
    p, compared, error = extrapolated_states(*chain)["transition"]
    assert compared == chain[0].p and abs(p / 20e3 - 1) <= error


def test_fading_pull_in_reaches_to_the_grids_own() -> None:
    # four grids of the assumed form, exact for it (the default cell's own 14.49, 9.49, 3.97,
    # 0.98 kPa on 128-16 as the tall caps' would be): where the base's gap before the jump holds
    # from grid to grid (the default cell: 3.06, 3.29 ranges on 128, 64) the estimate is the
    # assumed form's; where it falls (the tall caps: 1.54, 2.81; touched from 256 on, whose
    # transition, 22.7 kPa, lies 14 % below the extrapolation from 128) it reaches to the own
    def law(n: int) -> float:
        return 22.78e3 - 3.07e3 * (512 / n) + 0.50e3 * (512 / n) ** 1.5

    held = [Stand(law(128 // 2**i), gap) for i, gap in enumerate((3.06, 3.29, 2.95, 2.26))]
    p, compared, error = extrapolated_states(*held)["transition"]
    assert p == pytest.approx(22.78e3, rel=1e-12) and error == held[0].rtol
    fading = [Stand(law(128 // 2**i), gap) for i, gap in enumerate((1.54, 2.81, 3.23, 2.75))]
    assert fading[0].pull_in_ranges < FADE_RATIO * fading[1].pull_in_ranges
    p2, compared2, error2 = extrapolated_states(*fading)["transition"]
    assert p2 == p and compared2 == fading[0].p and error2 == pytest.approx(p / fading[0].p - 1, rel=1e-12)
    assert error2 >= abs(p / 22.7e3 - 1)  # covers the touched limit of the tall caps


@pytest.mark.slow
def test_square_lattice_takes_the_assumed_form() -> None:
    # the default caps on a square lattice at w 0.3 J/m2, grids 32-256 (~1-2 min): pulled in from
    # 2-4 ranges as the default cell; on 64-512 p* - a dx + b dx^(3/2) fits within 2 Pa (512's own
    # transition 17098.5 Pa, measured: 6 min), every other pair of orders 10 times worse or more.
    # The report at 256 (four grids) lies within its estimate of that limit
    from fingerpad.textures import spherical_caps

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cells = {g: AdhesiveUnitCell(spherical_caps(radius=100e-6, height=20e-6, spacing=175e-6, lattice="square",
                                                    grid=g), E, work_of_adhesion=0.3, cache=False).prepare()
                 for g in (32, 64, 128, 256)}
    assert all(c.pulled_in for c in cells.values())
    own = {g: c.own_state_pressure("transition") for g, c in cells.items()}
    limit = richardson([17098.5, own[256], own[128]])  # 19.34 kPa
    p, _, error = extrapolated_states(cells[256], cells[128], cells[64], cells[32])["transition"]
    assert abs(p / limit - 1) <= error < 0.03 and abs(p / limit - 1) < 0.005
    # the grid's own is 21 % low there; the first-order extrapolation alone 5 % low
    assert own[256] < 0.8 * limit and abs(richardson([own[256], own[128]]) / limit - 1) > 0.04
