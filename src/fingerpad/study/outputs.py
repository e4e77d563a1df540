"""The outputs of a prediction: ``predict.json``, ``predict.nc`` and the figures, all or none."""

from __future__ import annotations

import contextlib
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._version import __version__
from ..coupling import CurvePrediction
from ..errors import FingerpadError
from .run import Prediction

__all__ = ["OUTPUT_FILES", "OUTPUT_UNITS", "prediction_dataset", "prediction_json", "write_outputs"]

#: What the contact states mean (written into predict.json).
STATE_DEFINITIONS = {
    "transition": "lowest mean cell pressure at which the skin touches the texture's base level "
                  "(generated textures: their lowest level; measured maps: the base_quantile height)",
    "full": "lowest mean cell pressure at which at most 1 % of the cell is out of contact",
    "critical_load": "load at which the pad-centre pressure 1.5 F/A_fr reaches the transition pressure",
    "full_contact_load": "load at which the pad-centre pressure reaches the full-contact pressure",
}

#: Files written by :func:`write_outputs`, in order.
OUTPUT_FILES = ("predict.json", "predict.nc", "areas.png", "friction.png", "zones.png")

# =============================================================================================

#: Units of the quantities in predict.json / predict.nc.
OUTPUT_UNITS = {
    "load": "N", "critical_load": "N", "full_contact_load": "N",
    "gross_area": "m^2", "ridge_area": "m^2", "real_area": "m^2", "area_ratio": "1 (A_re / A_fr)",
    "ridge_radius": "m", "transition_radius": "m", "full_contact_radius": "m",
    "mu": "1", "mu_ref": "1", "mu_normalised": "1 (mu / mu_ref)",
    "transition_pressure": "Pa", "full_contact_pressure": "Pa", "pressure": "Pa", "modulus": "Pa",
    "interpolation_error": "1 (absolute error of psi)", "seconds": "s",
    "contact_state": "state at the pad centre: asperity, transition or full",
}


def prediction_json(pred: Prediction) -> dict[str, Any]:
    """The content of ``predict.json`` (SI units, listed in its ``units``; NaN and inf -> ``None``).

    * ``critical_load``: ``{"bem": F, "hertz": F}`` (N, ``None`` for a model not run);
      ``full_contact_load``: ``{"bem": F}``, load at which the pad centre reaches full contact;
    * ``model``: the model of ``results`` (``bem`` when run, else ``hertz``);
    * ``inputs``: texture (name, description, params, size, grid, periodic, source file),
      material, finger, E1* (``reduced_modulus``), loads, model, numerics, cache, zones_at;
    * ``cell``: the unit cell of ``results``: ``transition_pressure``, ``full_contact_pressure``
      (Pa), ``interpolation_error`` (of psi), ``grid``, ``nodes``, ``pressure_range`` (Pa),
      ``solves`` (done now; 0 when cached), ``cached``, ``unconverged``, ``seconds``;
      ``hertz_cell``: radius, height, (effective square) spacing, lattice spacing and lattice,
      critical asperity force (N) and transition pressure (Pa) of the Hertz cell;
    * ``zones``: zone radii (m) and centre state at ``inputs.zones_at``;
    * ``timings``: seconds for the unit cell and for the coupling; ``notes``: remarks;
    * ``results``: one entry per load with ``load``, ``gross_area``, ``ridge_area``,
      ``real_area``, ``area_ratio``, ``ridge_radius``, ``transition_radius``,
      ``full_contact_radius``, ``mu``, ``mu_ref``, ``mu_normalised``, ``contact_state`` (at the
      pad centre) and, for model ``both`` on caps, ``hertz``: ``real_area``, ``area_ratio``,
      ``transition_radius``, ``mu``, ``mu_normalised``, ``contact_state``.
    """
    from ..io import to_jsonable
    from ..textures import describe

    study, tex, cur = pred.study, pred.texture, pred.primary
    states = pred.states()
    hstates = pred.states("hertz") if pred.hertz is not None else None
    results = []
    for i in range(cur.load.size):
        row: dict[str, Any] = {
            "load": cur.load[i],
            "gross_area": cur.gross_area[i],
            "ridge_area": cur.ridge_area[i],
            "real_area": cur.real_area[i],
            "area_ratio": cur.area_ratio[i],
            "ridge_radius": cur.ridge_radius[i],
            "transition_radius": cur.transition_radius[i],
            "full_contact_radius": cur.full_contact_radius[i],
            "mu": cur.mu[i],
            "mu_ref": None if cur.mu_ref is None else cur.mu_ref[i],
            "mu_normalised": None if cur.mu_normalised is None else cur.mu_normalised[i],
            "contact_state": states[i],
        }
        if pred.bem is not None and pred.hertz is not None:
            h = pred.hertz
            row["hertz"] = {
                "real_area": h.real_area[i], "area_ratio": h.area_ratio[i],
                "transition_radius": h.transition_radius[i], "mu": h.mu[i],
                "mu_normalised": None if h.mu_normalised is None else h.mu_normalised[i],
                "contact_state": hstates[i] if hstates else None,
            }
        results.append(row)

    if pred.cell is not None:
        c = pred.cell
        cell = {
            "model": "bem",
            "transition_pressure": c.transition_pressure,
            "full_contact_pressure": c.full_contact_pressure,
            "interpolation_error": None if c.flat else c.interpolation_error,
            "grid": list(tex.shape),
            "transition_pressure_bracket": list(c.transition) if c.transition else None,
            "full_contact_pressure_bracket": list(c.full) if c.full else None,
            "definitions": STATE_DEFINITIONS,
            "nodes": len(c.points),
            "pressure_range": list(pred.pressure_range),
            "solves": pred.resolution["solves"] if pred.resolution else c.solves,
            "cached": (pred.resolution["solves"] if pred.resolution else c.solves) == 0,
            "resolution": pred.resolution,
            "unconverged": pred.unconverged,
            "seconds": pred.timings["cell"],
        }
    else:
        h = pred.hertz_cell
        assert h is not None
        cell = {
            "model": "hertz", "transition_pressure": h.transition_pressure,
            "full_contact_pressure": h.full_contact_pressure, "interpolation_error": None,
            "grid": None, "nodes": 0, "pressure_range": None, "solves": 0, "cached": False,
            "unconverged": 0, "seconds": pred.timings["cell"],
        }
    hertz_cell = None
    if pred.hertz_cell is not None:
        h = pred.hertz_cell
        hertz_cell = {"radius": h.radius, "height": h.height, "spacing": h.spacing,
                      "lattice_spacing": float(tex.params.get("spacing", h.spacing)),
                      "lattice": tex.params.get("lattice", "square"),
                      "critical_asperity_force": h.critical_force,
                      "transition_pressure": h.transition_pressure}
    texture = {
        "name": tex.name, "description": describe(tex), **study.texture_source,
        "params": dict(tex.params), "size": list(tex.size), "grid": list(tex.shape),
        "periodic": bool(tex.periodic),
    }
    inputs = {
        "study_file": study.source,
        "texture": texture,
        "material": {"modulus": study.material_modulus, "poisson": study.material_poisson,
                     "rigid": study.material_modulus is None},
        "finger": study.finger.as_dict(),
        "reduced_modulus": pred.reduced_modulus,
        "loads": list(study.loads),
        "model": study.model,
        "grid": study.grid,
        "tol": study.tol,
        "max_iter": study.max_iter,
        "cache": None if study.cache in (None, False, True) else os.fspath(study.cache),
        "zones_at": study.zone_load,
        "fingerpad_version": __version__,
    }
    payload = {
        "critical_load": dict(pred.critical_load),
        "full_contact_load": dict(pred.full_contact_load),
        "state_brackets": pred.state_brackets,
        "model": pred.primary_model,
        "units": OUTPUT_UNITS,
        "inputs": inputs,
        "cell": cell,
        "hertz_cell": hertz_cell,
        "zones": pred.zones,
        "timings": {"cell": pred.timings["cell"], "coupling": pred.timings["coupling"]},
        "notes": list(pred.notes),
        "results": results,
    }
    return to_jsonable(payload)


def prediction_dataset(pred: Prediction):
    """The :class:`xarray.Dataset` of ``predict.nc``: curves along ``load``, psi(p) along
    ``cell_pressure``; every variable has a ``units`` attribute, inputs are global attributes."""
    import xarray as xr

    from ..io import flatten_attrs

    cur = pred.primary
    long = {
        "gross_area": "gross contact area A_g", "ridge_area": "ridge contact area A_fr",
        "real_area": "real contact area A_re", "area_ratio": "A_re / A_fr",
        "real_pressure": "mean real contact pressure F / A_re", "ridge_radius": "ridge contact radius a_fr",
        "transition_radius": "outer radius of the zone past the transition",
        "full_contact_radius": "outer radius of the full-contact zone",
        "mu": "friction coefficient on the texture", "mu_ref": "friction coefficient on the flat reference",
        "mu_normalised": "mu / mu_ref",
    }
    units = {"real_pressure": "Pa", "area_ratio": "1", "mu_normalised": "1", "mu": "1", "mu_ref": "1"}
    data: dict[str, Any] = {}

    def add(prefix: str, curve: CurvePrediction, names: Sequence[str], label: str) -> None:
        for name in names:
            value = getattr(curve, name)
            if value is None:
                continue
            u = units.get(name, OUTPUT_UNITS.get(name, "1")).split(" ")[0]
            data[prefix + name] = xr.Variable(("load",), np.asarray(value, float),
                                              {"units": u, "long_name": f"{long[name]} ({label})"})

    add("", cur, list(long), pred.primary_model)
    data["contact_state"] = xr.Variable(("load",), np.array(pred.states(), dtype=object),
                                        {"units": "1", "long_name": "contact state at the pad centre"})
    if pred.bem is not None and pred.hertz is not None:
        add("hertz_", pred.hertz, ["real_area", "area_ratio", "transition_radius", "mu", "mu_normalised"], "hertz")
        data["hertz_contact_state"] = xr.Variable(("load",), np.array(pred.states("hertz"), dtype=object),
                                                  {"units": "1", "long_name": "contact state at the pad centre (hertz)"})
    coords = {"load": xr.Variable("load", np.asarray(cur.load, float), {"units": "N", "long_name": "normal load"})}
    if pred.cell is not None and not pred.cell.flat:
        nodes = pred.cell.curve()
        coords["cell_pressure"] = xr.Variable("cell_pressure", nodes["pressure"],
                                              {"units": "Pa", "long_name": "mean nominal pressure on the unit cell"})
        data["cell_contact_fraction"] = xr.Variable(("cell_pressure",), nodes["contact_fraction"],
                                                    {"units": "1", "long_name": "psi: real-to-nominal area fraction of the cell (BEM nodes)"})
        data["cell_mean_gap"] = xr.Variable(("cell_pressure",), nodes["mean_gap"], {"units": "m", "long_name": "mean gap"})
        data["cell_max_pressure"] = xr.Variable(("cell_pressure",), nodes["max_pressure"],
                                                {"units": "Pa", "long_name": "largest local pressure"})
        data["cell_contact_state"] = xr.Variable(("cell_pressure",), np.array([str(s) for s in nodes["contact_state"]], dtype=object),
                                                 {"units": "1", "long_name": "contact state of the cell"})
    elif pred.hertz_cell is not None:
        ps = np.geomspace(*pred.pressure_range, 49)
        coords["cell_pressure"] = xr.Variable("cell_pressure", ps, {"units": "Pa", "long_name": "mean nominal pressure on the unit cell"})
        data["cell_contact_fraction"] = xr.Variable(("cell_pressure",), pred.hertz_cell.contact_fraction(ps),
                                                    {"units": "1", "long_name": "psi of the Hertz cell (analytic, sampled)"})
    payload = prediction_json(pred)
    attrs = {"title": "fingerpad prediction: areas and friction against load", "Conventions": "CF-1.8",
             "source": f"fingerpad {__version__}", "units_system": "SI"}
    attrs.update(flatten_attrs({
        "model": payload["model"],
        "critical_load": payload["critical_load"], "full_contact_load": payload["full_contact_load"],
        "cell": {k: v for k, v in payload["cell"].items()},
        "inputs": {k: v for k, v in payload["inputs"].items() if k != "loads"},
        "notes": payload["notes"],
    }))
    return xr.Dataset(data, coords=coords, attrs=attrs)


# ---------------------------------------------------------------------------------------------
# figures (matplotlib Figure + Agg canvas; fixed margins: a layout engine costs seconds)


def write_outputs(pred: Prediction, out_dir: str | os.PathLike[str], *, dpi: int = 110) -> list[Path]:
    """Write :data:`OUTPUT_FILES` into ``out_dir`` (created if missing): all of them or none.

    Every file is first written under a hidden temporary name in ``out_dir`` and the set is moved
    into place only when all are complete.
    """
    import json

    from .. import io as fio
    from ..plotting.prediction import figure_areas, figure_friction, figure_zones

    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise FingerpadError(f"output {str(out)!r} exists and is not a directory")
    created = not out.exists()
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise FingerpadError(f"cannot create output directory {str(out)!r}: {exc.strerror or exc}") from None
    if not os.access(out, os.W_OK):
        raise FingerpadError(f"output directory {str(out)!r} is not writable")
    staging = fio.Staging()
    paths = [out / name for name in OUTPUT_FILES]
    try:
        text = json.dumps(prediction_json(pred), indent=2) + "\n"
        staging.stage(str(paths[0]), lambda tmp: fio.write_text(tmp, text))
        ds = prediction_dataset(pred)
        staging.stage(str(paths[1]), lambda tmp: fio.to_netcdf(ds, tmp))
        for path, maker in zip(paths[2:], (figure_areas, figure_friction, figure_zones), strict=True):
            fig = maker(pred)
            staging.stage(str(path), lambda tmp, fig=fig: fio.atomic_write(tmp, lambda t: fig.savefig(t, format="png", dpi=dpi)))
        staging.commit()
    except BaseException:
        staging.discard()
        if created:
            with contextlib.suppress(OSError):
                out.rmdir()
        raise
    return paths

