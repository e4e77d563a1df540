"""Sweeps on Dask: a point equals predict, resume after kill -9, an external scheduler, the map's
trends, inverse design, and the contract for bad input."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import shutil
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from fingerpad.cli import app

runner = CliRunner()

STUDY = """
[texture]
name = "caps"
radius = "100um"
height = "20um"
spacing = "175um"

[material]
modulus = "0.5GPa"
poisson = 0.4

[model]
kind = "both"
grid = 16

[sweep]
loads = "0.1N:4N:6"
chunk = 2
[sweep.axes]
spacing = "{spacing}"
height = {height}
"""


def write_study(folder: Path, spacing: str = "130um:300um:3", height: str = '["6um", "12um", "20um"]',
                grid: int = 16) -> Path:
    path = folder / "study.toml"
    path.write_text(STUDY.format(spacing=spacing, height=height).replace("grid = 16", f"grid = {grid}"))
    return path


def fingerpad_cmd() -> list[str]:
    exe = Path(sys.executable).with_name("fingerpad")
    return [str(exe)] if exe.exists() else [sys.executable, "-c", "from fingerpad.cli import main; main()"]


def run_cli(*args: object, env: dict[str, str] | None = None, timeout: float = 240) -> subprocess.CompletedProcess:
    return subprocess.run([*fingerpad_cmd(), *map(str, args)], capture_output=True, text=True, timeout=timeout,
                          env={**os.environ, **(env or {})})


def load(store: Path):
    from fingerpad.design.store import open_sweep

    return open_sweep(store).load()


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sweep")
    study = write_study(folder)
    cache = folder / "cache"
    res = run_cli("sweep", study, "--out", folder / "r.zarr", "--workers", "2", env={"FINGERPAD_CACHE": str(cache)})
    assert res.returncode == 0, res.stderr
    return folder, study, cache, load(folder / "r.zarr")


def test_a_sweep_point_equals_predict(swept):
    folder, _, cache, ds = swept
    assert bool(ds["done"].all()) and bool(ds["valid"].all())
    point = ds.sel(spacing=ds.spacing.values[1], height=ds.height.values[1])
    res = runner.invoke(app, ["predict", "--texture", "caps", "--radius", "100um", "--height",
                              f"{ds.height.values[1]}", "--spacing", f"{ds.spacing.values[1]}",
                              "--material-modulus", "0.5GPa", "--material-poisson", "0.4", "--grid", "16",
                              "--loads", "0.1N:4N:6", "--cache", cache, "--json", "-"])
    assert res.exit_code == 0, res.output
    pred = json.loads(res.stdout)
    assert float(point.critical_load_bem) == pytest.approx(pred["critical_load"]["bem"], rel=1e-9)
    assert float(point.critical_load_hertz) == pytest.approx(pred["critical_load"]["hertz"], rel=1e-9)
    np.testing.assert_allclose(point.mu_rel.values, [r["mu_normalised"] for r in pred["results"]], rtol=1e-9)
    np.testing.assert_allclose(point.area_ratio.values, [r["area_ratio"] for r in pred["results"]], rtol=1e-9)
    assert float(point.transition_pressure) == pytest.approx(pred["cell"]["transition_pressure"], rel=1e-9)


def test_impossible_points_are_stored_with_their_reason(tmp_path):
    """Overlapping caps cannot exist: stored invalid with the reason, the sweep goes on."""
    from fingerpad.design.evaluate import evaluate_point
    from fingerpad.design.spec import read_sweep_file, sweep_from_dict

    spec = sweep_from_dict(read_sweep_file(str(write_study(tmp_path, spacing="120um", height='["30um"]'))))
    data = spec.study_data(spec.assignment((0, 0)))
    res = evaluate_point(data, spec.loads, [1e3, 1e4])
    assert not res["valid"] and "overlap" in res["reason"] and np.all(np.isnan(res["mu"]))


def test_a_bad_setting_is_not_stored_as_an_impossible_point(tmp_path, monkeypatch):
    """A worker whose FFT setting is bad (an external scheduler's workers have their own
    environment) raises for the chunk, to be retried, instead of storing the point as invalid."""
    from fingerpad.design.evaluate import evaluate_point
    from fingerpad.design.spec import read_sweep_file, sweep_from_dict
    from fingerpad.errors import SetupError

    spec = sweep_from_dict(read_sweep_file(str(write_study(tmp_path))))
    data = spec.study_data(spec.assignment((0, 0)))
    monkeypatch.setenv("FINGERPAD_FFT", "fftw")
    monkeypatch.setenv("FINGERPAD_CACHE", str(tmp_path / "cache"))  # no cached cell to bypass the solver
    with pytest.raises(SetupError, match="unknown FFT engine 'fftw'"):
        evaluate_point(data, spec.loads, [1e3, 1e4])


def test_the_maps_trends(swept):
    """Critical load rises with height and falls with spacing (fixed radius)."""
    _, _, _, ds = swept
    crit = ds["critical_load_bem"].transpose("spacing", "height").values
    assert np.all(np.diff(crit, axis=1) > 0) and np.all(np.diff(crit, axis=0) < 0)
    from fingerpad.design.designmap import map_data

    data = map_data(ds, "spacing", "height", at=1.0)
    assert set(np.unique(data["region"].values[np.isfinite(data["region"].values)])) <= {0, 1, 2}
    assert float(data.mu_rel.max()) <= 1.05
    # what the figure draws travels with the data (plotting imports nothing of design/)
    # the literature's lines and the spacing felt at 250 Hz at 50 mm/s (docs/perception.md)
    assert [m[1] for m in json.loads(data.attrs["markers"])["lines"]] == [160e-6, 33.5e-6, 105e-6,
                                                                          pytest.approx(200e-6)]
    assert data["region"].attrs["flag_meanings"].split("; ")[1] == "transition inside the range"


def test_design_map_files(swept, tmp_path):
    folder, _, _, _ = swept
    res = runner.invoke(app, ["design-map", str(folder / "r.zarr"), "--x", "spacing", "--y", "height", "--at", "1N",
                              "--out", str(tmp_path / "map")])
    assert res.exit_code == 0, res.output
    names = sorted(p.name for p in (tmp_path / "map").iterdir())
    assert names == [".fingerpad-output.json", "design_map.csv", "design_map.nc", "design_map.png", "design_map.svg"]


def test_resume_after_kill(tmp_path):
    """kill -9 in the middle: finished points unchanged and not recomputed, the rest done."""
    # grid 48: long enough (several seconds) to be caught half-way on a fast machine too; since
    # issue 23's sweep speed-ups the grid-16 sweep finished in under 2 s, before the first poll
    study = write_study(tmp_path, spacing="120um:360um:6", grid=48)
    store = tmp_path / "r.zarr"
    env = {**os.environ, "FINGERPAD_CACHE": str(tmp_path / "cache")}
    proc = subprocess.Popen([*fingerpad_cmd(), "sweep", str(study), "--out", str(store), "--workers", "1"],
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, start_new_session=True)
    deadline = time.monotonic() + 180
    done = None
    while time.monotonic() < deadline:
        time.sleep(0.1)
        if store.exists():
            import zarr

            try:
                done = np.asarray(zarr.open_group(str(store), mode="r")["done"][...])
            except Exception:  # noqa: BLE001 - store being created
                continue
            if 2 <= done.sum() < done.size - 4:
                break
        if proc.poll() is not None:
            break
    os.killpg(proc.pid, signal.SIGKILL)  # the sweep and its cluster
    proc.wait(timeout=30)
    assert done is not None and 2 <= done.sum() < done.size, "the sweep finished before it could be killed"
    before = load(store)
    finished = before["done"].values
    res = run_cli("sweep", study, "--out", store, "--workers", "1", env={"FINGERPAD_CACHE": str(tmp_path / "cache")})
    assert res.returncode == 0, res.stderr
    assert f"{int(finished.sum())} done before" in res.stderr
    after = load(store)
    assert bool(after["done"].all())
    np.testing.assert_array_equal(after["critical_load_bem"].values[finished],
                                  before["critical_load_bem"].values[finished])
    np.testing.assert_array_equal(after["seconds"].values[finished], before["seconds"].values[finished])


def test_ctrl_c_is_one_line_without_worker_tracebacks(tmp_path):
    """Issue 30, item 7: Ctrl-C (SIGINT to the whole process group, as a terminal sends it)
    printed ~40 lines of worker KeyboardInterrupt tracebacks before `interrupted`."""
    # 60 points: a fast machine does not finish them in the second before the signal
    study = write_study(tmp_path, spacing="120um:360um:20", grid=48)
    store = tmp_path / "r.zarr"
    env = {**os.environ, "FINGERPAD_CACHE": str(tmp_path / "cache")}
    proc = subprocess.Popen([*fingerpad_cmd(), "sweep", str(study), "--out", str(store), "--workers", "2"],
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            start_new_session=True,
                            # SIGINT as a terminal delivers it, even when the suite runs in the
                            # background of a shell without job control (SIGINT ignored there,
                            # and inherited: the sweep ran to its end, exit code 0)
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 240
    while time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.1)
        if store.exists():  # the cluster is up and the tasks run
            time.sleep(1.0)
            break
    assert proc.poll() is None, proc.stderr.read()
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    tail = [ln for ln in lines if ln.startswith("interrupted:")]
    assert len(tail) == 1 and lines[-1] == tail[0], err
    assert tail[0].endswith(f"points kept in {store} (rerun the same command to finish)"), tail


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _lines_of(stream, found: list[str]) -> threading.Thread:
    """Collect the lines of ``stream`` in ``found`` (a thread, so that reading never blocks the test)."""
    def read() -> None:
        for line in stream:
            found.append(line)

    thread = threading.Thread(target=read, daemon=True)
    thread.start()
    return thread


def _stop(*procs: subprocess.Popen) -> None:
    for p in procs:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGTERM)
    for p in procs:
        try:
            p.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait(timeout=10)


def test_sweep_on_an_external_scheduler_waits_visibly_for_a_worker(tmp_path):
    """A scheduler with no worker: the sweep says so within seconds and keeps waiting; a worker
    started afterwards runs it to the end."""
    port = _free_port()
    bindir = Path(sys.executable).parent
    dask = str(bindir / "dask") if (bindir / "dask").exists() else "dask"
    env = {**os.environ, "FINGERPAD_CACHE": str(tmp_path / "cache")}
    sched = subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
                             env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    procs = [sched]
    try:
        study = write_study(tmp_path, spacing="150um:250um:2", height='["10um"]')
        for _ in range(100):  # the scheduler listens within seconds
            with socket.socket() as s:
                if s.connect_ex(("127.0.0.1", port)) == 0:
                    break
            time.sleep(0.2)
        sweep = subprocess.Popen([*fingerpad_cmd(), "sweep", str(study), "--out", str(tmp_path / "r.zarr"),
                                  "--scheduler", f"tcp://127.0.0.1:{port}"], env=env, stdout=subprocess.DEVNULL,
                                 stderr=subprocess.PIPE, text=True, start_new_session=True)
        procs.insert(0, sweep)
        lines: list[str] = []
        _lines_of(sweep.stderr, lines)
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and not any("no Dask worker has joined" in x for x in lines):
            assert sweep.poll() is None, "".join(lines)
            time.sleep(0.2)
        assert any("no Dask worker has joined" in x and "dask worker" in x for x in lines), "".join(lines)
        assert not (tmp_path / "r.zarr").exists() or not bool(load(tmp_path / "r.zarr")["done"].any())
        worker = subprocess.Popen([dask, "worker", f"tcp://127.0.0.1:{port}", "--nthreads", "1", "--nworkers", "1",
                                   "--no-dashboard", "--host", "127.0.0.1"], env=env, stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL, start_new_session=True)
        procs.insert(1, worker)
        assert sweep.wait(timeout=120) == 0, "".join(lines)
        assert bool(load(tmp_path / "r.zarr")["done"].all())
    finally:
        _stop(*procs)


def test_inverse_design_round_trip(swept):
    """The texture proposed for a target, predicted directly, meets the target."""
    folder, study, cache, ds = swept
    point = ds.isel(spacing=1, height=1)
    goal = float(point.mu_rel.sel(load=1.0, method="nearest"))
    load_1 = float(ds["load"].sel(load=1.0, method="nearest"))
    res = runner.invoke(app, ["design", str(study), "--vary", "spacing=130um:300um", "--vary", "height=6um:20um",
                              "--target", f"mu_rel={goal}@{load_1}N", "--from-sweep", str(folder / "r.zarr"),
                              "--candidates", "2", "--json", "-"], env={"FINGERPAD_CACHE": str(cache)})
    assert res.exit_code == 0, res.output
    out = json.loads(res.stdout)
    assert out["met"]
    best = out["candidates"][0]
    # check the proposal once more through predict itself
    pred = runner.invoke(app, ["predict", "--texture", "caps", "--radius", "100um",
                               "--height", f"{best['params']['height']}", "--spacing", f"{best['params']['spacing']}",
                               "--material-modulus", "0.5GPa", "--material-poisson", "0.4", "--grid", "16",
                               "--loads", f"{load_1}N", "--cache", str(cache), "--json", "-"])
    got = json.loads(pred.stdout)["results"][0]["mu_normalised"]
    assert got == pytest.approx(goal, rel=0.05)
    # the design names the publications of the methods its predictions used, as predict does
    assert [r["key"] for r in out["references"]] == [r["key"] for r in json.loads(pred.stdout)["references"]]
    assert "polonsky1999" in [r["key"] for r in out["references"]]
    # the Python API gives the command's document (the command parses, calls it once, prints)
    from fingerpad.design.inverse_design import design_textures

    api = design_textures(study, {"spacing": ("130um", "300um"), "height": ("6um", "20um")},
                          [f"mu_rel={goal}@{load_1}N"], from_sweep=str(folder / "r.zarr"), candidates=2)
    assert json.loads(json.dumps(api.document())) == out


def test_inverse_design_says_when_nothing_meets(tmp_path):
    study = write_study(tmp_path)
    res = runner.invoke(app, ["design", str(study), "--vary", "spacing=150um:200um", "--target", "mu_rel=0.01@1N",
                              "--evaluations", "4", "--candidates", "1", "--json", str(tmp_path / "d.json")],
                        env={"FINGERPAD_CACHE": str(tmp_path / "cache")})
    assert res.exit_code == 0, res.output
    assert "no texture in the box meets the target" in res.stderr
    assert json.loads((tmp_path / "d.json").read_text())["met"] is False


# ------------------------------------------------------------------------------------------------
# bad input: one error line, exit 2, nothing written


def error_line(result) -> str:
    assert result.exit_code == 2, (result.exit_code, result.output)
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr
    return lines[0]


@pytest.mark.parametrize("spacing, height, expect", [
    ("120um:300um:3", '["8um"]', None),  # valid: the reference for the others
    ("120um:300um:3", '{ values = [] }', "empty"),
    ("300um:120um:3", '["8um"]', "below START"),
    ("120kPa:300kPa:3", '["8um"]', "expected a length"),
])
def test_bad_axes(tmp_path, spacing, height, expect):
    study = write_study(tmp_path, spacing=spacing, height=height)
    if expect is None:
        from fingerpad.design.spec import read_sweep_file, sweep_from_dict

        assert sweep_from_dict(read_sweep_file(str(study))).size == 3
        return
    assert expect in error_line(runner.invoke(app, ["sweep", str(study), "--out", str(tmp_path / "r.zarr")]))
    assert not (tmp_path / "r.zarr").exists()


def test_unknown_axis_and_target(tmp_path):
    study = tmp_path / "s.toml"
    study.write_text(STUDY.format(spacing="120um:300um:2", height='["8um"]').replace("height =", "colour ="))
    assert "not a parameter" in error_line(runner.invoke(app, ["sweep", str(study), "--out", str(tmp_path / "r")]))
    good = write_study(tmp_path)
    line = error_line(runner.invoke(app, ["design", str(good), "--vary", "spacing=120um:300um",
                                          "--target", "grip=0.5@1N"]))
    assert "no quantity 'grip'" in line


def test_store_of_another_sweep_is_refused(swept, tmp_path):
    folder, _, _, _ = swept
    other = write_study(tmp_path, spacing="100um:200um:2", height='["8um"]')
    line = error_line(runner.invoke(app, ["sweep", str(other), "--out", str(folder / "r.zarr")]))
    assert "another sweep" in line and "--overwrite" in line


def test_scheduler_that_does_not_answer(tmp_path):
    study = write_study(tmp_path)
    t0 = time.monotonic()
    line = error_line(runner.invoke(app, ["sweep", str(study), "--out", str(tmp_path / "r.zarr"), "--scheduler",
                                          f"tcp://127.0.0.1:{_free_port()}"]))
    assert "no Dask scheduler answers" in line and time.monotonic() - t0 < 30
    assert not (tmp_path / "r.zarr").exists()


def test_bad_fft_setting_stops_the_sweep_before_any_work(tmp_path, monkeypatch):
    """Every solve would fail, and a failing point is stored as one that cannot exist: the sweep
    must refuse at once, with the variable named, and write nothing."""
    study = write_study(tmp_path)
    monkeypatch.setenv("FINGERPAD_FFT", "fftw")
    line = error_line(runner.invoke(app, ["sweep", str(study), "--out", str(tmp_path / "r.zarr")]))
    assert "unknown FFT engine 'fftw' (FINGERPAD_FFT)" in line
    assert not (tmp_path / "r.zarr").exists()


def test_scheduler_that_accepts_and_never_answers(tmp_path):
    """A peer that takes the connection and says nothing: one error line within the bound (the
    Client alone waited until the peer closed, ~120 s)."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    held: list[socket.socket] = []
    stop = threading.Event()

    def accept() -> None:
        server.settimeout(0.2)
        while not stop.is_set():
            try:
                held.append(server.accept()[0])
            except OSError:
                continue

    thread = threading.Thread(target=accept, daemon=True)
    thread.start()
    try:
        study = write_study(tmp_path)
        t0 = time.monotonic()
        line = error_line(runner.invoke(app, ["sweep", str(study), "--out", str(tmp_path / "r.zarr"), "--scheduler",
                                              f"tcp://127.0.0.1:{server.getsockname()[1]}"]))
        assert "no Dask scheduler answers" in line and time.monotonic() - t0 < 20
        assert held, "the test's peer was never reached"
        assert not (tmp_path / "r.zarr").exists()
    finally:
        stop.set()
        thread.join(timeout=5)
        for c in held:
            c.close()
        server.close()


@pytest.mark.parametrize("address, expect", [("notaurl", "missing port"),
                                             ("foo://127.0.0.1:1", "unknown address scheme"),
                                             ("tcp://127.0.0.1:99999", "out of range")])
def test_bad_scheduler_address_is_one_line_and_no_late_traceback(tmp_path, address, expect):
    """The Dask Client used to print a Client.__del__ traceback 10 s after the error line: the
    process now ends at once with only that line."""
    study = write_study(tmp_path)
    t0 = time.monotonic()
    res = run_cli("sweep", study, "--out", tmp_path / "r.zarr", "--scheduler", address, timeout=60)
    lines = [x for x in res.stderr.splitlines() if x.strip()]
    assert res.returncode == 2 and len(lines) == 1 and lines[0].startswith("error: --scheduler"), res.stderr
    assert expect in lines[0] and time.monotonic() - t0 < 8
    assert not (tmp_path / "r.zarr").exists()


def test_sub_pixel_texture_is_invalid_not_valid(tmp_path):
    """Caps of 68 um on a 16-point cell of 100 mm: the feature is not in the height map, the cell
    is flat (A_re/A_fr ~ 1, error estimate ~ 0): the point is 'grid too small', not valid."""
    from fingerpad.design.evaluate import evaluate_point
    from fingerpad.design.spec import read_sweep_file, sweep_from_dict

    spec = sweep_from_dict(read_sweep_file(str(write_study(tmp_path, spacing="100mm", height='["6um"]'))))
    res = evaluate_point(spec.study_data(spec.assignment((0, 0))), spec.loads, [1e3, 1e4])
    assert not res["valid"] and res["reason"].startswith("grid too small") and "pixels" in res["reason"]
    assert np.all(np.isnan(res["area_ratio"]))
    # the same caps on a cell they fill are valid: the check is about resolution, not the family
    spec = sweep_from_dict(read_sweep_file(str(write_study(tmp_path, spacing="200um", height='["6um"]'))))
    assert evaluate_point(spec.study_data(spec.assignment((0, 0))), spec.loads, [1e3, 1e4])["valid"]


def test_signature_depends_on_the_study_content_not_its_path(tmp_path, monkeypatch):
    from fingerpad.design.spec import read_sweep_file, sweep_from_dict

    study = write_study(tmp_path)
    (tmp_path / "other").mkdir()
    copy = tmp_path / "other" / "copy.toml"
    copy.write_text(study.read_text())
    monkeypatch.chdir(tmp_path)
    sigs = {sweep_from_dict(read_sweep_file(p)).signature() for p in ("study.toml", str(study), "./other/../study.toml",
                                                                      str(copy))}
    assert len(sigs) == 1
    changed = tmp_path / "changed.toml"
    changed.write_text(study.read_text().replace('radius = "100um"', 'radius = "90um"'))
    assert sweep_from_dict(read_sweep_file(str(changed))).signature() not in sigs


def test_finished_sweep_named_by_another_path_resumes_without_a_cluster(swept, tmp_path, monkeypatch):
    """The same study by its absolute path, from another folder, or an identical copy: the store
    is recognised, and with every point done no cluster is started (9-16 s for nothing)."""
    import fingerpad.design.engine as engine

    folder, study, _, ds = swept
    store = tmp_path / "r.zarr"
    shutil.copytree(folder / "r.zarr", store)

    def no_cluster(*args, **kwargs):
        raise AssertionError("a cluster was started for a finished sweep")

    monkeypatch.setattr(engine, "connect", no_cluster)
    (tmp_path / "elsewhere").mkdir()
    copy = tmp_path / "elsewhere" / "same.toml"
    copy.write_text(study.read_text())
    monkeypatch.chdir(tmp_path / "elsewhere")
    for name in (str(study.resolve()), str(copy), "same.toml", os.path.relpath(study)):
        res = runner.invoke(app, ["sweep", name, "--out", str(store)])
        assert res.exit_code == 0, res.output
        assert f"all {ds.done.size} points" in res.stderr and "nothing to compute" in res.stderr
        assert "nan" not in res.stderr


def _damage(store: Path, kind: str) -> str:
    if kind == "done chunk":
        (store / "done" / "0.0").write_bytes(b"not a chunk")
        return "'done'"
    if kind == "data chunk":
        (store / "mu" / "1.0.0").write_bytes(os.urandom(64))
        return "'mu'"
    if kind == "attributes":
        (store / ".zattrs").write_text("{")
        return ".zattrs"
    if kind == "array metadata":
        (store / "spacing" / ".zarray").write_text("junk")
        return "'spacing'"
    if kind == "lost array":
        shutil.rmtree(store / "mu_rel")
        return "'mu_rel'"
    (store / ".zmetadata").unlink()
    return ".zmetadata"


@pytest.mark.parametrize("kind", ["done chunk", "data chunk", "zmetadata", "attributes", "array metadata",
                                  "lost array"])
def test_damaged_store_is_one_error_line(swept, tmp_path, kind):
    """design-map and the sweep name the store and the damage in one line, and say how to repair."""
    folder, study, _, _ = swept
    store = tmp_path / "r.zarr"
    shutil.copytree(folder / "r.zarr", store)
    what = _damage(store, kind)
    line = error_line(runner.invoke(app, ["design-map", str(store), "--x", "spacing", "--y", "height",
                                          "--out", str(tmp_path / "map")]))
    assert str(store) in line and what in line and "--repair" in line
    assert not (tmp_path / "map").exists()
    line = error_line(runner.invoke(app, ["sweep", str(study), "--out", str(store)]))
    assert str(store) in line and what in line and "--repair" in line


def test_repair_recomputes_the_damaged_points(swept, tmp_path):
    """Garbage in a done chunk and a data chunk, and the consolidated metadata lost: --repair
    recomputes the points of those chunks (from the cell cache: the same numbers) and rewrites
    the metadata; the store then reads as the original."""
    folder, study, cache, ds = swept
    store = tmp_path / "r.zarr"
    shutil.copytree(folder / "r.zarr", store)
    for kind in ("done chunk", "data chunk", "zmetadata"):
        _damage(store, kind)
    res = run_cli("sweep", study, "--out", store, "--workers", "1", "--repair", env={"FINGERPAD_CACHE": str(cache)})
    assert res.returncode == 0, res.stderr
    assert "repairing" in res.stderr and "4 points computed again" in res.stderr  # two chunks of 2 points
    after = load(store)
    assert bool(after["done"].all())
    for name in ("critical_load_bem", "mu", "mu_rel", "area_ratio", "psi"):
        np.testing.assert_allclose(after[name].values, ds[name].values, rtol=1e-12, equal_nan=True)


def test_a_study_without_sweep_points_to_docs_that_exist(tmp_path):
    study = tmp_path / "plain.toml"
    study.write_text(STUDY.split("[sweep]")[0])
    line = error_line(runner.invoke(app, ["sweep", str(study), "--out", str(tmp_path / "r.zarr")]))
    doc = line.split("see ")[1].rstrip(")")
    assert doc == "docs/sweeps.md" and (Path(__file__).resolve().parents[2] / doc).is_file()


def test_repair_of_metadata_alone_recomputes_nothing(swept, tmp_path, monkeypatch):
    """The store's attributes (recognised by their consolidated copy) and an axis's array
    metadata damaged: --repair rewrites them from the study, computes no point and starts no
    cluster."""
    import fingerpad.design.engine as engine

    folder, study, _, ds = swept
    store = tmp_path / "r.zarr"
    shutil.copytree(folder / "r.zarr", store)
    for kind in ("attributes", "array metadata"):
        _damage(store, kind)

    def no_cluster(*args, **kwargs):
        raise AssertionError("a cluster was started to repair metadata")

    monkeypatch.setattr(engine, "connect", no_cluster)
    res = runner.invoke(app, ["sweep", str(study), "--out", str(store), "--repair"])
    assert res.exit_code == 0, res.output
    assert "repaired: " in res.stderr and "nothing to compute" in res.stderr
    after = load(store)
    assert after.attrs["signature"] == ds.attrs["signature"]
    for name in ("spacing", "critical_load_bem", "mu_rel", "done"):
        np.testing.assert_array_equal(after[name].values, ds[name].values)


def test_waiting_for_a_worker_is_said_then_repeated():
    """Unit test of the wait (a fake client): a notice after the first wait, then one per
    reminder period, each with the time waited; none once a worker is there."""
    from dask.distributed import TimeoutError as DaskTimeout

    from fingerpad.cli.sweep import _Progress
    from fingerpad.design import engine

    class Client:
        def __init__(self, misses: int) -> None:
            self.misses = misses

        def scheduler_info(self) -> dict:
            return {"workers": {} if self.misses else {"w": {}}}

        def wait_for_workers(self, n: int, timeout: float) -> None:
            if self.misses:
                self.misses -= 1
                raise DaskTimeout(timeout)

    said: list[str] = []
    engine._wait_for_a_worker(Client(misses=3), "tcp://127.0.0.1:1", said.append)
    assert len(said) == 3 and all("no Dask worker has joined the scheduler at tcp://127.0.0.1:1" in x for x in said)
    waited = [engine.NO_WORKER_NOTICE + k * engine.NO_WORKER_REPEAT for k in range(3)]
    assert [f"after {w:.0f} s" in x for x, w in zip(said, waited, strict=True)] == [True] * 3
    said.clear()
    engine._wait_for_a_worker(Client(misses=0), "tcp://127.0.0.1:1", said.append)
    assert said == []
    # the command shows its headline once, then the notices
    import io

    from rich.console import Console

    out = io.StringIO()
    bar = _Progress(Console(file=out, width=200), 4, "sweep: 4 points")
    bar.notice("first")
    bar.notice("second")
    assert out.getvalue().splitlines() == ["sweep: 4 points", "first", "second"]


def test_a_failed_cell_fails_its_chunk_alone_and_the_rerun_computes_it(tmp_path, monkeypatch):
    """A chunk whose every point is its cell's first point is written from its cells' results
    (no task of its own): a cell that fails fails that chunk with the cell's error, as its task
    did, the other chunks are written, and the same command computes only that chunk again."""
    from fingerpad.design import evaluate
    from fingerpad.design.engine import run_sweep
    from fingerpad.design.spec import read_sweep_file, sweep_from_dict

    monkeypatch.setenv("FINGERPAD_CACHE", str(tmp_path / "cache"))
    spec = sweep_from_dict(read_sweep_file(str(write_study(tmp_path, spacing="130um:300um:2",
                                                           height='["6um", "12um"]'))))
    real, bad = evaluate.evaluate_point, spec.study_data(spec.assignment((1, 0)))

    def failing(data, *args, **kwargs):  # the workers are forked from this process: they run it
        if data == bad:
            raise RuntimeError("a worker lost its disk")
        return real(data, *args, **kwargs)

    monkeypatch.setattr(evaluate, "evaluate_point", failing)
    store = tmp_path / "r.zarr"
    first = run_sweep(spec, store, workers=1)
    assert first.failures == ["chunk [1:2, 0:2]: RuntimeError('a worker lost its disk')"]
    assert (first.computed, first.cells) == (2, 4)
    assert load(store)["done"].values.tolist() == [[True, True], [False, False]]
    monkeypatch.setattr(evaluate, "evaluate_point", real)
    again = run_sweep(spec, store, workers=1)
    assert (again.done_before, again.computed, again.failures) == (2, 2, [])
    assert bool(load(store)["done"].all())


def test_forked_workers_inherit_what_a_point_imports(tmp_path):
    """The modules a point imports on its first prediction are all in POINT_MODULES, which a sweep
    imports before it forks its local workers (else each worker imports them for its first point:
    ~0.2 s of CPU each, issue 23), and the compiled loops its cells run on are loaded there too
    (Numba's ~0.5-1 s, once instead of once per worker)."""
    code = """
import importlib, sys, warnings
from fingerpad.contact.greens import Backend
from fingerpad.contact.solver import preload_compiled_kernels
from fingerpad.design.evaluate import POINT_MODULES, evaluate_point
from fingerpad.design.spec import read_sweep_file, sweep_from_dict
Backend()  # as run_sweep does before it starts the cluster
for name in POINT_MODULES:  # as design.engine._worker_start does before it forks
    importlib.import_module(name)
preload_compiled_kernels()
spec = sweep_from_dict(read_sweep_file(sys.argv[1]))
before = set(sys.modules)
with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    assert evaluate_point(spec.study_data(spec.assignment((0, 0))), spec.loads, [1e3, 1e4])["valid"]
print(sorted(m for m in set(sys.modules) - before if m.split(".")[0] in ("scipy", "fingerpad", "numba")))
"""
    res = subprocess.run([sys.executable, "-c", code, str(write_study(tmp_path))], capture_output=True, text=True,
                         timeout=120, env={**os.environ, "FINGERPAD_CACHE": str(tmp_path / "cache")})
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == "[]"
