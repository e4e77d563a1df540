"""Sweeps on Dask: a point equals predict, resume after kill -9, an external scheduler, the map's
trends, inverse design, and the contract for bad input."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
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


def write_study(folder: Path, spacing: str = "130um:300um:3", height: str = '["6um", "12um", "20um"]') -> Path:
    path = folder / "study.toml"
    path.write_text(STUDY.format(spacing=spacing, height=height))
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


def test_design_map_files(swept, tmp_path):
    folder, _, _, _ = swept
    res = runner.invoke(app, ["design-map", str(folder / "r.zarr"), "--x", "spacing", "--y", "height", "--at", "1N",
                              "--out", str(tmp_path / "map")])
    assert res.exit_code == 0, res.output
    names = sorted(p.name for p in (tmp_path / "map").iterdir())
    assert names == [".fingerpad-output.json", "design_map.csv", "design_map.nc", "design_map.png", "design_map.svg"]


def test_resume_after_kill(tmp_path):
    """kill -9 in the middle: finished points unchanged and not recomputed, the rest done."""
    study = write_study(tmp_path, spacing="120um:360um:6")
    store = tmp_path / "r.zarr"
    env = {**os.environ, "FINGERPAD_CACHE": str(tmp_path / "cache")}
    proc = subprocess.Popen([*fingerpad_cmd(), "sweep", str(study), "--out", str(store), "--workers", "1"],
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, start_new_session=True)
    deadline = time.monotonic() + 180
    done = None
    while time.monotonic() < deadline:
        time.sleep(0.5)
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


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_sweep_on_an_external_scheduler(tmp_path):
    port = _free_port()
    bindir = Path(sys.executable).parent
    dask = str(bindir / "dask") if (bindir / "dask").exists() else "dask"
    env = {**os.environ, "FINGERPAD_CACHE": str(tmp_path / "cache")}
    sched = subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
                             env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    worker = subprocess.Popen([dask, "worker", f"tcp://127.0.0.1:{port}", "--nthreads", "1", "--nworkers", "1",
                               "--no-dashboard", "--host", "127.0.0.1"], env=env, stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        study = write_study(tmp_path, spacing="150um:250um:2", height='["10um"]')
        res = run_cli("sweep", study, "--out", tmp_path / "r.zarr", "--scheduler", f"tcp://127.0.0.1:{port}",
                      env={"FINGERPAD_CACHE": str(tmp_path / "cache")}, timeout=120)
        assert res.returncode == 0, res.stderr
        assert bool(load(tmp_path / "r.zarr")["done"].all())
    finally:
        for p in (worker, sched):
            os.killpg(p.pid, signal.SIGTERM)
        for p in (worker, sched):
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)


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
