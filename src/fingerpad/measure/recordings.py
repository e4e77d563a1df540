"""Recordings: one tribometer file in SI units, manifests, whole studies."""

from __future__ import annotations

import csv
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import FingerpadError
from .columns import (
    ALIASES,
    COMPANION_SUFFIXES,
    DEFAULT_PATTERN,
    DIMENSIONS,
    LABELS,
    NOT_DATA,
    QUANTITIES,
    ColumnSpec,
    column_key,
    parse_filename,
    split_header,
    template_regex,
    unit_factor,
)
from .importers import RawTable, importer_for, read_table, supported_suffixes
from .importers.text import read_text_rows, sniff_delimiter


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
    session: str = ""

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


def _find_columns(path: Path, header: list[str], spec: ColumnSpec) -> dict[str, int]:
    keys = [column_key(split_header(h)[0]) for h in header]
    full = [column_key(h) for h in header]
    index: dict[str, int] = {}
    for q in QUANTITIES:
        wanted = spec.columns.get(q)
        if wanted:
            k = column_key(wanted)
            if k in full:
                index[q] = full.index(k)
            elif column_key(split_header(wanted)[0]) in keys:
                index[q] = keys.index(column_key(split_header(wanted)[0]))
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


def to_numbers(path: Path, table: RawTable, j: int) -> np.ndarray:
    """Column ``j`` of ``table`` as floats (empty cells NaN), vectorised.

    Raises
    ------
    FingerpadError
        Naming the file, the row and the cell that is not a number.
    """
    import pandas as pd

    col = table.columns[j]
    if col.dtype.kind in "fiub":
        return np.asarray(col, dtype=float)
    text = pd.Series(col, dtype=object).astype(str).str.strip()
    missing = pd.isna(pd.Series(col, dtype=object)).to_numpy() | text.isin(["", "nan", "NaN", "NA", "N/A"]).to_numpy()
    cleaned = text.str.replace(",", ".", regex=False) if table.decimal == "," else text
    values = pd.to_numeric(cleaned.where(~missing, None), errors="coerce").to_numpy(dtype=float)
    bad = np.flatnonzero(np.isnan(values) & ~missing)
    if bad.size:
        i = int(bad[0])
        raise FingerpadError(
            f"{path}, {table.row_word} {int(table.rows[i])}: cannot read {text.iloc[i]!r} in column "
            f"{table.header[j]!r} as a number"
        )
    return values


def read_recording(
    path: str | os.PathLike[str],
    spec: ColumnSpec | None = None,
    *,
    participant: str = "",
    sample: str = "",
    direction: str = "",
    repetition: str = "",
    session: str = "",
) -> Recording:
    """Read one recording (text, Excel, .xls, MATLAB, LabVIEW) into SI units.

    Parameters
    ----------
    path
        The data file; its suffix picks the importer (:mod:`fingerpad.measure.importers`).
    spec
        Column names, units and options (:class:`ColumnSpec`); defaults recognise common names.
    participant, sample, direction, repetition, session
        Metadata attached to the recording.

    Raises
    ------
    FingerpadError
        Naming the file (and the row where one is at fault) for a missing column, unknown unit,
        non-numeric or missing value, time that does not increase, or too few rows.
    """
    spec = spec or ColumnSpec()
    p = Path(path)
    table = read_table(p, spec)
    header = table.header
    index = _find_columns(p, header, spec)
    factors = {
        q: unit_factor(spec.units.get(q) or split_header(header[i])[1] or table.units[i], DIMENSIONS[q],
                       where=f"{p}, column {header[i]!r}")
        for q, i in index.items()
    }
    lines = np.asarray(table.rows, dtype=np.int64)
    values = {q: to_numbers(p, table, i) for q, i in index.items()}
    word = table.row_word
    finite = np.ones(lines.size, dtype=bool)
    for q, arr in values.items():
        ok = np.isfinite(arr)
        if spec.nan_policy == "raise" and not ok.all():
            j = int(np.flatnonzero(~ok)[0])
            raise FingerpadError(
                f"{p}, {word} {lines[j]}: missing or non-finite value in column {header[index[q]]!r} "
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
                f"{p}, {word} {lines[j]}: time does not increase ({t[j]:.6g} s after {t[j - 1]:.6g} s)"
            )
    return Recording(
        source=str(p), normal=data["normal"], friction=data["friction"], time=t,
        position=data.get("position"), velocity=data.get("velocity"), rows=lines,
        participant=str(participant), sample=str(sample), direction=str(direction),
        repetition=str(repetition), session=str(session),
    )


def _header_keys(path: Path) -> list[str]:
    """Keys of the first non-comment line of a text file (cheap manifest detection)."""
    if path.suffix.lower() not in (".csv", ".tsv", ".tab", ".txt"):
        return []
    try:
        with path.open(encoding="utf-8-sig") as fh:
            for line in fh:
                if line.strip() and not line.lstrip().startswith("#"):
                    return [column_key(c) for c in next(csv.reader([line], delimiter=sniff_delimiter(line)))]
    except (OSError, UnicodeDecodeError):
        return []
    return []


def _is_manifest(path: Path) -> bool:
    keys = _header_keys(path)
    return ("file" in keys or "path" in keys) and "participant" in keys


def read_manifest(path: str | os.PathLike[str], spec: ColumnSpec | None = None) -> list[Recording]:
    """Read the recordings listed in a manifest CSV.

    Columns: ``file`` (or ``path``, relative to the manifest's folder), ``participant``,
    ``sample``, optional ``direction``, ``repetition`` and ``session`` (recordings of one
    sitting: they share its skin state, so intervals treat them as one cluster); other columns
    are ignored.

    Raises
    ------
    FingerpadError
        Naming the manifest and row for a missing column, value or data file.
    """
    recordings: list[Recording] = []
    for task in _manifest_tasks(path, spec)[0]:
        recordings += task()
    return recordings


def _manifest_tasks(path: str | os.PathLike[str], spec: ColumnSpec | None
                    ) -> tuple[list[Callable[[], list[Recording]]], bool]:
    """The manifest's rows as tasks, in order, each reading one recording, and whether every row
    is readable: a row that is not (a missing value or data file) is the last task and raises
    its error, so that running the tasks one after another does what :func:`read_manifest`
    promises, whichever threads read the files."""
    p = Path(path)
    header, rows = read_text_rows(p, ColumnSpec())
    keys = [column_key(h) for h in header]
    file_col = "file" if "file" in keys else "path" if "path" in keys else None
    missing = [c for c in (file_col or "file", "participant", "sample") if c not in keys]
    if missing:
        raise FingerpadError(f"{p}: manifest lacks column(s) {', '.join(missing)} (columns: {', '.join(header)})")
    tasks: list[Callable[[], list[Recording]]] = []
    for line, cells in rows:
        rec = {k: (cells[i].strip() if i < len(cells) else "") for i, k in enumerate(keys)}
        empty = [col for col in (file_col, "participant", "sample") if not rec.get(col)]
        if empty:
            return [*tasks, _failing(f"{p}, row {line}: empty {empty[0]!r}")], False
        data = (p.parent / rec[file_col]) if not Path(rec[file_col]).is_absolute() else Path(rec[file_col])  # type: ignore[index]
        if not data.is_file():
            return [*tasks, _failing(f"{p}, row {line}: data file {rec[file_col]!r} not found")], False  # type: ignore[index]
        tasks.append(lambda data=data, rec=rec: [read_recording(
            data, spec, participant=rec["participant"], sample=rec["sample"],
            direction=rec.get("direction", ""), repetition=rec.get("repetition", ""),
            session=rec.get("session", ""),
        )])
    if not tasks:
        raise FingerpadError(f"{p}: manifest lists no files")
    return tasks, True


def _failing(message: str) -> Callable[[], list[Recording]]:
    """A task that raises ``message`` (a :class:`FingerpadError`) when run."""
    def raise_it() -> list[Recording]:
        raise FingerpadError(message)
    return raise_it


def load_study(
    inputs: Sequence[str | os.PathLike[str]],
    spec: ColumnSpec | None = None,
    *,
    pattern: str | None = None,
) -> list[Recording]:
    """Read every recording named by ``inputs``.

    Each input is a manifest CSV, a data file (metadata from its name by the template), or a
    folder: its ``manifest.csv`` if present, else every file whose name matches the template.
    A matching file that cannot be read (unknown format, corrupt) is an error, never skipped;
    hidden files, ``manifest.csv``/``samples.csv``/``truth.json`` and LabVIEW ``.tdms_index``
    files are not recordings.

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

    # each input becomes, in order, a task giving its recordings (or raising its error); the
    # files are then read by two threads: the CSV parser lets go of the interpreter while it
    # splits and converts numbers, so a second thread takes ~2.3 -> 1.4 s off the 150-file
    # benchmark's reading. Results and the first error are taken in the inputs' order, so
    # both are those of reading one file after another.
    tasks: list[Callable[[], list[Recording]]] = []

    fail = _failing

    if not inputs:
        raise FingerpadError("no data given")

    def manifest(m: Path) -> bool:
        """The manifest's rows as tasks (each file read by either thread); ``False`` after an error."""
        try:
            rows, complete = _manifest_tasks(m, spec)
        except FingerpadError as exc:
            tasks.append(fail(str(exc)))
            return False
        tasks.extend(rows)
        return complete

    def plan() -> None:  # the tasks up to the first error, which is the last task
        for item in inputs:
            p = Path(item)
            if p.is_dir():
                if (p / "manifest.csv").is_file():
                    if not manifest(p / "manifest.csv"):
                        return
                    continue
                found = 0
                for f in sorted(p.iterdir()):
                    if (not f.is_file() or f.name.startswith(".") or f.name in NOT_DATA
                            or f.suffix.lower() in COMPANION_SUFFIXES or _is_manifest(f)):
                        continue
                    meta = parse_filename(f, template)
                    if meta is None:
                        continue
                    if importer_for(f) is None:
                        # a file that looks like a recording but cannot be read must not vanish
                        tasks.append(fail(
                            f"{f}: matches the file-name pattern {template!r} but fingerpad cannot read "
                            f"{f.suffix or 'suffix-less'} files (readable: {', '.join(supported_suffixes())}); "
                            "convert it, move it out of the folder, or narrow --pattern"
                        ))
                        return
                    tasks.append(lambda f=f, meta=meta: [from_name(f, meta)])
                    found += 1
                if not found:
                    tasks.append(fail(f"{p}: no manifest.csv and no data file matching the pattern {template!r}"))
                    return
            elif p.is_file():
                if _is_manifest(p):
                    if not manifest(p):
                        return
                    continue
                meta = parse_filename(p, template)
                if meta is None:
                    tasks.append(fail(f"{p}: file name does not match the pattern {template!r}"))
                    return
                tasks.append(lambda p=p, meta=meta: [from_name(p, meta)])
            else:
                tasks.append(fail(f"{p}: no such file or folder"))
                return

    plan()
    recordings: list[Recording] = []
    if len(tasks) < 2:
        for task in tasks:
            recordings += task()
    else:
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(max_workers=2) as pool:
            futures = [pool.submit(task) for task in tasks]
            try:
                for future in futures:
                    recordings += future.result()
            finally:  # after an error, the files not started yet are not read
                for future in futures:
                    future.cancel()
    unique: dict[str, Recording] = {}
    for rec in recordings:
        unique.setdefault(os.path.realpath(rec.source), rec)
    return list(unique.values())
