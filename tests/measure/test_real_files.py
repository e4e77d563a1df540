"""Real lab files: separators, decimal commas, .xls, .mat, .tdms, force units, dead channels,
lift-off, unreadable files, plausibility, and the one-line error contract."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
import typer
from typer.testing import CliRunner

from fingerpad import measure as m
from fingerpad.cli.measure import register
from fingerpad.errors import FingerpadError

from .test_measurements import reciprocating, simple_file, write_csv


def _columns(s, scale_force=1.0):
    return [s["time"], s["normal"] * scale_force, s["friction"] * scale_force, s["position"] * 1e3]


# =============================================================================================
# text: separators, decimal comma, row numbers
# =============================================================================================


def test_decimal_comma_semicolon_detected(tmp_path):
    s = reciprocating(n_strokes=4, load=0.8, mu=0.45)
    f = tmp_path / "P1_glass_1.csv"
    with f.open("w") as fh:
        fh.write("# exported by the tribometer\n\ntime [s];Fn [N];Ft [N];x [mm]\n")
        for row in zip(*_columns(s)):
            fh.write(";".join(f"{v:.6f}".replace(".", ",") for v in row) + "\n")
    rec = m.read_recording(f)
    assert rec.time[-1] == pytest.approx(s["time"][-1], abs=1e-6)
    assert np.median(rec.normal) == pytest.approx(0.8, rel=0.02)
    assert m.measure_strokes(rec)["mu"].to_numpy() == pytest.approx(0.45, rel=0.03)
    # the spec may say so, and a point-decimal file read as comma-decimal fails loudly
    assert len(m.read_recording(f, m.ColumnSpec(decimal=","))) == len(rec)


def test_mixed_decimal_separators_is_an_error(tmp_path):
    f = tmp_path / "a.csv"
    f.write_text("t;Fn;Ft\n" + "".join(f"{i};1,5;0.5\n" for i in range(20)))
    with pytest.raises(FingerpadError, match=r"a\.csv: numbers are written with both decimal points and decimal commas"):
        m.read_recording(f)


def test_row_numbers_survive_comments_and_blank_lines(tmp_path):
    s = reciprocating(n_strokes=3)
    f = write_csv(tmp_path / "P1_glass_1.csv", ["time", "Fn", "Ft"], [s["time"], s["normal"], s["friction"]])
    lines = f.read_text().splitlines()
    lines.insert(5, "# a note in the middle")
    lines.insert(9, "")
    lines[30] = lines[30].replace(lines[30].split(",")[1], "oops")  # file line 31
    f.write_text("\n".join(lines) + "\n")
    with pytest.raises(FingerpadError, match=r"P1_glass_1\.csv, row 31: cannot read 'oops' in column 'Fn'"):
        m.read_recording(f)


def test_ragged_row_named(tmp_path):
    s = reciprocating(n_strokes=3)
    f = write_csv(tmp_path / "r.csv", ["time", "Fn", "Ft"], [s["time"], s["normal"], s["friction"]])
    lines = f.read_text().splitlines()
    lines[20] += ",7,8"
    f.write_text("\n".join(lines) + "\n")
    with pytest.raises(FingerpadError, match=r"r\.csv, row 21: more fields than the header"):
        m.read_recording(f)


@pytest.mark.parametrize("unit, factor", [("gf", 9.80665e-3), ("kgf", 9.80665), ("lbf", 4.4482216152605),
                                          ("mN", 1e-3)])
def test_force_units(tmp_path, unit, factor):
    s = reciprocating(n_strokes=3, load=1.0)
    f = write_csv(tmp_path / "u.csv", ["time", f"Fn [{unit}]", f"Ft [{unit}]"],
                  [s["time"], s["normal"] / factor, s["friction"] / factor], fmt="{:.9g}")
    rec = m.read_recording(f)
    assert np.median(rec.normal) == pytest.approx(1.0, rel=0.02)
    assert m.unit_factor(unit, "force") == pytest.approx(factor)
    with pytest.raises(FingerpadError, match="grams-force: write gf"):
        m.unit_factor("g", "force")


# =============================================================================================
# binary formats
# =============================================================================================


def test_xls_import(tmp_path):
    xlwt = pytest.importorskip("xlwt")
    s = reciprocating(n_strokes=4)
    book = xlwt.Workbook()
    sheet = book.add_sheet("run")
    sheet.write(0, 0, "instrument preamble")
    for j, name in enumerate(["time (s)", "Fn (mN)", "Ft (mN)", "x (mm)"]):
        sheet.write(1, j, name)
    for i, row in enumerate(zip(s["time"], s["normal"] * 1e3, s["friction"] * 1e3, s["position"] * 1e3)):
        for j, v in enumerate(row):
            sheet.write(i + 2, j, float(v))
    path = tmp_path / "P1_glass_1.xls"
    book.save(str(path))
    (rec,) = m.load_study([tmp_path], m.ColumnSpec(skip_rows=1))
    assert rec.participant == "P1" and rec.rows[0] == 3  # sheet row 3 holds the first data row
    assert np.median(rec.normal) == pytest.approx(1.0, rel=0.02)
    assert len(m.detect_strokes(rec)) == 4


def test_unreadable_matching_file_is_an_error_not_skipped(tmp_path):
    simple_file(tmp_path / "P1_flat_1.csv")
    (tmp_path / "P1_flat_2.xls").write_bytes(b"this is not a workbook" * 10)
    with pytest.raises(FingerpadError, match=r"P1_flat_2\.xls: cannot open as an \.xls workbook"):
        m.load_study([tmp_path])
    (tmp_path / "P1_flat_2.xls").unlink()
    (tmp_path / "P1_flat_2.docx").write_bytes(b"PK")
    with pytest.raises(FingerpadError, match=r"P1_flat_2\.docx: matches the file-name pattern .* cannot read \.docx"):
        m.load_study([tmp_path])
    (tmp_path / "P1_flat_2.docx").unlink()
    (tmp_path / "P1_flat_1.tdms_index").write_bytes(b"index")  # LabVIEW's companion: not a recording
    (tmp_path / ".P1_flat_3.csv").write_text("hidden")
    assert len(m.load_study([tmp_path])) == 1


def test_matlab_vectors_and_matrix(tmp_path):
    from scipy import io as sio

    s = reciprocating(n_strokes=4)
    sio.savemat(tmp_path / "P1_glass_1.mat", {"time": s["time"], "Fn": s["normal"] * 1e3, "Ft": s["friction"] * 1e3,
                                              "x": s["position"], "units": {"Fn": "mN", "Ft": "mN", "x": "m"},
                                              "fs": 200.0})
    (rec,) = m.load_study([tmp_path])
    assert np.median(rec.normal) == pytest.approx(1.0, rel=0.02)
    assert len(m.detect_strokes(rec)) == 4
    data = np.column_stack(_columns(s))
    names = np.array(["time [s]", "Fn [N]", "Ft [N]", "x [mm]"], dtype=object)
    sio.savemat(tmp_path / "P1_glass_2.mat", {"data": data, "header": names})
    rec2 = m.read_recording(tmp_path / "P1_glass_2.mat")
    assert rec2.position is not None and np.max(rec2.position) == pytest.approx(np.max(s["position"]), rel=1e-6)
    (tmp_path / "P1_glass_3.mat").write_bytes(b"MATLAB 5.0 MAT-file, garbage")
    with pytest.raises(FingerpadError, match=r"P1_glass_3\.mat: cannot read as a MATLAB file"):
        m.read_recording(tmp_path / "P1_glass_3.mat")


def test_matlab_v73(tmp_path):
    h5py = pytest.importorskip("h5py")
    s = reciprocating(n_strokes=3)
    path = tmp_path / "P1_glass_1.mat"
    with h5py.File(path, "w", userblock_size=512) as fh:
        for name, v in (("time", s["time"]), ("Fn", s["normal"]), ("Ft", s["friction"])):
            fh[name] = v[None, :]  # MATLAB writes a column vector as 1 x N in HDF5
    with path.open("r+b") as fh:  # the MATLAB 7.3 header scipy recognises
        fh.write(b"MATLAB 7.3 MAT-file".ljust(116, b" ") + b"\x00" * 8 + b"\x00\x02IM")
    rec = m.read_recording(path)
    assert len(rec) == s["time"].size and np.median(rec.normal) == pytest.approx(1.0, rel=0.02)


def test_tdms_import(tmp_path):
    nptdms = pytest.importorskip("nptdms")
    s = reciprocating(n_strokes=4)
    dt = float(s["time"][1] - s["time"][0])
    chans = []
    for name, v, unit in (("Fz", s["normal"] * 1e3, "mN"), ("Fx", s["friction"] * 1e3, "mN"),
                          ("x", s["position"] * 1e3, "mm")):
        chans.append(nptdms.ChannelObject("run", name, v, properties={"unit_string": unit, "wf_increment": dt,
                                                                      "wf_start_offset": 0.0}))
    path = tmp_path / "P1_glass_1.tdms"
    with nptdms.TdmsWriter(str(path)) as w:
        w.write_segment([nptdms.GroupObject("run")] + chans)
    rec = m.read_recording(path, m.ColumnSpec(columns={"normal": "Fz", "friction": "Fx"}))
    assert rec.time is not None and rec.time[1] == pytest.approx(dt)
    assert np.median(rec.normal) == pytest.approx(1.0, rel=0.02)
    assert len(m.detect_strokes(rec)) == 4
    with pytest.raises(FingerpadError, match=r"no group 'nope'"):
        m.read_recording(path, m.ColumnSpec(sheet="nope"))


# =============================================================================================
# dead channels, travel, lift-off
# =============================================================================================


@pytest.mark.parametrize("kind", ["constant", "roundoff", "noise"])
def test_dead_position_channel_gives_no_strokes(tmp_path, kind):
    s = reciprocating(n_strokes=6, seed=2)
    n = s["time"].size
    rng = np.random.default_rng(0)
    pos = {"constant": np.full(n, 12.5e-3), "roundoff": 12.5e-3 + 1e-16 * rng.standard_normal(n),
           "noise": 12.5e-3 + 2e-6 * rng.standard_normal(n)}[kind]
    rec = m.Recording(source="P1_flat_1.csv", time=s["time"], normal=s["normal"], friction=s["friction"],
                      position=pos)
    with pytest.raises(FingerpadError, match=r"P1_flat_1\.csv: no motion found: the position channel"):
        m.measure_strokes(rec)
    # the friction still tells the direction when asked
    strokes = m.measure_strokes(rec, m.StrokeOptions(direction_source="friction"))
    assert len(strokes) == 6


def test_minimum_travel_drops_tremor(tmp_path):
    s = reciprocating(n_strokes=4, seed=1)
    n = s["time"].size
    # between real strokes the finger trembles +-0.2 mm: not strokes
    tremor = 0.2e-3 * np.sin(2 * np.pi * 3.0 * s["time"])
    pos = s["position"] + np.where(np.abs(s["velocity"]) > 0, 0.0, tremor)
    rec = m.Recording(source="t.csv", time=s["time"], normal=s["normal"], friction=s["friction"], position=pos)
    strokes = m.detect_strokes(rec, m.StrokeOptions(min_stroke_fraction=0.0))
    assert len(strokes) == 4 and all(st.travel > 10e-3 for st in strokes)
    assert n > 0


def test_lift_off_reason_named(tmp_path):
    s = reciprocating(n_strokes=4, load=0.004)
    rec = m.Recording(source="P1_flat_1.csv", time=s["time"], normal=s["normal"], friction=s["friction"],
                      position=s["position"])
    with pytest.raises(FingerpadError, match=r"P1_flat_1\.csv: no usable strokes in rows .*normal force below the "
                                             r"0\.01 N lift-off threshold"):
        m.measure_strokes(rec)


def test_plausibility_warning_suggests_the_unit(tmp_path):
    s = reciprocating(n_strokes=6, load=1.0, mu=0.5)
    write_csv(tmp_path / "P1_flat_1.csv", ["time [s]", "Fn [N]", "Ft", "x [mm]"],
              [s["time"], s["normal"], s["friction"] * 1e3, s["position"] * 1e3])  # Ft written in mN
    strokes = m.stroke_table(m.load_study([tmp_path]))
    (msg,) = m.plausibility_warnings(strokes)
    assert "P1_flat_1.csv: median friction coefficient 500" in msg
    assert "friction force may be in mN while the normal force is in N" in msg
    assert m.plausibility_warnings(strokes.assign(mu=0.5)) == []


# =============================================================================================
# the command line keeps its contract on bad input
# =============================================================================================


@pytest.fixture()
def app():
    application = typer.Typer()
    register(application)
    return application


def test_cli_bad_file_one_error_line(app, tmp_path):
    runner = CliRunner()
    data, out = tmp_path / "data", tmp_path / "out"
    data.mkdir()
    simple_file(data / "P1_flat_1.csv")
    (data / "P1_flat_2.xls").write_bytes(b"garbage" * 20)
    r = runner.invoke(app, ["analyse", str(data), "--reference", "flat", "--out", str(out)])
    assert r.exit_code == 2 and not out.exists()
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and "P1_flat_2.xls" in lines[0]
    (data / "P1_flat_2.xls").unlink()
    r = runner.invoke(app, ["analyse", str(data), "--reference", "flat", "--out", str(out), "--decimal", ";"])
    assert r.exit_code == 2 and r.stderr.startswith("error: --decimal") and not out.exists()
    r = runner.invoke(app, ["analyse", str(data), "--reference", "flat", "--out", str(out), "--min-travel", "2kg"])
    assert r.exit_code == 2 and "--min-travel" in r.stderr and not out.exists()


def test_cli_warns_on_implausible_friction(app, tmp_path):
    runner = CliRunner()
    sim, out = tmp_path / "sim", tmp_path / "out"
    assert runner.invoke(app, ["simulate-measurement", "--out", str(sim), "--participants", "1",
                               "--strokes", "8"]).exit_code == 0
    # the files say 'Ft [mN]'; claim N for the friction: mu comes out 1000x too large
    r = runner.invoke(app, ["analyse", str(sim), "--reference", "flat", "--out", str(out), "--friction-unit", "N",
                            "--no-figures", "--no-sensitivity"])
    assert r.exit_code == 0, r.output
    warned = [ln for ln in r.stderr.splitlines() if ln.startswith("warning: ")]
    assert warned and all("implausible" in ln and "mN" in ln for ln in warned)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert Path(out / "summary.json").is_file()
