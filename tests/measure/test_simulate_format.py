"""The synthetic study writes the documented format (docs/formats.md section 3) and what it
writes reads back: recordings, manifest, samples table and truth; the flat friction follows the
participant's drawn power law."""

from __future__ import annotations

import json

import numpy as np
import pytest

from fingerpad import measure as m
from fingerpad.errors import FingerpadError


@pytest.fixture(scope="module")
def simulated(tmp_path_factory):
    out = tmp_path_factory.mktemp("sim") / "study"
    truth = m.simulate_study(out, m.SimulationConfig(participants=2, repetitions=1, strokes_per_file=8,
                                                      outlier_rate=0.0), seed=4)
    return out, truth


def test_files_and_columns_as_documented(simulated):
    out, truth = simulated
    names = sorted(p.name for p in out.iterdir() if not p.name.startswith("."))  # besides the hidden listing
    assert names == ["P01_bumps_1.csv", "P01_flat_1.csv", "P02_bumps_1.csv", "P02_flat_1.csv", "manifest.csv",
                     "samples.csv", "truth.json"]
    header = (out / "P01_flat_1.csv").read_text().splitlines()[0]
    assert header == "time [s],Fn [N],Ft [mN],x [mm]"
    assert json.loads((out / "truth.json").read_text()) == json.loads(json.dumps(truth))
    assert set(truth["participants"]) == {"P01", "P02"} and truth["reference"] == "flat" and truth["seed"] == 4


def test_manifest_and_folder_read_the_same(simulated):
    out, _ = simulated
    from_folder = m.load_study([out])
    from_manifest = m.read_manifest(out / "manifest.csv")
    assert sorted(r.source for r in from_folder) == sorted(r.source for r in from_manifest)
    rec = next(r for r in from_manifest if r.participant == "P01" and r.sample == "flat")
    assert rec.repetition == "1"
    # Ft is written in mN: read back in newtons, friction over load is a plausible mu
    assert 0.05 < np.median(np.abs(rec.friction)) / np.median(rec.normal) < 2.0


def test_flat_friction_follows_the_drawn_power_law(simulated):
    out, truth = simulated
    for participant, drawn in truth["participants"].items():
        rec = m.read_recording(out / f"{participant}_flat_1.csv")
        strokes = m.measure_strokes(rec)
        fit = m.fit_power_law_clustered(strokes["load"], strokes["mu"])
        assert fit.n == pytest.approx(drawn["n"], abs=0.1), participant
        assert fit.k == pytest.approx(drawn["k"], rel=0.15), participant


def test_samples_table_gives_the_texture(simulated):
    out, truth = simulated
    textures = m.read_textures(out / "samples.csv")
    bumps = textures["bumps"]
    assert (bumps.radius, bumps.height, bumps.spacing) == (truth["textures"]["bumps"]["radius"],
                                                          truth["textures"]["bumps"]["height"],
                                                          truth["textures"]["bumps"]["spacing"])
    assert textures["flat"] is None, "a flat sample has no geometry"
    assert bumps.micro_model == "bem" and bumps.material_modulus is None


def test_same_seed_same_files(simulated, tmp_path):
    out, _ = simulated
    again = tmp_path / "again"
    m.simulate_study(again, m.SimulationConfig(participants=2, repetitions=1, strokes_per_file=8, outlier_rate=0.0),
                     seed=4)
    assert (again / "P02_bumps_1.csv").read_bytes() == (out / "P02_bumps_1.csv").read_bytes()


@pytest.mark.parametrize("kwargs, message", [
    (dict(participants=0), "need at least 1 participant"),
    (dict(load_range=(2.0, 1.0)), "load range must satisfy 0 < low < high"),
    (dict(reference="bumps"), "cannot also be a textured sample"),
    (dict(speed=0.0), "speed must be positive"),
    (dict(sampling_rate=10.0), "at least 40 samples"),
    (dict(participants=1000, repetitions=100, strokes_per_file=100), "at most 5e\\+07 are allowed"),
    (dict(participants=300_000, strokes_per_file=2), "participants: at most 1000 in a simulated study, got 300000"),
    (dict(repetitions=10**9), "repetitions: at most 100"),
    (dict(strokes_per_file=10**6), "strokes per file: at most 10000"),
])
def test_config_refusals(kwargs, message):
    with pytest.raises(FingerpadError, match=message):
        m.SimulationConfig(**kwargs)
