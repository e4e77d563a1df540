"""Command line (`fingerpad solve`, `textures`, `run-default`), NetCDF output and plots.

`fingerpad predict` itself is tested in test_study.py.

Grids are kept at 32 points so that the whole module runs in a few seconds.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from fingerpad import textures
from fingerpad.cli import app

runner = CliRunner()

HAS_GENERATORS = bool(getattr(textures, "GENERATORS", None))
needs_generators = pytest.mark.skipif(not HAS_GENERATORS, reason="texture generators not available yet")
needs_reader = pytest.mark.skipif(not hasattr(textures, "read_surface"), reason="read_surface not available yet")

# A small, well-resolved texture: hexagonal caps, 32 points per axis.
CAPS = ["--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "100um",
        "--lattice", "hexagonal", "--grid", "32"]

SUMMARY_KEYS = {"mean_pressure", "contact_fraction", "real_contact_area", "max_pressure", "mean_gap",
                "contact_state", "iterations", "converged", "seconds"}


def invoke(*args: str):
    return runner.invoke(app, [str(a) for a in args])


def files_in(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir())


def assert_user_error(result, directory: Path | None = None, before: list[str] | None = None) -> str:
    """Exit code 2, exactly one `error: ...` line on stderr, no traceback, no new file."""
    assert result.exit_code == 2, (result.exit_code, result.stdout, result.stderr, result.exception)
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("error: "), result.stderr
    assert "Traceback" not in result.output
    if directory is not None:
        assert files_in(directory) == (before or []), "a file was left behind"
    return lines[0]


# ------------------------------------------------------------------------------------------------
# solve: JSON, units, outputs


@needs_generators
def test_solve_json_schema(tmp_path):
    out = tmp_path / "r.json"
    res = invoke("solve", *CAPS, "--pressure", "1kPa", "--pressure", "50kPa", "--json", out)
    assert res.exit_code == 0, res.output
    data = json.loads(out.read_text())
    assert set(data) >= {"inputs", "results"}
    assert len(data["results"]) == 2
    for item in data["results"]:
        assert SUMMARY_KEYS <= set(item)
        assert item["converged"] is True
        assert item["contact_state"] in ("asperity", "transition", "full")
        assert 0 < item["contact_fraction"] <= 1
    r1, r2 = data["results"]
    assert r1["mean_pressure"] == pytest.approx(1e3, rel=1e-6)
    assert r2["mean_pressure"] == pytest.approx(5e4, rel=1e-6)
    assert r2["contact_fraction"] > r1["contact_fraction"]
    inputs = data["inputs"]
    assert inputs["texture"]["name"] == "caps"
    assert inputs["texture"]["grid"] == [32, 56]  # hexagonal cell: Ly = sqrt(3) Lx
    assert inputs["texture"]["periodic"] is True
    # default materials: skin 0.3 MPa, nu 0.49, rigid counter-surface -> E* = E / (1 - nu^2)
    assert inputs["materials"]["skin_modulus"] == 0.3e6
    assert inputs["modulus"] == pytest.approx(0.3e6 / (1 - 0.49**2))
    # whole-cell real area = psi * cell area
    lx, ly = inputs["texture"]["size"]
    assert r1["real_contact_area"] == pytest.approx(r1["contact_fraction"] * lx * ly)
    # a table went to stdout
    assert "mean p" in res.stdout


@needs_generators
def test_json_to_stdout_replaces_table():
    res = invoke("solve", *CAPS, "--pressure", "20kPa", "--json", "-")
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    assert len(data["results"]) == 1
    assert SUMMARY_KEYS <= set(data["results"][0])


@needs_generators
def test_unit_suffixes_equal_plain_si():
    a = invoke("solve", *CAPS, "--modulus", "0.4MPa", "--pressure", "20kPa", "--json", "-")
    plain = ["--texture", "caps", "--radius", "5e-5", "--height", "0.00001", "--spacing", "1e-4",
             "--lattice", "hexagonal", "--grid", "32"]
    b = invoke("solve", *plain, "--modulus", "400000", "--pressure", "20000", "--json", "-")
    assert a.exit_code == 0 and b.exit_code == 0, (a.output, b.output)
    ja, jb = json.loads(a.stdout), json.loads(b.stdout)
    assert ja["inputs"]["modulus"] == jb["inputs"]["modulus"] == 4e5
    assert ja["inputs"]["pressures"] == jb["inputs"]["pressures"] == [2e4]
    assert ja["inputs"]["texture"]["params"]["radius"] == jb["inputs"]["texture"]["params"]["radius"] == 5e-5  # bit for bit
    assert ja["results"][0]["contact_fraction"] == jb["results"][0]["contact_fraction"]


@needs_generators
def test_pressure_range_log(tmp_path):
    out = tmp_path / "r.json"
    res = invoke("solve", *CAPS, "--pressure", "1kPa:100kPa:3", "--log", "--json", out)
    assert res.exit_code == 0, res.output
    data = json.loads(out.read_text())
    assert data["inputs"]["pressures"] == pytest.approx([1e3, 1e4, 1e5])
    assert [r["mean_pressure"] for r in data["results"]] == pytest.approx([1e3, 1e4, 1e5], rel=1e-6)


@needs_generators
def test_skin_and_material_options(tmp_path):
    res = invoke("solve", *CAPS, "--skin-modulus", "0.5MPa", "--skin-poisson", "0.5",
                 "--material-modulus", "1MPa", "--material-poisson", "0.5", "--pressure", "10kPa", "--json", "-")
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    expected = 1.0 / (0.75 / 0.5e6 + 0.75 / 1e6)
    assert data["inputs"]["modulus"] == pytest.approx(expected)


@needs_generators
def test_netcdf_round_trip(tmp_path):
    from fingerpad.netcdf import load_dataset

    nc = tmp_path / "f.nc"
    js = tmp_path / "f.json"
    res = invoke("solve", *CAPS, "--pressure", "2kPa", "--pressure", "30kPa", "--save", nc, "--json", js)
    assert res.exit_code == 0, res.output
    ds = load_dataset(nc)
    for name, var in ds.variables.items():
        assert "units" in var.attrs, name
    assert ds["pressure"].attrs["units"] == "Pa"
    assert ds["gap"].attrs["units"] == "m"
    assert ds["x"].attrs["units"] == "m"
    assert ds["pressure"].dims == ("mean_pressure", "x", "y")
    assert ds["heights"].dims == ("x", "y")
    assert ds["pressure"].shape == (2, 32, 56)
    data = json.loads(js.read_text())
    np.testing.assert_allclose(ds["mean_pressure"].values, [r["mean_pressure"] for r in data["results"]])
    np.testing.assert_allclose(ds["contact_fraction"].values, [r["contact_fraction"] for r in data["results"]])
    np.testing.assert_allclose(ds["pressure"].mean(dim=("x", "y")).values, ds["mean_pressure"].values, rtol=1e-6)
    np.testing.assert_array_equal(ds["contact"].values, (ds["pressure"].values > 0).astype(np.int8))
    assert list(ds["contact_state"].values) == [r["contact_state"] for r in data["results"]]
    # inputs as global attributes
    assert ds.attrs["texture_name"] == "caps"
    assert ds.attrs["texture_radius"] == pytest.approx(5e-5)
    assert ds.attrs["modulus"] == pytest.approx(data["inputs"]["modulus"])
    assert ds.attrs["material_modulus"] == "none"  # rigid
    assert ds.attrs["texture_periodic"] == "true"
    # no temporary files left next to the outputs
    assert files_in(tmp_path) == ["f.json", "f.nc"]


@needs_generators
def test_long_solve_shows_iterations(monkeypatch):
    """Large grids show the solver's grid, iteration and residual while they run (on stderr, when
    it is a terminal: piped, the bar would be drawn once at its end)."""
    import sys

    from rich.console import Console

    import fingerpad.cli.solve as cli_solve

    shown: list[str] = []
    monkeypatch.setattr(cli_solve, "_ITERATION_PROGRESS_POINTS", 64 * 64)
    monkeypatch.setattr(cli_solve.ProgressBar, "detail", lambda self, text: shown.append(text))
    assert invoke("solve", *CAPS[:-1], "128", "--pressure", "15kPa", "--json", "-").exit_code == 0
    assert not shown  # stderr is not a terminal here
    monkeypatch.setattr(cli_solve, "stderr_console", lambda: Console(file=sys.stderr, force_terminal=True))
    result = invoke("solve", *CAPS[:-1], "128", "--pressure", "15kPa", "--json", "-")
    assert result.exit_code == 0, result.output
    assert shown and shown[-1].startswith("grid 128x224  iteration ")  # hexagonal cell: 1 x sqrt(3)
    assert any(s.startswith("grid 64x112") for s in shown)  # the coarse level of the nested start
    monkeypatch.setattr(cli_solve, "_ITERATION_PROGRESS_POINTS", 1024 * 1024)
    shown.clear()
    assert invoke("solve", *CAPS, "--pressure", "15kPa", "--json", "-").exit_code == 0
    assert not shown  # small grids: no per-iteration display


def test_single_pressure_netcdf_and_plot(tmp_path):
    from fingerpad.netcdf import load_dataset

    nc, png = tmp_path / "one.nc", tmp_path / "one.png"
    res = invoke("solve", *CAPS, "--pressure", "5kPa", "--save", nc, "--plot", png)
    assert res.exit_code == 0, res.output
    ds = load_dataset(nc)
    assert ds["pressure"].dims == ("x", "y")
    assert ds["mean_pressure"].attrs["units"] == "Pa"
    assert float(ds["mean_pressure"]) == pytest.approx(5e3, rel=1e-6)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert png.stat().st_size > 10_000


@needs_generators
def test_unconverged_exit_code_1(tmp_path):
    out = tmp_path / "r.json"
    res = invoke("solve", *CAPS, "--pressure", "30kPa", "--tol", "1e-14", "--max-iter", "1", "--json", out)
    assert res.exit_code == 1, res.output
    assert "warning" in res.stderr and "converge" in res.stderr
    data = json.loads(out.read_text())
    assert data["results"][0]["converged"] is False
    assert data["converged"] is False


@needs_generators
@needs_reader
def test_surface_from_npy(tmp_path):
    n, size = 32, 200e-6
    x = (np.arange(n) + 0.5) / n * size - size / 2
    X, Y = np.meshgrid(x, x, indexing="ij")
    h_um = np.maximum(np.sqrt(np.maximum(50.0**2 - (X * 1e6) ** 2 - (Y * 1e6) ** 2, 0.0)) - 40.0, 0.0)
    path = tmp_path / "cap.npy"
    np.save(path, h_um)
    res = invoke("solve", "--surface", path, "--size", "200um", "--height-unit", "um", "--pressure", "1kPa",
                 "--json", "-")
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    tex = data["inputs"]["texture"]
    assert tex["periodic"] is False  # files default to a finite patch
    assert tex["size"] == pytest.approx([2e-4, 2e-4])
    assert tex["source"] == "file"
    assert data["results"][0]["converged"] is True
    res = invoke("solve", "--surface", path, "--size", "200um,200um", "--height-unit", "um", "--periodic",
                 "--pressure", "1kPa", "--json", "-")
    assert res.exit_code == 0, res.output
    assert json.loads(res.stdout)["inputs"]["texture"]["periodic"] is True


# ------------------------------------------------------------------------------------------------
# user errors: exit code 2, one line on stderr, no output file


def _bad_npy(tmp_path: Path, kind: str) -> Path:
    if kind == "nan":
        h = np.zeros((32, 32))
        h[3, 4] = np.nan
        path = tmp_path / "nan.npy"
        np.save(path, h)
        return path
    if kind == "garbage":
        path = tmp_path / "garbage.npy"
        path.write_bytes(b"this is not a numpy file at all\x00\x01")
        return path
    if kind == "ok":
        path = tmp_path / "ok.npy"
        np.save(path, np.random.default_rng(0).random((32, 32)))
        return path
    raise AssertionError(kind)


BAD_OPTIONS = {
    "zero modulus": [*CAPS, "--modulus", "0", "--pressure", "1kPa"],
    "negative modulus": [*CAPS, "--modulus", "-0.3MPa", "--pressure", "1kPa"],
    "zero skin modulus": [*CAPS, "--skin-modulus", "0Pa", "--pressure", "1kPa"],
    "poisson too large": [*CAPS, "--skin-poisson", "0.7", "--pressure", "1kPa"],
    "material poisson -1": [*CAPS, "--material-modulus", "1GPa", "--material-poisson", "-1", "--pressure", "1kPa"],
    "unknown unit": [*CAPS[:2], "--radius", "50furlongs", *CAPS[4:], "--pressure", "1kPa"],
    "wrong dimension": [*CAPS, "--modulus", "50um", "--pressure", "1kPa"],
    "pressure with length unit": [*CAPS, "--pressure", "3mm"],
    "negative pressure": [*CAPS, "--pressure", "-5kPa"],
    "bad range": [*CAPS, "--pressure", "1kPa:2kPa"],
    "log range from zero": [*CAPS, "--pressure", "0:2kPa:4", "--log"],
    "no pressure": [*CAPS],
    "both modulus and skin": [*CAPS, "--modulus", "0.4MPa", "--skin-modulus", "0.3MPa", "--pressure", "1kPa"],
    "grid too small": [*CAPS[:-1], "2", "--pressure", "1kPa"],
    "grid not a number": [*CAPS[:-1], "many", "--pressure", "1kPa"],
    "overlapping asperities": ["--texture", "caps", "--radius", "300um", "--height", "200um", "--spacing", "100um",
                               "--grid", "32", "--pressure", "1kPa"],
    "unknown texture": ["--texture", "bumpz", "--pressure", "1kPa"],
    "unknown texture parameter": [*CAPS, "--colour", "red", "--pressure", "1kPa"],
    "texture parameter without value": [*CAPS, "--pressure", "1kPa", "--radius"],
    "no surface": ["--pressure", "1kPa"],
    "tol out of range": [*CAPS, "--pressure", "1kPa", "--tol", "2"],
    "max-iter zero": [*CAPS, "--pressure", "1kPa", "--max-iter", "0"],
}


@needs_generators
@pytest.mark.parametrize("case", sorted(BAD_OPTIONS))
def test_bad_options(tmp_path, case):
    outs = ["--json", tmp_path / "o.json", "--save", tmp_path / "o.nc", "--plot", tmp_path / "o.png"]
    res = invoke("solve", *BAD_OPTIONS[case], *outs)
    assert_user_error(res, tmp_path, [])


def test_bad_options_without_generators(tmp_path):
    """Errors caught before the texture is built (run even while generators are missing)."""
    for args in (
        ["--texture", "caps", "--modulus", "0", "--pressure", "1kPa"],
        ["--texture", "caps", "--skin-poisson", "0.51", "--pressure", "1kPa"],
        ["--texture", "caps", "--modulus", "1MPa", "--skin-modulus", "1MPa", "--pressure", "1kPa"],
        ["--texture", "caps", "--modulus", "1furlong", "--pressure", "1kPa"],
    ):
        res = invoke("solve", *args, "--json", tmp_path / "o.json")
        assert_user_error(res, tmp_path, [])


@needs_reader
@pytest.mark.parametrize(
    "case",
    ["nan", "garbage", "missing size", "missing height unit", "missing file", "directory", "bad height unit",
     "grid with file", "texture params with file", "both surface and texture", "bad size"],
)
def test_bad_surface_files(tmp_path, case):
    data = tmp_path / "data"
    data.mkdir()
    out = tmp_path / "out"
    out.mkdir()
    ok = _bad_npy(data, "ok")
    common = ["--pressure", "1kPa", "--json", out / "o.json", "--save", out / "o.nc", "--plot", out / "o.png"]
    args = {
        "nan": ["--surface", _bad_npy(data, "nan"), "--size", "100um", "--height-unit", "um"],
        "garbage": ["--surface", _bad_npy(data, "garbage"), "--size", "100um", "--height-unit", "um"],
        "missing size": ["--surface", ok, "--height-unit", "um"],
        "missing height unit": ["--surface", ok, "--size", "100um"],
        "missing file": ["--surface", data / "nope.npy", "--size", "100um", "--height-unit", "um"],
        "directory": ["--surface", data, "--size", "100um", "--height-unit", "um"],
        "bad height unit": ["--surface", ok, "--size", "100um", "--height-unit", "furlong"],
        "grid with file": ["--surface", ok, "--size", "100um", "--height-unit", "um", "--grid", "64"],
        "texture params with file": ["--surface", ok, "--size", "100um", "--height-unit", "um", "--radius", "5um"],
        "both surface and texture": ["--surface", ok, "--texture", "caps", "--size", "100um", "--height-unit", "um"],
        "bad size": ["--surface", ok, "--size", "100um,-3um", "--height-unit", "um"],
    }[case]
    res = invoke("solve", *args, *common)
    assert_user_error(res, out, [])


@needs_generators
def test_unwritable_output_is_an_error_before_solving(tmp_path):
    res = invoke("solve", *CAPS, "--pressure", "1kPa", "--json", tmp_path / "missing-dir" / "o.json")
    line = assert_user_error(res)
    assert "does not exist" in line


@needs_generators
def test_failed_output_leaves_no_file(tmp_path, monkeypatch):
    """An error while writing the last output removes the ones staged before it."""
    import fingerpad.plotting.solution
    from fingerpad.errors import FingerpadError

    def boom(results, path, **kw):
        Path(path).write_bytes(b"partial")
        raise FingerpadError("disk full")

    monkeypatch.setattr(fingerpad.plotting.solution, "plot_solution", boom)
    res = invoke("solve", *CAPS, "--pressure", "1kPa", "--json", tmp_path / "o.json", "--save", tmp_path / "o.nc",
                 "--plot", tmp_path / "o.png")
    assert "disk full" in assert_user_error(res)
    assert files_in(tmp_path) == []


# ------------------------------------------------------------------------------------------------
# other commands


@needs_generators
def test_textures_command_lists_generators():
    res = invoke("textures")
    assert res.exit_code == 0, res.output
    for name in textures.GENERATORS:
        assert name in res.stdout
    assert "--radius" in res.stdout


@needs_generators
def test_run_default_small(tmp_path):
    out = tmp_path / "out"
    res = invoke("run-default", "--out", out, "--grid", "32", "--loads", "0.5N:2N:3", "--cache", tmp_path / "cache")
    assert res.exit_code == 0, res.output
    assert files_in(out) == [".fingerpad-output.json", "areas.png", "friction.png", "predict.json", "predict.nc",
                             "ridge_models.png",
                             "zones.png"]
    data = json.loads((out / "predict.json").read_text())
    assert len(data["results"]) == 3
    assert data["inputs"]["model"] == "both" and data["critical_load"]["hertz"] > 0


def test_console_script_user_error(tmp_path):
    """The installed console script: one-line error, exit code 2, no traceback."""
    exe = Path(sys.executable).with_name("fingerpad")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-c", "from fingerpad.cli import main; main()"]
    out = tmp_path / "o.json"
    proc = subprocess.run(
        [*cmd, "solve", "--texture", "caps", "--modulus", "-1MPa", "--pressure", "1kPa", "--json", str(out)],
        capture_output=True, text=True, timeout=60, env={**os.environ, "COLUMNS": "100"},
    )
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.strip().count("\n") == 0 and proc.stderr.startswith("error: "), proc.stderr
    assert "modulus" in proc.stderr
    assert not out.exists()


def test_main_builds_only_the_command_asked_for_and_it_is_the_same_command():
    """``main`` runs a group holding the named command alone (issue 23: Typer reads every
    command's parameters on each start); that command must be the full group's, option for
    option, and every command of the full group must be reachable that way."""
    import typer.main

    from fingerpad.cli import _COMMAND_MODULE, app_for

    full = typer.main.get_command(app)
    assert sorted(_COMMAND_MODULE) == sorted(full.commands)
    for name, command in full.commands.items():
        alone = typer.main.get_command(app_for([name, "--help"]))
        assert name in alone.commands
        # the module may register a sibling (predict and run-default), never another module's command
        assert set(alone.commands) <= {n for n, m in _COMMAND_MODULE.items() if m is _COMMAND_MODULE[name]}
        mine = alone.commands[name]
        assert [p.opts for p in mine.params] == [p.opts for p in command.params]
        assert [p.default for p in mine.params] == [p.default for p in command.params]
        assert mine.help == command.help
    # anything else (a typo, --help, --version, nothing) gets the full group and its suggestions
    for args in (["solv"], ["--help"], ["--version"], []):
        assert app_for(args) is app


def test_console_script_typo_suggests_the_command():
    exe = Path(sys.executable).with_name("fingerpad")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-c", "from fingerpad.cli import main; main()"]
    proc = subprocess.run([*cmd, "solv", "--texture", "caps"], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2
    assert proc.stderr.startswith("error: No such command 'solv'. Did you mean 'solve'?"), proc.stderr


# ------------------------------------------------------------------------------------------------
# io helpers without the solver


def _fake_result(texture, p: float):
    from types import SimpleNamespace

    pressure = np.where(texture.heights > texture.heights.mean(), 2 * p, 0.0)
    return SimpleNamespace(
        pressure=pressure, gap=np.where(pressure > 0, 0.0, 1e-6), displacement=np.zeros(texture.shape),
        mean_pressure=p, approach=1e-6, contact_fraction=float((pressure > 0).mean()),
        real_contact_area=float((pressure > 0).mean()) * texture.area, max_pressure=2 * p, mean_gap=5e-7,
        iterations=3, residual=1e-9, converged=True, seconds=0.01, formulation="primal",
        contact_state="asperity", texture=texture, modulus=4e5, tol=1e-8,
    )


def test_io_attrs_and_atomic_write(tmp_path):
    from fingerpad.errors import FingerpadError
    from fingerpad.netcdf import load_dataset, save_result, save_results
    from fingerpad.textures import Texture

    h = np.outer(np.sin(np.linspace(0, 2 * math.pi, 16)), np.ones(8)) * 1e-6
    tex = Texture(h, (1e-4, 5e-5), name="custom", params={"wavelength": 1e-4, "flag": True, "none": None,
                                                          "axes": (1e-6, 2e-6)})
    path = tmp_path / "a.nc"
    save_result(_fake_result(tex, 1e3), path, attrs={"note": None, "ok": False, "nested": {"a": 1, "b": "x"},
                                                     "labels": ["a", "b"]})
    ds = load_dataset(path)
    assert ds.attrs["texture_flag"] == "true"
    assert ds.attrs["texture_none"] == "none"
    np.testing.assert_allclose(ds.attrs["texture_axes"], [1e-6, 2e-6])
    assert ds.attrs["note"] == "none" and ds.attrs["ok"] == "false"
    assert ds.attrs["nested_a"] == 1 and ds.attrs["nested_b"] == "x"
    assert json.loads(ds.attrs["labels"]) == ["a", "b"]
    assert ds["x"].shape == (16,) and ds["y"].shape == (8,)
    assert ds["x"].values[1] == pytest.approx(1e-4 / 16)
    assert all("units" in v.attrs for v in ds.variables.values())

    # stacking along mean_pressure
    save_results([_fake_result(tex, p) for p in (1e3, 2e3, 4e3)], tmp_path / "b.nc")
    ds = load_dataset(tmp_path / "b.nc")
    assert ds["pressure"].shape == (3, 16, 8)
    np.testing.assert_allclose(ds["mean_pressure"].values, [1e3, 2e3, 4e3])

    # an error during the write leaves neither the file nor a temporary
    bad = _fake_result(tex, 1e3)
    bad.pressure = object()
    with pytest.raises(Exception):
        save_result(bad, tmp_path / "c.nc")
    assert files_in(tmp_path) == ["a.nc", "b.nc"]
    with pytest.raises(FingerpadError):
        save_result(_fake_result(tex, 1e3), tmp_path / "nodir" / "c.nc")
    with pytest.raises(FingerpadError):
        load_dataset(tmp_path / "missing.nc")



@needs_generators
def test_plot_load_curve_equals_form_and_plot_at(tmp_path):
    png = tmp_path / "curve.png"
    res = invoke("solve", "--texture", "caps", "--radius=50um", "--height=10um", "--spacing=100um", "--grid=32",
                 "--pressure", "500Pa:200kPa:4", "--log", "--plot", png, "--plot-at", "1.2kPa", "--json", "-")
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    assert data["inputs"]["texture"]["params"]["radius"] == pytest.approx(5e-5)
    assert len(data["results"]) == 4
    assert png.read_bytes()[:4] == b"\x89PNG"
    assert files_in(tmp_path) == ["curve.png"]


def test_solve_critical_pressure_bracket(tmp_path):
    out = tmp_path / "crit.json"
    r = invoke("solve", "--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "150um",
               "--grid", "48", "--pressure", "5kPa", "--critical", "1e-3", "--json", out)
    assert r.exit_code == 0, r.output
    crit = json.loads(out.read_text())["critical_pressure"]
    assert crit["lower"] < crit["estimate"] < crit["upper"]
    assert crit["relative_width"] <= 1e-3
    from fingerpad.contact import HalfSpaceSolver

    tex = textures.spherical_caps(radius=50e-6, height=10e-6, spacing=150e-6, grid=48)
    solver = HalfSpaceSolver(tex, 0.3e6 / (1 - 0.49**2))
    assert solver.solve_pressure(crit["lower"]).contact_state == "asperity"
    assert solver.solve_pressure(crit["upper"]).contact_state == "transition"


def test_solve_critical_bad_width(tmp_path):
    r = invoke("solve", "--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "150um",
               "--grid", "32", "--pressure", "5kPa", "--critical", "2", "--json", tmp_path / "x.json")
    assert r.exit_code == 2 and "--critical" in r.output
    assert not (tmp_path / "x.json").exists()


@pytest.mark.parametrize("given", [None, "28"])
def test_main_lets_openblas_threads_sleep_unless_the_user_chose(monkeypatch, capsys, given):
    """`main` sets OPENBLAS_THREAD_TIMEOUT (before NumPy loads in a real start) only where the
    user did not."""
    import gc
    import signal

    from fingerpad import cli

    if given is None:
        monkeypatch.delenv("OPENBLAS_THREAD_TIMEOUT", raising=False)
    else:
        monkeypatch.setenv("OPENBLAS_THREAD_TIMEOUT", given)
    monkeypatch.setattr(sys, "argv", ["fingerpad", "--version"])
    sigterm = signal.getsignal(signal.SIGTERM)
    try:
        with pytest.raises(SystemExit) as exc:
            cli.main()
    finally:
        gc.unfreeze()  # main freezes the heap for the process's end; a test process goes on
        signal.signal(signal.SIGTERM, sigterm)
    assert exc.value.code == 0 and capsys.readouterr().out.startswith("fingerpad ")
    assert os.environ["OPENBLAS_THREAD_TIMEOUT"] == (given or "4")
