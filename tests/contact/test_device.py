"""``--device`` / ``FINGERPAD_DEVICE``: the solver's array namespace chosen from the command line.

Everywhere: the names are checked, the CPU path gives NumPy's results, and a GPU library that is
missing or sees no CUDA device is refused with one ``error:`` line and exit code 2, nothing
written. Where CuPy or PyTorch sees a CUDA device (not in CI), the command's solve on it agrees
with the CPU's.
"""

from __future__ import annotations

import json
import os
import re
import sys
import types

import numpy as np
import pytest
from typer.testing import CliRunner

from fingerpad.cli import app
from fingerpad.contact.device import DEVICES, device_namespace, device_setting
from fingerpad.contact.greens import Backend
from fingerpad.errors import SetupError

SOLVE = ["solve", "--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "100um", "--grid", "32",
         "--modulus", "0.3MPa", "--pressure", "5kPa", "--pressure", "20kPa", "--json", "-"]


def invoke(*args: str):
    return CliRunner().invoke(app, [str(a) for a in args])


@pytest.fixture
def no_device_env(monkeypatch):
    monkeypatch.delenv("FINGERPAD_DEVICE", raising=False)


def test_device_setting_from_argument_environment_and_default(monkeypatch, no_device_env):
    assert device_setting() == ("cpu", "FINGERPAD_DEVICE")
    assert device_setting(" CuPy ") == ("cupy", "--device")
    monkeypatch.setenv("FINGERPAD_DEVICE", "Torch")
    assert device_setting() == ("torch", "FINGERPAD_DEVICE")
    assert device_setting("cpu") == ("cpu", "--device")  # the argument wins over the environment
    with pytest.raises(SetupError, match=r"unknown device 'gpu' \(--device\): choose one of cpu, cupy, torch"):
        device_setting("gpu")
    monkeypatch.setenv("FINGERPAD_DEVICE", "cuda")
    with pytest.raises(SetupError, match=r"'cuda' \(FINGERPAD_DEVICE\)"):
        device_setting()
    assert DEVICES == ("cpu", "cupy", "torch")


def test_cpu_is_numpy_and_a_backend_follows_the_environment(monkeypatch, no_device_env):
    assert device_namespace("cpu") is None
    assert Backend().is_numpy
    monkeypatch.setenv("FINGERPAD_DEVICE", "cpu")
    assert Backend().xp is np
    monkeypatch.setenv("FINGERPAD_DEVICE", "nowhere")
    with pytest.raises(SetupError, match="unknown device"):
        Backend()
    assert Backend(xp=np).xp is np  # an explicit namespace does not ask the environment


def _absent(monkeypatch, name: str) -> None:
    monkeypatch.setitem(sys.modules, name, None)  # `import name` raises ImportError


def _without_gpu(monkeypatch, name: str) -> None:
    """A stand-in of the library, installed but seeing no CUDA device."""
    fake = types.ModuleType(name)
    if name == "cupy":
        fake.cuda = types.SimpleNamespace(runtime=types.SimpleNamespace(getDeviceCount=lambda: 0))
    else:
        fake.cuda = types.SimpleNamespace(is_available=lambda: False)
    monkeypatch.setitem(sys.modules, name, fake)


@pytest.mark.parametrize("name", ["cupy", "torch"])
def test_a_missing_library_or_gpu_is_a_setup_error(monkeypatch, no_device_env, name):
    _absent(monkeypatch, name)
    with pytest.raises(SetupError, match=f"device '{name}' \\(--device\\) needs .* not installed"):
        device_namespace(name)
    _without_gpu(monkeypatch, name)
    monkeypatch.setenv("FINGERPAD_DEVICE", name)
    with pytest.raises(SetupError, match=f"device '{name}' \\(FINGERPAD_DEVICE\\): .* sees no CUDA device"):
        device_namespace()


@pytest.mark.parametrize("command", ["solve", "predict", "sweep"])
@pytest.mark.parametrize("name", ["cupy", "torch"])
def test_commands_refuse_an_absent_device_in_one_line(monkeypatch, tmp_path, no_device_env, command, name):
    _without_gpu(monkeypatch, name)
    out = tmp_path / "out"
    args = {"solve": [*SOLVE[:-2], "--json", out / "solve.json"],
            "predict": ["predict", "--grid", "16", "--out", out],
            "sweep": ["sweep", "examples/sweep.toml", "--out", out / "s.zarr"]}[command]
    res = invoke(*args, "--device", name)
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert lines == [f"error: device '{name}' (--device): {'CuPy' if name == 'cupy' else 'PyTorch'} sees no "
                     "CUDA device on this machine"], res.output
    assert not out.exists()  # nothing written
    assert "FINGERPAD_DEVICE" not in os.environ  # the command's setting does not outlive it


@pytest.mark.parametrize("door", ["design", "design-population", "explore", "predict", "sweep", "api-design"])
@pytest.mark.parametrize("name", ["cupy", "torch"])
def test_every_door_refuses_an_absent_device_of_the_environment(monkeypatch, tmp_path, no_device_env, door, name):
    """Issue 30, item 3: FINGERPAD_DEVICE=cupy fingerpad design exited 0 with NaN candidates and
    "no texture meets the target"; explore started and failed at its first BEM run. One check
    (contact.greens.check_setup), asked by every door."""
    _without_gpu(monkeypatch, name)
    monkeypatch.setenv("FINGERPAD_DEVICE", name)
    expected = f"device '{name}' (FINGERPAD_DEVICE): {'CuPy' if name == 'cupy' else 'PyTorch'} sees no CUDA device"
    design = ["design", "examples/study.toml", "--vary", "spacing=100um:400um", "--target", "mu_rel=0.5@1N",
              "--evaluations", "2"]
    if door == "api-design":
        from fingerpad.design.inverse_design import design_textures

        with pytest.raises(SetupError, match=re.escape(expected)):
            design_textures("examples/study.toml", ["spacing=100um:400um"], ["mu_rel=0.5@1N"], evaluations=2)
        return
    if door == "explore":
        pytest.importorskip("panel")
        from fingerpad.explore import server

        started = []
        monkeypatch.setattr(server, "server_populations", lambda *a: started.append(1) or {})
        res = invoke("explore", "--no-browser", "--port", "0")
        assert not started  # refused before anything is read or served
    else:
        args = {"design": design,
                "design-population": [*design, "--population", "adults", "--coverage", "0.5"],
                "predict": ["predict", "--grid", "16", "--out", tmp_path / "out"],
                "sweep": ["sweep", "examples/sweep.toml", "--out", tmp_path / "s.zarr"]}[door]
        res = invoke(*args)
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert lines == [f"error: {expected} on this machine"], res.output
    assert not any(tmp_path.iterdir())


def test_environment_variable_refused_like_the_option(monkeypatch, no_device_env):
    monkeypatch.setenv("FINGERPAD_DEVICE", "tpu")
    res = invoke(*SOLVE)
    assert res.exit_code == 2
    assert res.output.strip() == "error: unknown device 'tpu' (FINGERPAD_DEVICE): choose one of cpu, cupy, torch"


def test_cpu_device_gives_the_default_results(no_device_env):
    plain = invoke(*SOLVE)
    cpu = invoke(*SOLVE, "--device", "cpu")
    assert plain.exit_code == 0 and cpu.exit_code == 0, (plain.output, cpu.output)
    a, b = json.loads(plain.stdout)["results"], json.loads(cpu.stdout)["results"]
    for ra, rb in zip(a, b, strict=True):
        assert ra["contact_fraction"] == rb["contact_fraction"] and ra["iterations"] == rb["iterations"]
        assert ra["max_pressure"] == pytest.approx(rb["max_pressure"], rel=1e-12)


def _gpu(name: str) -> None:
    try:
        device_namespace(name)
    except SetupError as exc:
        pytest.skip(str(exc))


@pytest.mark.parametrize("name", ["cupy", "torch"])
def test_solve_on_a_gpu_agrees_with_the_cpu(no_device_env, name):
    _gpu(name)
    cpu = json.loads(invoke(*SOLVE).stdout)["results"]
    res = invoke(*SOLVE, "--device", name)
    assert res.exit_code == 0, res.output
    for rc, rg in zip(cpu, json.loads(res.stdout)["results"], strict=True):
        assert rg["contact_fraction"] == pytest.approx(rc["contact_fraction"], abs=2 / 32**2)
        assert rg["max_pressure"] == pytest.approx(rc["max_pressure"], rel=1e-6)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="workers are forked on Linux only")
def test_local_sweep_workers_are_forked_on_the_cpu_and_spawned_for_a_gpu(monkeypatch, no_device_env):
    import dask
    import distributed  # noqa: F401 - its configuration defaults

    from fingerpad.design.engine import _worker_start

    key = "distributed.worker.multiprocessing-method"
    with _worker_start():
        assert dask.config.get(key) == "fork"
    assert dask.config.get(key) == "spawn"  # only for the cluster's start
    monkeypatch.setenv("FINGERPAD_DEVICE", "cupy")  # its CUDA, initialised here, would not survive a fork
    with _worker_start():
        assert dask.config.get(key) == "spawn"
