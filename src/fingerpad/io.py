"""Writing files atomically, output folders as a whole, values as JSON and NetCDF attributes.

NetCDF files of solved cells are in :mod:`fingerpad.netcdf`. Values become NetCDF attributes by
:func:`flatten_attrs`: attributes hold only strings and numbers, so ``None`` becomes ``"none"``,
booleans ``"true"``/``"false"``, nested dicts are flattened to ``outer_inner`` keys and lists of
non-numbers are stored as JSON text.

Every writer goes through :func:`atomic_write`: the file is written to a temporary name in the
target directory and moved into place with :func:`os.replace` only once complete, so an error
never leaves a partial file behind.
:class:`Staging` does the same for a set of files that belong together (a command's outputs):
either all of them are moved into place or none.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import re
import tempfile
import uuid
from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .errors import FingerpadError



# ---------------------------------------------------------------------------------------------
# atomic writes
# ---------------------------------------------------------------------------------------------


def check_writable(path: str | os.PathLike[str], what: str = "output", suffixes: Sequence[str] = ()) -> Path:
    """Raise a :class:`FingerpadError` early if ``path`` cannot be written (missing directory,
    path is a directory, directory not writable, or a name not ending in one of ``suffixes``:
    the format follows the name, so ``--plot x.txt`` must not write a PNG). Returns the path."""
    p = Path(path)
    if suffixes and p.suffix.lower() not in suffixes:
        allowed = ", ".join(suffixes[:-1]) + (" or " if len(suffixes) > 1 else "") + suffixes[-1]
        raise FingerpadError(f"{what} {str(p)!r}: the file name must end in {allowed} (the format follows it)")
    parent = p.parent if str(p.parent) else Path(".")
    if p.is_dir():
        raise FingerpadError(f"{what} {str(p)!r} is a directory, expected a file name")
    if not parent.is_dir():
        raise FingerpadError(f"cannot write {what} {str(p)!r}: directory {str(parent)!r} does not exist")
    if not os.access(parent, os.W_OK):
        raise FingerpadError(f"cannot write {what} {str(p)!r}: directory {str(parent)!r} is not writable")
    return p


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on normal exit move it onto ``path``.

    On an exception the temporary file is removed and ``path`` is left untouched.
    """
    target = Path(path)
    check_writable(target)
    fd, tmp_name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent or ".")
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        yield tmp
        with contextlib.suppress(OSError):
            os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise


def atomic_write(path: str | os.PathLike[str], writer: Callable[[Path], Any]) -> Path:
    """Call ``writer(tmp_path)`` and move the file onto ``path`` only if it succeeds."""
    with atomic_path(path) as tmp:
        try:
            writer(tmp)
        except OSError as exc:
            raise FingerpadError(f"cannot write {str(path)!r}: {exc.strerror or exc}") from exc
    return Path(path)


def write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Atomically write ``text`` (UTF-8) to ``path``."""
    return atomic_write(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))


class Staging:
    """Write a set of output files all or none.

    Each output is first written to a hidden temporary file next to its final name
    (``.NAME.XXXXXXXX.part``, :meth:`stage`); :meth:`commit` moves all of them into place with
    :func:`os.replace` once every one is complete; :meth:`discard` removes the temporary files
    still staged (nothing after a :meth:`commit`). Call :meth:`discard` on every way out, so that an
    error while writing any output leaves neither partial files nor earlier outputs of the set::

        staging = Staging()
        try:
            staging.stage("out.json", lambda tmp: write_text(tmp, text))
            staging.stage("out.nc", lambda tmp: save_result(result, tmp))
            staging.commit()
        finally:
            staging.discard()
    """

    def __init__(self) -> None:
        self.staged: list[tuple[Path, Path]] = []

    def stage(self, final: str, write: Callable[[Path], Any]) -> None:
        """Call ``write(tmp)`` to write the output meant for ``final`` to a temporary file."""
        target = Path(final)
        tmp = target.parent / f".{target.name}.{uuid.uuid4().hex[:8]}.part"
        self.staged.append((tmp, target))
        write(tmp)

    def commit(self) -> None:
        """Move every staged file onto its final name."""
        for tmp, target in self.staged:
            os.replace(tmp, target)
        self.staged.clear()

    def discard(self) -> None:
        """Remove the temporary files still staged (after an error; harmless after :meth:`commit`)."""
        for tmp, _ in self.staged:
            with contextlib.suppress(OSError):
                tmp.unlink()
        self.staged.clear()


class OutputFolder:
    """A command's output folder, written as a whole: never a mix of two runs' files.

    The files are written into a hidden sibling folder (:meth:`path` gives their names there);
    :meth:`commit` swaps it in place of the old folder in two renames, :meth:`discard` removes
    it. An existing folder is replaced only if it holds nothing but files this command writes
    (``names``), or is empty; a folder with other files is refused, so that an output folder
    pointed at the wrong place destroys nothing.
    """

    def __init__(self, folder: str | os.PathLike[str], names: Sequence[str], option: str = "--out") -> None:
        self.final = Path(folder)
        parent = self.check(self.final, names, option)
        try:
            parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise FingerpadError(f"cannot create {option} folder {str(self.final)!r}: {exc.strerror or exc}") from None
        self.build = parent / f".{self.final.name}.{uuid.uuid4().hex[:8]}.part"
        self.build.mkdir()

    @staticmethod
    def check(folder: str | os.PathLike[str], names: Sequence[str], option: str = "--out") -> Path:
        """The checks of the constructor, without writing anything (to run before long work).

        Returns the folder's parent (which may not exist yet).
        """
        final = Path(folder)
        if final.exists() and not final.is_dir():
            raise FingerpadError(f"{option} {str(final)!r} exists and is not a folder")
        if final.is_dir():
            try:
                entries = sorted(p.name for p in final.iterdir())
            except OSError as exc:
                raise FingerpadError(f"cannot read {option} folder {str(final)!r}: {exc.strerror or exc}") from None
            foreign = [e for e in entries if e not in set(names)]
            if foreign:
                shown = ", ".join(foreign[:4]) + (", ..." if len(foreign) > 4 else "")
                raise FingerpadError(
                    f"{option} {str(final)!r} already holds files this command does not write ({shown}); "
                    f"choose a new or empty folder (outputs replace a folder as a whole)"
                )
        parent = final.absolute().parent
        existing = existing_parent(final)
        if not os.access(existing, os.W_OK):
            raise FingerpadError(f"{option} {str(final)!r}: the folder {str(existing)!r} is not writable")
        return parent

    def path(self, name: str) -> Path:
        """Where to write the output ``name`` now (inside the hidden folder)."""
        return self.build / name

    def final_path(self, name: str) -> Path:
        """Where the output ``name`` will be after :meth:`commit`."""
        return self.final / name

    def commit(self) -> None:
        """Put the new folder in place of the old one (the old one is removed)."""
        import shutil

        old = None
        if self.final.exists():
            old = self.final.absolute().parent / f".{self.final.name}.{uuid.uuid4().hex[:8]}.old"
            os.replace(self.final, old)
        os.replace(self.build, self.final)
        self.build.mkdir()  # discard() after commit finds an empty folder to remove
        umask = _umask()
        self.final.chmod(0o777 & ~umask)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)

    def discard(self) -> None:
        """Remove the hidden folder and whatever it holds."""
        import shutil

        shutil.rmtree(self.build, ignore_errors=True)


# ---------------------------------------------------------------------------------------------
# attributes
# ---------------------------------------------------------------------------------------------

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
        return json.dumps(_jsonable(items))
    return str(value)


def _jsonable(value: Any) -> Any:
    """Recursively convert numpy scalars/arrays, paths and non-finite floats for json.dumps."""
    if isinstance(value, Mapping):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return _jsonable(value.tolist())
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        v = float(value)
        return v if math.isfinite(v) else None
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if value is None or isinstance(value, str):
        return value
    return str(value)


def to_jsonable(value: Any) -> Any:
    """Public alias of the JSON conversion used by the command line (NaN/inf -> None)."""
    return _jsonable(value)


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


# ---------------------------------------------------------------------------------------------
# output folders written all at once
# ---------------------------------------------------------------------------------------------


def existing_parent(path: Path) -> Path:
    """The nearest existing ancestor folder of ``path`` (temporary folders go there, same disk)."""
    parent = path.absolute().parent
    while not parent.exists():
        parent = parent.parent
    return parent


def check_replaceable(out: Path, marker: str, option: str = "--out") -> None:
    """An output folder may be replaced as a whole only if it is empty or holds an earlier output
    of the same command (it contains ``marker``); anything else is refused, never mixed."""
    if out.exists() and not out.is_dir():
        raise FingerpadError(f"{option} {str(out)!r} exists and is not a folder")
    if out.is_dir() and any(out.iterdir()) and not (out / marker).exists():
        shown = ", ".join(sorted(p.name for p in out.iterdir())[:4])
        raise FingerpadError(f"{option} {str(out)!r} holds files of something else ({shown}); choose a new or empty "
                             f"folder (outputs replace a folder as a whole)")


def replace_folder(tmp: Path, out: Path) -> None:
    """Put the finished folder ``tmp`` in place of ``out`` (removed, if there) in two renames."""
    import shutil

    out = out.absolute()
    old = None
    if out.exists():
        old = out.parent / f".{out.name}.{uuid.uuid4().hex[:8]}.old"
        os.replace(out, old)
    out.parent.mkdir(parents=True, exist_ok=True)
    os.replace(tmp, out)
    out.chmod(0o777 & ~_umask())  # mkdtemp made it private; give it a plain folder's permissions
    tmp.mkdir()  # the caller removes its temporary folder afterwards
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)

