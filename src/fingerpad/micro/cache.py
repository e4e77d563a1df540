"""On-disk cache of unit-cell load curves, keyed by content, safe for concurrent writers.

A unit-cell curve psi(p) costs seconds to minutes of solving and is reused by every prediction
on the same texture shape, grid and solver settings, whatever the moduli and the texture's
scale (the curve is stored in p/E*, :mod:`fingerpad.micro.bem`). Entries are JSON files named by the
SHA-256 of that content. Several processes (sweep workers) may fill the same entry: each update
takes a file lock (``filelock``), re-reads the entry, merges its new points and replaces the file
atomically, so readers never see a partial file and no computed point is lost.

The cache folder is ``$FINGERPAD_CACHE`` if set, else ``~/.cache/fingerpad``.
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
from filelock import FileLock

from ..errors import FingerpadError

#: Bump when a solver change alters cached numbers (2: full contact = at most 1 % open; state
#: brackets searched beyond the asked range; 3: unit cells stored modulus- and length-free,
#: pressures over E* and lengths over the cell length, keyed without either).
CACHE_VERSION = 3


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

    def load(self, key: str) -> dict[str, Any]:
        """The entry for ``key`` (empty if absent or unreadable)."""
        path, _ = self._paths(key)
        try:
            with open(path, encoding="utf-8") as fh:
                data = json.load(fh)
        except (OSError, ValueError):
            return {}
        return data if isinstance(data, dict) else {}

    def update(self, key: str, new: dict[str, Any]) -> dict[str, Any]:
        """Merge ``new`` into the entry under a lock and write it atomically; return the merged entry.

        Top-level dictionaries are merged key by key (new values win), other values replaced.
        """
        path, lock = self._paths(key)
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise FingerpadError(f"cannot create cache folder {self.folder}: {exc.strerror}") from None
        with FileLock(str(lock), timeout=600):
            data = self.load(key)
            for k, v in new.items():
                if isinstance(v, dict) and isinstance(data.get(k), dict):
                    data[k].update(v)
                else:
                    data[k] = v
            fd, tmp = tempfile.mkstemp(dir=self.folder, prefix=f".{key[:12]}.", suffix=".tmp")
            try:
                with os.fdopen(fd, "w", encoding="utf-8") as fh:
                    json.dump(data, fh)
                os.replace(tmp, path)
            except BaseException:
                Path(tmp).unlink(missing_ok=True)
                raise
        return data
