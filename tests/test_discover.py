"""Pieces added by adding one file: ``fingerpad.discover.collect`` finds them by attribute."""

from __future__ import annotations

import importlib
import sys

import pytest

from fingerpad.discover import collect


@pytest.fixture
def plugin_package(tmp_path, monkeypatch):
    pkg = tmp_path / "fp_plugins_test"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "b_second.py").write_text("THING = 'b'\n")
    (pkg / "a_first.py").write_text("THING = ('a1', 'a2', 3)\n")
    (pkg / "_private.py").write_text("THING = 'hidden'\n")
    (pkg / "skipped.py").write_text("THING = 'skipped'\n")
    (pkg / "none.py").write_text("OTHER = 'x'\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    yield pkg
    for name in [m for m in sys.modules if m.startswith("fp_plugins_test")]:
        del sys.modules[name]


def test_collect_in_module_order_and_of_the_kind(plugin_package):
    import fp_plugins_test

    found = collect("fp_plugins_test", fp_plugins_test.__path__, "THING", str, skip=("skipped",))
    assert found == ["a1", "a2", "b"]  # the int 3 is not a str; _private and skipped are left out
    assert collect("fp_plugins_test", fp_plugins_test.__path__, "THING", (str, int), skip=("skipped",)) == \
        ["a1", "a2", 3, "b"]


def test_a_new_file_is_found_without_editing_anything(plugin_package):
    import fp_plugins_test

    before = collect("fp_plugins_test", fp_plugins_test.__path__, "THING", str)
    (plugin_package / "z_new.py").write_text("THING = 'z'\n")
    importlib.invalidate_caches()  # as a new process would see the folder
    after = collect("fp_plugins_test", fp_plugins_test.__path__, "THING", str)
    assert after == [*before, "z"]


def test_the_package_registries_are_found_this_way():
    from fingerpad.measure.importers import importers
    from fingerpad.textures import registry
    from fingerpad.textures.readers import readers

    assert {"caps", "dimples", "ridges", "ellipsoids", "pillars", "sinusoid", "bisinusoid", "flat"} <= set(registry())
    assert {i.name for i in importers()} >= {"text", "excel", "xls", "matlab", "tdms"}
    assert {r.name for r in readers()} >= {"npy", "text", "instrument"}
