"""fingerpad.netcdf: every output of a solved cell written and read back unchanged, with units.

A 16 x 8 sinusoid cell solves in milliseconds; the round trips check values, dimensions,
units and the input attributes, and that a failed write leaves nothing behind.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import fingerpad as fp
from fingerpad import netcdf
from fingerpad.errors import FingerpadError

E = 1e6  # Pa
PRESSURES = (500.0, 2e3, 8e3)


@pytest.fixture(scope="module")
def solver():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fp.errors.ResolutionWarning)
        tex = fp.make_texture("sinusoid", amplitude=5e-6, wavelength=100e-6, grid=16)
    return fp.HalfSpaceSolver(tex, E)


@pytest.fixture(scope="module")
def curve(solver):
    return fp.load_curve(solver, list(PRESSURES))


def test_one_result_round_trip(tmp_path, curve):
    res = curve.results[1]
    path = netcdf.save_result(res, tmp_path / "cell.nc", attrs={"study": {"grid": 16, "note": None}})
    ds = netcdf.load_dataset(path)
    np.testing.assert_array_equal(ds["pressure"].values, res.pressure)
    np.testing.assert_array_equal(ds["gap"].values, res.gap)
    np.testing.assert_array_equal(ds["displacement"].values, res.displacement)
    np.testing.assert_array_equal(ds["heights"].values, res.texture.heights)
    np.testing.assert_array_equal(ds["contact"].values, (res.pressure > 0).astype(np.int8))
    assert ds["pressure"].dims == ("x", "y") and ds["pressure"].shape == (16, 8)
    for name in ("mean_pressure", "approach", "contact_fraction", "real_contact_area", "max_pressure", "mean_gap",
                 "residual", "seconds"):
        assert float(ds[name]) == float(getattr(res, name)), name
    assert int(ds["iterations"]) == res.iterations
    assert int(ds["converged"]) == int(res.converged)
    assert str(ds["contact_state"].values) == res.contact_state
    assert str(ds["formulation"].values) == res.formulation
    x, y = res.texture.coordinates()
    np.testing.assert_array_equal(ds["x"].values, x)
    np.testing.assert_array_equal(ds["y"].values, y)


def test_every_variable_has_units(tmp_path, curve):
    ds = netcdf.load_dataset(netcdf.save_result(curve.results[0], tmp_path / "u.nc"))
    for name, var in ds.variables.items():
        assert "units" in var.attrs, name
    assert ds["pressure"].attrs["units"] == "Pa"
    assert ds["gap"].attrs["units"] == "m"
    assert ds["real_contact_area"].attrs["units"] == "m2"
    assert ds["x"].attrs["units"] == "m"


def test_input_attributes(tmp_path, curve, solver):
    ds = netcdf.load_dataset(netcdf.save_result(curve.results[0], tmp_path / "a.nc",
                                                attrs={"study": {"grid": 16, "note": None}, "flag": True}))
    a = ds.attrs
    assert a["texture_name"] == "sinusoid"
    assert a["texture_amplitude"] == 5e-6 and a["texture_wavelength"] == 100e-6
    assert a["texture_size_x"] == pytest.approx(solver.texture.size[0])
    assert a["texture_nx"] == 16 and a["texture_ny"] == 8
    assert a["texture_periodic"] == "true"
    assert a["modulus"] == E
    assert a["units_system"] == "SI" and a["Conventions"] == "CF-1.8"
    assert a["source"].startswith("fingerpad ")
    assert a["study_grid"] == 16 and a["study_note"] == "none" and a["flag"] == "true"


def test_stacked_results_round_trip(tmp_path, curve):
    ds = netcdf.load_dataset(netcdf.save_results(curve.results, tmp_path / "s.nc"))
    assert ds["pressure"].dims == ("mean_pressure", "x", "y")
    assert ds["heights"].dims == ("x", "y"), "the texture is never stacked"
    np.testing.assert_allclose(ds["mean_pressure"].values, [r.mean_pressure for r in curve.results])
    for k, r in enumerate(curve.results):
        np.testing.assert_array_equal(ds["pressure"].values[k], r.pressure)
        assert ds["contact_fraction"].values[k] == r.contact_fraction
        assert str(ds["contact_state"].values[k]) == r.contact_state
    assert ds.attrs["title"] == "fingerpad unit-cell load curve"


def test_load_curve_with_and_without_fields(tmp_path, curve):
    full = netcdf.load_dataset(netcdf.save_load_curve(curve, tmp_path / "full.nc"))
    assert "pressure" in full and full["pressure"].shape == (3, 16, 8)
    lean = type(curve)(**{**curve.__dict__, "results": []})
    ds = netcdf.load_dataset(netcdf.save_load_curve(lean, tmp_path / "lean.nc", attrs={"modulus": E}))
    assert "pressure" not in ds
    np.testing.assert_array_equal(ds["mean_pressure"].values, curve.mean_pressure)
    np.testing.assert_array_equal(ds["contact_fraction"].values, curve.contact_fraction)
    np.testing.assert_array_equal(ds["converged"].values, curve.converged.astype(np.int8))
    assert [str(s) for s in ds["contact_state"].values] == list(curve.contact_state)
    assert ds.attrs["modulus"] == E


def test_contact_fraction_grows_along_the_curve(curve):
    # an invariant of the stored curve: more load, more contact, less gap
    assert np.all(np.diff(curve.contact_fraction) >= 0)
    assert np.all(np.diff(curve.mean_gap) < 0)


def test_fields_are_compressed(tmp_path, curve):
    import h5py

    path = netcdf.save_results(curve.results, tmp_path / "z.nc")
    with h5py.File(path) as fh:
        assert fh["pressure"].compression == "gzip"


def test_refusals(tmp_path, curve):
    with pytest.raises(FingerpadError, match="not a contact result"):
        netcdf.result_dataset(object())
    with pytest.raises(FingerpadError, match="no results to save"):
        netcdf.results_dataset([])
    with pytest.raises(FingerpadError, match="no such file"):
        netcdf.load_dataset(tmp_path / "missing.nc")
    bad = tmp_path / "bad.nc"
    bad.write_text("not netcdf")
    with pytest.raises(FingerpadError, match="as NetCDF"):
        netcdf.load_dataset(bad)
    empty = type(curve)(**{**curve.__dict__, "results": [], "mean_pressure": np.array([])})
    with pytest.raises(FingerpadError, match="empty load curve"):
        netcdf.load_curve_dataset(empty)


def test_results_of_two_textures_refused(curve):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fp.errors.ResolutionWarning)
        other = fp.make_texture("sinusoid", amplitude=5e-6, wavelength=100e-6, grid=8)
    res = fp.HalfSpaceSolver(other, E).solve_pressure(2e3)
    with pytest.raises(FingerpadError, match="must share one texture"):
        netcdf.results_dataset([curve.results[0], res])


def test_failed_write_leaves_old_file(tmp_path, curve, monkeypatch):
    path = tmp_path / "keep.nc"
    netcdf.save_result(curve.results[0], path)
    before = path.read_bytes()
    import xarray as xr

    def broken(self, tmp, **kwargs):
        with open(tmp, "wb") as fh:
            fh.write(b"\x89HDF half")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", broken)
    with pytest.raises(FingerpadError, match="No space left on device"):
        netcdf.save_result(curve.results[1], path)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.nc"]
