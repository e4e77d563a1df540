"""Uploading a measured height map: size-limited, stored under a generated name in the server's
upload folder (the only place the explorer writes to; the user's file name is never a path)."""

from __future__ import annotations

import os
import re
import uuid
from collections.abc import Callable
from pathlib import Path
from typing import Any

import lazy_loader

pn = lazy_loader.load("panel")

__all__ = ["Upload", "store_upload"]

_SUFFIX = re.compile(r"^\.[A-Za-z0-9]{1,10}$")


def store_upload(folder: str | os.PathLike[str], name: str, data: bytes | str, limit: int) -> Path:
    """Write an uploaded file into ``folder`` under a new name that keeps only its suffix.

    Raises
    ------
    ValueError
        Too large (over ``limit`` bytes), empty, or a suffix that is not letters and digits.
    """
    raw = data.encode("utf-8") if isinstance(data, str) else bytes(data)
    if len(raw) > limit:
        raise ValueError(f"the map is {len(raw) / 2**20:.1f} MiB; uploads are limited to {limit / 2**20:.0f} MiB")
    if not raw:
        raise ValueError("the uploaded file is empty")
    suffix = Path(str(name)).suffix
    if suffix and not _SUFFIX.match(suffix):
        raise ValueError(f"unsupported file name suffix {suffix!r}")
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    target = folder / f"upload-{uuid.uuid4().hex[:16]}{suffix.lower()}"
    target.write_bytes(raw)
    return target


class Upload:
    """A drop zone for one measured map; ``on_change(path, message)`` receives the stored file."""

    def __init__(self, folder: str, limit: int, on_change: Callable[[str | None, str | None], None]) -> None:
        self.folder = folder
        self.limit = limit
        self.on_change = on_change
        self.original_name: str | None = None
        self.dropper = pn.widgets.FileDropper(max_file_size=f"{max(1, limit // 2**20)}MB", multiple=False,
                                              css_classes=["fp-upload"], sizing_mode="stretch_width",
                                              layout="compact")
        self.dropper.param.watch(self._changed, "value")
        self.panel = pn.Column(
            pn.pane.HTML(f"<div style='font-size:12px'>measured height map (at most {limit / 2**20:.0f} MiB): "
                         "text, .npy or instrument files</div>"),
            self.dropper, sizing_mode="stretch_width", margin=0)

    def _changed(self, event: Any) -> None:
        value = event.new or {}
        if not value:
            self.original_name = None
            self.on_change(None, None)
            return
        name, data = next(iter(value.items()))
        try:
            path = store_upload(self.folder, name, data, self.limit)
        except ValueError as exc:
            self.original_name = None
            self.on_change(None, str(exc))
            return
        self.original_name = Path(str(name)).name
        self.on_change(str(path), f"uploaded {self.original_name}")
