"""On-disk cache of unit-cell load curves, keyed by content, safe for concurrent writers.

A unit-cell curve psi(p) costs seconds to minutes of solving and is reused by every prediction
on the same texture shape, grid and solver settings, whatever the moduli and the texture's
scale (the curve is stored in p/E*, :mod:`fingerpad.micro.bem`). Entries are JSON files named by
the SHA-256 of that content. Several processes (sweep workers) may fill the same entry: each update
takes a file lock (``filelock``), re-reads the entry, merges its new points and replaces the file
atomically, so readers never see a partial file and no computed point is lost.

The cache folder is ``$FINGERPAD_CACHE`` if set, else ``~/.cache/fingerpad``. Entries and lock
files are written with the permissions the umask allows (``umask 002`` and a group-owned folder
give a cache shared by a group's workers). A folder that cannot be written (read-only, not a
folder, a lock another user holds with other permissions) never stops a prediction: it runs
without storing, with one :class:`CacheWarning` per folder.
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from filelock import FileLock, Timeout

#: Bump when a solver change alters cached numbers (2: full contact = at most 1 % open; state
#: brackets searched beyond the asked range; 3: unit cells stored modulus- and length-free,
#: pressures over E* and lengths over the cell length, keyed without either; 4: a node's value a
#: function of its pressure alone -- grid and refinement nodes solved cold, not warm-started from
#: whichever nodes a run happened to solve -- so that a cached node is what a solve would give;
#: 5: a solver's element-wise kernels chosen by its grid alone, not by the work it had done, whose
#: switch gave a cell's later nodes at 512^2 other last bits than the same nodes solved early; and
#: a cell's key holds its solver's arithmetic, the FFT engine and kernels, so that an entry one
#: installation wrote is never read as another's; and ducc0's FFTs cut into blocks fixed by the
#: field's shape, whose bits had depended on the number of threads from 256 x 448 up).
CACHE_VERSION = 5


class CacheWarning(UserWarning):
    """The cache folder cannot be used (the work goes on without storing its results), or an
    entry cannot be read (it is computed again and written anew)."""


#: Folders and entries already warned about (one warning each per process).
_WARNED: set[str] = set()


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def default_cache_dir() -> Path:
    env = os.environ.get("FINGERPAD_CACHE")
    return Path(env).expanduser() if env else Path.home() / ".cache" / "fingerpad"


def content_key(heights: np.ndarray, **settings: Any) -> str:
    """SHA-256 of a height map's bytes plus JSON-serialisable settings."""
    h = hashlib.sha256()
    arr = np.ascontiguousarray(heights, dtype=np.float64)
    h.update(str(arr.shape).encode())
    h.update(arr.tobytes())
    h.update(json.dumps({"version": CACHE_VERSION, **settings}, sort_keys=True, default=repr).encode())
    return h.hexdigest()


class CurveCache:
    """A folder of JSON entries ``{key}.json`` holding merged dictionaries of computed points."""

    def __init__(self, folder: str | Path | None = None) -> None:
        self.folder = Path(folder) if folder is not None else default_cache_dir()

    def _paths(self, key: str) -> tuple[Path, Path]:
        return self.folder / f"{key}.json", self.folder / f"{key}.lock"

    def load(self, key: str, check: Callable[[dict[str, Any]], bool] | None = None) -> dict[str, Any]:
        """The entry for ``key`` (empty if absent or unreadable: an unreadable one, cut short or
        corrupted, or one ``check`` refuses (its reader's idea of its content), is said in a
        :class:`CacheWarning`, once per entry, and its points are computed again)."""
        path, _ = self._paths(key)
        try:
            with open(path, encoding="utf-8") as fh:
                data = json.load(fh)
        except (FileNotFoundError, NotADirectoryError):  # no entry (a folder that is not one: warned by update)
            return {}
        except OSError as exc:
            _warn_unreadable(path, exc.strerror or type(exc).__name__)
            return {}
        except ValueError:
            _warn_unreadable(path, "it is not JSON: cut short or corrupted")
            return {}
        if not isinstance(data, dict) or (check is not None and not check(data)):
            _warn_unreadable(path, "it does not hold what fingerpad writes there: edited or corrupted")
            return {}
        return data

    def update(self, key: str, new: dict[str, Any], check: Callable[[dict[str, Any]], bool] | None = None
               ) -> dict[str, Any]:
        """Merge ``new`` into the entry under a lock and write it atomically; return the merged entry.

        Top-level dictionaries are merged key by key (new values win), other values replaced. An
        entry that cannot be read, or that ``check`` refuses, is replaced (see :meth:`load`).
        """
        path, lock = self._paths(key)
        mode = 0o666 & ~_umask()  # what a plain file gets: a shared cache needs group-writable entries and locks
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
            with FileLock(str(lock), timeout=600, mode=mode):
                data = self.load(key, check)
                _merge(data, new)
                fd, tmp = tempfile.mkstemp(dir=self.folder, prefix=f".{key[:12]}.", suffix=".tmp")
                try:
                    with os.fdopen(fd, "w", encoding="utf-8") as fh:
                        json.dump(data, fh)
                    os.chmod(tmp, mode)  # mkstemp makes it private (0600)
                    os.replace(tmp, path)
                except BaseException:
                    Path(tmp).unlink(missing_ok=True)
                    raise
        except (OSError, Timeout) as exc:
            reason = getattr(exc, "strerror", None) or str(exc) or type(exc).__name__
            if str(self.folder) not in _WARNED:
                _WARNED.add(str(self.folder))
                warnings.warn(f"cache folder {str(self.folder)!r} cannot be written ({reason}): running without "
                              f"storing results in the cache (set FINGERPAD_CACHE or --cache to a writable folder)",
                              CacheWarning, stacklevel=2)
            data = self.load(key, check)
            _merge(data, new)
        return data


def _warn_unreadable(path: Path, reason: str) -> None:
    if str(path) in _WARNED:
        return
    _WARNED.add(str(path))
    warnings.warn(f"cache entry {str(path)!r} cannot be read ({reason}): its unit-cell points are computed "
                  "again and the entry is written anew", CacheWarning, stacklevel=3)


def _merge(data: dict[str, Any], new: dict[str, Any]) -> None:
    """Top-level dictionaries merged key by key (new values win), other values replaced."""
    for k, v in new.items():
        if isinstance(v, dict) and isinstance(data.get(k), dict):
            data[k].update(v)
        else:
            data[k] = v
