"""The server's upload area: the only files the explorer reads on a client's behalf.

A browser sends widget values the server must not trust: the measured-map field is disabled in
the page, but a client can set its value to any text (``/etc/shadow``). So the path of a measured
map never comes from a widget. An upload is stored here under a generated name and the session
keeps the :class:`StoredUpload` server-side; before anything is read, :meth:`UploadArea.check`
resolves the path (symbolic links followed) and accepts it only if it is one of this area's own
files. A refused path gets one message whatever it names, so that a client cannot learn whether
a file outside exists. Messages about an upload name the user's file, never the server's path.

Nothing here imports Panel.
"""

from __future__ import annotations

import os
import re
import unicodedata
import uuid
from dataclasses import dataclass
from pathlib import Path

from ..errors import FingerpadError

__all__ = ["REFUSED", "StoredUpload", "UploadArea", "display_name", "page_message"]

#: The one message for a measured-map path the server will not read (the same for every path).
REFUSED = "measured map: upload a file (only a file uploaded in this page is read)"

_SUFFIX = re.compile(r"^\.[A-Za-z0-9]{1,10}$")
_FOLDER = re.compile(r"^upload-[0-9a-f]{16}$")
_STORED = re.compile(r"^[A-Za-z0-9_-][A-Za-z0-9_.-]{0,79}$")
_MAX_NAME = 120


def display_name(name: object) -> str:
    """The user's file name as the page may show it: the last path part, without control
    characters, at most 120 characters (a browser sends whatever name it likes)."""
    text = str(name).replace("\\", "/").rsplit("/", 1)[-1]
    text = "".join(c for c in text if unicodedata.category(c)[0] != "C").strip()
    if len(text) > _MAX_NAME:
        text = text[: _MAX_NAME - 3] + "..."
    return text or "map"


@dataclass(frozen=True)
class StoredUpload:
    """An uploaded map: where the server stored it and the name the user gave it."""

    path: Path
    name: str


class UploadArea:
    """The server's upload folder (created private, 0700, by :func:`tempfile.mkdtemp`)."""

    def __init__(self, folder: str | os.PathLike[str]) -> None:
        self.root = Path(folder).resolve(strict=True)

    def store(self, name: object, data: bytes | str, limit: int) -> StoredUpload:
        """Write an upload under a new name that keeps only its suffix.

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
        shown = display_name(name)
        suffix = Path(shown).suffix
        if suffix and not _SUFFIX.match(suffix):
            raise ValueError(f"unsupported file name suffix {suffix!r}")
        # a new folder per upload, the file under the user's name reduced to safe characters: the
        # texture and the library's messages name the user's file, and no name can be a path
        stem = re.sub(r"[^A-Za-z0-9_.-]", "_", shown[: len(shown) - len(suffix)]).lstrip(".")[:60] or "map"
        folder = self.root / f"upload-{uuid.uuid4().hex[:16]}"
        folder.mkdir(mode=0o700)
        target = folder / f"{stem}{suffix.lower()}"
        # O_EXCL|O_NOFOLLOW: never write through a link
        fd = os.open(target, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0), 0o600)
        with os.fdopen(fd, "wb") as fh:
            fh.write(raw)
        return StoredUpload(target, shown)

    def check(self, path: object) -> Path:
        """``path`` resolved, if it is a regular file this area stored; else :data:`REFUSED`.

        The path is resolved with every symbolic link followed, then must lie in a folder this
        area made (``upload-<16 hex digits>`` directly in the area's folder). Nothing outside the folder is opened or
        examined beyond what resolving the path needs, and the message is the same for a missing
        file, a directory, a link out of the folder or a file that exists elsewhere.
        """
        if not isinstance(path, (str, os.PathLike)) or not str(path).strip() or "\x00" in str(path):
            raise FingerpadError(REFUSED)
        try:
            real = Path(path).resolve(strict=True)
        except (OSError, RuntimeError, ValueError):
            raise FingerpadError(REFUSED) from None
        if (real.parent.parent != self.root or not _FOLDER.match(real.parent.name) or not _STORED.match(real.name)
                or not real.is_file()):
            raise FingerpadError(REFUSED)
        return real


def page_message(text: str, upload: StoredUpload | None = None, root: Path | None = None) -> str:
    """A library message about the study in the page's words: the stored path of ``upload`` (and
    any other path in the upload folder ``root``) replaced by the user's file name, the
    command-line options of measured maps by the fields that set them."""
    if upload is not None:
        for form in (repr(str(upload.path)), str(upload.path)):
            text = text.replace(form, repr(upload.name) if form.startswith(("'", '"')) else upload.name)
    if root is not None:
        text = re.sub(re.escape(str(root)) + r"[^\s'\",:;)]*", "the uploaded map", text)
    for option, field in _OPTION_FIELDS:
        text = text.replace(option, field)
    return text


#: Command-line options named by the library's messages (about measured maps, the model) -> the
#: page's fields.
_OPTION_FIELDS = (
    ("needs --model bem", 'needs the unit-cell model "bem" or "both"'),
    ("with --periodize (periodize = true, fingerpad.textures.periodize)", 'with "periodize" ticked'),
    ("give --periodic (periodic = true)", 'tick "the map is one period"'),
    ("give --fill-missing", 'tick "fill missing points"'),
    ("--size LX[,LY]", 'the "map size" field'),
    ("--size 200um,200um --height-unit um", '"map size" 200um,200um, "height unit" um'),
    ("--pixel-size DX[,DY]", 'the "pixel size" field'),
    ("--size or --pixel-size", '"map size" or "pixel size"'),
    ("--pixel-size", '"pixel size"'),
    ("--height-unit", '"height unit"'),
    ("--size", '"map size"'),
)
