"""MATLAB ``.mat`` files (v4/v5 with scipy.io, v7.3 HDF5 with h5py).

Two layouts are read:

* one numeric vector per channel (``time``, ``Fn``, ``Ft``, ``x`` ... all of one length), at the
  top level or as the fields of a single struct; an optional ``units`` struct (or a cell array
  ``units`` beside a cell array of names) gives their units;
* one numeric matrix (one channel per column, or per row when that is the short side) with the
  channel names in a cell array or char matrix called ``header``, ``names``, ``columns``,
  ``channels`` or ``labels`` (names may carry units, ``"Fn [mN]"``).

Rows in messages are sample numbers (1-based).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ...errors import FingerpadError
from . import Importer, RawTable

if TYPE_CHECKING:
    from ..columns import ColumnSpec

NAME_KEYS = ("header", "names", "columns", "channels", "labels")


def _strings(value: Any) -> list[str] | None:
    """A cell array / char matrix / list of names as Python strings, else None."""
    if isinstance(value, str):
        return [value]
    arr = np.asarray(value, dtype=object) if not isinstance(value, np.ndarray) else value
    if arr.dtype.kind in "US":
        return [str(s).strip() for s in np.atleast_1d(arr).ravel()]
    if arr.dtype == object:
        flat = [v for v in np.atleast_1d(arr).ravel()]
        if all(isinstance(v, str) or (isinstance(v, np.ndarray) and v.dtype.kind in "US") for v in flat):
            return [str(v if isinstance(v, str) else (v.item() if v.size == 1 else "")).strip() for v in flat]
    return None


def _numeric(value: Any) -> np.ndarray | None:
    if isinstance(value, np.ndarray) and value.dtype.kind in "fiub" and value.size:
        return np.asarray(value, dtype=float)
    return None


def _from_variables(path: Path, variables: dict[str, Any]) -> RawTable:
    # a single struct: its fields are the variables
    if len(variables) == 1:
        only = next(iter(variables.values()))
        if isinstance(only, dict):
            variables = only
    units_var = variables.get("units")
    names = None
    for key in NAME_KEYS:
        if key in variables:
            names = _strings(variables[key])
            if names:
                break
    matrices = {k: v for k, v in variables.items() if (a := _numeric(v)) is not None and a.ndim == 2
                and min(a.shape) > 1}
    if names and matrices:
        key = next(iter(matrices))
        mat = np.asarray(matrices[key], dtype=float)
        if mat.shape[1] != len(names) and mat.shape[0] == len(names):
            mat = mat.T
        if mat.shape[1] != len(names):
            raise FingerpadError(f"{path}: variable {key!r} has {mat.shape[1]} columns but {len(names)} names")
        units = _strings(units_var) if units_var is not None else None
        if units is not None and len(units) != len(names):
            units = None
        return RawTable(header=names, columns=[mat[:, j] for j in range(mat.shape[1])],
                        rows=np.arange(1, mat.shape[0] + 1), units=units or [], row_word="sample")
    vectors = {}
    for k, v in variables.items():
        a = _numeric(v)
        if a is not None and (a.ndim == 1 or (a.ndim == 2 and min(a.shape) == 1)) and a.size > 1:
            vectors[k] = a.ravel()
    if not vectors:
        raise FingerpadError(f"{path}: no channel vectors and no matrix with a {'/'.join(NAME_KEYS)} variable "
                             f"(variables: {', '.join(variables) or 'none'})")
    lengths = {k: v.size for k, v in vectors.items()}
    n = max(set(lengths.values()), key=list(lengths.values()).count)
    odd = sorted(k for k, size in lengths.items() if size != n)
    kept = {k: v for k, v in vectors.items() if v.size == n}
    units = []
    for k in kept:
        u = ""
        if isinstance(units_var, dict) and k in units_var:
            u = (_strings(units_var[k]) or [""])[0]
        units.append(u)
    table = RawTable(header=list(kept), columns=list(kept.values()), rows=np.arange(1, n + 1), units=units,
                     row_word="sample")
    table.ignored = odd  # type: ignore[attr-defined]  # vectors of another length (metadata)
    return table


def _load_v73(path: Path) -> dict[str, Any]:
    import h5py

    out: dict[str, Any] = {}
    with h5py.File(path, "r") as fh:
        for key, item in fh.items():
            if key.startswith("#"):
                continue
            if isinstance(item, h5py.Dataset) and item.dtype.kind in "fiu":
                out[key] = np.asarray(item[()], dtype=float).T  # MATLAB stores column-major
            elif isinstance(item, h5py.Group):
                fields = {k: np.asarray(v[()], dtype=float).T for k, v in item.items()
                          if isinstance(v, h5py.Dataset) and v.dtype.kind in "fiu"}
                if fields:
                    out[key] = fields
    return out


def read_mat_table(path: Path, spec: "ColumnSpec") -> RawTable:
    from scipy import io as sio

    try:
        variables = sio.loadmat(str(path), squeeze_me=True, simplify_cells=True)
    except FileNotFoundError:
        raise FingerpadError(f"{path}: file not found") from None
    except NotImplementedError:  # v7.3: an HDF5 file
        try:
            variables = _load_v73(path)
        except Exception as exc:  # h5py raises OSError/KeyError/... for a bad file
            raise FingerpadError(f"{path}: cannot read as a MATLAB v7.3 file ({type(exc).__name__}: {exc})") from None
    except Exception as exc:  # scipy raises ValueError, TypeError, MatReadError... for a bad file
        raise FingerpadError(f"{path}: cannot read as a MATLAB file ({type(exc).__name__}: {exc})") from None
    variables = {k: v for k, v in variables.items() if not k.startswith("__")}
    if spec.sheet is not None:  # a named struct holds the channels
        if spec.sheet not in variables:
            raise FingerpadError(f"{path}: no variable {spec.sheet!r} (variables: {', '.join(variables)})")
        variables = {spec.sheet: variables[spec.sheet]}
    return _from_variables(path, variables)


IMPORTER = Importer(name="matlab", suffixes=(".mat",), read_table=read_mat_table)
