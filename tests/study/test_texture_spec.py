"""Textures of a study: generators with their parameters, and height-map files with their size,
unit, periodicity and mirroring, each mistake named by the key or flag that set it."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from fingerpad import study
from fingerpad.errors import FingerpadError

HEIGHTS_UM = np.add.outer(np.arange(8.0), np.arange(6.0) * 0.5)  # 8 x 6, axis 0 along x


@pytest.fixture
def scan(tmp_path):
    path = tmp_path / "scan.npy"
    np.save(path, HEIGHTS_UM)
    return path


def build(**kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return study.TextureSpec(**kwargs).build()


def test_surface_file_with_size_and_unit(scan):
    tex = build(surface=str(scan), size="80um,60um", height_unit="um")
    assert tex.shape == (8, 6) and tex.size == (80e-6, 60e-6) and not tex.periodic
    assert tex.heights.min() == 0.0
    spec = study.TextureSpec(surface=str(scan), size="80um,60um", height_unit="um")
    assert spec.source == {"source": "file", "file": str(scan.resolve())}


def test_pixel_size_instead_of_size(scan):
    tex = build(surface=str(scan), pixel_size="10um", height_unit="um")
    assert tex.size == pytest.approx((80e-6, 60e-6))


def test_periodic_and_periodized_maps(scan):
    assert build(surface=str(scan), size="80um,60um", height_unit="um", periodic=True).periodic
    mirrored = build(surface=str(scan), size="80um,60um", height_unit="um", periodize=True)
    assert mirrored.periodic and mirrored.shape == (16, 12)
    assert mirrored.size == pytest.approx((160e-6, 120e-6))
    # mirrored: the second half along x is the first reversed
    np.testing.assert_array_equal(mirrored.heights[8:, :6], mirrored.heights[:8, :6][::-1])


def test_study_file_surface_round_trip(tmp_path, scan):
    path = tmp_path / "s.toml"
    path.write_text(f'[texture]\nsurface = "{scan.name}"\nsize = "80um,60um"\nheight_unit = "um"\n'
                    'periodize = true\n[model]\nkind = "bem"\n')
    s = study.load_study_file(path)
    tex = s.build_texture()
    assert tex.shape == (16, 12) and tex.periodic
    s.check()  # a periodized map is fine for the BEM


@pytest.mark.parametrize("kwargs, message", [
    (dict(), "exactly one of a generator name or a surface file"),
    (dict(name="caps", surface="x.npy"), "exactly one of a generator name or a surface file"),
    (dict(surface="x.npy", periodic=True, periodize=True), "--periodic and --periodize contradict each other"),
])
def test_spec_refusals(kwargs, message):
    with pytest.raises(FingerpadError, match=message):
        study.TextureSpec(**kwargs)


def test_build_refusals(scan):
    with pytest.raises(FingerpadError, match="--height-unit applies to surface files only"):
        build(name="flat", size="100um", height_unit="um")
    with pytest.raises(FingerpadError, match="unknown texture key\\(s\\) radius for a surface file"):
        build(surface=str(scan), size="80um", height_unit="um", params={"radius": "1um"})
    with pytest.raises(FingerpadError, match=r"--base-quantile: must lie in \[0, 1\)"):
        build(surface=str(scan), size="80um,60um", height_unit="um", base_quantile=1.0)
    with pytest.raises(FingerpadError, match="the grid applies to generated textures"):
        study.TextureSpec(surface=str(scan), size="80um,60um", height_unit="um").build(grid=16)
    with pytest.raises(FingerpadError, match="stores bare numbers: give --height-unit"):
        build(surface=str(scan), size="80um,60um")
    with pytest.raises(FingerpadError, match="no such file"):
        build(surface=str(scan.parent / "gone.npy"), size="80um", height_unit="um")


def test_labels_name_the_study_file_key(tmp_path, scan):
    path = tmp_path / "s.toml"
    path.write_text(f'[texture]\nsurface = "{scan.name}"\nsize = "80um,60um"\nheight_unit = "um"\n'
                    'periodic = true\nperiodize = true\n')
    with pytest.raises(FingerpadError, match=r"s\.toml \[texture\] periodic and s\.toml \[texture\] periodize"):
        study.load_study_file(path)


def test_generator_finite_patch():
    tex = build(name="caps", params={"radius": "50um", "height": "10um", "spacing": "100um"}, periodic=False)
    assert not tex.periodic and tex.name == "caps"
