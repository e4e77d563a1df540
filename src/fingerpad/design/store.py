"""The results of a sweep in a Zarr store: laid out once, filled chunk by chunk, resumable.

Layout (docs/sweeps.md): an xarray Dataset with one dimension per axis for a grid design, or a
``point`` dimension otherwise, plus ``load`` (the exploration loads) and ``cell_pressure`` (the
common pressure grid of psi). Every variable has ``units``; every input is a global attribute.

The store is created in full before any point runs (values NaN, ``done`` False). A task owns
whole chunks (along the sweep's dimensions every chunk is ``chunk`` points of the last axis and
one of each other; ``load`` and ``cell_pressure`` are not split), and its results are written
into exactly those chunks, data first and the ``done`` mask last: writing into part of a chunk
from two places loses data, whole chunks never do. After Ctrl-C, ``kill -9`` or a dead worker,
the same command finds the chunks not done and computes only those.
"""

from __future__ import annotations

import itertools
import json
import math
import shutil
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from .._version import __version__
from ..errors import FingerpadError
from .evaluate import STATE_CODES
from .spec import SweepSpec

__all__ = ["SweepStore", "chunk_slices", "check_store_path", "open_sweep", "points_done", "pressure_grid"]

_FLOAT_VARS = {
    "critical_load_bem": ("N", "load at which the pad centre reaches the transition (BEM cell)"),
    "critical_load_hertz": ("N", "critical load by per-asperity Hertz, Eq. 3.6"),
    "full_contact_load": ("N", "load at which the pad centre reaches full contact (BEM)"),
    "transition_pressure": ("Pa", "cell pressure of the transition"),
    "full_contact_pressure": ("Pa", "cell pressure of full contact (at most 1 % open)"),
    "grid_error": ("1", "estimated relative discretisation error of A_re/A_fr"),
    "grid": ("1", "grid points along x of the unit cell"),
    "seconds": ("s", "time to predict the point"),
}
_LOAD_VARS = {
    "area_ratio": ("1", "A_re / A_fr"),
    "mu": ("1", "friction coefficient on the texture"),
    "mu_ref": ("1", "friction coefficient on the flat reference"),
    "mu_rel": ("1", "mu / mu_ref"),
    "mu_perp_over_par": ("1", "mu sliding across the asperities' long axis / along it (with a direction)"),
}


def pressure_grid(p_min: float, p_max: float, per_decade: int = 12) -> np.ndarray:
    """The common pressures (Pa) of psi in a store: the global node grid over [p_min, p_max]."""
    k0 = math.floor(math.log10(p_min) * per_decade)
    k1 = math.ceil(math.log10(p_max) * per_decade)
    return 10.0 ** (np.arange(k0, k1 + 1) / per_decade)


def chunk_slices(shape: tuple[int, ...], chunk: int) -> list[tuple[slice, ...]]:
    """The chunks of a sweep's dimensions: one index along each but the last, ``chunk`` along it."""
    *lead, last = shape
    out = []
    for idx in itertools.product(*(range(n) for n in lead)):
        for start in range(0, last, chunk):
            out.append(tuple(slice(i, i + 1) for i in idx) + (slice(start, min(start + chunk, last)),))
    return out


class SweepStore:
    """A sweep's Zarr store (see the module docstring)."""

    def __init__(self, path: str | Path, spec: SweepSpec, pressures: np.ndarray) -> None:
        self.path = Path(path)
        self.spec = spec
        self.pressures = np.asarray(pressures, float)

    # ---------------------------------------------------------------- creating and opening

    def template(self) -> Any:
        import xarray as xr

        spec = self.spec
        shape, dims = spec.shape, spec.dims
        nl, npr = spec.loads.size, self.pressures.size
        coords: dict[str, Any] = {
            "load": xr.Variable("load", spec.loads, {"units": "N", "long_name": "exploration load"}),
            "cell_pressure": xr.Variable("cell_pressure", self.pressures,
                                         {"units": "Pa", "long_name": "mean nominal pressure on the unit cell"}),
        }
        data: dict[str, Any] = {}
        if spec.design == "grid":
            for axis in spec.axes:
                values = np.asarray(axis.values, dtype=float if axis.numeric else "<U32")
                coords[axis.name] = xr.Variable(axis.name, values, {"units": axis.unit, "log": str(axis.log).lower(),
                                                                     "kind": axis.kind})
        else:
            coords["point"] = xr.Variable("point", np.arange(spec.size), {"long_name": "sweep point"})
            for axis in spec.axes:
                values = np.asarray(spec.point_values[axis.name], dtype=float if axis.numeric else "<U32")
                data[axis.name] = xr.Variable("point", values, {"units": axis.unit, "log": str(axis.log).lower(),
                                                                "kind": axis.kind})
        for name, (unit, long) in _FLOAT_VARS.items():
            data[name] = xr.Variable(dims, np.full(shape, np.nan), {"units": unit, "long_name": long})
        for name, (unit, long) in _LOAD_VARS.items():
            data[name] = xr.Variable((*dims, "load"), np.full((*shape, nl), np.nan), {"units": unit, "long_name": long})
        data["contact_state"] = xr.Variable(
            (*dims, "load"), np.full((*shape, nl), -1, dtype=np.int8),
            {"units": "1", "long_name": "contact state at the pad centre",
             "flag_values": "0 1 2", "flag_meanings": " ".join(STATE_CODES)})
        data["psi"] = xr.Variable((*dims, "cell_pressure"), np.full((*shape, npr), np.nan),
                                  {"units": "1", "long_name": "psi: real-to-nominal area fraction of the cell"})
        data["valid"] = xr.Variable(dims, np.zeros(shape, bool), {"long_name": "the point's texture exists"})
        data["converged"] = xr.Variable(dims, np.zeros(shape, bool), {"long_name": "every cell solve converged"})
        data["reason"] = xr.Variable(dims, np.full(shape, "", dtype="<U200"), {"long_name": "why a point is invalid"})
        data["done"] = xr.Variable(dims, np.zeros(shape, bool), {"long_name": "the point has been computed"})
        attrs = {
            "fingerpad_sweep": 1,
            "title": "fingerpad sweep: design-map quantities of textures",
            "signature": spec.signature(),
            "design": spec.design,
            "axes": json.dumps([a.name for a in spec.axes]),
            "study": json.dumps({k: v for k, v in spec.base.items() if k != "_source"}, default=repr),
            "sweep": json.dumps(spec.raw, default=repr),
            "study_file": str(spec.source or ""),
            "chunk": spec.chunk,
            "units_system": "SI",
            "fingerpad_version": __version__,
        }
        return xr.Dataset(data, coords=coords, attrs=attrs)

    def encoding(self) -> dict[str, Any]:
        spec = self.spec
        lead = tuple(1 for _ in spec.shape[:-1]) + (min(spec.chunk, spec.shape[-1]),)
        enc: dict[str, Any] = {}
        for name in [*_FLOAT_VARS, "valid", "converged", "reason", "done"]:
            enc[name] = {"chunks": lead}
        for name in [*_LOAD_VARS, "contact_state"]:
            enc[name] = {"chunks": (*lead, spec.loads.size)}
        enc["psi"] = {"chunks": (*lead, self.pressures.size)}
        return enc

    def create(self, overwrite: bool = False) -> None:
        """Lay the store out (or find it): a store of another sweep is refused unless ``overwrite``."""
        if self.path.exists():
            if check_store_path(self.path, self.spec, overwrite) == "resume":
                return  # the same sweep: resume
            shutil.rmtree(self.path)
        tmp = self.path.with_name(f".{self.path.name}.creating")
        shutil.rmtree(tmp, ignore_errors=True)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            self.template().to_zarr(tmp, mode="w", encoding=self.encoding(), zarr_format=2, consolidated=True)
        tmp.rename(self.path)  # a store appears complete or not at all

    # ---------------------------------------------------------------- filling

    def done(self) -> np.ndarray:
        import zarr

        return np.asarray(zarr.open_group(str(self.path), mode="r")["done"][...], bool)

    def write(self, region: tuple[slice, ...], results: list[tuple[tuple[int, ...], dict[str, Any]]]) -> None:
        """Write the results of one chunk (``[(index, result), ...]``), the done mask last."""
        import zarr

        group = zarr.open_group(str(self.path), mode="r+")
        shape = tuple(s.stop - s.start for s in region)
        starts = tuple(s.start for s in region)
        nl, npr = self.spec.loads.size, self.pressures.size
        block: dict[str, np.ndarray] = {n: np.full(shape, np.nan) for n in _FLOAT_VARS}
        block.update({n: np.full((*shape, nl), np.nan) for n in _LOAD_VARS})
        block["contact_state"] = np.full((*shape, nl), -1, dtype=np.int8)
        block["psi"] = np.full((*shape, npr), np.nan)
        block["valid"] = np.zeros(shape, bool)
        block["converged"] = np.zeros(shape, bool)
        block["reason"] = np.full(shape, "", dtype="<U200")
        done = np.zeros(shape, bool)
        for index, res in results:
            local = tuple(i - s for i, s in zip(index, starts, strict=True))
            for name in _FLOAT_VARS:
                block[name][local] = res[name]
            for name in (*_LOAD_VARS, "contact_state", "psi"):
                block[name][local] = res[name]
            block["valid"][local] = res["valid"]
            block["converged"][local] = res["converged"]
            block["reason"][local] = str(res["reason"])[:200]
            done[local] = True
        for name, values in block.items():
            group[name][region] = values
        group["done"][region] = done

    @property
    def url(self) -> str:
        return str(self.path)


def _read_attrs(path: Path) -> dict[str, Any] | None:
    try:
        import zarr

        attrs = dict(zarr.open_group(str(path), mode="r").attrs)
    except Exception:  # noqa: BLE001 - anything unreadable is "not a sweep store"
        return None
    return attrs if attrs.get("fingerpad_sweep") == 1 else None


def check_store_path(path: str | Path, spec: SweepSpec | None = None, overwrite: bool = False) -> str:
    """What a sweep into ``path`` does there: ``"create"``, ``"resume"`` (the same sweep) or
    ``"replace"`` (another sweep, with ``overwrite``); cheap, to run before any work.

    Raises
    ------
    FingerpadError
        ``path`` holds something other than a sweep store (a folder of notes, the study file
        itself): it is a user's own and is never replaced, ``overwrite`` or not; or it holds
        another sweep and ``overwrite`` is not given.
    """
    p = Path(path)
    if not p.exists():
        return "create"
    existing = _read_attrs(p)
    if existing is None:
        if p.is_dir() and not any(p.iterdir()):
            return "replace"
        raise FingerpadError(f"{p}: exists and is not a fingerpad sweep store; it is left alone (name another --out)")
    if spec is not None and existing.get("signature") == spec.signature():
        return "resume"
    if spec is not None and not overwrite:
        raise FingerpadError(f"{p}: holds another sweep (other study or [sweep] table); "
                             "give --overwrite to replace it, or another --out")
    return "replace"


def points_done(path: str | Path) -> int | None:
    """How many points of the sweep store at ``path`` are done (``None``: no readable store)."""
    if _read_attrs(Path(path)) is None:
        return None
    try:
        import zarr

        return int(np.count_nonzero(zarr.open_group(str(path), mode="r")["done"][...]))
    except Exception:  # noqa: BLE001 - a damaged store: nothing to count
        return None


def open_sweep(path: str | Path) -> Any:
    """The results of a sweep as an :class:`xarray.Dataset` (lazy; read with ``.load()``).

    Raises
    ------
    FingerpadError
        When ``path`` is missing or not a fingerpad sweep store.
    """
    import xarray as xr

    p = Path(path)
    if not p.exists():
        raise FingerpadError(f"{str(p)!r}: no such sweep store (a folder written by `fingerpad sweep`)")
    if _read_attrs(p) is None:
        raise FingerpadError(f"{str(p)!r} is not a fingerpad sweep store (made by `fingerpad sweep`)")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return xr.open_zarr(p, consolidated=True)
