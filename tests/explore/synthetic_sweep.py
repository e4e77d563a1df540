"""A small sweep results store written by hand after the store layout of the sweep issue (grid
design over spacing x height of spherical caps, or scattered points), for the map view's tests.

The numbers are synthetic (smooth functions of the axes), not model results: the tests check
that the explorer reads, shows and opens what the store holds.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

BASE_STUDY = {
    "texture": {"name": "caps", "radius": "100um", "height": "20um", "spacing": "175um", "lattice": "hexagonal"},
    "material": {"modulus": "0.5GPa", "poisson": 0.4},
    "finger": {"preset": "default"},
    "loads": {"range": "0.1N:4N:40", "log": True},
    "model": {"kind": "hertz"},
}
SPACINGS = np.array([150e-6, 175e-6, 200e-6])
HEIGHTS = np.array([10e-6, 20e-6, 30e-6, 40e-6])


def synthetic_sweep(path: Path, design: str = "grid") -> Path:
    """Write the store at ``path`` (Zarr) and return it."""
    import xarray as xr

    loads = np.geomspace(0.1, 4.0, 40)
    cell_p = 10 ** (np.arange(36, 72) / 12)
    if design == "grid":
        s, h = np.meshgrid(SPACINGS, HEIGHTS, indexing="ij")
        dims = ("spacing", "height")
        coords = {
            "spacing": xr.Variable("spacing", SPACINGS, {"units": "m", "log": "false", "kind": "length"}),
            "height": xr.Variable("height", HEIGHTS, {"units": "m", "log": "false", "kind": "length"}),
        }
    else:
        s = np.array([150e-6, 175e-6, 200e-6, 160e-6])
        h = np.array([10e-6, 20e-6, 30e-6, 25e-6])
        dims = ("point",)
        coords = {"point": np.arange(s.size)}
    crit_h = 0.18 * (s / 175e-6) ** -2 * (h / 20e-6) ** 1.5
    crit_b = crit_h * 5.0
    crit_b[..., -1] = np.inf if design == "grid" else crit_b[-1]  # the tallest never reaches the transition
    shape = s.shape
    mu_rel = 0.4 + 0.5 * np.tanh(loads.reshape((1,) * len(shape) + (-1,)) / crit_b[..., None])
    valid = np.ones(shape, bool)
    reason = np.full(shape, "", dtype=object)
    if design == "grid":
        valid[0, -1] = False
        reason[0, -1] = "cap height exceeds the radius"
    data = {
        "valid": (dims, valid, {"units": "1", "long_name": "valid design"}),
        "reason": (dims, reason.astype(str), {"units": "1", "long_name": "why not valid"}),
        "converged": (dims, valid.copy(), {"units": "1", "long_name": "all solves converged"}),
        "done": (dims, np.ones(shape, bool), {"units": "1", "long_name": "computed"}),
        "critical_load_bem": (dims, np.where(valid, crit_b, np.nan), {"units": "N", "long_name": "critical load (BEM)"}),
        "critical_load_hertz": (dims, np.where(valid, crit_h, np.nan), {"units": "N", "long_name": "critical load (Hertz)"}),
        "full_contact_load": (dims, np.full(shape, np.inf), {"units": "N", "long_name": "full-contact load"}),
        "transition_pressure": (dims, 3e4 * h / 20e-6, {"units": "Pa", "long_name": "transition pressure"}),
        "full_contact_pressure": (dims, np.full(shape, np.inf), {"units": "Pa", "long_name": "full-contact pressure"}),
        "psi": ((*dims, "cell_pressure"), np.clip(np.ones(shape + (1,)) * cell_p / cell_p.max(), 0, 1),
                {"units": "1", "long_name": "psi"}),
        "contact_state": ((*dims, "load"), (loads > crit_b[..., None]).astype("int8"),
                          {"units": "1", "long_name": "centre state"}),
        "area_ratio": ((*dims, "load"), 0.2 * mu_rel, {"units": "1", "long_name": "A_re/A_fr"}),
        "mu": ((*dims, "load"), 0.5 * mu_rel, {"units": "1", "long_name": "mu"}),
        "mu_ref": ((*dims, "load"), np.full(shape + (loads.size,), 0.5), {"units": "1", "long_name": "mu_ref"}),
        "mu_rel": ((*dims, "load"), mu_rel, {"units": "1", "long_name": "mu / mu_ref"}),
        "grid_error": (dims, np.full(shape, 0.01), {"units": "1", "long_name": "estimated error of A_re/A_fr"}),
        "grid": (dims, np.full(shape, 64), {"units": "1", "long_name": "grid points along x"}),
    }
    if design != "grid":
        data["spacing"] = (dims, s, {"units": "m", "log": "false", "kind": "length"})
        data["height"] = (dims, h, {"units": "m", "log": "false", "kind": "length"})
    coords["load"] = xr.Variable("load", loads, {"units": "N"})
    coords["cell_pressure"] = xr.Variable("cell_pressure", cell_p, {"units": "Pa"})
    ds = xr.Dataset(data, coords=coords, attrs={
        "fingerpad_sweep": 1, "signature": "synthetic", "study": json.dumps(BASE_STUDY),
        "sweep": json.dumps({"spacing": "150um:200um:3", "height": "10um:40um:4"}), "design": design,
        "axes": json.dumps(["spacing", "height"]), "fingerpad_version": "test",
    })
    # the format the sweep store writes (fingerpad.design.store): Zarr v2, consolidated metadata
    ds.to_zarr(path, mode="w", zarr_format=2, consolidated=True)
    return path
