"""Output folders and files of fingerpad.io: replaced only when fingerpad wrote them, all or none."""

from __future__ import annotations

import errno
import os
from pathlib import Path

import pytest

from fingerpad.errors import FingerpadError
from fingerpad.io import MANIFEST, OutputFolder, Staging, WriteError, foreign_entries, write_text


def _write(folder: Path, names: dict[str, str]) -> None:
    with OutputFolder(folder, list(names)) as out:
        for name, text in names.items():
            out.path(name).parent.mkdir(parents=True, exist_ok=True)
            out.write(name, lambda tmp, text=text: write_text(tmp, text))
        out.commit()


def test_a_folder_fingerpad_wrote_is_replaced_with_its_subfolders(tmp_path):
    out = tmp_path / "out"
    _write(out, {"a.json": "1", "figures/b.png": "2"})
    assert foreign_entries(out) == []
    _write(out, {"c.json": "3"})
    assert sorted(p.name for p in out.iterdir()) == [MANIFEST, "c.json"]


def test_a_file_added_anywhere_keeps_the_folder(tmp_path):
    out = tmp_path / "out"
    _write(out, {"a.json": "1", "figures/b.png": "2"})
    (out / "figures" / "mine.txt").write_text("mine")
    assert foreign_entries(out) == ["figures/mine.txt"]
    with pytest.raises(FingerpadError, match="mine.txt"):
        _write(out, {"a.json": "new"})
    assert (out / "a.json").read_text() == "1" and (out / "figures" / "mine.txt").exists()


def test_a_file_added_while_the_command_runs_stops_the_swap(tmp_path):
    out = tmp_path / "out"
    _write(out, {"a.json": "1"})
    folder = OutputFolder(out, ["a.json"])
    with pytest.raises(FingerpadError, match="notes.txt"), folder:
        folder.write("a.json", lambda tmp: write_text(tmp, "2"))
        (out / "notes.txt").write_text("written meanwhile")
        folder.commit()
    assert (out / "a.json").read_text() == "1" and (out / "notes.txt").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]  # the hidden folder is gone


def test_a_folder_from_before_the_manifest_is_judged_by_its_names(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "predict.json").write_text("old")
    assert foreign_entries(out, ["predict.json", "predict.nc"]) == []
    (out / "report.html").write_text("x")
    assert foreign_entries(out, ["predict.json"]) == ["report.html"]
    assert foreign_entries(out) == ["predict.json", "report.html"]  # no names: nothing is known


def test_an_oserror_inside_the_folder_names_the_users_path(tmp_path):
    out = tmp_path / "out"
    with pytest.raises(WriteError) as info, OutputFolder(out, ["x.csv"]) as folder:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(folder.path("x.csv")))
    assert str(info.value) == f"cannot write {str(out / 'x.csv')!r}: No space left on device"
    assert list(tmp_path.iterdir()) == []


def test_staging_names_the_users_file_and_removes_the_rest(tmp_path):
    staging = Staging()
    first = tmp_path / "a.json"
    try:
        staging.stage(str(first), lambda tmp: write_text(tmp, "{}"))
        with pytest.raises(WriteError, match=r"'.*b\.nc': No space left on device"):
            staging.stage(str(tmp_path / "b.nc"),
                          lambda tmp: (_ for _ in ()).throw(OSError(errno.ENOSPC, "No space left on device", str(tmp))))
    finally:
        staging.discard()
    assert list(tmp_path.iterdir()) == []
