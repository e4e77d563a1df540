"""Issue 23's table, "where a user waits", from the benchmarks' own reports (``make bench``).

Each benchmark that measures a row of the table writes it into its JSON report under
``"issue23"``: a list of rows ``{"row", "script", "today", "now", "ratio", "ratio_of", "goal",
"met", "load"}``, where ``ratio`` is taken against issue 23's figure for the code before it or
against the peer measured in the same run (``ratio_of`` says which). This script collects the rows
of every ``out/bench/*.json`` and prints one Markdown table, in the issue's order; a row no report
holds yet is printed with the script that measures it::

    .venv/bin/python benchmarks/report.py                  # collect (after the benchmarks ran)
    .venv/bin/python benchmarks/report.py --run            # run the row's scripts first, then collect
    .venv/bin/python benchmarks/report.py --folder out/bench

The row order and the scripts: ``bench_analyse.py`` (the analysis with its figures),
``bench_deflection.py`` (``predict --direction 0``), ``bench_explorer.py`` (a texture
parameter changed in the explorer), ``bench_solver.py`` (the whole ``solve`` command against
tamaas), ``bench_sweep.py`` (points per minute of ``examples/sweep.toml``; 2 workers against 1).
A second table gives issue 34's rows (``"issue34"`` in the reports: ``bench_population_sweep.py``,
``bench_analyse.py``, ``bench_sweep_scheduler.py``, ``bench_map_speed.py``).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
DEFAULT_FOLDER = HERE.parent / "out" / "bench"

#: The issue's rows in its order: (what a user waits for, the script that measures it, today, goal).
ROWS: list[tuple[str, str, str, str]] = [
    ("`fingerpad analyse`, 150 recordings / 9 M rows, every figure", "bench_analyse.py", "88-92 s", "<= 15 s"),
    ("`predict --direction 0`, README ellipsoids, empty cache", "bench_deflection.py", "106 s", "<= 30 s"),
    ("explorer: a texture parameter changed -> new numbers", "bench_explorer.py",
     "new Hertz design 0.26 s, one already computed 1.44 s", "<= 0.5 s new, <= 0.3 s computed"),
    ("whole `solve` command, 1024², against tamaas 2.9", "bench_solver.py", "15.9x", ">= 25x"),
    ("`sweep examples/sweep.toml` (54 points, grid 48, 2 workers)", "bench_sweep.py", "220 points/min",
     ">= 2x"),
    ("2 workers against 1, 16-point sweep", "bench_sweep.py", "1.46x", ">= 1.7x"),
]

#: Issue 34's rows ("a design map of 10,000 textures for 1,000 fingers in ten minutes"), read from
#: the reports' ``"issue34"`` lists; told apart by a word of their wording where one script gives
#: several: (what is measured, the script, a word of its row, today, goal).
ROWS34: list[tuple[str, str, str, str, str]] = [
    ("a 16-point sweep with `adults` against the same sweep without a population", "bench_population_sweep.py",
     "without a population", "2.1x", "<= 1.3x"),
    ("members' coupling against its floor", "bench_population_sweep.py", "floor", "not measured", "<= 3x"),
    ("a 64-point nominal sweep at grid 48 on 2 workers, against the code before", "bench_map_speed.py",
     "code before", "1x", ">= 5x"),
    ("`adults` sweep extrapolated to 10,000 points on 2 cores", "bench_population_sweep.py", "extrapolated",
     "~1.5 h", "<= 10 min"),
    ("100-point `adults` sweep on 2 workers extrapolated to 10,000 points", "bench_map_speed.py", "extrapolated",
     "~1.5 h", "<= 10 min"),
    ("2 workers against 1 on a 64-point sweep", "bench_map_speed.py", "workers against 1", "2.00x", ">= 1.8x, kept"),
    # every panel shape bench_analyse.py measured (3-20 people, 1-8 textures): one row each
    ("`analyse`, 10 people x 5 samples x 3 recordings, every figure", "bench_analyse.py", "`analyse`", "70 s wall",
     "<= 15 s"),
    ("the same sweep on an external scheduler with N local workers", "bench_sweep_scheduler.py", "external",
     "-", "a scaling table in docs/benchmarks.md"),
]

#: What ``--run`` runs (each once, in this order) and with which arguments.
COMMANDS: dict[str, list[str]] = {
    "bench_analyse.py": [],
    "bench_deflection.py": [],
    "bench_explorer.py": [],
    "bench_solver.py": ["--sections", "command", "--grids", "1024", "--no-cm", "--no-previous"],
    "bench_sweep.py": [],
    "bench_population_sweep.py": [],
    "bench_sweep_scheduler.py": [],
    "bench_map_speed.py": [],
}


def collect(folder: Path, key: str = "issue23") -> list[dict[str, Any]]:
    """Every ``key`` row of the JSON reports in ``folder`` (unreadable files are skipped)."""
    rows: list[dict[str, Any]] = []
    for path in sorted(folder.glob("*.json")):
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
        for row in data.get(key, []) if isinstance(data, dict) else []:
            if isinstance(row, dict) and "row" in row:
                rows.append({**row, "report": path.name})
    return rows


def _cell(value: Any) -> str:
    return str(value).replace("|", "/") if value is not None else ""


def table(rows: list[dict[str, Any]]) -> str:
    """The Markdown table: the issue's rows in order, each measured row under its script."""
    lines = ["| where a user waits | script | today (issue 23) | now | ratio | goal | met | load |",
             "|---|---|---|---|---:|---|---|---|"]
    used: set[int] = set()
    for label, script, today, goal in ROWS:
        mine = [i for i, r in enumerate(rows) if r.get("script") == script and i not in used]
        if script == "bench_sweep.py":  # two rows from one script: told apart by their wording
            key = "workers against 1" if "against 1" in label else "sweep.toml"
            mine = [i for i in mine if key in rows[i]["row"]]
        if not mine:
            lines.append(f"| {label} | {script} | {today} | not measured: run benchmarks/{script} | | {goal} | | |")
            continue
        for i in mine:
            used.add(i)
            r = rows[i]
            ratio = r.get("ratio")
            ratio_text = f"{ratio:.2f}x" if isinstance(ratio, (int, float)) else _cell(ratio)
            met = {True: "yes", False: "**no**"}.get(r.get("met"), _cell(r.get("met")))
            lines.append(f"| {_cell(r['row'])} | {script} | {_cell(r.get('today', today))} | {_cell(r.get('now'))} "
                         f"| {ratio_text} ({_cell(r.get('ratio_of'))}) | {_cell(r.get('goal', goal))} | {met} "
                         f"| {_cell(r.get('load'))} |")
    for i, r in enumerate(rows):  # rows of the reports that the issue's list does not name
        if i not in used:
            lines.append(f"| {_cell(r['row'])} | {_cell(r.get('script'))} | {_cell(r.get('today'))} "
                         f"| {_cell(r.get('now'))} | {_cell(r.get('ratio'))} | {_cell(r.get('goal'))} "
                         f"| {_cell(r.get('met'))} | {_cell(r.get('load'))} |")
    return "\n".join(lines)


def table34(rows: list[dict[str, Any]]) -> str:
    """Issue 34's Markdown table, its rows in the issue's order (unmeasured ones say so)."""
    lines = ["| case | script | today (issue 34) | now | ratio | goal | met | load |",
             "|---|---|---|---|---:|---|---|---|"]
    for label, script, word, today, goal in ROWS34:
        mine = [r for r in rows if r.get("script") == script and word in str(r.get("row"))]
        if not mine:
            lines.append(f"| {label} | {script} | {today} | not measured | | {goal} | | |")
        for r in mine:
            ratio = r.get("ratio")
            # a row without a ratio (a panel shape the issue gave no time for) says nothing there
            ratio_text = (f"{ratio:.2f}x ({_cell(r.get('ratio_of'))})" if isinstance(ratio, (int, float))
                          else _cell(ratio))
            met = {True: "yes", False: "**no**"}.get(r.get("met"), _cell(r.get("met")))
            lines.append(f"| {_cell(r['row'])} | {script} | {_cell(r.get('today', today))} | {_cell(r.get('now'))} "
                         f"| {ratio_text} | {goal} | {met} | {_cell(r.get('load'))} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--folder", type=Path, default=DEFAULT_FOLDER, help="where the reports are (out/bench)")
    ap.add_argument("--run", action="store_true", help="run the scripts of the rows first (long: tens of minutes)")
    args = ap.parse_args(argv)
    if args.run:
        for script, extra in COMMANDS.items():
            if not (HERE / script).exists():
                print(f"[report] {script} is not in benchmarks/: its row stays unmeasured", file=sys.stderr)
                continue
            print(f"[report] running {script} ...", file=sys.stderr, flush=True)
            done = subprocess.run([sys.executable, str(HERE / script), *extra], check=False)
            if done.returncode != 0:
                print(f"[report] {script} failed (exit {done.returncode})", file=sys.stderr)
    print("## Issue 23: where a user waits\n")
    print(table(collect(args.folder)))
    print("\n## Issue 34: a design map of 10,000 textures for 1,000 fingers in ten minutes\n")
    print(table34(collect(args.folder, "issue34")))
    return 0


if __name__ == "__main__":
    sys.exit(main())
