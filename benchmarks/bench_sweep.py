"""Sweep throughput on Dask: points per minute, 1 against 2 workers, and the cache's effect.

Two parts, in one run (``make bench``; issue 23's sweep rows):

1. ``examples/sweep.toml`` as the README runs it (54 points, grid 48, 2 workers, an empty
   unit-cell cache): points per minute against issue 23's figure for the code before it,
   220 points/min on the quiet 2-core machine (goal: at least twice that).
2. A grid sweep of spherical caps (spacing x height, the default study's material and finger,
   ``--points``, 16 by default) three times into fresh stores: 1 worker and 2 workers, each with
   an empty cache, then 2 workers again on the filled cache. Goal: 2 workers at least 1.7x the
   points per minute of one (issue 23 measured 1.46x before). The cluster's start-up is
   included (it is part of what a user waits for). A 1-point sweep runs first, untimed, so that
   neither side pays this process's first imports; the two sides alternate, ``--rounds`` times
   (3 by default), and the medians are reported.
3. The ceiling of that ratio on this machine: the same LocalCluster (started by
   :func:`fingerpad.design.engine.connect`, as a sweep starts it) running one task per point
   that only burns the CPU a point cost in the 1-worker sweep and returns a small dict: no
   store, no cache, no physics. What Dask and two cores allow; the sweep's own overheads (the
   Zarr store laid out and written in the client, the cell cache, bigger task arguments) come
   on top.

    python benchmarks/bench_sweep.py [--points 16] [--grid 48] [--rounds 3] [--no-example]

Output: a table on stdout, JSON in ``out/bench/sweep.json`` (its ``issue23`` rows are read by
``benchmarks/report.py``). The machine is shared: the load average is printed beside the numbers.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import statistics
import tempfile
import time
from pathlib import Path

STUDY = """
[texture]
name = "caps"
radius = "100um"
height = "20um"
spacing = "175um"
lattice = "hexagonal"

[material]
modulus = "0.5GPa"
poisson = 0.4

[model]
kind = "bem"
grid = {grid}

[sweep]
loads = "0.1N:4N:20"
[sweep.axes]
spacing = "130um:400um:{n_spacing}"
height = "6um:20um:{n_height}"
"""


ROOT = Path(__file__).resolve().parent.parent
DEFAULT_OUT = ROOT / "out" / "bench" / "sweep.json"
#: Issue 23's figures for the code before it (quiet 2-core machine).
TODAY_POINTS_PER_MINUTE = 220.0
TODAY_SPEEDUP = 1.46


def ceiling(workers: int, points: int, cpu_seconds: float) -> float:
    """Wall seconds of ``points`` tasks that each burn ``cpu_seconds`` of CPU, on a LocalCluster of
    ``workers`` started as a sweep starts it (part 3 of the module's docstring)."""
    from distributed import as_completed

    from fingerpad.design.engine import _close_quietly, connect

    t0 = time.perf_counter()
    client, cluster = connect(None, workers)
    try:
        futures = [client.submit(_burn, i, cpu_seconds, pure=False) for i in range(points)]
        for fut in as_completed(futures, loop=client.loop):
            fut.result()
    finally:
        _close_quietly(client)
        cluster.close()
    return time.perf_counter() - t0


def _burn(index: int, cpu_seconds: float) -> dict:
    """A task that only costs CPU (this thread's, as a point's solves do) and returns a small dict."""
    start = time.thread_time()
    while time.thread_time() - start < cpu_seconds:
        pass
    return {"index": index, "values": [0.0] * 20}


def _cpu_children() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run(study: Path, folder: Path, workers: int, cache: Path) -> tuple[float, float, int, int]:
    from fingerpad.design.engine import run_sweep
    from fingerpad.design.spec import read_sweep_file, sweep_from_dict

    os.environ["FINGERPAD_CACHE"] = str(cache)
    spec = sweep_from_dict(read_sweep_file(str(study)))
    store = folder / f"r{workers}-{time.monotonic_ns()}.zarr"
    first: list[float] = []

    def progress(report) -> None:
        if report.computed and not first:
            first.append(time.perf_counter())

    t0 = time.perf_counter()
    report = run_sweep(spec, store, workers=workers, progress=progress)
    total = time.perf_counter() - t0
    shutil.rmtree(store, ignore_errors=True)
    return total, report.computed, report.cells_solved, report.cache_hits


def _load() -> str:
    return Path("/proc/loadavg").read_text().split()[0] if Path("/proc/loadavg").exists() else "?"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=16, help="points of the 1-vs-2-worker sweep (a near-square grid)")
    parser.add_argument("--grid", type=int, default=48, help="grid points along x of each cell")
    parser.add_argument("--example", type=Path, default=ROOT / "examples" / "sweep.toml",
                        help="the study of part 1 (default: examples/sweep.toml)")
    parser.add_argument("--rounds", type=int, default=3, help="alternating rounds of part 2 (medians reported)")
    parser.add_argument("--no-example", action="store_true", help="skip part 1")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help="JSON report (default: out/bench/sweep.json)")
    args = parser.parse_args()
    n_spacing = max(2, round(args.points ** 0.5))
    n_height = max(1, args.points // n_spacing)
    folder = Path(tempfile.mkdtemp(prefix="fingerpad-bench-sweep-"))
    report: dict = {"date": time.strftime("%Y-%m-%dT%H:%M:%S"), "cores": os.cpu_count(), "load_start": _load(),
                    "issue23": []}
    try:
        if not args.no_example:
            seconds, points, solved, hits = run(args.example, folder, 2, folder / "cache-example")
            rate = 60 * points / seconds
            report["example"] = {"study": str(args.example), "seconds": seconds, "points": points,
                                 "points_per_minute": rate, "cells_solved": solved, "load": _load()}
            print(f"{args.example.name}: {points} points, 2 workers, empty cache: {seconds:.1f} s, {rate:.1f} points/min "
                  f"({rate / TODAY_POINTS_PER_MINUTE:.2f}x issue 23's {TODAY_POINTS_PER_MINUTE:g}; goal 2x), "
                  f"load average {_load()}")
            report["issue23"].append({
                "row": "`sweep examples/sweep.toml` (54 points, grid 48, 2 workers)", "script": "bench_sweep.py",
                "today": f"{TODAY_POINTS_PER_MINUTE:g} points/min", "now": f"{rate:.0f} points/min ({seconds:.1f} s)",
                "ratio": rate / TODAY_POINTS_PER_MINUTE, "ratio_of": "now / today's figure", "goal": ">= 2x",
                "met": rate >= 2 * TODAY_POINTS_PER_MINUTE, "load": _load()})
        (folder / "study.toml").write_text(STUDY.format(grid=args.grid, n_spacing=n_spacing, n_height=n_height))
        # untimed: this process's first imports (Dask, Zarr, xarray, the point's modules) land here,
        # not in whichever side runs first
        (folder / "warm.toml").write_text(STUDY.format(grid=args.grid, n_spacing=1, n_height=1)
                                          .replace('spacing = "130um:400um:1"', 'spacing = { values = ["175um"] }')
                                          .replace('height = "6um:20um:1"', 'height = { values = ["20um"] }'))
        run(folder / "warm.toml", folder, 1, folder / "cache-warm")
        samples: dict[int, list[tuple[float, float, int, int, float]]] = {1: [], 2: []}
        for k in range(args.rounds):
            for workers in (1, 2):
                cache = folder / f"cache{workers}-{k}"
                cpu0 = _cpu_children()
                seconds, points, solved, hits = run(folder / "study.toml", folder, workers, cache)
                samples[workers].append((seconds, points, solved, hits, _cpu_children() - cpu0))
        # the 2-worker sweep again on the last round's filled cache
        filled = run(folder / "study.toml", folder, 2, folder / f"cache2-{args.rounds - 1}")
        median = {w: statistics.median(s[0] for s in v) for w, v in samples.items()}
        points = samples[1][0][1]
        # the CPU a point costs, from the 1-worker sweeps (the worker process's CPU per point)
        per_point = statistics.median(s[4] for s in samples[1]) / max(points, 1)
        ceilings = {w: statistics.median(ceiling(w, int(points), per_point) for _ in range(args.rounds))
                    for w in (1, 2)}
        rows = [("1 worker, empty cache", median[1], *samples[1][0][1:4]),
                ("2 workers, empty cache", median[2], *samples[2][0][1:4]),
                ("2 workers, filled cache", *filled)]
        print(f"sweep of {points:g} points (caps, grid {args.grid}), {os.cpu_count()} cores, load average {_load()}; "
              f"medians of {args.rounds} alternating rounds")
        print(f"{'run':26s} {'seconds':>8s} {'points/min':>11s} {'cells solved':>13s} {'from cache':>11s}")
        for label, seconds, pts, solved, hits in rows:
            print(f"{label:26s} {seconds:8.2f} {60 * pts / seconds:11.1f} {solved:13d} {hits:11d}")
        speedup = median[1] / median[2]
        ceiling_ratio = ceilings[1] / ceilings[2]
        print(f"speed-up of 2 workers over 1: {speedup:.2f}x (goal: at least 1.7x; rounds: "
              + ", ".join(f"{a[0]:.2f}/{b[0]:.2f} s" for a, b in zip(samples[1], samples[2], strict=True))
              + f"); the filled cache: {rows[1][1] / rows[2][1]:.1f}x faster")
        print(f"ceiling on this machine: {points:g} tasks burning {per_point:.3f} s of CPU each, no store: "
              f"1 worker {ceilings[1]:.2f} s, 2 workers {ceilings[2]:.2f} s, {ceiling_ratio:.2f}x")
        report["workers"] = [{"run": label, "seconds": sec, "points": pts, "cells_solved": sol, "cache_hits": hit}
                             for label, sec, pts, sol, hit in rows]
        report["rounds"] = {str(w): [s[0] for s in v] for w, v in samples.items()}
        report["ceiling"] = {"cpu_per_point": per_point, "seconds": {str(w): t for w, t in ceilings.items()},
                             "ratio": ceiling_ratio}
        report["issue23"].append({
            "row": f"2 workers against 1, {points:g}-point sweep (cluster start-up included)",
            "script": "bench_sweep.py", "today": f"{TODAY_SPEEDUP:g}x",
            "now": f"{speedup:.2f}x ({median[1]:.2f} s / {median[2]:.2f} s, medians of {args.rounds}); "
                   f"ceiling of burn-only tasks on this machine {ceiling_ratio:.2f}x",
            "ratio": speedup, "ratio_of": "1-worker seconds / 2-worker seconds, same run", "goal": ">= 1.7x",
            "met": speedup >= 1.7, "load": _load()})
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(json.dumps(report, indent=2) + "\n")
    finally:
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
