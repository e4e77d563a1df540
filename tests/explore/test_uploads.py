"""The upload area: the only files the explorer reads for a client (no browser needed here; the
forged values from a real browser are in test_browser_security.py)."""

from __future__ import annotations

import numpy as np
import pytest

from fingerpad.errors import FingerpadError
from fingerpad.explore.inputs import validate
from fingerpad.explore.uploads import REFUSED, UploadArea, display_name, page_message


@pytest.fixture()
def area(tmp_path):
    root = tmp_path / "area"
    root.mkdir()
    return UploadArea(root)


def test_uploads_are_size_limited_and_never_named_by_the_user(area, tmp_path):
    up = area.store("../../etc/passwd.npy", b"123", limit=100)
    assert up.path.parent.parent == area.root and up.path.name == "passwd.npy" and up.name == "passwd.npy"
    assert area.check(up.path) == up.path
    with pytest.raises(ValueError, match="limited"):
        area.store("big.txt", b"x" * 101, limit=100)
    with pytest.raises(ValueError, match="empty"):
        area.store("e.txt", b"", limit=100)
    with pytest.raises(ValueError, match="suffix"):
        area.store("map.t$t", b"1", 100)
    odd = area.store("..\\höhe karte.TXT", b"1", 100)
    assert odd.name == "höhe karte.TXT" and odd.path.name == "h_he_karte.txt"
    assert sorted(p.name for p in tmp_path.rglob("*") if p.is_file()) == sorted(["passwd.npy", "h_he_karte.txt"])


def test_only_files_of_the_area_pass_one_message_for_all(area, tmp_path):
    secret = tmp_path / "heights.txt"
    secret.write_text("1 2\n3 4\n")
    own = area.store("map.txt", b"1 2\n3 4\n", 100)
    link_dir = area.root / "upload-0123456789abcdef"
    link_dir.mkdir()
    (link_dir / "heights.txt").symlink_to(secret)  # a link in the area to a file outside
    (area.root / "upload-fedcba9876543210").symlink_to(tmp_path)  # a linked folder
    (link_dir / "d.txt").mkdir()
    outside = tmp_path / "upload-1111111111111111"
    outside.mkdir()
    (outside / "map.txt").write_text("1\n")
    bad = [secret, "/etc/shadow", "/etc/passwd", tmp_path / "missing.txt", link_dir / "heights.txt",
           area.root / "upload-fedcba9876543210" / "heights.txt", link_dir / "d.txt", area.root, link_dir,
           f"{own.path.parent}/../../heights.txt", outside / "map.txt", "map.txt", "", "  ", None, 3, "a\x00b",
           own.path.parent / ".." / own.path.parent.name / ".." / ".." / "heights.txt"]
    for path in bad:
        with pytest.raises(FingerpadError) as info:
            area.check(path)
        assert str(info.value) == REFUSED, path
    # a path that climbs out and back in names the same file: accepted as that file
    assert area.check(f"{own.path.parent}/../{own.path.parent.name}/map.txt") == own.path


def test_validate_refuses_a_map_outside_the_area(area, tmp_path):
    secret = tmp_path / "heights.txt"
    np.savetxt(secret, np.random.default_rng(0).random((8, 8)))
    data = {"texture": {"surface": str(secret), "size": "200um", "height_unit": "um", "periodize": True}}
    assert validate(data).ok  # the library itself reads any file it is given (the CLI's case)
    for study in (data, {"texture": {"size": "200um"}}):
        check = validate(study, uploads=area)
        assert not check.ok and [(e.field, e.message) for e in check.errors] == [("texture.surface", REFUSED)]


def test_messages_name_the_users_file_and_the_pages_fields(area):
    junk = area.store("junk.npy", b"junk junk junk", 100)
    check = validate({"texture": {"surface": str(junk.path), "size": "200um", "height_unit": "um"}},
                     uploads=area, upload=junk)
    (err,) = check.errors
    assert err.field == "texture.surface" and "junk.npy" in err.message and "not a valid .npy file" in err.message
    assert "pickle" not in err.message and str(area.root) not in err.message
    grid = np.ones((6, 6))
    grid[2, 3] = np.nan
    text = "\n".join(" ".join("nan" if np.isnan(v) else "1.0" for v in row) for row in grid).encode()
    gap = area.store("gaps.txt", text, 1000)
    (err,) = validate({"texture": {"surface": str(gap.path), "size": "200um", "height_unit": "um"}},
                      uploads=area, upload=gap).errors
    assert 'tick "fill missing points"' in err.message and "--fill-missing" not in err.message
    assert str(area.root) not in err.message and "gaps.txt" in err.message
    (err,) = validate({"texture": {"surface": str(gap.path)}}, uploads=area, upload=gap).errors
    assert '"map size"' in err.message and '"height unit"' in err.message and "--" not in err.message
    (err,) = validate({"texture": {"surface": str(gap.path), "size": "200um", "height_unit": "um",
                                   "fill_missing": True}}, uploads=area, upload=gap).errors
    assert 'with "periodize" ticked' in err.message and "--" not in err.message and "gaps.txt" in err.message
    assert validate({"texture": {"surface": str(gap.path), "size": "200um", "height_unit": "um",
                                 "fill_missing": True, "periodize": True}}, uploads=area, upload=gap).ok
    assert page_message(f"x {area.root}/upload-0/a.txt y", None, area.root) == "x the uploaded map y"
    (err,) = validate({"texture": {"surface": str(gap.path), "size": "200um", "height_unit": "um",
                                   "fill_missing": True, "periodize": True}, "model": {"kind": "hertz"}},
                      uploads=area, upload=gap).errors
    assert 'needs the unit-cell model "bem" or "both"' in err.message and "--" not in err.message


def test_display_name_is_a_name_not_a_path():
    assert display_name("C:\\Users\\me\\map.txt") == "map.txt"
    assert display_name("a/b/\x1b[31mred.txt") == "[31mred.txt"
    assert len(display_name("x" * 500 + ".txt")) == 120
    assert display_name("") == "map"


def test_page_limits_use_the_librarys_bounds():
    from fingerpad.explore.inputs import MAX_PAGE_LOADS
    from fingerpad.textures import MAX_GRID

    base = {"texture": {"name": "caps", "radius": "100um", "height": "20um", "spacing": "175um"},
            "model": {"kind": "hertz"}}
    bad = validate({**base, "model": {"kind": "hertz", "grid": str(MAX_GRID + 1)}})
    assert [e.field for e in bad.errors] == ["model.grid"] and str(MAX_GRID) in bad.errors[0].message
    many = validate({**base, "loads": {"range": f"0.1N:4N:{MAX_PAGE_LOADS + 1}"}})
    assert [e.field for e in many.errors] == ["loads.range"]
    assert validate({**base, "loads": {"range": f"0.1N:4N:{MAX_PAGE_LOADS}"}}).ok
    listed = validate({**base, "loads": {"values": ["1N"] * (MAX_PAGE_LOADS + 1)}})
    assert [e.field for e in listed.errors] == ["loads.values"] and "at most" in listed.errors[0].message


def test_download_names_are_the_servers():
    pytest.importorskip("panel")
    from fingerpad.explore.views.common import download

    widget = download("CSV", "fingerpad-areas.csv", lambda: "a,b\n", "fp-x")
    widget.filename = "../../etc/cron.d/evil"  # as a client may set it
    assert widget.callback().read() == b"a,b\n"
    assert widget.filename == "fingerpad-areas.csv"


def test_an_npy_of_python_objects_is_refused_without_pickle_advice(area, tmp_path):
    import io

    buf = io.BytesIO()
    np.save(buf, np.array([[1, "a"], [None, 2.0]], dtype=object), allow_pickle=True)
    objs = area.store("objects.npy", buf.getvalue(), 10_000)
    (err,) = validate({"texture": {"surface": str(objs.path), "size": "200um", "height_unit": "um"}},
                      uploads=area, upload=objs).errors
    assert "holds Python objects" in err.message and "allow_pickle" not in err.message
