"""Delimited text recordings: comma, semicolon, tab; decimal point and decimal comma; force units."""

from __future__ import annotations

import numpy as np
import pytest

from fingerpad import measure as m
from fingerpad.errors import FingerpadError

from .sample import FORCE_UNITS, N_ROWS, NORMAL, TIME, check_si, header, rows


def write(path, delimiter: str, decimal: str, unit: str, preamble: str = "") -> None:
    def cell(v: float) -> str:
        text = repr(float(v))
        return text.replace(".", ",") if decimal == "," else text

    lines = [preamble] if preamble else []
    lines.append(delimiter.join(header(unit)))
    lines += [delimiter.join(cell(v) for v in row) for row in rows()]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


@pytest.mark.parametrize("unit", list(FORCE_UNITS))
@pytest.mark.parametrize("name, delimiter, decimal", [
    ("run.csv", ",", "."),
    ("run.csv", ";", "."),
    ("run.csv", ";", ","),
    ("run.tsv", "\t", "."),
    ("run.tsv", "\t", ","),
    ("run.txt", "\t", "."),
    ("run.dat", ";", ","),
])
def test_text_sample_in_si(tmp_path, name, delimiter, decimal, unit):
    path = tmp_path / name
    write(path, delimiter, decimal, unit)
    table = m.read_table(path, m.ColumnSpec())
    assert table.header == header(unit)
    assert table.decimal == decimal
    np.testing.assert_array_equal(table.rows, np.arange(2, N_ROWS + 2))  # line 1 is the header
    np.testing.assert_array_equal(np.asarray(table.columns[1], float), NORMAL)
    check_si(m.read_recording(path), unit)


def test_preamble_skipped_and_rows_are_file_lines(tmp_path):
    path = tmp_path / "run.csv"
    write(path, ";", ",", "N", preamble="Tribometer X; serial 42")
    rec = m.read_recording(path, m.ColumnSpec(skip_rows=1))
    check_si(rec, "N")
    assert rec.rows[0] == 3 and rec.rows[-1] == N_ROWS + 2


def test_comment_lines_and_byte_order_mark(tmp_path):
    path = tmp_path / "run.csv"
    write(path, ",", ".", "mN")
    text = path.read_text().splitlines()
    text.insert(0, "# exported 2021-03-04")
    text.insert(4, "")
    path.write_bytes(b"\xef\xbb\xbf" + ("\n".join(text) + "\n").encode())
    rec = m.read_recording(path)
    check_si(rec, "mN")
    # comment on line 1, header on line 2, data on 3 and 4, a blank line 5, data again from 6
    assert list(rec.rows[:4]) == [3, 4, 6, 7]


def test_spec_units_override_the_header(tmp_path):
    path = tmp_path / "run.csv"
    write(path, ",", ".", "N")
    rec = m.read_recording(path, m.ColumnSpec(units={"normal": "gf", "friction": "gf"}))
    check_si(rec, "gf")


def test_named_columns_without_units_are_si(tmp_path):
    path = tmp_path / "plain.csv"
    path.write_text("t,load,drag\n" + "".join(f"{t},{n},{f}\n" for t, n, f, _ in rows()))
    rec = m.read_recording(path, m.ColumnSpec(columns={"time": "t", "normal": "load", "friction": "drag"}))
    np.testing.assert_array_equal(rec.time, TIME)
    np.testing.assert_array_equal(rec.normal, NORMAL)
    assert rec.position is None


def test_decimal_comma_with_comma_delimiter_refused(tmp_path):
    path = tmp_path / "run.csv"
    write(path, ",", ".", "N")
    with pytest.raises(FingerpadError, match=r"decimal separator and the delimiter are both ','"):
        m.read_table(path, m.ColumnSpec(decimal=","))


def test_binary_or_foreign_text_refused(tmp_path):
    path = tmp_path / "run.csv"
    path.write_bytes(b"PK\x03\x04\x00\x00binary")
    with pytest.raises(FingerpadError, match="not a text file"):
        m.read_table(path, m.ColumnSpec())
    path.write_bytes("time;Fn\n1;\xe9\n".encode("latin-1"))
    with pytest.raises(FingerpadError, match="not a UTF-8 text file"):
        m.read_table(path, m.ColumnSpec())
    path.write_text("# only a comment\n\n")
    with pytest.raises(FingerpadError, match="no header row"):
        m.read_table(path, m.ColumnSpec())


def test_too_few_rows_refused(tmp_path):
    path = tmp_path / "short.csv"
    path.write_text("time,Fn,Ft\n" + "".join(f"{i * 0.01},1,0.5\n" for i in range(9)))
    with pytest.raises(FingerpadError, match=r"short\.csv: only 9 data row\(s\); a recording needs at least 10"):
        m.read_recording(path)


@pytest.mark.parametrize("section", [
    b"1,2\n3,4\n", b"1,2\n3,4", b"1,2\n\n3,4\n", b"1,2\r\n\r\n3,4\r\n", b"\n1,2\n3,4", b"1,2\n3,4\n\n",
    b"# note\n1,2\n  # indented note\n3,4\n", b"5\n6\n7\n", b"1\n\n\n2", b"1\r\n\r2\r\n", b"",
])
def test_data_line_numbers_are_those_of_the_non_empty_non_comment_lines(section: bytes) -> None:
    """The line numbers the reader reports (file line numbers of the data lines) against the
    lines counted one by one in Python: blank lines (LF or CRLF) and lines starting with ``#``
    are not data lines, with the shortcut for files of data lines only or without."""
    from fingerpad.measure.importers.text import _data_line_numbers

    lines = section.split(b"\n")
    if lines and lines[-1] == b"":  # a final line break ends the last line, starts none
        lines = lines[:-1]
    expected = [7 + i for i, line in enumerate(lines)
                if line.rstrip(b"\r") and not line.startswith(b"#")]
    assert _data_line_numbers(section, 7).tolist() == expected
