"""Outputs of ``predict``: predict.json, the CSV table and predict.nc read back equal to the
prediction; the whole set written all or none."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from fingerpad import netcdf
from fingerpad.errors import FingerpadError
from fingerpad.study import outputs


def listing(folder):
    """The files a user sees (an output folder's hidden listing of what fingerpad wrote left out)."""
    return sorted(p.name for p in folder.iterdir() if p.name != ".fingerpad-output.json")


def test_prediction_invariants(prediction):
    """Real <= ridge <= gross area; A_re/A_fr and mu/mu_ref are the ratios they say."""
    cur = prediction.primary
    assert np.all(cur.real_area <= cur.ridge_area * (1 + 1e-12))
    assert np.all(cur.ridge_area <= cur.gross_area * (1 + 1e-12))
    np.testing.assert_allclose(cur.area_ratio, cur.real_area / cur.ridge_area, rtol=1e-12)
    np.testing.assert_allclose(cur.mu_normalised, cur.mu / cur.mu_ref, rtol=1e-12)
    # the default finger's constant-fraction ridges: A_fr = 0.5 A_g
    np.testing.assert_allclose(cur.ridge_area, 0.5 * cur.gross_area, rtol=1e-12)
    assert np.all(np.diff(cur.real_area) > 0)


def test_json_and_csv_round_trip(tmp_path, prediction):
    json_path, csv_path = tmp_path / "p.json", tmp_path / "p.csv"
    written = outputs.write_outputs(prediction, None, json_path=str(json_path), csv_path=str(csv_path))
    assert sorted(p.name for p in written) == ["p.csv", "p.json"]
    assert listing(tmp_path) == ["p.csv", "p.json"]

    data = json.loads(json_path.read_text())
    assert data == json.loads(json.dumps(outputs.prediction_json(prediction)))
    cur = prediction.primary
    np.testing.assert_allclose([r["load"] for r in data["results"]], cur.load, rtol=1e-15)
    np.testing.assert_allclose([r["real_area"] for r in data["results"]], cur.real_area, rtol=1e-15)
    assert data["critical_load"]["bem"] == pytest.approx(prediction.critical_load["bem"], rel=1e-15)
    assert data["model"] == "bem" and data["units"]["load"] == "N"

    with csv_path.open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == [header for _, header in outputs.CSV_COLUMNS]
    assert len(rows) == cur.load.size
    np.testing.assert_allclose([float(r["load_N"]) for r in rows], cur.load, rtol=1e-15)
    np.testing.assert_allclose([float(r["real_area_m2"]) for r in rows], cur.real_area, rtol=1e-15)
    np.testing.assert_allclose([float(r["mu_over_mu_ref"]) for r in rows], cur.mu_normalised, rtol=1e-15)
    assert [r["centre_state"] for r in rows] == prediction.states()


def test_json_has_no_nan(prediction):
    text = json.dumps(outputs.prediction_json(prediction), allow_nan=False)
    assert "NaN" not in text and "Infinity" not in text


def test_netcdf_round_trip(tmp_path, prediction):
    path = netcdf.to_netcdf(outputs.prediction_dataset(prediction), tmp_path / "predict.nc")
    ds = netcdf.load_dataset(path)
    cur = prediction.primary
    np.testing.assert_array_equal(ds["load"].values, cur.load)
    for name in ("gross_area", "ridge_area", "real_area", "area_ratio", "mu", "mu_ref", "mu_normalised"):
        np.testing.assert_array_equal(ds[name].values, getattr(cur, name), err_msg=name)
    np.testing.assert_array_equal(ds["hertz_real_area"].values, prediction.hertz.real_area)
    assert [str(s) for s in ds["contact_state"].values] == prediction.states()
    assert ds["real_area"].attrs["units"] == "m^2" and ds["load"].attrs["units"] == "N"
    assert ds["cell_pressure"].attrs["units"] == "Pa"
    psi = ds["cell_contact_fraction"].values
    assert np.all((psi >= 0) & (psi <= 1)) and np.all(np.diff(psi) >= -1e-12)
    assert ds.attrs["model"] == "bem" and ds.attrs["units_system"] == "SI"
    assert ds.attrs["critical_load_bem"] == pytest.approx(prediction.critical_load["bem"])


def test_output_folder_replaced_whole(tmp_path, prediction):
    out = tmp_path / "out"
    out.mkdir()
    (out / "ridge_models.png").write_bytes(b"from an earlier run-default")
    outputs.write_outputs(prediction, out, dpi=40)
    assert listing(out) == sorted(outputs.OUTPUT_FILES)
    assert listing(tmp_path) == ["out"]


def test_failure_while_drawing_writes_nothing(tmp_path, prediction, monkeypatch):
    out = tmp_path / "out"
    out.mkdir()
    (out / "predict.json").write_text("earlier run")
    json_path = tmp_path / "copy.json"

    from matplotlib.figure import Figure

    def broken(self, *args, **kwargs):
        raise RuntimeError("renderer crashed")

    monkeypatch.setattr(Figure, "savefig", broken)
    with pytest.raises(RuntimeError, match="renderer crashed"):
        outputs.write_outputs(prediction, out, json_path=str(json_path), csv_path=str(tmp_path / "t.csv"))
    assert listing(tmp_path) == ["out"], "neither --json nor --csv written, no hidden folder left"
    assert listing(out) == ["predict.json"] and (out / "predict.json").read_text() == "earlier run"


@pytest.mark.parametrize("kwargs, message", [
    (dict(json_path="x.txt"), r"--json 'x\.txt': the file name must end in \.json"),
    (dict(csv_path="x.json"), r"--csv 'x\.json': the file name must end in \.csv"),
])
def test_check_outputs_suffixes(tmp_path, monkeypatch, kwargs, message):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(FingerpadError, match=message):
        outputs.check_outputs(None, **kwargs)


def test_check_outputs_collisions(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    with pytest.raises(FingerpadError, match="lies inside --out"):
        outputs.check_outputs(out, json_path=str(out / "p.json"))
    (tmp_path / "foreign").mkdir()
    (tmp_path / "foreign" / "notes.txt").write_text("mine")
    with pytest.raises(FingerpadError, match=r"holds files fingerpad did not write there \(notes\.txt\)"):
        outputs.check_outputs(tmp_path / "foreign")
    outputs.check_outputs(out, json_path="-")  # stdout is fine
    assert listing(tmp_path) == ["foreign", "out"] and listing(out) == []


def test_rows_follow_the_csv_columns(prediction):
    rows = outputs.prediction_rows(prediction)
    assert len(rows) == prediction.primary.load.size
    assert all(list(r) == [h for _, h in outputs.CSV_COLUMNS] for r in rows)


def test_load_output_modules_leaves_write_outputs_nothing_heavy_to_import(tmp_path):
    """``predict --direction`` imports what writes the outputs on a core its ramps left free
    (issue 23): after :func:`outputs.load_output_modules`, writing a folder imports none of the
    libraries it draws and writes with (in a fresh interpreter: this one has them all)."""
    import subprocess
    import sys
    import textwrap

    code = textwrap.dedent(f"""
        import sys
        from fingerpad.study.outputs import load_output_modules, write_outputs
        from fingerpad.study.run import run_study
        from fingerpad.study.spec import Study
        from fingerpad.textures import spherical_caps
        pred = run_study(Study(texture=spherical_caps(radius=100e-6, height=20e-6, spacing=175e-6, grid=32),
                               model="hertz", cache=False))
        heavy = {{"matplotlib", "PIL", "xarray", "h5py", "h5netcdf", "dask", "distributed", "pandas"}}
        assert not heavy & {{m.split(".")[0] for m in sys.modules}}, "already imported before the test"
        load_output_modules()
        before = set(sys.modules)
        write_outputs(pred, {str(tmp_path / "out")!r}, dpi=40)
        late = sorted({{m.split(".")[0] for m in set(sys.modules) - before}} & heavy)
        print("LATE", late)
    """)
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr[-2000:]
    assert "LATE []" in run.stdout, run.stdout
    assert (tmp_path / "out" / "friction.png").exists() and (tmp_path / "out" / "predict.nc").exists()
