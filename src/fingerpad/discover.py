"""Finding the pieces that are added by adding one file: texture families, height-map readers,
tribometer importers. Each lives in a module of its package and names itself in a module-level
attribute; nothing else has to be edited to add one."""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Iterable
from typing import Any

__all__ = ["collect"]


def collect(package: str, path: Iterable[str], attribute: str, kind: type | tuple[type, ...],
            skip: Iterable[str] = ()) -> list[Any]:
    """Every ``attribute`` of the modules of ``package`` (its ``__path__`` is ``path``) that is a
    ``kind`` (or a tuple or list of them), in module-name order. Modules whose name starts with
    ``_`` or is in ``skip`` are left out."""
    found: list[Any] = []
    excluded = set(skip)
    for info in sorted(pkgutil.iter_modules(list(path)), key=lambda i: i.name):
        if info.name.startswith("_") or info.name in excluded:
            continue
        value = getattr(importlib.import_module(f"{package}.{info.name}"), attribute, None)
        items = value if isinstance(value, (tuple, list)) else (value,)
        found.extend(item for item in items if isinstance(item, kind))
    return found
