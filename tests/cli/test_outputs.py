"""Outputs never cost a user a file: every command's output folder or file is checked before the
work, replaced only when fingerpad wrote it, written through a symbolic link, and a failed write
names the user's path (issue 20, "Files a user owns must never be lost", "Fail before the work")."""

from __future__ import annotations

import errno
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from fingerpad.cli import app

runner = CliRunner()
CAPS = ["--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "100um"]
HERTZ = [*CAPS, "--model", "hertz", "--loads", "1N"]
SWEEP = """
[texture]
name = "caps"
radius = "100um"
height = "20um"
spacing = "175um"
[model]
kind = "bem"
grid = 16
[sweep]
loads = "1N"
[sweep.axes]
spacing = ["150um", "200um"]
"""
ELLIPSOIDS = ["--texture", "ellipsoids", "--height", "50um", "--semi-axis-x", "50um", "--semi-axis-y", "25um",
              "--spacing-x", "200um", "--spacing-y", "200um", "--material-modulus", "0.3MPa", "--levels", "1",
              "--direction", "0", "--no-cache"]


def invoke(*args, **kw):
    return runner.invoke(app, [str(a) for a in args], **kw)


def error_line(result) -> str:
    assert result.exit_code == 2, (result.exit_code, result.output)
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr
    return lines[0]


def listing(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def no_work(monkeypatch, *targets: str) -> None:
    """Make the work of a command fail the test if it is ever reached."""
    import importlib

    def boom(*args, **kw):
        raise AssertionError("the work ran before the output was checked")

    for target in targets:
        module, name = target.rsplit(".", 1)
        monkeypatch.setattr(importlib.import_module(module), name, boom)


@pytest.fixture()
def sweep_file(tmp_path) -> Path:
    path = tmp_path / "sweep.toml"
    path.write_text(SWEEP)
    return path


@pytest.fixture()
def store(tmp_path, sweep_file) -> Path:
    """A laid-out sweep store (no point computed): what `design-map` reads."""
    from fingerpad.design.spec import read_sweep_file, sweep_from_dict
    from fingerpad.design.store import SweepStore, pressure_grid

    spec = sweep_from_dict(read_sweep_file(str(sweep_file)))
    path = tmp_path / "r.zarr"
    SweepStore(path, spec, pressure_grid(1e2, 1e5)).create()
    return path


# ------------------------------------------------------------------------------------------------
# what is at --out is replaced only if fingerpad wrote it


def test_sweep_overwrite_never_deletes_a_users_folder_or_the_study(tmp_path, sweep_file, monkeypatch):
    no_work(monkeypatch, "fingerpad.design.engine.run_sweep")
    notes = tmp_path / "f"
    notes.mkdir()
    (notes / "notes.txt").write_text("mine")
    for target in (notes, sweep_file):
        line = error_line(invoke("sweep", sweep_file, "--out", target, "--overwrite"))
        assert "not a fingerpad sweep store" in line and "left alone" in line
        assert "give --overwrite" not in line  # the error no longer suggests destroying it
    assert (notes / "notes.txt").read_text() == "mine"
    assert sweep_file.read_text() == SWEEP


def test_a_sweep_store_of_another_sweep_is_still_replaced_with_overwrite(tmp_path, store, sweep_file):
    from fingerpad.design.spec import read_sweep_file, sweep_from_dict
    from fingerpad.design.store import check_store_path

    other = tmp_path / "other.toml"
    other.write_text(SWEEP.replace('"150um", "200um"', '"160um", "200um"'))
    spec = sweep_from_dict(read_sweep_file(str(other)))
    with pytest.raises(ValueError, match="another sweep"):
        check_store_path(store, spec, overwrite=False)
    assert check_store_path(store, spec, overwrite=True) == "replace"
    assert check_store_path(store, sweep_from_dict(read_sweep_file(str(sweep_file)))) == "resume"


@pytest.mark.parametrize("command", ["simulate-measurement", "analyse", "predict", "run-default", "deflection"])
def test_a_folder_of_the_users_files_is_refused(command, tmp_path, monkeypatch):
    no_work(monkeypatch, "fingerpad.measure.simulate_study", "fingerpad.measure.load_study",
            "fingerpad.study.run.run_study", "fingerpad.micro.deflection.gain.directional_gain")
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    args = {"simulate-measurement": [], "analyse": [tmp_path, "--reference", "flat"], "predict": HERTZ,
            "run-default": [], "deflection": ELLIPSOIDS}[command]
    line = error_line(invoke(command, *args, "--out", out))
    assert "notes.txt" in line and (out / "notes.txt").read_text() == "mine"


def test_an_output_folder_is_replaced_but_not_once_a_user_added_a_file(tmp_path):
    out = tmp_path / "sim"
    for _ in range(2):  # its own output: replaced
        res = invoke("simulate-measurement", "--out", out, "--participants", "2", "--repetitions", "1")
        assert res.exit_code == 0, res.output
    manifest = json.loads((out / ".fingerpad-output.json").read_text())
    assert "truth.json" in manifest["files"]
    (out / "notes.txt").write_text("mine")
    line = error_line(invoke("simulate-measurement", "--out", out, "--participants", "2"))
    assert "notes.txt" in line and (out / "notes.txt").read_text() == "mine"
    # analyse never replaces the recordings it reads, even though fingerpad wrote them
    (out / "notes.txt").unlink()
    line = error_line(invoke("analyse", out, "--reference", "flat", "--out", out))
    assert "holds the input" in line and (out / "truth.json").exists()


@pytest.mark.parametrize("command", ["predict", "run-default", "simulate-measurement", "analyse", "deflection",
                                     "design-map", "sweep"])
@pytest.mark.parametrize("where", ["", "."])
def test_the_current_folder_is_never_an_output(command, where, tmp_path, monkeypatch, sweep_file, store):
    monkeypatch.chdir(tmp_path)
    no_work(monkeypatch, "fingerpad.measure.simulate_study", "fingerpad.measure.load_study",
            "fingerpad.study.run.run_study", "fingerpad.micro.deflection.gain.directional_gain",
            "fingerpad.design.engine.run_sweep", "fingerpad.design.designmap.map_data")
    before = listing(tmp_path)
    args = {"simulate-measurement": [], "analyse": [store, "--reference", "flat"], "predict": HERTZ,
            "run-default": [], "deflection": ELLIPSOIDS, "sweep": [sweep_file],
            "design-map": [store, "--x", "spacing", "--y", "spacing"]}[command]
    line = error_line(invoke(command, *args, "--out", where))
    assert ("empty" in line or "current folder" in line), line
    assert listing(tmp_path) == before


def test_a_symlinked_out_is_written_through(tmp_path):
    real, link = tmp_path / "real", tmp_path / "link"
    real.mkdir()
    link.symlink_to(real)
    for _ in range(2):  # created, then replaced
        res = invoke("predict", *HERTZ, "--out", link)
        assert res.exit_code == 0, res.output
        assert link.is_symlink() and (real / "predict.json").is_file()
        assert sorted(p.name for p in tmp_path.iterdir()) == ["link", "real"]  # no .old, no .part
    json_link, json_real = tmp_path / "p.json", tmp_path / "target.json"
    json_real.write_text("{}")
    json_link.symlink_to(json_real)
    res = invoke("predict", *HERTZ, "--json", json_link, "--out", link)
    assert res.exit_code == 0, res.output
    assert json_link.is_symlink() and "critical_load" in json.loads(json_real.read_text())


def test_a_file_that_is_not_a_regular_file_is_never_replaced(tmp_path):
    fifo = tmp_path / "pipe.json"
    os.mkfifo(fifo)
    line = error_line(invoke("solve", *CAPS, "--grid", "32", "--pressure", "1kPa", "--json", fifo))
    assert "not a regular file" in line and fifo.exists()


# ------------------------------------------------------------------------------------------------
# checked before the work, in the user's words


def _unwritable(tmp_path: Path) -> str:
    if Path("/proc").is_dir():
        return "/proc/nope"  # the case: permission bits say nothing there for root
    blocker = tmp_path / "file"
    blocker.write_text("x")
    return str(blocker / "nope")


@pytest.mark.parametrize("command, args, work", [
    ("predict", HERTZ, "fingerpad.study.run.run_study"),
    ("run-default", [], "fingerpad.study.run.run_study"),
    ("simulate-measurement", [], "fingerpad.measure.simulate_study"),
    ("analyse", ["{tmp}", "--reference", "flat"], "fingerpad.measure.load_study"),
    ("deflection", ELLIPSOIDS, "fingerpad.micro.deflection.gain.directional_gain"),
    ("sweep", ["{sweep}"], "fingerpad.design.engine.run_sweep"),
    ("design-map", ["{store}", "--x", "spacing", "--y", "spacing"], "fingerpad.design.store.open_sweep"),
])
def test_an_unwritable_out_fails_before_the_work(command, args, work, tmp_path, monkeypatch, sweep_file, store):
    no_work(monkeypatch, work)
    args = [str(a).format(tmp=tmp_path, sweep=sweep_file, store=store) for a in args]
    where = _unwritable(tmp_path)
    line = error_line(invoke(command, *args, "--out", where))
    assert repr(where) in line and ".part" not in line


@pytest.mark.parametrize("option, name", [("--json", "r.json"), ("--save", "r.nc"), ("--plot", "r.png"),
                                          ("--csv", "r.csv")])
def test_solve_checks_its_files_before_solving(option, name, tmp_path, monkeypatch):
    no_work(monkeypatch, "fingerpad.study.cell_job.run_solve")
    where = os.path.join(os.path.dirname(_unwritable(tmp_path)), name)
    line = error_line(invoke("solve", *CAPS, "--grid", "32", "--pressure", "1kPa", option, where))
    assert repr(where) in line and ".part" not in line


def _full_disk(*args, **kw):
    target = args[-1] if args else kw.get("path")
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(target))


def test_a_full_disk_names_the_users_file_and_leaves_nothing(tmp_path, monkeypatch):
    import fingerpad.netcdf

    monkeypatch.setattr(fingerpad.netcdf, "save_result", lambda result, path, attrs=None: _full_disk(path))
    json_path, nc_path = tmp_path / "r.json", tmp_path / "r.nc"
    line = error_line(invoke("solve", *CAPS, "--grid", "32", "--pressure", "1kPa", "--json", json_path,
                             "--save", nc_path))
    assert line == f"error: cannot write {str(nc_path)!r}: No space left on device"
    assert listing(tmp_path) == []  # the JSON staged before it is gone too


def test_a_full_disk_in_an_output_folder_names_the_users_path(tmp_path, monkeypatch):
    import fingerpad.netcdf

    out = tmp_path / "out"
    first = invoke("predict", *HERTZ, "--out", out)
    assert first.exit_code == 0, first.output
    before = {p: p.read_bytes() for p in out.iterdir()}
    monkeypatch.setattr(fingerpad.netcdf, "to_netcdf", lambda ds, path, **kw: _full_disk(path))
    line = error_line(invoke("predict", *HERTZ, "--loads", "2N", "--out", out))
    assert line == f"error: cannot write {str(out / 'predict.nc')!r}: No space left on device"
    assert {p: p.read_bytes() for p in out.iterdir()} == before  # the earlier outputs untouched
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_a_full_disk_in_a_measurement_folder_names_the_users_path(tmp_path, monkeypatch):
    import fingerpad.measure.simulate as simulate

    real = simulate._write_csv

    def write_csv(path, *args, **kw):
        if Path(path).name == "samples.csv":
            _full_disk(path)
        return real(path, *args, **kw)

    monkeypatch.setattr(simulate, "_write_csv", write_csv)
    out = tmp_path / "sim"
    line = error_line(invoke("simulate-measurement", "--out", out, "--participants", "2", "--repetitions", "1"))
    assert line == f"error: cannot write {str(out / 'samples.csv')!r}: No space left on device"
    assert listing(tmp_path) == []


# ------------------------------------------------------------------------------------------------
# Ctrl-C says what it left


def _fingerpad_with(patch: str, *args: str) -> subprocess.Popen:
    code = f"{patch}\nimport sys\nfrom fingerpad.cli import main\nsys.argv = ['fingerpad', *{list(args)!r}]\nmain()"
    # Ctrl-C as a terminal delivers it: a suite started in the background of a shell without
    # job control (nohup ... &) has SIGINT ignored, which every child would inherit
    return subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))


def test_ctrl_c_says_nothing_was_written(tmp_path):
    started = tmp_path / "started"
    patch = ("import time, pathlib, fingerpad.study.run as r\n"
             "def slow(*a, **k):\n"
             f"    pathlib.Path({str(started)!r}).touch()\n"
             "    time.sleep(600)\n"
             "r.run_study = slow")
    proc = _fingerpad_with(patch, "predict", *HERTZ, "--out", str(tmp_path / "out"))
    # the signal once the job runs (a loaded machine took more than a minute to get there)
    deadline = time.monotonic() + 240
    while not started.exists() and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.05)
    assert started.exists(), proc.poll()
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130
    assert err.strip().splitlines()[-1] == "interrupted: nothing written"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["started"]


def test_ctrl_c_in_a_sweep_says_how_many_points_the_store_kept(tmp_path, store, sweep_file, monkeypatch):
    import zarr

    from fingerpad.design.store import points_done

    group = zarr.open_group(str(store), mode="r+")
    done = group["done"][...]
    done.flat[0] = True
    group["done"][...] = done
    assert points_done(store) == 1

    def interrupted(*args, **kw):
        raise KeyboardInterrupt

    monkeypatch.setattr("fingerpad.design.engine.run_sweep", interrupted)
    res = invoke("sweep", sweep_file, "--out", store)
    assert res.exit_code == 130
    assert res.stderr.strip().splitlines()[-1] == (
        f"interrupted: 1 of 2 points kept in {store} (rerun the same command to finish)")


@pytest.mark.parametrize("where", ["/", "..", "loop"])
def test_a_folder_above_here_or_a_link_loop_is_refused(where, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    no_work(monkeypatch, "fingerpad.study.run.run_study")
    (tmp_path / "loop").symlink_to("loop")
    line = error_line(invoke("predict", *HERTZ, "--out", where))
    assert "contains it" in line or "leads nowhere" in line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["loop"]


def test_finger_models_adds_its_figure_but_checks_the_folder_first(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert "empty" in error_line(invoke("finger-models", "--out", ""))
    where = _unwritable(tmp_path)
    assert repr(where) in error_line(invoke("finger-models", "--out", where))
    (tmp_path / "notes.txt").write_text("mine")
    res = invoke("finger-models", "--out", ".", "--loads", "0.5N:2N:3")
    assert res.exit_code == 0, res.output
    assert sorted(p.name for p in tmp_path.iterdir() if p.name != "file") == ["notes.txt", "ridge_models.png"]
