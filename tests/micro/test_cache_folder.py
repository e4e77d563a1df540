"""The unit-cell cache never stops a prediction and respects the umask (issue 20)."""

from __future__ import annotations

import os
import stat
import warnings

import pytest
from typer.testing import CliRunner

from fingerpad.cli import app
from fingerpad.micro import cache as cache_module
from fingerpad.micro.cache import CacheWarning, CurveCache

HERTZ_FREE = ["predict", "--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "100um",
              "--grid", "32", "--loads", "1N", "--json", "-"]


@pytest.fixture(autouse=True)
def _fresh_warnings(monkeypatch):
    monkeypatch.setattr(cache_module, "_WARNED", set())


def test_entries_and_locks_follow_the_umask(tmp_path):
    old = os.umask(0o002)  # a group-shared cache (README)
    try:
        CurveCache(tmp_path).update("k", {"points": {"1.0": {"x": 1}}})
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "k.json").stat().st_mode) == 0o664
    assert stat.S_IMODE((tmp_path / "k.lock").stat().st_mode) == 0o664
    assert CurveCache(tmp_path).load("k") == {"points": {"1.0": {"x": 1}}}


def test_an_unusable_folder_warns_once_and_the_work_goes_on(tmp_path):
    blocker = tmp_path / "cache"
    blocker.write_text("not a folder")
    store = CurveCache(blocker)
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        first = store.update("k", {"points": {"1.0": {"x": 1}}})
        second = store.update("k", {"points": {"2.0": {"x": 2}}})
    assert first == {"points": {"1.0": {"x": 1}}} and "2.0" in second["points"]
    assert [w.category for w in seen] == [CacheWarning]
    assert str(blocker) in str(seen[0].message) and blocker.read_text() == "not a folder"


@pytest.mark.skipif(hasattr(os, "geteuid") and os.geteuid() == 0, reason="root writes into read-only folders")
def test_a_read_only_folder_warns(tmp_path):
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        with pytest.warns(CacheWarning, match="cannot be written"):
            CurveCache(folder).update("k", {"a": 1})
    finally:
        folder.chmod(0o755)


def test_predict_runs_with_an_unusable_cache_and_one_warning(tmp_path, monkeypatch):
    blocker = tmp_path / "cache"
    blocker.write_text("x")
    monkeypatch.setenv("FINGERPAD_CACHE", str(blocker))
    res = CliRunner().invoke(app, HERTZ_FREE)
    assert res.exit_code == 0, res.output
    warned = [line for line in res.stderr.splitlines() if line.startswith("warning:")]
    assert len(warned) == 1 and "cache folder" in warned[0] and "running without" in warned[0]
    res = CliRunner().invoke(app, [*HERTZ_FREE, "--cache", str(blocker / "sub")])
    assert res.exit_code == 0, res.output
