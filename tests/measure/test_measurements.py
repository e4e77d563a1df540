"""Tests of fingerpad.measurements / report / cli_measurements (friction measurements)."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
import typer
from typer.testing import CliRunner

from fingerpad import measure as m
from fingerpad.cli.measure import register
from fingerpad.errors import FingerpadError
from fingerpad.io import MANIFEST
from fingerpad.finger import get_finger

# =============================================================================================
# helpers
# =============================================================================================


def reciprocating(n_strokes: int = 6, fs: float = 200.0, stroke_s: float = 1.0, dwell_s: float = 0.1,
                  load: float = 1.0, mu: float = 0.5, seed: int = 0) -> dict[str, np.ndarray]:
    """A clean reciprocating signal: triangle-like position, constant load, friction opposing motion."""
    rng = np.random.default_rng(seed)
    v_parts = []
    n_move, n_dwell = int(stroke_s * fs), int(dwell_s * fs)
    for j in range(n_strokes):
        v_parts.append(np.zeros(n_dwell))
        v_parts.append((1 if j % 2 == 0 else -1) * 0.02 * np.sin(np.linspace(0, np.pi, n_move)) ** 0.3)
    v_parts.append(np.zeros(n_dwell))
    v = np.concatenate(v_parts)
    t = np.arange(v.size) / fs
    x = np.cumsum(v) / fs + 1e-6 * rng.standard_normal(v.size)
    fn = load * (1 + 0.01 * rng.standard_normal(v.size))
    ft = -np.tanh(v / 1e-3) * mu * fn + 0.002 * rng.standard_normal(v.size)
    return {"time": t, "normal": fn, "friction": ft, "position": x, "velocity": v}


def write_csv(path: Path, header: list[str], columns: list[np.ndarray], *, fmt: str = "{:.6g}",
              delimiter: str = ",") -> Path:
    with path.open("w", newline="") as fh:
        w = csv.writer(fh, delimiter=delimiter)
        w.writerow(header)
        for row in zip(*columns):
            w.writerow([fmt.format(v) for v in row])
    return path


def simple_file(path: Path, **kw) -> Path:
    s = reciprocating(**kw)
    return write_csv(path, ["time [s]", "Fn [N]", "Ft [N]", "x [mm]"],
                     [s["time"], s["normal"], s["friction"], s["position"] * 1e3])


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """A simulated study (4 participants, flat + bumps) and its analysis."""
    out = tmp_path_factory.mktemp("sim") / "study"
    truth = m.simulate_study(out, m.SimulationConfig(), seed=0)
    recordings = m.load_study([out])
    result = m.analyse_study(recordings, m.AnalysisOptions(reference="flat"),
                             textures=m.read_textures(out / "samples.csv"))
    return out, truth, result


@pytest.fixture(scope="module")
def hertz_study(tmp_path_factory):
    """The same study simulated with the Hertz micro model (plus the empirical base growth), for
    which the closed-form inversion of Eq. 3.6 is the consistent estimator."""
    out = tmp_path_factory.mktemp("sim") / "hertz"
    geom = m.TextureGeometry(radius=50e-6, height=18e-6, spacing=100e-6, full_contact_ratio=1.5, micro_model="hertz")
    truth = m.simulate_study(out, m.SimulationConfig(textures={"bumps": geom}), seed=0)
    result = m.analyse_study(m.load_study([out]), m.AnalysisOptions(reference="flat"),
                             textures=m.read_textures(out / "samples.csv"))
    return out, truth, result


# =============================================================================================
# units, specs, file names
# =============================================================================================


def test_unit_factors():
    assert m.unit_factor("mN", "force") == pytest.approx(1e-3)
    assert m.unit_factor("ms", "time") == pytest.approx(1e-3)
    assert m.unit_factor("mm/s", "velocity") == pytest.approx(1e-3)
    assert m.unit_factor("", "length") == 1.0
    with pytest.raises(FingerpadError, match="unknown force unit 'kg'"):
        m.unit_factor("kg", "force")
    with pytest.raises(FingerpadError, match="velocity"):
        m.unit_factor("mm", "velocity")


def test_template_and_filename():
    meta = m.parse_filename("/data/P07_dimples_para_3.csv", "{participant}_{sample}_{direction}_{repetition}.csv")
    assert meta == {"participant": "P07", "sample": "dimples", "direction": "para", "repetition": "3"}
    assert m.parse_filename("x/P1/glass_2.tsv", "{participant}/{sample}_{repetition:\\d+}.*") == {
        "participant": "P1", "sample": "glass", "repetition": "2"}
    assert m.parse_filename("P1_glass.csv", "{participant}_{sample}_{repetition}.csv") is None
    with pytest.raises(FingerpadError, match="appears twice"):
        m.template_regex("{sample}_{sample}")


def test_spec_toml(tmp_path):
    spec_file = tmp_path / "spec.toml"
    spec_file.write_text('[columns]\nnormal = "Load"\nfriction = "Drag"\n[units]\nnormal = "mN"\nfriction = "mN"\n'
                         'position = "mm"\n[files]\ndelimiter = ";"\npattern = "{participant}-{sample}-{repetition}.txt"\n')
    spec = m.load_spec(spec_file)
    s = reciprocating(n_strokes=4, load=0.5, mu=0.4)
    f = write_csv(tmp_path / "A-glass-1.txt", ["t", "Load", "Drag", "x"],
                  [s["time"], s["normal"] * 1e3, s["friction"] * 1e3, s["position"] * 1e3], delimiter=";")
    (rec,) = m.load_study([f], spec)
    assert (rec.participant, rec.sample, rec.repetition) == ("A", "glass", "1")
    assert np.median(rec.normal) == pytest.approx(0.5, rel=0.02)
    strokes = m.measure_strokes(rec)
    assert len(strokes) == 4
    assert strokes["mu"].to_numpy() == pytest.approx(0.4, rel=0.03)
    bad = tmp_path / "bad.toml"
    bad.write_text('[files]\ndelimeter = ";"\n')
    with pytest.raises(FingerpadError, match=r"bad\.toml.*delimeter"):
        m.load_spec(bad)


def test_excel_import(tmp_path):
    openpyxl = pytest.importorskip("openpyxl")
    s = reciprocating(n_strokes=4)
    book = openpyxl.Workbook()
    sheet = book.active
    sheet.title = "run"
    sheet.append(["instrument preamble"])
    sheet.append(["time (ms)", "Fz (mN)", "Fx (mN)", "velocity (mm/s)"])
    for row in zip(s["time"] * 1e3, s["normal"] * 1e3, s["friction"] * 1e3, s["velocity"] * 1e3):
        sheet.append([float(v) for v in row])
    path = tmp_path / "P1_glass_1.xlsx"
    book.save(path)
    rec = m.read_recording(path, m.ColumnSpec(sheet="run", skip_rows=1), participant="P1", sample="glass")
    assert rec.time[-1] == pytest.approx(s["time"][-1])
    assert rec.velocity is not None and np.max(rec.velocity) == pytest.approx(np.max(s["velocity"]), rel=1e-9)
    assert len(m.detect_strokes(rec)) == 4
    with pytest.raises(FingerpadError, match="no sheet 'nope'"):
        m.read_recording(path, m.ColumnSpec(sheet="nope"))


# =============================================================================================
# strokes and outliers
# =============================================================================================


@pytest.mark.parametrize("source", ["velocity", "position", "friction"])
def test_stroke_detection_count(source):
    s = reciprocating(n_strokes=7, seed=3)
    rec = m.Recording(source="synthetic", time=s["time"], normal=s["normal"], friction=s["friction"],
                      position=s["position"], velocity=s["velocity"])
    strokes = m.detect_strokes(rec, m.StrokeOptions(direction_source=source, trim=0.2))
    assert len(strokes) == 7
    assert [st.sense for st in strokes] == [1, -1, 1, -1, 1, -1, 1]
    for st in strokes:  # the steady part lies inside the stroke, trimmed at both ends
        length = st.stop - st.start
        assert st.start < st.steady_start < st.steady_stop < st.stop
        assert st.steady_start - st.start == pytest.approx(0.2 * length, abs=1)


def test_outliers_flagged_and_directions_kept_apart(study):
    _, truth, result = study
    s = result.strokes
    s = s.assign(name=[Path(f).name for f in s["file"]])
    flagged = set(zip(s.loc[s["outlier"], "name"], s.loc[s["outlier"], "stroke"]))
    injected = {(o["file"], o["stroke"]) for o in truth["outliers"]}
    assert injected and injected <= flagged
    assert len(flagged - injected) <= 3
    assert set(s["sense"]) == {"+", "-"}
    assert set(result.fits["sense"]) == {"+", "-", "both"}
    # every file gave all its strokes
    assert (s.groupby("file").size() == m.SimulationConfig().strokes_per_file).all()


# =============================================================================================
# recovery of the simulated parameters
# =============================================================================================


def test_recovers_power_law_and_skin_modulus(study):
    """k within 8 %, n within 0.05, E_s (BEM model fit) within 20 %."""
    _, truth, result = study
    parts = result.participants.set_index("participant")
    cond = result.conditions.set_index(["participant", "sample"])
    for pid, tr in truth["participants"].items():
        assert parts.loc[pid, "ref_k"] == pytest.approx(tr["k"], rel=0.08)
        assert parts.loc[pid, "ref_n"] == pytest.approx(tr["n"], abs=0.05)
        e = parts.loc[pid, "skin_modulus"]
        assert e == pytest.approx(tr["skin_modulus"], rel=0.20)
        assert parts.loc[pid, "skin_modulus_ci_low"] < e < parts.loc[pid, "skin_modulus_ci_high"]
        assert not parts.loc[pid, "skin_modulus_at_bound"]
        row = cond.loc[(pid, "bumps")]
        # Issue 10 (on purpose): a breakpoint is reported only when the sup-LR test finds one.
        # Under the BEM transition physics the slope barely changes, so mostly it does not.
        if row["breakpoint_detected"]:
            assert row["breakpoint_p"] < 0.05
            assert row["breakpoint_ci_low"] < row["breakpoint_load"] < row["breakpoint_ci_high"]
            assert row["slope_above"] > row["slope_below"]
        elif row["breakpoint_outside"]:  # the best change at the edge of the load range: not reported
            assert math.isnan(row["breakpoint_load"]) and "edge of the load range" in row["transition"]
        else:
            assert row["breakpoint_p"] >= 0.05 and math.isnan(row["breakpoint_load"])
            assert row["transition"].startswith("no transition detected in ")


def test_closed_form_modulus_on_hertz_data(hertz_study):
    """On data from the Hertz micro model the closed form (Eq. 3.6 inverted at the friction
    breakpoint) recovers E_s within 40 %, and the model fit within 20 %. A break in the outer
    fifth of the load range (here P03's, at 2.8 N with 4 of 24 strokes above it) is not reported,
    and neither is an E_s from it."""
    _, truth, result = hertz_study
    parts = result.participants.set_index("participant")
    cond = result.conditions.set_index(["participant", "sample"])
    reported = 0
    for pid, tr in truth["participants"].items():
        assert parts.loc[pid, "skin_modulus"] == pytest.approx(tr["skin_modulus"], rel=0.20)
        row = cond.loc[(pid, "bumps")]
        if row["breakpoint_outside"]:
            assert not row["breakpoint_detected"] and math.isnan(row["breakpoint_load"])
            assert math.isnan(row.get("skin_modulus_closed_form", math.nan))
            assert "edge of the load range" in row["transition"]
            continue
        reported += 1
        assert row["skin_modulus_closed_form"] == pytest.approx(tr["skin_modulus"], rel=0.40)
        lo, hi = row["skin_modulus_closed_form_ci_low"], row["skin_modulus_closed_form_ci_high"]
        assert lo <= row["skin_modulus_closed_form"] <= hi
        assert row["breakpoint_edge_low"] <= row["breakpoint_load"] <= row["breakpoint_edge_high"]
    assert reported >= 3
    if reported < len(truth["participants"]):  # the report says why, too
        from fingerpad.measure.htmlreport import conditions_table

        assert "the best change lies at the edge of the load range" in conditions_table(result)


def test_normalisation_reduces_spread(study):
    _, _, result = study
    summary = result.spread_summary.set_index("sample")
    assert summary.loc["bumps", "cv_norm"] < summary.loc["bumps", "cv_raw"]
    assert summary.loc["bumps", "reduction"] > 0.2
    ref = result.strokes[result.strokes["sample"] == "flat"]
    assert ref["mu_norm"].median() == pytest.approx(1.0, abs=0.03)


def test_closed_form_matches_eq_3_6():
    finger = get_finger("default")
    geometry = dict(radius=50e-6, height=18e-6, spacing=100e-6)
    f_crit = m.transition_load(0.3e6, ridge_area=finger, **geometry)
    from fingerpad.micro.hertz import HertzUnitCell

    cell = HertzUnitCell.for_finger(finger.with_overrides(skin_modulus=0.3e6), **geometry)
    assert f_crit == pytest.approx(cell.critical_load(finger.ridge_area), rel=1e-6)
    assert m.modulus_from_transition(f_crit, ridge_area=finger, **geometry) == pytest.approx(0.3e6, rel=1e-6)
    # a constant ridge area: E1* = 9 F lambda^2 / (8 sqrt(h^3 R) A_fr), rigid texture
    e = m.modulus_from_transition(1.0, ridge_area=50e-6, skin_poisson=0.5, **geometry)
    e1 = 9 * 1.0 * 100e-6**2 / (8 * math.sqrt(18e-6**3 * 50e-6) * 50e-6)
    assert e == pytest.approx(0.75 * e1)


def test_breakpoint_recovered_profile_and_bootstrap():
    rng = np.random.default_rng(1)
    f = np.geomspace(0.1, 5, 60)
    y = np.exp(np.where(f < 0.8, 0.25 * np.log(f / 0.8), 0.6 * np.log(f / 0.8)) + 0.02 * rng.standard_normal(f.size))
    for method in ("profile", "bootstrap"):
        bp = m.find_breakpoint(f, y, method=method, trend="steeper", n_boot=50)
        assert bp.ci_low < 0.8 < bp.ci_high
        assert bp.load == pytest.approx(0.8, rel=0.2)
        assert bp.slope_below == pytest.approx(0.25, abs=0.05) and bp.slope_above == pytest.approx(0.6, abs=0.05)
        # Issue 10 (on purpose): the p-value is now the sup-LR parametric bootstrap, whose
        # smallest value is 1 / (n_null + 1); before, an F-test that ignored the location search.
        assert bp.detected and bp.p_value == pytest.approx(1 / (bp.n_null + 1))
    with pytest.raises(FingerpadError, match="need at least 7 points"):
        m.find_breakpoint(f[:5], y[:5])


def test_estimate_skin_modulus_with_injected_model():
    def model(loads, e):  # toy model: the stiffer the skin, the lower the normalised friction
        return 0.5 * (np.asarray(loads) / (e / 1e5)) ** 0.3

    rng = np.random.default_rng(2)
    f = np.geomspace(0.1, 4, 40)
    y = model(f, 3e5) * np.exp(0.05 * rng.standard_normal(f.size))
    fit = m.estimate_skin_modulus(f, y, model)
    assert fit.ci_low < 3e5 < fit.ci_high
    assert fit.skin_modulus == pytest.approx(3e5, rel=0.1)
    with pytest.raises(FingerpadError, match="model returned"):
        m.estimate_skin_modulus(f, y, lambda loads, e: np.ones(3))


# =============================================================================================
# bad input: FingerpadError naming file and row
# =============================================================================================


def test_missing_column(tmp_path):
    s = reciprocating()
    f = write_csv(tmp_path / "P1_glass_1.csv", ["time", "Fn", "x"], [s["time"], s["normal"], s["position"]])
    with pytest.raises(FingerpadError, match=r"P1_glass_1\.csv: no friction force column"):
        m.load_study([f])


def test_unknown_unit(tmp_path):
    s = reciprocating()
    f = write_csv(tmp_path / "P1_glass_1.csv", ["time", "Fn [kg]", "Ft [N]"], [s["time"], s["normal"], s["friction"]])
    with pytest.raises(FingerpadError, match=r"P1_glass_1\.csv, column 'Fn \[kg\]': unknown force unit 'kg'"):
        m.load_study([f])


def test_time_backwards(tmp_path):
    s = reciprocating()
    t = s["time"].copy()
    t[100] = t[98]  # data row 101 -> file line 102 (after the header)
    f = write_csv(tmp_path / "P1_glass_1.csv", ["time", "Fn", "Ft"], [t, s["normal"], s["friction"]])
    with pytest.raises(FingerpadError, match=r"P1_glass_1\.csv, row 102: time does not increase"):
        m.load_study([f])


def test_nan_and_text(tmp_path):
    s = reciprocating()
    fn = s["normal"].copy()
    fn[40] = np.nan
    f = write_csv(tmp_path / "P1_glass_1.csv", ["time", "Fn", "Ft"], [s["time"], fn, s["friction"]])
    with pytest.raises(FingerpadError, match=r"P1_glass_1\.csv, row 42: missing or non-finite value in column 'Fn'"):
        m.load_study([f])
    (rec,) = m.load_study([f], m.ColumnSpec(nan_policy="drop"))
    assert len(rec) == s["time"].size - 1
    lines = f.read_text().splitlines()
    lines[10] = lines[10].replace(lines[10].split(",")[2], "abc")
    f.write_text("\n".join(lines) + "\n")
    with pytest.raises(FingerpadError, match=r"row 11: cannot read 'abc' in column 'Ft'"):
        m.read_recording(f)


def test_too_few_strokes(tmp_path):
    f = simple_file(tmp_path / "P1_glass_1.csv", n_strokes=1)
    (rec,) = m.load_study([f])
    with pytest.raises(FingerpadError, match=r"P1_glass_1\.csv: found 1 usable stroke\(s\) in rows 2-\d+, need at least 2"):
        m.stroke_table([rec])


def test_participant_without_reference(tmp_path):
    for name in ("P1_flat_1", "P1_glass_1", "P2_glass_1"):
        simple_file(tmp_path / f"{name}.csv", n_strokes=6, load=1.0)
    recs = m.load_study([tmp_path])
    # loads must vary for a power law: give every stroke its own load
    for i, rec in enumerate(recs):
        rec.normal *= np.linspace(0.3, 3.0, len(rec))
    with pytest.raises(FingerpadError, match=r"participant 'P2' has no recordings of the reference sample 'flat' \(P2_glass_1\.csv\)"):
        m.analyse_study(recs, m.AnalysisOptions(reference="flat"))
    with pytest.raises(FingerpadError, match="reference sample 'glas' is not in the data"):
        m.analyse_study(recs, m.AnalysisOptions(reference="glas"))


def test_manifest_errors(tmp_path):
    simple_file(tmp_path / "a.csv")
    (tmp_path / "manifest.csv").write_text("file,participant,sample\na.csv,P1,flat\nmissing.csv,P1,glass\n")
    with pytest.raises(FingerpadError, match=r"manifest\.csv, row 3: data file 'missing\.csv' not found"):
        m.load_study([tmp_path])
    (tmp_path / "manifest.csv").write_text("file,sample\na.csv,flat\n")
    with pytest.raises(FingerpadError, match=r"manifest\.csv: manifest lacks column\(s\) participant"):
        m.read_manifest(tmp_path / "manifest.csv")


def test_samples_table_errors(tmp_path):
    p = tmp_path / "samples.csv"
    p.write_text("sample,radius,height,spacing\nflat,,,\nbumps,50um,18um,100kg\n")
    with pytest.raises(FingerpadError, match=r"samples\.csv, row 3: spacing: .*100kg"):
        m.read_textures(p)
    p.write_text("sample,radius,height,spacing,full_contact_ratio\nflat,,,\nbumps,50um,18um,0.1mm,2\n")
    tex = m.read_textures(p)
    assert tex["flat"] is None and tex["bumps"].spacing == pytest.approx(1e-4)
    assert tex["bumps"].full_contact_ratio == 2.0


# =============================================================================================
# outputs: nothing half-written
# =============================================================================================


def test_report_atomic(study, tmp_path, monkeypatch):
    from fingerpad.measure import report

    _, _, result = study
    out = tmp_path / "res"
    out.mkdir()
    (out / "report.html").write_text("an earlier report")  # an earlier analysis: replaced as a whole
    (out / MANIFEST).write_text('{"files": ["report.html"]}')  # written by fingerpad (the manifest says so)

    def boom(*args, **kwargs):
        raise FingerpadError("figure failed")

    monkeypatch.setattr(report, "participant_png", boom)  # after the tables are written
    with pytest.raises(FingerpadError, match="figure failed"):
        # every figure drawn here: a pool's workers, once their QC sheets are done, may draw
        # every participant figure before this process reaches the failing one
        report.write_report(result, out, workers=1)
    assert sorted(p.name for p in out.iterdir()) == [MANIFEST, "report.html"]  # left as it was
    other = tmp_path / "other"
    other.mkdir()
    (other / "keep.txt").write_text("mine")
    with pytest.raises(FingerpadError, match="did not write"):
        report.write_report(result, other)  # never mixed with another study's files
    assert sorted(p.name for p in other.iterdir()) == ["keep.txt"]
    with pytest.raises(FingerpadError):
        report.write_report(result, tmp_path / "new", workers=1)
    assert not (tmp_path / "new").exists()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


def test_write_report_contents(study, tmp_path):
    import xarray as xr

    from fingerpad.measure.report import write_report

    _, truth, result = study
    files = write_report(result, tmp_path / "res", figures=False)
    names = {p.name for p in files}
    assert {"summary.csv", "summary.json", "curves.nc", "report.html", "strokes.csv"} <= names
    summary = json.loads((tmp_path / "res" / "summary.json").read_text())
    assert summary["study"]["reference_sample"] == "flat"
    assert len(summary["participants"]) == len(truth["participants"])
    # the population numbers say where they come from, in the JSON, the table and the page
    (pop,) = [r for r in summary["population_fits"] if r["sample"] == "flat"]
    assert pop["source"] in ("mixed model", "two-stage") and pop["two_stage_n"] is not None
    assert "population" in summary["study"] and summary["study"]["n_clipped_strokes"] == 0
    html = (tmp_path / "res" / "report.html").read_text()
    assert "numbers from" in html and f">{pop['source']}</td>" in html
    with xr.open_dataset(tmp_path / "res" / "curves.nc", engine="h5netcdf") as ds:
        assert set(ds["participant"].values) == set(truth["participants"])
        assert ds["skin_modulus"].sel(condition="bumps").notnull().all()
        assert ds["mu_fit"].attrs["units"] == "1"


# =============================================================================================
# command line
# =============================================================================================


@pytest.fixture()
def app():
    application = typer.Typer()
    register(application)
    return application


def test_cli_simulate_and_analyse(app, tmp_path):
    runner = CliRunner()
    sim, res = tmp_path / "sim", tmp_path / "res"
    r = runner.invoke(app, ["simulate-measurement", "--out", str(sim), "--participants", "2", "--strokes", "10",
                            "--seed", "5"])
    assert r.exit_code == 0, r.output
    truth = json.loads((sim / "truth.json").read_text())
    assert len(list(sim.glob("P0*_*.csv"))) == 8 and (sim / "manifest.csv").is_file()
    r = runner.invoke(app, ["analyse", str(sim), "--reference", "flat", "--out", str(res), "--qc-recordings"])
    assert r.exit_code == 0, r.output
    html = (res / "report.html").read_text()
    # issue 10: the report names quantities for people (E_s in MPa), not by column name
    assert "data:image/png;base64," in html and "E<sub>s</sub> model fit (MPa)" in html
    assert {p.name for p in (res / "figures").iterdir() if p.is_file()} == {
        "participant_P01.png", "participant_P02.png", "sample_bumps.png", "sample_flat.png",
        "qc_P01.png", "qc_P02.png"}  # a QC sheet per participant
    assert len(list((res / "figures" / "qc").glob("*.png"))) == 8  # --qc-recordings: one full figure each
    import pandas as pd

    summary = pd.read_csv(res / "summary.csv")
    bumps = summary[summary["sample"] == "bumps"].set_index("participant")
    for pid, tr in truth["participants"].items():
        assert bumps.loc[pid, "skin_modulus"] == pytest.approx(tr["skin_modulus"], rel=0.25)


def test_cli_errors_leave_nothing(app, tmp_path):
    runner = CliRunner()
    sim, res = tmp_path / "sim", tmp_path / "res"
    r = runner.invoke(app, ["simulate-measurement", "--out", str(sim), "--participants", "1", "--repetitions", "1",
                            "--strokes", "6"])
    assert r.exit_code == 0, r.output
    r = runner.invoke(app, ["analyse", str(sim), "--reference", "glass", "--out", str(res)])
    assert r.exit_code == 2
    assert r.stderr.strip() == "error: reference sample 'glass' is not in the data (samples: bumps, flat)"
    assert not res.exists()
    r = runner.invoke(app, ["analyse", str(sim), "--reference", "flat", "--out", str(res), "--trim", "0.9"])
    assert r.exit_code == 2 and r.stderr.startswith("error: trim must lie in [0, 0.45]") and not res.exists()
    r = runner.invoke(app, ["simulate-measurement", "--out", str(tmp_path / "x"), "--loads", "5N:1N"])
    assert r.exit_code == 2 and "--loads" in r.stderr and not (tmp_path / "x").exists()


def test_simulation_deterministic(tmp_path):
    cfg = m.SimulationConfig(participants=1, repetitions=1, strokes_per_file=4)
    m.simulate_study(tmp_path / "a", cfg, seed=11)
    m.simulate_study(tmp_path / "b", cfg, seed=11)
    m.simulate_study(tmp_path / "c", cfg, seed=12)
    names = sorted(p.name for p in (tmp_path / "a").iterdir())
    assert names == sorted(p.name for p in (tmp_path / "b").iterdir())
    assert all((tmp_path / "a" / n).read_bytes() == (tmp_path / "b" / n).read_bytes() for n in names)
    assert (tmp_path / "a" / "P01_flat_1.csv").read_bytes() != (tmp_path / "c" / "P01_flat_1.csv").read_bytes()


def test_a_manifests_files_are_read_by_two_threads_in_its_order(tmp_path, monkeypatch):
    """The files a manifest lists are read by two threads (the CSV parser lets go of the
    interpreter), not one after another in one: the same recordings, in the manifest's order."""
    import threading
    import time

    from fingerpad.measure import recordings as rec_module

    names = [f"r{i}.csv" for i in range(8)]
    for name in names:
        simple_file(tmp_path / name)
    (tmp_path / "manifest.csv").write_text("file,participant,sample\n" + "".join(f"{n},P{i},s\n" for i, n in enumerate(names)))
    threads = set()
    real = rec_module.read_recording

    def slow(*args, **kwargs):
        threads.add(threading.get_ident())
        time.sleep(0.05)  # long enough that the second thread starts on the next file
        return real(*args, **kwargs)

    monkeypatch.setattr(rec_module, "read_recording", slow)
    recs = m.load_study([tmp_path])
    assert [r.participant for r in recs] == [f"P{i}" for i in range(8)]
    assert [Path(r.source).name for r in recs] == names
    assert len(threads) == 2
