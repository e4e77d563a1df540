"""The adhesive unit cell (fingerpad.micro.adhesive_cell) and the adhesive pad (micro.adhesive_pad).

* a nearly flat cell closes at zero load and its work of separation is the work of adhesion w;
* an isolated cap's pull-off pressure is JKR's 1.5 pi w R per cell area, its zero-load contact
  JKR's radius;
* the loading branch is monotone, lets go below its pull-off, is the same on every preparation
  and from the cache; the unloading branch holds more contact and more tension (hysteresis);
* the cache is modulus-free per adhesion: (2 E*, 2 w) reads the cell of (E*, w);
* the pad: JKR's areas and pull-off, the pressure of Eq. 3.17 integrates to the load,
  w_pad = (A_fr/A_g) W, the threshold load found where the change crosses 10 %.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad.errors import FingerpadError
from fingerpad.finger import get_finger
from fingerpad.macro.hertz import HertzArea
from fingerpad.macro.jkr import JKRArea, jkr_contact_radius, jkr_load
from fingerpad.macro.pressure import adhesive_disc_average, disc_average
from fingerpad.micro.adhesive_cell import AdhesiveUnitCell
from fingerpad.micro.adhesive_pad import adhesion_threshold, adhesive_pad
from fingerpad.micro.bem import BEMUnitCell
from fingerpad.micro.cache import CurveCache
from fingerpad.textures import bisinusoid, spherical_caps

E = 4e5


def isolated_cap(grid: int = 64) -> tuple:
    # R 100 um, a cell 4.6x the JKR zero-load contact radius (26 um at w 0.05): a nearly isolated
    # asperity; the pull-off contact radius (16 um) spans 9 pixels at grid 64
    return spherical_caps(radius=100e-6, height=10e-6, spacing=120e-6, grid=grid), 100e-6


@pytest.fixture(scope="module")
def cap_cell(tmp_path_factory) -> AdhesiveUnitCell:
    tex, _ = isolated_cap()
    cache = CurveCache(tmp_path_factory.mktemp("adhesive"))
    return AdhesiveUnitCell(tex, E, work_of_adhesion=0.05, cache=cache).prepare()


def test_nearly_flat_cell_closes_and_separates_with_w() -> None:
    tex = bisinusoid(amplitude=5e-9, wavelength=100e-6, grid=32)
    cell = AdhesiveUnitCell(tex, E, work_of_adhesion=0.05, cache=False).prepare()
    assert cell.zero_load_fraction == 1.0
    # pulling a closed interface apart costs the law's integral, w, per unit area, and a little
    # more where the skin lets go unevenly (a snap loses elastic energy): w <= W <= 1.1 w
    assert 0.05 * (1 - 1e-3) <= cell.work_of_separation <= 0.05 * 1.1


def test_isolated_cap_pull_off_and_zero_load_contact_are_jkr(cap_cell: AdhesiveUnitCell) -> None:
    tex, radius = isolated_cap()
    w = 0.05
    jkr_pressure = -1.5 * math.pi * w * radius / tex.area
    # the regularised range at this grid: within 6 % (3.5 % at grid 96, first order in the pixel)
    assert cap_cell.pull_off_pressure == pytest.approx(jkr_pressure, rel=0.06)
    a0 = float(jkr_contact_radius(0.0, radius, E, w))
    assert cap_cell.zero_load_fraction == pytest.approx(math.pi * a0**2 / tex.area, rel=0.10)
    assert cap_cell.regularised and cap_cell.adhesion_range > 1e-9


def test_loading_branch_is_monotone_and_lets_go(cap_cell: AdhesiveUnitCell) -> None:
    p = np.linspace(cap_cell.pull_off_pressure, 2e4, 400)
    psi = cap_cell.contact_fraction(p)
    assert np.all(np.diff(psi) >= -1e-12)
    assert psi[0] > 0
    assert float(cap_cell.contact_fraction(1.01 * cap_cell.pull_off_pressure)) == 0.0
    # adhesion enlarges the contact: above the non-adhesive cell's at every pressure
    plain = BEMUnitCell(cap_cell.texture, E, cache=False).prepare(100.0, 2e4)
    q = np.geomspace(100.0, 2e4, 20)
    assert np.all(cap_cell.contact_fraction(q) >= plain.contact_fraction(q))


def test_cell_is_deterministic_and_cached(cap_cell: AdhesiveUnitCell) -> None:
    tex, _ = isolated_cap()
    again = AdhesiveUnitCell(tex, E, work_of_adhesion=0.05, cache=False).prepare()
    assert again.curve()["contact_fraction"].tolist() == cap_cell.curve()["contact_fraction"].tolist()
    assert again.pull_off_pressure == cap_cell.pull_off_pressure
    cached = AdhesiveUnitCell(tex, E, work_of_adhesion=0.05, cache=cap_cell.cache).prepare()
    assert cached.solves == 0 and cached.work_of_separation == cap_cell.work_of_separation
    # the modulus-free cache: twice the modulus and twice w is the same unit cell
    doubled = AdhesiveUnitCell(tex, 2 * E, work_of_adhesion=0.1, cache=cap_cell.cache).prepare()
    assert doubled.solves == 0 and doubled.key == cap_cell.key
    assert doubled.pull_off_pressure == pytest.approx(2 * cap_cell.pull_off_pressure, rel=1e-12)
    assert doubled.work_of_separation == pytest.approx(2 * cap_cell.work_of_separation, rel=1e-12)
    # another w / E* is another cell
    other = AdhesiveUnitCell(tex, E, work_of_adhesion=0.1, cache=False)
    assert other.key != cap_cell.key


def test_unloading_branch_holds_more(cap_cell: AdhesiveUnitCell) -> None:
    back = cap_cell.unloading()
    assert back["pull_off_pressure"] <= cap_cell.pull_off_pressure * (1 - 1e-9)
    at = back["pressure"] > 0
    load = cap_cell.contact_fraction(back["pressure"][at])
    assert np.all(back["contact_fraction"][at] >= load - 1e-9)


def test_cell_refuses_bad_input() -> None:
    tex, _ = isolated_cap(32)
    with pytest.raises(FingerpadError, match="work of adhesion must be a positive"):
        AdhesiveUnitCell(tex, E, work_of_adhesion=0.0)
    with pytest.raises(FingerpadError, match="unknown adhesion law"):
        AdhesiveUnitCell(tex, E, work_of_adhesion=0.05, law="sticky")
    with pytest.raises(FingerpadError, match="not prepared"):
        _ = AdhesiveUnitCell(tex, E, work_of_adhesion=0.05, cache=False).pull_off_pressure


# ------------------------------------------------------------------------------------------------
# the pad


def test_jkr_pad_is_hertz_without_adhesion_and_pulls_off_at_15_pi_w_r() -> None:
    loads = np.array([0.1, 1.0, 4.0])
    assert np.allclose(JKRArea(9e-3, 40e3, 0.0).area(loads), HertzArea(9e-3, 40e3).area(loads), rtol=1e-14)
    pad = JKRArea(9e-3, 40e3, 0.05)
    assert pad.pull_off_force == pytest.approx(1.5 * math.pi * 0.05 * 9e-3)
    a = jkr_contact_radius(loads, 9e-3, 40e3, 0.05)
    assert np.allclose(jkr_load(a, 9e-3, 40e3, 0.05), loads, rtol=1e-12)
    f_h, f_a = pad.pressure_parts(loads)
    assert np.allclose(f_h - f_a, loads, rtol=1e-12)
    with pytest.raises(FingerpadError, match="pull-off force"):
        pad.area(-2 * pad.pull_off_force)


def test_jkr_disc_pressure_integrates_to_the_load() -> None:
    c_h, c_a = 3e3, 400.0
    mean = adhesive_disc_average(lambda p: p, c_h, c_a, ())
    assert mean == pytest.approx(2 * c_h / 3 - 2 * c_a, rel=1e-10)
    # no edge tension: the Hertz disc average, to round-off
    f = lambda p: np.sqrt(p / 1e4)  # noqa: E731
    assert adhesive_disc_average(f, 2e3, 0.0, (500.0,)) == pytest.approx(
        float(disc_average(f, 2e3, (500.0,))[0]), rel=1e-13)


def test_adhesive_pad_work_and_threshold(cap_cell: AdhesiveUnitCell) -> None:
    finger = get_finger("default").with_overrides(work_of_adhesion=0.05)
    pad = adhesive_pad(finger, cap_cell)
    assert pad.ridge_fraction == pytest.approx(0.5)
    assert pad.work_of_adhesion == pytest.approx(0.5 * cap_cell.work_of_separation)
    assert pad.pull_off_force == pytest.approx(1.5 * math.pi * pad.work_of_adhesion * finger.radius)
    plain = BEMUnitCell(cap_cell.texture, E, cache=False).prepare(0.05, 5e4)
    threshold = adhesion_threshold(pad, plain)
    from fingerpad.micro.adhesive_pad import plain_real_area

    assert math.isfinite(threshold)  # this cell: 39 N (the skin pulled onto the base past the transition)
    for f, above in ((0.7 * threshold, True), (1.4 * threshold, False)):
        change = pad.real_area(np.array([f])) / plain_real_area(finger, plain, np.array([f])) - 1
        assert (change[0] > 0.1) == above
