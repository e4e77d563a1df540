"""The outputs of a prediction: ``predict.json``, ``predict.nc`` and the figures, all or none."""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .. import references
from .._version import __version__
from ..coupling import CurvePrediction
from ..errors import FingerpadError
from ..finger import skin_units
from .citations import prediction_references
from .run import Prediction

__all__ = ["OUTPUT_FILES", "OUTPUT_UNITS", "load_output_modules", "prediction_dataset", "prediction_json",
           "write_outputs"]

#: What the contact states mean (written into predict.json).
STATE_DEFINITIONS = {
    "transition": "lowest mean cell pressure at which the skin touches the texture's base level "
                  "(generated textures: their lowest level; measured maps: the base_quantile height plus 4 "
                  "noise standard deviations)",
    "full": "lowest mean cell pressure at which at most 1 % of the cell is out of contact",
    "critical_load": "load at which the pad-centre pressure 1.5 F/A_fr reaches the transition pressure",
    "full_contact_load": "load at which the pad-centre pressure reaches the full-contact pressure",
}

#: Files an output folder of a prediction may hold (``run-default`` adds the ridge-model figure):
#: a folder holding only these is replaced as a whole by the next prediction.
FOLDER_FILES = ("predict.json", "predict.nc", "areas.png", "friction.png", "zones.png", "ridge_models.png")
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
    "direction": "deg from the texture's x axis", "mu_perpendicular_over_parallel": "1",
}


#: Units of the adhesion's outputs (only in the outputs of an adhesive prediction).
ADHESION_UNITS = {
    "work_of_adhesion": "J/m^2", "pad_work_of_adhesion": "J/m^2", "work_of_separation": "J/m^2 (of nominal area)",
    "adhesion_range": "m", "adhesion_range_used": "m", "pull_off_force": "N", "pull_off_pressure": "Pa",
    "threshold_load": "N", "reference_load": "N", "real_area_without_adhesion": "m^2",
    "adhesive_share": "1 (1 - A_re without adhesion / A_re)", "zero_load_contact_fraction": "1",
    "pull_off_force_error": "1 (relative error estimate)",
}


def prediction_json(pred: Prediction, population: Any = None) -> dict[str, Any]:
    """The content of ``predict.json`` (SI units, listed in its ``units``; NaN and inf -> ``None``).

    * ``critical_load``: ``{"bem": F, "hertz": F}`` (N, ``None`` for a model not run);
      ``full_contact_load``: ``{"bem": F}``, load at which the pad centre reaches full contact;
      ``critical_load_error``, ``full_contact_load_error``: ``{"bem": e}``, the relative error
      estimate of each (its state pressure's grid convergence, ``state_brackets``);
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
    * ``references``: the publications of the methods this run used (key, citation, DOI, what
      for; :mod:`fingerpad.references`), those of ``population`` (the population result this
      prediction is the nominal of) included;
    * ``results``: one entry per load with ``load``, ``gross_area``, ``ridge_area``,
      ``real_area``, ``area_ratio``, ``ridge_radius``, ``transition_radius``,
      ``full_contact_radius``, ``mu``, ``mu_ref``, ``mu_normalised``, ``contact_state`` (at the
      pad centre) and, for model ``both`` on caps, ``hertz``: ``real_area``, ``area_ratio``,
      ``transition_radius``, ``mu``, ``mu_normalised``, ``contact_state``.
    """
    from ..encode import to_jsonable
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
        if pred.adhesion is not None and "adhesive_share" in pred.adhesion:
            # the real area without adhesion (the finger's own pad on the non-adhesive cell) and
            # the share of A_re that adhesion adds
            row["real_area_without_adhesion"] = pred.adhesion["real_area_without_adhesion"][i]
            row["adhesive_share"] = pred.adhesion["adhesive_share"][i]
        if pred.directional is not None:
            d = pred.directional
            row["mu_parallel"] = d["mu_parallel"][i]
            row["mu_perpendicular"] = d["mu_perpendicular"][i]
            row["mu_perpendicular_over_parallel"] = d["mu_perpendicular_over_parallel"][i]
            row["gain_held"] = bool(d["gain_held_parallel"][i] or d["gain_held_perpendicular"][i])
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
        "accuracy": study.accuracy,
        "direction": study.direction,
        "tol": study.tol,
        "max_iter": study.max_iter,
        "cache": None if study.cache in (None, False, True) else os.fspath(study.cache),
        "zones_at": study.zone_load,
        "fingerpad_version": __version__,
    }
    errors = {state: (pred.state_brackets.get(state) or {}).get("load_error") for state in ("transition", "full")}
    payload = {
        "critical_load": dict(pred.critical_load),
        # beside each state load, its estimated error (relative; the state's own grid convergence)
        "critical_load_error": {"bem": errors["transition"]} if pred.cell is not None else {},
        "full_contact_load": dict(pred.full_contact_load),
        "full_contact_load_error": {"bem": errors["full"]} if pred.cell is not None else {},
        "state_brackets": pred.state_brackets,
        "directional": None if pred.directional is None else {
            k: v for k, v in pred.directional.items() if not k.startswith(("mu_", "area_ratio_"))},
        "model": pred.primary_model,
        # with adhesion: its block (the per-load arrays are in the results' rows)
        **({} if pred.adhesion is None else {"adhesion": {k: v for k, v in pred.adhesion.items()
                                                          if k not in ("real_area_without_adhesion", "adhesive_share")}}),
        # a layered skin's fields (inputs.finger) with their units; a half-space's units as before
        "units": {**OUTPUT_UNITS, **({} if study.finger.layer is None else skin_units()),
                  **({} if pred.adhesion is None else ADHESION_UNITS)},
        "inputs": inputs,
        "cell": cell,
        "hertz_cell": hertz_cell,
        "zones": pred.zones,
        "timings": {"cell": pred.timings["cell"], "coupling": pred.timings["coupling"]},
        "notes": list(pred.notes),
        "references": references.metadata(prediction_references(pred, population)),
        "results": results,
    }
    return to_jsonable(payload)


def prediction_dataset(pred: Prediction, population: Any = None):
    """The :class:`xarray.Dataset` of ``predict.nc``: curves along ``load``, psi(p) along
    ``cell_pressure``; every variable has a ``units`` attribute, inputs are global attributes,
    the publications of the methods used the CF ``references`` attribute (``population``'s
    included)."""
    import xarray as xr

    from ..encode import flatten_attrs

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
    if pred.adhesion is not None and "adhesive_share" in pred.adhesion:
        data["real_area_without_adhesion"] = xr.Variable(
            ("load",), np.asarray(pred.adhesion["real_area_without_adhesion"], float),
            {"units": "m^2", "long_name": "real contact area without adhesion (the same finger's own pad, non-adhesive cell)"})
        data["adhesive_share"] = xr.Variable(("load",), np.asarray(pred.adhesion["adhesive_share"], float),
                                             {"units": "1", "long_name": "share of A_re that adhesion adds"})
    if pred.directional is not None:
        d = pred.directional
        for name, long_name in (("mu_parallel", "friction coefficient sliding along the asperities' long axis"),
                                ("mu_perpendicular", "friction coefficient sliding across the long axis"),
                                ("mu_perpendicular_over_parallel", "mu_perpendicular / mu_parallel")):
            data[name] = xr.Variable(("load",), np.asarray(d[name], float), {"units": "1", "long_name": long_name})
        data["gain_held"] = xr.Variable(("load",), np.asarray(d["gain_held_parallel"], np.int8)
                                        | np.asarray(d["gain_held_perpendicular"], np.int8),
                                        {"units": "1", "long_name": "1: deflection gain held past the shear its ramps reached"})
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
             "source": f"fingerpad {__version__}", "units_system": "SI",
             "references": references.netcdf_attribute(prediction_references(pred, population))}
    attrs.update(flatten_attrs({
        "model": payload["model"],
        "critical_load": payload["critical_load"], "full_contact_load": payload["full_contact_load"],
        "critical_load_error": payload["critical_load_error"],
        "full_contact_load_error": payload["full_contact_load_error"],
        "state_brackets": payload["state_brackets"],
        "cell": {k: v for k, v in payload["cell"].items()},
        "inputs": {k: v for k, v in payload["inputs"].items() if k != "loads"},
        "notes": payload["notes"],
        **({} if pred.study.finger.layer is None else {"units": skin_units()}),
        **({} if "adhesion" not in payload else {"adhesion": payload["adhesion"]}),
    }))
    return xr.Dataset(data, coords=coords, attrs=attrs)


# ---------------------------------------------------------------------------------------------
# figures (matplotlib Figure + Agg canvas; fixed margins: a layout engine costs seconds)


#: Suffixes of the files a user names.
JSON_SUFFIXES, CSV_SUFFIXES, NETCDF_SUFFIXES, IMAGE_SUFFIXES = (".json",), (".csv",), (".nc",), (".png", ".svg", ".pdf")
#: Columns of the CSV table of a prediction: (key, header with unit).
CSV_COLUMNS = (
    ("load", "load_N"), ("gross_area", "gross_area_m2"), ("ridge_area", "ridge_area_m2"),
    ("real_area", "real_area_m2"), ("area_ratio", "area_ratio_Are_over_Afr"), ("ridge_radius", "ridge_radius_m"),
    ("transition_radius", "transition_radius_m"), ("full_contact_radius", "full_contact_radius_m"),
    ("mu", "mu"), ("mu_ref", "mu_ref"), ("mu_normalised", "mu_over_mu_ref"), ("contact_state", "centre_state"),
)


def check_outputs(out_dir: str | os.PathLike[str] | None, json_path: str | None = None, csv_path: str | None = None,
                  names: Sequence[str] = FOLDER_FILES) -> None:
    """The checks :func:`write_outputs` makes, run before any solving so that a bad path costs
    nothing: the folder may be replaced as a whole, the files can be written, their names end in
    the suffix of their format and do not collide."""
    from .. import io as fio

    if out_dir is not None:
        fio.OutputFolder.check(out_dir, names)
    targets = {}
    for option, path, suffixes in (("--json", json_path, JSON_SUFFIXES), ("--csv", csv_path, CSV_SUFFIXES)):
        if path is None or (option == "--json" and path == "-"):  # (--json - is stdout; a CSV is a file)
            continue
        fio.check_writable(path, option, suffixes)
        key = os.path.abspath(path)
        if out_dir is not None and Path(os.path.realpath(key)).parent == Path(os.path.realpath(out_dir)):
            raise FingerpadError(f"{option} {path!r} lies inside --out {os.fspath(out_dir)!r}, which is replaced as a whole")
        if key in targets:
            raise FingerpadError(f"{option} and {targets[key]} name the same file {path!r}")
        targets[key] = option


def prediction_rows(pred: Prediction) -> list[dict[str, Any]]:
    """One row per load: the quantities of :data:`CSV_COLUMNS` (SI units)."""
    payload = prediction_json(pred)
    return [{header: row.get(key) for key, header in CSV_COLUMNS} for row in payload["results"]]


def load_output_modules() -> None:
    """Import now what :func:`write_outputs` imports on its first call into a folder (matplotlib,
    Pillow, xarray, the NetCDF engine, Dask's modules that xarray consults): ~0.7 s on the 2-core
    machine. ``predict --direction`` calls it where its deflection ramps leave a core free, so
    that the outputs are written without it after the ramps (issue 23)."""
    from .. import netcdf
    from ..plotting import prediction  # noqa: F401 - the figures' own modules
    from ..plotting.render import load_drawing_modules

    load_drawing_modules()
    netcdf.load_writer_modules()


def write_outputs(
    pred: Prediction,
    out_dir: str | os.PathLike[str] | None,
    *,
    json_path: str | None = None,
    csv_path: str | None = None,
    extra: dict[str, Any] | None = None,
    dpi: int = 110,
    sections: Mapping[str, Any] | None = None,
    dataset: Callable[[Any], Any] | None = None,
    cited: Any = None,
) -> list[Path]:
    """Write the outputs of a prediction, all of them or none.

    Parameters
    ----------
    out_dir
        Folder of :data:`OUTPUT_FILES` (and ``extra``), replaced as a whole (see
        :class:`fingerpad.io.OutputFolder`); ``None`` for none.
    json_path, csv_path
        Further files: ``predict.json``'s content and the per-load table (``None``: none; the
        JSON path ``"-"`` is stdout, written by the caller).
    extra
        More figures for the folder: file name -> ``Figure``, or -> ``str`` for a text file.
    sections
        More top-level entries of the JSON (already JSON-ready), e.g. a population's
        (:func:`fingerpad.population.outputs.write_population_outputs`).
    dataset
        Applied to ``predict.nc``'s dataset before it is written (a population adds its
        ``member`` dimension).
    cited
        A further result whose publications are listed with the prediction's (an object with
        ``references()``, e.g. a population's, :func:`.citations.prediction_references`).

    Returns
    -------
    list of Path
        The files written.
    """
    import csv

    from .. import io as fio
    from .. import netcdf
    from ..plotting.prediction import figure_areas, figure_friction, figure_zones

    names = [*OUTPUT_FILES, *(extra or {})]
    replaceable = sorted({*FOLDER_FILES, *names})
    check_outputs(out_dir, json_path, csv_path, replaceable)
    from ..encode import json_text

    doc = prediction_json(pred, cited)
    doc.update(sections or {})
    text = json_text(doc)  # members one per line: the pure-Python indenting of 1000 of them was slow
    staging = fio.Staging()
    folder = fio.OutputFolder(out_dir, replaceable) if out_dir is not None else None
    written: list[Path] = []
    try:
        if json_path is not None and json_path != "-":
            staging.stage(json_path, lambda tmp: fio.write_text(tmp, text))
            written.append(Path(json_path))
        if csv_path is not None:
            rows = prediction_rows(pred)

            def write_csv(tmp: Path) -> None:
                with open(tmp, "w", newline="", encoding="utf-8") as fh:
                    writer = csv.DictWriter(fh, fieldnames=[h for _, h in CSV_COLUMNS])
                    writer.writeheader()
                    writer.writerows(rows)

            staging.stage(csv_path, write_csv)
            written.append(Path(csv_path))
        if folder is not None:
            folder.write(OUTPUT_FILES[0], lambda tmp: fio.write_text(tmp, text))
            folder.write(OUTPUT_FILES[1], lambda tmp: netcdf.to_netcdf(
                prediction_dataset(pred, cited) if dataset is None else dataset(prediction_dataset(pred, cited)),
                tmp))
            figures = dict(zip(OUTPUT_FILES[2:], (figure_areas(pred), figure_friction(pred), figure_zones(pred)),
                               strict=True))
            figures.update(extra or {})
            for name, fig in figures.items():  # a str is a text file's content (e.g. a CSV table)
                folder.write(name, lambda tmp, fig=fig: fio.write_text(tmp, fig) if isinstance(fig, str)
                             else fig.savefig(tmp, format="png", dpi=dpi))
            written += [folder.final_path(name) for name in names]
        staging.commit()
        if folder is not None:
            folder.commit()
    finally:
        staging.discard()
        if folder is not None:
            folder.discard()
    return written
