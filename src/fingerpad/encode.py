"""Values made writable: JSON documents and NetCDF attributes (SI numbers, no NaN in JSON).

:func:`to_jsonable` turns results (NumPy scalars and arrays, tuples, non-finite floats) into
plain JSON values; :func:`flatten_attrs` turns nested metadata into flat NetCDF attributes of
the types NetCDF takes.
"""

from __future__ import annotations

import json
import math
import os
import re
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

__all__ = ["flatten_attrs", "json_text", "to_jsonable"]


_BAD_KEY = re.compile(r"[^A-Za-z0-9_]+")


def _attr_key(key: Any) -> str:
    text = _BAD_KEY.sub("_", str(key)).strip("_")
    if not text:
        text = "attr"
    if text[0].isdigit():
        text = "_" + text
    return text


def _attr_value(value: Any) -> str | int | float | np.ndarray:
    """Convert one value to something NetCDF accepts as an attribute."""
    if value is None:
        return "none"
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        v = float(value)
        return v if math.isfinite(v) else str(v)
    if isinstance(value, str):
        return value
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if isinstance(value, np.ndarray) and value.dtype.kind in "iuf" and value.ndim <= 1:
        if value.size == 0:
            return "[]"
        return value.astype(float if value.dtype.kind == "f" else np.int64)
    if isinstance(value, (list, tuple, np.ndarray)):
        items = list(value)
        if items and all(
            isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, (bool, np.bool_))
            for v in items
        ):
            arr = np.asarray(items, dtype=float)
            if np.all(np.isfinite(arr)):
                return arr
        return json.dumps(to_jsonable(items))
    return str(value)


def to_jsonable(value: Any, nonfinite: Callable[[float], Any] | None = None) -> Any:
    """``value`` ready for ``json.dumps``: mappings (keys as text), lists and tuples, NumPy scalars
    and arrays, paths, and anything else as its text. A NaN or infinite float becomes ``None``,
    or ``nonfinite(value)`` (``repr`` keeps ``"inf"``: what a sweep's signature records).
    The one conversion of the package (outputs, the measurement report, sweep stores)."""
    def convert(value: Any) -> Any:
        if isinstance(value, Mapping):
            return {str(k): convert(v) for k, v in value.items()}
        if isinstance(value, (list, tuple)):
            return [convert(v) for v in value]
        if isinstance(value, np.ndarray):
            if value.dtype.kind == "f" and np.all(np.isfinite(value)):
                return value.tolist()  # already JSON numbers: no walk over every element
            return convert(value.tolist())
        if isinstance(value, (bool, np.bool_)):
            return bool(value)
        if isinstance(value, (int, np.integer)):
            return int(value)
        if isinstance(value, (float, np.floating)):
            v = float(value)
            return v if math.isfinite(v) else (None if nonfinite is None else nonfinite(v))
        if isinstance(value, os.PathLike):
            return os.fspath(value)
        if value is None or isinstance(value, str):
            return value
        return str(value)

    return convert(value)


#: Keys whose lists :func:`json_text` writes one compact item per line (a population's members).
ROW_LISTS = ("members", "member_results")


def json_text(doc: Any, rows: tuple[str, ...] = ROW_LISTS) -> str:
    """``json.dumps(doc, indent=2)`` plus a newline, except that a list under one of the keys
    ``rows`` is written one compact item per line (a member's parameters or curves on one
    line). The same JSON value; the indented form is written by Python's pure-Python encoder,
    which took 0.16 s for the 6 MB of 1000 members, the compact items by its C encoder.
    ``doc`` must already be JSON-ready (:func:`to_jsonable`)."""
    parts: dict[str, str] = {}

    def swap(value: Any, depth: int) -> Any:
        if isinstance(value, dict):
            out = {}
            for k, v in value.items():
                if k in rows and isinstance(v, list) and v:
                    mark = f"\x00row-list-{len(parts)}\x00"
                    pad = "  " * (depth + 1)
                    parts[json.dumps(mark)] = ("[\n" + ",\n".join(pad + "  " + json.dumps(item) for item in v)
                                               + "\n" + pad + "]")
                    out[k] = mark
                else:
                    out[k] = swap(v, depth + 1)
            return out
        if isinstance(value, list):
            return [swap(v, depth + 1) for v in value]
        return value

    text = json.dumps(swap(doc, 0), indent=2)
    for mark, body in parts.items():
        text = text.replace(mark, body, 1)
    return text + "\n"


def flatten_attrs(attrs: Mapping[str, Any] | None, prefix: str = "") -> dict[str, Any]:
    """Flatten ``attrs`` (nested dicts joined with ``_``) into NetCDF-safe attributes."""
    out: dict[str, Any] = {}
    for key, value in (attrs or {}).items():
        name = _attr_key(f"{prefix}_{key}" if prefix else key)
        if isinstance(value, Mapping):
            if value:
                out.update(flatten_attrs(value, name))
            else:
                out[name] = "{}"
        else:
            out[name] = _attr_value(value)
    return out
