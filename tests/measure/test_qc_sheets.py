"""QC sheets: every recording of a participant on one figure (small multiples), drawn on a kept
figure with the same pixels as a new one, written by default in place of a figure per recording."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from fingerpad.measure.report import write_report
from fingerpad.plotting import qcsheet
from fingerpad.plotting.measure import png_bytes
from fingerpad.plotting.qcsheet import figure_qc_sheet, qc_sheet_png, qc_sheets


def test_every_recording_is_on_exactly_one_sheet_of_its_participant(study_small):
    sheets = qc_sheets(study_small)
    participants = sorted(study_small.strokes["participant"].unique())
    assert [s.participant for s in sheets] == participants
    on_sheets = [(s.participant, cell.source) for s in sheets for cell in s.cells]
    expected = sorted((r.participant, r.source) for r in study_small.recordings if r.source in study_small.stroke_reports)
    assert sorted(on_sheets) == expected and len(set(on_sheets)) == len(on_sheets)
    for sheet in sheets:
        # one row per sample, the reference first, each panel in its own place on the grid
        rows = [[cell.recording.sample for cell, (r, _) in zip(sheet.cells, sheet.places) if r == row]
                for row in range(sheet.rows)]
        assert all(len(set(row)) == 1 for row in rows) and rows[0][0] == "flat"
        assert len(set(sheet.places)) == len(sheet.places)
        assert all(0 <= c < sheet.columns for _, c in sheet.places)


def test_a_participant_with_more_rows_than_a_sheet_holds_gets_several_pages(study_small, monkeypatch):
    monkeypatch.setattr(qcsheet, "QC_SHEET_ROWS", 1)
    sheets = qc_sheets(study_small)
    n_samples = study_small.strokes["sample"].nunique()
    first = [s for s in sheets if s.participant == sheets[0].participant]
    assert [(s.page, s.pages, s.rows) for s in first] == [(k + 1, n_samples, 1) for k in range(n_samples)]
    assert sum(len(s.cells) for s in sheets) == len(study_small.stroke_reports)


def test_a_sheet_shows_one_panel_per_recording_with_its_traces_and_strokes(study_small):
    sheet = qc_sheets(study_small)[0]
    fig = figure_qc_sheet(sheet)
    shown = [ax for ax in fig.axes if ax.get_visible()]
    assert len(shown) == len(sheet.cells)
    for ax, cell in zip(shown, sheet.cells):
        normal, friction = ax.lines[0].get_ydata(), ax.lines[1].get_ydata()
        # the traces reach each recording's extremes (min/max decimation)
        assert normal.max() == cell.recording.normal.max() and friction.min() == cell.recording.friction.min()
        n_bands = sum(len(c.get_paths()) for c in ax.collections[1:3])  # stroke shades of both senses
        assert n_bands == len(cell.report.used)
        assert ax.get_title().startswith(f"{cell.recording.sample} {cell.recording.repetition}: "
                                         f"{len(cell.report.used)} strokes")
        assert ax.get_xlim() == shown[0].get_xlim() and ax.get_ylim() == shown[0].get_ylim()  # one scale


def test_sheet_png_on_a_kept_figure_is_the_same_as_on_a_new_one(study_small, monkeypatch):
    """qc_sheet_png redraws one kept figure per grid: each PNG is byte-identical to a new
    figure's, whatever sheet was drawn on it before (panels left empty, a saturated level)."""
    monkeypatch.setattr(qcsheet, "_KEPT", {})
    sheets = qc_sheets(study_small)
    short = dataclasses.replace(sheets[1], cells=sheets[1].cells[:-1], places=sheets[1].places[:-1])
    clip = type("Clip", (), {"channel": "normal", "level": float(np.max(sheets[2].cells[0].recording.normal))})()
    clipped_report = dataclasses.replace(sheets[2].cells[0].report, clips=[clip])
    clipped = dataclasses.replace(sheets[2], cells=(dataclasses.replace(sheets[2].cells[0], report=clipped_report),
                                                    *sheets[2].cells[1:]))
    order = [sheets[0], clipped, short, sheets[0], clipped, sheets[1]]
    fresh = {id(s): png_bytes(figure_qc_sheet(s), 30) for s in order}
    assert len(set(fresh.values())) == 4
    for i, sheet in enumerate(order):
        assert qc_sheet_png(sheet, 30) == fresh[id(sheet)], i


def test_the_report_draws_sheets_by_default_and_per_recording_figures_on_request(study_small, tmp_path):
    default = write_report(study_small, tmp_path / "default", dpi=30, workers=1)
    names = sorted(p.relative_to(tmp_path / "default").as_posix() for p in default if p.suffix == ".png")
    participants = sorted(study_small.strokes["participant"].unique())
    assert [n for n in names if "qc" in n] == [f"figures/qc_{p}.png" for p in participants]
    html = (tmp_path / "default" / "report.html").read_text()
    assert all(f"<h3>QC of participant {p}</h3>" in html for p in participants)
    full = write_report(study_small, tmp_path / "full", dpi=30, workers=1, qc_recordings=True)
    per_recording = [p for p in full if "/qc/" in p.as_posix()]
    assert len(per_recording) == len(study_small.stroke_reports)
    for a in default:  # the sheets and everything else: the same files either way
        assert a.read_bytes() == (tmp_path / "full" / a.relative_to(tmp_path / "default")).read_bytes() or \
            a.name == "report.html", a.name
    none = write_report(study_small, tmp_path / "none", dpi=30, workers=1, qc=False)
    assert not any("qc" in p.name or "/qc/" in p.as_posix() for p in none)


def test_an_empty_sheet_is_refused(study_small):
    from fingerpad.errors import FingerpadError

    sheet = dataclasses.replace(qc_sheets(study_small)[0], cells=(), places=())
    with pytest.raises(FingerpadError, match="no recordings on the QC sheet"):
        figure_qc_sheet(sheet)


def test_rows_follow_the_reference_in_natural_order(study_small):
    """A sheet's rows: the reference, then the samples with their numbers read as numbers
    (bumps8 before bumps22, which string order puts first)."""
    from types import SimpleNamespace

    seen: dict[str, int] = {}
    renamed = []
    for r in study_small.recordings:  # each participant's textured recordings: bumps22, bumps8, ...
        if r.sample != "flat":
            seen[r.participant] = seen.get(r.participant, 0) + 1
            r = dataclasses.replace(r, sample="bumps22" if seen[r.participant] % 2 else "bumps8")
        renamed.append(r)
    result = SimpleNamespace(recordings=renamed, stroke_reports=study_small.stroke_reports,
                             strokes=study_small.strokes, clipped_strokes=study_small.clipped_strokes,
                             options=study_small.options)
    for sheet in qc_sheets(result):
        rows = [next(cell.recording.sample for cell, (r, _) in zip(sheet.cells, sheet.places) if r == row)
                for row in range(sheet.rows)]
        assert rows == ["flat", "bumps8", "bumps22"]
    assert sorted(["bumps22", "bumps8", "b2x", "b10x", "flat"], key=qcsheet.natural_key) == \
        ["b2x", "b10x", "bumps8", "bumps22", "flat"]
