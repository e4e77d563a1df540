"""The measurement report read back: every CSV table equals the result's, the NetCDF curves carry
units, the figures are images with something on them, and the folder is replaced as a whole."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from fingerpad.errors import FingerpadError
from fingerpad.measure.report import write_report

TABLES = {"summary.csv": "conditions", "participants.csv": "participants", "strokes.csv": "strokes",
          "fits.csv": "fits", "bins.csv": "bins", "spread.csv": "spread"}


@pytest.fixture(scope="module")
def report(study_small, tmp_path_factory):
    out = tmp_path_factory.mktemp("report") / "results"
    files = write_report(study_small, out, dpi=40, qc=True, qc_recordings=True)
    return out, files


@pytest.mark.parametrize("name", sorted(TABLES))
def test_tables_round_trip(report, study_small, name):
    out, _ = report
    expected = getattr(study_small, TABLES[name])
    got = pd.read_csv(out / name, keep_default_na=True)
    assert list(got.columns) == [str(c) for c in expected.columns]
    assert len(got) == len(expected)
    for col in expected.columns:
        if pd.api.types.is_bool_dtype(expected[col]):
            assert got[col].astype(bool).tolist() == expected[col].tolist(), col
        elif pd.api.types.is_numeric_dtype(expected[col]):
            np.testing.assert_allclose(got[col].to_numpy(float), expected[col].to_numpy(float), rtol=1e-14,
                                       equal_nan=True, err_msg=col)


def test_summary_json(report, study_small):
    out, _ = report
    text = (out / "summary.json").read_text()
    summary = json.loads(text)
    assert "NaN" not in text and "Infinity" not in text
    assert summary["study"]["reference_sample"] == "flat"
    assert len(summary["participants"]) == len(study_small.participants)
    assert len(summary["conditions"]) == len(study_small.conditions)


def test_curves_netcdf_has_units(report):
    from fingerpad import netcdf

    out, _ = report
    ds = netcdf.load_dataset(out / "curves.nc")
    assert {"P01", "P02", "P03"} <= set(ds["participant"].values.astype(str))
    for name, var in ds.data_vars.items():
        assert "units" in var.attrs, name


def test_figures_are_drawn(report, study_small):
    from matplotlib.image import imread

    out, files = report
    pngs = sorted((out / "figures").rglob("*.png"))
    n_participants = study_small.strokes["participant"].nunique()
    n_samples = study_small.strokes["sample"].nunique()
    # a QC sheet per participant, and (qc_recordings) a full QC figure per recording
    assert len(pngs) == 2 * n_participants + n_samples + len(study_small.stroke_reports)
    for path in pngs[:: max(1, len(pngs) // 4)]:
        img = imread(path)[..., :3]
        assert img.var() > 1e-3 and len(np.unique(img.reshape(-1, 3), axis=0)) > 2, path.name
    html = (out / "report.html").read_text()
    for path in pngs:
        if "qc" in path.parts:
            assert path.relative_to(out).as_posix() in html, "QC figures are linked"
    assert html.count("<h3>QC of participant ") == n_participants, "QC sheets are embedded"
    # every file the report wrote, besides the folder's hidden listing of them (fingerpad.io.MANIFEST)
    assert sorted(files) == sorted(p for p in out.rglob("*") if p.is_file() and not p.name.startswith("."))


def test_report_replaces_an_earlier_report_whole(study_small, tmp_path):
    out = tmp_path / "res"
    write_report(study_small, out, figures=False)
    (out / "summary.csv").write_text("an older summary of this report")
    write_report(study_small, out, figures=False)
    assert (out / "summary.csv").read_text() != "an older summary of this report"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["res"], "no temporary folder left"


def test_report_keeps_a_file_the_user_added(study_small, tmp_path):
    """A file fingerpad did not write (not in the folder's listing) is the user's: the folder
    is not replaced (issue 20), and nothing in it changes."""
    out = tmp_path / "res"
    write_report(study_small, out, figures=False)
    (out / "my_notes.csv").write_text("mine")
    with pytest.raises(FingerpadError, match=r"holds files fingerpad did not write there \(my_notes\.csv\)"):
        write_report(study_small, out, figures=False)
    assert (out / "my_notes.csv").read_text() == "mine"


def test_report_refuses_a_foreign_folder(study_small, tmp_path):
    out = tmp_path / "thesis"
    out.mkdir()
    (out / "chapter1.tex").write_text("mine")
    with pytest.raises(FingerpadError, match=r"holds files fingerpad did not write there \(chapter1\.tex\)"):
        write_report(study_small, out, figures=False)
    assert sorted(p.name for p in out.iterdir()) == ["chapter1.tex"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["thesis"]


def test_qc_figures_drawn_by_a_process_pool_are_the_same_files(study_small, tmp_path):
    """Two worker processes draw the QC figures; every file of the report is byte-identical to
    the one drawn here without a pool (the figures do not depend on where they are drawn)."""
    one = write_report(study_small, tmp_path / "one", dpi=30, workers=1, qc_recordings=True)
    two = write_report(study_small, tmp_path / "two", dpi=30, workers=2, qc_recordings=True)
    qc = [p for p in one if "/qc/" in p.as_posix()]
    assert len(qc) == len(study_small.recordings) >= 4
    sheets = [p for p in one if p.name.startswith("qc_")]
    assert len(sheets) == study_small.strokes["participant"].nunique()
    assert [p.relative_to(tmp_path / "one") for p in one] == [p.relative_to(tmp_path / "two") for p in two]
    for a, b in zip(one, two):
        if a.suffix in {".png", ".csv", ".json"}:
            assert a.read_bytes() == b.read_bytes(), a.name


@pytest.mark.slow  # ~24 s; the pool's same-bytes check runs in the fast suite (drawn by a process pool)
def test_qc_figures_started_during_the_analysis_are_the_same_files(small_study_dir, tmp_path):
    """EarlyQC starts the QC figures from analyse_study's on_strokes hook, before any fit: every
    file of the report is the same as the one drawn here from the finished result (the hook
    sees the recordings, reports, strokes and outlier flags the result ends with)."""
    from fingerpad import measure as m
    from fingerpad.measure.report import EarlyQC

    opts = m.AnalysisOptions(reference="flat", n_null=199)
    recordings = m.load_study([small_study_dir])
    textures = m.read_textures(small_study_dir / "samples.csv")
    with EarlyQC(dpi=30, workers=2) as early:
        result = m.analyse_study(recordings, opts, textures=textures, on_strokes=early.start)
        assert len(early._futures) == 3  # the sheets, started before the report
        started = write_report(result, tmp_path / "early", dpi=30, early_qc=early)
    plain = write_report(result, tmp_path / "plain", dpi=30, workers=1)
    assert [p.relative_to(tmp_path / "plain") for p in plain] == [p.relative_to(tmp_path / "early") for p in started]
    assert sum(p.name.startswith("qc_") for p in plain) == 3
    for a, b in zip(plain, started):
        if a.suffix in {".png", ".csv", ".json"}:
            assert a.read_bytes() == b.read_bytes(), a.name


@pytest.mark.slow  # ~23 s
def test_strokes_found_by_the_qc_pool_give_the_same_report(small_study_dir, tmp_path):
    """EarlyQC.find_strokes finds every recording's strokes in the pool's forked workers (which
    inherit the recordings), then draws the QC figures there from the inherited samples: the
    whole report is the same, byte for byte, as one analysed and drawn in this process alone."""
    from fingerpad import measure as m
    from fingerpad.measure.report import EarlyQC

    opts = m.AnalysisOptions(reference="flat", n_null=199)
    recordings = m.load_study([small_study_dir])
    textures = m.read_textures(small_study_dir / "samples.csv")
    plain_result = m.analyse_study(recordings, opts, textures=textures)
    plain = write_report(plain_result, tmp_path / "plain", dpi=30, workers=1, qc_recordings=True)
    with EarlyQC(dpi=30, workers=2, recordings=True) as early:
        result = m.analyse_study(recordings, opts, textures=textures, on_strokes=early.start,
                                 find_strokes=early.find_strokes)
        assert len(early._forked) == len(recordings) >= 4  # the workers found the strokes
        pooled = write_report(result, tmp_path / "pooled", dpi=30, early_qc=early, qc_recordings=True)
    assert [p.relative_to(tmp_path / "plain") for p in plain] == [p.relative_to(tmp_path / "pooled") for p in pooled]
    for a, b in zip(plain, pooled):
        if a.suffix in {".png", ".csv", ".json"}:
            assert a.read_bytes() == b.read_bytes(), a.name
    assert [r.used for r in result.stroke_reports.values()] == [r.used for r in plain_result.stroke_reports.values()]


def _figures_to_draw(result):
    from fingerpad.plotting.measure import participant_png, sample_png

    return ([("participant", p, participant_png) for p in sorted(result.strokes["participant"].unique())]
            + [("sample", s, sample_png) for s in sorted(result.strokes["sample"].unique())])


def test_participant_and_sample_figures_drawn_by_a_worker_are_the_same_bytes(study_small):
    """A pool's worker draws a participant or sample figure from the result pickled without its
    recordings, stroke reports and models (_figure_payload): the same PNG bytes as here."""
    from concurrent.futures import ProcessPoolExecutor

    from fingerpad.measure.figurepool import _figure_payload, _pool_figure

    drawn = _figures_to_draw(study_small)
    here = [draw(study_small, key, 30) for _, key, draw in drawn]
    payload = _figure_payload(study_small)
    assert b"recordings" in payload and len(payload) < 2e6  # the samples are not in it
    with ProcessPoolExecutor(2) as pool:
        there = list(pool.map(_pool_figure, *zip(*[(kind, key, 30, "t", payload) for kind, key, _ in drawn])))
    assert len(there) == len(here) >= 4 and there == here


class _Pool:
    """A pool whose workers have taken the first ``taken`` tasks (they cannot be cancelled) and
    draw them in this process (_pool_figure, as a worker would)."""

    def __init__(self, taken: int) -> None:
        self.taken, self.submitted = taken, 0

    def submit(self, fn, *args):
        from concurrent.futures import Future

        future: Future = Future()
        if self.submitted < self.taken:
            future.set_running_or_notify_cancel()
            future.set_result(fn(*args))
        self.submitted += 1
        return future


@pytest.mark.parametrize("taken", [0, 2, 99])
def test_figures_are_drawn_here_unless_a_worker_took_them(study_small, monkeypatch, taken):
    """draw_figures: every figure is a pool task; this process cancels and draws, from the last
    one back, those no worker has started, and takes the others' results: in order, the same
    bytes, whichever side drew each."""
    from fingerpad.measure import figurepool

    drawn = _figures_to_draw(study_small)
    here = [draw(study_small, key, 30) for _, key, draw in drawn]
    calls = []
    counted = [(kind, key, lambda r, k, d, draw=draw: calls.append(k) or draw(r, k, d)) for kind, key, draw in drawn]
    got = list(figurepool.draw_figures(study_small, counted, 30, _Pool(taken)))
    assert got == here
    assert calls == [key for _, key, _ in counted][min(taken, len(drawn)):][::-1]  # the rest, from the back


def _stream_of_worker(parent_stderr_id: int) -> tuple[bool, bool]:
    import sys
    import warnings

    warnings.warn("from a QC worker", RuntimeWarning, stacklevel=1)  # must not block
    return id(sys.stderr) != parent_stderr_id, sys.stderr.fileno() != 2


def test_qc_workers_write_on_streams_of_their_own():
    """The QC pool is forked where a progress bar's thread writes to stderr: a worker gets its own
    stdout/stderr objects (on copies of the descriptors), so a stream lock that thread held at the
    fork cannot block the worker's writes."""
    import sys

    from fingerpad.measure.figurepool import _start_pool

    pool = _start_pool(1)
    try:
        fresh, duplicated = pool.submit(_stream_of_worker, id(sys.stderr)).result(timeout=60)
    finally:
        pool.shutdown()
    assert fresh and duplicated


def test_outputs_list_the_references_of_the_methods_used(report, study_small):
    """summary.json's ``references``, curves.nc's CF ``references`` attribute and the report's
    References section name the same publications: the analysis's statistics (outlier flag,
    transition test and its early stop), the friction law, and both micro-models of the E_s
    fits (the textures' BEM, the sensitivity refits' Hertz)."""
    from fingerpad import netcdf
    from fingerpad.references import REFERENCES

    out, _ = report
    entries = json.loads((out / "summary.json").read_text())["references"]
    keys = [e["key"] for e in entries]
    assert {"iglewicz1993", "davies1987", "besag1991", "greenwood1958", "polonsky1999", "johnson1985"} <= set(keys)
    assert keys[:2] == ["sergachev2021", "fingerpad"] and len(keys) == len(set(keys))
    ds = netcdf.load_dataset(out / "curves.nc")
    assert ds.attrs["references"].splitlines() == [e["citation"] for e in entries]
    page = (out / "report.html").read_text()
    section = page[page.index("<h2>References</h2>"):]
    assert section.count("<li>") == len(keys)
    assert all(REFERENCES[k].title.split(":")[0][:30] in section for k in keys if k != "fingerpad")
