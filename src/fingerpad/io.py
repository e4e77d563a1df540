"""Reading the TOML files users write, and writing files atomically and output folders as a whole.

:func:`read_toml` reads every TOML file a user gives (study files, population files, column
specs) with the same checks and messages.

NetCDF files of solved cells are in :mod:`fingerpad.netcdf`; values become JSON or NetCDF
attributes in :mod:`fingerpad.encode`.

Every writer goes through :func:`atomic_write`: the file is written to a temporary name in the
target directory and moved into place with :func:`os.replace` only once complete, so an error
never leaves a partial file behind.
:class:`Staging` does the same for a set of files that belong together (a command's outputs):
either all of them are moved into place or none. :class:`OutputFolder` writes a command's output
folder as a whole and replaces an existing one only while it holds nothing but what fingerpad
wrote there (its :data:`MANIFEST`). Every output location is checked before the work
(:func:`check_writable`, :func:`check_output_location`, :meth:`OutputFolder.check`), and a write
that fails anyway raises :class:`WriteError` naming the user's path, never a temporary one.
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
import uuid
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any


from . import locks
from .errors import FingerpadError


# ---------------------------------------------------------------------------------------------
# TOML files a user writes
# ---------------------------------------------------------------------------------------------

#: Largest TOML file read (bytes): a study, population or column file is a few kB of text; a
#: bigger one is a mistake (a data file named instead), refused before it is read into memory.
MAX_TOML_BYTES = 16 * 2**20


def read_toml(path: str | os.PathLike[str], what: str = "file") -> dict[str, Any]:
    """The tables of the TOML file ``path``; ``what`` names it in messages (``study file``).

    Raises
    ------
    FingerpadError
        ``cannot read {what} 'PATH': ...``: no such file, a folder, not a regular file (a FIFO or
        a device, never opened: reading one would wait for a writer), larger than
        :data:`MAX_TOML_BYTES`, unreadable, binary, not UTF-8 (UTF-16 said so), not TOML, nested
        too deeply for the parser or holding an integer too long to convert. A UTF-8 byte-order
        mark is skipped.
    """
    import stat
    import tomllib

    text = os.fspath(path)
    head = f"cannot read {what} {text!r}"
    try:
        st = os.stat(text)
    except FileNotFoundError:
        raise FingerpadError(f"{head}: no such file") from None
    except OSError as exc:
        raise FingerpadError(f"{head}: {exc.strerror or exc}") from None
    if stat.S_ISDIR(st.st_mode):
        raise FingerpadError(f"{head}: it is a directory")
    if not stat.S_ISREG(st.st_mode):
        kind = "a FIFO (named pipe)" if stat.S_ISFIFO(st.st_mode) else "not a regular file"
        raise FingerpadError(f"{head}: it is {kind}; give a TOML text file")
    if st.st_size > MAX_TOML_BYTES:
        raise FingerpadError(f"{head}: it is {st.st_size / 2**20:.0f} MiB, more than the {MAX_TOML_BYTES // 2**20} MiB "
                             f"a TOML file may have here (a data file named instead?)")
    try:
        with open(text, "rb") as fh:
            raw = fh.read(MAX_TOML_BYTES + 1)
    except OSError as exc:
        raise FingerpadError(f"{head}: {exc.strerror or exc}") from None
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise FingerpadError(f"{what} {text!r} is saved as UTF-16 (a byte-order mark says so); save it as UTF-8 "
                             "TOML text")
    if b"\x00" in raw[:4096]:
        raise FingerpadError(f"{what} {text!r} is a binary file, not a text file; save it as UTF-8 TOML text")
    try:
        decoded = raw.decode("utf-8-sig")  # a byte-order mark (Windows editors write one) is skipped
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise FingerpadError(f"{what} {text!r} is not UTF-8 text (byte {exc.start + 1}, line {line}: "
                             f"{raw[exc.start:exc.start + 1]!r}); save it as UTF-8 TOML text") from None
    try:
        return tomllib.loads(decoded)
    except tomllib.TOMLDecodeError as exc:
        raise FingerpadError(f"{what} {text!r}: {exc}") from None
    except RecursionError:
        raise FingerpadError(f"{what} {text!r}: arrays or tables nested too deeply to read") from None
    except ValueError as exc:  # an integer of thousands of digits (Python's conversion limit)
        raise FingerpadError(f"{what} {text!r}: {exc.args[0].split(';')[0] if exc.args else exc}") from None


# ---------------------------------------------------------------------------------------------
# output locations: checked before the work, written all or none, a user's files never replaced
# ---------------------------------------------------------------------------------------------

#: The hidden file every output folder gets: the files the command wrote there. A folder is
#: replaced as a whole only while it holds nothing else (:meth:`OutputFolder.check`), so a
#: folder of a user's own files, or one a user added a file to, is never replaced.
MANIFEST = ".fingerpad-output.json"


class WriteError(FingerpadError):
    """An output could not be written. The message names the user's path (never the hidden
    temporary file the output was being written to) and the reason."""

    def __init__(self, path: str | os.PathLike[str], reason: str, what: str = "") -> None:
        self.path = os.fspath(path)
        self.reason = reason
        super().__init__(f"cannot write {what + ' ' if what else ''}{self.path!r}: {reason}")


def _reason(exc: BaseException) -> str:
    """The reason of a failed write, without a file name (the caller names the user's path)."""
    if isinstance(exc, WriteError):
        return exc.reason
    if isinstance(exc, OSError):
        return exc.strerror or str(exc)
    return str(exc)


def real_path(path: str | os.PathLike[str]) -> Path:
    """``path`` with a symbolic link followed: an output named through a link is written where
    the link points (the link stays a link, its target gets the outputs)."""
    p = Path(path)
    return Path(os.path.realpath(p)) if p.is_symlink() else p


def _probe(folder: Path) -> str | None:
    """Why nothing can be created in ``folder``, or ``None`` if something can.

    Tried, not guessed from permission bits, which say nothing for root, a read-only mount or
    ``/proc``: a hidden empty file is created and removed at once.
    """
    name = folder / f".fingerpad-probe-{uuid.uuid4().hex[:8]}"
    try:
        fd = os.open(name, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    except OSError as exc:
        return exc.strerror or str(exc)
    os.close(fd)
    with contextlib.suppress(OSError):
        os.unlink(name)
    return None


def _check_replaceable(path: Path, label: str) -> None:
    """Raise a :class:`FingerpadError` if the existing ``path`` cannot be replaced by a rename
    (an immutable or append-only file or folder, ``chattr +i``): tried, as :func:`_probe` tries,
    by renaming it to a hidden name and back, so that the refusal comes before the work."""
    probe = path.parent / f".{path.name}.{uuid.uuid4().hex[:8]}.probe"
    try:
        os.rename(path, probe)
    except OSError as exc:
        raise FingerpadError(f"cannot replace {label}: {exc.strerror or exc}") from None
    os.rename(probe, path)


def check_folder_writable(folder: str | os.PathLike[str], label: str) -> None:
    """Raise a :class:`FingerpadError` if files cannot be created in, or written into, the
    existing ``folder`` (a store resumed in place), or it cannot be replaced by a rename; tried."""
    path = Path(folder)
    reason = _probe(path)
    if reason is not None:
        raise FingerpadError(f"cannot write into {label}: {reason}")
    _check_replaceable(path, label)


def existing_parent(path: Path) -> Path:
    """The nearest existing ancestor of ``path`` (temporary folders go there, same disk)."""
    parent = Path(os.path.abspath(path)).parent
    while not parent.exists() and parent != parent.parent:
        parent = parent.parent
    return parent


def check_writable(path: str | os.PathLike[str], what: str = "output", suffixes: Sequence[str] = (),
                   claim: bool = True) -> Path:
    """Raise a :class:`FingerpadError` early if the file ``path`` cannot be written: an empty
    name, a name not ending in one of ``suffixes`` (the format follows the name, so ``--plot
    x.txt`` must not write a PNG), a folder, something that is not a regular file (``/dev/null``
    is never replaced), a missing folder, a folder where nothing can be created, an existing
    file that cannot be replaced (both tried), or a file another run is writing
    (:mod:`fingerpad.locks`; ``claim``: inside a command, hold its lock until the command ends).
    A symbolic link is written through. Returns the path."""
    text = os.fspath(path)
    if not text.strip():
        raise FingerpadError(f"{what}: the file name is empty")
    p = real_path(text)
    if suffixes and Path(text).suffix.lower() not in suffixes:
        allowed = ", ".join(suffixes[:-1]) + (" or " if len(suffixes) > 1 else "") + suffixes[-1]
        raise FingerpadError(f"{what} {text!r}: the file name must end in {allowed} (the format follows it)")
    if p.is_dir():
        raise FingerpadError(f"{what} {text!r} is a directory, expected a file name")
    if p.exists() and not p.is_file():
        raise FingerpadError(f"{what} {text!r} exists and is not a regular file; it is not replaced")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        reason = "is not a folder" if parent.exists() else "does not exist"
        raise FingerpadError(f"cannot write {what} {text!r}: the folder {str(parent)!r} {reason}")
    reason = _probe(parent)
    if reason is not None:
        raise FingerpadError(f"cannot write {what} {text!r}: {reason} (folder {str(parent)!r})")
    if p.exists():
        _check_replaceable(p, f"{what} {text!r}")
    if claim:
        locks.claim(text, what)  # no other run writes it (held to the command's end, see locks.claims)
    return Path(text)


def check_output_location(path: str | os.PathLike[str], option: str = "--out",
                          inputs: Sequence[str | os.PathLike[str]] = (), replaces: bool = True) -> Path:
    """The checks every output folder or store gets before the work; returns where it will be
    written (absolute, a symbolic link followed).

    Refused: an empty name (it would be the current folder), the current folder or one that
    contains it, a path through a file, and a location where nothing can be created (tried).
    So is a folder that is, or holds, one of the command's ``inputs`` (``analyse sim --out sim``
    would replace the recordings it reads). What the folder holds is the caller's check
    (:meth:`OutputFolder.check`, a sweep store's). ``replaces=False``: the command only adds
    files to the folder (``finger-models``), so the current folder is allowed.
    """
    text = os.fspath(path)
    if not text.strip():
        raise FingerpadError(f"{option} is empty: name a folder (the current folder is never replaced)")
    final = Path(os.path.abspath(real_path(text)))
    here = Path(os.path.realpath(os.getcwd()))
    real = Path(os.path.realpath(final))
    if real.is_symlink():
        raise FingerpadError(f"{option} {text!r} is a symbolic link that leads nowhere (a loop): name a folder")
    if replaces and (real == here or real in here.parents):
        raise FingerpadError(f"{option} {text!r} is the current folder or contains it: name a new folder "
                             f"for the outputs")
    # Where the outputs are created: beside an existing folder (it is swapped by renames there),
    # else in the nearest existing ancestor (missing folders are created).
    for item in inputs:
        source = Path(os.path.realpath(item))
        if source == real or real in source.parents:
            raise FingerpadError(f"{option} {text!r} holds the input {os.fspath(item)!r}: name another folder "
                                 f"(an output folder is replaced as a whole)")
    existing = final.parent if final.exists() else existing_parent(final)
    if not existing.is_dir():
        raise FingerpadError(f"cannot write {option} {text!r}: {str(existing)!r} is a file, not a folder")
    reason = _probe(existing)
    if reason is not None:
        raise FingerpadError(f"cannot write {option} {text!r}: {reason} (folder {str(existing)!r})")
    locks.claim(final, option, text)  # no other run writes it (held to the command's end, see locks.claims)
    return final


def _files(folder: Path, limit: int = 100_000) -> list[str]:
    """Relative paths of every file under ``folder`` (links not followed; at most ``limit``)."""
    out: list[str] = []
    for root, dirs, files in os.walk(folder):
        rel = Path(root).relative_to(folder)
        out += [(rel / f).as_posix() for f in files]
        out += [(rel / d).as_posix() for d in dirs if (Path(root) / d).is_symlink()]
        if len(out) > limit:
            break
    return sorted(out)


def foreign_entries(folder: Path, names: Sequence[str] = ()) -> list[str]:
    """What in the existing output folder ``folder`` this package did not write, [] if nothing.

    A folder with a :data:`MANIFEST` may hold only the files listed there; one without (written
    before the manifest existed) only plain files named in ``names``.
    """
    manifest = folder / MANIFEST
    listed: set[str] | None = None
    if manifest.is_file():
        try:
            data = json.loads(manifest.read_text(encoding="utf-8"))
            listed = {str(f) for f in data["files"]}
        except (OSError, ValueError, KeyError, TypeError):
            listed = None
    if listed is None:
        entries = sorted(p.name for p in folder.iterdir())
        return [e for e in entries if e not in set(names) or not (folder / e).is_file() or (folder / e).is_symlink()]
    return [f for f in _files(folder) if f not in listed and f != MANIFEST]


def _write_manifest(build: Path) -> None:
    from ._version import __version__

    files = [f for f in _files(build) if f != MANIFEST]
    text = json.dumps({"written_by": f"fingerpad {__version__}", "files": files}, indent=1) + "\n"
    (build / MANIFEST).write_text(text, encoding="utf-8")


def _swap_in(build: Path, final: Path, given: str, option: str) -> None:
    """Put the finished folder ``build`` in place of ``final`` (removed, if there) in two renames."""
    import shutil

    _write_manifest(build)
    old = None
    try:
        if final.exists():
            old = final.parent / f".{final.name}.{uuid.uuid4().hex[:8]}.old"
            os.replace(final, old)
        os.replace(build, final)
    except OSError as exc:
        if old is not None and not final.exists():
            with contextlib.suppress(OSError):
                os.replace(old, final)
        raise WriteError(given, _reason(exc), f"{option} folder") from None
    with contextlib.suppress(OSError):
        final.chmod(0o777 & ~_umask())  # a hidden temporary folder may be private; a plain folder's permissions
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on normal exit move it onto ``path``.

    On an exception the temporary file is removed and ``path`` is left untouched. A symbolic
    link is written through (the link stays).
    """
    target = real_path(path)
    check_writable(path, claim=False)
    # a user's file is locked while it is written (a temporary one of ours, .NAME..., is ours alone)
    key = locks.hold(target, "output") if not target.name.startswith(".") else None
    try:
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
    finally:
        if key is not None:
            locks.release(key)


def atomic_write(path: str | os.PathLike[str], writer: Callable[[Path], Any]) -> Path:
    """Call ``writer(tmp_path)`` and move the file onto ``path`` only if it succeeds.

    A failed write raises :class:`WriteError` naming ``path``."""
    try:
        with atomic_path(path) as tmp:
            writer(tmp)
    except WriteError as exc:
        raise WriteError(path, exc.reason) from None
    except OSError as exc:
        raise WriteError(path, _reason(exc)) from None
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

    A failed write (a full disk) raises :class:`WriteError` naming the user's file, not the
    temporary one; a symbolic link is written through.
    """

    def __init__(self) -> None:
        self.staged: list[tuple[Path, Path, str]] = []
        self.locks: list[str] = []

    def stage(self, final: str | os.PathLike[str], write: Callable[[Path], Any]) -> None:
        """Call ``write(tmp)`` to write the output meant for ``final`` to a temporary file
        (``final`` locked until :meth:`commit` or :meth:`discard`, see :mod:`fingerpad.locks`)."""
        given = os.fspath(final)
        target = real_path(given)
        self.locks.append(locks.hold(target, "output"))
        tmp = target.parent / f".{target.name}.{uuid.uuid4().hex[:8]}.part"
        self.staged.append((tmp, target, given))
        try:
            write(tmp)
        except (OSError, WriteError) as exc:
            raise WriteError(given, _reason(exc)) from None

    def commit(self) -> None:
        """Move every staged file onto its final name."""
        for tmp, target, given in self.staged:
            try:
                os.replace(tmp, target)
            except OSError as exc:
                raise WriteError(given, _reason(exc)) from None
        self.staged.clear()
        self._unlock()

    def discard(self) -> None:
        """Remove the temporary files still staged (after an error; harmless after :meth:`commit`)."""
        for tmp, _, _ in self.staged:
            with contextlib.suppress(OSError):
                tmp.unlink()
        self.staged.clear()
        self._unlock()

    def _unlock(self) -> None:
        while self.locks:
            locks.release(self.locks.pop())


class OutputFolder:
    """A command's output folder, written as a whole: never a mix of two runs' files, never a
    folder of the user's own files replaced.

    The files are written into a hidden sibling folder (:meth:`path` gives their names there,
    :meth:`write` writes one); :meth:`commit` adds the :data:`MANIFEST` and swaps the folder in
    place of the old one in two renames; :meth:`discard` removes it. :meth:`check` (also run by
    the constructor, and to be run before long work) refuses what may not be replaced. Used as
    a context manager it discards on every way out and reports a failed write (``OSError``
    inside the hidden folder, e.g. a full disk) under the user's path::

        with OutputFolder(out, names) as folder:
            folder.write("a.json", lambda tmp: write_text(tmp, text))
            folder.commit()
    """

    def __init__(self, folder: str | os.PathLike[str], names: Sequence[str] = (), option: str = "--out") -> None:
        self.given = os.fspath(folder)
        self.option = option
        self.names = tuple(names)
        self.final = self.check(folder, names, option)
        # held from here to discard: the hidden folder's name is only removed as stale by a
        # writer holding the lock (fingerpad.locks)
        self._lock: str | None = locks.hold(self.final, option, self.given)
        try:
            self.final.parent.mkdir(parents=True, exist_ok=True)
            self.build = self.final.parent / f".{self.final.name}.{uuid.uuid4().hex[:8]}.part"
            self.build.mkdir()
        except OSError as exc:
            self._unlock()
            raise WriteError(self.given, _reason(exc), f"{option} folder") from None

    def _unlock(self) -> None:
        if self._lock is not None:
            locks.release(self._lock)
            self._lock = None

    @staticmethod
    def check(folder: str | os.PathLike[str], names: Sequence[str] = (), option: str = "--out",
              inputs: Sequence[str | os.PathLike[str]] = ()) -> Path:
        """The checks of the constructor, without writing anything (to run before long work).

        Refused: what :func:`check_output_location` refuses (a folder another run writes among
        them); a file; a folder holding anything this package did not write there
        (:func:`foreign_entries`); a folder holding one of ``inputs``; a folder that cannot be
        replaced (tried). Returns the folder that
        will be written (absolute, a symbolic link followed).
        """
        final = check_output_location(folder, option, inputs)
        text = os.fspath(folder)
        if final.exists() and not final.is_dir():
            raise FingerpadError(f"{option} {text!r} is a file, not an output folder; it is left alone "
                                 f"(name a new folder)")
        if final.is_dir():
            try:
                foreign = foreign_entries(final, names)
            except OSError as exc:
                raise FingerpadError(f"cannot read {option} folder {text!r}: {exc.strerror or exc}") from None
            if foreign:
                shown = ", ".join(foreign[:4]) + (", ..." if len(foreign) > 4 else "")
                raise FingerpadError(
                    f"{option} {text!r} holds files fingerpad did not write there ({shown}); it is left alone: "
                    f"name a new or empty folder (an output folder is replaced as a whole)"
                )
            _check_replaceable(final, f"{option} {text!r}")
        return final

    def path(self, name: str) -> Path:
        """Where to write the output ``name`` now (inside the hidden folder)."""
        return self.build / name

    def final_path(self, name: str) -> Path:
        """Where the output ``name`` will be after :meth:`commit` (as the user named the folder)."""
        return Path(self.given) / name

    def write(self, name: str, writer: Callable[[Path], Any]) -> Path:
        """``writer(path)`` for the output ``name``; a failure names the user's path."""
        try:
            writer(self.path(name))
        except (OSError, WriteError) as exc:
            raise WriteError(self.final_path(name), _reason(exc)) from None
        return self.final_path(name)

    def commit(self) -> None:
        """Put the new folder in place of the old one (the old one is removed).

        The old folder is checked again first: a file a user put there while the command ran
        stops the swap (the new outputs are discarded, the folder left as it is)."""
        self.check(self.given, self.names, self.option)
        _swap_in(self.build, self.final, self.given, self.option)

    def discard(self) -> None:
        """Remove the hidden folder and whatever it holds."""
        import shutil

        shutil.rmtree(self.build, ignore_errors=True)
        self._unlock()

    def __enter__(self) -> OutputFolder:
        return self

    def __exit__(self, exc_type: Any, exc: BaseException | None, tb: Any) -> None:
        self.discard()
        if isinstance(exc, OSError):
            name = os.fspath(exc.filename) if getattr(exc, "filename", None) else ""
            build = os.fspath(self.build)
            user = self.given
            if name.startswith(build):
                user = os.path.join(self.given, os.path.relpath(name, build))
            raise WriteError(user, _reason(exc)) from None
