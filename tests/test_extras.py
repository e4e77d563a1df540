"""The optional parts: one message per missing extra, the same from the Python API and the
command line; pyproject.toml's extras and fingerpad.extras name the same packages; the solver
runs without Numba."""

from __future__ import annotations

import sys
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import fingerpad as fp
from fingerpad import extras
from fingerpad.cli import app
from fingerpad.errors import FingerpadError, SetupError

ROOT = Path(__file__).resolve().parents[1]


def hide(monkeypatch, *modules: str) -> None:
    """Make ``modules`` look uninstalled (an import of a None entry fails, find_spec finds none)."""
    for name in modules:
        monkeypatch.setitem(sys.modules, name, None)


def test_missing_extra_is_an_import_error_and_a_user_error(monkeypatch):
    hide(monkeypatch, "zarr")
    with pytest.raises(extras.MissingExtraError) as info:
        extras.require("sweep", modules=("zarr",))
    exc = info.value
    assert isinstance(exc, ImportError) and isinstance(exc, FingerpadError) and isinstance(exc, SetupError)
    assert exc.name == "zarr"
    assert str(exc) == ("sweeps and their stores (fingerpad sweep, design-map): the 'sweep' extra is not installed "
                        "(zarr missing): pip install 'fingerpad[sweep]'")


def test_load_names_the_extra_and_lets_other_errors_through(monkeypatch):
    hide(monkeypatch, "openpyxl")
    with pytest.raises(extras.MissingExtraError, match=r"x.xlsx: reading .*'measure' extra .*openpyxl missing"):
        extras.load("openpyxl", "x.xlsx: reading Excel files")
    assert extras.load("numpy") is np  # a core module
    hide(monkeypatch, "not_a_fingerpad_extra")
    with pytest.raises(ModuleNotFoundError):  # a module of no extra: not dressed up as one
        extras.load("not_a_fingerpad_extra")


def test_from_import_error_maps_a_deep_import_to_its_extra():
    err = extras.from_import_error(ModuleNotFoundError("No module named 'distributed.comm'", name="distributed.comm"))
    assert isinstance(err, extras.MissingExtraError) and "pip install 'fingerpad[sweep]'" in str(err)
    assert extras.from_import_error(ModuleNotFoundError("x", name="yaml")) is None


def test_pyproject_extras_install_what_the_helper_names():
    """Every module fingerpad.extras names for an extra comes with that extra in pyproject.toml
    (distribution names as pip knows them), and `all` is every user-facing extra."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    optional = project["optional-dependencies"]
    distribution = {"nptdms": "nptdms", "SurfaceTopography": "surfacetopography", "distributed": "dask"}
    for extra, (_, modules) in extras.EXTRAS.items():
        names = {req.split(">")[0].split("[")[0].split("=")[0].strip().lower() for req in optional[extra]}
        for module in modules:
            assert distribution.get(module, module).lower() in names, (extra, module)
    assert optional["all"] == [f"fingerpad[{','.join(extras.EXTRAS)}]"]
    core = " ".join(project["dependencies"]).lower()
    assert not any(m.lower() in core for _, modules in extras.EXTRAS.values() for m in modules)


def test_api_and_command_say_the_same(monkeypatch, tmp_path):
    """`fingerpad sweep` without Dask: one error line, exit 2, nothing written; the library's
    run_sweep raises the same message."""
    from fingerpad.design.engine import run_sweep

    hide(monkeypatch, "dask", "distributed")
    res = CliRunner().invoke(app, ["sweep", str(ROOT / "examples" / "sweep.toml"), "--out", str(tmp_path / "s.zarr")])
    assert res.exit_code == 2 and len(res.stderr.splitlines()) == 1, res.stderr
    with pytest.raises(extras.MissingExtraError) as info:
        run_sweep(None, tmp_path / "s.zarr")  # type: ignore[arg-type]  # refused before the spec is read
    assert res.stderr.strip() == f"error: {info.value}"
    assert list(tmp_path.iterdir()) == []


def test_a_deep_import_of_a_missing_extra_is_one_error_line(monkeypatch, capsys):
    """The command line's safety net: an extra's package imported somewhere the feature's own
    check did not foresee still ends in the extra's one line."""
    from fingerpad.cli import common

    def command() -> None:
        with common.user_errors():
            import zarr  # noqa: F401

    import typer

    hide(monkeypatch, "zarr")
    with pytest.raises(typer.Exit) as info:
        command()
    assert info.value.exit_code == 2
    err = capsys.readouterr().err
    assert err.splitlines() == ["error: sweeps and their stores (fingerpad sweep, design-map): the 'sweep' extra is "
                                "not installed (zarr missing): pip install 'fingerpad[sweep]'"]


def test_solver_runs_without_numba_silently(monkeypatch):
    """Without Numba, kernels='auto' stays on the NumPy loops even where it would turn to the
    compiled ones, with no warning and the NumPy kernels' answer; kernels='numba' asked for is
    refused with the extras message."""
    import fingerpad.contact.solver as solver_mod
    from fingerpad import HalfSpaceSolver
    from fingerpad.contact.kernels import NumpyKernels

    tex = fp.make_texture("caps", radius=50e-6, height=10e-6, spacing=100e-6, grid=64)
    pbar = 0.3 * 1e6 * tex.peak_to_valley / tex.size[0]
    reference = HalfSpaceSolver(tex, 1e6, kernels="numpy").solve_pressure(pbar)
    hide(monkeypatch, "numba")
    monkeypatch.setattr(solver_mod, "COMPILED_FIRST_POINTS", 1)  # would turn compiled at once
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        solver = HalfSpaceSolver(tex, 1e6)
        result = solver.solve_pressure(pbar)
    assert type(solver._kern) is NumpyKernels
    assert np.array_equal(result.pressure, reference.pressure)
    # a caller of many solves (a unit cell) asks for them wherever Numba is: here, none
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cell_solver = HalfSpaceSolver(tex, 1e6, kernels="compiled")
        assert cell_solver.arithmetic.endswith("/numpy")
        assert np.array_equal(cell_solver.solve_pressure(pbar).pressure, reference.pressure)
    assert type(cell_solver._kern) is NumpyKernels
    with pytest.raises(extras.MissingExtraError, match=r"kernels='numba': the 'fast' extra .*\(numba missing\)"):
        HalfSpaceSolver(tex, 1e6, kernels="numba")
