"""``fingerpad analyse``: ranges decided in one place (the options classes), and a summary
that fits an 80-column terminal."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest
import typer
from typer.testing import CliRunner

from fingerpad import measure as m
from fingerpad.cli.measure import _print_summary, register
from fingerpad.errors import FingerpadError


@pytest.fixture()
def app():
    application = typer.Typer()
    register(application)
    return application


class _Stop(Exception):
    pass


@pytest.fixture()
def captured(monkeypatch):
    """Stop ``analyse`` at the library call, keeping the options it built: the options were
    accepted exactly when the call is reached."""
    seen = {}

    def fake_analyse(recordings, options, **kw):
        seen["options"] = options
        raise FingerpadError("stopped before the work")

    monkeypatch.setattr(m, "load_study", lambda *a, **k: [])
    monkeypatch.setattr(m, "analyse_study", fake_analyse)
    return seen


# option, library field, values on both sides of every bound (the CLI had its own, stricter
# ranges for --level (0.5-0.999) and --outlier-z (>= 0.5))
CASES = [
    ("--level", lambda v: m.AnalysisOptions(level=float(v)), ["0.3", "0.9995", "0.95", "1", "0", "-0.2"]),
    ("--outlier-z", lambda v: m.AnalysisOptions(outlier_z=float(v)), ["0.3", "0.5", "3.5", "0", "-1"]),
    ("--trim", lambda v: m.StrokeOptions(trim=float(v)), ["0", "0.45", "0.46", "-0.1"]),
    ("--n-null", lambda v: m.AnalysisOptions(n_null=int(v)), ["19", "18", "999"]),
    ("--bins", lambda v: m.AnalysisOptions(n_bins=int(v)), ["1", "0", "-3"]),
    ("--seed", lambda v: m.AnalysisOptions(seed=int(v)), ["0", "7", "-1"]),
    ("--min-strokes", lambda v: m.StrokeOptions(min_strokes=int(v)), ["1", "0"]),
    ("--trend", lambda v: m.AnalysisOptions(breakpoint_trend=v), ["any", "steeper", "up"]),
]


@pytest.mark.parametrize("option, build, values", CASES, ids=[c[0] for c in CASES])
def test_cli_accepts_exactly_what_the_library_accepts(app, captured, tmp_path, option, build, values):
    runner = CliRunner()
    for value in values:
        try:
            build(value)
            library_ok, library_error = True, ""
        except FingerpadError as exc:
            library_ok, library_error = False, str(exc)
        res = runner.invoke(app, ["analyse", str(tmp_path), "--reference", "flat", "--out",
                                  str(tmp_path / "out"), option, value])
        assert res.exit_code == 2  # every run ends: either at the library call or at the check
        line = res.stderr.strip()
        assert line.count("\n") == 0 and line.startswith("error: ")
        if library_ok:
            assert line == "error: stopped before the work", (option, value, line)
        else:  # the library's own message, not a second opinion of the CLI
            assert line == f"error: {library_error}", (option, value, line)


def test_cli_still_parses(app, captured, tmp_path):
    res = CliRunner().invoke(app, ["analyse", str(tmp_path), "--reference", "flat", "--out", str(tmp_path / "o"),
                                   "--level", "high"])
    assert res.exit_code == 2 and res.stderr.strip() == "error: --level: expected a number, got 'high'"
    res = CliRunner().invoke(app, ["analyse", str(tmp_path), "--reference", "flat", "--out", str(tmp_path / "o"),
                                   "--level", "0.3", "--outlier-z", "0.2", "--trend", " Steeper "])
    assert res.stderr.strip() == "error: stopped before the work"
    opts = captured["options"]
    assert (opts.level, opts.outlier_z, opts.breakpoint_trend) == (0.3, 0.2, "steeper")


# =============================================================================================
# the E_s table at 80 columns
# =============================================================================================


def _stub_result(rows: list[dict]) -> SimpleNamespace:
    strokes = pd.DataFrame({"participant": ["P1"], "sample": ["flat"], "file": ["a"], "outlier": [False]})
    return SimpleNamespace(strokes=strokes, participants=pd.DataFrame(rows), conditions=pd.DataFrame(),
                           spread_summary=pd.DataFrame(columns=["is_reference", "reduction"]),
                           options=SimpleNamespace(level=0.95))


def test_modulus_table_fits_80_columns(monkeypatch, capsys, tmp_path):
    """Worst cases of the cells: a two-piece set, an undetermined E_s, long participant names."""
    monkeypatch.setenv("COLUMNS", "80")
    rows = [
        {"participant": "P01", "ref_k": 0.4721, "ref_n": 0.6081, "skin_modulus": 2.91e5,
         "skin_modulus_interval": "0.179-0.452 MPa", "skin_modulus_model": "bem", "skin_modulus_other": 3.31e5,
         "skin_modulus_other_model": "hertz", "skin_modulus_sens_low": 1.54e5, "skin_modulus_sens_high": 1.71e6},
        {"participant": "volunteer-12", "ref_k": 0.376, "ref_n": 0.711, "skin_modulus": 3.72e5,
         "skin_modulus_determined": False, "skin_modulus_interval": "0.0213-0.162 or 1.56-19.9 MPa",
         "skin_modulus_model": "hertz", "skin_modulus_other": math.nan, "skin_modulus_sens_low": math.nan,
         "skin_modulus_sens_high": math.nan},
    ]
    _print_summary(_stub_result(rows), [], tmp_path)
    out = capsys.readouterr().out
    lines = out.splitlines()
    assert max(len(line) for line in lines) <= 80
    assert "…" not in out
    for piece in ("0.179-0.452", "0.0213-0.162", "1.56-19.9", "0.154-1.71", "0.331", "volunteer-12"):
        assert any(piece in line for line in lines), piece  # whole, on one line


def test_labels_from_files_are_printed_escaped(monkeypatch, capsys, tmp_path):
    """Issue 30, item 12: a participant label holding terminal escapes cleared the screen and
    recoloured it; one holding Rich markup lost its brackets."""
    monkeypatch.setenv("COLUMNS", "120")
    evil = "P01\x1b[2J\x1b[31m[bold]x\u202e"
    rows = [{"participant": evil, "ref_k": 0.47, "ref_n": 0.61, "skin_modulus": 2.91e5,
             "skin_modulus_interval": "0.179-0.452 MPa", "skin_modulus_model": "bem", "skin_modulus_other": math.nan,
             "skin_modulus_sens_low": math.nan, "skin_modulus_sens_high": math.nan}]
    result = _stub_result(rows)
    result.conditions = pd.DataFrame([{"participant": evil, "sample": "bumps\x07", "direction": "",
                                       "transition": "no transition detected"}])
    _print_summary(result, [], tmp_path)
    out = capsys.readouterr().out
    assert "\x1b" not in out and "\x07" not in out and "\u202e" not in out
    assert "P01\\x1b[2J\\x1b[31m[bold]x\\u202e" in out  # shown as written, escapes visible
    assert "P01\\x1b[2J\\x1b[31m[bold]x\\u202e bumps\\x07: no transition detected" in out


def test_analyse_summary_at_80_columns(app, small_study_dir, tmp_path):
    """The real command on a simulated study: every 95 % set printed whole."""
    res = CliRunner(env={"COLUMNS": "80"}).invoke(
        app, ["analyse", str(small_study_dir), "--reference", "flat", "--out", str(tmp_path / "r"), "--no-figures",
              "--n-null", "99"])
    assert res.exit_code == 0, res.output
    lines = res.stdout.splitlines()
    table = [line for line in lines if line.startswith("P0")]
    assert table and max(len(line) for line in lines) <= 80 and "…" not in res.stdout
    parts = pd.read_csv(tmp_path / "r" / "participants.csv")
    for row in parts.itertuples():
        interval = str(row.skin_modulus_interval).removesuffix(" MPa")
        assert any(line.startswith(row.participant) and interval in line for line in table), interval
    assert np.isfinite(parts["skin_modulus"]).all()


def test_simulate_several_textures_from_a_sample_table(app, tmp_path):
    """``simulate-measurement --samples``: the textures of a sample table (the format ``analyse
    --samples`` reads), each with its own micro-model; the study's samples.csv lists them as
    the table gave them, and a recording per participant, sample and repetition is written."""
    table = tmp_path / "textures.csv"
    table.write_text("sample,radius,height,spacing,micro_model,full_contact_ratio\n"
                     "flat,,,,,\n"
                     "edge,50um,18um,100um,hertz,1.5\n"
                     "low,40um,8um,90um,hertz,\n")
    out = tmp_path / "sim"
    res = CliRunner().invoke(app, ["simulate-measurement", "--out", str(out), "--participants", "2",
                                   "--repetitions", "1", "--strokes", "4", "--samples", str(table)])
    assert res.exit_code == 0, res.output
    assert sorted(p.name for p in out.glob("P*.csv")) == [f"P0{i}_{s}_1.csv" for i in (1, 2)
                                                          for s in ("edge", "flat", "low")]
    assert m.read_textures(out / "samples.csv") == {k: v for k, v in m.read_textures(table).items()}
    assert "wrote 6 recordings" in res.stdout


@pytest.mark.parametrize("extra, rows, message", [
    (["--height", "20um"], "bumps,50um,18um,100um\n", "--samples gives the textures: leave out --height"),
    (["--texture", "x", "--micro-model", "hertz"], "bumps,50um,18um,100um\n",
     "--samples gives the textures: leave out --texture, --micro-model"),
    ([], "glass,,,\nbumps,50um,18um,100um\n", "sample 'glass' has no geometry"),
    ([], "flat,,,\n", "no textured sample"),
    ([], "flat,50um,18um,100um\n", "the reference 'flat' cannot also be a textured sample"),
    ([], "bumps,50um,-1um,100um\n", "row 2"),
])
def test_simulate_sample_table_mistakes_are_one_line(app, tmp_path, extra, rows, message):
    table = tmp_path / "textures.csv"
    table.write_text("sample,radius,height,spacing\n" + rows)
    out = tmp_path / "sim"
    res = CliRunner().invoke(app, ["simulate-measurement", "--out", str(out), "--samples", str(table), *extra])
    assert res.exit_code == 2, res.output
    assert res.stderr.startswith("error: ") and message in res.stderr and res.stderr.count("\n") == 1
    assert not out.exists()


@pytest.mark.parametrize("field, bad", [("level", 1.5), ("n_bins", 0), ("outlier_z", -1.0), ("n_null", 10),
                                        ("breakpoint_space", "ln"), ("breakpoint_method", "guess"),
                                        ("breakpoint_trend", "up"), ("seed", -1)])
def test_each_setting_is_named_alone_with_its_option(field, bad):
    """A bad setting is named alone with the analyse option that sets it (it was 'n_null must lie
    in ... and n_boot in ..., got X and 200', naming a setting the user had not touched)."""
    from fingerpad.measure.study import ANALYSIS_OPTION_NAMES

    with pytest.raises(FingerpadError) as info:
        m.AnalysisOptions(**{field: bad})
    message = str(info.value)
    assert message.startswith(f"{field} ({ANALYSIS_OPTION_NAMES[field]}): ") and message.endswith(f"got {bad!r}")
    others = set(ANALYSIS_OPTION_NAMES) - {field}
    assert not any(f"{other} " in message or f"{other}:" in message for other in others)


def test_library_only_settings_are_named_and_capped():
    with pytest.raises(FingerpadError, match=r"^n_boot: must lie in 20\.\.100000, got 10$"):
        m.AnalysisOptions(n_boot=10)
    with pytest.raises(FingerpadError, match=r"^min_fit_strokes: must lie in 3\.\.100000, got 10000000$"):
        m.AnalysisOptions(min_fit_strokes=10_000_000)
