"""NumPy ``.npy`` height maps: a 2-D array, axis 0 along x (``np.save(path, texture.heights)``)."""

from __future__ import annotations

from pathlib import Path

import lazy_loader

# NumPy loads on first use: listing the texture families (`fingerpad textures`) must start fast.
np = lazy_loader.load("numpy")

from ...errors import FingerpadError
from . import Reader


def one_line_exception(exc: BaseException) -> str:
    """``Type: message`` on one line."""
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def _load_npy(path: Path) -> np.ndarray:
    with open(path, "rb") as fh:
        magic = fh.read(6)
    if magic != b"\x93NUMPY":  # NumPy would take it for a pickle and advise allow_pickle=True
        raise FingerpadError(f"cannot read {path}: not a valid .npy file (no NumPy header; save the map with numpy.save)")
    try:
        data = np.load(path, allow_pickle=False)
    except ValueError as exc:
        if "pickle" in str(exc):  # an array of Python objects: never loaded, whatever the source
            raise FingerpadError(f"cannot read {path}: the .npy file holds Python objects, not numbers") from None
        raise FingerpadError(f"cannot read {path}: not a valid .npy file ({one_line_exception(exc)})") from None
    except Exception as exc:
        raise FingerpadError(f"cannot read {path}: not a valid .npy file ({one_line_exception(exc)})") from None
    if not isinstance(data, np.ndarray):
        raise FingerpadError(f"cannot read {path}: expected a single array")
    return data



def _load(path: Path, size: tuple[float, float] | None, factor: float | None):
    assert size is not None and factor is not None  # bare format: checked by read_surface
    return _load_npy(path), size, factor


READER = Reader(name="npy", suffixes=(".npy",), bare=True, load=_load)
