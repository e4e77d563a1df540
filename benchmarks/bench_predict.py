"""Benchmark of ``fingerpad predict`` on the default study (``make bench``).

Reports, in one run on this machine:

* the first, uncached prediction of the default study at its default grid (unit-cell curve
  computed into an empty cache folder, then the coupling over 40 loads);
* a 50-load prediction with the unit-cell curve cached (the targets: under a minute and under
  0.5 s);
* the whole command ``fingerpad run-default`` (imports, figures and files included), cached.

Usage: ``.venv/bin/python benchmarks/bench_predict.py [--repeats 5]``.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from fingerpad.study.run import run_study
from fingerpad.study.spec import DEFAULT_GRID, DEFAULT_STUDY, study_from_dict


def _study(cache: str, loads: str) -> object:
    data = {k: dict(v) for k, v in DEFAULT_STUDY.items()}
    data["loads"] = {"range": loads, "log": True}
    data["model"] = {**data["model"], "grid": int(DEFAULT_GRID), "cache": cache}
    return study_from_dict(data)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5, help="repetitions of the cached prediction")
    ap.add_argument("--out", default="out/bench/predict.json")
    args = ap.parse_args()

    cache = tempfile.mkdtemp(prefix="fingerpad-bench-cache-")
    try:
        t = time.perf_counter()
        first = run_study(_study(cache, "0.1N:4N:40"))  # type: ignore[arg-type]
        uncached = time.perf_counter() - t

        cached = []
        for _ in range(args.repeats):
            t = time.perf_counter()
            pred = run_study(_study(cache, "0.1N:4N:50"))  # type: ignore[arg-type]
            cached.append(time.perf_counter() - t)

        env = {**os.environ, "FINGERPAD_CACHE": cache}
        exe = Path(sys.executable).with_name("fingerpad")
        outdir = tempfile.mkdtemp(prefix="fingerpad-bench-out-")
        t = time.perf_counter()
        subprocess.run([str(exe), "run-default", "--out", outdir], env=env, check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        command = time.perf_counter() - t
        shutil.rmtree(outdir, ignore_errors=True)
    finally:
        shutil.rmtree(cache, ignore_errors=True)

    rows = {
        "cpu_count": os.cpu_count(),
        "grid": int(DEFAULT_GRID),
        "uncached_default_seconds": uncached,
        "uncached_cell_solves": int(first.cell.solves),
        "uncached_timings": first.timings,
        "cached_50_loads_seconds_median": statistics.median(cached),
        "cached_50_loads_seconds_all": cached,
        "run_default_command_cached_seconds": command,
        "cached_timings": pred.timings,
        "critical_load_N": pred.critical_load,
    }
    print(f"cores: {os.cpu_count()}, default grid {DEFAULT_GRID}")
    print("| case | seconds | target |")
    print("|---|---:|---|")
    print(f"| first prediction of the default, uncached (40 loads, {first.cell.solves} cell solves) | {uncached:.2f} | < 60 |")
    print(f"| 50-load prediction, unit cell cached (median of {args.repeats}) | {statistics.median(cached):.3f} | < 0.5 |")
    print(f"| `fingerpad run-default`, cached, whole command | {command:.2f} | |")
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(rows, indent=2), encoding="utf-8")


if __name__ == "__main__":
    main()
