"""Micro-models of the normalised friction used to estimate E_s: the base-contact cell's psi, the
Hertz texture model against the coupling done by hand, samples tables."""

from __future__ import annotations

import math

import numpy as np
import pytest

import fingerpad as fp
from fingerpad import measure as m
from fingerpad.errors import FingerpadError

R, H, LAM = 50e-6, 18e-6, 100e-6


@pytest.fixture
def hertz_cell():
    return fp.HertzUnitCell(radius=R, height=H, spacing=LAM, reduced_modulus=0.4e6)


def test_base_contact_cell_psi(hertz_cell):
    cell = m.BaseContactCell(hertz_cell, full_contact_ratio=4.0)
    pt = cell.transition_pressure
    assert pt == hertz_cell.transition_pressure and cell.full_contact_pressure == pytest.approx(4 * pt)
    below = np.array([0.1, 0.5, 0.99]) * pt
    np.testing.assert_array_equal(cell.contact_fraction(below), hertz_cell.contact_fraction(below))
    psi_t = float(hertz_cell.contact_fraction(np.array(pt)))
    # log-linear from psi_t at p_t to 1 at 4 p_t: halfway in log at 2 p_t
    assert float(cell.contact_fraction(np.array(2 * pt))) == pytest.approx(max(psi_t + (1 - psi_t) / 2,
                                                                            float(hertz_cell.contact_fraction(np.array(2 * pt)))))
    assert float(cell.contact_fraction(np.array(4 * pt))) == pytest.approx(1.0)
    assert float(cell.contact_fraction(np.array(40 * pt))) == 1.0
    p = np.geomspace(0.01, 100, 300) * pt
    assert np.all(np.diff(cell.contact_fraction(p)) >= -1e-15), "monotone"
    assert cell.breakpoints == hertz_cell.breakpoints
    with pytest.raises(FingerpadError, match="full-contact ratio must exceed 1"):
        m.BaseContactCell(hertz_cell, full_contact_ratio=1.0)


def test_hertz_texture_model_is_the_coupling_with_e1_from_eq_3_4():
    model = m.hertz_texture_model(R, H, LAM, "default", material_modulus=1e9, material_poisson=0.4)
    loads = np.array([0.2, 1.0, 3.0])
    es = 0.3e6
    got = model(loads, es)
    finger = fp.get_finger("default").with_overrides(skin_modulus=es)
    cell = fp.HertzUnitCell.for_finger(finger, radius=R, height=H, spacing=LAM, material_modulus=1e9,
                                       material_poisson=0.4)
    from fingerpad import coupling

    expected = coupling.predict_curve(loads, finger, cell, n_rings=6).mu_normalised
    np.testing.assert_allclose(got, expected, rtol=1e-12)
    assert model.geometry.micro_model == "hertz" and model.finger.name == "default"
    # a stiffer skin touches less of the asperities: the normalised friction falls
    assert np.all(model(loads, 0.6e6) < got)


def test_model_variant_rebuilds_for_another_finger():
    model = m.hertz_texture_model(R, H, LAM)
    other = m.model_variant(model, "soft")
    assert other.finger.name == "soft" and other.geometry == model.geometry
    with pytest.raises(FingerpadError, match="cannot be rebuilt for another finger"):
        m.model_variant(lambda f, e: f, "soft")


@pytest.mark.parametrize("kwargs, message", [
    (dict(micro_model="fem"), "micro model must be 'bem' or 'hertz'"),
    (dict(full_contact_ratio=2.0), "applies to the 'hertz' micro model only"),
    (dict(micro_model="hertz", full_contact_ratio=0.5), "full_contact_ratio must exceed 1"),
    (dict(radius=0.0), "texture radius must be a positive length"),
    (dict(material_modulus=-1.0), "material modulus must be positive"),
])
def test_geometry_refusals(kwargs, message):
    with pytest.raises(FingerpadError, match=message):
        m.TextureGeometry(**{"radius": R, "height": H, "spacing": LAM, **kwargs})


def test_samples_table_with_units(tmp_path):
    path = tmp_path / "samples.csv"
    path.write_text("sample,radius,height,spacing,material_modulus,micro_model,full_contact_ratio\n"
                    "glass,,,,,,\nbumps,50um,18um,0.1mm,0.5GPa,,\nhertzy,50um,18um,100um,,hertz,3\n")
    t = m.read_textures(path)
    assert t["glass"] is None
    assert t["bumps"] == m.TextureGeometry(50e-6, 18e-6, 1e-4, 0.5e9)
    assert t["hertzy"].micro_model == "hertz" and t["hertzy"].full_contact_ratio == 3.0


@pytest.mark.parametrize("content, message", [
    ("name,radius\nx,1um\n", r"lacks a 'sample' column"),
    ("sample,radius,height,spacing\n,1um,1um,2um\n", r"row 2: empty sample name"),
    ("sample,radius,height,spacing\nb,1um,,2um\n", r"row 2: radius, height and spacing must all be given"),
    ("sample,radius,height,spacing\nb,1N,1um,2um\n", r"row 2: .*radius"),
])
def test_bad_samples_tables_named(tmp_path, content, message):
    path = tmp_path / "samples.csv"
    path.write_text(content)
    with pytest.raises(FingerpadError, match=message):
        m.read_textures(path)


def test_closed_form_agrees_with_the_hertz_model_transition():
    """At the E_s the closed form gives for a transition load, the Hertz cell's centre pressure
    reaches p_t at exactly that load."""
    finger = fp.get_finger("default")
    fcrit = 1.2
    es = m.modulus_from_transition(fcrit, R, H, LAM, finger)
    cell = fp.HertzUnitCell.for_finger(finger.with_overrides(skin_modulus=es), radius=R, height=H, spacing=LAM)
    assert 1.5 * fcrit / finger.ridge_area(fcrit) == pytest.approx(cell.transition_pressure, rel=1e-9)
    assert math.isfinite(es) and es > 0


def test_model_table_rows_kept_for_a_scan_are_the_splines():
    """ModelTable.log_rows keeps the rows of the last scans (every E_s fit starts from the same
    coarse scan): the same values as the spline, clipped to the table, read-only, and a kept
    scan's rows come back as they were computed."""
    table = m.ModelTable(lambda loads, e: (1.0 + 0.0 * loads) * (e / 1e6) ** 0.1 * loads ** -0.05, (0.1, 5.0))
    scan = np.linspace(math.log(1e4), math.log(5e7), 41)  # beyond both ends of the table
    rows = table.log_rows(scan)
    np.testing.assert_array_equal(rows, table._spline(np.clip(scan, table.log_moduli[0], table.log_moduli[-1])))
    assert not rows.flags.writeable
    assert table.log_rows(scan.copy()) is rows
    other = table.log_rows(scan[:7])
    assert other.shape == (7, table.loads.size) and table.log_rows(scan) is rows
