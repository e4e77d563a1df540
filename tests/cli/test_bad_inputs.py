"""Bad inputs as a new user gives them, against the contract: one ``error:`` line on stderr, exit
code 2, no traceback, nothing written, the same message at every door (issue 30).

Each case fails before any long work (a check up front), so the whole file runs in seconds.
benchmarks/bad_inputs.py runs a wider list as real subprocesses and counts tried / held / broke.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from fingerpad.cli import app

runner = CliRunner()
CAPS = ["--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "100um"]
BIG = "9" * 5000  # more digits than Python converts to int by default (4300)
STUDY = """
[texture]
name = "caps"
radius = "100um"
height = "20um"
spacing = "175um"
[model]
grid = 16
{model}
[sweep]
loads = "0.1N:4N:4"
{sweep}
[sweep.axes]
spacing = "130um:300um:2"
"""


def error_line(result) -> str:
    assert result.exit_code == 2, (result.exit_code, result.output[-2000:])
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr[-2000:]
    assert "Traceback" not in result.output
    return lines[0]


@pytest.fixture
def here(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


def study(folder: Path, model: str = "", sweep: str = "") -> str:
    (folder / "s.toml").write_text(STUDY.format(model=model, sweep=sweep))
    return "s.toml"


# ------------------------------------------------------------------------------------------------
# every count a user can give has a cap (issue 30, items 4, 13 and 19)

COUNTS = [
    (["sweep", "S", "--workers", "100000"], r"--workers: must be at most \d+, got 100000"),
    (["sweep", "S", "--workers", "0"], "--workers: must be at least 1, got 0"),
    (["sweep", "S", "--workers", BIG], r"--workers: must be at most \d+, got a number of 5000 digits"),
    (["predict", *CAPS, "--grid", BIG], "--grid: must be at most 8192, got a number of 5000 digits"),
    (["predict", *CAPS, "--max-iter", BIG], "--max-iter: must be at most 100000, got a number of 5000 digits"),
    (["predict", *CAPS, "--max-iter", "1000000"], "--max-iter: must be at most 100000, got 1000000"),
    (["solve", *CAPS, "--pressure", "1kPa", "--grid", BIG], "--grid: must be at most 8192, got a number of 5000 "),
    (["solve", *CAPS, "--pressure", "1kPa", "--max-iter", "10000000"], "--max-iter: must be at most 100000"),
    (["solve", *CAPS, "--pressure", f"1kPa:2kPa:{BIG}"], "--pressure: COUNT of 5000 digits is more than the 10000"),
    (["predict", *CAPS, "--loads", f"1N:2N:{BIG}"], "--loads: COUNT of 5000 digits is more than"),
    (["design", "S", "--vary", "spacing=100um:400um", "--target", "mu_rel=0.5@1N", "--candidates", "1000000000"],
     "--candidates: must be at most 10000"),
    (["design", "S", "--vary", "spacing=100um:400um", "--target", "mu_rel=0.5@1N", "--evaluations", BIG],
     "--evaluations: must be at most 10000, got a number of 5000 digits"),
    (["analyse", "D", "--reference", "flat", "--out", "r", "--n-null", "1000000000"],
     r"n_null \(--n-null\): must lie in 19..100000, got 1000000000"),
    (["analyse", "D", "--reference", "flat", "--out", "r", "--n-null", BIG], "--n-null: must be an integer of at most 30 digits"),
    (["analyse", "D", "--reference", "flat", "--out", "r", "--bins", "1000000"], r"n_bins \(--bins\): must lie in 1..1000, got 1000000"),
    (["simulate-measurement", "--out", "sim", "--participants", "300000"],
     "participants: at most 1000 in a simulated study, got 300000"),
    (["simulate-measurement", "--out", "sim", "--seed", BIG], "--seed: must be"),
]


@pytest.mark.parametrize("args, message", COUNTS, ids=[" ".join(a[:1] + a[-2:-1]) for a, _ in COUNTS])
def test_every_count_has_a_cap(here, args, message):
    import re

    (here / "D").mkdir()
    study(here)
    args = ["s.toml" if a == "S" else a for a in args]
    line = error_line(runner.invoke(app, args))
    assert re.search(message, line), line
    assert len(line) < 400  # a 5000-digit value is not echoed back
    assert sorted(p.name for p in here.iterdir()) == ["D", "s.toml"]  # nothing written


@pytest.mark.parametrize("model, sweep, message", [
    (f'max_iter = "{BIG}"', "", r"\[model\] max_iter: must be at most 100000, got a number of 5000 digits"),
    ('grid = "99999999"', "", None),  # [model] grid given twice in the template: replaced below
    ("", 'chunk = "abc"', r"\[sweep\] chunk: expected an integer, got 'abc'"),
    ("", "chunk = [1]", r"\[sweep\] chunk: expected an integer, got \[1\]"),
    ("", "chunk = 1.5", r"\[sweep\] chunk: expected an integer, got 1.5"),
    ("", "chunk = 10000000", r"\[sweep\] chunk: must be at most 1000000"),
    ("", 'design = "lhs"\npoints = 1000000000000', r"\[sweep\] points: must be at most 1000000"),
    ("", 'design = "lhs"\npoints = 4\nseed = -1', r"\[sweep\] seed: must be at least 0, got -1"),
])
def test_study_file_counts_have_caps(here, model, sweep, message):
    import re

    text = STUDY.format(model=model, sweep=sweep)
    if message is None:
        text = text.replace("grid = 16\n", "")
        message = r"\[model\] grid: must be at most 8192, got 99999999"
    if "lhs" in sweep:
        text = text.replace('spacing = "130um:300um:2"', 'spacing = "130um:300um"')
    (here / "s.toml").write_text(text)
    line = error_line(runner.invoke(app, ["sweep", "s.toml", "--out", "r.zarr"]))
    assert re.search(message, line), line


def test_the_explorer_grid_field_is_capped():
    from fingerpad.explore.inputs import validate

    data = {"texture": {"name": "caps", "radius": "50um", "height": "10um", "spacing": "100um"},
            "model": {"grid": BIG}}
    errors = [e for e in validate(data).errors if e.field == "model.grid"]
    assert len(errors) == 1 and "must be at most 8192, got a number of 5000 digits" in errors[0].message


# ------------------------------------------------------------------------------------------------
# messages that said something else than what was wrong (issue 30, item 19)


def test_a_non_finite_number_is_not_read_as_a_missing_unit():
    from fingerpad.errors import FingerpadError
    from fingerpad.params import Param

    p = Param("sd", "length", "a spread", low=0)
    for value in ("nan", float("nan"), "inf", "-inf"):
        with pytest.raises(FingerpadError, match=r"^sd: must be a finite number, got "):
            p.parse(value, "sd", require_unit=True)  # it said: 'nan' has no unit ... "nanm"


def test_a_unit_where_a_plain_number_is_expected_says_so():
    from fingerpad.errors import FingerpadError
    from fingerpad.units import parse_quantity

    with pytest.raises(FingerpadError, match=r"^values: '5kPa' is a pressure, expected a plain number \(no unit\)$"):
        parse_quantity("5kPa", "none", name="values")  # it said: expected a none


def test_design_vary_names_its_option(here):
    line = error_line(runner.invoke(app, ["design", study(here), "--vary", "nosuch=1:2", "--target", "mu_rel=0.5@1N"]))
    assert line.startswith("error: --vary 'nosuch' is not a parameter of texture 'caps'"), line  # not "[sweep] axis"


def test_a_layer_modulus_is_named_as_given_at_every_door(here):
    caps = [*CAPS, "--grid", "16"]
    layer = ["--skin-layer-thickness", "300um", "--skin-layer-modulus", "1e12Pa", "--skin-substrate-modulus", "40kPa"]
    for command in (["solve", *caps, *layer, "--pressure", "1kPa"], ["predict", *caps, *layer, "--loads", "1N",
                                                                       "--json", "-"]):
        res = runner.invoke(app, command)
        warned = [ln for ln in res.stderr.splitlines() if ln.startswith("warning:")]
        assert warned and warned[0].startswith("warning: --skin-layer-modulus = 1000 GPa is very large for a skin "
                                               "layer modulus"), (command[0], res.stderr)  # solve said --skin-modulus


def test_fingers_lists_models_in_words_and_units():
    # wide enough that no model's cell wraps (main's adhesion columns widened the table)
    res = runner.invoke(app, ["fingers"], env={"COLUMNS": "300"})
    assert res.exit_code == 0
    assert "HertzArea(" not in res.stdout and "ConstantFractionRidges(" not in res.stdout  # Python reprs
    assert "hertz: R_fp 9 mm, E_fp* 40 kPa" in res.stdout and "constant_fraction: fraction 0.5" in res.stdout
    assert "sinusoidal: wavelength 450 um" in res.stdout


@pytest.mark.parametrize("command", ["predict", "sweep", "design"])
def test_an_empty_population_is_named_empty(here, command):
    args = {"predict": ["predict", *CAPS, "--json", "-"], "sweep": ["sweep", study(here), "--out", "r.zarr"],
            "design": ["design", study(here), "--vary", "spacing=100um:400um", "--target", "mu_rel=0.5@1N",
                       "--coverage", "0.5"]}[command]
    line = error_line(runner.invoke(app, [*args, "--population", ""]))
    assert line.startswith("error: --population: empty; name a preset (adults"), line  # it named '.'


@pytest.mark.parametrize("value, message", [
    ("100000", "FINGERPAD_FFT_WORKERS must be a whole number of threads in 0..1024 (0: all cores), got 100000"),
    (BIG, "FINGERPAD_FFT_WORKERS must be a whole number of threads in 0..1024, got a value of 5000 characters"),
])
def test_fft_threads_have_a_cap(here, monkeypatch, value, message):
    monkeypatch.setenv("FINGERPAD_FFT_WORKERS", value)
    for command in (["solve", *CAPS, "--grid", "16", "--pressure", "1kPa"], ["predict", *CAPS, "--json", "-"]):
        res = runner.invoke(app, command)
        assert res.exit_code == 2 and res.stderr == f"error: {message}\n", res.stderr  # before any work



@pytest.mark.parametrize("args, message", [
    (["predict", *CAPS, "--grid", "16", "--json", "-", "--grid", "32"], "--grid is given twice (16 and 32): give it once"),
    (["predict", *CAPS, "--out=a", "--out", "b"], "--out is given twice (a and b): give it once"),
    (["solve", *CAPS, "--radius", "60um", "--pressure", "1kPa"], "--radius is given twice (50um and 60um): give it once"),
])
def test_an_option_given_twice_is_refused(here, args, message):
    """Found by the bad-input audit: the last one won silently."""
    line = error_line(runner.invoke(app, args))
    assert line.startswith(f"error: {message}"), line


@pytest.mark.parametrize("data, message", [
    (["texture"], "a study is a mapping of sections (texture, material, finger, loads, model, perception) to their "
                  "values, got list"),
    ({"texture": 3}, "[texture]: must be a table of values (a mapping), got int"),
    ({"texture": {"name": "flat", "size": "1mm"}, "loads": [1]}, "[loads]: must be a table of values (a mapping), "
                                                                 "got list"),
])
def test_study_from_dict_refuses_what_is_not_a_study(data, message):
    """Found by the bad-input audit: a TypeError or AttributeError traceback from the Python API."""
    from fingerpad.errors import FingerpadError
    from fingerpad.study import study_from_dict

    with pytest.raises(FingerpadError) as got:
        study_from_dict(data)
    assert str(got.value) == message



def test_csv_dash_is_not_a_file_named_dash(here):
    """Found by the bad-input audit: predict --csv - wrote a file named '-' (solve refused it)."""
    for command in (["predict", *CAPS, "--grid", "32", "--loads", "1N", "--json", "-"],
                    ["solve", *CAPS, "--grid", "32", "--pressure", "1kPa"]):
        line = error_line(runner.invoke(app, [*command, "--csv", "-"]))
        assert line == "error: --csv '-': the file name must end in .csv (the format follows it)", line
    assert not (here / "-").exists()


def test_a_manifest_given_as_the_sample_table_is_refused(tmp_path):
    """Found by the bad-input audit: analyse --samples manifest.csv read every sample as flat,
    its unknown columns ignored; a sample given twice took the last row silently."""
    from fingerpad.errors import FingerpadError
    from fingerpad.measure.micro_models import read_textures

    manifest = tmp_path / "manifest.csv"
    manifest.write_text("file,participant,sample,repetition\nP01_flat_1.csv,P01,flat,1\n")
    with pytest.raises(FingerpadError, match=r"unknown column\(s\) 'file', 'participant', 'repetition' in a sample "
                                             r"table \(columns: sample, radius"):
        read_textures(manifest)
    twice = tmp_path / "samples.csv"
    twice.write_text("sample,radius,height,spacing\nbumps,50um,10um,100um\nbumps,60um,10um,100um\n")
    with pytest.raises(FingerpadError, match=r"row 3: sample 'bumps' is given twice"):
        read_textures(twice)


def test_api_refusals_are_fingerpad_errors():
    """Found by the bad-input audit: tracebacks of other kinds from the Python API."""
    from fingerpad.errors import FingerpadError
    from fingerpad.finger import finger_param
    from fingerpad.textures import periodize

    with pytest.raises(FingerpadError, match=r"^unknown finger parameter 'nosuch' \(finger parameters: radius, "):
        finger_param("nosuch")  # was StopIteration
    with pytest.raises(FingerpadError, match="periodize takes a fingerpad Texture .*got list"):
        periodize([1, 2])  # was AttributeError


def test_the_sweep_summary_counts_one_worker_in_the_singular():
    """Issue 30, item 19: "1 workers"."""
    import io

    from rich.console import Console

    from fingerpad.cli.sweep import _summary
    from fingerpad.design.engine import SweepReport, eta

    for n, words in ((1, "1 worker)"), (2, "2 workers)")):
        out = io.StringIO()
        _summary(Console(file=out, width=200), SweepReport(points=4, computed=4, seconds=60.0, workers=n), "r.zarr", eta)
        assert words in out.getvalue().splitlines()[0], out.getvalue()
