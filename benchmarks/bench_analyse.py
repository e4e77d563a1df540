"""Benchmark of ``fingerpad analyse`` on a lab-sized study.

10 participants x 5 samples (a flat reference and four bump textures) x 3 recordings of 60 s at
1 kHz: 150 CSV files, 9 million rows. Goal (issue 10): read and analyse in under 10 s on a
2-core machine.

Phases, each timed in the same run:

* ``read``: :func:`fingerpad.measure.load_study` (vectorised parsing, row numbers kept);
* ``analyse``: :func:`fingerpad.measure.analyse_study` without texture geometry (strokes,
  outliers, normalisation, power laws with recording-level intervals, breakpoint tests with
  999 null simulations each, population fits);
* ``analyse + E_s``: the same with the texture table (Hertz micro-model): the E_s fits and
  their sensitivity refits (other micro-model, friction parameters);
* ``report``: tables, NetCDF and HTML without figures;
* ``report + figures``: the same with every figure (participants, samples and the 150 per-recording
  QC figures, drawn by the default process pool), as ``fingerpad analyse`` writes it; ``figures``
  is its difference from ``report``, and ``QC figures, one process`` draws the QC figures alone
  without a pool (``--no-serial`` leaves that out);
* ``fingerpad analyse`` (the command, defaults, as a user runs it: start-up, read, analysis with
  E_s, report with every figure) in a subprocess: the user's wait, against issue 23's 88-92 s;
* the line-by-line reader (the exact fallback, as slow as the former cell-by-cell parser) on
  one file, against the vectorised reader on the same file: their ratio.

The study is generated once into ``--data`` (default: a folder in the system's temp dir) and
reused.

Usage::

    python benchmarks/bench_analyse.py [--data DIR] [--json OUT.json]
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


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", default=os.path.join(tempfile.gettempdir(), "fingerpad-bench-analyse"))
    parser.add_argument("--json", default=None, help="write the timings here")
    parser.add_argument("--no-serial", action="store_true", help="leave out the one-process QC figures timing")
    args = parser.parse_args(argv)

    from fingerpad import measure as m
    from fingerpad.measure.importers.text import _numbered_lines, _slow_table, read_text_table
    from fingerpad.measure.recordings import to_numbers
    from fingerpad.measure.report import write_report

    folder = Path(args.data)
    t0 = time.perf_counter()
    generate(folder)
    print(f"data: {folder} (generated/checked in {time.perf_counter() - t0:.1f} s)")

    timings: dict[str, float] = {}
    cpu: dict[str, float] = {}
    t, c = time.perf_counter(), time.process_time()
    recordings = m.load_study([folder])
    timings["read"], cpu["read"] = time.perf_counter() - t, time.process_time() - c
    rows = sum(len(r) for r in recordings)
    opts = m.AnalysisOptions(reference="flat")
    t, c = time.perf_counter(), time.process_time()
    result = m.analyse_study(recordings, opts)
    timings["analyse"], cpu["analyse"] = time.perf_counter() - t, time.process_time() - c
    t = time.perf_counter()
    result_es = m.analyse_study(recordings, opts, textures=m.read_textures(folder / "samples.csv"))
    timings["analyse + E_s"] = time.perf_counter() - t
    with tempfile.TemporaryDirectory() as tmp:
        t = time.perf_counter()
        write_report(result_es, Path(tmp) / "out", figures=False)
        timings["report (no figures)"] = time.perf_counter() - t
        t = time.perf_counter()
        written = write_report(result_es, Path(tmp) / "fig")
        timings["report + figures"] = time.perf_counter() - t
        n_qc = sum("/qc/" in p.as_posix() for p in written)
        timings["figures"] = timings["report + figures"] - timings["report (no figures)"]
        if not args.no_serial:
            from fingerpad.plotting.measure import qc_inputs, qc_png

            t = time.perf_counter()
            for r in result_es.recordings:
                qc_png(qc_inputs(result_es, r.source), 100)
            timings["QC figures, one process"] = time.perf_counter() - t
        t = time.perf_counter()
        subprocess.run([str(Path(sys.executable).with_name("fingerpad")), "analyse", str(folder), "--reference", "flat",
                        "--out", str(Path(tmp) / "cli")], check=True, stdout=subprocess.DEVNULL)
        timings["fingerpad analyse (command)"] = time.perf_counter() - t

    one = Path(recordings[0].source)
    spec = m.ColumnSpec()
    t = time.perf_counter()
    table = read_text_table(one, spec)
    for j in range(len(table.header)):
        to_numbers(one, table, j)
    fast = time.perf_counter() - t
    t = time.perf_counter()
    section = one.read_bytes().split(b"\n", 1)[1]
    slow_table = _slow_table(one, _numbered_lines(section, 2), table.header, ",", ".")
    for j in range(len(table.header)):
        [float(c) for c in slow_table.columns[j]]  # the former cell-by-cell float()
    slow = time.perf_counter() - t

    print(f"{len(recordings)} recordings, {rows / 1e6:.2f} M rows, {len(result.strokes)} strokes, "
          f"{os.cpu_count()} CPU(s)")
    print(f"  load average before: {os.getloadavg()[0]:.1f} (other work on the machine slows the wall time)")
    for name, seconds in timings.items():
        extra = f"   (CPU {cpu[name]:.2f} s)" if name in cpu else ""
        print(f"  {name:24s} {seconds:7.2f} s{extra}")
    goal = timings["read"] + timings["analyse"]
    print(f"  {'read + analyse':24s} {goal:7.2f} s   (CPU {cpu['read'] + cpu['analyse']:.2f} s; goal: < 10 s)")
    print(f"  one file ({len(table.rows)} rows): vectorised {fast * 1e3:.0f} ms, line by line {slow * 1e3:.0f} ms "
          f"(x{slow / fast:.0f})")
    analysis = timings["read"] + timings["analyse + E_s"]
    print(f"  issue 23 (today: analysis alone 9.5 s, each QC figure ~0.5 s, command 88-92 s; goal <= 15 s):")
    print(f"    analysis alone (read + analyse + E_s) {analysis:6.2f} s   (x{9.5 / analysis:.2f} of 9.5 s)")
    print(f"    figures ({n_qc} QC + participants + samples) {timings['figures']:6.2f} s"
          f"   ({timings['figures'] / max(n_qc, 1):.3f} s per QC figure, x{0.5 * n_qc / timings['figures']:.1f} of"
          f" {n_qc} x 0.5 s)")
    if "QC figures, one process" in timings:
        print(f"    QC figures, one process {timings['QC figures, one process']:6.2f} s"
              f"   ({timings['QC figures, one process'] / max(n_qc, 1):.3f} s each)")
    total = timings["fingerpad analyse (command)"]
    print(f"    fingerpad analyse, total {total:6.2f} s   (x{90.0 / total:.1f} faster than 88-92 s; goal <= 15 s:"
          f" {'met' if total <= 15 else 'not met'})")
    detected = int(result_es.conditions.get("breakpoint_detected", np.zeros(0)).fillna(False).sum())
    print(f"  transitions detected: {detected} of {int((~result_es.conditions['is_reference']).sum())} conditions")
    if args.json:
        Path(args.json).write_text(json.dumps({"rows": rows, "recordings": len(recordings), "timings_s": timings,
                                               "read_plus_analyse_s": goal, "cpu_s": cpu,
                                               "parse_speedup": slow / fast}, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
