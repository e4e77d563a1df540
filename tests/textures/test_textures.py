"""Tests of fingerpad.textures: generated unit cells and measured height maps."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from fingerpad.errors import FingerpadError, ResolutionWarning
from fingerpad.textures import (
    GENERATORS,
    Texture,
    base_mask,
    bisinusoid,
    describe,
    dimples,
    ellipsoids,
    flat,
    level_plane,
    make_texture,
    periodize,
    pillars,
    read_surface,
    ridges,
    sinusoid,
    spherical_caps,
)

UM = 1e-6


def mirror_x(h: np.ndarray) -> np.ndarray:
    """Heights of the texture reflected through x = 0 (i -> -i mod nx)."""
    return np.roll(h[::-1, :], 1, axis=0)


def mirror_y(h: np.ndarray) -> np.ndarray:
    return np.roll(h[:, ::-1], 1, axis=1)


# ------------------------------------------------------------------------------------------------
# Generators: shapes, sizes, conventions
# ------------------------------------------------------------------------------------------------

EXAMPLES = {
    "caps": dict(radius=50 * UM, height=10 * UM, spacing=100 * UM),
    "dimples": dict(radius=50 * UM, depth=10 * UM, spacing=100 * UM, lattice="hexagonal"),
    "ridges": dict(width=40 * UM, height=10 * UM, spacing=100 * UM, profile="sinusoidal"),
    "ellipsoids": dict(semi_axis_x=30 * UM, semi_axis_y=15 * UM, height=10 * UM,
                       spacing_x=100 * UM, spacing_y=50 * UM, orientation=0.3),
    "pillars": dict(diameter=40 * UM, height=10 * UM, spacing=80 * UM),
    "sinusoid": dict(amplitude=2 * UM, wavelength=100 * UM),
    "bisinusoid": dict(amplitude=2 * UM, wavelength=100 * UM),
    "flat": dict(size=(200 * UM, 100 * UM)),
}


def test_registry_covers_all_cli_names():
    assert set(GENERATORS) == set(EXAMPLES)


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_generated_texture_conventions(name):
    with warnings.catch_warnings():
        warnings.simplefilter("error", ResolutionWarning)
        tex = make_texture(name, **EXAMPLES[name])
    assert isinstance(tex, Texture)
    assert tex.periodic
    assert tex.name == name
    assert tex.heights.ndim == 2 and tex.heights.dtype == float
    assert tex.heights.min() == 0.0
    nx, ny = tex.shape
    assert 64 <= nx <= 2048
    dx, dy = tex.spacing
    assert dx == pytest.approx(tex.size[0] / nx)
    assert dy / dx == pytest.approx(1.0, abs=0.02)  # (nearly) square pixels
    # params hold SI inputs and regenerate the same texture
    again = make_texture(name, **tex.params)
    np.testing.assert_array_equal(again.heights, tex.heights)
    assert again.size == tex.size
    text = describe(tex)
    assert "\n" not in text and text.startswith(name)


def test_cell_sizes():
    assert spherical_caps(radius=50 * UM, height=5 * UM, spacing=100 * UM).size == (100 * UM, 100 * UM)
    hexa = spherical_caps(radius=50 * UM, height=5 * UM, spacing=100 * UM, lattice="hexagonal", grid=64)
    assert hexa.size == pytest.approx((100 * UM, math.sqrt(3) * 100 * UM), rel=1e-15)
    assert hexa.shape == (64, 112)  # 64 sqrt 3 = 110.9 -> nearest even 7-smooth size 112 = 2^4 7
    ell = ellipsoids(semi_axis_x=20 * UM, semi_axis_y=10 * UM, height=5 * UM,
                     spacing_x=100 * UM, spacing_y=50 * UM, grid=128)
    assert ell.shape == (128, 64) and ell.size == (100 * UM, 50 * UM)
    rid = ridges(width=50 * UM, height=5 * UM, spacing=100 * UM, grid=128, ny=3)
    assert rid.shape == (128, 3)
    assert rid.size == pytest.approx((100 * UM, 3 * 100 * UM / 128))
    sin = sinusoid(amplitude=1 * UM, wavelength=40 * UM, grid=32)
    assert sin.shape == (32, 8) and sin.size[0] == 40 * UM
    fl = flat(size=1e-3, grid=16)
    assert fl.shape == (16, 16) and fl.size == (1e-3, 1e-3) and fl.peak_to_valley == 0.0


def test_default_grid_resolves_smallest_feature():
    # base radius a = sqrt(2*20*2 - 4) um = 8.7 um in a 200 um cell: >= 16 px -> >= 368 -> 384
    tex = spherical_caps(radius=20 * UM, height=2 * UM, spacing=200 * UM)
    a = math.sqrt(2 * 20 * 2 - 4) * UM
    assert tex.shape[0] == 384
    assert a / tex.spacing[0] >= 16
    # tiny features are capped at 2048 and warned about
    with pytest.warns(ResolutionWarning):
        tex = pillars(diameter=1 * UM, height=1 * UM, spacing=1000 * UM)
    assert tex.shape[0] == 2048


# ------------------------------------------------------------------------------------------------
# Spherical caps and dimples
# ------------------------------------------------------------------------------------------------


def test_cap_height_and_footprint_radius():
    radius, height, spacing = 40 * UM, 8 * UM, 100 * UM
    a = math.sqrt(2 * radius * height - height**2)
    tex = spherical_caps(radius=radius, height=height, spacing=spacing, grid=256)
    h = tex.heights
    nx, ny = tex.shape
    dx, dy = tex.spacing
    assert h.max() == pytest.approx(height, rel=1e-14)
    assert h[nx // 2, ny // 2] == h.max()  # centred cap
    x, y = tex.coordinates()
    r = np.hypot(x[:, None] - spacing / 2, y[None, :] - spacing / 2)
    inside = h > 0
    assert r[inside].max() <= a
    assert r[inside].max() >= a - dx
    assert np.all(h[r > a] == 0.0)
    # footprint area within a perimeter-pixel band of pi a^2
    area = np.count_nonzero(inside) * dx * dy
    assert abs(area - math.pi * a**2) < 2 * math.pi * a * dx
    # a sample point obeys the sphere equation
    i, j = nx // 2 + 10, ny // 2 + 5
    rr = math.hypot(10 * dx, 5 * dy)
    assert h[i, j] == pytest.approx(math.sqrt(radius**2 - rr**2) - (radius - height), rel=1e-12)


def test_hexagonal_cell_is_exactly_periodic_with_six_neighbours():
    spacing = 60 * UM
    tex = spherical_caps(radius=20 * UM, height=5 * UM, spacing=spacing, lattice="hexagonal", grid=96)
    h = tex.heights
    nx, ny = tex.shape
    assert nx % 2 == 0 and ny % 2 == 0
    assert abs(ny / (nx * math.sqrt(3)) - 1) <= 0.02  # nearly square pixels, FFT-friendly ny
    # the two caps per cell are identical: the map equals itself shifted by half a cell
    np.testing.assert_array_equal(h, np.roll(h, (nx // 2, ny // 2), axis=(0, 1)))
    assert h[0, 0] == h.max() == h[nx // 2, ny // 2]
    # tile 3x3 and locate the cap tops: caps of the middle cell have 6 neighbours at `spacing`
    tiled = np.tile(h, (3, 3))
    dx, dy = tex.spacing
    ii, jj = np.nonzero(tiled == h.max())
    pts = np.column_stack([ii * dx, jj * dy])
    assert len(pts) == 18  # two per cell
    dist = np.hypot(*(pts[:, None, :] - pts[None, :, :]).transpose(2, 0, 1))
    np.fill_diagonal(dist, np.inf)
    assert dist.min() == pytest.approx(spacing, rel=1e-12)
    lx, ly = tex.size
    for cx, cy in [(lx, ly), (1.5 * lx, 1.5 * ly)]:  # corner cap and centre cap of the middle cell
        k = np.argmin(np.hypot(pts[:, 0] - cx, pts[:, 1] - cy))
        assert np.hypot(pts[k, 0] - cx, pts[k, 1] - cy) < 1e-12
        assert np.count_nonzero(np.isclose(dist[k], spacing, rtol=1e-12)) == 6


@pytest.mark.parametrize("lattice", ["square", "hexagonal"])
def test_caps_mirror_symmetry_is_exact(lattice):
    tex = spherical_caps(radius=30 * UM, height=6 * UM, spacing=70 * UM, lattice=lattice, grid=64)
    h = tex.heights
    np.testing.assert_array_equal(mirror_x(h), h)
    np.testing.assert_array_equal(mirror_y(h), h)
    if lattice == "square":
        np.testing.assert_array_equal(h.T, h)


def test_touching_caps_are_allowed_overlapping_are_not():
    radius, height = 50 * UM, 10 * UM
    a = math.sqrt(2 * radius * height - height**2)
    tex = spherical_caps(radius=radius, height=height, spacing=2 * a, grid=64)
    assert base_mask(tex).any()
    for lattice in ("square", "hexagonal"):
        with pytest.raises(FingerpadError, match="overlap"):
            spherical_caps(radius=radius, height=height, spacing=1.9 * a, lattice=lattice)
        with pytest.raises(FingerpadError, match="overlap"):
            dimples(radius=radius, depth=height, spacing=1.9 * a, lattice=lattice)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(radius=10 * UM, height=11 * UM, spacing=100 * UM), "exceeds the sphere radius"),
        (dict(radius=-10 * UM, height=5 * UM, spacing=100 * UM), "radius: must be positive"),
        (dict(radius=10 * UM, height=0.0, spacing=100 * UM), "height: must be positive"),
        (dict(radius=10 * UM, height=5 * UM, spacing=0.0), "spacing: must be positive"),
        (dict(radius=10 * UM, height=5 * UM, spacing=100 * UM, lattice="triangle"), "lattice"),
        (dict(radius=10 * UM, height=5 * UM, spacing=100 * UM, grid=4), "at least 8"),
        (dict(radius=10 * UM, height=5 * UM, spacing=100 * UM, grid=65), "even"),
    ],
)
def test_cap_parameter_errors(kwargs, match):
    with pytest.raises(FingerpadError, match=match):
        spherical_caps(**kwargs)


def test_hemispherical_cap_allowed():
    tex = spherical_caps(radius=10 * UM, height=10 * UM, spacing=20 * UM, grid=64)
    assert tex.heights.max() == pytest.approx(10 * UM)


@pytest.mark.parametrize("lattice", ["square", "hexagonal"])
def test_dimples_are_negative_caps(lattice):
    kw = dict(radius=40 * UM, spacing=90 * UM, lattice=lattice, grid=64)
    caps = spherical_caps(height=7 * UM, **kw)
    dim = dimples(depth=7 * UM, **kw)
    assert dim.size == caps.size
    np.testing.assert_array_equal(dim.heights, 7 * UM - caps.heights)
    assert dim.heights.min() == 0.0 and dim.heights.max() == pytest.approx(7 * UM)
    # the flat top is the highest level; the base mask holds the dimple bottoms only
    assert np.count_nonzero(base_mask(dim)) == (1 if lattice == "square" else 2)


# ------------------------------------------------------------------------------------------------
# Ridges, ellipsoids, pillars, sinusoids, flat
# ------------------------------------------------------------------------------------------------


def test_circular_ridge_profile():
    w, h, s = 60 * UM, 10 * UM, 100 * UM
    tex = ridges(width=w, height=h, spacing=s, profile="circular", grid=200)
    z = tex.heights
    assert np.all(z == z[:, :1])  # constant along y
    np.testing.assert_array_equal(mirror_x(z), z)
    rad = (w**2 / 4 + h**2) / (2 * h)
    x = tex.coordinates()[0] - s / 2
    expected = np.where(np.abs(x) <= w / 2, np.sqrt(np.maximum(rad**2 - x**2, 0)) - (rad - h), 0)
    np.testing.assert_allclose(z[:, 0], np.maximum(expected, 0), atol=1e-12 * h)
    assert z.max() == pytest.approx(h, rel=1e-14)
    with pytest.raises(FingerpadError, match="half its width"):
        ridges(width=10 * UM, height=6 * UM, spacing=s, profile="circular")


def test_sinusoidal_ridge_of_full_width_is_a_sinusoid():
    s, h = 100 * UM, 4 * UM
    rid = ridges(width=s, height=h, spacing=s, profile="sinusoidal", grid=64)
    sin = sinusoid(amplitude=h / 2, wavelength=s, grid=64)
    # the ridge is centred at Lx/2, the sinusoid peaks at x = 0
    np.testing.assert_allclose(np.roll(rid.heights, 32, axis=0), sin.heights, atol=1e-15 * h)


def test_trapezoidal_ridge():
    w, t, h, s = 60 * UM, 20 * UM, 5 * UM, 100 * UM
    tex = ridges(width=w, height=h, spacing=s, profile="trapezoidal", top_width=t, grid=100)
    z = tex.heights[:, 0]
    dx = tex.spacing[0]
    assert np.count_nonzero(z == h) == round(t / dx) + 1  # 20 um / 1 um: 21 points
    assert np.count_nonzero(z > 0) == round(w / dx) - 1  # the flank feet are at z = 0
    x = tex.coordinates()[0] - s / 2
    flank = (np.abs(x) > t / 2) & (np.abs(x) < w / 2)
    np.testing.assert_allclose(z[flank], h * (w / 2 - np.abs(x[flank])) / ((w - t) / 2), rtol=1e-12)
    assert tex.params["top_width"] == t
    assert ridges(width=w, height=h, spacing=s, profile="trapezoidal").params["top_width"] == w / 2
    with pytest.raises(FingerpadError, match="top_width"):
        ridges(width=w, height=h, spacing=s, profile="trapezoidal", top_width=2 * w)
    with pytest.raises(FingerpadError, match="trapezoidal"):
        ridges(width=w, height=h, spacing=s, profile="circular", top_width=t)


def test_ridge_width_larger_than_spacing_is_an_error():
    with pytest.raises(FingerpadError, match="exceeds the ridge spacing"):
        ridges(width=120 * UM, height=5 * UM, spacing=100 * UM)
    with pytest.raises(FingerpadError, match="profile"):
        ridges(width=50 * UM, height=5 * UM, spacing=100 * UM, profile="square")


def test_ellipsoid_axes_and_orientation():
    a, b, h = 30 * UM, 10 * UM, 5 * UM
    kw = dict(semi_axis_x=a, semi_axis_y=b, height=h, spacing_x=80 * UM, spacing_y=80 * UM, grid=160)
    tex0 = ellipsoids(**kw)
    z = tex0.heights
    dx = tex0.spacing[0]
    nx, ny = tex0.shape
    assert z.max() == pytest.approx(h, rel=1e-14) and z[nx // 2, ny // 2] == z.max()
    half_x = np.count_nonzero(z[:, ny // 2] > 0) // 2
    half_y = np.count_nonzero(z[nx // 2, :] > 0) // 2
    assert a - dx <= half_x * dx <= a and b - dx <= half_y * dx <= b
    np.testing.assert_array_equal(mirror_x(z), z)
    np.testing.assert_array_equal(mirror_y(z), z)
    # rotating by 90 degrees swaps the axes (up to rounding of cos(pi/2), amplified by the
    # square root at the footprint edge)
    tex90 = ellipsoids(orientation="90deg", **kw)
    np.testing.assert_allclose(tex90.heights, z.T, atol=1e-7 * h)
    # any orientation keeps the point symmetry exactly
    tex30 = ellipsoids(orientation=math.radians(30), **kw)
    np.testing.assert_array_equal(mirror_x(mirror_y(tex30.heights)), tex30.heights)
    assert not np.array_equal(mirror_x(tex30.heights), tex30.heights)


def test_ellipsoid_overlap_uses_rotated_footprint():
    kw = dict(semi_axis_x=40 * UM, semi_axis_y=10 * UM, height=5 * UM, spacing_x=100 * UM, spacing_y=50 * UM)
    ellipsoids(grid=128, **kw)  # fits unrotated
    with pytest.raises(FingerpadError, match="overlap along y"):
        ellipsoids(orientation=math.pi / 2, **kw)
    with pytest.raises(FingerpadError, match="overlap along x"):
        ellipsoids(**{**kw, "spacing_x": 70 * UM})


def test_pillars():
    d, h, s = 30 * UM, 4 * UM, 60 * UM
    for lattice in ("square", "hexagonal"):
        tex = pillars(diameter=d, height=h, spacing=s, lattice=lattice, grid=120)
        z = tex.heights
        assert set(np.unique(z)) == {0.0, h}
        np.testing.assert_array_equal(mirror_x(z), z)
        np.testing.assert_array_equal(mirror_y(z), z)
        count = 1 if lattice == "square" else 2
        area = np.count_nonzero(z == h) * tex.spacing[0] * tex.spacing[1]
        assert area == pytest.approx(count * math.pi * d**2 / 4, rel=0.05)
        # the top is exactly flat and the rest is the base
        assert np.array_equal(base_mask(tex), z == 0)
    with pytest.raises(FingerpadError, match="overlap"):
        pillars(diameter=70 * UM, height=h, spacing=s)


def test_sinusoid_and_bisinusoid_forms():
    h, lam = 2 * UM, 50 * UM
    sin = sinusoid(amplitude=h, wavelength=lam, grid=64)
    x = sin.coordinates()[0]
    np.testing.assert_allclose(sin.heights[:, 0], h * (1 + np.cos(2 * np.pi * x / lam)), atol=1e-15 * h)
    np.testing.assert_array_equal(mirror_x(sin.heights), sin.heights)
    assert sin.peak_to_valley == pytest.approx(2 * h)

    jgh = bisinusoid(amplitude=h, wavelength=lam, grid=64)
    assert jgh.params["form"] == "sum"
    assert jgh.peak_to_valley == pytest.approx(4 * h, rel=1e-14)
    x, y = jgh.coordinates()
    expected = h * (np.cos(2 * np.pi * x / lam)[:, None] + np.cos(2 * np.pi * y / lam)[None, :]) + 2 * h
    np.testing.assert_allclose(jgh.heights, expected, atol=1e-14 * h)
    egg = bisinusoid(amplitude=h, wavelength=lam, form="product", grid=64)
    expected = h * np.cos(2 * np.pi * x / lam)[:, None] * np.cos(2 * np.pi * y / lam)[None, :] + h
    np.testing.assert_allclose(egg.heights, expected, atol=1e-14 * h)
    assert egg.peak_to_valley == pytest.approx(2 * h, rel=1e-14)
    for tex in (jgh, egg):
        np.testing.assert_array_equal(mirror_x(tex.heights), tex.heights)
        np.testing.assert_array_equal(tex.heights.T, tex.heights)
    with pytest.raises(FingerpadError, match="form"):
        bisinusoid(amplitude=h, wavelength=lam, form="difference")


def test_flat_reference():
    tex = flat(size=(2e-3, 1e-3), grid=32)
    assert tex.shape == (32, 16) and np.all(tex.heights == 0)
    assert base_mask(tex).all()
    with pytest.raises(FingerpadError, match="grid"):
        flat(size=1e-3, grid=2)


# ------------------------------------------------------------------------------------------------
# Resolution, registry
# ------------------------------------------------------------------------------------------------


def test_resolution_warning_for_coarse_grid():
    kw = dict(radius=20 * UM, height=2 * UM, spacing=200 * UM)  # a = 8.7 um
    with pytest.warns(ResolutionWarning, match="pixels"):
        spherical_caps(grid=64, **kw)  # 3.125 um pixels: 2.8 px across a
    with warnings.catch_warnings():
        warnings.simplefilter("error", ResolutionWarning)
        spherical_caps(grid=192, **kw)  # 1.04 um pixels: 8.3 px
    with pytest.warns(ResolutionWarning):
        ridges(width=5 * UM, height=1 * UM, spacing=100 * UM, grid=64)


def test_make_texture_errors_list_valid_choices():
    with pytest.raises(FingerpadError, match="unknown texture 'bumps'.*caps.*dimples"):
        make_texture("bumps", radius=1)
    with pytest.raises(FingerpadError, match=r"unknown parameter\(s\) radiuss; valid: radius, height"):
        make_texture("caps", radiuss=1e-5, height=1e-6, spacing=1e-4)
    with pytest.raises(FingerpadError, match=r"missing parameter\(s\) spacing; valid:.*lattice='square'"):
        make_texture("caps", radius=1e-5, height=1e-6)


def test_make_texture_accepts_unit_strings():
    a = make_texture("caps", radius="50um", height="10 um", spacing="0.1mm", grid="64")
    b = spherical_caps(radius=50e-6, height=10e-6, spacing=100e-6, grid=64)
    np.testing.assert_allclose(a.heights, b.heights, rtol=1e-12, atol=1e-20)
    assert a.params.keys() == b.params.keys()
    for key, value in b.params.items():
        assert a.params[key] == (pytest.approx(value, rel=1e-12) if isinstance(value, float) else value)
    with pytest.raises(FingerpadError, match="radius"):
        make_texture("caps", radius="50kPa", height=1e-6, spacing=1e-4)


# ------------------------------------------------------------------------------------------------
# Measured surfaces
# ------------------------------------------------------------------------------------------------


def _bumpy(nx=24, ny=16, seed=0):
    rng = np.random.default_rng(seed)
    return rng.random((nx, ny))


def test_read_npy_round_trip(tmp_path):
    h = _bumpy()
    path = tmp_path / "scan.npy"
    np.save(path, h)
    tex = read_surface(path, size=(240 * UM, 160 * UM), height_unit="um", level=False)
    assert tex.name == "scan" and not tex.periodic
    assert tex.shape == (24, 16) and tex.size == (240 * UM, 160 * UM)
    np.testing.assert_allclose(tex.heights, (h - h.min()) * 1e-6, rtol=1e-12, atol=1e-20)
    assert tex.params["height_factor"] == 1e-6
    # a size of the wrong aspect would stretch the map: refused (issue 8), the pixel size is the way out
    with pytest.raises(FingerpadError, match="aspect"):
        read_surface(path, size="1mm", height_unit=1e-9, level=False)
    square = read_surface(path, pixel_size="10um", height_unit=1e-9, level=False)
    assert square.size == pytest.approx((240e-6, 160e-6))
    np.testing.assert_allclose(square.heights, (h - h.min()) * 1e-9, rtol=1e-12)
    assert "finite patch" in describe(square)
    stretched = read_surface(path, pixel_size=("10um", "15um"), height_unit="um", level=False)
    assert stretched.size == pytest.approx((240e-6, 240e-6))


@pytest.mark.parametrize("suffix, delimiter", [(".txt", " "), (".csv", ","), (".dat", "\t"), (".asc", ";")])
def test_read_text_round_trip(tmp_path, suffix, delimiter):
    h = _bumpy(7, 5)
    path = tmp_path / f"map{suffix}"
    # image-like layout: each row a profile along x at one y
    np.savetxt(path, h.T, delimiter=delimiter, header="exported by an instrument", fmt="%.17g")
    tex = read_surface(path, size=(70 * UM, 50 * UM), height_unit="mm", level=False)
    assert tex.shape == (7, 5)
    np.testing.assert_allclose(tex.heights, (h - h.min()) * 1e-3, rtol=1e-12)


@pytest.mark.parametrize("suffix", [".npy", ".txt"])
def test_missing_size_or_unit(tmp_path, suffix):
    path = tmp_path / f"m{suffix}"
    if suffix == ".npy":
        np.save(path, _bumpy())
    else:
        np.savetxt(path, _bumpy())
    with pytest.raises(FingerpadError, match="size"):
        read_surface(path, height_unit="um")
    with pytest.raises(FingerpadError, match="height_unit"):
        read_surface(path, size=1e-3)
    with pytest.raises(FingerpadError, match="height_unit"):
        read_surface(path, size=1e-3, height_unit="furlong")
    with pytest.raises(FingerpadError, match="size"):
        read_surface(path, size=(1e-3, -1e-3), height_unit="um")


def test_missing_points(tmp_path):
    h = _bumpy()
    h[3, 4] = np.nan
    h[10, 2] = np.nan
    path = tmp_path / "holes.npy"
    np.save(path, h)
    with pytest.raises(FingerpadError, match="2 of 384 height values are missing"):
        read_surface(path, size=(240e-6, 160e-6), height_unit="um")
    tex = read_surface(path, size=(240e-6, 160e-6), height_unit="um", level=False, fill_missing=True)
    assert np.all(np.isfinite(tex.heights))
    assert tex.params["filled_points"] == 2
    # filled from a nearest valid neighbour
    scaled = (h - np.nanmin(h)) * 1e-6
    neighbours = [scaled[2, 4], scaled[4, 4], scaled[3, 3], scaled[3, 5]]
    assert any(tex.heights[3, 4] == pytest.approx(v) for v in neighbours)
    # empty csv fields are missing points too
    csv = tmp_path / "holes.csv"
    csv.write_text("1,2,3\n4,,6\n7,8,9\n")
    with pytest.raises(FingerpadError, match="1 of 9"):
        read_surface(csv, size=1e-3, height_unit="um")


def test_bad_files(tmp_path):
    with pytest.raises(FingerpadError, match="not found"):
        read_surface(tmp_path / "nothing.npy", size=1e-3, height_unit="um")
    line = tmp_path / "line.npy"
    np.save(line, np.arange(10.0))
    with pytest.raises(FingerpadError, match="line scan"):
        read_surface(line, size=1e-3, height_unit="um")
    row = tmp_path / "row.txt"
    row.write_text("1 2 3 4 5\n")
    with pytest.raises(FingerpadError, match="line scan"):
        read_surface(row, size=1e-3, height_unit="um")
    words = tmp_path / "words.txt"
    words.write_text("x y z\n1 2 3\n")
    with pytest.raises(FingerpadError, match="line 1: cannot read 'x'"):
        read_surface(words, size=1e-3, height_unit="um")
    ragged = tmp_path / "ragged.txt"
    ragged.write_text("1 2 3\n4 5\n")
    with pytest.raises(FingerpadError, match="line 2 has 2 values"):
        read_surface(ragged, size=1e-3, height_unit="um")
    junk = tmp_path / "junk.npy"
    junk.write_bytes(b"not numpy")
    with pytest.raises(FingerpadError, match="not a valid .npy"):
        read_surface(junk, size=1e-3, height_unit="um")
    unknown = tmp_path / "junk.sur"
    unknown.write_bytes(b"\x00\x01 definitely not a topography")
    with pytest.raises(FingerpadError, match="cannot read surface file"):
        read_surface(unknown)


def test_level_plane_removes_tilt_exactly():
    nx, ny = 40, 30
    size = (400 * UM, 300 * UM)
    x = (np.arange(nx) * size[0] / nx)[:, None]
    y = (np.arange(ny) * size[1] / ny)[None, :]
    plane = 3 * UM + 0.01 * x - 0.02 * y
    np.testing.assert_allclose(level_plane(plane, size), 0.0, atol=1e-18)
    bumps = _bumpy(nx, ny) * UM
    np.testing.assert_allclose(level_plane(bumps + plane, size), level_plane(bumps, size), atol=1e-18)
    residual = level_plane(bumps, size)
    assert abs(residual.mean()) < 1e-20
    assert abs(np.sum(residual * x)) < 1e-22 and abs(np.sum(residual * y)) < 1e-22


def test_read_surface_levels_and_shifts(tmp_path):
    nx, ny = 32, 16
    size = (320 * UM, 160 * UM)
    x = (np.arange(nx) * size[0] / nx)[:, None]
    y = (np.arange(ny) * size[1] / ny)[None, :]
    bumps = _bumpy(nx, ny, seed=3)  # in um
    path = tmp_path / "tilted.npy"
    np.save(path, bumps + 5 + 0.02 * x / UM + 0.01 * y / UM)
    tex = read_surface(path, size=size, height_unit="um")
    expected = level_plane(bumps * UM, size)
    np.testing.assert_allclose(tex.heights, expected - expected.min(), atol=1e-15)
    assert tex.heights.min() == 0.0


def test_periodize_mirrors_into_periodic_cell():
    h = _bumpy(6, 4)
    tex = Texture(h, (60 * UM, 40 * UM), periodic=False, name="scan")
    per = periodize(tex)
    assert per.periodic and per.shape == (12, 8) and per.size == (120 * UM, 80 * UM)
    p = per.heights
    np.testing.assert_array_equal(p[:6, :4], h)
    np.testing.assert_array_equal(p[::-1, :], p)  # mirror about the cell's middle
    np.testing.assert_array_equal(p[:, ::-1], p)
    # continuous across the periodic edges: wrap-around neighbours are equal samples
    np.testing.assert_array_equal(p[0, :], p[-1, :])
    np.testing.assert_array_equal(p[:, 0], p[:, -1])


def test_base_mask_of_caps():
    tex = spherical_caps(radius=50 * UM, height=10 * UM, spacing=100 * UM, grid=128)
    mask = base_mask(tex)
    a = math.sqrt(2 * 50 * 10 - 100) * UM
    assert mask.mean() == pytest.approx(1 - math.pi * a**2 / (100 * UM) ** 2, abs=0.02)
    assert not mask[64, 64] and mask[0, 0]


# ------------------------------------------------------------------------------------------------
# Instrument files through SurfaceTopography
# ------------------------------------------------------------------------------------------------


def test_read_x3p_written_by_surface_topography(tmp_path):
    st = pytest.importorskip("SurfaceTopography")
    h = _bumpy(20, 12)  # micrometres
    path = tmp_path / "scan.x3p"
    st.Topography(h, (200.0, 120.0), unit="µm").to_x3p(str(path))
    tex = read_surface(path, level=False)
    assert tex.shape == (20, 12)
    assert tex.size == pytest.approx((200 * UM, 120 * UM), rel=1e-12)
    np.testing.assert_allclose(tex.heights, (h - h.min()) * UM, rtol=1e-9, atol=1e-18)
    assert not tex.periodic
    # a size given explicitly overrides the file's
    assert read_surface(path, size=(1e-3, 0.6e-3), level=False).size == (1e-3, 0.6e-3)

    masked = np.ma.masked_array(h, mask=np.zeros_like(h, dtype=bool))
    masked.mask[5, 5] = True
    holes = tmp_path / "holes.x3p"
    st.Topography(masked, (200.0, 120.0), unit="µm").to_x3p(str(holes))
    with pytest.raises(FingerpadError, match="1 of 240 height values are missing"):
        read_surface(holes)
    filled = read_surface(holes, fill_missing=True, level=False)
    assert np.all(np.isfinite(filled.heights))


def test_instrument_file_without_metadata_needs_size_and_unit(tmp_path):
    pytest.importorskip("SurfaceTopography")
    h = _bumpy(10, 8)
    path = tmp_path / "raw.topo"  # numpy content under an extension we do not handle ourselves
    with open(path, "wb") as fh:
        np.save(fh, h)
    with pytest.raises(FingerpadError, match="no physical size"):
        read_surface(path)
    with pytest.raises(FingerpadError, match="no height unit"):
        read_surface(path, size=(1e-4, 8e-5))
    tex = read_surface(path, size=(1e-4, 8e-5), height_unit="nm", level=False)
    assert tex.size == (1e-4, 8e-5)
    np.testing.assert_allclose(tex.heights, (h - h.min()) * 1e-9, rtol=1e-12)
