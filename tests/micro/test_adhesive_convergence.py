"""Grid convergence of the adhesive unit cell past the transition (docs/model.md 6.6).

* the range of an adhesive cell follows the pixel and its attraction acts at the contact's edge
  only: the default cell's transition pressure and A_re / A_fr up to it converge with the grid
  at w 0.05 J/m^2 (within 2 % between grids 128 and 256);
* the grid's error estimate of an adhesive cell is the change from the half grid scaled to the
  error left at convergence order 1/2 (Maugis's parameter grows as the pixel's -1/2 power),
  while a non-adhesive cell's estimate is unchanged;
* a transition the attraction pulled in (w 0.3 J/m^2) is extrapolated with the orders 1 and 3/2
  removed, exact for that form, its estimate exact for an order-2 remainder and safeguarded
  where the grids show another form; on grids 32-256 it is met within 0.2 % of 512's.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from fingerpad.materials import reduced_modulus
from fingerpad.micro.adhesive_cell import AdhesiveUnitCell
from fingerpad.micro.bem import BEMUnitCell
from fingerpad.errors import FingerpadError
from fingerpad.micro.companions import halve
from fingerpad.micro.pull_in import PULL_IN_ORDERS, eighth_of, extrapolated_states, richardson
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


@pytest.fixture(scope="module")
def pulled_in_cells() -> dict[int, AdhesiveUnitCell]:
    # w 0.3 J/m2 on the default cell: the caps' contacts pull the skin onto the base (and into
    # full contact) from about three ranges, their edges 2.5-3 pixels short of the caps' feet
    # (grids 32 and 64: ~3 s; the convergence on 64-256 is the slow test below)
    return {g: prepared(g, 0.3) for g in (32, 64)}


def test_pulled_in_transition_is_told_from_the_base_gap(pulled_in_cells) -> None:
    for cell in pulled_in_cells.values():
        gap = cell._entry["loading"]["transition_gap"] / cell.law.range
        # measured 2.96, 3.31 ranges on 32, 64 (3.05, 2.92, 2.83 on 128, 256, 512)
        assert cell.pulled_in and 2.0 < gap < 4.5
        assert cell.full == cell.transition  # the jump goes into full contact at once
        assert cell.describe()["transition_pulled_in"] is True
    # at w 0.05 the skin sags onto the base where it touches it (0.02 ranges at 128): not pulled in
    # (the slow test below), and an unprepared cell is refused, not guessed
    with pytest.raises(FingerpadError):
        AdhesiveUnitCell(default_cell(32), E, work_of_adhesion=0.3, cache=False).pulled_in  # noqa: B018


def test_pulled_in_transition_is_extrapolated_at_first_order(pulled_in_cells) -> None:
    c32, c64 = pulled_in_cells[32], pulled_in_cells[64]
    own = [c.own_state_pressure("transition") for c in (c32, c64)]
    ex = extrapolated_states(c64, c32)
    p = ex["transition"][0]
    # Richardson at first order: p_N + (p_N - p_{N/2}) (measured 15.0 kPa against the grid's own
    # 9.49: 19.5, 21.6, 22.4 kPa on 128, 256, 512), the full contact with it
    assert p == pytest.approx(2 * own[1] - own[0], rel=1e-12) and ex["full"] == ex["transition"]
    # without the quarter grid the estimate compares it with the grid's own value
    assert ex["transition"][1] == own[1] and ex["transition"][2] == pytest.approx(p / own[1] - 1, rel=1e-12)
    assert own[1] < p < 32e3  # above the grid's jump, below the non-adhesive transition
    # nothing without a half grid, or with a half grid that was not pulled in
    assert extrapolated_states(c64, None) == {}
    # the cell reports what it adopts; its own bracket stays its own (psi(p): test_adhesive_reported.py)
    c64.adopt_pressure("transition", p)
    try:
        assert c64.transition_pressure == p and c64.own_state_pressure("transition") == own[1]
        lo, hi = c64.transition  # the grid's own bracket, below what is reported
        assert lo <= own[1] <= hi < p
        assert c64.full_contact_pressure == c64.own_state_pressure("full")  # not adopted
    finally:
        c64.adopt_pressure("transition", None)
    assert c64.transition_pressure == own[1]
    with pytest.raises(FingerpadError):
        c64.adopt_pressure("contact", p)


class PulledIn:
    """A stand-in pulled-in cell whose transition is ``p(N)`` (Pa) on a grid of ``N`` points: the
    extrapolation's bookkeeping only, no solves."""

    rtol = 1e-3
    pulled_in = True

    def __init__(self, law, grid: int) -> None:
        self.law, self.grid, self.p = law, grid, law(grid)
        self.transition = self.full = (self.p, self.p)

    @property
    def texture(self):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return default_cell(self.grid)

    def sibling(self, texture) -> "PulledIn":
        return PulledIn(self.law, texture.shape[0])

    def prepare(self) -> "PulledIn":
        return self

    def own_state_pressure(self, name: str) -> float:
        return self.p


def chain(law, grid: int) -> list[PulledIn]:
    return [PulledIn(law, grid // 2**i) for i in range(4)]


def test_pulled_in_extrapolation_is_exact_for_orders_one_and_three_halves() -> None:
    # p_N = p* - a / N + b / N^(3/2), the form the default cell's transitions take (64-512 within
    # 0.02 %: 22.78 kPa - 3.07 kPa (512 / N) + 0.50 kPa (512 / N)^(3/2)); the two extrapolations
    # recover p* to rounding, the first-order one alone is 2.2 % low at 256
    def law(n: int) -> float:
        return 22.78e3 - 3.07e3 * (512 / n) + 0.50e3 * (512 / n) ** 1.5

    fine, coarse, quarter, eighth = chain(law, 256)
    p, pc, error = extrapolated_states(fine, coarse, quarter, eighth)["transition"]
    assert p == pytest.approx(22.78e3, rel=1e-12) and pc == pytest.approx(22.78e3, rel=1e-12)
    assert error == fine.rtol  # nothing left but the bracket
    assert PULL_IN_ORDERS == (1.0, 1.5)
    first = richardson([fine.p, coarse.p], PULL_IN_ORDERS)
    assert first == 2 * fine.p - coarse.p and abs(first / 22.78e3 - 1) > 0.02
    # two grids: the first-order extrapolation, compared with the grid's own (as before)
    two = extrapolated_states(fine, coarse)
    assert two["transition"] == (first, fine.p, abs(first / fine.p - 1)) and two["full"] == two["transition"]


def test_pulled_in_estimate_covers_what_the_extrapolations_leave() -> None:
    # a term of order 2 left: the estimate (the change from the half grid's over 2^2 - 1) is the
    # error, on every grid (5.1, 1.3, 0.3 % at 128, 256, 512); an error of order 1/4, which the extrapolations cannot remove (not
    # the form they assume: the first extrapolation's changes shrink by 0.84 per doubling), gets
    # the distance to the limit at the order its own changes show (here exact: the value is 17 %
    # low at 256 and the estimate says so)
    for law, limit in ((lambda n: 20e3 - 3e3 * (512 / n) + 0.5e3 * (512 / n) ** 1.5 + 0.05e3 * (512 / n) ** 2, 20e3),
                       (lambda n: 20e3 - 4e3 * (512 / n) ** 0.25, 20e3)):
        for grid in (128, 256, 512):
            p, _, error = extrapolated_states(*chain(law, grid))["transition"]
            assert error >= abs(p / limit - 1) * (1 - 1e-9) > 1e-4
            if law(grid) > law(grid // 2) * 1.05:  # the first law's: the estimate is the error
                assert error == pytest.approx(abs(p / limit - 1), rel=1e-6)
    # without the eighth grid it is made from the quarter's map halved (a sixty-fourth of the
    # work), the same answer; where the quarter's map cannot be halved (grid 16), three grids
    # cannot check the form: the estimate reaches to the farther of the last correction p1 and the
    # grid's own (here the own, 17.8 %; the value is 1.3 % off: docs/model.md 6.6.1)
    law = lambda n: 20e3 - 3e3 * (512 / n) + 0.5e3 * (512 / n) ** 2  # noqa: E731
    fine, coarse, quarter, eighth = chain(law, 256)
    assert extrapolated_states(fine, coarse, quarter) == extrapolated_states(fine, coarse, quarter, eighth)
    fine, coarse, quarter, _ = chain(lambda n: 20e3 - 3e3 * (64 / n) + 0.2e3 * (64 / n) ** 2, 64)
    p, pc, error = extrapolated_states(fine, coarse, quarter)["transition"]
    assert pc == fine.p and error == pytest.approx(abs(p / pc - 1), rel=1e-12)
    assert error > abs(p / (2 * fine.p - coarse.p) - 1) and error > abs(p / 20e3 - 1)
    # an eighth not pulled in is not used; a quarter not pulled in leaves the two-grid answer
    quarter.pulled_in = False
    assert extrapolated_states(fine, coarse, quarter) == extrapolated_states(fine, coarse)


def test_eighth_grid_is_the_quarters_map_halved() -> None:
    # the eighth grid a prediction does not hold is made from the quarter's map block-averaged
    # (as a measured map's companion is), with the quarter's skin, adhesion and settings (on the
    # default cell its transition bracket is the generated grid 32's, 3966.0-3969.0 Pa)
    cell = AdhesiveUnitCell(default_cell(64), E, work_of_adhesion=0.3, cache=False, rtol=2e-3)
    twin = cell.sibling(halve(default_cell(64)))
    assert twin.key == AdhesiveUnitCell(halve(default_cell(64)), E, work_of_adhesion=0.3, rtol=2e-3).key
    assert twin.key != AdhesiveUnitCell(halve(default_cell(64)), E, work_of_adhesion=0.3).key
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # grid 16: coarse on purpose
        assert eighth_of(AdhesiveUnitCell(default_cell(16), E, work_of_adhesion=0.3, cache=False)) is None


@pytest.mark.slow
def test_pulled_in_transition_converges_at_the_grids_a_prediction_takes() -> None:
    # w 0.3 J/m2, grids 32 to 256 (256: ~1 min): the grid's own transition 3.97, 9.49, 14.49,
    # 18.06 kPa (20.21 on 512); reported at 256 with orders 1 and 3/2 removed, 22.81 kPa, its
    # estimate 1.3 %, the same from 128, 256, 512 22.76 kPa (0.2 % apart; 512 took 30 min)
    cells = {g: prepared(g, 0.3) for g in (32, 64, 128, 256)}
    own = {g: cells[g].own_state_pressure("transition") for g in cells}
    assert own[256] == pytest.approx(18.06e3, rel=1e-3)
    p, pc, error = extrapolated_states(cells[256], cells[128], cells[64], cells[32])["transition"]
    at_512 = richardson([20.209e3, own[256], own[128]])  # 512's own transition, measured
    assert abs(p / at_512 - 1) < 0.005 and abs(p / at_512 - 1) <= error <= 0.02
    # compared with the limit the next order (2) gives with grid 32 too, 23.10 kPa
    assert pc == pytest.approx(richardson([own[g] for g in (256, 128, 64, 32)], (1.0, 1.5, 2.0)), rel=1e-12)
    # the first-order extrapolation alone is 5 % lower, its estimate 20 %
    assert abs(richardson([own[256], own[128]]) / at_512 - 1) > 0.04
    # the eighth made from the quarter, when not given: the same bracket, the same numbers
    assert extrapolated_states(cells[256], cells[128], cells[64]) == \
        extrapolated_states(cells[256], cells[128], cells[64], cells[32])
    # w 0.05: touched, not pulled in, so nothing is extrapolated: today's numbers
    plain = {g: prepared(g, 0.05) for g in (128, 256)}
    assert not plain[128].pulled_in and not plain[256].pulled_in
    assert extrapolated_states(plain[256], plain[128]) == {}


class JumpCell:
    """A stand-in adhesive cell reporting an extrapolated transition (the estimate's bookkeeping
    only, no solves): its A_re/A_fr is a branch of its own plus a term that moves with the
    transition it reports, as a pad's does when its full-contact zone grows with a lower one."""

    convergence_order = AdhesiveUnitCell.convergence_order
    solves = 0
    #: the branch per grid (a first-order change between grids), the transition's pull on A_re
    BRANCH = {32: np.array([0.30, 0.40]), 64: np.array([0.301, 0.4005])}
    PULL = np.array([0.0, 0.2])  # the first load below the jump, the second past it
    OWN = {32: 10e3, 64: 15e3}

    def __init__(self, texture, modulus, **options) -> None:
        self.texture, self.adopted = texture, {}

    def prepare(self, *args, progress=None):
        return self

    def own_state_pressure(self, name: str) -> float:
        return self.OWN[self.texture.shape[0]]

    def reported_state_pressure(self, name: str) -> float:
        return self.adopted.get(name, self.own_state_pressure(name))

    def adopt_pressure(self, name: str, pressure) -> None:
        self.adopted.pop(name, None) if pressure is None else self.adopted.__setitem__(name, float(pressure))

    def ratio(self) -> np.ndarray:
        return self.BRANCH[self.texture.shape[0]] + self.PULL * np.log(20e3 / self.reported_state_pressure("transition"))


def test_pulled_in_estimate_charges_the_grid_with_its_own_jump_not_the_half_grids() -> None:
    # the grid reports its transition at 21 kPa, estimated 2 %; the half grid its own at 18 kPa
    # (a 14 % error of its jump's position that is the half grid's, estimated by it)
    reported = {64: 21e3, 32: 18e3}
    e_t = 0.02

    def settle(cell, cells):
        for g, c in cells.items():
            c.adopt_pressure("transition", reported[g])
        return {"transition": (reported[64], reported[64] * (1 + e_t), e_t)}

    choice = choose_grid(default_cell, default_cell(64), E, (0.0, 0.0), JumpCell.ratio, target=None,
                         cell_type=JumpCell, settle=settle)
    fine, coarse = choice.cell, choice.coarse
    # the branch: the half grid with its jump where the grid reports it, scaled to order 1/2
    r = fine.ratio()
    aligned = JumpCell.BRANCH[32] + JumpCell.PULL * np.log(20e3 / reported[64])
    branch = np.abs(r / aligned - 1) / (2**0.5 - 1)
    # where the jump comes: r_N with the transition moved by its own estimate, both ways
    moved = [JumpCell.BRANCH[64] + JumpCell.PULL * np.log(20e3 / (reported[64] * s)) for s in (1 - e_t, 1 + e_t)]
    jump = np.max([np.abs(m / r - 1) for m in moved], axis=0)
    assert choice.error == pytest.approx(float(np.max(branch + jump)), rel=1e-12)
    # the curves as reported differ by far more (the half grid's jump 14 % low): not charged
    assert float(np.max(np.abs(r / coarse.ratio() - 1))) / (2**0.5 - 1) > 2 * choice.error
    # both cells report as before
    assert fine.reported_state_pressure("transition") == reported[64]
    assert coarse.reported_state_pressure("transition") == reported[32]
    assert estimate_method(AdhesiveUnitCell, True) != estimate_method(AdhesiveUnitCell)


@pytest.mark.slow
def test_pulled_in_area_ratio_estimate_covers_the_error_against_finer_grids() -> None:
    # the README caps, the default finger at w 0.3 J/m2, loads 0.1, 0.3, 1 N and the zone load 4 N;
    # grids 16 to 256 (256: a few minutes). Each grid's estimate of A_re/A_fr (the branch against
    # the half grid with its jump aligned, plus the transition's own estimate carried to A_re)
    # covers its error against every finer grid at every load, and 256's is within the 2 % asked
    # (measured: 60, 4.2 and 1.5 % on 64, 128 and 256; the reported curves compared, 142, 43 and
    # 9.2 %). 512 (30 min) is not taken here: its reported transition, 22.76 kPa, is 0.2 % from
    # 256's (the transition test above), within the 1.3 % the jump term moves it by.
    from fingerpad.coupling import predict_curve
    from fingerpad.finger import FINGER_PRESETS
    from fingerpad.micro.pull_in import adopt_extrapolated, adopted_ratio_error

    finger = FINGER_PRESETS["default"].with_overrides(work_of_adhesion=0.3)
    loads = np.array([0.1, 0.3, 1.0, 4.0])

    def ratio(cell):
        return predict_curve(loads, finger, cell, reference=False).area_ratio

    cells = {g: prepared(g, 0.3) for g in (16, 32, 64, 128, 256)}
    r, estimate = {}, {}
    for g in (64, 128, 256):
        for c in cells.values():
            for name in ("transition", "full"):
                c.adopt_pressure(name, None)
        settled = adopt_extrapolated(cells, g)
        assert "transition" in settled
        r[g] = ratio(cells[g])
        estimate[g] = adopted_ratio_error(cells[g], cells[g // 2], ratio, settled, order_factor(AdhesiveUnitCell))
    for g in (64, 128):
        for finer in (h for h in r if h > g):
            assert np.all(np.abs(r[g] / r[finer] - 1) <= estimate[g])
    assert float(np.max(estimate[256])) <= 0.02
    assert r[256] == pytest.approx([0.3155, 0.3517, 0.6474, 0.8538], abs=2e-4)
