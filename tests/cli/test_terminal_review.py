"""Terminal output of the review (2026-11-26): `fingerpad fingers` and `fingerpad textures` on an
80-column terminal (every line fits, long entries continue indented under their own line: they
ran to ~160 columns, or restarted at column 0), and a progress bar that ends full."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from fingerpad.cli import app
from fingerpad.finger import FINGER_PARAMS, FINGER_PRESETS


@pytest.mark.parametrize("command", ["fingers", "textures"])
def test_listing_fits_80_columns(command):
    res = CliRunner().invoke(app, [command], terminal_width=80, env={"COLUMNS": "80"})
    assert res.exit_code == 0, res.output
    lines = res.stdout.splitlines()
    assert max(len(line) for line in lines) <= 80, max(lines, key=len)
    words = " ".join(res.stdout.split())
    if command == "fingers":
        for name in (*FINGER_PRESETS, *(p.name for p in FINGER_PARAMS)):
            assert f"{name}" in words
        assert "skin layered: t 300 um, E_1 300 kPa, E_2 30.4 kPa" in words
    else:
        assert "--lattice TEXT, square: square: one asperity per spacing x spacing cell; hexagonal:" in words
        # the continuation of an entry is indented under it, not restarted at column 0
        assert all(line.startswith("      ") for line in lines if "six neighbours at spacing" in line)


def test_progress_bar_finishes_full_when_work_ends_early():
    """`design` announces its --evaluations budget; a search that converges earlier closed its
    bar at e.g. 44/60, as if cut short. finish() closes it full at the count done."""
    import io

    from rich.console import Console

    from fingerpad.cli.common import ProgressBar

    out = io.StringIO()
    with ProgressBar(Console(file=out, width=80, force_terminal=True), "direct predictions") as bar:
        bar(44, 60)
        bar.finish()
        task = bar.bar.tasks[0]
        assert (task.completed, task.total) == (44, 44) and task.finished
    ProgressBar(Console(file=io.StringIO()), "never started").finish()  # no bar: nothing to do


def test_progress_written_to_a_log_is_plain_lines_not_a_frozen_bar(monkeypatch):
    """Issue 30, item 21: a bar written where stderr is not a terminal (a log, a pipe) cannot
    redraw itself and was left in the log at its last state, a line of box characters. There:
    no bar, plain lines at most every PLAIN_PROGRESS_EVERY seconds (none for short work)."""
    import io

    from rich.console import Console

    from fingerpad.cli import common

    out = io.StringIO()
    with common.ProgressBar(Console(file=out, width=80, force_terminal=False), "unit cell ψ(p)") as bar:
        for i in range(5):
            bar(i, 202)
        bar.finish()
    assert out.getvalue() == "" and bar.bar is None  # short work: nothing
    monkeypatch.setattr(common, "PLAIN_PROGRESS_EVERY", 0.0)
    with common.ProgressBar(Console(file=out, width=80, force_terminal=False), "unit cell ψ(p)") as bar:
        bar(45, 202)
        bar.detail("iteration 3")
        bar.stage("deflection ramps")("shear ramp 3/6 done")
    lines = out.getvalue().splitlines()
    assert [ln.rsplit(" (", 1)[0] for ln in lines] == ["unit cell ψ(p): 45/202", "unit cell ψ(p): 45/202, iteration 3",
                                                        "deflection ramps: shear ramp 3/6 done"], lines
    assert not any(c in out.getvalue() for c in "━╸\x1b")


def test_progress_bar_stage_row_has_its_own_clock_and_no_count():
    """`predict --direction`: after the unit cell's bar is full, the deflection ramps run for
    tens of seconds. Their messages went to the full bar's detail, whose clock had stopped and
    whose long text pushed the bar out of an 80-column terminal; they get a row of their own:
    a running (unfinished) task, no count, its label and message."""
    import io

    from rich.console import Console

    from fingerpad.cli.common import ProgressBar

    out = io.StringIO()
    with ProgressBar(Console(file=out, width=80, force_terminal=True), "unit cell ψ(p)") as bar:
        bar(70, 70)
        show = bar.stage("deflection ramps")
        show("shear ramp 3/6 done (p = 26.8 kPa)")
        main, ramps = bar.bar.tasks
        assert main.finished and main.fields["count"] == "70/70"
        assert not ramps.finished and ramps.total is None and ramps.fields["count"] == ""
        assert ramps.description == "deflection ramps" and ramps.fields["detail"].startswith("shear ramp 3/6")
        bar.bar.refresh()
    lines = [line for line in out.getvalue().splitlines() if "deflection ramps" in line]
    assert lines and "shear ramp 3/6 done" in lines[-1]
    # a stage alone (the unit cell cached: its bar never started) shows its row only
    with ProgressBar(Console(file=io.StringIO(), width=80, force_terminal=True), "unit cell ψ(p)") as bar:
        bar.stage("deflection ramps")("pressing 2 section(s)")
        assert [t.description for t in bar.bar.tasks] == ["deflection ramps"]


def test_textures_piped_keeps_each_meaning_beside_its_parameter():
    """Issue 30, item 21: piped to a file (140 columns), `fingerpad textures` printed each family's
    parameters and meanings as two cells of many lines, so a wrapped meaning pushed the next ones
    down beside other parameters ("--spacing LENGTH ... (h <= R)")."""
    from typer.testing import CliRunner

    from fingerpad.cli import app
    from fingerpad.textures import registry

    res = CliRunner().invoke(app, ["textures"])
    assert res.exit_code == 0
    lines = res.stdout.splitlines()
    for fam in registry().values():
        start = next(i for i, ln in enumerate(lines) if ln.startswith(f"│ {fam.name} "))
        for p in fam.params:
            row = next(ln for ln in lines[start:] if f"│ {p.option} {p.metavar} " in ln)
            words = " ".join(p.doc.split()[:2])
            assert words in row, (fam.name, p.name, row)  # the meaning starts on the option's own line
