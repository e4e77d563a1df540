"""Sweeps and the design map for a population of fingers (issue 22): the per-point bands are the
quantiles of the members, a population without spread is the nominal sweep, the 10/90 % contours
bracket the median's, and a store of another population is refused."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
from typer.testing import CliRunner

from fingerpad.cli import app
from fingerpad.design.evaluate import evaluate_point
from fingerpad.design.spec import sweep_from_dict
from fingerpad.population import load_population, run_population
from fingerpad.study.spec import study_from_dict

from .test_sweep import STUDY as SWEEP_STUDY

runner = CliRunner()

BASE = {
    "texture": {"name": "caps", "radius": "100um", "height": "20um", "spacing": "175um"},
    "material": {"modulus": "0.5GPa", "poisson": 0.4},
    "model": {"kind": "both", "grid": 16},
}
SWEEP = {"loads": "0.1N:4N:5", "chunk": 2, "axes": {"spacing": ["130um", "200um"], "height": ["8um", "20um"]}}
SPREAD = {"size": 24, "skin_modulus": {"distribution": "uniform", "low": "0.2MPa", "high": "0.5MPa"},
          "ridge_fraction": {"distribution": "uniform", "low": 0.1, "high": 0.7},
          "tau0": {"distribution": "uniform", "low": "4kPa", "high": "12kPa"}}
NO_SPREAD = {"size": 8, "skin_modulus": {"distribution": "normal", "mean": "0.3MPa", "sd": "0MPa"},
             "tau0": {"values": ["8.1kPa"]}}


@pytest.fixture(autouse=True)
def cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("FINGERPAD_CACHE", str(tmp_path_factory.getbasetemp() / "pop-sweep-cache"))


def spec_for(population=None, quantiles=None):
    return sweep_from_dict({**BASE, "sweep": SWEEP}, population=population, quantiles=quantiles)


def point(spec, index):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return evaluate_point(spec.study_data(spec.assignment(index)), spec.loads, [1e3, 1e4],
                              spec.population_payload())


@pytest.mark.parametrize("kind", ["both", "hertz"])
def test_no_spread_gives_the_nominal_values_exactly(kind):
    """Every member is the study's finger: every band is the nominal point's value, bit for bit,
    and every member is in the nominal's state."""
    spec = sweep_from_dict({**BASE, "model": {**BASE["model"], "kind": kind}, "sweep": SWEEP},
                           population=NO_SPREAD)
    for index in [(0, 0), (1, 1)]:
        res = point(spec, index)
        assert res["valid"]
        for q in range(len(spec.quantiles)):
            np.testing.assert_array_equal(res["band_area_ratio"][q], res["area_ratio"])
            np.testing.assert_array_equal(res["band_mu"][q], res["mu"])
            np.testing.assert_array_equal(res["band_mu_ref"][q], res["mu_ref"])
            np.testing.assert_array_equal(res["band_mu_rel"][q], res["mu_rel"])
            crit = res["critical_load_bem"] if kind == "both" else res["critical_load_hertz"]
            assert res["band_critical_load"][q] == crit
        full = res["full_contact_load"]
        assert np.array_equal(res["band_full_contact_load"], np.full(len(spec.quantiles), full), equal_nan=True)
        for code in range(3):
            np.testing.assert_array_equal(res["state_probability"][code], (res["contact_state"] == code) * 1.0)


@pytest.mark.parametrize("kind, curve_rtol", [("hertz", 0.0), ("both", 1e-12)])
def test_bands_are_the_quantiles_of_a_direct_population_prediction(kind, curve_rtol):
    """A point's stored bands equal the quantiles of run_population's members on that texture.

    One member path (fingerpad.population.members) for both, so the numbers agree bit for bit on the
    same cell; with BEM the sweep's cell holds the nodes of its own pressure range, whose
    interpolant may differ from the direct run's in the last digits (1e-12 allowed)."""
    spec = sweep_from_dict({**BASE, "model": {**BASE["model"], "kind": kind}, "sweep": SWEEP}, population=SPREAD)
    res = point(spec, (0, 1))
    data = spec.study_data(spec.assignment((0, 1)))
    data["loads"] = {"values": [float(f) for f in spec.loads]}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        direct = run_population(study_from_dict(data), load_population(SPREAD), spec.quantiles)
    levels = np.asarray(spec.quantiles)
    crit = direct.critical_load
    assert np.isfinite(crit).all()
    np.testing.assert_allclose(res["band_critical_load"], np.quantile(crit, levels), rtol=1e-11)
    if kind == "both":
        np.testing.assert_allclose(res["band_full_contact_load"], np.quantile(direct.full_contact_load, levels),
                                   rtol=1e-11)
    else:
        assert np.isnan(res["band_full_contact_load"]).all()
    # the mu_ref's need no integral: exact
    np.testing.assert_array_equal(res["band_mu_ref"], np.quantile(direct.values("mu_ref"), levels, axis=0))
    for band, name in (("band_area_ratio", "area_ratio"), ("band_mu", "mu"), ("band_mu_rel", "mu_normalised")):
        np.testing.assert_allclose(res[band], np.quantile(direct.values(name), levels, axis=0), rtol=curve_rtol)
    states = np.array(direct.states)
    for code, state in enumerate(("asperity", "transition", "full")):
        np.testing.assert_array_equal(res["state_probability"][code], np.mean(states == state, axis=0))
    assert res["asperity_over_range"] == np.mean(np.all(states == "asperity", axis=1))


def test_members_read_one_cell_exactly():
    """The members' A_re/A_fr is the exact integral of the interpolated psi (adaptive quadrature
    to 1e-13), at every member's own E*."""
    from scipy.integrate import quad

    from fingerpad.population.members import evaluate_members
    from fingerpad.population.members import member_finger
    from fingerpad.study.run import run_study

    data = {**BASE, "model": {"kind": "bem", "grid": 16}, "loads": {"values": [0.2, 1.0, 3.0]}}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        nominal = run_study(study_from_dict(data))
    members = load_population(SPREAD).sample()[:3]
    fingers = [member_finger(nominal.study.finger, m) for m in members]
    moduli = [f.micro_modulus(nominal.study.material_modulus, nominal.study.material_poisson) for f in fingers]
    values = evaluate_members(nominal, fingers)
    cell = nominal.cell
    nodes = list(cell.curve()["pressure"]) + [cell.transition_pressure, cell.full_contact_pressure]
    for i, (f, e) in enumerate(zip(fingers, moduli, strict=True)):
        scaled = cell.at_modulus(e)
        for j, load in enumerate(nominal.study.loads):
            peak = 1.5 * load / float(f.ridge_area(load))
            big_p = peak * cell.modulus / e  # the base cell's pressure
            cuts = sorted(p for p in nodes if 0 < p < big_p)
            val, _ = quad(lambda u: float(cell.contact_fraction(np.array([u]))[0]) * u, 0, big_p, points=cuts,
                          limit=2000, epsabs=0, epsrel=1e-13)
            assert values.area_ratio[i, j] == pytest.approx(2 * val / big_p**2, rel=1e-12)
            state = 2 if peak >= scaled.full_contact_pressure else 1 if peak >= scaled.transition_pressure else 0
            assert values.states[i, j] == state


def test_quantiles_keep_infinite_members():
    """Numpy gives NaN between two infinite values; a critical load never reached stays inf."""
    from fingerpad.population.members import member_quantiles

    v = np.array([1.0, 2.0, np.inf, np.inf])
    out = member_quantiles(v, [0.0, 0.5, 0.9, 1.0])
    np.testing.assert_array_equal(out, [1.0, np.inf, np.inf, np.inf])
    np.testing.assert_array_equal(member_quantiles(np.array([1.0, np.nan, 3.0]), [0.5], drop_nan=True), [2.0])


def test_the_map_contours_of_10_and_90_percent_bracket_the_median(tmp_path):
    """design-map --population: the critical load of the 10 % finger is at most the median's,
    which is at most the 90 % finger's, at every point; so every contour of the 10 % finger lies
    on the median's high side: {F10 >= c} within {F50 >= c} within {F90 >= c}. The >= 90 % region
    is where the 10 % finger's critical load is beyond the range."""
    import xarray as xr

    from fingerpad.design.designmap import map_data
    from fingerpad.design.store import SweepStore

    spec = spec_for(SPREAD)
    store = SweepStore(tmp_path / "r.zarr", spec, np.array([1e3, 1e4]))
    store.create()
    for region_ in [(slice(0, 1), slice(0, 2)), (slice(1, 2), slice(0, 2))]:
        items = [((region_[0].start, j), point(spec, (region_[0].start, j))) for j in range(2)]
        store.write(region_, items)
    ds = xr.open_zarr(store.path).load()
    out = map_data(ds, "spacing", "height", at=1.0, population=True)
    q10, q50, q90 = (out[f"critical_load_q{q}"].values for q in (10, 50, 90))
    assert np.all(q10 <= q50) and np.all(q50 <= q90) and np.any(q10 < q90)
    for level in (0.1, 0.5, 1.0, 2.0, 4.0):
        assert np.all((q10 >= level) <= (q50 >= level)) and np.all((q50 >= level) <= (q90 >= level))
    frac = out["asperity_over_range"].values
    assert np.all((frac >= 0) & (frac <= 1))
    np.testing.assert_array_equal(out["robust_asperity"].values == 1, frac >= 0.9)
    # the median colour is the stored median band, interpolated at 1 N as the nominal map is
    nominal = map_data(ds.assign(mu_rel=ds["band_mu_rel"].sel(quantile=0.5)), "spacing", "height", at=1.0)
    np.testing.assert_array_equal(out["mu_rel"].values, nominal["mu_rel"].values)

    from fingerpad.plotting.designmap import figure_design_map

    fig = figure_design_map(out)
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert any("10 % finger" in t and "(N)" in t for t in labels) and any(">= 90 % of fingers" in t for t in labels)
    # the colour bar's label is no longer than the bar (on one line it ran past both ends of it)
    fig.canvas.draw()
    bar = next(ax for ax in fig.axes if "median over the population" in ax.yaxis.label.get_text())
    box, frame = bar.yaxis.label.get_window_extent(), bar.get_window_extent()
    assert frame.y0 <= box.y0 and box.y1 <= frame.y1, (box, frame)


POPULATION = """
[population]
size = 8
skin_modulus = { distribution = "uniform", low = "0.2MPa", high = "0.5MPa" }
"""
#: test_sweep.py's small sweep (2 x 2 points here) with a population of 8 fingers.
STUDY = SWEEP_STUDY.format(spacing="130um:200um:2", height='["8um", "20um"]') + POPULATION


@pytest.mark.slow
def test_sweep_and_map_from_the_command_line(tmp_path):
    """The whole path on a local cluster: the study's [population], the bands in the store, the
    map drawn with that population; another population refused for resume and for the map."""
    study = tmp_path / "study.toml"
    study.write_text(STUDY)
    pop = tmp_path / "pop.toml"
    pop.write_text(POPULATION)
    store = tmp_path / "r.zarr"
    res = runner.invoke(app, ["sweep", str(study), "--out", str(store), "--workers", "1"])
    assert res.exit_code == 0, res.output
    from fingerpad.design.store import open_sweep

    ds = open_sweep(store).load()
    assert ds["band_mu_rel"].dims == ("spacing", "height", "quantile", "load")
    assert list(ds["quantile"].values) == [0.05, 0.1, 0.25, 0.5, 0.75, 0.9, 0.95]
    assert ds.attrs["fingerpad_sweep"] == 1 and ds.attrs["fingerpad_sweep_population"] == 1
    assert json.loads(ds.attrs["population"])["size"] == 8
    res = runner.invoke(app, ["design-map", str(store), "--x", "spacing", "--y", "height", "--population",
                              str(pop), "--out", str(tmp_path / "map")])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "map" / "design_map.png").is_file()
    for args in (["sweep", str(study), "--out", str(store), "--population", "adults"],
                 ["design-map", str(store), "--x", "spacing", "--y", "height", "--population", "adults",
                  "--out", str(tmp_path / "map2")]):
        res = runner.invoke(app, args)
        assert res.exit_code == 2
        lines = [ln for ln in res.output.splitlines() if ln.strip()]
        assert len(lines) == 1 and lines[0].startswith("error:") and "population 'adults'" in lines[0], res.output
    assert not (tmp_path / "map2").exists()


def write_study(tmp_path, population=True):
    study = tmp_path / "study.toml"
    study.write_text(STUDY if population else STUDY.split("[population]")[0])
    return study


@pytest.mark.parametrize("args, message", [
    (["--population", "nope"], "--population: 'nope' is neither a preset"),
    (["--quantiles", "0.5,2"], "--quantiles: each must lie in [0, 1]"),
])
def test_bad_population_is_one_error_line(tmp_path, args, message):
    study = write_study(tmp_path)
    res = runner.invoke(app, ["sweep", str(study), "--out", str(tmp_path / "r.zarr"), *args])
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error:") and message in lines[0], res.output
    assert not (tmp_path / "r.zarr").exists()


def test_resume_with_another_population_is_refused(tmp_path):
    """A store laid out for one population (no point computed: the refusal comes first) is not
    resumed with another, nor without one; a store without a population is not resumed with one."""
    from fingerpad.design.spec import read_sweep_file
    from fingerpad.design.store import SweepStore

    study = write_study(tmp_path)
    spec = sweep_from_dict(read_sweep_file(str(study)))
    store = tmp_path / "r.zarr"
    SweepStore(store, spec, np.array([1e3, 1e4])).create()
    for extra in (["--population", "adults"], ["--population", str(tmp_path / "other.toml")]):
        (tmp_path / "other.toml").write_text("[population]\nsize = 9\n")
        res = runner.invoke(app, ["sweep", str(study), "--out", str(store), *extra])
        assert res.exit_code == 2, res.output
        lines = [ln for ln in res.output.splitlines() if ln.strip()]
        assert len(lines) == 1 and "holds this sweep with population 'study.toml' (8 members" in lines[0], res.output
    (tmp_path / "plain").mkdir()
    plain = write_study(tmp_path / "plain", population=False)
    res = runner.invoke(app, ["sweep", str(plain), "--out", str(store)])
    assert res.exit_code == 2 and "and this run asks for no population" in res.output, res.output
    # a store without a population, resumed with one
    store2 = tmp_path / "r2.zarr"
    SweepStore(store2, sweep_from_dict(read_sweep_file(str(plain))), np.array([1e3, 1e4])).create()
    res = runner.invoke(app, ["sweep", str(plain), "--out", str(store2), "--population", "adults"])
    assert res.exit_code == 2 and "holds this sweep with no population" in res.output, res.output


def test_an_axis_the_population_varies_is_refused():
    from fingerpad.errors import FingerpadError

    with pytest.raises(FingerpadError, match=r"\[sweep.axes\] skin_modulus: the population .* draws skin_modulus for every finger"):
        sweep_from_dict({**BASE, "sweep": {"axes": {"skin_modulus": ["0.2MPa", "0.4MPa"]}}}, population=SPREAD)


def test_a_map_of_a_population_the_store_lacks_is_refused(tmp_path):
    """design-map --population on a store swept without one: one error line, exit 2, no folder."""
    from fingerpad.design.spec import read_sweep_file
    from fingerpad.design.store import SweepStore

    plain = write_study(tmp_path, population=False)
    store = tmp_path / "r.zarr"
    SweepStore(store, sweep_from_dict(read_sweep_file(str(plain))), np.array([1e3, 1e4])).create()
    res = runner.invoke(app, ["design-map", str(store), "--x", "spacing", "--y", "height", "--population", "adults",
                              "--out", str(tmp_path / "map")])
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error:") and "holds no population" in lines[0], res.output
    assert not (tmp_path / "map").exists()


@pytest.mark.slow  # ~10 s of the 2-core CI's suite: run by make test-slow
def test_the_repair_of_a_damaged_population_store_names_its_population(tmp_path):
    """Issue 30, defect 9: the repair command suggested for a damaged population store left out
    --population (and named absolute paths); typed as given, the sweep suggested --overwrite,
    which would have thrown the store away. Now the suggestion, typed as given, repairs it, and a
    run that forgets the population is told to give it, not to overwrite."""
    import os
    import shlex
    import subprocess

    from .test_sweep import fingerpad_cmd

    def run(*args: str) -> subprocess.CompletedProcess:
        return subprocess.run([*fingerpad_cmd(), *args], capture_output=True, text=True, timeout=240, cwd=tmp_path,
                              env={**os.environ, "FINGERPAD_CACHE": str(tmp_path / "cache")})

    (tmp_path / "study.toml").write_text(SWEEP_STUDY.format(spacing="130um:200um:2", height='["8um", "20um"]'))
    (tmp_path / "pop.toml").write_text(POPULATION)
    first = run("sweep", "study.toml", "--population", "pop.toml", "--quantiles", "0.2,0.8", "--out", "r.zarr",
                "--workers", "1")
    assert first.returncode == 0, first.stderr
    (tmp_path / "r.zarr" / "band_mu" / "0.0.0.0").write_bytes(b"not a chunk")
    forgot = run("sweep", "study.toml", "--out", "r.zarr")
    assert forgot.returncode == 2
    assert "give --population pop.toml --quantiles 0.1,0.2,0.5,0.8,0.9 as the sweep that wrote it did" in forgot.stderr
    assert "--overwrite would discard its points" in forgot.stderr
    damaged = run("sweep", "study.toml", "--population", "pop.toml", "--quantiles", "0.2,0.8", "--out", "r.zarr")
    assert damaged.returncode == 2, damaged.stderr
    line = damaged.stderr.strip()
    command = line[line.index("fingerpad sweep "):line.index(" recomputes")]
    assert command == ("fingerpad sweep study.toml --out r.zarr --population pop.toml --quantiles 0.1,0.2,0.5,0.8,0.9 "
                       "--repair"), line
    repaired = run(*shlex.split(command)[1:], "--workers", "1")
    assert repaired.returncode == 0, repaired.stderr
    assert "repairing" in repaired.stderr
