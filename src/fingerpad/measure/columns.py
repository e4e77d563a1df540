"""Column specification of a recording: which columns hold which quantity, in which unit; file-name templates."""

from __future__ import annotations

import os
import re
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Literal

from ..errors import FingerpadError
from ..units import UNITS

#: Time units -> factor to seconds (``fingerpad.units`` covers force and length only).
TIME_UNITS: dict[str, float] = {
    "s": 1.0, "sec": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "μs": 1e-6, "min": 60.0, "h": 3600.0,
}


def unit_factor(unit: str, dimension: str, *, where: str = "unit") -> float:
    """Factor that converts a value in ``unit`` to SI.

    Parameters
    ----------
    unit
        Unit symbol, e.g. ``"mN"``, ``"mm"``, ``"ms"``, ``"mm/s"``; empty means SI.
    dimension
        ``"force"``, ``"length"``, ``"time"`` or ``"velocity"`` (``LENGTH/TIME``).
    where
        Context for the error message (file and column).

    Raises
    ------
    FingerpadError
        For an unknown unit or one of the wrong dimension.
    """
    u = str(unit).strip()
    if not u:
        return 1.0
    if dimension == "time":
        u = u if u in TIME_UNITS else UNIT_SYNONYMS.get(u.lower(), u)  # "seconds", as LabVIEW writes
        if u in TIME_UNITS:
            return TIME_UNITS[u]
        raise FingerpadError(f"{where}: unknown time unit {u!r} (use one of: {', '.join(TIME_UNITS)})")
    if dimension == "velocity":
        num, sep, den = u.partition("/")
        if not (sep and num.strip() and den.strip()):
            raise FingerpadError(f"{where}: unknown velocity unit {u!r} (write LENGTH/TIME, e.g. mm/s)")
        return unit_factor(num, "length", where=where) / unit_factor(den, "time", where=where)
    u = UNIT_SYNONYMS.get(u.lower(), u) if u not in UNITS and u not in EXTRA_UNITS else u
    entry = UNITS.get(u) or EXTRA_UNITS.get(u)
    if entry is None or entry[0] != dimension:
        known = ", ".join([k for k, v in UNITS.items() if v[0] == dimension]
                          + [k for k, v in EXTRA_UNITS.items() if v[0] == dimension])
        hint = " (grams-force: write gf)" if dimension == "force" and u in ("g", "kg", "lb") else ""
        raise FingerpadError(f"{where}: unknown {dimension} unit {u!r}{hint} (use one of: {known})")
    return entry[1]


#: Force units of tribometers beyond ``fingerpad.units`` (standard gravity 9.80665 m/s^2).
EXTRA_UNITS: dict[str, tuple[str, float]] = {
    "uN": ("force", 1e-6), "µN": ("force", 1e-6), "μN": ("force", 1e-6), "cN": ("force", 1e-2),
    "gf": ("force", 9.80665e-3), "kgf": ("force", 9.80665), "lbf": ("force", 4.4482216152605),
    "ozf": ("force", 0.27801385095378125),
}
#: Spelled-out units some instruments write (LabVIEW ``unit_string``), lower case -> symbol.
UNIT_SYNONYMS: dict[str, str] = {
    "newton": "N", "newtons": "N", "millinewton": "mN", "millinewtons": "mN", "gram-force": "gf",
    "grams-force": "gf", "kilogram-force": "kgf", "pound-force": "lbf", "pounds-force": "lbf",
    "meter": "m", "meters": "m", "metre": "m", "metres": "m", "millimeter": "mm", "millimeters": "mm",
    "millimetre": "mm", "millimetres": "mm", "micrometer": "um", "micrometers": "um",
    "second": "s", "seconds": "s", "millisecond": "ms", "milliseconds": "ms",
}



QUANTITIES = ("time", "normal", "friction", "position", "velocity")
DIMENSIONS = {"time": "time", "normal": "force", "friction": "force", "position": "length",
              "velocity": "velocity"}
LABELS = {"time": "time", "normal": "normal force", "friction": "friction force",
          "position": "position", "velocity": "velocity"}
#: Column names recognised without a spec (compared after lower-casing, spaces -> "_").
ALIASES: dict[str, tuple[str, ...]] = {
    "time": ("time", "t", "timestamp", "time_s"),
    "normal": ("normal", "normal_force", "normal_load", "fn", "f_n", "fz", "load", "force_normal"),
    "friction": ("friction", "friction_force", "tangential", "tangential_force", "ft", "f_t", "ff",
                 "f_f", "fx", "force_friction"),
    "position": ("position", "pos", "x", "displacement", "disp"),
    "velocity": ("velocity", "vel", "v", "speed"),
}
DATA_SUFFIXES = (".csv", ".tsv", ".tab", ".txt", ".dat", ".xlsx", ".xlsm", ".xls", ".mat", ".tdms")
#: Files written beside recordings that are not recordings (LabVIEW's index of a .tdms).
COMPANION_SUFFIXES = (".tdms_index",)
#: Default file-name template: ``P01_glass_2.csv`` -> participant P01, sample glass, repetition 2.
DEFAULT_PATTERN = "{participant}_{sample}_{repetition}.*"
#: Files in a data folder that are never recordings (written by :func:`simulate_study`).
NOT_DATA = ("manifest.csv", "samples.csv", "truth.json")
METADATA_FIELDS = ("participant", "sample", "direction", "repetition", "session")

_HEADER_UNIT = re.compile(r"^(.*?)\s*[\[(]\s*([^\])]*?)\s*[\])]\s*$")


def split_header(text: str) -> tuple[str, str]:
    """``"Fn [mN]"`` -> ``("Fn", "mN")``; a header without a bracketed unit has unit ``""``."""
    m = _HEADER_UNIT.match(str(text).strip())
    return (m.group(1), m.group(2)) if m else (str(text).strip(), "")


def column_key(name: str) -> str:
    return re.sub(r"[\s\-_.]+", "_", str(name).strip().lower()).strip("_")


@dataclass(frozen=True)
class ColumnSpec:
    """How to read recordings: column names, units and file options.

    Attributes
    ----------
    columns
        Quantity (``time``, ``normal``, ``friction``, ``position``, ``velocity``) -> column name.
        Unnamed quantities are looked up among :data:`ALIASES`.
    units
        Quantity -> unit symbol; overrides a unit written in the header (``"Fn [mN]"``).
        Without either, values are taken as SI (N, m, s, m/s).
    pattern
        File-name template for metadata (see :func:`template_regex`).
    delimiter
        Field separator of text files; ``None`` guesses it (tab for ``.tsv``).
    decimal
        Decimal separator of text files (``"."`` or ``","``); ``None`` detects it (a comma is
        possible only with another delimiter, e.g. ``;``).
    sheet
        Excel sheet name, LabVIEW group or MATLAB struct variable; ``None`` takes the first.
    skip_rows
        Lines (rows) before the header to ignore, e.g. an instrument preamble.
    invert_normal
        Negate the normal force (instruments that report compression as negative).
    nan_policy
        ``"raise"``: a missing/non-numeric value is an error naming file and row;
        ``"drop"``: such rows are dropped.
    """

    columns: Mapping[str, str] = field(default_factory=dict)
    units: Mapping[str, str] = field(default_factory=dict)
    pattern: str | None = None
    delimiter: str | None = None
    decimal: str | None = None
    sheet: str | None = None
    skip_rows: int = 0
    invert_normal: bool = False
    nan_policy: Literal["raise", "drop"] = "raise"

    def __post_init__(self) -> None:
        for mapping, what in ((self.columns, "column"), (self.units, "unit")):
            for key in mapping:
                if key not in QUANTITIES:
                    raise FingerpadError(
                        f"unknown quantity {key!r} in the {what} mapping (use one of: {', '.join(QUANTITIES)})"
                    )
        for key, unit in self.units.items():
            unit_factor(unit, DIMENSIONS[key], where=f"unit of {key}")
        if self.nan_policy not in ("raise", "drop"):
            raise FingerpadError(f"nan_policy must be 'raise' or 'drop', got {self.nan_policy!r}")
        if not isinstance(self.skip_rows, int) or self.skip_rows < 0:
            raise FingerpadError(f"skip_rows must be a non-negative integer, got {self.skip_rows!r}")
        if self.pattern is not None:
            template_regex(self.pattern)
        if self.decimal not in (None, ".", ","):
            raise FingerpadError(f"decimal must be '.' or ',', got {self.decimal!r}")
        if self.delimiter is not None and len(self.delimiter) != 1:
            raise FingerpadError(f"delimiter must be one character (or 'tab'), got {self.delimiter!r}")

    def with_options(self, **kwargs: Any) -> ColumnSpec:
        """Copy with some options replaced; ``None`` values and empty mappings are ignored.

        ``columns``/``units`` are merged into the existing mappings (command-line options on
        top of a TOML spec).
        """
        values = {k: v for k, v in kwargs.items() if v is not None}
        for name in ("columns", "units"):
            if name in values:
                values[name] = {**getattr(self, name), **{k: v for k, v in values[name].items() if v}}
        return ColumnSpec(**{**asdict(self), **values})


def load_spec(path: str | os.PathLike[str]) -> ColumnSpec:
    """Read a :class:`ColumnSpec` from a TOML file.

    Layout::

        [columns]           # quantity = "column name"
        normal = "Fz"
        friction = "Fx"
        position = "x"
        [units]             # quantity = "unit"
        normal = "mN"
        position = "mm"
        time = "ms"
        velocity = "mm/s"
        [files]
        pattern = "{participant}_{sample}_{direction}_{repetition}.csv"
        delimiter = ";"
        decimal = ","          # or "."; detected when absent
        sheet = "data"
        skip_rows = 3
        invert_normal = false
        nan_policy = "raise"   # or "drop"

    Raises
    ------
    FingerpadError
        For a missing file, invalid TOML, or an unknown section, key or unit (naming the file).
    """
    from ..io import read_toml

    p = Path(path)
    data = read_toml(p, "column spec")
    unknown = sorted(set(data) - {"columns", "units", "files"})
    if unknown:
        raise FingerpadError(f"{p}: unknown section(s) {', '.join(unknown)} (use [columns], [units], [files])")
    files = data.get("files", {})
    bad = sorted(set(files) - {"pattern", "delimiter", "decimal", "sheet", "skip_rows", "invert_normal", "nan_policy"})
    if bad:
        raise FingerpadError(f"{p}: unknown key(s) {', '.join(bad)} in [files]")
    for section in ("columns", "units"):
        if not isinstance(data.get(section, {}), dict) or not all(
            isinstance(v, str) for v in data.get(section, {}).values()
        ):
            raise FingerpadError(f"{p}: [{section}] must map quantities to strings")
    delimiter = files.get("delimiter")
    if isinstance(delimiter, str) and delimiter.lower() in ("tab", "\\t"):
        delimiter = "\t"
    try:
        return ColumnSpec(
            columns=dict(data.get("columns", {})),
            units=dict(data.get("units", {})),
            pattern=files.get("pattern"),
            delimiter=delimiter,
            decimal=files.get("decimal"),
            sheet=files.get("sheet"),
            skip_rows=files.get("skip_rows", 0),
            invert_normal=bool(files.get("invert_normal", False)),
            nan_policy=files.get("nan_policy", "raise"),
        )
    except FingerpadError as exc:
        raise FingerpadError(f"{p}: {exc}") from None



_FIELD = re.compile(r"\{([A-Za-z_][A-Za-z0-9_]*)(?::([^{}]+))?\}")


def _literal(text: str) -> str:
    # "*" is the only wildcard; everything else is matched literally.
    return ".*".join(re.escape(part) for part in text.split("*"))


def template_regex(template: str) -> re.Pattern[str]:
    """Compile a file-name template into a regular expression.

    ``{name}`` matches one path component's worth of text (shortest match, no ``/``);
    ``{name:REGEX}`` uses ``REGEX``; ``*`` matches anything; the rest is literal. Recognised
    names are ``participant``, ``sample``, ``direction``, ``repetition`` and ``session``; others
    are matched and ignored. A template with ``/`` is matched against as many trailing path components,
    e.g. ``"{participant}/{sample}_{repetition}.csv"``.

    Examples
    --------
    >>> template_regex("{participant}_{sample}_{repetition}.csv").fullmatch("P1_flat_2.csv")["sample"]
    'flat'
    """
    parts, pos, seen = [], 0, set()
    for m in _FIELD.finditer(template):
        name, rx = m.group(1), m.group(2)
        if name in seen:
            raise FingerpadError(f"pattern {template!r}: field {{{name}}} appears twice")
        seen.add(name)
        parts.append(_literal(template[pos:m.start()]))
        parts.append(f"(?P<{name}>{rx or r'[^/]+?'})")
        pos = m.end()
    parts.append(_literal(template[pos:]))
    if "{" in template[pos:] or "}" in template[pos:]:
        raise FingerpadError(f"pattern {template!r}: unbalanced braces")
    try:
        return re.compile("".join(parts))
    except re.error as exc:
        raise FingerpadError(f"pattern {template!r}: invalid ({exc})") from None


def parse_filename(path: str | os.PathLike[str], template: str) -> dict[str, str] | None:
    """Metadata from a file path by ``template``; ``None`` if it does not match."""
    rx = template_regex(template)
    depth = template.count("/") + 1
    target = "/".join(Path(path).parts[-depth:])
    m = rx.fullmatch(target)
    if m is None:
        return None
    return {k: v for k, v in m.groupdict().items() if k in METADATA_FIELDS and v is not None}
