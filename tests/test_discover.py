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
    (pkg / "a_first.py").write_text("THING = ('a1', 'a2')\n")
    (pkg / "_private.py").write_text("THING = 'hidden'\n")
    (pkg / "skipped.py").write_text("THING = 'skipped'\n")
    (pkg / "none.py").write_text("OTHER = 'x'\n")  # declares nothing: an error unless skipped
    monkeypatch.syspath_prepend(str(tmp_path))
    yield pkg
    for name in [m for m in sys.modules if m.startswith("fp_plugins_test")]:
        del sys.modules[name]


def test_collect_in_module_order_and_of_the_kind(plugin_package):
    import fp_plugins_test

    found = collect("fp_plugins_test", fp_plugins_test.__path__, "THING", str, skip=("skipped", "none"))
    assert found == ["a1", "a2", "b"]  # _private and the skipped helper modules are left out


def test_a_module_that_declares_nothing_or_the_wrong_kind_is_an_error(plugin_package):
    """Strict discovery: a misspelt attribute or a wrong type is not silently skipped."""
    import fp_plugins_test

    from fingerpad.discover import DiscoveryError

    with pytest.raises(DiscoveryError, match="none.py"):
        collect("fp_plugins_test", fp_plugins_test.__path__, "THING", str, skip=("skipped",))
    (plugin_package / "c_third.py").write_text("THING = ('c', 3)\n")
    importlib.invalidate_caches()
    with pytest.raises(DiscoveryError, match="c_third"):
        collect("fp_plugins_test", fp_plugins_test.__path__, "THING", str, skip=("skipped", "none"))


def test_a_new_file_is_found_without_editing_anything(plugin_package):
    import fp_plugins_test

    helpers = ("skipped", "none")
    before = collect("fp_plugins_test", fp_plugins_test.__path__, "THING", str, skip=helpers)
    (plugin_package / "z_new.py").write_text("THING = 'z'\n")
    importlib.invalidate_caches()  # as a new process would see the folder
    after = collect("fp_plugins_test", fp_plugins_test.__path__, "THING", str, skip=helpers)
    assert after == [*before, "z"]


def test_the_package_registries_are_found_this_way():
    from fingerpad.measure.importers import importers
    from fingerpad.textures import registry
    from fingerpad.textures.readers import readers

    assert {"caps", "dimples", "ridges", "ellipsoids", "pillars", "sinusoid", "bisinusoid", "flat"} <= set(registry())
    assert {i.name for i in importers()} >= {"text", "excel", "xls", "matlab", "tdms"}
    assert {r.name for r in readers()} >= {"npy", "text", "instrument"}
