"""Shared test set-up: a private unit-cell cache per test session (never ~/.cache)."""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True, scope="session")
def _private_cache(tmp_path_factory: pytest.TempPathFactory) -> None:
    mp = pytest.MonkeyPatch()
    mp.setenv("FINGERPAD_CACHE", str(tmp_path_factory.mktemp("fingerpad-cache")))
    yield
    mp.undo()
