"""Benchmark of ``fingerpad predict --population adults`` against one plain ``predict`` (issue 22).

The goal: the 1,000-member population of the default study within 2x the time of one plain
``predict`` when the unit cell is cached, and within 1.5x cold (an empty ``FINGERPAD_CACHE``).
Both commands are run as a user runs them (interpreter start-up, imports, figures and files
included), alternately in one run, so that both sides see the same machine load:

* cold: plain and population each in a fresh, empty cache folder (``--repeats`` times);
* cached: plain and population with the cell in the cache (``--repeats`` times);
* optionally the sensitivity analysis (``--sensitivity``) on top of the cached population.

Reported: the median wall time of each, the ratios, the CPU time (user + system of the child)
and its ratios (less sensitive to other load on a shared machine), and the load average before
and after. Usage: ``.venv/bin/python benchmarks/bench_population.py [--repeats 3] [--sensitivity]``.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
STUDY = ROOT / "examples" / "study.toml"


def _run(args: list[str], cache: str) -> tuple[float, float]:
    """Wall and CPU seconds (user + system) of one ``fingerpad`` command."""
    exe = Path(sys.executable).with_name("fingerpad")
    out = tempfile.mkdtemp(prefix="fingerpad-bench-pop-out-")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    try:
        subprocess.run([str(exe), "predict", str(STUDY), *args, "--out", out], check=True,
                       env={**os.environ, "FINGERPAD_CACHE": cache},
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    finally:
        wall = time.perf_counter() - t
        shutil.rmtree(out, ignore_errors=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3, help="repetitions of each case (alternating)")
    ap.add_argument("--sensitivity", action="store_true", help="also time --sensitivity (cached)")
    ap.add_argument("--out", default="out/bench/population.json")
    args = ap.parse_args()

    load_before = os.getloadavg()
    cases: dict[str, list[tuple[float, float]]] = {}
    warm = tempfile.mkdtemp(prefix="fingerpad-bench-pop-cache-")
    try:
        for _ in range(args.repeats):
            for name, extra in (("plain", []), ("population", ["--population", "adults"])):
                cold = tempfile.mkdtemp(prefix="fingerpad-bench-pop-cold-")
                try:
                    cases.setdefault(f"{name} cold", []).append(_run(extra, cold))
                finally:
                    shutil.rmtree(cold, ignore_errors=True)
        _run(["--population", "adults"], warm)  # fills the cache over the population's pressures
        for _ in range(args.repeats):
            cases.setdefault("plain cached", []).append(_run([], warm))
            cases.setdefault("population cached", []).append(_run(["--population", "adults"], warm))
            if args.sensitivity:
                cases.setdefault("population + sensitivity cached", []).append(
                    _run(["--population", "adults", "--sensitivity"], warm))
    finally:
        shutil.rmtree(warm, ignore_errors=True)
    load_after = os.getloadavg()

    wall = {k: statistics.median(w for w, _ in v) for k, v in cases.items()}
    cpu = {k: statistics.median(c for _, c in v) for k, v in cases.items()}
    ratios = {
        "cached": (wall["population cached"] / wall["plain cached"], cpu["population cached"] / cpu["plain cached"]),
        "cold": (wall["population cold"] / wall["plain cold"], cpu["population cold"] / cpu["plain cold"]),
    }
    print(f"cores: {os.cpu_count()}, load average before {load_before[0]:.2f} / after {load_after[0]:.2f} "
          f"(1 min); medians of {args.repeats}")
    print("| case | wall s | CPU s |")
    print("|---|---:|---:|")
    for k in cases:
        print(f"| `predict examples/study.toml` {k} | {wall[k]:.2f} | {cpu[k]:.2f} |")
    print("| ratio | wall | CPU | goal |")
    print("|---|---:|---:|---|")
    print(f"| population / plain, cached | {ratios['cached'][0]:.2f}x | {ratios['cached'][1]:.2f}x | <= 2x |")
    print(f"| population / plain, cold | {ratios['cold'][0]:.2f}x | {ratios['cold'][1]:.2f}x | <= 1.5x |")
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps({
        "cpu_count": os.cpu_count(), "load_average_before": load_before, "load_average_after": load_after,
        "runs": cases, "wall_median_s": wall, "cpu_median_s": cpu,
        "ratio_cached": {"wall": ratios["cached"][0], "cpu": ratios["cached"][1]},
        "ratio_cold": {"wall": ratios["cold"][0], "cpu": ratios["cold"][1]},
    }, indent=2), encoding="utf-8")


if __name__ == "__main__":
    main()
