"""Benchmark of ``fingerpad analyse`` on lab-sized studies of several shapes.

A study of P participants x (a flat reference and T textures) x 3 recordings of 60 s at 1 kHz
(46 strokes each, loads 0.1-5 N), generated once per shape by ``fingerpad
simulate-measurement --samples`` as a new user would make it: the first texture is the Hertz
cell with contact spreading over the base (``full_contact_ratio`` 1.5: a contact transition
in the load range), the others caps of 8-22 um on the BEM cell (the default micro-model). The
shapes (``--shapes``, ``PxT``) default to issue 34's panel, 10 people x 4 textures (150 files,
9 M rows), and its corners, 3 x 1 and 20 x 8. Goals: the whole command with every figure in
<= 15 s (issue 34: 70 s wall, 65 s CPU on the 2-core machine for 10 x 4).

For the first shape, the phases timed in one process (wall and CPU seconds; ``--no-phases``
skips them):

* ``read``: :func:`fingerpad.measure.load_study`;
* ``analyse``: :func:`fingerpad.measure.analyse_study` without texture geometry (strokes,
  outliers, normalisation, power laws with recording-level intervals, breakpoint tests with
  999 null simulations each, population fits);
* ``analyse + E_s``: the same with the texture table: the E_s fits and their sensitivity
  refits (other micro-model, friction parameters);
* ``report``: tables, NetCDF and HTML without figures;
* ``report + figures``: the same with every figure (participants, samples and the QC sheets,
  drawn by the default process pool), as ``fingerpad analyse`` writes it; ``figures`` is its
  difference from ``report``; ``participant + sample figures``, ``QC sheets`` and ``QC figures``
  (the full figure per recording of ``--qc-recordings``) draw them in this process alone
  (``--no-serial`` leaves those out);
* the line-by-line reader (the exact fallback, as slow as the former cell-by-cell parser) on
  one file, against the vectorised reader on the same file: their ratio.

Then, for every shape, the command itself as a user runs it (``fingerpad analyse``, defaults:
start-up, read, analysis with E_s, report with every figure) in a subprocess, after one
untimed run that fills the unit-cell cache (``FINGERPAD_CACHE``, a folder of the data's): wall
seconds and CPU seconds (its processes together), with the load average before each run. With
``--baseline PYTHON`` (the interpreter of another checkout, e.g. the main branch's virtual
environment) the same command runs under that interpreter too, alternating with this one
(``--reps`` each), so that both see the same load; the ratios of their medians are the
speed-up, and the two reports are compared file by file (byte for byte; PNGs that differ are
also compared by their pixels, to tell an encoding from a drawing difference).

The studies are generated into ``--data`` (default: a folder in the system's temp dir, one
subfolder per shape) and reused. The JSON report (default ``out/bench/analyse.json``) holds the
rows of issue 23 (``"issue23"``) and issue 34 (``"issue34"``) for ``benchmarks/report.py``.

Usage::

    python benchmarks/bench_analyse.py [--shapes 10x4,3x1,20x8] [--data DIR] [--json OUT.json]
        [--baseline PYTHON] [--reps N] [--no-phases] [--no-serial] [--no-warm]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

#: Recordings per participant and sample, strokes per recording and samples per second: 46
#: strokes of 1 s with 0.15 s pauses make a 60 s recording.
REPETITIONS, STROKES, RATE = 3, 46, 1000


def samples_table(textures: int) -> str:
    """The texture table (``simulate-measurement --samples``) of ``textures`` textures: the
    first with a contact transition (Hertz, contact spreading over the base), the others caps
    on the BEM cell, heights spread over 8-22 um."""
    lines = ["sample,radius,height,spacing,micro_model,full_contact_ratio",
             "transition,50um,18um,100um,hertz,1.5"]
    heights = np.linspace(8, 22, max(textures - 1, 1)) if textures > 2 else [14.0][: textures - 1]
    lines += [f"bumps{round(h)},50um,{h:.4g}um,100um,bem," for h in heights]
    return "\n".join(lines) + "\n"


def _shape(text: str) -> tuple[int, int]:
    people, _, textures = text.lower().partition("x")
    p, t = int(people), int(textures)
    if not (1 <= p <= 99 and 1 <= t <= 12):
        raise argparse.ArgumentTypeError(f"a shape is PxT with 1-99 people and 1-12 textures, got {text!r}")
    return p, t


def generate(folder: Path, participants: int = 10, textures: int = 4, python: str = sys.executable) -> None:
    """Write the study (recordings, manifest, samples table, truth) with ``fingerpad
    simulate-measurement`` unless it is there already."""
    stamp = folder / ".complete"
    if stamp.is_file():
        return
    folder.parent.mkdir(parents=True, exist_ok=True)
    table = folder.parent / f"samples-{textures}.csv"
    table.write_text(samples_table(textures))
    subprocess.run([python, "-c", _COMMAND, "simulate-measurement", "--out", str(folder), "--seed", "0",
                    "--participants", str(participants), "--repetitions", str(REPETITIONS), "--strokes",
                    str(STROKES), "--sampling-rate", str(RATE), "--samples", str(table)],
                   check=True, stdout=subprocess.DEVNULL, env=_env(folder))
    stamp.write_text("ok")


def _env(folder: Path) -> dict[str, str]:
    """The environment of the commands: this one, with the unit-cell cache of the data's folder."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["FINGERPAD_CACHE"] = str(folder.parent / "cell-cache")
    return env


ROOT = Path(__file__).resolve().parent.parent
DEFAULT_OUT = ROOT / "out" / "bench" / "analyse.json"
ISSUE_START_S = 90.0  # issue 23: the command took 88-92 s
_COMMAND = "import sys; from fingerpad.cli import main; sys.argv[0] = 'fingerpad'; sys.exit(main())"


def run_command(python: str, folder: Path, out: Path) -> dict[str, float]:
    """``fingerpad analyse`` (defaults, every figure) under ``python``: wall and CPU seconds
    (user + system of the command and the processes it waited for), load average before."""
    import resource

    load = os.getloadavg()[0]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    subprocess.run([python, "-c", _COMMAND, "analyse", str(folder), "--reference", "flat", "--out", str(out)],
                   check=True, stdout=subprocess.DEVNULL, env=_env(folder))
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {"wall_s": wall, "cpu_s": cpu, "load_before": load}


def _pixels(data: bytes) -> bytes:
    """The decoded pixels of PNG bytes (mode, size and samples)."""
    import io

    from PIL import Image

    with Image.open(io.BytesIO(data)) as im:
        return f"{im.mode} {im.size}".encode() + im.tobytes()


def _html_parts(text: str) -> tuple[str, list[bytes]]:
    """``report.html`` with its embedded PNGs taken out, and their pixels."""
    import base64
    import re

    images: list[bytes] = []

    def cut(match: re.Match[str]) -> str:
        images.append(_pixels(base64.b64decode(match.group(1))))
        return "data:image/png;base64,(image)"

    return re.sub(r"data:image/png;base64,([A-Za-z0-9+/=]+)", cut, text), images


def same_report(a: Path, b: Path) -> tuple[int, list[str], list[str]]:
    """Files of two reports compared: how many, those whose bytes differ (or that are on one
    side only), and among them those whose content differs too (PNGs by their pixels,
    ``report.html`` with its embedded PNGs decoded)."""
    names = sorted({p.relative_to(a).as_posix() for p in a.rglob("*") if p.is_file()}
                   | {p.relative_to(b).as_posix() for p in b.rglob("*") if p.is_file()})
    bytes_differ, content_differs = [], []
    for name in names:
        fa, fb = a / name, b / name
        if not (fa.is_file() and fb.is_file()):
            bytes_differ.append(name)
            content_differs.append(name)
            continue
        da, db = fa.read_bytes(), fb.read_bytes()
        if da == db:
            continue
        bytes_differ.append(name)
        if name.endswith(".png"):
            same = _pixels(da) == _pixels(db)
        elif name.endswith(".html"):
            same = _html_parts(da.decode("utf-8")) == _html_parts(db.decode("utf-8"))
        else:
            same = False
        if not same:
            content_differs.append(name)
    return len(names), bytes_differ, content_differs


def phases(folder: Path, serial: bool) -> tuple[dict[str, float], dict[str, float], int, object]:
    """The in-process phases (module doc): wall and CPU seconds, the number of QC figures, and
    the study's result without texture geometry."""
    from fingerpad import measure as m
    from fingerpad.measure.report import write_report

    timings: dict[str, float] = {}
    cpu: dict[str, float] = {}

    class timed:
        def __init__(self, name: str) -> None:
            self.name = name

        def __enter__(self) -> None:
            self.t, self.c = time.perf_counter(), time.process_time()

        def __exit__(self, *exc: object) -> None:
            timings[self.name] = time.perf_counter() - self.t
            cpu[self.name] = time.process_time() - self.c

    with timed("read"):
        recordings = m.load_study([folder])
    opts = m.AnalysisOptions(reference="flat")
    with timed("analyse"):
        result = m.analyse_study(recordings, opts)
    with timed("analyse + E_s"):
        result_es = m.analyse_study(recordings, opts, textures=m.read_textures(folder / "samples.csv"))
    with tempfile.TemporaryDirectory() as tmp:
        with timed("report (no figures)"):
            write_report(result_es, Path(tmp) / "out", figures=False)
        with timed("report + figures"):
            written = write_report(result_es, Path(tmp) / "fig")
        n_qc = len(result_es.stroke_reports)  # recordings with QC traces (on sheets, or one figure each)
        timings["figures"] = timings["report + figures"] - timings["report (no figures)"]
        if serial:
            from fingerpad.plotting import measure as pm

            kept = all(hasattr(pm, name) for name in ("participant_png", "sample_png"))
            with timed("participant + sample figures"):  # one process (kept figures where the code has them)
                for p in sorted(result_es.strokes["participant"].unique()):
                    pm.participant_png(result_es, p, 100) if kept else pm.png_bytes(
                        pm.figure_participant(result_es, p), 100)
                for s in sorted(result_es.strokes["sample"].unique()):
                    pm.sample_png(result_es, s, 100) if kept else pm.png_bytes(pm.figure_sample(result_es, s), 100)
            try:
                from fingerpad.plotting.qcsheet import qc_sheet_png, qc_sheets
            except ImportError:  # code before the QC sheets
                qc_sheets = None
            if qc_sheets is not None:
                with timed("QC sheets"):  # one process: every recording on its participant's sheet
                    for sheet in qc_sheets(result_es):
                        qc_sheet_png(sheet, 100)
            with timed("QC figures"):  # one process, a full figure per recording (--qc-recordings)
                for r in result_es.recordings:
                    pm.qc_png(pm.qc_inputs(result_es, r.source), 100)
    return timings, cpu, n_qc, result


def parse_ratio(one: Path) -> tuple[float, float, int]:
    """Seconds to read ``one`` with the vectorised reader and line by line (the exact fallback,
    as slow as the former cell-by-cell parser), and its rows."""
    from fingerpad import measure as m
    from fingerpad.measure.importers.text import _numbered_lines, _slow_table, read_text_table
    from fingerpad.measure.recordings import to_numbers

    t = time.perf_counter()
    table = read_text_table(one, m.ColumnSpec())
    for j in range(len(table.header)):
        to_numbers(one, table, j)
    fast = time.perf_counter() - t
    t = time.perf_counter()
    section = one.read_bytes().split(b"\n", 1)[1]
    slow_table = _slow_table(one, _numbered_lines(section, 2), table.header, ",", ".")
    for j in range(len(table.header)):
        [float(c) for c in slow_table.columns[j]]  # the former cell-by-cell float()
    return fast, time.perf_counter() - t, len(table.rows)


def _median(runs: list[dict[str, float]], key: str) -> float:
    return float(np.median([r[key] for r in runs]))


def command_runs(folder: Path, python: dict[str, str], reps: int, warm: bool = True
                 ) -> tuple[dict[str, list[dict[str, float]]], tuple[int, list[str], list[str]] | None]:
    """The command on ``folder`` under each interpreter of ``python`` (``"this"`` and maybe
    ``"baseline"``), alternating, ``reps`` times each, after one untimed run of each that fills
    the unit-cell cache (``warm``); and the two reports compared (:func:`same_report`) with a
    baseline."""
    runs: dict[str, list[dict[str, float]]] = {side: [] for side in python}
    with tempfile.TemporaryDirectory() as tmp:
        for side in python if warm else ():  # untimed: the cells of the textures solved or read into the cache
            run_command(python[side], folder, Path(tmp) / f"warm-{side}")
        for rep in range(max(reps, 1)):
            order = ["baseline", "this"] if rep % 2 == 0 else ["this", "baseline"]
            for side in order:
                if side in python:
                    runs[side].append(run_command(python[side], folder, Path(tmp) / side))
        compared = same_report(Path(tmp) / "this", Path(tmp) / "baseline") if "baseline" in python else None
    return runs, compared


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--shapes", default="10x4,3x1,20x8",
                        help="studies to time, PxT: P participants, T textures (default 10x4,3x1,20x8)")
    parser.add_argument("--data", default=os.path.join(tempfile.gettempdir(), "fingerpad-bench-analyse-34"))
    parser.add_argument("--json", type=Path, default=DEFAULT_OUT, help="JSON report (default: out/bench/analyse.json)")
    parser.add_argument("--no-serial", action="store_true", help="leave out the one-process figure timings")
    parser.add_argument("--no-phases", action="store_true", help="time the commands only")
    parser.add_argument("--baseline", default=None, metavar="PYTHON",
                        help="interpreter of another checkout: its command runs alternately with this one")
    parser.add_argument("--reps", type=int, default=1, help="runs of each command (median)")
    parser.add_argument("--no-warm", action="store_true",
                        help="no untimed run first (the data's cell cache already filled, e.g. by generating it)")
    args = parser.parse_args(argv)
    shapes = [_shape(text) for text in args.shapes.split(",") if text.strip()]

    data = Path(args.data)
    report: dict[str, object] = {"date": time.strftime("%Y-%m-%dT%H:%M:%S"), "cores": os.cpu_count(),
                                 "load_average_start": os.getloadavg(), "issue23": [], "issue34": [], "shapes": {}}
    folders = {}
    for people, textures in shapes:
        folder = data / f"{people}x{textures}"
        t0 = time.perf_counter()
        generate(folder, people, textures)
        folders[(people, textures)] = folder
        print(f"data {people} people x {textures} texture(s) + flat x {REPETITIONS} recordings: {folder} "
              f"(generated/checked in {time.perf_counter() - t0:.1f} s)")
    print(f"{os.cpu_count()} CPU(s); load average at the start: {', '.join(f'{x:.2f}' for x in os.getloadavg())} "
          "(other work on the machine slows the wall time; compare the ratios of one run)")

    if not args.no_phases:
        folder = folders[shapes[0]]
        os.environ["FINGERPAD_CACHE"] = _env(folder)["FINGERPAD_CACHE"]
        timings, cpu, n_qc, result = phases(folder, not args.no_serial)
        report.update(phases_s=timings, phases_cpu_s=cpu)
        print(f"in-process phases, {folder.name} ({len(result.strokes)} strokes, {n_qc} recordings; load average now "
              f"{os.getloadavg()[0]:.2f}):")
        for name, seconds in timings.items():
            extra = f"   (CPU {cpu[name]:.2f} s)" if name in cpu else ""
            print(f"  {name:30s} {seconds:7.2f} s{extra}")
        if "QC figures" in cpu:
            print(f"  one full QC figure: {cpu['QC figures'] / max(n_qc, 1):.3f} s of CPU in one process")
        if "QC sheets" in cpu:
            print(f"  one recording on a QC sheet: {cpu['QC sheets'] / max(n_qc, 1):.3f} s of CPU in one process")
        fast, slow, n_rows = parse_ratio(Path(result.recordings[0].source))
        report["parse_speedup"] = slow / fast
        print(f"  one file ({n_rows} rows): vectorised {fast * 1e3:.0f} ms, line by line {slow * 1e3:.0f} ms "
              f"(x{slow / fast:.0f})")

    python = {"this": sys.executable, **({"baseline": args.baseline} if args.baseline else {})}
    print("fingerpad analyse (the command, defaults, every figure), a subprocess, after one untimed run:")
    print(f"  {'study':>6s} {'files':>5s} {'side':8s} {'wall s':>7s} {'CPU s':>7s} {'CPU/wall':>8s}  "
          "runs (wall/CPU), load before")
    for (people, textures), folder in folders.items():
        runs, compared = command_runs(folder, python, args.reps, warm=not args.no_warm)
        files = people * (textures + 1) * REPETITIONS
        label = f"{people}x{textures}"
        for side, rs in runs.items():
            detail = ", ".join(f"{r['wall_s']:.1f}/{r['cpu_s']:.1f}" for r in rs)
            loads = ", ".join(f"{r['load_before']:.1f}" for r in rs)
            w, c = _median(rs, "wall_s"), _median(rs, "cpu_s")
            print(f"  {label:>6s} {files:5d} {side:8s} {w:7.2f} {c:7.2f} {c / w:8.2f}  {detail}; load {loads}")
        wall, cpu_s = _median(runs["this"], "wall_s"), _median(runs["this"], "cpu_s")
        # CPU / wall: how many of the cores the command kept busy (2 at most on the 2-core machine);
        # CPU seconds hardly change with the machine's other work, the wall time does
        now = f"{wall:.1f} s wall, {cpu_s:.1f} s CPU (CPU/wall {cpu_s / wall:.2f})"
        entry: dict[str, object] = {"people": people, "textures": textures, "files": files, "runs": runs}
        if compared is not None:
            n, bytes_differ, content_differs = compared
            base_wall, base_cpu = _median(runs["baseline"], "wall_s"), _median(runs["baseline"], "cpu_s")
            print(f"  {label:>6s} this / baseline, same run: wall x{base_wall / wall:.2f} faster, CPU "
                  f"x{base_cpu / cpu_s:.2f} less; reports: {n} files, "
                  + ("all byte-identical" if not bytes_differ else
                     f"{len(bytes_differ)} differ in bytes ({', '.join(bytes_differ[:4])}), "
                     f"{len(content_differs)} in content"))
            now += (f" (baseline in the same run: {base_wall:.1f} s wall, {base_cpu:.1f} s CPU; x{base_wall / wall:.2f} "
                    f"wall, x{base_cpu / cpu_s:.2f} CPU; reports {'identical' if not bytes_differ else 'DIFFER'})")
            entry["compared"] = {"files": n, "bytes_differ": bytes_differ, "content_differs": content_differs}
        report["shapes"][label] = entry  # type: ignore[index]
        load = ", ".join(f"{r['load_before']:.1f}" for rs in runs.values() for r in rs)
        report["issue34"].append({  # type: ignore[union-attr]
            "row": f"`analyse`, {people} people x {textures + 1} samples x {REPETITIONS} recordings, every figure",
            "script": "bench_analyse.py", "today": "70 s wall" if (people, textures) == (10, 4) else "-",
            "now": now, "ratio": 70.0 / wall if (people, textures) == (10, 4) else None,
            "ratio_of": "issue 34's 70 s / now", "goal": "<= 15 s", "met": wall <= 15, "load": load})
        if (people, textures) == (10, 4):
            report["issue23"].append({  # type: ignore[union-attr]
                "row": "`fingerpad analyse`, 150 recordings / 9 M rows, every figure", "script": "bench_analyse.py",
                "today": "88-92 s", "now": now, "ratio": ISSUE_START_S / wall, "ratio_of": "issue 23's 90 s / now",
                "goal": "<= 15 s", "met": wall <= 15, "load": load})
        print(f"  {label:>6s} goal <= 15 s: {'met' if wall <= 15 else 'not met'} in this run")
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(report, indent=2, default=float) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
