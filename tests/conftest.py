"""Shared test set-up: a private unit-cell cache per test session (never ~/.cache), and a small
prediction to write and draw."""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True, scope="session")
def _private_cache(tmp_path_factory: pytest.TempPathFactory) -> None:
    mp = pytest.MonkeyPatch()
    mp.setenv("FINGERPAD_CACHE", str(tmp_path_factory.mktemp("fingerpad-cache")))
    yield
    mp.undo()


@pytest.fixture(scope="module")
def prediction(tmp_path_factory):
    """Caps on the default finger by BEM (32-point cell) and Hertz, 0.2-3 N (~0.3 s); one per
    test module, so that a module may change it."""
    from fingerpad.study import run as study_run
    from fingerpad.study import study_from_dict

    study = study_from_dict({
        "texture": {"name": "caps", "radius": "50um", "height": "10um", "spacing": "100um"},
        "material": {"modulus": "0.5GPa", "poisson": 0.4},
        "loads": {"range": "0.2N:3N:5"},
        "model": {"kind": "both", "grid": 32, "cache": str(tmp_path_factory.mktemp("cells"))},
    })
    return study_run.run_study(study)
