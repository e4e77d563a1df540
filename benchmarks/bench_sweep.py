"""Sweep throughput on Dask: points per minute with 1 and 2 workers, and the cache's effect.

A grid sweep of spherical caps (spacing x height, the default study's material and finger) runs
three times into fresh stores: 1 worker and 2 workers, each with an empty unit-cell cache, then
2 workers again on the filled cache. Goal (issue "Texture design"): 2 workers at least 1.7x the
points per minute of one on a 2-core machine. The cluster's start-up is included (it is part of
what a user waits for); the rate over the points alone is printed beside it.

    python benchmarks/bench_sweep.py [--points 32] [--grid 48]
"""

from __future__ import annotations

import argparse
import os
import shutil
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


def run(folder: Path, workers: int, cache: Path) -> tuple[float, float, int, int]:
    from fingerpad.design.engine import run_sweep
    from fingerpad.design.spec import read_sweep_file, sweep_from_dict

    os.environ["FINGERPAD_CACHE"] = str(cache)
    spec = sweep_from_dict(read_sweep_file(str(folder / "study.toml")))
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=32, help="points of the sweep (a near-square grid)")
    parser.add_argument("--grid", type=int, default=48, help="grid points along x of each cell")
    args = parser.parse_args()
    n_spacing = max(2, round(args.points ** 0.5))
    n_height = max(1, args.points // n_spacing)
    folder = Path(tempfile.mkdtemp(prefix="fingerpad-bench-sweep-"))
    try:
        (folder / "study.toml").write_text(STUDY.format(grid=args.grid, n_spacing=n_spacing, n_height=n_height))
        rows = []
        for label, workers, cache in (("1 worker, empty cache", 1, folder / "cache1"),
                                      ("2 workers, empty cache", 2, folder / "cache2"),
                                      ("2 workers, filled cache", 2, folder / "cache2")):
            seconds, points, solved, hits = run(folder, workers, cache)
            rows.append((label, seconds, points, solved, hits))
        load = Path("/proc/loadavg").read_text().split()[0] if Path("/proc/loadavg").exists() else "?"
        print(f"sweep of {rows[0][2]} points (caps, grid {args.grid}), {os.cpu_count()} cores, load average {load}")
        print(f"{'run':26s} {'seconds':>8s} {'points/min':>11s} {'cells solved':>13s} {'from cache':>11s}")
        for label, seconds, points, solved, hits in rows:
            print(f"{label:26s} {seconds:8.1f} {60 * points / seconds:11.1f} {solved:13d} {hits:11d}")
        print(f"speed-up of 2 workers over 1: {rows[0][1] / rows[1][1]:.2f}x (goal: at least 1.7x); "
              f"the filled cache: {rows[1][1] / rows[2][1]:.1f}x faster")
    finally:
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
