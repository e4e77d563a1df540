"""The design map's data: the critical-load region and mu/mu_ref interpolated at a load."""

from __future__ import annotations

import json

import numpy as np
import pytest

from fingerpad.design.designmap import map_data
from fingerpad.errors import FingerpadError

LOADS = np.array([0.1, 0.4, 1.6])


def store_like():
    import xarray as xr

    spacing = np.array([100e-6, 200e-6])
    height = np.array([5e-6, 10e-6, 20e-6])
    crit = np.array([[0.05, 0.5, np.inf], [0.2, 1.0, 3.0]])  # N
    mu_rel = np.broadcast_to(np.array([0.5, 0.7, 0.9]), (2, 3, 3)).copy()
    valid = np.ones((2, 3), bool)
    valid[1, 2] = False
    return xr.Dataset(
        {"critical_load_bem": (("spacing", "height"), crit), "critical_load_hertz": (("spacing", "height"), crit / 4),
         "valid": (("spacing", "height"), valid), "done": (("spacing", "height"), np.ones((2, 3), bool)),
         "mu_rel": (("spacing", "height", "load"), mu_rel)},
        coords={"spacing": ("spacing", spacing, {"kind": "length", "log": "true"}),
                "height": ("height", height, {"kind": "length", "log": "false"}), "load": LOADS},
        attrs={"design": "grid", "axes": json.dumps(["spacing", "height"])})


def test_regions_and_critical_loads():
    out = map_data(store_like(), "spacing", "height", at=0.4)
    assert out["region"].dims == ("height", "spacing")
    region = out["region"].transpose("spacing", "height").values
    # 0.05 N below the 0.1-1.6 N range, 0.5 and 1.0 inside, inf never (asperity), invalid: no region
    assert region[0].tolist() == [0, 1, 2]
    assert region[1, 0] == 1 and region[1, 1] == 1 and np.isnan(region[1, 2])
    assert np.isnan(out["critical_load"].transpose("spacing", "height").values[1, 2])
    assert out.attrs["x_log"] is True and out.attrs["y_log"] is False
    assert (out.attrs["load_min"], out.attrs["load_max"]) == (0.1, 1.6)


def test_mu_rel_interpolated_in_log_load():
    out = map_data(store_like(), "spacing", "height", at=0.2)
    # halfway between 0.1 and 0.4 in log: halfway between 0.5 and 0.7
    assert float(out["mu_rel"].sel(spacing=100e-6, height=5e-6)) == pytest.approx(0.6, rel=1e-12)
    out = map_data(store_like(), "spacing", "height", at=1.6)
    assert float(out["mu_rel"].sel(spacing=100e-6, height=5e-6)) == pytest.approx(0.9, rel=1e-12)
    # without --at: 1 N, inside the range
    assert map_data(store_like(), "spacing", "height").attrs["at"] == 1.0


@pytest.mark.parametrize("kwargs, message", [
    (dict(x="radius", y="height"), r"--x 'radius': not an axis of this sweep \(axes: spacing, height\)"),
    (dict(x="height", y="height"), "two different axes"),
    (dict(x="spacing", y="height", at=5.0), r"--at 5 N is outside the sweep's exploration loads 0.1-1.6 N"),
    (dict(x="spacing", y="height", quantity="psi"), r"--quantity 'psi': one of"),
    (dict(x="spacing", y="height", quantity="mu"), r"does not hold it"),
    (dict(x="spacing", y="height", select={"spacing": "1um"}), r"--select spacing: not a further axis"),
])
def test_map_refusals(kwargs, message):
    with pytest.raises(FingerpadError, match=message):
        map_data(store_like(), **kwargs)
