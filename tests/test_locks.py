"""One writer per output (fingerpad.locks): a second run is refused naming the first, the
left-overs of killed writers are removed by the next one, never those of a live one (issue 30,
items 2, 15 and 16); an output that cannot be replaced is refused before the work (item 18)."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from typer.testing import CliRunner

from fingerpad import io as fio
from fingerpad import locks
from fingerpad.cli import app
from fingerpad.errors import FingerpadError

runner = CliRunner()
CAPS = ["--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "100um", "--grid", "32"]
STUDY = """
[texture]
name = "caps"
radius = "100um"
height = "20um"
spacing = "175um"
[model]
grid = 16
[sweep]
loads = "0.1N:4N:4"
[sweep.axes]
spacing = "130um:300um:2"
"""


@pytest.fixture
def holder(tmp_path):
    """Another process holding the lock of an output until the test ends."""
    procs = []

    def hold(path: Path) -> subprocess.Popen:
        code = textwrap.dedent(f"""
            import sys, time
            sys.argv = ["fingerpad", "sweep"]
            from fingerpad import locks
            locks.hold({str(path)!r})
            print("held", flush=True)
            time.sleep(60)
        """)
        proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
        procs.append(proc)
        assert proc.stdout.readline().strip() == "held"
        return proc

    yield hold
    for proc in procs:
        proc.kill()
        proc.wait()
        proc.stdout.close()


def error_line(result) -> str:
    assert result.exit_code == 2, (result.exit_code, result.output)
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr
    return lines[0]


def test_a_second_writer_is_refused_naming_the_first(tmp_path, holder, monkeypatch):
    monkeypatch.chdir(tmp_path)
    proc = holder(tmp_path / "out")
    line = error_line(runner.invoke(app, ["predict", *CAPS, "--out", "out"]))
    assert line.startswith("error: --out 'out' is in use by another fingerpad run (fingerpad sweep, "
                           f"pid {proc.pid} on "), line
    assert "since 20" in line and line.endswith("wait for it to end, or name another --out")
    assert not (tmp_path / "out").exists()
    # the Python API too: writing the folder takes the lock
    with pytest.raises(locks.OutputBusy, match="in use by another fingerpad run"):
        fio.OutputFolder(tmp_path / "out")


def test_a_sweep_into_a_store_in_use_is_refused_before_any_cluster(tmp_path, holder, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text(STUDY)
    proc = holder(tmp_path / "r.zarr")
    line = error_line(runner.invoke(app, ["sweep", "s.toml", "--out", "r.zarr"]))
    assert f"--out 'r.zarr' is in use by another fingerpad run (fingerpad sweep, pid {proc.pid} on " in line
    # and the library's run_sweep holds it itself
    from fingerpad.design.engine import run_sweep
    from fingerpad.design.spec import read_sweep_file, sweep_from_dict

    with pytest.raises(locks.OutputBusy):
        run_sweep(sweep_from_dict(read_sweep_file("s.toml")), tmp_path / "r.zarr")


def test_the_lock_is_released_and_its_file_removed_on_every_way_out(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    ok = runner.invoke(app, ["predict", *CAPS, "--out", "out", "--loads", "1N"])
    assert ok.exit_code == 0, ok.output
    bad = runner.invoke(app, ["predict", *CAPS, "--out", "out2", "--loads", "1N", "--skin-modulus", "-1Pa"])
    assert bad.exit_code == 2
    assert not locks._HELD
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]  # no .out.lock, no hidden folder
    # the same process may take a lock it holds again (a command's check, then its writing)
    key = locks.hold(tmp_path / "x")
    assert locks.hold(tmp_path / "x") == key
    locks.release(key)
    assert (tmp_path / ".x.lock").exists()
    locks.release(key)
    assert not (tmp_path / ".x.lock").exists()


def _leftovers(folder: Path) -> list[Path]:
    """What kill -9 leaves of each writer: a hidden build folder, a swapped-out old folder, a
    staged file, an atomic write's temporary file, a sweep store being laid out."""
    made = [folder / ".out.1234abcd.part", folder / ".out.5678abcd.old", folder / ".r.zarr.creating",
            folder / ".r.zarr.done.repair"]
    for d in made:
        d.mkdir()
        (d / "big").write_bytes(b"0" * 1000)
    files = [folder / ".p.json.9abcdef0.part", folder / ".p.json.k2_x9zq1.tmp", folder / ".out.lock"]
    for f in files:
        f.write_text("x")
    return made + files


def test_later_runs_remove_what_killed_writers_left(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    left = _leftovers(tmp_path)
    keep = [tmp_path / ".outx.1234abcd.part", tmp_path / ".out.1234abcd.partial", tmp_path / "out.1234abcd.part"]
    for k in keep:
        k.mkdir()
    res = runner.invoke(app, ["predict", *CAPS, "--out", "out", "--json", "p.json", "--loads", "1N"])
    assert res.exit_code == 0, res.output
    assert not [p for p in left if p.name.startswith((".out", ".p.json")) and p.exists()]
    assert all(k.exists() for k in keep)  # other outputs' names, and names not ours, are left alone
    # the store's left-overs go with the next writer of the store
    key = locks.hold(tmp_path / "r.zarr")
    locks.release(key)
    assert not [p for p in left if p.exists()]


def test_a_live_writers_files_are_never_removed(tmp_path, holder, monkeypatch):
    monkeypatch.chdir(tmp_path)
    holder(tmp_path / "out")
    holder(tmp_path / "p.json")
    left = [p for p in _leftovers(tmp_path) if p.name != ".out.lock"]  # (the holder's own lock file)
    res = runner.invoke(app, ["predict", *CAPS, "--out", "out", "--loads", "1N"])
    assert res.exit_code == 2 and "in use" in res.stderr
    res = runner.invoke(app, ["solve", *CAPS, "--pressure", "1kPa", "--json", "p.json"])
    assert res.exit_code == 2 and "--json 'p.json' is in use" in res.stderr
    assert [p.name for p in left if p.name.startswith((".out", ".p.json")) and not p.exists()] == []


def test_repair_without_a_store_is_refused(tmp_path, monkeypatch):
    """Issue 30, item 15: it ran a whole new sweep."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text(STUDY)
    line = error_line(runner.invoke(app, ["sweep", "s.toml", "--out", "r.zarr", "--repair"]))
    assert line == ("error: --repair: there is no sweep store at 'r.zarr' to repair; run the sweep without --repair "
                    "to start it (or name the store to repair with --out)")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]
    from fingerpad.design.engine import run_sweep
    from fingerpad.design.spec import read_sweep_file, sweep_from_dict

    with pytest.raises(FingerpadError, match="no sweep store"):  # the library's door too
        run_sweep(sweep_from_dict(read_sweep_file("s.toml")), tmp_path / "r.zarr", repair=True)


def _immutable(path: Path) -> bool:
    """Make ``path`` immutable (chattr +i: root on a file system that has it)."""
    try:
        return subprocess.run(["chattr", "+i", str(path)], capture_output=True).returncode == 0
    except OSError:
        return False


@pytest.fixture
def immutable():
    made = []

    def make(path: Path) -> None:
        if not _immutable(path):
            pytest.skip("chattr +i is not available here (needs root and a file system with it)")
        made.append(path)

    yield make
    for path in made:
        subprocess.run(["chattr", "-i", str(path)], capture_output=True)


def test_an_immutable_output_is_refused_before_the_work(tmp_path, monkeypatch, immutable):
    monkeypatch.chdir(tmp_path)
    first = runner.invoke(app, ["predict", *CAPS, "--out", "out", "--loads", "1N"])
    assert first.exit_code == 0, first.output
    immutable(tmp_path / "out")
    solved = []
    import fingerpad.study.run as study_run

    monkeypatch.setattr(study_run, "run_study", lambda *a, **k: solved.append(1))  # the work must not start
    line = error_line(runner.invoke(app, ["predict", *CAPS, "--out", "out", "--loads", "1N"]))
    assert line == "error: cannot replace --out 'out': Operation not permitted"
    (tmp_path / "p.json").write_text("{}")
    immutable(tmp_path / "p.json")
    line = error_line(runner.invoke(app, ["solve", *CAPS, "--pressure", "1kPa", "--json", "p.json"]))
    assert line == "error: cannot replace --json 'p.json': Operation not permitted"
    with pytest.raises(FingerpadError, match="cannot replace"):
        fio.OutputFolder.check(tmp_path / "out")
    assert not solved


def test_an_immutable_sweep_store_is_refused_before_the_work(tmp_path, immutable):
    from fingerpad.design.spec import read_sweep_file, sweep_from_dict
    from fingerpad.design.store import check_store_path

    (tmp_path / "s.toml").write_text(STUDY)
    (tmp_path / "r.zarr").mkdir()  # an empty folder is replaced by the store
    immutable(tmp_path / "r.zarr")
    spec = sweep_from_dict(read_sweep_file(tmp_path / "s.toml"))
    with pytest.raises(FingerpadError, match=r"cannot write into --out '.*r.zarr': Operation not permitted"):
        check_store_path(tmp_path / "r.zarr", spec)
