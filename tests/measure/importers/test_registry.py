"""The importers are found by suffix, one per format; unknown suffixes are refused by name."""

from __future__ import annotations

from pathlib import Path

import pytest

from fingerpad import measure as m
from fingerpad.errors import FingerpadError
from fingerpad.measure import importers


def test_every_documented_suffix_has_an_importer():
    documented = {".csv", ".tsv", ".tab", ".txt", ".dat", ".xlsx", ".xlsm", ".xls", ".mat", ".tdms"}
    assert documented <= set(m.supported_suffixes())


@pytest.mark.parametrize("name, fmt", [("a.csv", "text"), ("a.TSV", "text"), ("a.xlsx", "excel"), ("a.xlsm", "excel"),
                                       ("a.xls", "xls"), ("a.mat", "matlab"), ("a.tdms", "tdms")])
def test_importer_by_suffix(name, fmt):
    imp = importers.importer_for(Path(name))
    assert imp is not None and imp.name == fmt


def test_one_importer_per_suffix():
    seen: dict[str, str] = {}
    for imp in importers.importers():
        for suffix in imp.suffixes:
            assert suffix == suffix.lower() and suffix.startswith(".")
            assert suffix not in seen, (suffix, seen.get(suffix), imp.name)
            seen[suffix] = imp.name


def test_unknown_suffix_and_missing_file(tmp_path):
    f = tmp_path / "run.docx"
    f.write_bytes(b"PK\x03\x04")
    with pytest.raises(FingerpadError, match=r"run\.docx: cannot read \.docx files \(readable: .*\.csv.*\.tdms"):
        m.read_table(f, m.ColumnSpec())
    with pytest.raises(FingerpadError, match="file not found"):
        m.read_table(tmp_path / "gone.csv", m.ColumnSpec())
    bare = tmp_path / "noext"
    bare.write_text("x")
    with pytest.raises(FingerpadError, match="cannot read suffix-less files"):
        m.read_table(bare, m.ColumnSpec())


def test_read_rows_gives_text_cells(tmp_path):
    f = tmp_path / "t.csv"
    f.write_text("a,b\n1,x\n2.5,y\n")
    header, rows = importers.read_rows(f, m.ColumnSpec())
    assert header == ["a", "b"]
    assert rows == [(2, ["1.0", "x"]), (3, ["2.5", "y"])]
