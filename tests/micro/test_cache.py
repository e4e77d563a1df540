"""The on-disk cache of unit-cell curves: content keys, merged updates, nothing half-written."""

from __future__ import annotations

import json

import numpy as np
import pytest

from fingerpad.errors import FingerpadError
from fingerpad.micro import cache


def test_content_key_follows_heights_shape_and_settings():
    z = np.arange(12.0).reshape(3, 4)
    key = cache.content_key(z, modulus=1e6, tol=1e-8)
    assert len(key) == 64 and key == cache.content_key(z.copy(), tol=1e-8, modulus=1e6)  # order of settings
    assert key == cache.content_key(z.astype(np.float32), modulus=1e6, tol=1e-8)  # same values, as float64
    assert key != cache.content_key(z.reshape(4, 3), modulus=1e6, tol=1e-8)
    z2 = z.copy()
    z2[0, 0] += 1e-12
    assert key != cache.content_key(z2, modulus=1e6, tol=1e-8)
    assert key != cache.content_key(z, modulus=1.1e6, tol=1e-8)
    assert key != cache.content_key(np.asfortranarray(z) * 1.0 + 0.0, modulus=1e6, tol=1e-7)


def test_update_merges_points(tmp_path):
    c = cache.CurveCache(tmp_path / "cells")
    assert c.load("k") == {}
    c.update("k", {"points": {"100": [0.1], "200": [0.2]}, "grid": 16})
    merged = c.update("k", {"points": {"200": [0.25], "400": [0.4]}, "grid": 32})
    assert merged == {"points": {"100": [0.1], "200": [0.25], "400": [0.4]}, "grid": 32}
    assert c.load("k") == merged
    assert json.loads((tmp_path / "cells" / "k.json").read_text()) == merged
    # no temporary files left beside the entry (the lock file may stay)
    assert sorted(p.name for p in (tmp_path / "cells").iterdir() if not p.name.endswith(".lock")) == ["k.json"]


def test_unreadable_entry_is_empty(tmp_path):
    c = cache.CurveCache(tmp_path)
    (tmp_path / "bad.json").write_text("{half")
    assert c.load("bad") == {}
    (tmp_path / "list.json").write_text("[1, 2]")
    assert c.load("list") == {}
    assert c.update("bad", {"a": 1}) == {"a": 1}


def test_failed_write_keeps_the_old_entry(tmp_path):
    c = cache.CurveCache(tmp_path)
    c.update("k", {"a": 1})
    with pytest.raises(TypeError):
        c.update("k", {"b": object()})  # not JSON
    assert c.load("k") == {"a": 1}
    assert not [p for p in tmp_path.iterdir() if p.suffix == ".tmp"]


def test_default_folder(monkeypatch, tmp_path):
    monkeypatch.setenv("FINGERPAD_CACHE", str(tmp_path / "x"))
    assert cache.default_cache_dir() == tmp_path / "x"
    assert cache.CurveCache().folder == tmp_path / "x"
    monkeypatch.delenv("FINGERPAD_CACHE")
    assert cache.default_cache_dir().parts[-2:] == (".cache", "fingerpad")


def test_uncreatable_folder_warns_and_the_work_goes_on(tmp_path):
    """A cache folder that cannot be made never stops the work (issue 20): one warning, the
    entry is handed back unstored."""
    (tmp_path / "file").write_text("")
    with pytest.warns(cache.CacheWarning):
        entry = cache.CurveCache(tmp_path / "file" / "sub").update("k", {"a": 1})
    assert entry["a"] == 1


@pytest.mark.parametrize("content", [
    "{\"points\": {\"0.001\": {\"contact_fr",  # cut short
    "[]",
    "{\"points\": 3}",
    "{\"points\": {\"abc\": {\"contact_fraction\": 0.1}}}",
    "{\"points\": {\"0.001\": {\"contact_fraction\": 2, \"mean_gap\": 0, \"max_pressure\": 0, "
    "\"contact_state\": \"asperity\", \"converged\": true, \"iterations\": 3}}}",
    "{\"transition\": \"x\"}",
    "{\"full\": [1, 0]}",
])
def test_a_damaged_entry_is_said_and_computed_again(tmp_path, content):
    """Issue 30, item 19: a corrupted cache entry was recomputed without a word (and a tampered
    one, valid JSON of another shape, ended in a traceback)."""
    import warnings

    from fingerpad import textures
    from fingerpad.micro.bem import BEMUnitCell
    from fingerpad.micro.cache import _WARNED, CacheWarning, CurveCache

    cell = textures.spherical_caps(radius=50e-6, height=10e-6, spacing=100e-6, grid=32)
    cache = CurveCache(tmp_path)
    ref = BEMUnitCell(cell, 1e6, cache=cache).prepare(1e2, 1e4)
    expected = {k: v.tolist() for k, v in ref.curve().items()}
    entry = next(tmp_path.glob("*.json"))
    entry.write_text(content)
    _WARNED.discard(str(entry))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        again = BEMUnitCell(cell, 1e6, cache=cache).prepare(1e2, 1e4)
    said = [str(w.message) for w in caught if issubclass(w.category, CacheWarning)]
    assert len(said) == 1 and said[0].startswith(f"cache entry {str(entry)!r} cannot be read ("), said
    assert said[0].endswith("its unit-cell points are computed again and the entry is written anew")
    assert {k: v.tolist() for k, v in again.curve().items()} == expected  # the same numbers, whatever the cache held
    # and the entry is whole again: a third cell reads every node from it (main's issue 31: a
    # cell's nodes are those its ranges need, so a new cell's .points is empty until prepared)
    assert BEMUnitCell(cell, 1e6, cache=cache).prepare(1e2, 1e4).solves == 0
