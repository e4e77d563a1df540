"""The command line's contract: one `error:` line and exit 2 for any user mistake, nothing
half-written, files only where asked, units and plausibility, tables that fit the terminal."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from fingerpad.cli import app

runner = CliRunner()
CAPS = ["--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "100um", "--grid", "32"]


def invoke(*args, **kw):
    return runner.invoke(app, [str(a) for a in args], **kw)


def error_line(result) -> str:
    assert result.exit_code == 2, (result.exit_code, result.output)
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr
    return lines[0]


def listing(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


# ------------------------------------------------------------------------------------------------
# typer's own errors and unknown options


@pytest.mark.parametrize("args, expect", [
    (["solve", *CAPS, "--pressure"], "requires an argument"),
    (["predict", *CAPS, "--outt", "x"], "did you mean --out?"),
    (["solve", *CAPS, "--pressur", "1kPa"], "did you mean --pressure?"),
    (["solve", *CAPS[:6], "--heigth", "10um", "--spacing", "100um", "--pressure", "1kPa"], "did you mean --height?"),
    (["frobnicate"], "No such command"),
])
def test_usage_errors_are_one_line(args, expect):
    assert expect in error_line(invoke(*args))


@pytest.mark.parametrize("args, expect", [
    (["solve", *CAPS, "--pressure", "1kPa:10kPa:3", "--log", "--linear"], "contradict"),
    (["predict", *CAPS, "--log", "--linear"], "contradict"),
    (["predict", "--surface", "x.npy", "--periodic", "--no-periodic"], "contradict"),
    (["predict", *CAPS, "--loads", "4N:0.1N:5"], "below START"),
    (["solve", *CAPS, "--pressure", "10kPa:1kPa:5"], "below START"),
    (["solve", *CAPS, "--pressure", "1kPa:10kPa:100000000"], "allowed"),
    (["predict", *CAPS, "--loads", "0.1N:4N:100000000"], "allowed"),
])
def test_contradictions_and_sizes_are_errors(args, expect, tmp_path):
    assert expect in error_line(invoke(*args, "--cache", tmp_path) if args[0] == "predict" else invoke(*args))


def test_periodic_and_periodize_contradict(tmp_path):
    np.save(tmp_path / "m.npy", np.random.default_rng(0).random((16, 16)))
    line = error_line(invoke("solve", "--surface", tmp_path / "m.npy", "--size", "100um", "--height-unit", "um",
                             "--periodic", "--periodize", "--pressure", "1kPa"))
    assert "contradict" in line


def test_binary_study_file_is_one_line(tmp_path):
    path = tmp_path / "study.toml"
    path.write_bytes(bytes(range(256)) * 4)
    assert "not a text" in error_line(invoke("predict", path, "--out", tmp_path / "o"))
    assert not (tmp_path / "o").exists()


# ------------------------------------------------------------------------------------------------
# nothing half-written, files only where asked


def test_bad_json_path_writes_nothing(tmp_path):
    out = tmp_path / "out"
    line = error_line(invoke("predict", *CAPS, "--loads", "1N", "--out", out, "--json", tmp_path / "nope" / "p.json",
                             "--cache", tmp_path / "cache"))
    assert "does not exist" in line and not out.exists()


def test_json_to_stdout_writes_no_files(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    res = invoke("predict", *CAPS, "--model", "hertz", "--loads", "1N", "--json", "-")
    assert res.exit_code == 0, res.output
    assert json.loads(res.stdout)["model"] == "hertz"
    assert listing(tmp_path) == []  # neither the staging folder nor the lock


def test_out_folder_is_replaced_as_a_whole_or_refused(tmp_path):
    out = tmp_path / "out"
    first = invoke("run-default", "--out", out, "--grid", "16", "--loads", "1N:2N:2", "--cache", tmp_path / "c")
    assert first.exit_code == 0, first.output
    assert "ridge_models.png" in listing(out)
    second = invoke("predict", *CAPS, "--model", "hertz", "--loads", "1N", "--out", out)
    assert second.exit_code == 0, second.output
    assert "ridge_models.png" not in listing(out)  # no figure of another study left beside the new ones
    assert json.loads((out / "predict.json").read_text())["inputs"]["texture"]["params"]["spacing"] == pytest.approx(1e-4)
    (out / "notes.txt").write_text("mine")
    line = error_line(invoke("predict", *CAPS, "--model", "hertz", "--loads", "1N", "--out", out))
    assert "notes.txt" in line and (out / "notes.txt").read_text() == "mine"


@pytest.mark.parametrize("option, name", [("--plot", "x.txt"), ("--save", "x.json"), ("--json", "x.nc"),
                                          ("--csv", "x.png")])
def test_file_names_must_match_their_format(option, name, tmp_path):
    line = error_line(invoke("solve", *CAPS, "--pressure", "1kPa", option, tmp_path / name))
    assert "must end in" in line and listing(tmp_path) == []


def test_csv_tables(tmp_path):
    res = invoke("solve", *CAPS, "--pressure", "1kPa:10kPa:3", "--csv", tmp_path / "s.csv")
    assert res.exit_code == 0, res.output
    rows = list(csv.DictReader(open(tmp_path / "s.csv")))
    assert len(rows) == 3 and float(rows[0]["mean_pressure_Pa"]) == pytest.approx(1e3, rel=1e-6)
    res = invoke("predict", *CAPS, "--model", "hertz", "--loads", "0.5N:2N:3", "--csv", tmp_path / "p.csv",
                 "--json", "-")
    assert res.exit_code == 0, res.output
    rows = list(csv.DictReader(open(tmp_path / "p.csv")))
    assert [float(r["load_N"]) for r in rows] == pytest.approx([0.5, 1.0, 2.0])
    assert {"area_ratio_Are_over_Afr", "mu", "mu_over_mu_ref", "centre_state"} <= set(rows[0])


# ------------------------------------------------------------------------------------------------
# units, plausibility, tables


def test_angles_are_degrees_by_default(tmp_path):
    base = ["solve", "--texture", "ellipsoids", "--semi-axis-x", "40um", "--semi-axis-y", "20um", "--height",
            "10um", "--spacing-x", "100um", "--spacing-y", "100um", "--grid", "32", "--pressure", "1kPa", "--json", "-"]
    deg = json.loads(invoke(*base, "--orientation", "90").stdout)["inputs"]["texture"]["params"]["orientation"]
    rad = json.loads(invoke(*base, "--orientation", f"{math.pi / 2}rad").stdout)["inputs"]["texture"]["params"]
    assert deg == pytest.approx(math.pi / 2) and rad["orientation"] == pytest.approx(math.pi / 2)


def test_implausible_values_warn_once(tmp_path):
    res = invoke("solve", "--texture", "caps", "--radius", "50", "--height", "10um", "--spacing", "200",
                 "--grid", "16", "--pressure", "1kPa", "--json", "-")
    assert res.exit_code == 0, res.output
    warns = [line for line in res.stderr.splitlines() if line.startswith("warning:")]
    assert any("--radius" in w and "unit" in w for w in warns) and len(warns) == len(set(warns))


def test_tables_fit_an_80_column_terminal(tmp_path):
    res = invoke("solve", *CAPS, "--pressure", "1kPa:100kPa:3", terminal_width=80, env={"COLUMNS": "80"})
    assert res.exit_code == 0, res.output
    assert max(len(line) for line in res.stdout.splitlines()) <= 80, res.stdout


def test_flat_punch_converges(tmp_path):
    """A flat finite patch is a flat punch: full contact, load balance, edge pressures highest."""
    res = invoke("solve", "--texture", "flat", "--size", "100um", "--grid", "32", "--no-periodic",
                 "--modulus", "0.4MPa", "--pressure", "10kPa", "--json", "-", "--save", tmp_path / "f.nc")
    assert res.exit_code == 0, res.output
    r = json.loads(res.stdout)["results"][0]
    assert r["converged"] and r["contact_fraction"] == 1.0
    from fingerpad.netcdf import load_dataset

    p = load_dataset(tmp_path / "f.nc")["pressure"].values
    assert p.mean() == pytest.approx(1e4, rel=1e-6)
    assert p[0, 0] > p[16, 16] and np.allclose(p, p[::-1, :]) and np.allclose(p, p.T)
    # the punch's approach: between the circular punch's P/(2 a E*) for the inscribed and the
    # circumscribed discs (a rigid square punch lies between them)
    force = 1e4 * (100e-6) ** 2
    inscribed, circumscribed = force / (2 * 50e-6 * 0.4e6), force / (2 * 50e-6 * math.sqrt(2) * 0.4e6)
    assert circumscribed < r["approach"] < inscribed


def test_solve_periodize(tmp_path):
    np.save(tmp_path / "m.npy", np.random.default_rng(0).random((16, 12)))
    res = invoke("solve", "--surface", tmp_path / "m.npy", "--size", "160um,120um", "--height-unit", "um",
                 "--periodize", "--pressure", "1kPa", "--json", "-")
    assert res.exit_code == 0, res.output
    tex = json.loads(res.stdout)["inputs"]["texture"]
    assert tex["periodic"] and tex["grid"] == [32, 24]


def test_zones_beyond_the_largest_load_are_computed(tmp_path):
    res = invoke("predict", *CAPS, "--model", "bem", "--loads", "0.2N:0.5N:2", "--zones-at", "3N",
                 "--cache", tmp_path / "c", "--json", "-")
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    z = data["zones"]
    assert z["load"] == 3.0 and data["cell"]["pressure_range"][1] >= 1.5 * z["mean_pressure"] * 0.99


def test_state_loads_do_not_depend_on_the_loads_asked(tmp_path):
    common = [*CAPS, "--model", "bem", "--cache", tmp_path / "c", "--json", "-"]
    a = json.loads(invoke("predict", *common, "--loads", "0.1N:4N:5").stdout)
    b = json.loads(invoke("predict", *common, "--loads", "1N:1000N:6").stdout)
    fresh = json.loads(invoke("predict", *CAPS, "--model", "bem", "--cache", tmp_path / "d", "--json", "-",
                              "--loads", "0.1N:4N:5").stdout)
    for other in (b, fresh):
        assert other["critical_load"]["bem"] == a["critical_load"]["bem"]
        assert other["full_contact_load"]["bem"] == a["full_contact_load"]["bem"]


def test_fingers_and_textures_list_units():
    res = invoke("fingers")
    assert res.exit_code == 0 and "stiffening" in res.stdout and "kPa" in res.stdout
    res = invoke("textures", terminal_width=200)
    assert res.exit_code == 0 and "--orientation" in res.stdout and "deg" in res.stdout


def test_huge_simulation_is_refused_before_allocating(tmp_path):
    line = error_line(invoke("simulate-measurement", "--out", tmp_path / "sim", "--sampling-rate", "1e9"))
    assert "at most" in line and not (tmp_path / "sim").exists()


def test_terminated_command_leaves_no_staging(tmp_path):
    """SIGTERM (a killed job) unwinds like Ctrl-C: the hidden staging folder is removed."""
    import os
    import signal
    import subprocess
    import sys
    import time

    exe = Path(sys.executable).with_name("fingerpad")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-c", "from fingerpad.cli import main; main()"]
    proc = subprocess.Popen([*cmd, "simulate-measurement", "--out", str(tmp_path / "sim"), "--sampling-rate", "2e4",
                             "--participants", "3"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 60
    def staging() -> bool:  # the hidden folder being written (beside it, the lock .sim.lock)
        return any(p.name.startswith(".sim.") and p.name.endswith(".part") for p in tmp_path.iterdir())

    while time.monotonic() < deadline and not staging():
        time.sleep(0.1)
    assert staging(), "no staging folder appeared"
    os.kill(proc.pid, signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130 and err.decode().strip().splitlines()[-1] == "interrupted: nothing written"
    assert listing(tmp_path) == []
