"""Finding the pieces that are added by adding one file: texture families, height-map readers,
tribometer importers, pad (gross-area) and ridge-area models. Each lives in a module of its
package and names itself in a module-level attribute; nothing else has to be edited to add one.

Discovery is strict: a module of such a package that declares nothing (a misspelt attribute,
``FAMILY = ...`` for ``FAMILIES``, or a helper module not marked as one) is a
:class:`DiscoveryError` naming the file and the attribute expected, never a silently skipped
file. Helper modules of a package start with ``_`` or are listed in ``skip``.
"""

from __future__ import annotations

import difflib
import importlib
import pkgutil
from collections.abc import Iterable
from typing import Any

__all__ = ["DiscoveryError", "collect", "fill_registry"]


class DiscoveryError(ImportError):
    """A module of a discovery package declares nothing, or something of the wrong type
    (a programming error of the package or of a file added to it)."""


def _kind_name(kind: type | tuple[type, ...]) -> str:
    kinds = kind if isinstance(kind, tuple) else (kind,)
    return " or ".join(k.__name__ for k in kinds)


def collect(package: str, path: Iterable[str], attribute: str, kind: type | tuple[type, ...],
            skip: Iterable[str] = ()) -> list[Any]:
    """Every ``attribute`` of the modules of ``package`` (its ``__path__`` is ``path``): a ``kind``
    or a tuple or list of them, in module-name order.

    Modules whose name starts with ``_`` or is in ``skip`` are helpers and are left out.

    Raises
    ------
    DiscoveryError
        A module (not a helper) without ``attribute``, with an empty one, or holding something
        that is not a ``kind``: the message names the file and the attribute expected (and a
        close misspelling, if the module has one).
    """
    found: list[Any] = []
    excluded = set(skip)
    for info in sorted(pkgutil.iter_modules(list(path)), key=lambda i: i.name):
        if info.name.startswith("_") or info.name in excluded:
            continue
        module = importlib.import_module(f"{package}.{info.name}")
        where = getattr(module, "__file__", None) or f"{package}.{info.name}"
        expected = f"{attribute} = ({_kind_name(kind)}(...),)"
        if not hasattr(module, attribute):
            names = [n for n in vars(module) if n.isupper() and not n.startswith("__")]
            close = difflib.get_close_matches(attribute, names, n=1, cutoff=0.6)
            hint = f" (it defines {close[0]}: did you mean {attribute}?)" if close else ""
            raise DiscoveryError(
                f"{where}: module {package}.{info.name} declares no {attribute}{hint}; every module of "
                f"{package} must declare {expected}, or be a helper (a name starting with _ or listed "
                "as a helper module of the package)"
            )
        value = getattr(module, attribute)
        items = list(value) if isinstance(value, (tuple, list)) else [value]
        bad = [item for item in items if not isinstance(item, kind)]
        if bad or not items:
            what = f"holds {type(bad[0]).__name__} {bad[0]!r:.60}" if bad else "is empty"
            raise DiscoveryError(f"{where}: {package}.{info.name}.{attribute} {what}; expected {expected}")
        found.extend(items)
    return found


def fill_registry(registry: dict[str, Any], package: str, path: Iterable[str], attribute: str, kind: type,
                  skip: Iterable[str] = (), what: str = "model") -> dict[str, Any]:
    """Replace the contents of ``registry`` with the declarations :func:`collect` finds, keyed by
    their ``name`` (the pad and ridge model registries). Returns ``registry``.

    Raises
    ------
    DiscoveryError
        As :func:`collect`.
    ValueError
        Two declarations of the same name (``what`` names them in the message).
    """
    found: dict[str, Any] = {}
    for item in collect(package, path, attribute, kind, skip=skip):
        if item.name in found:
            raise ValueError(f"two {what}s are named {item.name!r}")
        found[item.name] = item
    registry.clear()
    registry.update(found)
    return registry
