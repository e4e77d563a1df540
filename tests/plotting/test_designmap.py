"""The design-map figure from a small synthetic sweep (grid and scattered designs)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from fingerpad.design.designmap import map_data
from fingerpad.plotting.designmap import figure_design_map

SPACINGS = np.array([150e-6, 175e-6, 200e-6])
HEIGHTS = np.array([10e-6, 20e-6, 30e-6, 40e-6])
LOADS = np.geomspace(0.1, 4.0, 12)


def sweep(design: str = "grid"):
    """A store-shaped dataset: critical load and mu_rel smooth in the axes (numbers synthetic)."""
    import xarray as xr

    if design == "grid":
        s, h = np.meshgrid(SPACINGS, HEIGHTS, indexing="ij")
        dims = ("spacing", "height")
        coords = {"spacing": xr.Variable("spacing", SPACINGS, {"units": "m", "log": "false", "kind": "length"}),
                  "height": xr.Variable("height", HEIGHTS, {"units": "m", "log": "false", "kind": "length"})}
    else:
        s = np.array([150e-6, 175e-6, 200e-6, 160e-6, 190e-6, 170e-6, 155e-6])
        h = np.array([10e-6, 20e-6, 30e-6, 25e-6, 15e-6, 35e-6, 40e-6])
        dims = ("point",)
        coords = {"point": np.arange(s.size)}
    crit = 0.5 * (s / 175e-6) ** -2 * (h / 20e-6) ** 1.5
    mu_rel = 0.4 + 0.5 * np.tanh(LOADS / crit[..., None])
    data = {
        "valid": (dims, np.ones(s.shape, bool)), "done": (dims, np.ones(s.shape, bool)),
        "critical_load_bem": (dims, crit), "critical_load_hertz": (dims, crit / 5),
        "mu_rel": ((*dims, "load"), mu_rel),
    }
    if design != "grid":
        data["spacing"] = (dims, s, {"units": "m", "log": "false", "kind": "length"})
        data["height"] = (dims, h, {"units": "m", "log": "false", "kind": "length"})
    coords["load"] = xr.Variable("load", LOADS, {"units": "N"})
    return xr.Dataset(data, coords=coords, attrs={"design": design, "axes": json.dumps(["spacing", "height"])})


@pytest.mark.parametrize("design", ["grid", "points"])
def test_design_map_png(tmp_path, png_is_drawn, design):
    fig = figure_design_map(map_data(sweep(design), "spacing", "height", at=1.0))
    path = tmp_path / "map.png"
    fig.savefig(path, format="png", dpi=50)
    png_is_drawn(path)
    ax = fig.axes[0]
    assert ax.get_xlabel() == "spacing (µm)" and ax.get_ylabel() == "height (µm)"
    assert fig._suptitle.get_text().startswith("Design map: critical load (white contours), μ/μ_ref at 1 N (colour)")
    assert fig.axes[-1].get_ylabel().startswith("μ/μ_ref at 1 N"), "the colour bar names the quantity and load"


def sweep3():
    """A grid over spacing x height x material_modulus (two moduli: two panels)."""
    import xarray as xr

    base = sweep("grid")
    moduli = np.array([1e6, 1e9])
    data = {name: xr.concat([base[name], base[name] * (1.0 if name != "mu_rel" else 0.9)], dim="material_modulus")
            for name in ("valid", "done", "critical_load_bem", "critical_load_hertz", "mu_rel")}
    ds = xr.Dataset(data, coords={**{k: v for k, v in base.coords.items()},
                                  "material_modulus": ("material_modulus", moduli,
                                                       {"kind": "pressure", "log": "true"})},
                    attrs={"design": "grid", "axes": json.dumps(["spacing", "height", "material_modulus"])})
    ds["valid"] = ds["valid"].astype(bool)
    ds["done"] = ds["done"].astype(bool)
    return ds


def test_a_further_axis_gives_one_panel_per_value(tmp_path, png_is_drawn):
    fig = figure_design_map(map_data(sweep3(), "spacing", "height", at=1.0))
    visible = [ax for ax in fig.axes if ax.get_visible() and ax.get_title()]
    # panel titles in the axis' display unit (kPa for pressures)
    assert [ax.get_title() for ax in visible] == ["material_modulus = 1000 kPa", "material_modulus = 1e+06 kPa"]
    path = tmp_path / "panels.png"
    fig.savefig(path, format="png", dpi=40)
    png_is_drawn(path)
    # a selection leaves one panel
    one = figure_design_map(map_data(sweep3(), "spacing", "height", at=1.0, select={"material_modulus": "1GPa"}))
    assert not [ax for ax in one.axes if ax.get_visible() and ax.get_title().startswith("material_modulus")]
