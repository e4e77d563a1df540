"""Fixtures shared by the measurement tests."""

from __future__ import annotations

import pytest

from fingerpad import measure as m


@pytest.fixture(scope="session")
def small_study_dir(tmp_path_factory):
    """A small simulated study (3 participants, flat + bumps, 2 recordings each)."""
    out = tmp_path_factory.mktemp("small") / "study"
    m.simulate_study(out, m.SimulationConfig(participants=3, repetitions=2, strokes_per_file=10), seed=3)
    return out


@pytest.fixture(scope="session")
def study_small(small_study_dir):
    """Its analysis (BEM model, sensitivity, population)."""
    return m.analyse_study(m.load_study([small_study_dir]), m.AnalysisOptions(reference="flat", n_null=199),
                           textures=m.read_textures(small_study_dir / "samples.csv"))
