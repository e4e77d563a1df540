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
import uuid
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._version import __version__
from ..errors import FingerpadError
from ..extras import require
from ..references import netcdf_attribute
from .evaluate import STATE_CODES
from .spec import SweepSpec
from ..perception.discrimination import WEBER_FRACTION
from .store_population import (
    POP_FRACTION_VARS,
    POP_MEMBER_VARS,
    POP_LOAD_VARS,
    POP_QUANTILE_VARS,
    POPULATION_LAYOUT,
    population_flags,
    population_template,
    shell_path,
    stored_population_text,
)

__all__ = ["StoreDamage", "SweepStore", "check_store", "check_store_path", "chunk_slices", "open_sweep",
           "points_done", "pressure_grid"]

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
        if spec.population is not None:
            population_template(spec, coords, data)
        attrs = {
            "fingerpad_sweep": 1,
            "title": "fingerpad sweep: design-map quantities of textures",
            "signature": spec.signature(),
            "design": spec.design,
            "axes": json.dumps([a.name for a in spec.axes]),
            "study": json.dumps({k: v for k, v in spec.base.items() if k != "_source"}, default=repr),
            "sweep": json.dumps(spec.raw, default=repr),
            "study_file": str(Path(spec.source).resolve()) if spec.source else "",
            "chunk": spec.chunk,
            "units_system": "SI",
            "fingerpad_version": __version__,
            "references": netcdf_attribute(spec.references()),  # CF: the methods' publications
            # the same sweep without a population: a resume with another population is told apart
            "sweep_signature": spec.signature(population=False),
        }
        if spec.population is not None:
            attrs.update({"fingerpad_sweep_population": POPULATION_LAYOUT,
                          "population": json.dumps(spec.population_description()),
                          "population_name": spec.population.name, "population_size": spec.population.size,
                          # the W of tell_flat: the study's person's, NaN where the members draw their own
                          "weber_fraction": math.nan if "weber_fraction" in spec.population.distributions else
                          float(WEBER_FRACTION.parse(spec.base.get("perception", {}).get("weber_fraction", WEBER_FRACTION.default))),
                          # how the sweep named it: the flags a resume or a repair must repeat
                          "population_source": spec.population_source or ""})
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
        if spec.population is not None:
            nq = len(spec.quantiles)
            for name in POP_LOAD_VARS:
                enc[name] = {"chunks": (*lead, nq, spec.loads.size)}
            for name in POP_QUANTILE_VARS:
                enc[name] = {"chunks": (*lead, nq)}
            enc["state_probability"] = {"chunks": (*lead, len(STATE_CODES), spec.loads.size)}
            enc.update({name: {"chunks": (*lead, spec.loads.size)} for name in POP_FRACTION_VARS})
            enc.update({name: {"chunks": (*lead, len(spec.members), spec.loads.size)} for name in POP_MEMBER_VARS})
            enc["asperity_over_range"] = {"chunks": lead}
        return enc

    def check_existing(self, overwrite: bool = False) -> str:
        """What is at the store's path: ``"new"`` (nothing), ``"resume"`` (this sweep) or
        ``"replace"`` (an empty folder, or another sweep with ``overwrite``): see
        :func:`check_store_path`, whose refusals it raises."""
        state = check_store_path(self.path, self.spec, overwrite)
        return "new" if state == "create" else state

    def create(self, overwrite: bool = False) -> None:
        """Lay the store out (or find it): a store of another sweep is refused unless ``overwrite``."""
        if self.check_existing(overwrite) == "resume":
            return  # the same sweep: resume
        tmp = self.path.with_name(f".{self.path.name}.creating")
        shutil.rmtree(tmp, ignore_errors=True)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            self.template().to_zarr(tmp, mode="w", encoding=self.encoding(), zarr_format=2, consolidated=True)
        if self.path.exists():
            # an empty folder or another sweep's store (check_store_path): moved aside in one
            # rename, then removed, so that an interruption leaves the old store or none, never
            # half of one (a hidden .NAME.XXXXXXXX.old left by kill -9 goes with the next run,
            # fingerpad.locks.remove_stale)
            old = self.path.with_name(f".{self.path.name}.{uuid.uuid4().hex[:8]}.old")
            self.path.rename(old)
            shutil.rmtree(old, ignore_errors=True)
        tmp.rename(self.path)  # a store appears complete or not at all

    def check(self) -> StoreDamage:
        """:func:`check_store` of this store, knowing which arrays this sweep's store has."""
        return check_store(self.path, expected=list(self.template().variables))

    def repair(self, damage: StoreDamage) -> int:
        """Make a damaged store of this sweep whole again; returns the points to compute again.

        Damaged chunks of results are rewritten as not computed (NaN, ``done`` False) so that the
        sweep computes their points again; a result array that is lost (or whose own metadata is
        unreadable) is laid out anew, all its points to compute again; damaged inputs (axis values,
        loads, pressures) and the store's attributes are rewritten from the study; the
        consolidated metadata is written anew.
        """
        import zarr

        template = self.template()
        if damage.root:
            # the group's own metadata, as xarray writes it (the attributes hold the signature)
            (self.path / ".zgroup").write_text(json.dumps({"zarr_format": 2}), encoding="utf-8")
            (self.path / ".zattrs").write_text(json.dumps(template.attrs), encoding="utf-8")
        redo = np.zeros(self.spec.shape, bool)
        encoding = self.encoding()
        for name in damage.arrays:
            tmp = self.path.with_name(f".{self.path.name}.{name}.repair")
            shutil.rmtree(tmp, ignore_errors=True)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                template[[name]].to_zarr(tmp, mode="w", zarr_format=2, consolidated=False,
                                         encoding={name: encoding[name]} if name in encoding else {})
            shutil.rmtree(self.path / name, ignore_errors=True)
            (tmp / name).rename(self.path / name)
            shutil.rmtree(tmp, ignore_errors=True)
            if name in _RESULT_VARS:
                redo[...] = True
        group = zarr.open_group(str(self.path), mode="r+", use_consolidated=False)
        if redo.all():
            group["done"][...] = False
        for name, regions in damage.chunks.items():
            if name in damage.arrays:
                continue
            var = template[name]
            for region in regions:
                group[name][region] = var.values[region]  # results: not computed (NaN, -1, "", False)
                if name in _RESULT_VARS:
                    lead = region[: len(self.spec.shape)]
                    group["done"][lead] = False
                    redo[lead] = True
        zarr.consolidate_metadata(str(self.path), zarr_format=2)
        return int(redo.sum())

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
        pop = self.spec.population is not None
        if pop:
            nq = len(self.spec.quantiles)
            block.update({n: np.full((*shape, nq, nl), np.nan) for n in POP_LOAD_VARS})
            block.update({n: np.full((*shape, nq), np.nan) for n in POP_QUANTILE_VARS})
            block["state_probability"] = np.full((*shape, len(STATE_CODES), nl), np.nan)
            block.update({n: np.full((*shape, nl), np.nan) for n in POP_FRACTION_VARS})
            block.update({n: np.full((*shape, len(self.spec.members), nl), np.nan) for n in POP_MEMBER_VARS})
            block["asperity_over_range"] = np.full(shape, np.nan)
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
            if pop:
                for name in (*POP_LOAD_VARS, *POP_QUANTILE_VARS, *POP_FRACTION_VARS, *POP_MEMBER_VARS,
                             "state_probability", "asperity_over_range"):
                    block[name][local] = res[name]
            done[local] = True
        for name, values in block.items():
            group[name][region] = values
        group["done"][region] = done

    @property
    def url(self) -> str:
        return str(self.path)


#: The variables a sweep computes (the others are its inputs: axis values, loads, pressures).
_RESULT_VARS = {*_FLOAT_VARS, *_LOAD_VARS, "contact_state", "psi", "valid", "converged", "reason", "done",
                *POP_LOAD_VARS, *POP_QUANTILE_VARS, *POP_FRACTION_VARS, *POP_MEMBER_VARS, "state_probability",
                "asperity_over_range"}


@dataclass
class StoreDamage:
    """What is damaged in a sweep store (:func:`check_store`); false when nothing is.

    Attributes
    ----------
    path
        The store.
    metadata
        Damaged metadata, in words (the consolidated ``.zmetadata``, the group's own).
    root
        Whether the group's own metadata (``.zgroup``, ``.zattrs``) is damaged.
    arrays
        Arrays lost, or whose own metadata (``.zarray``) is unreadable.
    chunks
        ``{variable: [region, ...]}``: chunks that cannot be read, as index regions of the variable.
    study_file
        The study file the store records (for the message that says how to repair it).
    flags
        The population flags of the sweep that wrote the store (``--population adults``), which
        the repair must repeat (:func:`~.store_population.population_flags`).

    Every kind is mended by :meth:`SweepStore.repair` (``fingerpad sweep ... --repair``).
    """

    path: Path
    metadata: list[str] = field(default_factory=list)
    root: bool = False
    arrays: dict[str, str] = field(default_factory=dict)
    chunks: dict[str, list[tuple[slice, ...]]] = field(default_factory=dict)
    study_file: str = ""
    flags: str = ""

    def __bool__(self) -> bool:
        return bool(self.metadata or self.root or self.arrays or self.chunks)

    def describe(self) -> str:
        """The damage in a few words (the first chunks of each variable named)."""
        parts = list(self.metadata) + list(self.arrays.values())
        for name, regions in self.chunks.items():
            shown = ", ".join(_region_text(r) for r in regions[:3])
            more = f" and {len(regions) - 3} more" if len(regions) > 3 else ""
            parts.append(f"{len(regions)} unreadable chunk{'s' if len(regions) > 1 else ''} of {name!r} "
                         f"({shown}{more})")
        return "; ".join(parts)

    def message(self) -> str:
        """One line: the store, what is damaged, and how to mend it."""
        study = shell_path(self.study_file) if self.study_file else "STUDY.toml"
        return (f"{self.path}: damaged sweep store: {self.describe()}; fingerpad sweep {study} --out "
                f"{shell_path(self.path)}{self.flags} --repair recomputes the damaged points and rewrites the "
                "metadata")


def _region_text(region: tuple[slice, ...]) -> str:
    return "[" + ", ".join(f"{s.start}:{s.stop}" for s in region) + "]"


def check_store(path: str | Path, expected: list[str] | None = None) -> StoreDamage:
    """Read every chunk and the metadata of a sweep store; what cannot be read is damage.

    A chunk of garbage (a disk error, a copy cut short) otherwise shows as a decoding traceback
    when the store is read, or is silently resumed over; a lost ``.zmetadata`` makes the store
    unreadable by :func:`open_sweep` although its arrays are whole. ``expected`` names the
    arrays the store must have (the sweep knows them; otherwise those of ``.zmetadata``).
    """
    import zarr

    p = Path(path)
    damage = StoreDamage(p)
    attrs = _read_attrs(p) or {}
    damage.study_file = str(attrs.get("study_file", ""))
    damage.flags = population_flags(attrs)
    for name in (".zgroup", ".zattrs"):
        try:
            if not isinstance(json.loads((p / name).read_text(encoding="utf-8")), dict):
                raise ValueError(name)
        except (OSError, ValueError):
            damage.root = True
            damage.metadata.append(f"the store's own metadata ({name}) is unreadable")
    listed: list[str] = []
    try:
        meta = json.loads((p / ".zmetadata").read_text(encoding="utf-8"))
        listed = sorted({k.split("/")[0] for k in meta["metadata"] if "/" in k})
    except FileNotFoundError:
        damage.metadata.append(".zmetadata (the consolidated metadata) is missing")
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        damage.metadata.append(".zmetadata (the consolidated metadata) is unreadable")
    on_disk = sorted(d.name for d in p.iterdir() if d.is_dir() and not d.name.startswith("."))
    for name in sorted(set(on_disk) | set(listed) | set(expected or [])):
        if name not in on_disk:
            damage.arrays[name] = f"the array {name!r} is missing"
            continue
        try:
            arr = zarr.open_array(str(p / name), mode="r", zarr_format=2)
        except Exception:  # noqa: BLE001 - any unreadable metadata is damage
            damage.arrays[name] = f"the metadata of {name!r} ({name}/.zarray) is unreadable"
            continue
        bad = _unreadable_chunks(arr)
        if bad:
            damage.chunks[name] = bad
    return damage


def _unreadable_chunks(arr: Any) -> list[tuple[slice, ...]]:
    """Regions of the chunks of ``arr`` that cannot be read (whole array first: usually all is well)."""
    try:
        arr[...]
        return []
    except Exception:  # noqa: BLE001 - a codec error, a short file: any failure is a damaged chunk
        pass
    bad = []
    grid = [range(math.ceil(n / c)) for n, c in zip(arr.shape, arr.chunks, strict=True)]
    for idx in itertools.product(*grid):
        region = tuple(slice(i * c, min((i + 1) * c, n)) for i, c, n in zip(idx, arr.chunks, arr.shape, strict=True))
        try:
            arr[region]
        except Exception:  # noqa: BLE001 - see above
            bad.append(region)
    return bad


def _read_attrs(path: Path) -> dict[str, Any] | None:
    try:
        import zarr

        # the group's own attributes, not the consolidated copy: a store whose .zmetadata is
        # lost is still this sweep's store (damaged, and repairable) ...
        attrs = dict(zarr.open_group(str(path), mode="r", use_consolidated=False).attrs)
    except Exception:  # noqa: BLE001 - anything unreadable is "not a sweep store" ...
        try:  # ... unless the consolidated copy of the attributes says it is one (damaged)
            meta = json.loads((Path(path) / ".zmetadata").read_text(encoding="utf-8"))
            attrs = dict(meta["metadata"][".zattrs"])
        except Exception:  # noqa: BLE001 - see above
            return None
    return attrs if attrs.get("fingerpad_sweep") == 1 else None


def check_store_path(path: str | Path, spec: SweepSpec | None = None, overwrite: bool = False,
                     repair: bool = False) -> str:
    """What a sweep into ``path`` does there: ``"create"``, ``"resume"`` (the same sweep) or
    ``"replace"`` (another sweep, with ``overwrite``); cheap, to run before any work.

    Raises
    ------
    FingerpadError
        ``path`` holds something other than a sweep store (a folder of notes, the study file
        itself): it is a user's own and is never replaced, ``overwrite`` or not; or it holds
        another sweep and ``overwrite`` is not given; or ``repair`` is asked where there is no
        store to repair (it would run the whole sweep anew).
    """
    p = Path(path)
    if not p.exists():
        if repair:
            raise FingerpadError(f"--repair: there is no sweep store at {str(p)!r} to repair; run the sweep without "
                                 "--repair to start it (or name the store to repair with --out)")
        return "create"
    existing = _read_attrs(p)
    if existing is None and not (p.is_dir() and not any(p.iterdir())):
        raise FingerpadError(f"{p}: exists and is not a fingerpad sweep store; it is left alone (name another --out)")
    from ..io import check_folder_writable

    check_folder_writable(p, f"--out {str(p)!r}")  # before the work, not after it (a read-only store)
    if existing is None:
        return "replace"
    if spec is not None and existing.get("signature") == spec.signature():
        return "resume"
    if spec is not None and not overwrite and spec.signature(population=False) in (
            existing.get("sweep_signature"), existing.get("signature")):
        # this sweep, with another population (or with one where the store has none, or none
        # where it has one): the bands of two populations must not mix in one store
        flags = population_flags(existing)
        if spec.population is None and flags:
            # the run forgot the population the store was swept with: say how to name it, before
            # --overwrite, which would throw the store's points away
            raise FingerpadError(f"{p}: holds this sweep with {stored_population_text(existing)}, and this run asks "
                                 f"for none; give{flags} as the sweep that wrote it did (--overwrite would discard "
                                 "its points)")
        raise FingerpadError(f"{p}: holds this sweep with {stored_population_text(existing)}, and this run asks for "
                             f"{spec.population_text()}; give --overwrite to replace it, or another --out")
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


def open_sweep(path: str | Path, check: bool = True) -> Any:
    """The results of a sweep as an :class:`xarray.Dataset` (lazy; read with ``.load()``).

    With ``check`` (default), every chunk is read first (:func:`check_store`), so that a damaged
    store is said in one line instead of failing somewhere in the reading.

    Raises
    ------
    FingerpadError
        When ``path`` is missing, not a fingerpad sweep store, or damaged.
    MissingExtraError
        Zarr not installed (the ``sweep`` extra).
    """
    import xarray as xr

    require("sweep", modules=("zarr",))

    p = Path(path)
    if not p.exists():
        raise FingerpadError(f"{str(p)!r}: no such sweep store (a folder written by `fingerpad sweep`)")
    if _read_attrs(p) is None:
        raise FingerpadError(f"{str(p)!r} is not a fingerpad sweep store (made by `fingerpad sweep`)")
    if check:
        damage = check_store(p)
        if damage:
            raise FingerpadError(damage.message())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return xr.open_zarr(p, consolidated=True)
