"""Height-map readers, one per format: NumPy, text matrices, instrument files (SurfaceTopography).

Each test writes a small map with known heights and reads it back through
``fingerpad.read_surface``: heights in metres shifted to a zero minimum, axis 0 along x, the
size from the file or the caller.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import fingerpad as fp
from fingerpad.errors import FingerpadError
from fingerpad.textures.readers import reader_for, readers

# heights in um on an 8 x 6 grid (axis 0 along x): a tilted ramp plus a bump, minimum 0.5 um
X, Y = np.meshgrid(np.arange(8.0), np.arange(6.0), indexing="ij")
HEIGHTS_UM = 0.5 + 0.1 * X + 0.2 * Y + (X == 3) * (Y == 2) * 2.0
SIZE = (80e-6, 60e-6)


def expected_m() -> np.ndarray:
    return (HEIGHTS_UM - HEIGHTS_UM.min()) * 1e-6


# ---------------------------------------------------------------------------------------------
# registry
# ---------------------------------------------------------------------------------------------


def test_readers_by_suffix_and_fallback():
    names = [r.name for r in readers()]
    assert names[-1] == "instrument", "the fallback comes last"
    assert {"npy", "text", "instrument"} <= set(names)
    assert reader_for(Path("a.npy")).name == "npy"
    for suffix in (".txt", ".csv", ".dat", ".asc", ".TXT"):
        assert reader_for(Path("a" + suffix)).name == "text"
    assert reader_for(Path("a.x3p")).name == "instrument"
    assert reader_for(Path("a.sur")).name == "instrument"
    assert reader_for(Path("a.npy")).bare and not reader_for(Path("a.x3p")).bare


# ---------------------------------------------------------------------------------------------
# NumPy
# ---------------------------------------------------------------------------------------------


def test_npy_round_trip(tmp_path):
    path = tmp_path / "scan.npy"
    np.save(path, HEIGHTS_UM)
    tex = fp.read_surface(path, size=SIZE, height_unit="um", level=False)
    np.testing.assert_allclose(tex.heights, expected_m(), rtol=0, atol=1e-18)
    assert tex.size == SIZE and tex.shape == (8, 6) and tex.name == "scan" and not tex.periodic


def test_npy_height_unit_factor(tmp_path):
    path = tmp_path / "scan.npy"
    np.save(path, HEIGHTS_UM * 1e3)  # nm
    tex = fp.read_surface(path, size=SIZE, height_unit="nm", level=False)
    np.testing.assert_allclose(tex.heights, expected_m(), rtol=1e-12, atol=1e-20)
    tex = fp.read_surface(path, size=SIZE, height_unit=1e-9, level=False)
    np.testing.assert_allclose(tex.heights, expected_m(), rtol=1e-12, atol=1e-20)


def test_npy_levelling_removes_the_plane(tmp_path):
    path = tmp_path / "tilted.npy"
    np.save(path, 0.1 * X + 0.2 * Y)  # a pure plane: levelled, it is flat
    tex = fp.read_surface(path, size=SIZE, height_unit="um")
    assert np.ptp(tex.heights) < 1e-18


def test_npy_refusals(tmp_path):
    bad = tmp_path / "bad.npy"
    bad.write_bytes(b"not numpy at all")
    with pytest.raises(FingerpadError, match=r"not a valid \.npy file"):
        fp.read_surface(bad, size=SIZE, height_unit="um")
    line = tmp_path / "line.npy"
    np.save(line, np.arange(5.0))
    with pytest.raises(FingerpadError):
        fp.read_surface(line, size=SIZE, height_unit="um")
    holes = tmp_path / "holes.npy"
    h = HEIGHTS_UM.copy()
    h[2, 3] = np.nan
    np.save(holes, h)
    with pytest.raises(FingerpadError, match="missing"):
        fp.read_surface(holes, size=SIZE, height_unit="um", level=False)
    filled = fp.read_surface(holes, size=SIZE, height_unit="um", level=False, fill_missing=True)
    assert np.isfinite(filled.heights).all() and filled.params["filled_points"] == 1


# ---------------------------------------------------------------------------------------------
# text matrices (stored image-like: one line per y)
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name, sep", [("m.txt", " "), ("m.csv", ","), ("m.dat", ";"), ("m.asc", "\t")])
def test_text_round_trip(tmp_path, name, sep):
    path = tmp_path / name
    lines = ["# exported by a profilometer", "% units: um"]
    lines += [sep.join(repr(float(v)) for v in row) for row in HEIGHTS_UM.T]
    path.write_text("\n".join(lines) + "\n")
    tex = fp.read_surface(path, size=SIZE, height_unit="um", level=False)
    np.testing.assert_allclose(tex.heights, expected_m(), rtol=0, atol=1e-18)
    assert tex.shape == (8, 6)


def test_text_empty_fields_are_missing(tmp_path):
    path = tmp_path / "m.csv"
    rows = [",".join(repr(float(v)) for v in row) for row in HEIGHTS_UM.T]
    cells = rows[1].split(",")
    cells[4] = ""  # y = 1, x = 4
    rows[1] = ",".join(cells)
    path.write_text("\n".join(rows) + "\n")
    with pytest.raises(FingerpadError, match="missing"):
        fp.read_surface(path, size=SIZE, height_unit="um", level=False)
    tex = fp.read_surface(path, size=SIZE, height_unit="um", level=False, fill_missing=True)
    assert tex.params["filled_points"] == 1


@pytest.mark.parametrize("content, message", [
    ("1 2 3\n4 5\n", r"line 2 has 2 values, earlier lines have 3"),
    ("1 2 3\n4 x 6\n", r"line 2: cannot read 'x' as a number \(comment lines must start with #\)"),
    ("# only comments\n\n", r"no height data found"),
])
def test_text_refusals(tmp_path, content, message):
    path = tmp_path / "m.txt"
    path.write_text(content)
    with pytest.raises(FingerpadError, match=message):
        fp.read_surface(path, size=SIZE, height_unit="um")


# ---------------------------------------------------------------------------------------------
# instrument files (written here with SurfaceTopography, the library that reads them)
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("suffix", [".x3p", ".nc"])
def test_instrument_file_carries_size_and_unit(tmp_path, suffix):
    st = pytest.importorskip("SurfaceTopography")
    path = tmp_path / f"scan{suffix}"
    topo = st.Topography(HEIGHTS_UM, (80.0, 60.0), unit="um")
    (topo.to_x3p if suffix == ".x3p" else topo.to_netcdf)(str(path))
    tex = fp.read_surface(path, level=False)
    assert tex.size == pytest.approx(SIZE, rel=1e-12)
    np.testing.assert_allclose(tex.heights, expected_m(), rtol=1e-9, atol=1e-15)
    # the caller's size overrides the file's
    other = fp.read_surface(path, size=(160e-6, 120e-6), level=False)
    assert other.size == (160e-6, 120e-6)
    np.testing.assert_allclose(other.heights, tex.heights, rtol=1e-12, atol=1e-20)


def test_instrument_height_unit_multiplies_the_stored_heights(tmp_path):
    """A NetCDF topography stores heights in its own unit (here um): height_unit replaces it."""
    st = pytest.importorskip("SurfaceTopography")
    path = tmp_path / "scan.nc"
    st.Topography(HEIGHTS_UM, (80.0, 60.0), unit="um").to_netcdf(str(path))
    nm = fp.read_surface(path, height_unit="nm", level=False)
    np.testing.assert_allclose(nm.heights, expected_m() * 1e-3, rtol=1e-9, atol=1e-20)
    assert nm.size == pytest.approx(SIZE, rel=1e-12), "the lateral size keeps the file's unit"


def test_unknown_format_refused(tmp_path):
    path = tmp_path / "scan.xyz123"
    path.write_bytes(b"\x00\x01 nothing an instrument writes")
    with pytest.raises(FingerpadError, match=r"cannot read surface file .*scan\.xyz123"):
        fp.read_surface(path)
