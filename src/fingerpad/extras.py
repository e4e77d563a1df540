"""The optional parts of fingerpad and the packages each needs: one rule, one message.

``pip install fingerpad`` installs the core: ``solve``, ``predict`` (populations, sensitivity
and directional friction included), ``textures``, ``fingers``, ``finger-models``,
``deflection`` and every figure. The rest comes with an *extra*, named by what a user does
(pyproject.toml's ``[project.optional-dependencies]`` lists the same packages):

========== ============================================== ==========================================
extra      what it brings                                 packages
========== ============================================== ==========================================
measure    ``analyse``: friction measurements, lab files  statsmodels, openpyxl, xlrd, npTDMS
sweep      ``sweep``, ``design-map``, stores of sweeps    Dask (distributed), Zarr
maps       instrument height maps (.x3p, .sur, .opd ...)  SurfaceTopography
explore    ``explore``: the browser explorer              Panel, Bokeh, Zarr
fast       faster solves (same answers to rounding)       ducc0 (GPL), Numba
all        all of the above
========== ============================================== ==========================================

A feature that needs an extra asks :func:`require` (or loads its package by :func:`load`) before
it does any work; a missing package raises :class:`MissingExtraError`, a
:class:`~fingerpad.errors.FingerpadError` and an :class:`ImportError` at once, whose one-line
message names the extra to install. The command line prints it as ``error: ...`` with exit
code 2, like any user mistake.
"""

from __future__ import annotations

import importlib
import importlib.util
from types import ModuleType

from .errors import SetupError

__all__ = ["EXTRAS", "MissingExtraError", "extra_of", "from_import_error", "load", "message", "missing", "require"]

#: Extra -> (what it serves, the importable modules it brings).
EXTRAS: dict[str, tuple[str, tuple[str, ...]]] = {
    "measure": ("friction measurements (fingerpad analyse)",
                ("statsmodels", "openpyxl", "xlrd", "nptdms", "threadpoolctl")),
    "sweep": ("sweeps and their stores (fingerpad sweep, design-map)", ("dask", "distributed", "zarr")),
    "maps": ("instrument height-map files", ("SurfaceTopography",)),
    "explore": ("the explorer (fingerpad explore)", ("panel", "bokeh", "zarr")),
    "fast": ("the faster FFTs and compiled loops", ("ducc0", "numba")),
}

#: Importable module -> the extra that installs it (the first extra that lists it).
MODULE_EXTRA: dict[str, str] = {}
for _extra, (_, _modules) in EXTRAS.items():
    for _module in _modules:
        MODULE_EXTRA.setdefault(_module, _extra)


class MissingExtraError(SetupError, ImportError):
    """An optional package a feature needs is not installed; the message names the extra
    (``pip install 'fingerpad[sweep]'``). ``name`` is the missing module, as ImportError's."""

    def __init__(self, message: str, name: str | None = None) -> None:
        super().__init__(message)
        self.name = name


def extra_of(module: str) -> str | None:
    """The extra that installs ``module`` (its top-level package), or ``None`` for a core one."""
    return MODULE_EXTRA.get(module.split(".")[0])


def _installed(module: str) -> bool:
    try:
        return importlib.util.find_spec(module) is not None
    except (ImportError, ValueError):  # a broken or half-removed package counts as missing
        return False


def missing(extra: str, modules: tuple[str, ...] | None = None) -> list[str]:
    """The modules of ``extra`` (or only ``modules`` of it) that cannot be imported here."""
    if extra not in EXTRAS:
        raise KeyError(f"unknown extra {extra!r}")
    return [m for m in (modules or EXTRAS[extra][1]) if not _installed(m)]


def message(extra: str, absent: list[str], what: str | None = None) -> str:
    """The one line every front door gives for a missing extra: what needs it (by default what
    the extra serves), the packages missing, the command that installs them."""
    what = what or EXTRAS[extra][0]
    return f"{what}: the '{extra}' extra is not installed ({', '.join(absent)} missing): pip install 'fingerpad[{extra}]'"


def require(extra: str, what: str | None = None, modules: tuple[str, ...] | None = None) -> None:
    """Raise :class:`MissingExtraError` unless every module of ``extra`` (or ``modules`` of it)
    can be imported; ``what`` names the feature in the message (default: what the extra serves,
    :data:`EXTRAS`), so the command and the Python API say the same."""
    absent = missing(extra, modules)
    if absent:
        raise MissingExtraError(message(extra, absent, what), name=absent[0])


def load(module: str, what: str | None = None) -> ModuleType:
    """Import ``module`` (of an extra) and return it; if its package is missing, raise
    :class:`MissingExtraError` naming the extra. Errors inside an installed package propagate."""
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as exc:
        top = module.split(".")[0]
        extra = extra_of(top)
        if extra is None or (exc.name or "").split(".")[0] != top:
            raise
        raise MissingExtraError(message(extra, [top], what), name=top) from None


def from_import_error(exc: ImportError, what: str | None = None) -> MissingExtraError | None:
    """The :class:`MissingExtraError` for an import of an extra's package that failed deep inside
    a feature (the command line's safety net), or ``None`` when the missing module belongs to no
    extra (a bug or a broken installation, to be seen as such)."""
    if isinstance(exc, MissingExtraError):
        return exc
    name = (getattr(exc, "name", None) or "").split(".")[0]
    extra = extra_of(name) if name else None
    if extra is None:
        return None
    return MissingExtraError(message(extra, [name], what), name=name)
