"""Benchmark of ``fingerpad analyse`` on a lab-sized study.

10 participants x 5 samples (a flat reference and four bump textures) x 3 recordings of 60 s at
1 kHz: 150 CSV files, 9 million rows. Goals: read and analyse in under 10 s on a 2-core machine
(issue 10); the whole command with every figure in <= 15 s (issue 23, where it took 88-92 s).

Phases, each timed in the same run (wall and CPU seconds of this process; ``--no-phases``
skips them):

* ``read``: :func:`fingerpad.measure.load_study` (vectorised parsing, row numbers kept);
* ``analyse``: :func:`fingerpad.measure.analyse_study` without texture geometry (strokes,
  outliers, normalisation, power laws with recording-level intervals, breakpoint tests with
  999 null simulations each, population fits);
* ``analyse + E_s``: the same with the texture table (Hertz micro-model): the E_s fits and
  their sensitivity refits (other micro-model, friction parameters);
* ``report``: tables, NetCDF and HTML without figures;
* ``report + figures``: the same with every figure (participants, samples and the 150 per-recording
  QC figures, drawn by the default process pool), as ``fingerpad analyse`` writes it; ``figures``
  is its difference from ``report``; ``participant + sample figures`` and ``QC figures`` draw
  them in this process alone (``--no-serial`` leaves those out);
* the line-by-line reader (the exact fallback, as slow as the former cell-by-cell parser) on
  one file, against the vectorised reader on the same file: their ratio.

Then the command itself as a user runs it (``fingerpad analyse``, defaults: start-up, read,
analysis with E_s, report with every figure) in a subprocess: wall seconds and CPU seconds (its
processes together), with the load average before each run. With ``--baseline PYTHON`` (the
interpreter of another checkout, e.g. the main branch's virtual environment) the same command
runs under that interpreter too, alternating with this one (``--reps`` each), so that both see
the same load; the ratios of their medians are the speed-up, and the two reports are compared
file by file (PNG images by their pixels: the encoder's settings may differ; ``report.html``
with its embedded images decoded).

The study is generated once into ``--data`` (default: a folder in the system's temp dir) and
reused. The JSON report (default ``out/bench/analyse.json``) holds issue 23's row under
``"issue23"`` for ``benchmarks/report.py``.

Usage::

    python benchmarks/bench_analyse.py [--data DIR] [--json OUT.json] [--baseline PYTHON] [--reps N]
        [--no-phases] [--no-serial]
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


def generate(folder: Path, participants: int = 10, repetitions: int = 3, seconds: float = 60.0,
             rate: float = 1000.0) -> None:
    """Write the study (recordings, manifest, samples table) unless it is there already."""
    from fingerpad import measure as m
    from fingerpad.measure.simulate import _simulate_file

    stamp = folder / ".complete"
    if stamp.is_file():
        return
    folder.mkdir(parents=True, exist_ok=True)
    textures = {f"bumps{i}": m.TextureGeometry(radius=50e-6, height=h, spacing=100e-6, micro_model="hertz")
                for i, h in enumerate((10e-6, 14e-6, 18e-6, 22e-6), start=1)}
    cfg = m.SimulationConfig(participants=participants, repetitions=repetitions, strokes_per_file=52,
                             sampling_rate=rate, textures=textures)
    rng = np.random.default_rng(0)
    finger = m.models.resolve_finger("default")
    models = {name: m.texture_model(g, finger) for name, g in textures.items()}
    grid = np.geomspace(0.01, 10.0, 64)
    rows = []
    for p in range(participants):
        pid = f"P{p + 1:02d}"
        es, k, n = rng.uniform(0.25e6, 0.4e6), rng.uniform(0.35, 0.8), rng.uniform(0.6, 0.8)
        laws = {"flat": (lambda f, k=k, n=n: k * f ** (n - 1))}
        for name, model in models.items():
            curve = np.log(np.asarray(model(grid, es), dtype=float))
            laws[name] = (lambda f, k=k, n=n, c=curve: k * f ** (n - 1) * np.exp(np.interp(np.log(f), np.log(grid), c)))
        for sample, law in laws.items():
            for rep in range(1, repetitions + 1):
                data, _ = _simulate_file(rng, cfg, law, first_sense=1 if rep % 2 else -1)
                keep = data["time"] < seconds
                table = np.column_stack([data["time"][keep], data["normal"][keep], data["friction"][keep] * 1e3,
                                         data["position"][keep] * 1e3])
                name = f"{pid}_{sample}_{rep}.csv"
                with (folder / name).open("w") as fh:
                    fh.write("time [s],Fn [N],Ft [mN],x [mm]\n")
                    np.savetxt(fh, table, fmt="%.4f,%.5f,%.3f,%.4f")
                rows.append(name)
    with (folder / "samples.csv").open("w") as fh:
        fh.write("sample,radius,height,spacing,micro_model\nflat,,,,\n")
        for name, g in textures.items():
            fh.write(f"{name},{g.radius},{g.height},{g.spacing},hertz\n")
    stamp.write_text("ok")


ROOT = Path(__file__).resolve().parent.parent
DEFAULT_OUT = ROOT / "out" / "bench" / "analyse.json"
ISSUE_START_S = 90.0  # issue 23: the command took 88-92 s
_COMMAND = "import sys; from fingerpad.cli import main; sys.argv[0] = 'fingerpad'; sys.exit(main())"


def run_command(python: str, folder: Path, out: Path) -> dict[str, float]:
    """``fingerpad analyse`` (defaults, every figure) under ``python``: wall and CPU seconds
    (user + system of the command and the processes it waited for), load average before."""
    import resource

    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    load = os.getloadavg()[0]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    subprocess.run([python, "-c", _COMMAND, "analyse", str(folder), "--reference", "flat", "--out", str(out)],
                   check=True, stdout=subprocess.DEVNULL, env=env)
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


def same_report(a: Path, b: Path) -> tuple[int, list[str]]:
    """Files of two reports compared, and those that differ (or are on one side only): PNGs by
    their pixels, ``report.html`` with its embedded PNGs decoded, the rest byte by byte."""
    names = sorted({p.relative_to(a).as_posix() for p in a.rglob("*") if p.is_file()}
                   | {p.relative_to(b).as_posix() for p in b.rglob("*") if p.is_file()})
    differ = []
    for name in names:
        fa, fb = a / name, b / name
        if not (fa.is_file() and fb.is_file()):
            differ.append(name)
            continue
        da, db = fa.read_bytes(), fb.read_bytes()
        if da == db:
            continue
        if name.endswith(".png"):
            same = _pixels(da) == _pixels(db)
        elif name.endswith(".html"):
            same = _html_parts(da.decode("utf-8")) == _html_parts(db.decode("utf-8"))
        else:
            same = False
        if not same:
            differ.append(name)
    return len(names), differ


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
        n_qc = sum("/qc/" in p.as_posix() for p in written)
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
            with timed("QC figures"):  # one process
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


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", default=os.path.join(tempfile.gettempdir(), "fingerpad-bench-analyse"))
    parser.add_argument("--json", type=Path, default=DEFAULT_OUT, help="JSON report (default: out/bench/analyse.json)")
    parser.add_argument("--no-serial", action="store_true", help="leave out the one-process figure timings")
    parser.add_argument("--no-phases", action="store_true", help="time the command only")
    parser.add_argument("--baseline", default=None, metavar="PYTHON",
                        help="interpreter of another checkout: its command runs alternately with this one")
    parser.add_argument("--reps", type=int, default=1, help="runs of each command (median)")
    args = parser.parse_args(argv)

    folder = Path(args.data)
    t0 = time.perf_counter()
    generate(folder)
    print(f"data: {folder} (generated/checked in {time.perf_counter() - t0:.1f} s), {os.cpu_count()} CPU(s)")
    report: dict[str, object] = {"date": time.strftime("%Y-%m-%dT%H:%M:%S"), "cores": os.cpu_count(),
                                 "load_average_start": os.getloadavg(), "issue23": []}
    print(f"  load average at the start: {', '.join(f'{x:.2f}' for x in os.getloadavg())} "
          "(other work on the machine slows the wall time; compare the ratios of one run)")

    if not args.no_phases:
        timings, cpu, n_qc, result = phases(folder, not args.no_serial)
        report.update(phases_s=timings, phases_cpu_s=cpu)
        print(f"in-process phases ({len(result.strokes)} strokes, {n_qc} QC figures; load average now "
              f"{os.getloadavg()[0]:.2f}):")
        for name, seconds in timings.items():
            extra = f"   (CPU {cpu[name]:.2f} s)" if name in cpu else ""
            print(f"  {name:30s} {seconds:7.2f} s{extra}")
        print(f"  read + analyse (goal < 10 s): {timings['read'] + timings['analyse']:.2f} s; with E_s "
              f"{timings['read'] + timings['analyse + E_s']:.2f} s")
        if "QC figures" in cpu:
            print(f"  one QC figure: {cpu['QC figures'] / max(n_qc, 1):.3f} s of CPU in one process")
        fast, slow, n_rows = parse_ratio(Path(result.recordings[0].source))
        report["parse_speedup"] = slow / fast
        print(f"  one file ({n_rows} rows): vectorised {fast * 1e3:.0f} ms, line by line {slow * 1e3:.0f} ms "
              f"(x{slow / fast:.0f})")

    runs: dict[str, list[dict[str, float]]] = {"this": []}
    python = {"this": sys.executable}
    if args.baseline:
        runs["baseline"] = []
        python["baseline"] = args.baseline
    with tempfile.TemporaryDirectory() as tmp:
        for rep in range(max(args.reps, 1)):
            order = ["baseline", "this"] if rep % 2 == 0 else ["this", "baseline"]
            for side in order:
                if side in runs:
                    runs[side].append(run_command(python[side], folder, Path(tmp) / side))
        compared = same_report(Path(tmp) / "this", Path(tmp) / "baseline") if args.baseline else None

    def median(side: str, key: str) -> float:
        return float(np.median([r[key] for r in runs[side]]))

    print("fingerpad analyse (the command, defaults, every figure), a subprocess:")
    for side, rs in runs.items():
        walls = ", ".join(f"{r['wall_s']:.1f}" for r in rs)
        cpus = ", ".join(f"{r['cpu_s']:.1f}" for r in rs)
        loads = ", ".join(f"{r['load_before']:.1f}" for r in rs)
        print(f"  {side:8s} ({python[side]}): wall {median(side, 'wall_s'):6.2f} s (runs {walls}), CPU "
              f"{median(side, 'cpu_s'):6.2f} s (runs {cpus}); load average before each run {loads}")
    wall, cpu_s = median("this", "wall_s"), median("this", "cpu_s")
    load = ", ".join(f"{r['load_before']:.1f}" for rs in runs.values() for r in rs)
    now = f"{wall:.1f} s wall, {cpu_s:.1f} s CPU"
    if args.baseline:
        n, differ = compared  # type: ignore[misc]
        base_wall, base_cpu = median("baseline", "wall_s"), median("baseline", "cpu_s")
        print(f"  this / baseline, same run: wall x{base_wall / wall:.2f} faster, CPU x{base_cpu / cpu_s:.2f} less")
        print(f"  reports compared file by file: {n} files, "
              + ("all the same" if not differ else f"{len(differ)} differ: {', '.join(differ[:5])}"))
        now += (f" (baseline in the same run: {base_wall:.1f} s wall, {base_cpu:.1f} s CPU; x{base_wall / wall:.2f} "
                f"wall, x{base_cpu / cpu_s:.2f} CPU; reports {'the same' if not differ else 'DIFFER'})")
        report["compared"] = {"files": n, "differ": differ}
    print(f"  against issue 23: x{ISSUE_START_S / wall:.1f} of {ISSUE_START_S:.0f} s; goal <= 15 s: "
          f"{'met' if wall <= 15 else 'not met'} in this run")
    report["command"] = runs
    report["issue23"].append({  # type: ignore[union-attr]
        "row": "`fingerpad analyse`, 150 recordings / 9 M rows, every figure", "script": "bench_analyse.py",
        "today": "88-92 s", "now": now, "ratio": ISSUE_START_S / wall, "ratio_of": "issue 23's 90 s / now",
        "goal": "<= 15 s", "met": wall <= 15, "load": load})
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(report, indent=2, default=float) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
