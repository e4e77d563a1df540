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
    with ProgressBar(Console(file=out, width=80, force_terminal=False), "direct predictions") as bar:
        bar(44, 60)
        bar.finish()
        task = bar.bar.tasks[0]
        assert (task.completed, task.total) == (44, 44) and task.finished
    ProgressBar(Console(file=io.StringIO()), "never started").finish()  # no bar: nothing to do
