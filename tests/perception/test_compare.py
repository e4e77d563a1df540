"""`fingerpad compare` and :func:`fingerpad.perception.compare.compare`: two surfaces on the same
fingers. The reported summaries are recomputed from the reported member arrays."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from fingerpad.cli import app
from fingerpad.perception.compare import compare
from fingerpad.perception.discrimination import THRESHOLD, p_correct
from fingerpad.population.distributions import population_from_table
from fingerpad.study.spec import study_from_dict

runner = CliRunner()

POP = {"size": 16, "seed": 3, "skin_modulus": {"distribution": "uniform", "low": "0.2MPa", "high": "0.5MPa"},
       "modulus": {"distribution": "uniform", "low": "10kPa", "high": "100kPa"},
       "ridge_fraction": {"distribution": "uniform", "low": 0.1, "high": 0.7}}


def _study(spacing: str, cache: Path, lattice: str = "hexagonal") -> dict:
    return {"texture": {"name": "caps", "radius": "100um", "height": "20um", "spacing": spacing,
                        "lattice": lattice},
            "material": {"modulus": "0.5GPa", "poisson": 0.4}, "loads": {"values": ["0.5N", "1N", "2N"]},
            "model": {"kind": "bem", "grid": 32, "cache": str(cache)}}


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("cells")


def test_identical_surfaces_nobody_tells_apart(cache):
    a = study_from_dict(_study("175um", cache))
    res = compare(a, study_from_dict(_study("175um", cache)), population=population_from_table(POP))
    assert np.array_equal(res.mu_a, res.mu_b)
    assert np.all(res.p == 0.5) and np.all(res.summary()["fraction"] == 0)


def test_flat_reference_is_every_finger_mu_ref(cache):
    from fingerpad.population.run import run_population

    a = study_from_dict(_study("175um", cache))
    pop = population_from_table(POP)
    res = compare(a, "flat", population=pop, speeds=(0.02, 0.1))
    ref = run_population(a, pop)
    assert np.array_equal(res.mu_b, ref.values("mu_ref")) and np.array_equal(res.mu_a, ref.values("mu"))
    # the vibration list: f = v / lambda at both speeds, along x (s) and y (sqrt(3) s, hexagonal)
    vib = [e for e in res.vibration() if e["texture"] == res.a.label and e["harmonic"] == 1]
    assert {(e["direction_deg"], e["speed_m_s"]) for e in vib} == {(0.0, 0.02), (0.0, 0.1), (90.0, 0.02),
                                                                  (90.0, 0.1)}
    for e in vib:
        lam = 175e-6 * (1 if e["direction_deg"] == 0 else math.sqrt(3))
        assert e["wavelength_m"] == pytest.approx(lam, rel=1e-9)
        assert e["frequency_hz"] == pytest.approx(e["speed_m_s"] / lam, rel=1e-9)
        assert e["channel"] == "P"
    assert res.regimes["flat"][0]["verdict"] == "smooth (flat)"


def test_cli_json_summaries_recomputed_from_member_arrays(cache, tmp_path):
    a, b = tmp_path / "a.toml", tmp_path / "b.toml"
    pop = tmp_path / "pop.toml"

    _write(a, _study("175um", cache))
    _write(b, _study("250um", cache))
    pop.write_text("[population]\nsize = 16\nseed = 3\n"
                   'skin_modulus = { distribution = "uniform", low = "0.2MPa", high = "0.5MPa" }\n'
                   'ridge_fraction = { distribution = "uniform", low = 0.1, high = 0.7 }\n')
    out = tmp_path / "out"
    res = runner.invoke(app, ["compare", str(a), str(b), "--population", str(pop), "--speed", "20mm/s:100mm/s",
                              "--weber-fraction", "0.15", "--out", str(out), "--json", str(tmp_path / "c.json")])
    assert res.exit_code == 0, res.stderr
    for name in ("compare.json", "compare.nc", "compare.csv", "compare_vibration.csv", "compare.png"):
        assert (out / name).is_file()
    doc = json.loads((tmp_path / "c.json").read_text())["perception"]
    members = doc["members"]
    mu_a, mu_b, p = (np.array(members[k], float) for k in ("mu_a", "mu_b", "p_correct"))
    w = np.array(members["weber_fraction"], float)
    assert p.shape == (16, 3) and np.all(w == 0.15)
    # P from the member arrays by Eqs. P.1-P.3, then the fraction and the median, exactly
    assert np.array_equal(p_correct(mu_a, mu_b, w[:, None]), p)
    for i, load in enumerate(doc["loads"]):
        key = f"{load:g}"
        assert doc["discrimination"]["fraction"][key] == np.mean(p[:, i] >= THRESHOLD)
        assert doc["discrimination"]["p_correct_median"][key] == np.median(p[:, i])
    assert doc["weber_fraction"] == {"value": 0.15, "drawn": False}
    cited = runner.invoke(app, ["cite", str(out / "compare.json")])
    assert cited.exit_code == 0 and "Gueorguiev" in cited.stdout, cited.stderr
    assert {"texture", "direction_deg", "wavelength_m", "speed_m_s", "frequency_hz", "channel"} <= set(
        doc["vibration"][0])
    import xarray as xr

    with xr.open_dataset(out / "compare.nc") as ds:
        assert np.array_equal(ds["p_correct"].values, p) and ds["fraction"].attrs["units"] == "1"


def _write(path: Path, data: dict) -> None:
    lines = []
    for section, values in data.items():
        lines.append(f"[{section}]")
        for k, v in values.items():
            lines.append(f"{k} = {json.dumps(v)}")
    path.write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize("args, fragment", [
    (["--speed", "-1mm/s"], "--speed"),
    (["--speed", "20N"], "--speed"),
    (["--weber-fraction", "0"], "--weber-fraction"),
    (["--directions", "0,,90"], "--directions"),
])
def test_cli_bad_inputs_one_line(tmp_path, cache, args, fragment):
    a = tmp_path / "a.toml"
    _write(a, _study("175um", cache))
    res = runner.invoke(app, ["compare", str(a), "flat", *args, "--out", str(tmp_path / "o")])
    assert res.exit_code == 2, (res.stdout, res.stderr)
    lines = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: ") and fragment in lines[0], res.stderr
    assert not (tmp_path / "o").exists()


def test_speeds_take_units():
    from fingerpad.perception.compare import parse_directions, parse_speeds
    from fingerpad.units import parse_quantity

    assert parse_quantity("20mm/s", "speed") == 0.02 and parse_quantity("0.1m/s", "speed") == 0.1
    assert parse_speeds("20mm/s:100mm/s") == (0.02, 0.1)
    assert parse_speeds("50mm/s") == (0.05,)
    assert parse_speeds("10mm/s:50mm/s:5") == pytest.approx((0.01, 0.02, 0.03, 0.04, 0.05))
    assert parse_directions("0,90deg") == (0.0, 90.0)
    with pytest.raises(Exception, match="16 allowed"):
        parse_speeds("10mm/s:50mm/s:17")


def test_predict_perception_cli(cache, tmp_path):
    study = tmp_path / "s.toml"
    _write(study, _study("175um", cache))
    res = runner.invoke(app, ["predict", str(study), "--perception", "--speed", "50mm/s", "--json", "-"])
    assert res.exit_code == 0, res.stderr
    doc = json.loads(res.stdout)
    perc = doc["perception"]
    assert perc["b"]["label"] == "flat" and perc["speeds"] == [0.05]
    mu = np.array([r["mu"] for r in doc["results"]])
    mu_ref = np.array([r["mu_ref"] for r in doc["results"]])
    p = np.array(perc["members"]["p_correct"], float)
    assert np.array_equal(p[0], p_correct(mu, mu_ref, 0.11))  # the study's finger against its own mu_ref
    keys = [r["key"] for r in doc["references"]]
    assert "gueorguiev2017" in keys and "greenwood1958" in keys  # the perception's and the prediction's
    res = runner.invoke(app, ["predict", str(study), "--speed", "50mm/s", "--json", "-"])
    assert res.exit_code == 2 and "--speed needs --perception" in res.stderr


def test_against_a_measured_map(cache, tmp_path):
    """B a measured (periodic) map: its friction is compared; it has no lattice, so no vibration
    entries and no roughness regime, said in a note."""
    from fingerpad import textures

    cell = textures.spherical_caps(radius=100e-6, height=20e-6, spacing=200e-6, grid=32)
    heights = cell.heights + np.random.default_rng(0).normal(0.0, 0.2e-6, cell.heights.shape)
    np.save(tmp_path / "map.npy", heights)
    b = study_from_dict({"texture": {"surface": str(tmp_path / "map.npy"), "size": "200um,200um",
                                     "height_unit": "m", "periodic": True},
                         "material": {"modulus": "0.5GPa", "poisson": 0.4},
                         "model": {"kind": "bem", "cache": str(cache)}})
    res = compare(study_from_dict(_study("175um", cache)), b)
    assert np.all(np.isfinite(res.p)) and np.all(res.p >= 0.5)
    assert {e["texture"] for e in res.vibration()} == {res.a.label}
    assert any("measured map has no lattice" in n for n in res.notes)
    assert res.regimes[res.b.label][0]["verdict"].startswith("not estimated")


def test_outputs_cite_the_perception_sources(cache):
    res = compare(study_from_dict(_study("175um", cache)), "flat")
    keys = [r["key"] for r in res.as_dict()["references"]]
    for key in ("sergachev2021", "gueorguiev2017", "bolanowski1988", "verrillo1963", "hollins2007", "delhaye2012"):
        assert key in keys
    assert "Gueorguiev" in res.dataset().attrs["references"]
