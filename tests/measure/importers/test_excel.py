"""Excel workbooks: .xlsx written by openpyxl and .xls written by xlwt, sheets chosen by name."""

from __future__ import annotations

import numpy as np
import pytest

from fingerpad import measure as m
from fingerpad.errors import FingerpadError

from .sample import FORCE_UNITS, N_ROWS, NORMAL, check_si, header, rows


def write_xlsx(path, unit: str, *, preamble: bool = False, sheet: str = "run", first_sheet: str | None = None):
    import openpyxl

    book = openpyxl.Workbook()
    ws = book.active
    if first_sheet:
        ws.title = first_sheet
        ws.append(["nothing here"])
        ws = book.create_sheet(sheet)
    else:
        ws.title = sheet
    if preamble:
        ws.append(["Tribometer export", None, None, None])
    ws.append(header(unit))
    for row in rows():
        ws.append(list(row))
    book.save(path)


def write_xls(path, unit: str, *, sheet: str = "run", first_sheet: str | None = None):
    xlwt = pytest.importorskip("xlwt")
    book = xlwt.Workbook()
    if first_sheet:
        book.add_sheet(first_sheet).write(0, 0, "nothing here")
    ws = book.add_sheet(sheet)
    for j, name in enumerate(header(unit)):
        ws.write(0, j, name)
    for i, row in enumerate(rows()):
        for j, v in enumerate(row):
            ws.write(i + 1, j, float(v))
    book.save(str(path))


@pytest.mark.parametrize("unit", list(FORCE_UNITS))
def test_xlsx_sample_in_si(tmp_path, unit):
    path = tmp_path / "run.xlsx"
    write_xlsx(path, unit)
    table = m.read_table(path, m.ColumnSpec())
    assert table.header == header(unit)
    np.testing.assert_array_equal(table.rows, np.arange(2, N_ROWS + 2))  # sheet rows
    np.testing.assert_array_equal(table.columns[1], NORMAL)
    check_si(m.read_recording(path), unit)


@pytest.mark.parametrize("unit", list(FORCE_UNITS))
def test_xls_sample_in_si(tmp_path, unit):
    path = tmp_path / "run.xls"
    write_xls(path, unit)
    table = m.read_table(path, m.ColumnSpec())
    assert table.header == header(unit)
    np.testing.assert_array_equal(table.rows, np.arange(2, N_ROWS + 2))
    check_si(m.read_recording(path), unit)


def test_xlsx_preamble_row_skipped(tmp_path):
    path = tmp_path / "run.xlsx"
    write_xlsx(path, "mN", preamble=True)
    rec = m.read_recording(path, m.ColumnSpec(skip_rows=1))
    check_si(rec, "mN")
    assert rec.rows[0] == 3


def test_sheet_chosen_by_name(tmp_path):
    xlsx, xls = tmp_path / "run.xlsx", tmp_path / "run.xls"
    write_xlsx(xlsx, "N", sheet="data", first_sheet="notes")
    write_xls(xls, "N", sheet="data", first_sheet="notes")
    for path in (xlsx, xls):
        check_si(m.read_recording(path, m.ColumnSpec(sheet="data")), "N")
        with pytest.raises(FingerpadError, match=r"no sheet 'nope' \(sheets: notes, data\)"):
            m.read_table(path, m.ColumnSpec(sheet="nope"))


def test_empty_cell_is_named_by_row(tmp_path):
    import openpyxl

    path = tmp_path / "gap.xlsx"
    write_xlsx(path, "N")
    book = openpyxl.load_workbook(path)
    book.active.cell(row=6, column=2).value = None
    book.save(path)
    with pytest.raises(FingerpadError, match=r"gap\.xlsx, row 6: missing or non-finite value in column 'Fn \[N\]'"):
        m.read_recording(path)
    rec = m.read_recording(path, m.ColumnSpec(nan_policy="drop"))
    assert len(rec) == N_ROWS - 1 and 6 not in set(rec.rows)


def test_text_cells_are_kept_as_text(tmp_path):
    import openpyxl

    path = tmp_path / "text.xlsx"
    write_xlsx(path, "N")
    book = openpyxl.load_workbook(path)
    book.active.cell(row=4, column=3).value = "overload"
    book.save(path)
    table = m.read_table(path, m.ColumnSpec())
    assert table.columns[2].dtype == object and table.columns[2][2] == "overload"
    with pytest.raises(FingerpadError, match=r"text\.xlsx, row 4: cannot read 'overload' in column 'Ft \[N\]'"):
        m.read_recording(path)


@pytest.mark.parametrize("suffix, what", [(".xlsx", "an Excel workbook"), (".xls", r"an \.xls workbook")])
def test_corrupt_workbooks_refused(tmp_path, suffix, what):
    path = tmp_path / f"bad{suffix}"
    path.write_bytes(b"not a workbook at all" * 8)
    with pytest.raises(FingerpadError, match=rf"bad\{suffix}: cannot open as {what}"):
        m.read_table(path, m.ColumnSpec())


def test_empty_sheet_has_no_header(tmp_path):
    import openpyxl

    path = tmp_path / "empty.xlsx"
    openpyxl.Workbook().save(path)
    with pytest.raises(FingerpadError, match="no header row"):
        m.read_table(path, m.ColumnSpec())
