"""MATLAB .mat recordings: channel vectors with a units struct, a matrix with names, a struct, v7.3."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import io as sio

from fingerpad import measure as m
from fingerpad.errors import FingerpadError

from .sample import FORCE_UNITS, FRICTION, N_ROWS, NORMAL, POSITION_MM, TIME, check_si, header


@pytest.mark.parametrize("unit", list(FORCE_UNITS))
def test_vectors_with_units_struct(tmp_path, unit):
    path = tmp_path / "run.mat"
    sio.savemat(path, {"time": TIME, "Fn": NORMAL, "Ft": FRICTION, "x": POSITION_MM,
                       "units": {"time": "s", "Fn": unit, "Ft": unit, "x": "mm"},
                       "fs": 100.0, "note": "sample"})
    table = m.read_table(path, m.ColumnSpec())
    assert table.row_word == "sample"
    assert set(table.header) == {"time", "Fn", "Ft", "x"}
    assert dict(zip(table.header, table.units))["Fn"] == unit
    check_si(m.read_recording(path), unit)


@pytest.mark.parametrize("unit", ["N", "mN", "lbf"])
def test_matrix_with_header_names(tmp_path, unit):
    path = tmp_path / "run.mat"
    data = np.column_stack([TIME, NORMAL, FRICTION, POSITION_MM])
    sio.savemat(path, {"data": data, "header": np.array(header(unit), dtype=object)})
    table = m.read_table(path, m.ColumnSpec())
    assert table.header == header(unit)
    np.testing.assert_array_equal(table.rows, np.arange(1, N_ROWS + 1))
    check_si(m.read_recording(path), unit)


def test_matrix_stored_one_channel_per_row(tmp_path):
    path = tmp_path / "run.mat"
    data = np.vstack([TIME, NORMAL, FRICTION, POSITION_MM])  # 4 x 12: channels along the short side
    sio.savemat(path, {"data": data, "channels": np.array(header("gf"), dtype=object)})
    check_si(m.read_recording(path), "gf")


def test_single_struct_and_named_struct(tmp_path):
    path = tmp_path / "run.mat"
    fields = {"time": TIME, "Fn": NORMAL * 1e3, "Ft": FRICTION * 1e3, "x": POSITION_MM * 1e-3}
    sio.savemat(path, {"trial": fields})
    rec = m.read_recording(path, m.ColumnSpec(units={"normal": "mN", "friction": "mN"}))
    check_si(rec, "N")
    two = tmp_path / "two.mat"
    sio.savemat(two, {"trial": fields, "other": {"a": np.arange(3.0)}})
    check_si(m.read_recording(two, m.ColumnSpec(sheet="trial", units={"normal": "mN", "friction": "mN"})), "N")
    with pytest.raises(FingerpadError, match=r"no variable 'nope' \(variables: trial, other\)"):
        m.read_table(two, m.ColumnSpec(sheet="nope"))


def test_vectors_of_another_length_are_ignored(tmp_path):
    path = tmp_path / "run.mat"
    sio.savemat(path, {"time": TIME, "Fn": NORMAL, "Ft": FRICTION, "calibration": np.array([1.0, 2.0, 3.0])})
    table = m.read_table(path, m.ColumnSpec())
    assert "calibration" not in table.header and table.ignored == ["calibration"]


def test_matrix_names_of_wrong_count_refused(tmp_path):
    path = tmp_path / "run.mat"
    sio.savemat(path, {"data": np.ones((12, 4)), "names": np.array(["a", "b", "c"], dtype=object)})
    with pytest.raises(FingerpadError, match="has 4 columns but 3 names"):
        m.read_table(path, m.ColumnSpec())


def test_no_channels_refused(tmp_path):
    path = tmp_path / "run.mat"
    sio.savemat(path, {"fs": 100.0, "who": "P1"})
    with pytest.raises(FingerpadError, match=r"no channel vectors and no matrix .*\(variables: fs, who\)"):
        m.read_table(path, m.ColumnSpec())


def test_v73_hdf5_file(tmp_path):
    h5py = pytest.importorskip("h5py")
    path = tmp_path / "run.mat"
    with h5py.File(path, "w", userblock_size=512) as fh:
        for name, v in (("time", TIME), ("Fn", NORMAL), ("Ft", FRICTION), ("x", POSITION_MM * 1e-3)):
            fh[name] = v[None, :]  # MATLAB writes a column vector as 1 x N in HDF5
        g = fh.create_group("meta")
        g["fs"] = np.array([[100.0]])
    with path.open("r+b") as fh:  # the MATLAB 7.3 header scipy recognises
        fh.write(b"MATLAB 7.3 MAT-file".ljust(116, b" ") + b"\x00" * 8 + b"\x00\x02IM")
    check_si(m.read_recording(path), "N")


def test_garbage_refused(tmp_path):
    path = tmp_path / "bad.mat"
    path.write_bytes(b"MATLAB 5.0 MAT-file, but then nothing" + b"\x00" * 64)
    with pytest.raises(FingerpadError, match=r"bad\.mat: cannot read as a MATLAB"):
        m.read_table(path, m.ColumnSpec())
