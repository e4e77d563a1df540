"""Finger friction measured on a tribometer: import, strokes, curves, normalisation, skin modulus.

The pipeline follows MODEL.md ("Friction", "Using it"):

1. **Import** (:func:`load_study`): CSV/TSV/Excel time series of normal and friction force,
   optionally time, position and velocity; columns and units mapped by a :class:`ColumnSpec`
   (options or a small TOML file, :func:`load_spec`); metadata (participant, sample, sliding
   direction, repetition) from a file-name template (:func:`template_regex`) or a manifest CSV.
2. **Strokes** (:func:`detect_strokes`, :func:`stroke_table`): reciprocating strokes are split at
   direction changes; start/stop transients are trimmed and the steady part gives one
   ``mu = mean(|F_t| / F_n)`` per stroke. Outliers are flagged by a robust z-score
   (:func:`flag_outliers`); the two sliding senses are kept apart.
3. **Curves** (:func:`analyse_study`): power law ``mu = k F^(n-1)`` per participant and sample
   (:func:`fingerpad.friction.fit_power_law`), normalisation by the participant's flat reference
   (``mu_tex / mu_ref`` at matched loads, which cancels the person's ridge area, MODEL.md
   "Normalisation") and the spread between people before/after.
4. **Transition and modulus**: the change of trend in the normalised friction
   (:func:`find_breakpoint`, segmented regression with a profile-likelihood or bootstrap
   interval), and the skin micro-modulus E_s per participant, either by fitting an injected
   model (:func:`estimate_skin_modulus`, default :func:`bem_texture_model` on
   :mod:`fingerpad.coupling`; its interval includes the reference curve's uncertainty and the
   clustering of strokes in files) or in closed form from the transition load
   (:func:`modulus_from_transition`, Eq. 3.6; the breakpoint interval maps to an E_s interval).
   Pure Hertz cannot follow the skin onto the texture's base, so it shows no change of trend;
   :class:`BaseContactCell` adds contact spreading over the base past the transition.

:func:`simulate_study` writes synthetic recordings with known parameters for testing.
SI units throughout (N, m, Pa, s).
"""

from __future__ import annotations

import csv
import json
import math
import os
import re
import shutil
import tempfile
import tomllib
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
import pandas as pd
from scipy import optimize, stats
from scipy.ndimage import uniform_filter1d

from .errors import FingerpadError
from .materials import DEFAULT_SKIN_POISSON, reduced_modulus
from .units import UNITS, parse_quantity

__all__ = [
    "AnalysisOptions",
    "BaseContactCell",
    "Breakpoint",
    "ColumnSpec",
    "ModelTable",
    "ModulusFit",
    "Recording",
    "SimulationConfig",
    "Stroke",
    "StrokeOptions",
    "StudyResult",
    "TextureGeometry",
    "analyse_study",
    "bin_strokes",
    "design_effect",
    "detect_strokes",
    "direction_signal",
    "estimate_skin_modulus",
    "estimate_skin_modulus_joint",
    "find_breakpoint",
    "fit_curves",
    "flag_outliers",
    "bem_texture_model",
    "hertz_texture_model",
    "texture_model",
    "load_bin_edges",
    "load_spec",
    "load_study",
    "measure_strokes",
    "modulus_from_transition",
    "move_into_place",
    "normalise",
    "parse_filename",
    "read_manifest",
    "read_recording",
    "read_textures",
    "simulate_study",
    "spread_summary",
    "spread_table",
    "stroke_table",
    "template_regex",
    "transition_load",
    "unit_factor",
]

#: A micro-scale model of the normalised friction: ``model(loads, skin_modulus) -> mu_tex/mu_ref``.
Model = Callable[[np.ndarray, float], np.ndarray]

# =============================================================================================
# units
# =============================================================================================

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
        if u in TIME_UNITS:
            return TIME_UNITS[u]
        raise FingerpadError(f"{where}: unknown time unit {u!r} (use one of: {', '.join(TIME_UNITS)})")
    if dimension == "velocity":
        num, sep, den = u.partition("/")
        if not (sep and num.strip() and den.strip()):
            raise FingerpadError(f"{where}: unknown velocity unit {u!r} (write LENGTH/TIME, e.g. mm/s)")
        return unit_factor(num, "length", where=where) / unit_factor(den, "time", where=where)
    entry = UNITS.get(u)
    if entry is None or entry[0] != dimension:
        known = ", ".join(k for k, v in UNITS.items() if v[0] == dimension)
        raise FingerpadError(f"{where}: unknown {dimension} unit {u!r} (use one of: {known})")
    return entry[1]


# =============================================================================================
# column specification
# =============================================================================================

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
DATA_SUFFIXES = (".csv", ".tsv", ".tab", ".txt", ".xlsx", ".xlsm")
#: Default file-name template: ``P01_glass_2.csv`` -> participant P01, sample glass, repetition 2.
DEFAULT_PATTERN = "{participant}_{sample}_{repetition}.*"
#: Files in a data folder that are never recordings (written by :func:`simulate_study`).
_NOT_DATA = ("manifest.csv", "samples.csv", "truth.json")
METADATA_FIELDS = ("participant", "sample", "direction", "repetition")

_HEADER_UNIT = re.compile(r"^(.*?)\s*[\[(]\s*([^\])]*?)\s*[\])]\s*$")


def _split_header(text: str) -> tuple[str, str]:
    """``"Fn [mN]"`` -> ``("Fn", "mN")``; a header without a bracketed unit has unit ``""``."""
    m = _HEADER_UNIT.match(str(text).strip())
    return (m.group(1), m.group(2)) if m else (str(text).strip(), "")


def _key(name: str) -> str:
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
    sheet
        Excel sheet name; ``None`` takes the first sheet.
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
        sheet = "data"
        skip_rows = 3
        invert_normal = false
        nan_policy = "raise"   # or "drop"

    Raises
    ------
    FingerpadError
        For a missing file, invalid TOML, or an unknown section, key or unit (naming the file).
    """
    p = Path(path)
    try:
        data = tomllib.loads(p.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise FingerpadError(f"{p}: spec file not found") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise FingerpadError(f"{p}: not a valid TOML file ({exc})") from None
    unknown = sorted(set(data) - {"columns", "units", "files"})
    if unknown:
        raise FingerpadError(f"{p}: unknown section(s) {', '.join(unknown)} (use [columns], [units], [files])")
    files = data.get("files", {})
    bad = sorted(set(files) - {"pattern", "delimiter", "sheet", "skip_rows", "invert_normal", "nan_policy"})
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
            sheet=files.get("sheet"),
            skip_rows=files.get("skip_rows", 0),
            invert_normal=bool(files.get("invert_normal", False)),
            nan_policy=files.get("nan_policy", "raise"),
        )
    except FingerpadError as exc:
        raise FingerpadError(f"{p}: {exc}") from None


# =============================================================================================
# file-name templates and manifests
# =============================================================================================

_FIELD = re.compile(r"\{([A-Za-z_][A-Za-z0-9_]*)(?::([^{}]+))?\}")


def _literal(text: str) -> str:
    # "*" is the only wildcard; everything else is matched literally.
    return ".*".join(re.escape(part) for part in text.split("*"))


def template_regex(template: str) -> re.Pattern[str]:
    """Compile a file-name template into a regular expression.

    ``{name}`` matches one path component's worth of text (shortest match, no ``/``);
    ``{name:REGEX}`` uses ``REGEX``; ``*`` matches anything; the rest is literal. Recognised
    names are ``participant``, ``sample``, ``direction`` and ``repetition``; others are matched
    and ignored. A template with ``/`` is matched against as many trailing path components,
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


# =============================================================================================
# recordings
# =============================================================================================


@dataclass(eq=False)
class Recording:
    """One recorded time series (SI units) and its metadata.

    ``rows[i]`` is the 1-based row (line) of sample ``i`` in the source file, for messages.
    """

    source: str
    normal: np.ndarray
    friction: np.ndarray
    time: np.ndarray | None = None
    position: np.ndarray | None = None
    velocity: np.ndarray | None = None
    rows: np.ndarray | None = None
    participant: str = ""
    sample: str = ""
    direction: str = ""
    repetition: str = ""

    def __post_init__(self) -> None:
        n = len(self.normal)
        for name in ("friction", "time", "position", "velocity", "rows"):
            arr = getattr(self, name)
            if arr is not None and len(arr) != n:
                raise FingerpadError(f"{self.source}: {name} has {len(arr)} samples, normal force {n}")
        if self.rows is None:
            self.rows = np.arange(1, n + 1)

    def __len__(self) -> int:
        return len(self.normal)

    def row(self, index: int) -> int:
        """File row of sample ``index``."""
        return int(self.rows[index])  # type: ignore[index]


def _sniff_delimiter(header: str) -> str:
    counts = {d: header.count(d) for d in ("\t", ";", ",")}
    best = max(counts, key=counts.get)  # type: ignore[arg-type]
    return best if counts[best] else ","


def _read_text_rows(path: Path, spec: ColumnSpec) -> tuple[list[str], list[tuple[int, list[str]]]]:
    try:
        text = path.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise FingerpadError(f"{path}: file not found") from None
    except UnicodeDecodeError:
        raise FingerpadError(f"{path}: not a UTF-8 text file (is it a binary or Excel file?)") from None
    numbered = [
        (i + 1, line) for i, line in enumerate(text.splitlines())
        if i >= spec.skip_rows and line.strip() and not line.lstrip().startswith("#")
    ]
    if not numbered:
        raise FingerpadError(f"{path}: no header row")
    delim = spec.delimiter or ("\t" if path.suffix.lower() in (".tsv", ".tab") else _sniff_delimiter(numbered[0][1]))
    parsed = csv.reader([line for _, line in numbered], delimiter=delim)
    rows = [(n, cells) for (n, _), cells in zip(numbered, parsed)]
    return [c.strip() for c in rows[0][1]], rows[1:]


def _read_excel_rows(path: Path, spec: ColumnSpec) -> tuple[list[str], list[tuple[int, list[str]]]]:
    try:
        import openpyxl
    except ImportError:  # pragma: no cover - openpyxl ships with the environment
        raise FingerpadError(f"{path}: reading Excel files needs openpyxl (pip install openpyxl)") from None
    if not path.exists():
        raise FingerpadError(f"{path}: file not found")
    try:
        book = openpyxl.load_workbook(path, read_only=True, data_only=True)
    except Exception as exc:  # openpyxl raises many types for a corrupt workbook
        raise FingerpadError(f"{path}: cannot open as an Excel workbook ({type(exc).__name__}: {exc})") from None
    try:
        if spec.sheet is None:
            sheet = book.worksheets[0]
        elif spec.sheet in book.sheetnames:
            sheet = book[spec.sheet]
        else:
            raise FingerpadError(f"{path}: no sheet {spec.sheet!r} (sheets: {', '.join(book.sheetnames)})")
        rows = []
        for i, values in enumerate(sheet.iter_rows(values_only=True), start=1):
            if i <= spec.skip_rows:
                continue
            cells = ["" if v is None else str(v) for v in values]
            if not any(c.strip() for c in cells) or (cells and cells[0].lstrip().startswith("#")):
                continue
            rows.append((i, cells))
    finally:
        book.close()
    if not rows:
        raise FingerpadError(f"{path}: no header row")
    return [c.strip() for c in rows[0][1]], rows[1:]


def _read_rows(path: Path, spec: ColumnSpec) -> tuple[list[str], list[tuple[int, list[str]]]]:
    suffix = path.suffix.lower()
    if suffix in (".xlsx", ".xlsm"):
        return _read_excel_rows(path, spec)
    if suffix == ".xls":
        raise FingerpadError(f"{path}: old .xls workbooks are not supported; save it as .xlsx or CSV")
    return _read_text_rows(path, spec)


def _find_columns(path: Path, header: list[str], spec: ColumnSpec) -> dict[str, int]:
    keys = [_key(_split_header(h)[0]) for h in header]
    full = [_key(h) for h in header]
    index: dict[str, int] = {}
    for q in QUANTITIES:
        wanted = spec.columns.get(q)
        if wanted:
            k = _key(wanted)
            if k in full:
                index[q] = full.index(k)
            elif _key(_split_header(wanted)[0]) in keys:
                index[q] = keys.index(_key(_split_header(wanted)[0]))
            else:
                raise FingerpadError(
                    f"{path}: column {wanted!r} for the {LABELS[q]} not found (columns: {', '.join(header)})"
                )
            continue
        for alias in ALIASES[q]:
            if alias in keys and keys.index(alias) not in index.values():
                index[q] = keys.index(alias)
                break
    for q in ("normal", "friction"):
        if q not in index:
            raise FingerpadError(
                f"{path}: no {LABELS[q]} column (looked for {', '.join(ALIASES[q])}; columns: "
                f"{', '.join(header) or 'none'}); name it with --{q}-column or in the spec"
            )
    return index


def read_recording(
    path: str | os.PathLike[str],
    spec: ColumnSpec | None = None,
    *,
    participant: str = "",
    sample: str = "",
    direction: str = "",
    repetition: str = "",
) -> Recording:
    """Read one recording (CSV/TSV/Excel) into SI units.

    Parameters
    ----------
    path
        The data file.
    spec
        Column names, units and options (:class:`ColumnSpec`); defaults recognise common names.
    participant, sample, direction, repetition
        Metadata attached to the recording.

    Raises
    ------
    FingerpadError
        Naming the file (and the row where one is at fault) for a missing column, unknown unit,
        non-numeric or missing value, time that does not increase, or too few rows.
    """
    spec = spec or ColumnSpec()
    p = Path(path)
    header, rows = _read_rows(p, spec)
    index = _find_columns(p, header, spec)
    factors = {
        q: unit_factor(spec.units.get(q) or _split_header(header[i])[1], DIMENSIONS[q],
                       where=f"{p}, column {header[i]!r}")
        for q, i in index.items()
    }
    lines = np.array([n for n, _ in rows], dtype=int)
    values = {q: np.empty(len(rows)) for q in index}
    for j, (line, cells) in enumerate(rows):
        for q, i in index.items():
            cell = cells[i].strip() if i < len(cells) else ""
            if cell == "":
                values[q][j] = math.nan
                continue
            try:
                values[q][j] = float(cell)
            except ValueError:
                raise FingerpadError(
                    f"{p}, row {line}: cannot read {cell!r} in column {header[i]!r} as a number"
                ) from None
    finite = np.ones(len(rows), dtype=bool)
    for q, arr in values.items():
        ok = np.isfinite(arr)
        if spec.nan_policy == "raise" and not ok.all():
            j = int(np.flatnonzero(~ok)[0])
            raise FingerpadError(
                f"{p}, row {lines[j]}: missing or non-finite value in column {header[index[q]]!r} "
                "(use nan_policy = \"drop\" to skip such rows)"
            )
        finite &= ok
    if not finite.all():
        lines = lines[finite]
        values = {q: arr[finite] for q, arr in values.items()}
    if len(lines) < 10:
        raise FingerpadError(f"{p}: only {len(lines)} data row(s); a recording needs at least 10")
    data = {q: values[q] * factors[q] for q in values}
    if spec.invert_normal:
        data["normal"] = -data["normal"]
    if np.median(data["normal"]) < 0:
        raise FingerpadError(
            f"{p}: the normal force is mostly negative; set invert_normal = true in the spec (or --invert-normal)"
        )
    t = data.get("time")
    if t is not None:
        bad = np.flatnonzero(np.diff(t) <= 0)
        if bad.size:
            j = int(bad[0]) + 1
            raise FingerpadError(
                f"{p}, row {lines[j]}: time does not increase ({t[j]:.6g} s after {t[j - 1]:.6g} s)"
            )
    return Recording(
        source=str(p), normal=data["normal"], friction=data["friction"], time=t,
        position=data.get("position"), velocity=data.get("velocity"), rows=lines,
        participant=str(participant), sample=str(sample), direction=str(direction),
        repetition=str(repetition),
    )


def _header_keys(path: Path) -> list[str]:
    """Keys of the first non-comment line of a text file (cheap manifest detection)."""
    if path.suffix.lower() not in (".csv", ".tsv", ".tab", ".txt"):
        return []
    try:
        with path.open(encoding="utf-8-sig") as fh:
            for line in fh:
                if line.strip() and not line.lstrip().startswith("#"):
                    return [_key(c) for c in next(csv.reader([line], delimiter=_sniff_delimiter(line)))]
    except (OSError, UnicodeDecodeError):
        return []
    return []


def _is_manifest(path: Path) -> bool:
    keys = _header_keys(path)
    return ("file" in keys or "path" in keys) and "participant" in keys


def read_manifest(path: str | os.PathLike[str], spec: ColumnSpec | None = None) -> list[Recording]:
    """Read the recordings listed in a manifest CSV.

    Columns: ``file`` (or ``path``, relative to the manifest's folder), ``participant``,
    ``sample``, optional ``direction`` and ``repetition``; other columns are ignored.

    Raises
    ------
    FingerpadError
        Naming the manifest and row for a missing column, value or data file.
    """
    p = Path(path)
    header, rows = _read_text_rows(p, ColumnSpec())
    keys = [_key(h) for h in header]
    file_col = "file" if "file" in keys else "path" if "path" in keys else None
    missing = [c for c in (file_col or "file", "participant", "sample") if c not in keys]
    if missing:
        raise FingerpadError(f"{p}: manifest lacks column(s) {', '.join(missing)} (columns: {', '.join(header)})")
    recordings = []
    for line, cells in rows:
        rec = {k: (cells[i].strip() if i < len(cells) else "") for i, k in enumerate(keys)}
        for col in (file_col, "participant", "sample"):
            if not rec.get(col):
                raise FingerpadError(f"{p}, row {line}: empty {col!r}")
        data = (p.parent / rec[file_col]) if not Path(rec[file_col]).is_absolute() else Path(rec[file_col])  # type: ignore[index]
        if not data.is_file():
            raise FingerpadError(f"{p}, row {line}: data file {rec[file_col]!r} not found")  # type: ignore[index]
        recordings.append(read_recording(
            data, spec, participant=rec["participant"], sample=rec["sample"],
            direction=rec.get("direction", ""), repetition=rec.get("repetition", ""),
        ))
    if not recordings:
        raise FingerpadError(f"{p}: manifest lists no files")
    return recordings


def load_study(
    inputs: Sequence[str | os.PathLike[str]],
    spec: ColumnSpec | None = None,
    *,
    pattern: str | None = None,
) -> list[Recording]:
    """Read every recording named by ``inputs``.

    Each input is a manifest CSV, a data file (metadata from its name by the template), or a
    folder: its ``manifest.csv`` if present, else every data file whose name matches the
    template (others are skipped).

    Parameters
    ----------
    inputs
        Files and folders.
    spec
        Column mapping and options; ``spec.pattern`` is the template unless ``pattern`` is given.
    pattern
        File-name template (:func:`template_regex`), default :data:`DEFAULT_PATTERN`.

    Raises
    ------
    FingerpadError
        For a missing path, a file name that does not match, a folder without matching files,
        or any error reading a file.
    """
    spec = spec or ColumnSpec()
    template = pattern or spec.pattern or DEFAULT_PATTERN
    template_regex(template)

    def from_name(f: Path, meta: Mapping[str, str]) -> Recording:
        for need in ("participant", "sample"):
            if not meta.get(need):
                raise FingerpadError(
                    f"{f}: the pattern {template!r} gives no {need}; add {{{need}}} to it or use a manifest"
                )
        return read_recording(f, spec, **meta)

    recordings: list[Recording] = []
    if not inputs:
        raise FingerpadError("no data given")
    for item in inputs:
        p = Path(item)
        if p.is_dir():
            if (p / "manifest.csv").is_file():
                recordings += read_manifest(p / "manifest.csv", spec)
                continue
            found = 0
            for f in sorted(p.iterdir()):
                if (not f.is_file() or f.suffix.lower() not in DATA_SUFFIXES or f.name in _NOT_DATA
                        or _is_manifest(f)):
                    continue
                meta = parse_filename(f, template)
                if meta is not None:
                    recordings.append(from_name(f, meta))
                    found += 1
            if not found:
                raise FingerpadError(f"{p}: no manifest.csv and no data file matching the pattern {template!r}")
        elif p.is_file():
            if _is_manifest(p):
                recordings += read_manifest(p, spec)
                continue
            meta = parse_filename(p, template)
            if meta is None:
                raise FingerpadError(f"{p}: file name does not match the pattern {template!r}")
            recordings.append(from_name(p, meta))
        else:
            raise FingerpadError(f"{p}: no such file or folder")
    unique: dict[str, Recording] = {}
    for rec in recordings:
        unique.setdefault(os.path.realpath(rec.source), rec)
    return list(unique.values())


# =============================================================================================
# strokes
# =============================================================================================


@dataclass(frozen=True)
class StrokeOptions:
    """Stroke detection and steady-state extraction.

    Attributes
    ----------
    trim
        Fraction of each stroke dropped at its start and at its end (static-friction peak,
        acceleration, deceleration), in [0, 0.45].
    deadband
        Standstill threshold as a fraction of the 90th percentile of |direction signal|;
        a sense change needs the signal to cross the opposite threshold (hysteresis).
    smooth
        Samples in the moving average applied before differentiating position (or to the
        friction force when it gives the direction).
    min_stroke_fraction
        Strokes shorter than this fraction of the median stroke are dropped (fragments).
    min_strokes
        Fewest usable strokes a file must give.
    min_load
        Normal force (N) below which a sample counts as lifted off and is ignored.
    direction_source
        ``"auto"`` (velocity, else position, else friction sign) or one of ``"velocity"``,
        ``"position"``, ``"friction"``.
    """

    trim: float = 0.2
    deadband: float = 0.1
    smooth: int = 5
    min_stroke_fraction: float = 0.3
    min_strokes: int = 2
    min_load: float = 0.01
    direction_source: Literal["auto", "velocity", "position", "friction"] = "auto"

    def __post_init__(self) -> None:
        if not 0.0 <= self.trim <= 0.45:
            raise FingerpadError(f"trim must lie in [0, 0.45], got {self.trim!r}")
        if not 0.0 < self.deadband < 1.0:
            raise FingerpadError(f"deadband must lie in (0, 1), got {self.deadband!r}")
        if self.smooth < 1 or self.min_strokes < 1:
            raise FingerpadError("smooth and min_strokes must be at least 1")
        if self.direction_source not in ("auto", "velocity", "position", "friction"):
            raise FingerpadError(f"unknown direction source {self.direction_source!r}")
        if not self.min_load >= 0:
            raise FingerpadError(f"min_load must be non-negative, got {self.min_load!r}")


@dataclass(frozen=True)
class Stroke:
    """One stroke: sample ranges ``[start, stop)`` and its steady part, and the sense (+1/-1)."""

    start: int
    stop: int
    steady_start: int
    steady_stop: int
    sense: int


def direction_signal(rec: Recording, options: StrokeOptions = StrokeOptions()) -> tuple[np.ndarray, str]:
    """The signal whose sign gives the sliding sense, and its name.

    Velocity if recorded; else the derivative of the (smoothed) position; else minus the
    smoothed friction force: the force on the finger opposes its motion, so sense ``+`` (as with
    a positive velocity) is where ``F_t < 0``. (A force recorded on the sample has the other
    sign; the two senses then swap labels but stay apart.)
    """
    src = options.direction_source
    if src in ("auto", "velocity") and rec.velocity is not None:
        return rec.velocity, "velocity"
    if src == "velocity":
        raise FingerpadError(f"{rec.source}: no velocity column (direction source 'velocity')")
    if src in ("auto", "position") and rec.position is not None:
        pos = uniform_filter1d(rec.position, size=options.smooth, mode="nearest")
        return (np.gradient(pos, rec.time) if rec.time is not None else np.gradient(pos)), "position"
    if src == "position":
        raise FingerpadError(f"{rec.source}: no position column (direction source 'position')")
    return -uniform_filter1d(rec.friction, size=options.smooth, mode="nearest"), "friction"


def detect_strokes(rec: Recording, options: StrokeOptions = StrokeOptions()) -> list[Stroke]:
    """Split a reciprocating recording into strokes at direction changes.

    The sense is the sign of :func:`direction_signal` with hysteresis: inside the dead band
    the previous sense holds, so noise at a reversal cannot split a stroke. A stroke spans the
    samples moving faster than the dead band; ``trim`` of it is dropped at each end.

    Raises
    ------
    FingerpadError
        If the direction signal is constant (no motion).
    """
    signal, name = direction_signal(rec, options)
    scale = float(np.percentile(np.abs(signal), 90))
    if not scale > 0:
        raise FingerpadError(f"{rec.source}: no motion found (the {name} signal is constant)")
    thr = options.deadband * scale
    raw = np.where(signal > thr, 1, np.where(signal < -thr, -1, 0))
    last = np.where(raw != 0, np.arange(raw.size), 0)
    np.maximum.accumulate(last, out=last)
    state = raw[last]
    bounds = np.flatnonzero(np.diff(state) != 0) + 1
    candidates = []
    for a, b in zip(np.r_[0, bounds], np.r_[bounds, state.size]):
        s = int(state[a])
        if s == 0:
            continue
        moving = np.flatnonzero(raw[a:b] == s)
        candidates.append((a + int(moving[0]), a + int(moving[-1]) + 1, s))
    if not candidates:
        return []
    median = float(np.median([b - a for a, b, _ in candidates]))
    strokes = []
    for a, b, s in candidates:
        length = b - a
        if length < max(5, options.min_stroke_fraction * median):
            continue
        cut = int(round(options.trim * length))
        if b - cut - (a + cut) < 3:
            continue
        strokes.append(Stroke(a, b, a + cut, b - cut, s))
    return strokes


STROKE_COLUMNS = [
    "file", "participant", "sample", "direction", "repetition", "stroke", "sense", "row_start",
    "row_end", "load", "load_sd", "mu", "mu_sd", "n_samples", "speed",
]


def measure_strokes(rec: Recording, options: StrokeOptions = StrokeOptions()) -> pd.DataFrame:
    """Steady-state friction of every stroke of one recording (one row per stroke).

    Columns: file, metadata, ``stroke`` (1-based), ``sense`` (``"+"``/``"-"``), ``row_start``,
    ``row_end`` (file rows of the stroke), ``load`` (mean F_n, N), ``mu`` (mean |F_t|/F_n over
    the steady part), their standard deviations, ``n_samples`` and ``speed`` (m/s, NaN unknown).

    Raises
    ------
    FingerpadError
        If fewer than ``options.min_strokes`` usable strokes are found (naming file and rows).
    """
    strokes = detect_strokes(rec, options)
    signal, source = direction_signal(rec, options)
    rows = []
    for st in strokes:
        sl = slice(st.steady_start, st.steady_stop)
        fn, ft = rec.normal[sl], rec.friction[sl]
        ok = fn > options.min_load
        if ok.sum() < 3:
            continue  # finger lifted off during the stroke
        ratio = np.abs(ft[ok]) / fn[ok]
        speed = float(np.mean(np.abs(signal[sl]))) if source != "friction" else math.nan
        rows.append({
            "file": rec.source, "participant": rec.participant, "sample": rec.sample,
            "direction": rec.direction, "repetition": rec.repetition, "stroke": len(rows) + 1,
            "sense": "+" if st.sense > 0 else "-", "row_start": rec.row(st.start),
            "row_end": rec.row(st.stop - 1), "load": float(fn[ok].mean()),
            "load_sd": float(fn[ok].std(ddof=1)), "mu": float(ratio.mean()),
            "mu_sd": float(ratio.std(ddof=1)), "n_samples": int(ok.sum()), "speed": speed,
        })
    if len(rows) < options.min_strokes:
        raise FingerpadError(
            f"{rec.source}: found {len(rows)} usable stroke(s) in rows {rec.row(0)}-{rec.row(len(rec) - 1)}, "
            f"need at least {options.min_strokes} (direction from {source}; check the columns or --min-strokes)"
        )
    return pd.DataFrame(rows, columns=STROKE_COLUMNS)


def stroke_table(recordings: Iterable[Recording], options: StrokeOptions = StrokeOptions()) -> pd.DataFrame:
    """:func:`measure_strokes` over all recordings, concatenated."""
    frames = [measure_strokes(rec, options) for rec in recordings]
    if not frames:
        raise FingerpadError("no recordings to analyse")
    return pd.concat(frames, ignore_index=True)


GROUP = ["participant", "sample", "direction"]


def _robust_trend(x: np.ndarray, y: np.ndarray, group: np.ndarray) -> np.ndarray:
    """Robust trend of y(x): a quadratic (linear below 8 points) plus an offset per ``group``
    level, fitted with a soft-L1 loss so that a few outliers barely pull it."""
    deg = 2 if x.size >= 8 else 1
    xc = x - x.mean()
    levels = np.unique(group)
    design = np.column_stack([xc**d for d in range(deg, 0, -1)] + [(group == lv).astype(float) for lv in levels])
    coef, *_ = np.linalg.lstsq(design, y, rcond=None)
    r0 = y - design @ coef
    scale = max(1.4826 * float(np.median(np.abs(r0 - np.median(r0)))), 1e-6)
    res = optimize.least_squares(lambda c: y - design @ c, coef, loss="soft_l1", f_scale=scale)
    return design @ res.x


def flag_outliers(strokes: pd.DataFrame, threshold: float = 3.5, min_strokes: int = 6) -> pd.DataFrame:
    """Flag strokes whose mu departs from the trend of their group (robust z-score).

    Within each participant, sample and direction, ``log mu`` against ``log F`` gets a robust
    (soft-L1) quadratic trend with a separate level per sliding sense -- it follows a power
    law, the gentle bend of a contact transition and a direction asymmetry, while a few
    outliers barely pull it. Residuals are scaled by their median absolute deviation,
    ``z = 0.6745 (r - median r) / MAD`` (Iglewicz-Hoaglin). Groups of fewer than
    ``min_strokes`` strokes are not flagged.

    Returns
    -------
    DataFrame
        A copy with ``robust_z`` and ``outlier`` (``|z| > threshold``) columns.
    """
    df = strokes.copy()
    df["robust_z"] = 0.0
    df["outlier"] = False
    for _, g in df.groupby(GROUP, sort=False):
        if len(g) < max(min_strokes, 5):
            continue
        x = np.log(g["load"].to_numpy())
        y = np.log(np.clip(g["mu"].to_numpy(), 1e-12, None))
        r = y - _robust_trend(x, y, g["sense"].to_numpy())
        mad = float(np.median(np.abs(r - np.median(r))))
        z = np.zeros(r.size) if mad == 0 else 0.6745 * (r - np.median(r)) / mad
        df.loc[g.index, "robust_z"] = z
        df.loc[g.index, "outlier"] = np.abs(z) > threshold
    return df


def load_bin_edges(loads: np.ndarray, n_bins: int) -> np.ndarray:
    """Log-spaced bin edges spanning ``loads`` (shared by the whole study, so bins compare)."""
    lo, hi = float(np.min(loads)), float(np.max(loads))
    if not (lo > 0 and hi > lo):
        return np.array([lo * 0.9, hi * 1.1]) if lo > 0 else np.array([0.0, max(hi, 1e-3)])
    return np.geomspace(lo * (1 - 1e-9), hi * (1 + 1e-9), int(n_bins) + 1)


def _bin_index(loads: np.ndarray, edges: np.ndarray) -> np.ndarray:
    return np.clip(np.searchsorted(edges, loads, side="right") - 1, 0, len(edges) - 2)


def bin_strokes(strokes: pd.DataFrame, edges: np.ndarray) -> pd.DataFrame:
    """Mean mu (and mu_norm) per participant, sample, direction, sense and load bin.

    Outliers are left out. ``sense`` is ``"+"``, ``"-"`` or ``"both"`` (pooled).
    """
    df = strokes[~strokes["outlier"]]
    df = pd.concat([df, df.assign(sense="both")], ignore_index=True)
    df = df.assign(bin=_bin_index(df["load"].to_numpy(), edges))
    agg: dict[str, tuple[str, str]] = {
        "load": ("load", "median"), "n": ("mu", "size"), "mu": ("mu", "mean"), "mu_sd": ("mu", "std"),
    }
    if "mu_norm" in df:
        agg.update(mu_norm=("mu_norm", "mean"), mu_norm_sd=("mu_norm", "std"))
    out = df.groupby(GROUP + ["sense", "bin"], sort=True).agg(**agg).reset_index()
    out["mu_sem"] = out["mu_sd"] / np.sqrt(out["n"])
    if "mu_norm" in out:
        out["mu_norm_sem"] = out["mu_norm_sd"] / np.sqrt(out["n"])
    out["bin_low"] = edges[out["bin"].to_numpy()]
    out["bin_high"] = edges[out["bin"].to_numpy() + 1]
    return out


# =============================================================================================
# power-law curves and normalisation
# =============================================================================================


def _fit_power(loads: np.ndarray, mu: np.ndarray) -> Any:
    from .friction import fit_power_law  # written alongside; imported late to keep imports light

    return fit_power_law(np.asarray(loads, float), np.asarray(mu, float))


def _ci(obj: Any, name: str) -> tuple[float, float]:
    ci = getattr(obj, f"{name}_ci", None)
    if ci is None:
        return math.nan, math.nan
    lo, hi = ci
    return float(lo), float(hi)


def _fit_row(fit: Any) -> dict[str, float]:
    k_lo, k_hi = _ci(fit, "k")
    n_lo, n_hi = _ci(fit, "n")
    return {
        "k": float(fit.k), "k_se": float(getattr(fit, "k_stderr", math.nan)), "k_ci_low": k_lo, "k_ci_high": k_hi,
        "n": float(fit.n), "n_se": float(getattr(fit, "n_stderr", math.nan)), "n_ci_low": n_lo, "n_ci_high": n_hi,
    }


def _fit_group(g: pd.DataFrame, min_strokes: int) -> tuple[Any | None, str]:
    g = g[~g["outlier"]]
    if len(g) < min_strokes or g["load"].nunique() < 3:
        return None, f"{len(g)} usable strokes at {g['load'].nunique()} loads, need {min_strokes} at 3 or more"
    try:
        return _fit_power(g["load"].to_numpy(), g["mu"].to_numpy()), ""
    except FingerpadError as exc:
        return None, str(exc)


def fit_curves(strokes: pd.DataFrame, min_strokes: int = 4) -> tuple[pd.DataFrame, dict[tuple[str, ...], Any]]:
    """Power-law fits ``mu = k F^(n-1)`` per participant, sample, direction and sense.

    Returns
    -------
    table, fits
        A table (one row per group and sense ``+``/``-``/``both``, with ``k``, ``n``, standard
        errors, CIs, ``n_strokes``, ``note``) and the fit objects keyed by
        ``(participant, sample, direction, sense)``.
    """
    rows, fits = [], {}
    for key, g in strokes.groupby(GROUP, sort=True):
        for sense in ("+", "-", "both"):
            part = g if sense == "both" else g[g["sense"] == sense]
            fit, note = _fit_group(part, min_strokes)
            row = dict(zip(GROUP, key), sense=sense, n_strokes=int((~part["outlier"]).sum()), note=note)
            if fit is not None:
                fits[(*key, sense)] = fit
                row.update(_fit_row(fit))
                row["load_min"] = float(part["load"].min())
                row["load_max"] = float(part["load"].max())
            rows.append(row)
    return pd.DataFrame(rows), fits


def normalise(strokes: pd.DataFrame, reference: str, min_strokes: int = 4) -> tuple[pd.DataFrame, dict[tuple[str, str], Any]]:
    """Divide every stroke's mu by the participant's reference curve at the same load.

    ``mu_norm = mu / mu_ref(F)`` with ``mu_ref`` the power law fitted to the participant's
    strokes on the flat ``reference`` sample (all its directions pooled; the same sense where
    that fit exists, else both senses). By MODEL.md "Normalisation", ``mu_norm`` estimates
    ``A_re,tex / A_re,ref`` and no longer depends on the person's ridge area.

    Returns
    -------
    strokes, reference_fits
        A copy with ``mu_ref``, ``mu_norm`` and ``ref_extrapolated`` (load outside the
        reference's measured range by more than 25 %), and the fits keyed by (participant, sense).

    Raises
    ------
    FingerpadError
        If the reference sample is absent, or a participant has no (or too few) strokes on it.
    """
    samples = sorted(set(strokes["sample"]))
    if reference not in samples:
        raise FingerpadError(f"reference sample {reference!r} is not in the data (samples: {', '.join(samples)})")
    df = strokes.copy()
    df["mu_ref"] = math.nan
    df["ref_extrapolated"] = False
    ref_fits: dict[tuple[str, str], Any] = {}
    for participant, g in df.groupby("participant", sort=True):
        ref = g[g["sample"] == reference]
        if ref.empty:
            files = ", ".join(sorted({Path(f).name for f in g["file"]}))
            raise FingerpadError(
                f"participant {participant!r} has no recordings of the reference sample {reference!r} ({files})"
            )
        for sense in ("+", "-", "both"):
            part = ref if sense == "both" else ref[ref["sense"] == sense]
            fit, note = _fit_group(part, min_strokes)
            if fit is not None:
                ref_fits[(participant, sense)] = fit
        if (participant, "both") not in ref_fits:
            files = ", ".join(sorted({Path(f).name for f in ref["file"]}))
            raise FingerpadError(
                f"participant {participant!r}: cannot fit the reference sample {reference!r} ({note}; files: {files})"
            )
        lo, hi = ref["load"].min() / 1.25, ref["load"].max() * 1.25
        for sense, sub in g.groupby("sense"):
            fit = ref_fits.get((participant, sense), ref_fits[(participant, "both")])
            loads = sub["load"].to_numpy()
            df.loc[sub.index, "mu_ref"] = np.asarray(fit(loads), dtype=float)
            df.loc[sub.index, "ref_extrapolated"] = (loads < lo) | (loads > hi)
    df["mu_norm"] = df["mu"] / df["mu_ref"]
    return df, ref_fits


def spread_table(strokes: pd.DataFrame, edges: np.ndarray, reference: str) -> pd.DataFrame:
    """Spread between participants per sample, direction and load bin, before/after normalising.

    Each participant contributes the mean of its (non-outlier) strokes in the bin; the table
    gives the number of participants, mean, standard deviation and coefficient of variation
    (``cv = sd / mean``) of raw ``mu`` and of ``mu_norm`` (left NaN for the reference, which is 1
    by construction).
    """
    df = strokes[~strokes["outlier"]]
    df = df.assign(bin=_bin_index(df["load"].to_numpy(), edges))
    per = df.groupby(GROUP + ["bin"]).agg(mu=("mu", "mean"), mu_norm=("mu_norm", "mean")).reset_index()
    rows = []
    for (sample, direction, b), g in per.groupby(["sample", "direction", "bin"], sort=True):
        row: dict[str, Any] = {"sample": sample, "direction": direction, "bin": int(b),
                               "bin_low": edges[b], "bin_high": edges[b + 1], "n_participants": len(g)}
        for col in ("mu", "mu_norm"):
            v = g[col].to_numpy()
            mean = float(v.mean())
            sd = float(v.std(ddof=1)) if len(v) > 1 else math.nan
            if col == "mu_norm" and sample == reference:
                mean = sd = math.nan
            row[f"{col}_mean"], row[f"{col}_sd"] = mean, sd
            row[f"{col}_cv"] = sd / mean if mean else math.nan
        rows.append(row)
    return pd.DataFrame(rows)


def spread_summary(spread: pd.DataFrame, reference: str, min_participants: int = 2) -> pd.DataFrame:
    """Mean coefficient of variation over load bins, before and after normalisation.

    ``reduction = 1 - cv_norm / cv_raw`` (positive when normalising brings people together).
    Only bins with at least ``min_participants`` participants count.
    """
    rows = []
    if spread.empty:
        return pd.DataFrame(columns=["sample", "direction", "n_bins", "cv_raw", "cv_norm", "reduction"])
    ok = spread[spread["n_participants"] >= min_participants]
    for (sample, direction), g in ok.groupby(["sample", "direction"], sort=True):
        cv_raw = float(g["mu_cv"].mean())
        cv_norm = float(g["mu_norm_cv"].mean()) if sample != reference else math.nan
        rows.append({"sample": sample, "direction": direction, "is_reference": sample == reference,
                     "n_bins": len(g), "cv_raw": cv_raw, "cv_norm": cv_norm,
                     "reduction": 1.0 - cv_norm / cv_raw if cv_raw > 0 else math.nan})
    return pd.DataFrame(rows)


# =============================================================================================
# change of trend (segmented regression)
# =============================================================================================


@dataclass(frozen=True)
class Breakpoint:
    """A continuous two-segment (hinge) fit ``y = c + s1 min(x - x0, 0) + s2 max(x - x0, 0)``.

    ``x`` is ``log F`` and ``y`` ``log value`` when ``space == "log"``, else F and value.

    Attributes
    ----------
    load
        Breakpoint load F_b, N.
    ci_low, ci_high
        Confidence interval of F_b at ``level`` (profile likelihood or bootstrap).
    slope_below, slope_above
        Segment slopes (in log space: local exponents of value vs load).
    level_at_break
        Fitted y at the breakpoint (the hinge height ``c``).
    rss, rss_line
        Residual sums of squares of the hinge and of one straight line.
    p_value
        Approximate F-test of the hinge against one line (2 extra parameters; the breakpoint
        is not identified under the null, so treat it as indicative).
    """

    load: float
    ci_low: float
    ci_high: float
    slope_below: float
    slope_above: float
    level_at_break: float
    rss: float
    rss_line: float
    p_value: float
    n: int
    space: str
    method: str
    level: float

    def predict(self, loads: np.ndarray) -> np.ndarray:
        """The fitted hinge at ``loads`` (in value units)."""
        f = np.asarray(loads, dtype=float)
        x = np.log(f) if self.space == "log" else f
        x0 = math.log(self.load) if self.space == "log" else self.load
        y = self.level_at_break + self.slope_below * np.minimum(x - x0, 0) + self.slope_above * np.maximum(x - x0, 0)
        return np.exp(y) if self.space == "log" else y


def _hinge_fit(x: np.ndarray, y: np.ndarray, x0: float) -> tuple[float, np.ndarray]:
    design = np.column_stack([np.ones_like(x), np.minimum(x - x0, 0.0), np.maximum(x - x0, 0.0)])
    coef, *_ = np.linalg.lstsq(design, y, rcond=None)
    r = y - design @ coef
    return float(r @ r), coef


def _hinge_profile(x: np.ndarray, y: np.ndarray, grid: np.ndarray, trend: str = "any") -> np.ndarray:
    """RSS of the hinge at each candidate breakpoint; ``inf`` where the slope change has the
    wrong sign for ``trend`` (``"steeper"``: slope_above > slope_below, ``"flatter"``: <)."""
    out = np.empty(grid.size)
    for i, g in enumerate(grid):
        rss, coef = _hinge_fit(x, y, g)
        bad = (trend == "steeper" and coef[2] <= coef[1]) or (trend == "flatter" and coef[2] >= coef[1])
        out[i] = math.inf if bad else rss
    return out


def _hinge_grid(x: np.ndarray, min_side: int, n_grid: int) -> np.ndarray:
    xs = np.sort(x)
    lo, hi = xs[min_side - 1], xs[-min_side]
    inner = xs[(xs >= lo) & (xs <= hi)]
    return np.unique(np.r_[np.linspace(lo, hi, n_grid), inner])


def find_breakpoint(
    loads: Sequence[float] | np.ndarray,
    values: Sequence[float] | np.ndarray,
    *,
    space: Literal["log", "linear"] = "log",
    method: Literal["profile", "bootstrap"] = "profile",
    trend: Literal["any", "steeper", "flatter"] = "any",
    level: float = 0.95,
    n_boot: int = 200,
    seed: int = 0,
    min_side: int = 3,
    n_grid: int = 200,
) -> Breakpoint:
    """Locate the change of trend of ``values`` vs load by segmented regression.

    The breakpoint ``x0`` minimises the residual sum of squares of a continuous two-segment
    line (profiled over a grid that leaves at least ``min_side`` points on each side, then
    refined). Its confidence interval is either

    * ``"profile"``: the ``x0`` with ``n log(RSS(x0)/RSS_min) <= chi2_1(level)`` (likelihood
      ratio with the noise variance profiled out), or
    * ``"bootstrap"``: percentiles of ``x0`` refitted on ``n_boot`` case resamples.

    Parameters
    ----------
    loads, values
        Loads (N, > 0) and the quantity (e.g. normalised friction; > 0 in log space).
    space
        ``"log"`` (log-log, slopes are power-law exponents) or ``"linear"``.
    trend
        Admit only breakpoints where the curve gets ``"steeper"`` (the contact transition on a
        texture: friction rises faster once the skin touches the base) or ``"flatter"``;
        ``"any"`` takes the largest change. A curve may bend twice in the measured range (onset
        of base contact, then saturation towards full contact); the sign picks the one wanted.

    Raises
    ------
    FingerpadError
        For fewer than ``2 min_side + 1`` points, non-finite or non-positive input.
    """
    f = np.asarray(loads, dtype=float)
    v = np.asarray(values, dtype=float)
    if f.shape != v.shape or f.ndim != 1:
        raise FingerpadError("loads and values must be 1-D arrays of the same length")
    if space not in ("log", "linear"):
        raise FingerpadError(f"space must be 'log' or 'linear', got {space!r}")
    if method not in ("profile", "bootstrap"):
        raise FingerpadError(f"method must be 'profile' or 'bootstrap', got {method!r}")
    if trend not in ("any", "steeper", "flatter"):
        raise FingerpadError(f"trend must be 'any', 'steeper' or 'flatter', got {trend!r}")
    if not (np.all(np.isfinite(f)) and np.all(np.isfinite(v)) and np.all(f > 0)):
        raise FingerpadError("breakpoint: loads must be positive and values finite")
    if space == "log" and np.any(v <= 0):
        raise FingerpadError("breakpoint: values must be positive for a log-log fit")
    n = f.size
    if n < 2 * min_side + 1 or np.unique(f).size < 2 * min_side:
        raise FingerpadError(f"breakpoint: need at least {2 * min_side + 1} points at distinct loads, got {n}")
    x = np.log(f) if space == "log" else f
    y = np.log(v) if space == "log" else v
    grid = _hinge_grid(x, min_side, n_grid)
    rss = _hinge_profile(x, y, grid, trend)
    if not np.any(np.isfinite(rss)):
        raise FingerpadError(f"breakpoint: the curve never turns {trend} within the data")
    i = int(np.argmin(rss))
    a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
    x0, rss_min = float(grid[i]), float(rss[i])
    if b > a:
        # The trend filter makes the profile infinite where the curve turns the other way; the
        # bounded search then does inf - inf internally. Its result is only taken if it improves
        # on the grid minimum, so the warnings are noise.
        with np.errstate(invalid="ignore"):
            res = optimize.minimize_scalar(lambda t: float(_hinge_profile(x, y, np.array([t]), trend)[0]),
                                           bounds=(a, b), method="bounded",
                                           options={"xatol": 1e-6 * max(1.0, abs(x0))})
        if np.isfinite(res.fun) and res.fun < rss_min:
            x0, rss_min = float(res.x), float(res.fun)
    _, coef = _hinge_fit(x, y, x0)
    line = np.polyfit(x, y, 1)
    rss_line = float(np.sum((y - np.polyval(line, x)) ** 2))
    dof = n - 4
    if dof > 0 and rss_min > 0:
        fstat = max(rss_line - rss_min, 0.0) / 2.0 / (rss_min / dof)
        p_value = float(stats.f.sf(fstat, 2, dof))
    else:
        p_value = math.nan
    if method == "profile":
        tiny = max(rss_min, 1e-300)
        accepted = grid[n * np.log(np.maximum(rss, tiny) / tiny) <= stats.chi2.ppf(level, 1)]
        lo, hi = float(min(accepted.min(), x0)), float(max(accepted.max(), x0))
    else:
        rng = np.random.default_rng(seed)
        boots = []
        for _ in range(int(n_boot)):
            idx = rng.integers(0, n, n)
            xb, yb = x[idx], y[idx]
            if np.unique(xb).size < 2 * min_side:
                continue
            gb = _hinge_grid(xb, min_side, max(50, n_grid // 4))
            rb = _hinge_profile(xb, yb, gb, trend)
            if np.any(np.isfinite(rb)):
                boots.append(gb[int(np.argmin(rb))])
        if len(boots) < 10:
            raise FingerpadError("breakpoint: too few valid bootstrap resamples")
        alpha = (1.0 - level) / 2.0
        lo, hi = (float(q) for q in np.quantile(boots, [alpha, 1.0 - alpha]))
    back = np.exp if space == "log" else (lambda t: t)
    return Breakpoint(
        load=float(back(x0)), ci_low=float(back(lo)), ci_high=float(back(hi)),
        slope_below=float(coef[1]), slope_above=float(coef[2]), level_at_break=float(coef[0]),
        rss=rss_min, rss_line=rss_line, p_value=p_value, n=n, space=space, method=method, level=level,
    )


# =============================================================================================
# skin modulus
# =============================================================================================


@dataclass(frozen=True)
class TextureGeometry:
    """A spherical-cap bump texture (square lattice) and its material, SI units.

    ``material_modulus=None`` means a rigid counter-surface. ``micro_model`` picks the unit-cell
    model: ``"bem"`` (default, :func:`bem_texture_model`: the half-space solver through the
    asperity, transition and full-contact states) or ``"hertz"`` (:func:`hertz_texture_model`,
    MODEL.md 3.1-3.6, asperity tops only). ``full_contact_ratio`` (Hertz only) adds the empirical
    :class:`BaseContactCell` growth past the transition.
    """

    radius: float
    height: float
    spacing: float
    material_modulus: float | None = None
    material_poisson: float = 0.35
    full_contact_ratio: float | None = None
    micro_model: str = "bem"

    def __post_init__(self) -> None:
        if self.micro_model not in ("bem", "hertz"):
            raise FingerpadError(f"micro model must be 'bem' or 'hertz', got {self.micro_model!r}")
        if self.full_contact_ratio is not None and self.micro_model != "hertz":
            raise FingerpadError("full_contact_ratio applies to the 'hertz' micro model only")
        for name in ("radius", "height", "spacing"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise FingerpadError(f"texture {name} must be a positive length, got {value!r}")
        if self.material_modulus is not None and not self.material_modulus > 0:
            raise FingerpadError(f"material modulus must be positive, got {self.material_modulus!r}")
        if self.full_contact_ratio is not None and not self.full_contact_ratio > 1:
            raise FingerpadError(f"full_contact_ratio must exceed 1, got {self.full_contact_ratio!r}")


def read_textures(path: str | os.PathLike[str]) -> dict[str, TextureGeometry | None]:
    """Read a sample table (CSV): ``sample, radius, height, spacing`` and optional
    ``material_modulus``, ``material_poisson``, ``micro_model`` (bem/hertz), ``full_contact_ratio``.

    Values may carry units (``50um``, ``0.5GPa``). A sample with empty geometry is flat.

    Raises
    ------
    FingerpadError
        Naming the file and row for a missing column or a bad value.
    """
    p = Path(path)
    header, rows = _read_text_rows(p, ColumnSpec())
    keys = [_key(h) for h in header]
    if "sample" not in keys:
        raise FingerpadError(f"{p}: sample table lacks a 'sample' column (columns: {', '.join(header)})")
    out: dict[str, TextureGeometry | None] = {}
    for line, cells in rows:
        rec = {k: (cells[i].strip() if i < len(cells) else "") for i, k in enumerate(keys)}
        name = rec["sample"]
        if not name:
            raise FingerpadError(f"{p}, row {line}: empty sample name")
        geom = [rec.get(k, "") for k in ("radius", "height", "spacing")]
        if not any(geom):
            out[name] = None
            continue
        try:
            if not all(geom):
                raise FingerpadError("radius, height and spacing must all be given (or none, for a flat sample)")
            em = rec.get("material_modulus", "")
            out[name] = TextureGeometry(
                radius=parse_quantity(geom[0], "length", name="radius"),
                height=parse_quantity(geom[1], "length", name="height"),
                spacing=parse_quantity(geom[2], "length", name="spacing"),
                material_modulus=parse_quantity(em, "pressure", name="material_modulus") if em else None,
                material_poisson=float(rec.get("material_poisson") or 0.35),
                full_contact_ratio=float(rec["full_contact_ratio"]) if rec.get("full_contact_ratio") else None,
                micro_model=rec.get("micro_model") or ("hertz" if rec.get("full_contact_ratio") else "bem"),
            )
        except (FingerpadError, ValueError) as exc:
            raise FingerpadError(f"{p}, row {line}: {exc}") from None
    return out


def _resolve_finger(finger: Any) -> Any:
    from .finger import Finger, get_finger

    if finger is None:
        return get_finger("default")
    if isinstance(finger, Finger):
        return finger
    return get_finger(str(finger))


@dataclass(frozen=True)
class BaseContactCell:
    """A Hertzian bump cell extended past the transition by contact spreading over the base.

    :class:`fingerpad.coupling.HertzUnitCell` follows the asperity tops only (Hertz cannot
    follow the skin onto the base, MODEL.md 3.1). Measured friction, however, changes trend at
    the transition because the skin starts to touch the base (MODEL.md "Using it"). This
    phenomenological cell keeps Hertz below the transition pressure ``p_t`` and lets psi rise
    from ``psi_t = psi_Hertz(p_t)`` to 1 linearly in ``log p`` up to full contact at
    ``full_contact_ratio * p_t``, which steepens ``d log psi / d log p`` at ``p_t`` from 2/3
    to ``(1 - psi_t) / (psi_t ln ratio)``.

    Attributes
    ----------
    hertz
        The asperity-contact cell.
    full_contact_ratio
        ``p_full / p_t`` (> 1).
    """

    hertz: Any
    full_contact_ratio: float = 4.0

    def __post_init__(self) -> None:
        if not (isinstance(self.full_contact_ratio, (int, float)) and self.full_contact_ratio > 1):
            raise FingerpadError(f"full-contact ratio must exceed 1, got {self.full_contact_ratio!r}")

    @property
    def transition_pressure(self) -> float:
        """Pressure at which the skin touches the base, Pa (Hertz, Eq. 3.3)."""
        return float(self.hertz.transition_pressure)

    @property
    def full_contact_pressure(self) -> float:
        """``full_contact_ratio * p_t``, Pa."""
        return self.full_contact_ratio * self.transition_pressure

    @property
    def breakpoints(self) -> tuple[float, ...]:
        return tuple(getattr(self.hertz, "breakpoints", ()))

    def contact_fraction(self, p: np.ndarray) -> np.ndarray:
        """psi(p): Hertz below ``p_t``, log-linear growth to 1 between ``p_t`` and ``p_full``."""
        pp = np.clip(np.asarray(p, dtype=float), 0.0, None)
        pt = self.transition_pressure
        psi_t = float(self.hertz.contact_fraction(np.array(pt)))
        below = np.asarray(self.hertz.contact_fraction(pp), dtype=float)
        with np.errstate(divide="ignore"):
            grow = psi_t + (1.0 - psi_t) * np.log(np.maximum(pp, pt) / pt) / math.log(self.full_contact_ratio)
        return np.where(pp < pt, below, np.clip(np.maximum(grow, below), 0.0, 1.0))


def hertz_texture_model(
    radius: float,
    height: float,
    spacing: float,
    finger: Any = None,
    material_modulus: float | None = None,
    *,
    material_poisson: float = 0.35,
    full_contact_ratio: float | None = None,
    n_rings: int = 6,
) -> Model:
    """Default normalised-friction model: Hertzian bumps under the finger's ridge contact.

    Built on :mod:`fingerpad.coupling`: for a trial skin modulus E_s the finger (a preset name,
    a :class:`fingerpad.finger.Finger` or ``None`` for the default) gets ``skin_modulus=E_s``,
    the unit cell :class:`fingerpad.coupling.HertzUnitCell` gets ``E1*`` from Eq. 3.4, and
    :func:`fingerpad.coupling.predict_curve` gives ``mu_normalised`` (adhesion, pressure term
    and hysteresis included, so not exactly the area ratio).

    Parameters
    ----------
    radius, height, spacing
        Cap radius R, height h and lattice spacing lambda of the bumps, m.
    finger
        Preset name, :class:`fingerpad.finger.Finger`, or ``None`` (default finger).
    material_modulus, material_poisson
        Counter-surface elasticity (``None`` = rigid), Eq. 3.4.
    full_contact_ratio
        ``None``: pure Hertz (asperity tops only, no change of trend at the transition).
        A number > 1: :class:`BaseContactCell` -- contact spreads over the base past the
        transition and is full at this multiple of the transition pressure.
    n_rings
        Quadrature density of :func:`fingerpad.coupling.couple`; 6 keeps the relative error
        far below measurement noise at a third of the cost of the default 16 (a fit calls the
        model some fifty times).

    Returns
    -------
    callable
        ``model(loads, skin_modulus) -> mu_normalised`` (1-D ndarray like ``loads``), with
        attributes ``geometry`` and ``finger``.
    """
    from . import coupling

    geometry = TextureGeometry(radius, height, spacing, material_modulus, material_poisson, full_contact_ratio, "hertz")
    base = _resolve_finger(finger)

    def model(loads: np.ndarray, skin_modulus: float) -> np.ndarray:
        f = base.with_overrides(skin_modulus=float(skin_modulus))
        cell: Any = coupling.HertzUnitCell.for_finger(
            f, radius=geometry.radius, height=geometry.height, spacing=geometry.spacing,
            material_modulus=geometry.material_modulus, material_poisson=geometry.material_poisson,
        )
        if geometry.full_contact_ratio is not None:
            cell = BaseContactCell(cell, geometry.full_contact_ratio)
        curve = coupling.predict_curve(np.asarray(loads, dtype=float), f, cell, n_rings=n_rings)
        return np.asarray(curve.mu_normalised, dtype=float)

    model.geometry = geometry  # type: ignore[attr-defined]
    model.finger = base  # type: ignore[attr-defined]
    return model


def bem_texture_model(
    radius: float,
    height: float,
    spacing: float,
    finger: Any = None,
    material_modulus: float | None = None,
    *,
    material_poisson: float = 0.35,
    grid: int = 64,
    modulus_range: tuple[float, float] = (0.05e6, 5e6),
    load_range: tuple[float, float] = (0.01, 20.0),
    cache: Any = None,
    n_rings: int = 6,
) -> Model:
    """Normalised-friction model with the numerical unit cell (the model of ``fingerpad predict``).

    One :class:`fingerpad.unitcell.BEMUnitCell` of the cap texture is computed (or read from the
    cache) at the finger's own E1*, over the local pressures that loads in ``load_range`` produce
    for any skin modulus in ``modulus_range``; every trial E_s then reuses it by the p/E* scaling
    of the contact problem (:meth:`~fingerpad.unitcell.BEMUnitCell.at_modulus`), so a fit costs
    no further solves. Unlike the Hertz cell it covers the transition and full contact, which is
    where the change of trend in friction comes from.

    Parameters
    ----------
    radius, height, spacing
        Cap radius R, height h and square-lattice spacing lambda, m.
    finger
        Preset name, :class:`fingerpad.finger.Finger`, or ``None`` (default finger).
    material_modulus, material_poisson
        Counter-surface elasticity (``None`` = rigid), Eq. 3.4.
    grid
        Unit-cell grid points per side.
    modulus_range, load_range
        Skin moduli (Pa) and loads (N) the model must answer for.
    cache
        Passed to :class:`~fingerpad.unitcell.BEMUnitCell` (``None``: default cache folder).

    Returns
    -------
    callable
        ``model(loads, skin_modulus) -> mu_normalised``, with ``geometry``, ``finger`` and ``cell``.
    """
    from . import coupling
    from .textures import spherical_caps
    from .unitcell import BEMUnitCell

    geometry = TextureGeometry(radius, height, spacing, material_modulus, material_poisson)
    base = _resolve_finger(finger)
    lo_e, hi_e = (float(v) for v in modulus_range)
    lo_f, hi_f = (float(v) for v in load_range)
    if not (0 < lo_e < hi_e and 0 < lo_f < hi_f):
        raise FingerpadError("modulus_range and load_range must be increasing positive pairs")

    def e1(skin_modulus: float) -> float:
        return float(base.with_overrides(skin_modulus=skin_modulus).micro_modulus(material_modulus, material_poisson))

    e_ref = e1(base.skin_modulus)
    ridge = np.asarray(base.ridge_area(np.array([lo_f, hi_f])), dtype=float)
    p_lo, p_hi = 0.02 * lo_f / ridge[0], 1.5 * hi_f / ridge[1]
    texture = spherical_caps(radius=radius, height=height, spacing=spacing, grid=grid)
    cell = BEMUnitCell(texture, e_ref, cache=cache).prepare(p_lo * e_ref / e1(hi_e), p_hi * e_ref / e1(lo_e))

    def model(loads: np.ndarray, skin_modulus: float) -> np.ndarray:
        f = base.with_overrides(skin_modulus=float(skin_modulus))
        scaled = cell.at_modulus(float(f.micro_modulus(material_modulus, material_poisson)))
        curve = coupling.predict_curve(np.asarray(loads, dtype=float), f, scaled, n_rings=n_rings)
        return np.asarray(curve.mu_normalised, dtype=float)

    model.geometry = geometry  # type: ignore[attr-defined]
    model.finger = base  # type: ignore[attr-defined]
    model.cell = cell  # type: ignore[attr-defined]
    return model


def texture_model(geometry: TextureGeometry, finger: Any = None) -> Model:
    """The normalised-friction model that ``geometry.micro_model`` names."""
    if geometry.micro_model == "bem":
        return bem_texture_model(
            geometry.radius, geometry.height, geometry.spacing, finger, geometry.material_modulus,
            material_poisson=geometry.material_poisson,
        )
    return hertz_texture_model(
        geometry.radius, geometry.height, geometry.spacing, finger, geometry.material_modulus,
        material_poisson=geometry.material_poisson, full_contact_ratio=geometry.full_contact_ratio,
    )


@dataclass(frozen=True)
class ModulusFit:
    """Least-squares skin modulus E_s and its confidence interval.

    Attributes
    ----------
    skin_modulus
        Best E_s, Pa.
    ci_low, ci_high
        Interval at ``level``: the profile-likelihood interval, widened (in ``log E_s``, in
        quadrature) by the uncertainty of the reference curve when one was given. A bound of
        the search range when the profile does not rise far enough there (``at_bound``).
    profile_ci
        The profile-likelihood interval alone (data scatter only).
    reference_sd
        Standard deviation of ``log E_s`` due to the reference curve (delta method; 0 without).
    design_effect
        Variance inflation for strokes clustered in files (1 without ``clusters``): strokes
        of one session share its skin condition, so they carry less than independent weight.
    scale
        Fitted amplitude factor (1 unless ``fit_scale``).
    rss
        Residual sum of squares (of log residuals when ``log_residuals``).
    n
        Number of points.
    """

    skin_modulus: float
    ci_low: float
    ci_high: float
    profile_ci: tuple[float, float]
    reference_sd: float
    design_effect: float
    scale: float
    rss: float
    n: int
    level: float
    at_bound: bool
    method: str = "profile likelihood"


def _check_xy(loads: Any, values: Any, what: str) -> tuple[np.ndarray, np.ndarray]:
    f = np.asarray(loads, dtype=float).ravel()
    v = np.asarray(values, dtype=float).ravel()
    if f.shape != v.shape:
        raise FingerpadError(f"{what}: loads and values differ in length ({f.size} vs {v.size})")
    if f.size < 3:
        raise FingerpadError(f"{what}: need at least 3 points, got {f.size}")
    if not (np.all(np.isfinite(f)) and np.all(f > 0) and np.all(np.isfinite(v)) and np.all(v > 0)):
        raise FingerpadError(f"{what}: loads and values must be positive and finite")
    return f, v


class ModelTable:
    """A model tabulated on a grid of skin moduli and loads, interpolated in between.

    The model (a disc integral per load) is the costly part of a fit; tabulating it once per
    texture -- ``n_moduli`` log-spaced E_s in ``bounds`` times ``n_loads`` log-spaced loads in
    ``load_range`` -- makes every fit, profile and participant that shares the texture nearly
    free. Interpolation: cubic spline in ``log E_s``, linear in ``log F`` of ``log model``.

    Parameters
    ----------
    model
        ``model(loads, skin_modulus) -> mu_normalised``.
    load_range
        (lowest, highest) load to cover, N.
    bounds
        (lowest, highest) skin modulus, Pa.
    n_loads, n_moduli
        Grid sizes.

    Raises
    ------
    FingerpadError
        For bad ranges, or a model returning the wrong shape, non-finite or non-positive values.
    """

    def __init__(
        self,
        model: Model,
        load_range: tuple[float, float],
        bounds: tuple[float, float] = (2e4, 2e7),
        *,
        n_loads: int = 32,
        n_moduli: int = 49,
    ) -> None:
        from scipy.interpolate import CubicSpline

        lo, hi = (float(v) for v in load_range)
        e_lo, e_hi = (float(v) for v in bounds)
        if not (0 < e_lo < e_hi and math.isfinite(e_hi)):
            raise FingerpadError(f"modulus bounds must satisfy 0 < low < high, got {bounds!r}")
        if not (0 < lo <= hi and math.isfinite(hi)):
            raise FingerpadError(f"load range must be positive, got {load_range!r}")
        if hi <= lo * 1.001:  # a single load: widen a little so interpolation is defined
            lo, hi = lo / 1.01, hi * 1.01
        self.model = model
        self.bounds = (e_lo, e_hi)
        self.loads = np.geomspace(lo, hi, int(n_loads))
        self.log_moduli = np.linspace(math.log(e_lo), math.log(e_hi), int(n_moduli))
        rows = []
        for le in self.log_moduli:
            curve = np.asarray(model(self.loads, math.exp(le)), dtype=float)
            if curve.shape != self.loads.shape or not np.all(np.isfinite(curve)) or np.any(curve <= 0):
                raise FingerpadError(
                    f"model returned {curve.shape} values for {self.loads.size} loads at "
                    f"E_s = {math.exp(le):.4g} Pa (need positive finite values)"
                )
            rows.append(np.log(curve))
        self.table = np.array(rows)
        self._spline = CubicSpline(self.log_moduli, self.table, axis=0)

    def covers(self, loads: np.ndarray) -> bool:
        """Whether ``loads`` lie inside the tabulated range."""
        return bool(np.min(loads) >= self.loads[0] * (1 - 1e-9) and np.max(loads) <= self.loads[-1] * (1 + 1e-9))

    def log_predict(self, loads: np.ndarray, log_modulus: float) -> np.ndarray:
        """``log model(loads, exp(log_modulus))`` by interpolation."""
        row = self._spline(float(np.clip(log_modulus, self.log_moduli[0], self.log_moduli[-1])))
        return np.interp(np.log(loads), np.log(self.loads), row)

    def __call__(self, loads: np.ndarray, skin_modulus: float) -> np.ndarray:
        """Interpolated ``model(loads, skin_modulus)``."""
        return np.exp(self.log_predict(np.asarray(loads, dtype=float), math.log(skin_modulus)))


def design_effect(residuals: np.ndarray, clusters: np.ndarray) -> float:
    """Kish design effect ``1 + (m - 1) rho`` of residuals grouped in clusters (files).

    ``rho`` is the intra-class correlation from a one-way ANOVA (clipped at 0), ``m`` the mean
    cluster size; 1 for fewer than two clusters.
    """
    r = np.asarray(residuals, dtype=float)
    labels, inv = np.unique(np.asarray(clusters), return_inverse=True)
    k, n = labels.size, r.size
    if k < 2 or n <= k:
        return 1.0
    counts = np.bincount(inv, minlength=k).astype(float)
    means = np.bincount(inv, weights=r, minlength=k) / counts
    msw = float(np.sum((r - means[inv]) ** 2) / (n - k))
    msb = float(np.sum(counts * (means - r.mean()) ** 2) / (k - 1))
    m = n / k
    if msb + (m - 1) * msw <= 0:
        return 1.0
    rho = max(0.0, (msb - msw) / (msb + (m - 1) * msw))
    return 1.0 + (m - 1.0) * rho


def _reference_shift_var(reference: Any, loads: np.ndarray) -> float:
    """Variance of the mean log-level error of a fitted reference power law over ``loads``."""
    cov = getattr(reference, "log_covariance", None)
    if cov is None:
        return 0.0
    v = np.array([1.0, float(np.mean(np.log(loads)))])
    return float(max(v @ np.asarray(cov, dtype=float) @ v, 0.0))


def _profile_fit(
    datasets: Sequence[tuple[np.ndarray, np.ndarray, ModelTable]],
    *,
    level: float,
    fit_scale: bool,
    log_residuals: bool,
    reference: Any = None,
    reference_design_effect: float = 1.0,
    clusters: np.ndarray | None = None,
) -> ModulusFit:
    if not 0 < level < 1:
        raise FingerpadError(f"level must lie in (0, 1), got {level!r}")
    ys = np.concatenate([v for _, v, _ in datasets])
    n = ys.size
    grid = datasets[0][2].log_moduli
    lo_b = max(t.log_moduli[0] for _, _, t in datasets)
    hi_b = min(t.log_moduli[-1] for _, _, t in datasets)

    def log_pred(log_e: float) -> np.ndarray:
        return np.concatenate([t.log_predict(f, log_e) for f, _, t in datasets])

    def rss_and_scale(log_e: float) -> tuple[float, float]:
        lp = log_pred(log_e)
        if log_residuals:
            r = np.log(ys) - lp
            shift = float(r.mean()) if fit_scale else 0.0
            return float(np.sum((r - shift) ** 2)), math.exp(shift)
        ps = np.exp(lp)
        scale = float(ys @ ps / (ps @ ps)) if fit_scale else 1.0
        r = ys - scale * ps
        return float(r @ r), scale

    def rss(log_e: float) -> float:
        return rss_and_scale(log_e)[0]

    scan = grid[(grid >= lo_b) & (grid <= hi_b)]
    values = np.array([rss(s) for s in scan])
    i = int(np.argmin(values))
    a, b = scan[max(i - 1, 0)], scan[min(i + 1, scan.size - 1)]
    res = optimize.minimize_scalar(rss, bounds=(a, b), method="bounded", options={"xatol": 1e-5})
    best = float(res.x) if res.fun <= values[i] else float(scan[i])
    rss_min, scale = rss_and_scale(best)
    threshold = stats.chi2.ppf(level, 1)
    deff = 1.0
    if clusters is not None:
        deff = design_effect(np.log(ys) - log_pred(best), clusters)
    n_eff = n / deff

    def excess(log_e: float) -> float:
        return n_eff * math.log(max(rss(log_e), 1e-300) / max(rss_min, 1e-300)) - threshold

    def edge(step: int) -> tuple[float, bool]:
        # walk outward from the best point until the profile crosses the threshold
        inner, j = best, i
        while 0 <= j + step < scan.size:
            j += step
            if (scan[j] - best) * step <= 0:
                continue
            if excess(scan[j]) > 0:
                return float(optimize.brentq(excess, min(inner, scan[j]), max(inner, scan[j]), xtol=1e-6)), False
            inner = scan[j]
        return float(scan[0] if step < 0 else scan[-1]), True

    lo, lo_hit = edge(-1)
    hi, hi_hit = edge(+1)
    ref_sd = 0.0
    if reference is not None and not fit_scale:
        # delta method: a reference curve off by d(log mu_ref) shifts every mu_norm by -d, which
        # moves log E_s by d / (d mean log model / d log E_s)
        h = 0.01
        slope = float(np.mean(log_pred(best + h) - log_pred(best - h)) / (2 * h))
        var = _reference_shift_var(reference, np.concatenate([f for f, _, _ in datasets]))
        var *= max(float(reference_design_effect), 1.0)
        ref_sd = math.sqrt(var) / abs(slope) if slope != 0 else math.inf
    z = stats.norm.ppf(0.5 + level / 2.0)
    lo_all = best - math.hypot(best - lo, z * ref_sd)
    hi_all = best + math.hypot(hi - best, z * ref_sd)
    return ModulusFit(
        skin_modulus=math.exp(best), ci_low=math.exp(max(lo_all, scan[0])), ci_high=math.exp(min(hi_all, scan[-1])),
        profile_ci=(math.exp(lo), math.exp(hi)), reference_sd=ref_sd, design_effect=deff, scale=scale, rss=rss_min, n=n,
        level=level, at_bound=bool(lo_hit or hi_hit or best <= scan[0] + 1e-9 or best >= scan[-1] - 1e-9),
        method="profile likelihood" + (" + reference delta method" if ref_sd else ""),
    )


def _as_table(model: Model | ModelTable, loads: np.ndarray, bounds: tuple[float, float], n_grid: int) -> ModelTable:
    if isinstance(model, ModelTable):
        if not model.covers(loads):
            raise FingerpadError("model table does not cover the loads of the data")
        return model
    return ModelTable(model, (float(loads.min()), float(loads.max())), bounds, n_loads=n_grid)


def estimate_skin_modulus(
    loads: Sequence[float] | np.ndarray,
    mu_normalised: Sequence[float] | np.ndarray,
    model: Model | ModelTable,
    *,
    bounds: tuple[float, float] = (2e4, 2e7),
    level: float = 0.95,
    fit_scale: bool = False,
    log_residuals: bool = True,
    reference: Any = None,
    reference_design_effect: float = 1.0,
    clusters: Sequence[Any] | np.ndarray | None = None,
    n_grid: int = 32,
) -> ModulusFit:
    """Fit the skin micro-modulus E_s to normalised friction with an injected model.

    Minimises ``sum (log y - log(c model(F, E_s)))^2`` (or linear residuals) over ``log E_s``
    in ``bounds`` (grid scan, then bounded Brent). The interval is the set of E_s with
    ``n log(RSS/RSS_min) <= chi2_1(level)`` (profile likelihood: noise variance and ``c``
    profiled out), widened by the reference curve's uncertainty when ``reference`` is given.

    Parameters
    ----------
    loads, mu_normalised
        Strokes' loads (N) and ``mu_tex / mu_ref``.
    model
        ``model(loads, skin_modulus) -> predicted mu_normalised`` (e.g. :func:`hertz_texture_model`),
        or a :class:`ModelTable` of it (shared between fits).
    bounds
        Search range of E_s, Pa.
    fit_scale
        Also fit an amplitude ``c`` (absorbs a shear-strength difference between samples);
        otherwise ``c = 1`` as MODEL.md's normalisation assumes the same tau.
    log_residuals
        Residuals of ``log mu`` (multiplicative scatter, the default) or of ``mu``.
    reference
        The reference power-law fit used to normalise (with ``log_covariance``, as from
        :func:`fingerpad.friction.fit_power_law`): its uncertainty is propagated into the interval.
    reference_design_effect
        Variance inflation of the reference fit for strokes clustered in files
        (:func:`design_effect` of its residuals by file).
    clusters
        Cluster label (e.g. file) of each point: the profile uses ``n / design_effect``
        effective points, so session-to-session variation widens the interval.
    n_grid
        Loads in the model table (when ``model`` is a callable).

    Returns
    -------
    ModulusFit

    Raises
    ------
    FingerpadError
        For invalid data or bounds, or a model returning the wrong shape or non-finite values.
    """
    f, v = _check_xy(loads, mu_normalised, "skin modulus fit")
    table = _as_table(model, f, bounds, n_grid)
    labels = None if clusters is None else np.asarray(clusters).ravel()
    if labels is not None and labels.size != f.size:
        raise FingerpadError(f"skin modulus fit: {labels.size} cluster labels for {f.size} points")
    return _profile_fit([(f, v, table)], level=level, fit_scale=fit_scale, log_residuals=log_residuals,
                        reference=reference, reference_design_effect=reference_design_effect, clusters=labels)


def estimate_skin_modulus_joint(
    datasets: Sequence[tuple[Sequence[float] | np.ndarray, Sequence[float] | np.ndarray, Model | ModelTable]],
    *,
    bounds: tuple[float, float] = (2e4, 2e7),
    level: float = 0.95,
    fit_scale: bool = False,
    log_residuals: bool = True,
    reference: Any = None,
    reference_design_effect: float = 1.0,
    clusters: Sequence[Sequence[Any] | np.ndarray] | None = None,
    n_grid: int = 32,
) -> ModulusFit:
    """One E_s fitted to several textures of one participant: ``datasets = [(loads, mu_norm, model), ...]``.

    Arguments as for :func:`estimate_skin_modulus`; ``clusters`` holds one label array per data set.
    """
    if not datasets:
        raise FingerpadError("joint skin modulus fit: no data sets")
    checked = []
    for f, v, m in datasets:
        ff, vv = _check_xy(f, v, "skin modulus fit")
        checked.append((ff, vv, _as_table(m, ff, bounds, n_grid)))
    labels = None
    if clusters is not None:
        labels = np.concatenate([np.asarray(c, dtype=object).ravel() for c in clusters])
        if labels.size != sum(f.size for f, _, _ in checked):
            raise FingerpadError("joint skin modulus fit: cluster labels do not match the data")
    return _profile_fit(checked, level=level, fit_scale=fit_scale, log_residuals=log_residuals,
                        reference=reference, reference_design_effect=reference_design_effect, clusters=labels)


def _ridge_area_of(ridge_area: float | Callable[[float], float] | Any, load: float) -> float:
    if hasattr(ridge_area, "ridge_area"):
        return float(ridge_area.ridge_area(load))
    if callable(ridge_area):
        return float(ridge_area(load))
    return float(ridge_area)


def modulus_from_transition(
    critical_load: float,
    radius: float,
    height: float,
    spacing: float,
    ridge_area: float | Callable[[float], float] | Any,
    *,
    skin_poisson: float = DEFAULT_SKIN_POISSON,
    material_modulus: float | None = None,
    material_poisson: float = 0.35,
) -> float:
    """Skin modulus E_s from the transition load, closed form (MODEL.md Eq. 3.6 and 3.4).

    ``F_crit = (8/9) E1* sqrt(h^3 R) A_fr / lambda^2`` gives
    ``E1* = 9 F_crit lambda^2 / (8 sqrt(h^3 R) A_fr(F_crit))``, and Eq. 3.4 solved for E_s:
    ``E_s = (1 - nu_s^2) / (1/E1* - (1 - nu_m^2)/E_m)``.

    Parameters
    ----------
    critical_load
        F_crit, N.
    radius, height, spacing
        Asperity radius R, height h and lattice spacing lambda, m.
    ridge_area
        A_fr in m^2: a number, a callable of the load, or a finger (``ridge_area(load)``).

    Raises
    ------
    FingerpadError
        For non-positive input, or if E1* exceeds what the counter-surface alone allows.
    """
    geometry = TextureGeometry(radius, height, spacing, material_modulus, material_poisson)
    if not (math.isfinite(critical_load) and critical_load > 0):
        raise FingerpadError(f"critical load must be positive, got {critical_load!r}")
    a_fr = _ridge_area_of(ridge_area, critical_load)
    if not a_fr > 0:
        raise FingerpadError(f"ridge area must be positive, got {a_fr!r}")
    e1 = 9.0 * critical_load * spacing**2 / (8.0 * math.sqrt(height**3 * radius) * a_fr)
    compliance = 1.0 / e1
    if geometry.material_modulus is not None:
        compliance -= (1.0 - material_poisson**2) / geometry.material_modulus
    if compliance <= 0:
        raise FingerpadError(
            f"transition at {critical_load:.4g} N implies E1* = {e1:.4g} Pa, stiffer than the counter-surface allows"
        )
    return (1.0 - skin_poisson**2) / compliance


def transition_load(
    skin_modulus: float,
    radius: float,
    height: float,
    spacing: float,
    ridge_area: float | Callable[[float], float] | Any,
    *,
    skin_poisson: float = DEFAULT_SKIN_POISSON,
    material_modulus: float | None = None,
    material_poisson: float = 0.35,
    bracket: tuple[float, float] = (1e-6, 1e4),
) -> float:
    """Transition load F_crit for a skin modulus: Eq. 3.6 solved for F with A_fr(F).

    The inverse of :func:`modulus_from_transition`.

    Raises
    ------
    FingerpadError
        If no load in ``bracket`` satisfies Eq. 3.6.
    """
    e1 = reduced_modulus(skin_modulus, skin_poisson, material_modulus, material_poisson)
    TextureGeometry(radius, height, spacing)
    c = (8.0 / 9.0) * e1 * math.sqrt(height**3 * radius) / spacing**2

    def g(log_f: float) -> float:
        f = math.exp(log_f)
        return math.log(f) - math.log(c * _ridge_area_of(ridge_area, f))

    a, b = (math.log(x) for x in bracket)
    if g(a) * g(b) > 0:
        raise FingerpadError(f"no transition load within {bracket[0]:.3g}-{bracket[1]:.3g} N")
    return math.exp(optimize.brentq(g, a, b, xtol=1e-10))


# =============================================================================================
# the whole study
# =============================================================================================


@dataclass(frozen=True)
class AnalysisOptions:
    """Options of :func:`analyse_study`.

    Attributes
    ----------
    reference
        Name of the flat reference sample every participant slid on.
    strokes
        Stroke detection (:class:`StrokeOptions`).
    outlier_z
        Robust z-score threshold of :func:`flag_outliers`.
    n_bins
        Log-spaced load bins shared by the study (tables, spread, figures).
    min_fit_strokes
        Fewest strokes for a power-law fit.
    breakpoint_space, breakpoint_method, breakpoint_trend, n_boot
        See :func:`find_breakpoint`; the default trend ``"steeper"`` looks for the contact
        transition (friction rising faster once the skin reaches the texture's base).
    level
        Confidence level of every interval.
    seed
        Random seed (bootstrap).
    finger
        Finger preset (or :class:`fingerpad.finger.Finger`) for the default model and the
        closed-form route's ridge area.
    modulus_bounds
        Search range of E_s, Pa.
    fit_scale
        Fit an amplitude factor with E_s (:func:`estimate_skin_modulus`).
    """

    reference: str = "flat"
    strokes: StrokeOptions = field(default_factory=StrokeOptions)
    outlier_z: float = 3.5
    n_bins: int = 8
    min_fit_strokes: int = 4
    breakpoint_space: Literal["log", "linear"] = "log"
    breakpoint_method: Literal["profile", "bootstrap"] = "profile"
    breakpoint_trend: Literal["any", "steeper", "flatter"] = "steeper"
    n_boot: int = 200
    level: float = 0.95
    seed: int = 0
    finger: Any = None
    modulus_bounds: tuple[float, float] = (2e4, 2e7)
    fit_scale: bool = False

    def __post_init__(self) -> None:
        if not self.reference:
            raise FingerpadError("a reference sample must be named")
        if not 0 < self.level < 1:
            raise FingerpadError(f"level must lie in (0, 1), got {self.level!r}")
        if self.n_bins < 1 or self.min_fit_strokes < 3:
            raise FingerpadError("n_bins must be >= 1 and min_fit_strokes >= 3")
        if not self.outlier_z > 0:
            raise FingerpadError(f"outlier_z must be positive, got {self.outlier_z!r}")


@dataclass
class StudyResult:
    """Everything :func:`analyse_study` found; tables are pandas DataFrames (SI units).

    Attributes
    ----------
    strokes
        One row per stroke: metadata, load, mu, robust_z, outlier, mu_ref, mu_norm.
    bins
        Binned means per participant/sample/direction/sense (:func:`bin_strokes`).
    fits
        Power-law fits per participant/sample/direction/sense (:func:`fit_curves`).
    spread, spread_summary
        Between-participant variation before/after normalisation.
    conditions
        The summary table: one row per participant, sample and direction.
    participants
        One row per participant: reference power law and E_s fitted jointly to all textures.
    """

    options: AnalysisOptions
    strokes: pd.DataFrame
    bins: pd.DataFrame
    fits: pd.DataFrame
    spread: pd.DataFrame
    spread_summary: pd.DataFrame
    conditions: pd.DataFrame
    participants: pd.DataFrame
    bin_edges: np.ndarray
    power_laws: dict[tuple[str, ...], Any] = field(repr=False, default_factory=dict)
    reference_fits: dict[tuple[str, str], Any] = field(repr=False, default_factory=dict)
    breakpoints: dict[tuple[str, str, str], Breakpoint] = field(repr=False, default_factory=dict)
    modulus_fits: dict[tuple[str, ...], ModulusFit] = field(repr=False, default_factory=dict)
    models: dict[str, Model] = field(repr=False, default_factory=dict)
    tables: dict[str, ModelTable] = field(repr=False, default_factory=dict)
    textures: dict[str, TextureGeometry | None] = field(default_factory=dict)

    @property
    def summary(self) -> pd.DataFrame:
        """The summary table (alias of :attr:`conditions`)."""
        return self.conditions


def _closed_form(bp: Breakpoint, geom: TextureGeometry, finger: Any) -> tuple[float, float, float]:
    def one(load: float) -> float:
        try:
            return modulus_from_transition(load, geom.radius, geom.height, geom.spacing, finger,
                                           skin_poisson=finger.skin_poisson, material_modulus=geom.material_modulus,
                                           material_poisson=geom.material_poisson)
        except FingerpadError:
            return math.nan
    vals = [one(bp.load), one(bp.ci_low), one(bp.ci_high)]
    lo, hi = np.nanmin(vals[1:] + [vals[0]]), np.nanmax(vals[1:] + [vals[0]])
    return vals[0], float(lo), float(hi)


def analyse_study(
    recordings: Sequence[Recording],
    options: AnalysisOptions = AnalysisOptions(),
    *,
    textures: Mapping[str, TextureGeometry | None] | None = None,
    models: Mapping[str, Model] | None = None,
) -> StudyResult:
    """Run the whole analysis on a set of recordings.

    Parameters
    ----------
    recordings
        From :func:`load_study`.
    options
        :class:`AnalysisOptions` (the reference sample among them).
    textures
        Geometry of textured samples (:func:`read_textures`); enables the default model
        (:func:`hertz_texture_model`) and the closed-form E_s for those samples.
    models
        Sample -> normalised-friction model; overrides the default for that sample.

    Raises
    ------
    FingerpadError
        For unreadable strokes, a missing reference, or a participant without one.
    """
    opts = options
    textures = dict(textures or {})
    strokes = stroke_table(recordings, opts.strokes)
    strokes = flag_outliers(strokes, opts.outlier_z)
    strokes, ref_fits = normalise(strokes, opts.reference, opts.min_fit_strokes)
    fits, power_laws = fit_curves(strokes, opts.min_fit_strokes)
    edges = load_bin_edges(strokes["load"].to_numpy(), opts.n_bins)
    bins = bin_strokes(strokes, edges)
    spread = spread_table(strokes, edges, opts.reference)
    summary_spread = spread_summary(spread, opts.reference)

    finger = _resolve_finger(opts.finger) if (textures or models) else None
    all_models: dict[str, Model] = {}
    for sample, geom in textures.items():
        if geom is not None and sample != opts.reference:
            all_models[sample] = texture_model(geom, finger)
    all_models.update(models or {})

    usable = strokes[~strokes["outlier"]]
    tables: dict[str, ModelTable] = {}
    for sample, model in all_models.items():
        loads = usable.loc[usable["sample"] == sample, "load"].to_numpy()
        if loads.size and sample != opts.reference:
            try:  # one table per texture, shared by every participant's fit
                tables[sample] = ModelTable(model, (float(loads.min()), float(loads.max())), opts.modulus_bounds)
            except FingerpadError as exc:
                raise FingerpadError(f"model of sample {sample!r}: {exc}") from None

    # session (file) effects on the reference: its residuals' design effect widens E_s intervals
    ref_deff: dict[str, float] = {}
    for participant, ref in usable[usable["sample"] == opts.reference].groupby("participant"):
        resid = np.log(ref["mu"].to_numpy()) - np.log(ref["mu_ref"].to_numpy())
        ref_deff[participant] = design_effect(resid, ref["file"].to_numpy())

    breakpoints: dict[tuple[str, str, str], Breakpoint] = {}
    modulus_fits: dict[tuple[str, ...], ModulusFit] = {}
    rows = []
    for key, g in strokes.groupby(GROUP, sort=True):
        participant, sample, direction = key
        good = usable[(usable["participant"] == participant) & (usable["sample"] == sample)
                      & (usable["direction"] == direction)]
        row: dict[str, Any] = dict(zip(GROUP, key))
        row.update(is_reference=sample == opts.reference, n_files=g["file"].nunique(), n_strokes=len(g),
                   n_outliers=int(g["outlier"].sum()), load_min=float(g["load"].min()),
                   load_max=float(g["load"].max()))
        fit = power_laws.get((*key, "both"))
        row.update(_fit_row(fit) if fit is not None else {})
        row["mu_at_1N"] = float(fit(np.array([1.0]))[0]) if fit is not None else math.nan
        fp, fm = power_laws.get((*key, "+")), power_laws.get((*key, "-"))
        mid = float(np.sqrt(row["load_min"] * row["load_max"]))
        row["sense_ratio"] = (float(fp(np.array([mid]))[0] / fm(np.array([mid]))[0])
                              if fp is not None and fm is not None else math.nan)
        row["mu_norm_mean"] = float(good["mu_norm"].mean()) if sample != opts.reference else 1.0
        notes = []
        if sample != opts.reference:
            try:
                bp = find_breakpoint(good["load"].to_numpy(), good["mu_norm"].to_numpy(),
                                     space=opts.breakpoint_space, method=opts.breakpoint_method,
                                     trend=opts.breakpoint_trend, level=opts.level, n_boot=opts.n_boot, seed=opts.seed)
                breakpoints[key] = bp
                row.update(breakpoint_load=bp.load, breakpoint_ci_low=bp.ci_low, breakpoint_ci_high=bp.ci_high,
                           slope_below=bp.slope_below, slope_above=bp.slope_above, breakpoint_p=bp.p_value)
                geom = textures.get(sample)
                if geom is not None:
                    e, lo, hi = _closed_form(bp, geom, finger)
                    row.update(skin_modulus_closed_form=e, skin_modulus_closed_form_ci_low=lo,
                               skin_modulus_closed_form_ci_high=hi)
            except FingerpadError as exc:
                notes.append(f"breakpoint: {exc}")
            table = tables.get(sample)
            if table is not None:
                try:
                    mf = estimate_skin_modulus(good["load"], good["mu_norm"], table, level=opts.level,
                                               fit_scale=opts.fit_scale, reference=ref_fits[(participant, "both")],
                                               reference_design_effect=ref_deff[participant],
                                               clusters=good["file"].to_numpy())
                    modulus_fits[key] = mf
                    row.update(skin_modulus=mf.skin_modulus, skin_modulus_ci_low=mf.ci_low,
                               skin_modulus_ci_high=mf.ci_high, skin_modulus_at_bound=mf.at_bound,
                               model_scale=mf.scale)
                except FingerpadError as exc:
                    notes.append(f"modulus: {exc}")
        row["note"] = "; ".join(notes)
        rows.append(row)
    conditions = pd.DataFrame(rows)

    prow = []
    for participant, g in usable.groupby("participant", sort=True):
        ref = ref_fits[(participant, "both")]
        row = {"participant": participant, "n_strokes": int((strokes["participant"] == participant).sum())}
        row.update({f"ref_{k}": v for k, v in _fit_row(ref).items()})
        keys = [(participant, s, d) for (s, d) in g.groupby(["sample", "direction"]).groups if s in tables]
        subs = [sub for (s, _), sub in g.groupby(["sample", "direction"]) if s in tables]
        data = [(sub["load"].to_numpy(), sub["mu_norm"].to_numpy(), tables[sub["sample"].iloc[0]]) for sub in subs]
        if data:
            try:
                if len(keys) == 1 and keys[0] in modulus_fits:
                    mf = modulus_fits[keys[0]]  # one texture: the joint fit is that fit
                else:
                    mf = estimate_skin_modulus_joint(data, level=opts.level, fit_scale=opts.fit_scale,
                                                     reference=ref, reference_design_effect=ref_deff[participant],
                                                     clusters=[sub["file"].to_numpy() for sub in subs])
                modulus_fits[(participant,)] = mf
                row.update(skin_modulus=mf.skin_modulus, skin_modulus_ci_low=mf.ci_low,
                           skin_modulus_ci_high=mf.ci_high, skin_modulus_at_bound=mf.at_bound,
                           n_textures=len(data))
            except FingerpadError as exc:
                row["note"] = f"modulus: {exc}"
        prow.append(row)
    return StudyResult(
        options=opts, strokes=strokes, bins=bins, fits=fits, spread=spread, spread_summary=summary_spread,
        conditions=conditions, participants=pd.DataFrame(prow), bin_edges=edges, power_laws=power_laws,
        reference_fits=ref_fits, breakpoints=breakpoints, modulus_fits=modulus_fits, models=all_models,
        tables=tables, textures=textures,
    )


# =============================================================================================
# synthetic recordings
# =============================================================================================


@dataclass(frozen=True)
class SimulationConfig:
    """A synthetic study (see :func:`simulate_study`); SI units.

    Attributes
    ----------
    participants
        Number of participants; each draws E_s, k, n uniformly from the ranges below.
    repetitions
        Files per participant and sample.
    strokes_per_file
        Reciprocating strokes in each file, each at its own load.
    load_range
        Loads (N) spread log-uniformly over the strokes of a file.
    stroke_length, speed, dwell
        Stroke travel (m), sliding speed (m/s) and pause at each reversal (s).
    sampling_rate
        Samples per second.
    reference
        Name of the flat reference sample.
    textures
        Textured samples: name -> :class:`TextureGeometry`.
    skin_modulus_range, k_range, n_range
        Ranges of the participants' E_s (Pa) and power law ``mu_ref = k F^(n-1)``.
    force_noise
        Relative noise of the friction force (stick-slip, sensor) per sample.
    stroke_noise, file_noise
        Log-normal spread of mu between strokes and between files (repetitions): skin
        moisture and finger posture change from stroke to stroke and session to session.
    drift
        Sensor offset drift over a file, N (normal and friction).
    outlier_rate
        Probability that a stroke's friction is raised 1.5-2x (e.g. a moisture burst).
    finger
        Finger preset of the micro-model (the same for everybody, so the normalisation holds).
    """

    participants: int = 4
    repetitions: int = 2
    strokes_per_file: int = 12
    load_range: tuple[float, float] = (0.1, 5.0)
    stroke_length: float = 0.03
    speed: float = 0.03
    dwell: float = 0.15
    sampling_rate: float = 200.0
    reference: str = "flat"
    textures: Mapping[str, TextureGeometry] = field(
        default_factory=lambda: {
            "bumps": TextureGeometry(radius=50e-6, height=18e-6, spacing=100e-6)
        }
    )
    skin_modulus_range: tuple[float, float] = (0.25e6, 0.4e6)
    k_range: tuple[float, float] = (0.35, 0.8)
    n_range: tuple[float, float] = (0.6, 0.8)
    force_noise: float = 0.03
    stroke_noise: float = 0.05
    file_noise: float = 0.03
    drift: float = 0.003
    outlier_rate: float = 0.02
    finger: str = "default"

    def __post_init__(self) -> None:
        if self.participants < 1 or self.repetitions < 1 or self.strokes_per_file < 2:
            raise FingerpadError("need at least 1 participant, 1 repetition and 2 strokes per file")
        lo, hi = self.load_range
        if not 0 < lo < hi:
            raise FingerpadError(f"load range must satisfy 0 < low < high, got {self.load_range!r}")
        if self.reference in self.textures:
            raise FingerpadError(f"the reference {self.reference!r} cannot also be a textured sample")
        for name in ("stroke_length", "speed", "sampling_rate"):
            if not getattr(self, name) > 0:
                raise FingerpadError(f"{name} must be positive")
        if self.stroke_length / self.speed * self.sampling_rate < 40:
            raise FingerpadError("a stroke must span at least 40 samples (raise the sampling rate)")


def _smoothstep(u: np.ndarray) -> np.ndarray:
    u = np.clip(u, 0.0, 1.0)
    return u * u * (3.0 - 2.0 * u)


def _simulate_file(
    rng: np.random.Generator,
    cfg: SimulationConfig,
    mu_of_load: Callable[[np.ndarray], np.ndarray],
    first_sense: int,
) -> tuple[dict[str, np.ndarray], list[int]]:
    """Time series of one reciprocating recording (SI) and the (1-based) outlier strokes."""
    fs = cfg.sampling_rate
    m = cfg.strokes_per_file
    lo, hi = cfg.load_range
    # loads spread over the range, shuffled, so that drift and load are not confounded
    loads = np.exp(rng.permutation(np.linspace(math.log(lo), math.log(hi), m)) + rng.normal(0, 0.05, m))
    t_move = cfg.stroke_length / cfg.speed
    t_acc = 0.1 * t_move
    n_move, n_dwell = int(round(t_move * fs)), int(round(cfg.dwell * fs))
    pieces_v, pieces_target, pieces_phase, burst = [], [], [], []
    bursts = rng.random(m) < cfg.outlier_rate
    level = np.exp(cfg.file_noise * rng.standard_normal() + cfg.stroke_noise * rng.standard_normal(m))
    for j in range(m):
        sense = first_sense if j % 2 == 0 else -first_sense
        # dwell: at rest while the participant adjusts the load to the next target
        pieces_v.append(np.zeros(n_dwell))
        prev = loads[j - 1] if j else loads[0]
        u = np.arange(n_dwell) / max(n_dwell - 1, 1)
        pieces_target.append(prev + (loads[j] - prev) * _smoothstep(u))
        pieces_phase.append(np.full(n_dwell, -1.0))
        burst.append(np.ones(n_dwell))
        tt = np.arange(n_move) / fs
        ramp = _smoothstep(tt / t_acc) * _smoothstep((t_move - tt) / t_acc)
        pieces_v.append(sense * cfg.speed * ramp)
        pieces_target.append(np.full(n_move, loads[j]))
        pieces_phase.append(tt)
        burst.append(np.full(n_move, level[j] * (rng.uniform(1.5, 2.0) if bursts[j] else 1.0)))
    pieces_v.append(np.zeros(n_dwell))
    pieces_target.append(np.full(n_dwell, loads[-1]))
    pieces_phase.append(np.full(n_dwell, -1.0))
    burst.append(np.ones(n_dwell))
    v = np.concatenate(pieces_v)
    target = np.concatenate(pieces_target)
    phase = np.concatenate(pieces_phase)
    factor = np.concatenate(burst)
    n = v.size
    t = np.arange(n) / fs
    x = np.cumsum(v) / fs
    # participant's load control: slow wobble and tremor around the target
    wobble = 1.0 + 0.04 * np.sin(2 * math.pi * rng.uniform(0.5, 1.5) * t + rng.uniform(0, 2 * math.pi))
    fn_true = target * wobble * (1.0 + 0.01 * rng.standard_normal(n))
    mu = mu_of_load(np.clip(fn_true, lo / 10, None)) * factor
    # static-friction peak at the start of each stroke, friction vanishing at standstill
    peak = np.where(phase >= 0, 1.0 + 0.4 * np.exp(-np.clip(phase, 0, None) / (0.04 * t_move)), 1.0)
    ft_true = -np.tanh(v / (0.02 * cfg.speed)) * mu * fn_true * peak
    ft_true *= 1.0 + cfg.force_noise * rng.standard_normal(n)
    drift_n = cfg.drift * rng.uniform(-1, 1) * t / t[-1]
    drift_t = cfg.drift * rng.uniform(-1, 1) * t / t[-1]
    sensor = 0.002
    return {
        "time": t,
        "normal": fn_true + drift_n + sensor * rng.standard_normal(n),
        "friction": ft_true + drift_t + sensor * rng.standard_normal(n),
        "position": x + 2e-6 * rng.standard_normal(n),
    }, [int(j) + 1 for j in np.flatnonzero(bursts)]


def _write_csv(path: Path, header: Sequence[str], rows: Iterable[Sequence[Any]]) -> None:
    with path.open("w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        w.writerows(rows)


def simulate_study(
    out: str | os.PathLike[str],
    config: SimulationConfig = SimulationConfig(),
    *,
    seed: int = 0,
    model_factory: Callable[[TextureGeometry, Any], Model] | None = None,
) -> dict[str, Any]:
    """Write a synthetic tribometer study: recordings, ``manifest.csv``, ``samples.csv``, ``truth.json``.

    Each participant gets a skin modulus E_s and a reference power law ``mu_ref = k F^(n-1)``;
    on a texture ``mu = mu_ref(F) * model(F, E_s)`` with the same micro-model as the analysis
    (:func:`hertz_texture_model`). Recordings (``{participant}_{sample}_{repetition}.csv``:
    ``time [s]``, ``Fn [N]``, ``Ft [mN]``, ``x [mm]``) hold reciprocating strokes at loads over
    ``config.load_range`` with load wobble, friction noise, static-friction peaks at stroke
    starts, sensor drift and occasional outlier strokes. Files are written into a temporary
    folder and moved into ``out`` at the end.

    Parameters
    ----------
    out
        Output folder (created; existing files of the same names are replaced).
    config
        :class:`SimulationConfig`.
    seed
        Random seed; the same seed gives the same files.
    model_factory
        ``(geometry, finger) -> model``; default :func:`texture_model` (BEM unless the geometry says hertz).

    Returns
    -------
    dict
        The truth: per participant ``skin_modulus``, ``k``, ``n``; textures; files.
    """
    rng = np.random.default_rng(seed)
    finger = _resolve_finger(config.finger)
    factory = model_factory or texture_model
    models = {name: factory(geom, finger) for name, geom in config.textures.items()}
    grid = np.geomspace(config.load_range[0] / 10, config.load_range[1] * 2, 64)
    width = max(2, len(str(config.participants)))
    truth: dict[str, Any] = {"seed": seed, "reference": config.reference, "finger": config.finger,
                             "participants": {}, "textures": {k: asdict(v) for k, v in config.textures.items()},
                             "outliers": []}
    manifest = []
    out_path = Path(out)
    tmp = Path(tempfile.mkdtemp(prefix=".simulate-", dir=_existing_parent(out_path)))
    try:
        for i in range(config.participants):
            pid = f"P{i + 1:0{width}d}"
            es = float(rng.uniform(*config.skin_modulus_range))
            k = float(rng.uniform(*config.k_range))
            n_exp = float(rng.uniform(*config.n_range))
            truth["participants"][pid] = {"skin_modulus": es, "k": k, "n": n_exp}
            samples: dict[str, Callable[[np.ndarray], np.ndarray]] = {
                config.reference: (lambda f, k=k, n_exp=n_exp: k * f ** (n_exp - 1.0))
            }
            for name, model in models.items():
                curve = np.log(np.clip(np.asarray(model(grid, es), float), 1e-12, None))
                samples[name] = (lambda f, k=k, n_exp=n_exp, curve=curve:
                                 k * f ** (n_exp - 1.0) * np.exp(np.interp(np.log(f), np.log(grid), curve)))
            for sample, mu_of_load in samples.items():
                for rep in range(1, config.repetitions + 1):
                    data, bursts = _simulate_file(rng, config, mu_of_load, first_sense=1 if rep % 2 else -1)
                    name = f"{pid}_{sample}_{rep}.csv"
                    truth["outliers"] += [{"file": name, "stroke": b} for b in bursts]
                    _write_csv(tmp / name, ["time [s]", "Fn [N]", "Ft [mN]", "x [mm]"],
                               zip((f"{v:.4f}" for v in data["time"]), (f"{v:.5f}" for v in data["normal"]),
                                   (f"{v * 1e3:.3f}" for v in data["friction"]),
                                   (f"{v * 1e3:.4f}" for v in data["position"])))
                    manifest.append((name, pid, sample, rep))
        _write_csv(tmp / "manifest.csv", ["file", "participant", "sample", "repetition"], manifest)
        _write_csv(tmp / "samples.csv",
                   ["sample", "radius", "height", "spacing", "material_modulus", "micro_model", "full_contact_ratio"],
                   [(config.reference, "", "", "", "", "", "")]
                   + [(name, g.radius, g.height, g.spacing, g.material_modulus or "", g.micro_model,
                       g.full_contact_ratio or "")
                      for name, g in config.textures.items()])
        truth["files"] = [m[0] for m in manifest]
        (tmp / "truth.json").write_text(json.dumps(truth, indent=2), encoding="utf-8")
        move_into_place(tmp, out_path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return truth


# =============================================================================================
# output folders written all at once
# =============================================================================================


def _existing_parent(path: Path) -> Path:
    """The nearest existing ancestor folder of ``path`` (temporary folders go there, same disk)."""
    parent = path.absolute().parent
    while not parent.exists():
        parent = parent.parent
    return parent


def move_into_place(tmp: Path, out: Path) -> None:
    """Move the contents of the finished folder ``tmp`` to ``out``.

    A missing ``out`` is created by one rename; into an existing folder every file is moved
    with :func:`os.replace` (atomic per file), replacing files of the same name and leaving
    others alone.
    """
    out = out.absolute()
    if out.exists() and not out.is_dir():
        raise FingerpadError(f"{out}: exists and is not a folder")
    if not out.exists():
        out.parent.mkdir(parents=True, exist_ok=True)
        try:
            os.replace(tmp, out)
        except OSError:
            out.mkdir(parents=True, exist_ok=True)
        else:
            # mkdtemp made the folder private (0700); give it the permissions of a plain mkdir
            umask = os.umask(0)
            os.umask(umask)
            out.chmod(0o777 & ~umask)
            tmp.mkdir()  # the caller removes its temporary folder afterwards
            return
    for src in sorted(tmp.rglob("*")):
        dst = out / src.relative_to(tmp)
        if src.is_dir():
            dst.mkdir(parents=True, exist_ok=True)
        else:
            dst.parent.mkdir(parents=True, exist_ok=True)
            os.replace(src, dst)
