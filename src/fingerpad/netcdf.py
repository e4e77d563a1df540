"""NetCDF files of solved cells (xarray + h5netcdf), written atomically.

Layout of a saved unit-cell solution (all SI, every variable carries a ``units`` attribute):

* coordinates ``x`` (nx,) and ``y`` (ny,): pixel positions in m;
* fields ``pressure`` (Pa), ``gap`` (m), ``displacement`` (m), ``contact`` (1 = in contact,
  ``pressure > 0``) on ``(x, y)`` -- with a leading ``mean_pressure`` dimension (Pa) when several
  loads are saved together (:func:`save_results`, :func:`save_load_curve`);
* ``heights`` (m) on ``(x, y)``: the texture, never stacked;
* scalar results ``mean_pressure``, ``approach``, ``contact_fraction``, ``real_contact_area``,
  ``max_pressure``, ``mean_gap``, ``iterations``, ``residual``, ``converged`` (0/1), ``seconds``,
  ``contact_state`` (0-d, or 1-D along ``mean_pressure``);
* ``formulation`` (string, per result): the solver formulation used (primal or dual);
* global attributes: every input (``texture_name``, ``texture_<param>``, ``texture_size_x/_y``,
  ``texture_nx/_ny``, ``texture_periodic``, ``modulus``, ``tol``) and whatever the caller passes in
  ``attrs`` (see :func:`fingerpad.encode.flatten_attrs` for how values become attributes).
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ._version import __version__
from .errors import FingerpadError
from .encode import flatten_attrs
from .io import atomic_write

ENGINE = "h5netcdf"

#: Scalar results of a ContactResult: name -> (units, long name).
SCALARS: dict[str, tuple[str, str]] = {
    "mean_pressure": ("Pa", "mean (nominal) pressure over the unit cell"),
    "approach": ("m", "rigid-body approach of the skin"),
    "contact_fraction": ("1", "real-to-nominal contact area ratio psi"),
    "real_contact_area": ("m2", "real contact area in the whole cell"),
    "max_pressure": ("Pa", "largest local contact pressure"),
    "mean_gap": ("m", "mean gap between skin and texture"),
    "iterations": ("1", "solver iterations"),
    "residual": ("1", "final relative residual"),
    "converged": ("1", "1 if the solver reached its tolerance"),
    "seconds": ("s", "wall-clock solve time"),
}

#: Fields of a ContactResult: name -> (units, long name).
FIELDS: dict[str, tuple[str, str]] = {
    "pressure": ("Pa", "local contact pressure"),
    "gap": ("m", "gap between deformed skin and texture"),
    "displacement": ("m", "normal surface displacement of the skin"),
}

__all__ = ["load_curve_dataset", "load_dataset", "load_writer_modules", "result_dataset", "results_dataset",
           "save_load_curve", "save_result", "save_results", "to_netcdf"]


def _input_attrs(result: Any) -> dict[str, Any]:
    texture = result.texture
    attrs: dict[str, Any] = {
        "texture_name": getattr(texture, "name", "custom"),
        "texture_size_x": float(texture.size[0]),
        "texture_size_y": float(texture.size[1]),
        "texture_nx": int(texture.shape[0]),
        "texture_ny": int(texture.shape[1]),
        "texture_periodic": bool(texture.periodic),
        "modulus": float(result.modulus),
        "tol": float(result.tol),
    }
    for key, value in dict(getattr(texture, "params", {}) or {}).items():
        if isinstance(value, Mapping):
            attrs.update(flatten_attrs(value, f"texture_{key}"))
        else:
            attrs[f"texture_{key}"] = value
    return attrs


def _global_attrs(result: Any, attrs: Mapping[str, Any] | None, title: str) -> dict[str, Any]:
    merged = {
        "title": title,
        "Conventions": "CF-1.8",
        "source": f"fingerpad {__version__}",
        "units_system": "SI",
    }
    merged.update(flatten_attrs(_input_attrs(result)))
    merged.update(flatten_attrs(attrs))
    return merged



def _coords(texture: Any) -> dict[str, Any]:
    import xarray as xr

    x, y = texture.coordinates()
    return {
        "x": xr.Variable("x", np.asarray(x, float), {"units": "m", "long_name": "x position of pixel"}),
        "y": xr.Variable("y", np.asarray(y, float), {"units": "m", "long_name": "y position of pixel"}),
    }


#: The contact mask's description: without adhesion (pressure > 0) and with (closed gap).
_CONTACT_NAME = {False: "contact mask (1 where pressure > 0)",
                 True: "contact mask (1 where the gap is closed; adhesion: a contact may carry tension)"}


def _contact(result: Any) -> np.ndarray:
    """The contact mask: ``pressure > 0``, or with adhesion the closed gaps."""
    if getattr(result, "adhesion", None) is not None:
        return np.asarray(result.gap) <= 0
    return np.asarray(result.pressure) > 0


def _check_result(result: Any) -> None:
    missing = [n for n in ("pressure", "gap", "displacement", "texture", "modulus", "tol") if not hasattr(result, n)]
    if missing:
        raise FingerpadError(f"not a contact result (missing {', '.join(missing)})")


def result_dataset(result: Any, attrs: Mapping[str, Any] | None = None):
    """The :class:`xarray.Dataset` of one contact result (see the module docstring)."""
    import xarray as xr

    _check_result(result)
    dims = ("x", "y")
    data: dict[str, Any] = {}
    for name, (units, long_name) in FIELDS.items():
        data[name] = xr.Variable(dims, np.asarray(getattr(result, name), float), {"units": units, "long_name": long_name})
    data["contact"] = xr.Variable(dims, _contact(result).astype(np.int8), {"units": "1", "long_name": _CONTACT_NAME[
        getattr(result, "adhesion", None) is not None]})
    data["heights"] = xr.Variable(
        dims, np.asarray(result.texture.heights, float), {"units": "m", "long_name": "texture height (toward the skin)"}
    )
    for name, (units, long_name) in SCALARS.items():
        value = getattr(result, name, np.nan)
        if name == "converged":
            value = np.int8(bool(value))
        elif name == "iterations":
            value = np.int64(value)
        else:
            value = float(value)
        data[name] = xr.Variable((), value, {"units": units, "long_name": long_name})
    data["contact_state"] = xr.Variable(
        (), str(getattr(result, "contact_state", "")), {"units": "1", "long_name": "contact state: asperity, transition or full"}
    )
    data["formulation"] = xr.Variable(
        (), str(getattr(result, "formulation", "")), {"units": "1", "long_name": "solver formulation used (primal or dual)"}
    )
    return xr.Dataset(data, coords=_coords(result.texture), attrs=_global_attrs(result, attrs, "fingerpad unit-cell contact solution"))


def results_dataset(results: Sequence[Any], attrs: Mapping[str, Any] | None = None):
    """Several results on the same texture, stacked along a ``mean_pressure`` dimension."""
    import xarray as xr

    results = list(results)
    if not results:
        raise FingerpadError("no results to save")
    for r in results:
        _check_result(r)
    first = results[0]
    shape = first.texture.shape
    for r in results[1:]:
        if r.texture.shape != shape or r.texture.size != first.texture.size:
            raise FingerpadError("results to save together must share one texture (same grid and size)")
    dims = ("mean_pressure", "x", "y")
    mp = np.array([float(r.mean_pressure) for r in results])
    data: dict[str, Any] = {}
    for name, (units, long_name) in FIELDS.items():
        stack = np.stack([np.asarray(getattr(r, name), float) for r in results])
        data[name] = xr.Variable(dims, stack, {"units": units, "long_name": long_name})
    data["contact"] = xr.Variable(
        dims,
        np.stack([_contact(r) for r in results]).astype(np.int8),
        {"units": "1", "long_name": _CONTACT_NAME[getattr(results[0], "adhesion", None) is not None]},
    )
    data["heights"] = xr.Variable(
        ("x", "y"), np.asarray(first.texture.heights, float), {"units": "m", "long_name": "texture height (toward the skin)"}
    )
    for name, (units, long_name) in SCALARS.items():
        if name == "mean_pressure":
            continue
        values = [getattr(r, name, np.nan) for r in results]
        if name == "converged":
            arr = np.array([bool(v) for v in values], dtype=np.int8)
        elif name == "iterations":
            arr = np.array(values, dtype=np.int64)
        else:
            arr = np.array(values, dtype=float)
        data[name] = xr.Variable(("mean_pressure",), arr, {"units": units, "long_name": long_name})
    data["contact_state"] = xr.Variable(
        ("mean_pressure",),
        np.array([str(getattr(r, "contact_state", "")) for r in results], dtype=object),
        {"units": "1", "long_name": "contact state: asperity, transition or full"},
    )
    data["formulation"] = xr.Variable(
        ("mean_pressure",),
        np.array([str(getattr(r, "formulation", "")) for r in results], dtype=object),
        {"units": "1", "long_name": "solver formulation used (primal or dual)"},
    )
    coords = _coords(first.texture)
    coords["mean_pressure"] = xr.Variable(
        "mean_pressure", mp, {"units": "Pa", "long_name": SCALARS["mean_pressure"][1]}
    )
    return xr.Dataset(data, coords=coords, attrs=_global_attrs(first, attrs, "fingerpad unit-cell load curve"))


def load_writer_modules() -> None:
    """Import now what the first :func:`to_netcdf` imports: xarray, the h5netcdf engine with h5py,
    xarray's list of engines, and Dask's array and distributed modules (xarray asks Dask which
    scheduler runs before it writes, wherever Dask is installed: ~0.2 s of importing
    ``distributed`` for a file of NumPy arrays). For a caller that has the time now and not
    later (``predict --direction`` on a core the deflection ramps left free, issue 23)."""
    import importlib
    import importlib.util

    from xarray.backends import list_engines

    list_engines()
    for name in (ENGINE, f"{ENGINE}.legacyapi", "h5py._hl.dims", "dask.array", "dask.distributed"):
        if importlib.util.find_spec(name.split(".")[0]) is not None:  # Dask is optional for a file
            importlib.import_module(name)


def to_netcdf(ds: Any, path: str | os.PathLike[str]) -> Path:
    """Write a dataset of this module to NetCDF (atomically; object variables as strings, fields gzipped)."""
    encoding: dict[str, dict[str, Any]] = {}
    for name, var in ds.variables.items():
        if var.dtype == object:
            encoding[name] = {"dtype": str}
        elif var.ndim >= 2:
            # Contact fields are mostly zeros or smooth: gzip shrinks them several times.
            encoding[name] = {"zlib": True, "complevel": 4}
    return atomic_write(path, lambda tmp: ds.to_netcdf(tmp, engine=ENGINE, encoding=encoding or None))


def save_result(result: Any, path: str | os.PathLike[str], attrs: Mapping[str, Any] | None = None) -> Path:
    """Write one :class:`~fingerpad.contact.ContactResult` to NetCDF (atomically).

    ``attrs`` (any JSON-like mapping) is added to the global attributes after conversion.
    """
    return to_netcdf(result_dataset(result, attrs), path)


def save_results(results: Sequence[Any], path: str | os.PathLike[str], attrs: Mapping[str, Any] | None = None) -> Path:
    """Write several results on one texture, stacked along ``mean_pressure`` (atomically)."""
    return to_netcdf(results_dataset(results, attrs), path)


def load_curve_dataset(curve: Any, attrs: Mapping[str, Any] | None = None):
    """Dataset of a :class:`~fingerpad.micro.loadcurve.LoadCurve` (fields stacked by mean pressure)."""
    import xarray as xr

    results = list(getattr(curve, "results", None) or [])
    if results:
        return results_dataset(results, attrs)
    # A curve without kept fields: scalar arrays only.
    mp = np.asarray(curve.mean_pressure, float)
    if mp.size == 0:
        raise FingerpadError("empty load curve: nothing to save")
    data = {}
    for name in ("contact_fraction", "mean_gap", "max_pressure", "iterations", "converged", "seconds"):
        units, long_name = SCALARS[name]
        arr = np.asarray(getattr(curve, name))
        if name == "converged":
            arr = arr.astype(bool).astype(np.int8)
        data[name] = xr.Variable(("mean_pressure",), arr, {"units": units, "long_name": long_name})
    data["contact_state"] = xr.Variable(
        ("mean_pressure",), np.array([str(s) for s in curve.contact_state], dtype=object),
        {"units": "1", "long_name": "contact state: asperity, transition or full"},
    )
    coords = {"mean_pressure": xr.Variable("mean_pressure", mp, {"units": "Pa", "long_name": SCALARS["mean_pressure"][1]})}
    g = {"title": "fingerpad unit-cell load curve", "Conventions": "CF-1.8", "source": f"fingerpad {__version__}"}
    g.update(flatten_attrs(attrs))
    return xr.Dataset(data, coords=coords, attrs=g)


def save_load_curve(curve: Any, path: str | os.PathLike[str], attrs: Mapping[str, Any] | None = None) -> Path:
    """Write a :class:`~fingerpad.micro.loadcurve.LoadCurve` to NetCDF (atomically)."""
    return to_netcdf(load_curve_dataset(curve, attrs), path)


def load_dataset(path: str | os.PathLike[str]):
    """Read a file written by this module fully into memory (the file is closed on return)."""
    import xarray as xr

    p = Path(path)
    if not p.is_file():
        raise FingerpadError(f"cannot read {str(p)!r}: no such file")
    try:
        return xr.load_dataset(p, engine=ENGINE)
    except OSError as exc:
        raise FingerpadError(f"cannot read {str(p)!r} as NetCDF: {exc}") from exc
