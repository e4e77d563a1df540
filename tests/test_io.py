"""fingerpad.io: atomic files, output sets and folders written all or none, NetCDF attributes, JSON.

The rule under test everywhere: an error while writing never leaves a half-written file, a mix of
two runs' files or a stray temporary behind, and a folder holding someone else's files is never
replaced.
"""

from __future__ import annotations

import json
import math
import os
import stat
from pathlib import Path

import numpy as np
import pytest

from fingerpad import io as fio
from fingerpad.encode import flatten_attrs, to_jsonable
from fingerpad.errors import FingerpadError


class Boom(RuntimeError):
    """An error raised half-way through a writer."""


def listing(folder: Path) -> list[str]:
    """The files a user sees; an output folder's hidden listing of what fingerpad wrote
    (``fio.MANIFEST``) is left out."""
    names = sorted(p.name for p in folder.iterdir())
    if folder.is_dir() and names and any(n != fio.MANIFEST for n in names) and fio.MANIFEST in names:
        names.remove(fio.MANIFEST)
    return names


# ---------------------------------------------------------------------------------------------
# atomic single files
# ---------------------------------------------------------------------------------------------


def test_write_text_round_trip_utf8(tmp_path):
    target = tmp_path / "out.txt"
    returned = fio.write_text(target, "E_s = 0.4 MPa, µm, ψ\n")
    assert returned == target
    assert target.read_text(encoding="utf-8") == "E_s = 0.4 MPa, µm, ψ\n"
    assert listing(tmp_path) == ["out.txt"]


def test_write_text_replaces_an_existing_file_whole(tmp_path):
    target = tmp_path / "out.txt"
    target.write_text("old " * 1000)
    fio.write_text(target, "new")
    assert target.read_text() == "new"
    assert listing(tmp_path) == ["out.txt"]


def test_failed_writer_leaves_old_file_and_no_temporary(tmp_path):
    target = tmp_path / "keep.json"
    target.write_text('{"old": true}')

    def writer(tmp: Path) -> None:
        tmp.write_text('{"new": ')  # half of it
        raise Boom("disk gone")

    with pytest.raises(Boom):
        fio.atomic_write(target, writer)
    assert target.read_text() == '{"old": true}'
    assert listing(tmp_path) == ["keep.json"]


def test_failed_writer_creates_nothing_when_no_file_was_there(tmp_path):
    with pytest.raises(Boom):
        fio.atomic_write(tmp_path / "new.txt", lambda tmp: (tmp.write_text("part"), (_ for _ in ()).throw(Boom())))
    assert listing(tmp_path) == []


def test_os_error_of_writer_becomes_user_error(tmp_path):
    def writer(tmp: Path) -> None:
        raise PermissionError(13, "Permission denied")

    with pytest.raises(FingerpadError, match=r"cannot write '.*x\.txt': Permission denied"):
        fio.atomic_write(tmp_path / "x.txt", writer)
    assert listing(tmp_path) == []


def test_atomic_path_moves_only_on_success(tmp_path):
    target = tmp_path / "a.bin"
    with fio.atomic_path(target) as tmp:
        assert tmp.parent == tmp_path and tmp.name.startswith(".a.bin.") and tmp.name.endswith(".tmp")
        assert not target.exists()
        tmp.write_bytes(b"\x00\x01")
    assert target.read_bytes() == b"\x00\x01"
    assert listing(tmp_path) == ["a.bin"]


def test_atomic_file_gets_ordinary_permissions(tmp_path):
    target = fio.write_text(tmp_path / "p.txt", "x")
    mask = os.umask(0o022)
    os.umask(mask)
    # mkstemp makes 0600 files; the written file must be readable like any other (0666 & ~umask)
    assert stat.S_IMODE(target.stat().st_mode) == 0o666 & ~mask


def test_check_writable_refusals(tmp_path):
    (tmp_path / "dir").mkdir()
    with pytest.raises(FingerpadError, match="is a directory"):
        fio.check_writable(tmp_path / "dir")
    with pytest.raises(FingerpadError, match="does not exist"):
        fio.check_writable(tmp_path / "missing" / "x.png")
    with pytest.raises(FingerpadError, match=r"--plot '.*x\.txt': the file name must end in \.png or \.pdf"):
        fio.check_writable(tmp_path / "x.txt", "--plot", (".png", ".pdf"))
    with pytest.raises(FingerpadError, match=r"must end in \.nc \(the format"):
        fio.check_writable(tmp_path / "x.txt", "--save", (".nc",))
    # a suffix in any case is accepted
    assert fio.check_writable(tmp_path / "x.PNG", "--plot", (".png",)) == tmp_path / "x.PNG"


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes anywhere")
def test_check_writable_read_only_folder(tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o500)
    try:
        with pytest.raises(FingerpadError, match="is not writable"):
            fio.check_writable(ro / "x.txt")
        with pytest.raises(FingerpadError, match="is not writable"):
            fio.write_text(ro / "x.txt", "x")
    finally:
        ro.chmod(0o700)


# ---------------------------------------------------------------------------------------------
# Staging: a set of files, all or none
# ---------------------------------------------------------------------------------------------


def test_staging_commits_all_files(tmp_path):
    staging = fio.Staging()
    try:
        staging.stage(str(tmp_path / "a.json"), lambda tmp: tmp.write_text("{}"))
        staging.stage(str(tmp_path / "b.csv"), lambda tmp: tmp.write_text("x\n1\n"))
        # nothing final exists before the commit, only hidden parts (and the files' locks)
        assert all(name.startswith(".") and name.endswith((".part", ".lock")) for name in listing(tmp_path))
        staging.commit()
    finally:
        staging.discard()
    assert listing(tmp_path) == ["a.json", "b.csv"]
    assert (tmp_path / "b.csv").read_text() == "x\n1\n"


def test_staging_failure_leaves_neither_partial_nor_earlier_outputs(tmp_path):
    (tmp_path / "a.json").write_text("previous run")
    staging = fio.Staging()
    with pytest.raises(Boom):
        try:
            staging.stage(str(tmp_path / "a.json"), lambda tmp: tmp.write_text("new"))
            staging.stage(str(tmp_path / "b.nc"), lambda tmp: (tmp.write_text("half"), (_ for _ in ()).throw(Boom())))
            staging.commit()
        finally:
            staging.discard()
    assert listing(tmp_path) == ["a.json"]
    assert (tmp_path / "a.json").read_text() == "previous run"


def test_staging_discard_after_commit_is_harmless(tmp_path):
    staging = fio.Staging()
    staging.stage(str(tmp_path / "a.txt"), lambda tmp: tmp.write_text("a"))
    staging.commit()
    staging.discard()
    assert (tmp_path / "a.txt").read_text() == "a"
    assert staging.staged == []


# ---------------------------------------------------------------------------------------------
# OutputFolder: a command's folder, replaced as a whole
# ---------------------------------------------------------------------------------------------

NAMES = ("predict.json", "predict.nc", "areas.png")


def test_output_folder_new(tmp_path):
    out = tmp_path / "deep" / "run"
    folder = fio.OutputFolder(out, NAMES)
    fio.write_text(folder.path("predict.json"), "{}")
    assert not out.exists(), "nothing visible before the commit"
    assert folder.final_path("predict.json") == out / "predict.json"
    folder.commit()
    folder.discard()
    assert listing(out) == ["predict.json"]
    assert listing(tmp_path / "deep") == ["run"], "no hidden build folder left"


def test_output_folder_replaces_an_earlier_run_whole(tmp_path):
    out = tmp_path / "run"
    out.mkdir()
    (out / "predict.json").write_text("old")
    (out / "areas.png").write_text("old figure")
    folder = fio.OutputFolder(out, NAMES)
    fio.write_text(folder.path("predict.json"), "new")
    folder.commit()
    folder.discard()
    # the old figure is not mixed with the new run's files
    assert listing(out) == ["predict.json"]
    assert (out / "predict.json").read_text() == "new"
    assert listing(tmp_path) == ["run"]


def test_output_folder_failure_keeps_the_old_folder(tmp_path):
    out = tmp_path / "run"
    out.mkdir()
    (out / "predict.json").write_text("old")
    folder = fio.OutputFolder(out, NAMES)
    try:
        fio.write_text(folder.path("predict.json"), "new")
        raise Boom("the solver failed after the first file")
    except Boom:
        pass
    finally:
        folder.discard()
    assert listing(out) == ["predict.json"]
    assert (out / "predict.json").read_text() == "old"
    assert listing(tmp_path) == ["run"]


def test_output_folder_refuses_foreign_files_before_writing(tmp_path):
    out = tmp_path / "home"
    out.mkdir()
    (out / "thesis.tex").write_text("years of work")
    (out / "predict.json").write_text("{}")
    with pytest.raises(FingerpadError, match=r"--out '.*home' holds files fingerpad did not write there \(thesis\.tex\)"):
        fio.OutputFolder(out, NAMES)
    assert listing(out) == ["predict.json", "thesis.tex"]
    assert listing(tmp_path) == ["home"], "no hidden folder created"


def test_output_folder_lists_at_most_four_foreign_names(tmp_path):
    out = tmp_path / "many"
    out.mkdir()
    for i in range(6):
        (out / f"f{i}").write_text("")
    with pytest.raises(FingerpadError, match=r"\(f0, f1, f2, f3, \.\.\.\)"):
        fio.OutputFolder.check(out, NAMES, "--results")


def test_output_folder_refuses_a_file(tmp_path):
    f = tmp_path / "file"
    f.write_text("x")
    with pytest.raises(FingerpadError, match="is a file, not an output folder"):
        fio.OutputFolder(f, NAMES)
    assert f.read_text() == "x"


def test_output_folder_check_writes_nothing(tmp_path):
    out = tmp_path / "a" / "b"
    fio.OutputFolder.check(out, NAMES)
    assert listing(tmp_path) == []


def test_empty_folder_is_accepted(tmp_path):
    out = tmp_path / "empty"
    out.mkdir()
    folder = fio.OutputFolder(out, NAMES)
    fio.write_text(folder.path("areas.png"), "png")
    folder.commit()
    folder.discard()
    assert listing(out) == ["areas.png"]


def test_existing_parent(tmp_path):
    assert fio.existing_parent(tmp_path / "a" / "b" / "c") == tmp_path.absolute()
    assert fio.existing_parent(tmp_path / "x") == tmp_path.absolute()


# ---------------------------------------------------------------------------------------------
# NetCDF attributes
# ---------------------------------------------------------------------------------------------


def test_flatten_attrs_conversions():
    attrs = flatten_attrs({
        "none": None,
        "yes": True,
        "no": np.bool_(False),
        "count": np.int32(7),
        "x": np.float32(0.5),
        "nan": float("nan"),
        "text": "caps",
        "path": Path("a/b.toml"),
        "numbers": [1, 2.5, 3],
        "mixed": ["a", 1, None],
        "array": np.array([1, 2], dtype=np.int16),
        "empty": np.array([]),
        "texture": {"radius": 5e-5, "lattice": {"kind": "hex"}},
        "nested_empty": {},
        "bad key!": 1,
        "3d": 2,
    })
    assert attrs["none"] == "none"
    assert attrs["yes"] == "true" and attrs["no"] == "false"
    assert attrs["count"] == 7 and type(attrs["count"]) is int
    assert attrs["x"] == 0.5 and type(attrs["x"]) is float
    assert attrs["nan"] == "nan"
    assert attrs["text"] == "caps"
    assert attrs["path"] == os.fspath(Path("a/b.toml"))
    np.testing.assert_array_equal(attrs["numbers"], [1.0, 2.5, 3.0])
    assert json.loads(attrs["mixed"]) == ["a", 1, None]
    assert attrs["array"].dtype == np.int64 and list(attrs["array"]) == [1, 2]
    assert attrs["empty"] == "[]"
    assert attrs["texture_radius"] == 5e-5
    assert attrs["texture_lattice_kind"] == "hex"
    assert attrs["nested_empty"] == "{}"
    assert attrs["bad_key"] == 1
    assert attrs["_3d"] == 2
    assert set(attrs) == {"none", "yes", "no", "count", "x", "nan", "text", "path", "numbers", "mixed", "array",
                          "empty", "texture_radius", "texture_lattice_kind", "nested_empty", "bad_key", "_3d"}


def test_flatten_attrs_non_finite_lists_become_json():
    attrs = flatten_attrs({"loads": [1.0, float("inf")]})
    assert json.loads(attrs["loads"]) == [1.0, None]


def test_flatten_attrs_empty_and_prefix():
    assert flatten_attrs(None) == {}
    assert flatten_attrs({"a": 1}, "finger") == {"finger_a": 1}
    assert flatten_attrs({"!!": 1}) == {"attr": 1}


# ---------------------------------------------------------------------------------------------
# JSON
# ---------------------------------------------------------------------------------------------


def test_to_jsonable_round_trip_through_json(tmp_path):
    value = {
        "loads": np.array([0.1, 1.0, 4.0]),
        "grid": np.int64(64),
        "converged": np.bool_(True),
        "psi": np.float32(0.25),
        "bad": [float("nan"), float("-inf"), 1.5],
        "path": Path("out") / "predict.nc",
        "nested": ({"k": (1, 2)},),
        "other": complex(1, 2),
        7: "key becomes text",
    }
    text = json.dumps(to_jsonable(value), allow_nan=False)
    fio.write_text(tmp_path / "x.json", text)
    back = json.loads((tmp_path / "x.json").read_text())
    assert back["loads"] == [0.1, 1.0, 4.0]
    assert back["grid"] == 64 and back["converged"] is True
    assert back["psi"] == pytest.approx(0.25)
    assert back["bad"] == [None, None, 1.5]
    assert back["path"] == os.fspath(Path("out") / "predict.nc")
    assert back["nested"] == [{"k": [1, 2]}]
    assert back["other"] == "(1+2j)"
    assert back["7"] == "key becomes text"


def test_to_jsonable_keeps_plain_values():
    plain = {"a": [1, 2.5, "x", None, True]}
    assert to_jsonable(plain) == plain
    assert math.isnan(float("nan")) and to_jsonable(float("nan")) is None


# ------------------------------------------------------------------------------------------------
# read_toml: every TOML file a user gives, one set of checks (issue 30, items 13 and 19)


@pytest.mark.parametrize("content, message", [
    (b"x = " + b"[" * 2000 + b"]" * 2000, r"^study file '.*f\.toml': arrays or tables nested too deeply to read$"),
    (b"x = " + b"{a = " * 2000 + b"1" + b"}" * 2000, "nested too deeply"),
    (b"x = " + b"9" * 5000, r"^study file '.*f\.toml': Exceeds the limit \(4300 digits\) for integer string "
                            r"conversion: value has 5000 digits$"),
    (b"\xff\xfex = 1", "is saved as UTF-16"),
    (b"x = 1\x00", "is a binary file"),
    (b"x = '\xe9'", r"is not UTF-8 text \(byte 6, line 1"),
    (b"x = ", r"^study file '.*f\.toml': Invalid value"),
])
def test_read_toml_refuses_in_one_line(tmp_path, content, message):
    path = tmp_path / "f.toml"
    path.write_bytes(content)
    with pytest.raises(FingerpadError, match=message):
        fio.read_toml(path, "study file")


def test_read_toml_names_what_is_not_a_file(tmp_path):
    import os

    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)  # never opened: reading it would wait for a writer
    with pytest.raises(FingerpadError, match=r"^cannot read study file '.*pipe\.toml': it is a FIFO \(named pipe\); "
                                             r"give a TOML text file$"):
        fio.read_toml(fifo, "study file")
    with pytest.raises(FingerpadError, match=r"^cannot read study file '.*none\.toml': no such file$"):
        fio.read_toml(tmp_path / "none.toml", "study file")
    with pytest.raises(FingerpadError, match="it is a directory"):
        fio.read_toml(tmp_path, "study file")
    big = tmp_path / "big.toml"
    with open(big, "wb") as fh:
        fh.truncate(fio.MAX_TOML_BYTES + 1)
    with pytest.raises(FingerpadError, match="more than the 16 MiB a TOML file may have here"):
        fio.read_toml(big, "study file")
    bom = tmp_path / "bom.toml"
    bom.write_bytes(b"\xef\xbb\xbfx = 1\n")
    assert fio.read_toml(bom) == {"x": 1}
