"""Instrument files read by SurfaceTopography (``.sur``, ``.x3p``, ``.plu``, ``.datx``, ``.opd``, ``.di``, ``.gwy``, ``.nc``, ...)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import lazy_loader

# NumPy loads on first use: listing the texture families (`fingerpad textures`) must start fast.
np = lazy_loader.load("numpy")

from ...errors import FingerpadError
from ...extras import load
from . import Reader
from .npy import one_line_exception

#: Length units found in instrument files (SurfaceTopography ``.unit``), factor to metres.
_FILE_UNITS = {
    "km": 1e3, "m": 1.0, "dm": 0.1, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "μm": 1e-6,
    "nm": 1e-9, "Å": 1e-10, "A": 1e-10, "pm": 1e-12,
}



def _load(path: Path, size: tuple[float, float] | None, factor: float | None):
    """Heights (file units, NaN where undefined), lateral size (m) and height factor to m."""
    open_topography = load("SurfaceTopography", f"reading {path.suffix} files").open_topography
    try:
        with open_topography(str(path)) as reader:
            channel = reader.default_channel
            if channel.dim is not None and channel.dim != 2:
                raise FingerpadError(f"{path}: holds a line scan; a 2-D height map is needed")
            kwargs: dict[str, Any] = {}
            if channel.physical_sizes is None:
                if size is None:
                    raise FingerpadError(
                        f"{path}: the file gives no physical size; pass size=(Lx, Ly) in metres"
                    )
                kwargs["physical_sizes"] = size  # metres; replaced below anyway
            topo = reader.topography(**kwargs)
    except FingerpadError:
        raise
    except Exception as exc:
        if type(exc).__name__ in ("CannotDetectFileFormat", "UnknownFileFormat"):
            reason = "file format not recognised (neither by fingerpad nor by SurfaceTopography)"
        else:
            reason = one_line_exception(exc)
            if len(reason) > 300:
                reason = reason[:300] + " ..."
        raise FingerpadError(f"cannot read surface file {path}: {reason}") from None
    if topo.dim != 2:
        raise FingerpadError(f"{path}: holds a line scan; a 2-D height map is needed")
    raw = topo.heights()
    mask = np.ma.getmaskarray(raw)
    heights = np.array(np.ma.getdata(raw), dtype=float)
    heights[mask] = np.nan
    unit = topo.unit
    unit_factor = None
    if unit is not None:
        unit_factor = _FILE_UNITS.get(str(unit).strip())
        if unit_factor is None and factor is None:
            raise FingerpadError(f"{path}: unknown length unit {unit!r} in the file; pass height_unit")
    if factor is None:
        if unit_factor is None:
            raise FingerpadError(f"{path}: the file gives no height unit; pass height_unit")
        factor = unit_factor
    if size is None:
        lateral = unit_factor if unit_factor is not None else factor
        lx, ly = (float(s) * lateral for s in topo.physical_sizes)
        size = (lx, ly)
    return heights, size, factor


READER = Reader(name="instrument", suffixes=(), bare=False, load=_load)
