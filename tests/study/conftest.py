"""A prediction to write: caps on the default finger, BEM on a 32-point cell and Hertz (~0.3 s)."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="module")
def prediction(tmp_path_factory):
    from fingerpad.study import run as study_run
    from fingerpad.study import study_from_dict

    study = study_from_dict({
        "texture": {"name": "caps", "radius": "50um", "height": "10um", "spacing": "100um"},
        "material": {"modulus": "0.5GPa", "poisson": 0.4},
        "loads": {"range": "0.2N:3N:5"},
        "model": {"kind": "both", "grid": 32, "cache": str(tmp_path_factory.mktemp("cells"))},
    })
    return study_run.run_study(study)
