"""One writer per output: a lock beside every output a command writes, and the temporary files of
writers that are gone cleaned up.

Two commands writing the same ``--out`` (two sweeps into one store, two predictions into one
folder) would otherwise interleave their files or silently replace each other's. A writer holds
an advisory lock (``flock``) on a hidden file beside its output, ``.NAME.lock``, from the check
before the work to the end of the writing; the lock file holds who took it (command, pid, host,
time), which the second writer's refusal quotes:

    error: --out 'r.zarr' is in use by another fingerpad run (fingerpad sweep, pid 4242 on lab-3,
    since 2026-11-28 19:18:02); wait for it to end, or name another --out

The second writer is refused at once rather than made to wait: a wait behind a sweep of hours
looks like a hang, and its result would replace the first one's anyway. The kernel releases a
lock when its process ends, however it ends (``kill -9`` included), so a lock never outlives its
writer and needs no clearing by hand; the lock file itself is removed by its holder at the end
(after ``kill -9`` it stays, unlocked, and the next writer takes it over and removes it).

Whoever holds the lock of an output knows that no other writer of it is alive: the hidden
temporary files and folders of an earlier writer of that output (``.NAME.XXXXXXXX.part``, the
``.old`` folder of a swap, a sweep store's ``.NAME.creating``) are then left-overs of one that
was killed, and are removed (:func:`remove_stale`).

Where ``fcntl`` does not exist (Windows), nothing is locked and nothing is cleaned.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
import socket
import sys
import time
from collections.abc import Iterator
from pathlib import Path

from .errors import FingerpadError

try:  # POSIX only
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None  # type: ignore[assignment]

__all__ = ["OutputBusy", "claim", "claims", "hold", "lock_path", "release", "remove_stale"]


class OutputBusy(FingerpadError):
    """Another process holds the lock of an output."""


#: output (absolute) -> [lock file descriptor or None, lock file, hold count]
_HELD: dict[str, list] = {}
#: The open claim scopes (:func:`claims`): outputs claimed in each, released at its end.
_SCOPES: list[list[str]] = []


def _key(path: str | os.PathLike[str]) -> str:
    p = Path(path)
    if p.is_symlink():  # an output named through a link is written where it points
        p = Path(os.path.realpath(p))
    return os.path.abspath(p)


def lock_path(path: str | os.PathLike[str]) -> Path:
    """The lock file of the output ``path``: ``.NAME.lock`` beside it; where its folder does not
    exist yet, in the nearest existing ancestor, named after the path below it."""
    final = Path(_key(path))
    parent = final.parent
    if parent.is_dir():
        return parent / f".{final.name}.lock"
    base = parent
    while not base.is_dir() and base != base.parent:
        base = base.parent
    rel = final.relative_to(base).as_posix().replace("/", "%")
    return base / f".{rel}.lock"


def _holder(lock: Path) -> str:
    """Who holds ``lock``, in words, from what its holder wrote into it."""
    try:
        info = json.loads(lock.read_text(encoding="utf-8"))
        return f"{info['command']}, pid {info['pid']} on {info['host']}, since {info['since']}"
    except (OSError, ValueError, KeyError, TypeError):
        return "a process that has not said which yet"


def _command() -> str:
    name = Path(sys.argv[0]).name if sys.argv and sys.argv[0] else "python"
    if name in ("fingerpad", "__main__.py", "-c") and len(sys.argv) > 1:
        return f"fingerpad {sys.argv[1]}"
    return name


def hold(path: str | os.PathLike[str], option: str = "--out", shown: str | None = None) -> str:
    """Take the lock of the output ``path`` (again, if this process holds it: holds are counted)
    and remove the left-overs of earlier writers that are gone (:func:`remove_stale`). Returns
    the key to :func:`release`. ``option`` and ``shown`` (default ``path``) name the output in
    messages as the user gave it.

    Raises
    ------
    OutputBusy
        Another process holds it: the message names it (command, pid, host, since when).
    FingerpadError
        The lock file cannot be created (the folder is not writable).
    """
    key = _key(path)
    shown = os.fspath(path) if shown is None else shown
    if key in _HELD:
        _HELD[key][2] += 1
        return key
    lock = lock_path(key)
    if fcntl is None:  # pragma: no cover - Windows: no advisory locks
        _HELD[key] = [None, lock, 1]
        return key
    while True:
        try:
            fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o666)
        except OSError as exc:
            raise FingerpadError(f"cannot write {option} {shown!r}: {exc.strerror or exc} "
                                 f"(folder {str(lock.parent)!r})") from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            raise OutputBusy(f"{option} {shown!r} is in use by another fingerpad run ({_holder(lock)}); "
                             f"wait for it to end, or name another {option}") from None
        except OSError:  # a file system without locks (some network mounts): write unlocked
            os.close(fd)
            _HELD[key] = [None, lock, 1]
            return key
        # The holder before may have removed the file between our open and our lock: then we
        # hold a lock on a file nobody else will find; take the one that is there now.
        try:
            same = os.path.samestat(os.fstat(fd), os.stat(lock))
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    info = {"command": _command(), "pid": os.getpid(), "host": socket.gethostname(),
            "since": time.strftime("%Y-%m-%d %H:%M:%S")}
    with contextlib.suppress(OSError):
        os.ftruncate(fd, 0)
        os.write(fd, (json.dumps(info) + "\n").encode())
    _HELD[key] = [fd, lock, 1]
    remove_stale(key)
    return key


def release(key: str) -> None:
    """Give back one hold of :func:`hold`; the last removes the lock file and unlocks it."""
    entry = _HELD.get(key)
    if entry is None:
        return
    entry[2] -= 1
    if entry[2] > 0:
        return
    del _HELD[key]
    fd, lock, _ = entry
    if fd is not None:
        with contextlib.suppress(OSError):
            os.unlink(lock)  # while still locked: the next writer locks a file that is there
        os.close(fd)


@contextlib.contextmanager
def claims() -> Iterator[None]:
    """A scope (a command's run) in which :func:`claim` holds each output's lock until the scope
    ends: from the check before the work to the end of the writing."""
    _SCOPES.append([])
    try:
        yield
    finally:
        for key in reversed(_SCOPES.pop()):
            release(key)


def claim(path: str | os.PathLike[str], option: str = "--out", shown: str | None = None) -> None:
    """Inside :func:`claims`: hold the lock of ``path`` until the scope ends. Outside one (the
    Python API): only check that no other process holds it (the writing itself locks)."""
    key = hold(path, option, shown)
    if _SCOPES:
        _SCOPES[-1].append(key)
    else:
        release(key)


def _stale_pattern(name: str) -> re.Pattern[str]:
    n = re.escape(name)
    return re.compile(
        rf"^(?:\.{n}\.[0-9a-f]{{8}}\.(?:part|old)"            # io.Staging, io.OutputFolder and its swap
        rf"|\.{n}\.[a-z0-9_]{{8}}\.tmp"                       # io.atomic_path
        rf"|\.\.{n}\.[0-9a-f]{{8}}\.part\.[a-z0-9_]{{8}}\.tmp"  # io.atomic_path writing a staged file
        rf"|\.{n}\.creating|\.{n}\..+\.repair)$"              # a sweep store laid out or repaired
    )


def remove_stale(path: str | os.PathLike[str]) -> list[str]:
    """Remove the hidden temporary files and folders of earlier writers of the output ``path``;
    returns their names. Only to be called while holding its lock (:func:`hold` does): no other
    writer of it is alive then, so whatever they left is a killed writer's."""
    final = Path(_key(path))
    try:
        entries = list(os.scandir(final.parent))
    except OSError:
        return []
    pattern = _stale_pattern(final.name)
    removed = []
    for entry in entries:
        if not pattern.match(entry.name):
            continue
        try:
            if entry.is_dir(follow_symlinks=False):
                shutil.rmtree(entry.path)
            else:
                os.unlink(entry.path)
            removed.append(entry.name)
        except OSError:
            continue
    return removed
