"""A design map's wait (issue 34): real sweeps on a local cluster, the code before and this code in
one run.

Three measurements, each a ``fingerpad.design.engine.run_sweep`` of caps (spacing x height, the
sweep study of ``bench_population_sweep.py``: R 100 um, hexagonal, 0.5 GPa, grid 48, 40 loads) in
a fresh process with an empty unit-cell cache and a fresh store, as ``fingerpad sweep`` runs it
(the local cluster's start and close included, after an untimed 1-point sweep in the same
process: its first imports and first cluster, as ``bench_sweep.py`` does):

1. ``--points`` (64) nominal points on 2 workers, with the code before (``--before REV``; by
   default :data:`BEFORE`, main before issue 34's unit-cell work: its ``src/`` unpacked by ``git archive`` into a temporary folder and put first on
   ``PYTHONPATH``, so the same interpreter and libraries run the old package) and with this
   code, alternating, ``--rounds`` times (medians). Goal: at least 5x.
2. The same sweep with this code on 1 worker against 2 (goal: at least 1.8x, kept).
3. ``--population-points`` (100) points with ``--population adults`` on 2 workers (this code):
   the wall time x 10,000 / points, the 10,000-point map extrapolated (goal: at most 10 min);
   beside it the CPU time x 10,000 / points / 2, the map on two cores free of other work.

CPU seconds are those of the process and its waited-for children (the workers) during the
timed sweep. The machine is
shared: the load average is printed beside the numbers.

    python benchmarks/bench_map_speed.py [--points 64] [--population-points 100] [--rounds 1]
                                         [--before REV] [--no-before]

Output: a table on stdout, JSON in ``out/bench/map_speed.json`` (its ``issue34`` rows are read by
``benchmarks/report.py``).
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

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_OUT = ROOT / "out" / "bench" / "map_speed.json"
MAP_POINTS = 10_000
#: The code before issue 34's unit-cell speed-ups (main on 2026-11-29, the members' coupling done).
BEFORE = "d973244"


def axes(points: int) -> dict:
    """A spacing x height grid of about ``points`` points (spacings 150-300 um, heights 8-25 um)."""
    import math

    side = max(1, int(round(math.sqrt(points))))
    other = max(1, points // side)
    step = lambda lo, hi, n: [lo + (hi - lo) * i / max(n - 1, 1) for i in range(n)]  # noqa: E731
    return {"spacing": [f"{s:.2f}um" for s in step(150.0, 300.0, side)],
            "height": [f"{h:.3f}um" for h in step(8.0, 25.0, other)]}


def spec(points: int, cache: str, population: str | None):
    """The sweep measured: caps (R 100 um, hexagonal, 0.5 GPa) over ``axes(points)``, grid 48,
    40 loads, the unit-cell cache in ``cache``, ``population`` a preset or ``None``."""
    from fingerpad.design.spec import sweep_from_dict

    return sweep_from_dict({
        "texture": {"name": "caps", "radius": "100um", "height": "20um", "spacing": "175um",
                    "lattice": "hexagonal"},
        "material": {"modulus": "0.5GPa", "poisson": 0.4},
        "model": {"kind": "bem", "grid": 48, "cache": cache},
        "sweep": {"loads": "0.1N:4N:40", "axes": axes(points)},
    }, population=population)


def one_sweep(points: int, workers: int, population: str | None, folder: str) -> None:
    """Run one sweep in this process after an untimed 1-point sweep (this process's first imports
    and its first cluster, which both sides pay alike) and print its report and times as JSON."""
    import warnings

    warnings.simplefilter("ignore")
    from fingerpad.design.engine import run_sweep

    run_sweep(spec(1, str(Path(folder) / "warm-cache"), population), Path(folder) / "warm.zarr", workers=workers)
    s = spec(points, str(Path(folder) / "cache"), population)
    c0 = [resource.getrusage(w) for w in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)]
    t0 = time.perf_counter()
    report = run_sweep(s, Path(folder) / "s.zarr", workers=workers)
    wall = time.perf_counter() - t0
    c1 = [resource.getrusage(w) for w in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)]
    cpu = sum((b.ru_utime - a.ru_utime) + (b.ru_stime - a.ru_stime) for a, b in zip(c0, c1))
    print(json.dumps({"points": s.size, "computed": report.computed, "solves": report.solves,
                      "failures": len(report.failures), "wall": wall, "cpu": cpu}))


def timed(python_path: str | None, points: int, workers: int, population: str | None) -> dict:
    """Wall and CPU seconds of one sweep in a fresh process (``python_path``: PYTHONPATH first),
    after that process's warm-up (:func:`one_sweep`)."""
    folder = tempfile.mkdtemp(prefix="fingerpad-bench-map-")
    env = dict(os.environ)
    if python_path:
        env["PYTHONPATH"] = python_path + os.pathsep + env.get("PYTHONPATH", "")
    cmd = [sys.executable, __file__, "--one", str(points), str(workers), population or "-", folder]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=False)
    shutil.rmtree(folder, ignore_errors=True)
    if out.returncode != 0:
        raise SystemExit(f"sweep failed ({'before' if python_path else 'now'}):\n{out.stderr[-3000:]}")
    report = json.loads(out.stdout.strip().splitlines()[-1])
    if report["failures"] or report["computed"] != report["points"]:
        raise SystemExit(f"sweep incomplete: {report}")
    return report


def checkout(rev: str) -> Path:
    """``rev``'s ``src/`` unpacked into a temporary folder (its path to put on PYTHONPATH)."""
    folder = Path(tempfile.mkdtemp(prefix="fingerpad-before-"))
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", rev, "src"], capture_output=True, check=True)
    subprocess.run(["tar", "-x", "-C", str(folder)], input=archive.stdout, check=True)
    return folder / "src"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=64)
    parser.add_argument("--population-points", type=int, default=100, help="0 skips part 3")
    parser.add_argument("--rounds", type=int, default=1)
    parser.add_argument("--before", default=BEFORE, help="the git revision of the code before")
    parser.add_argument("--no-before", action="store_true", help="skip the code before (part 1)")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT)
    parser.add_argument("--one", nargs=4, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:
        points, workers, population, folder = args.one
        one_sweep(int(points), int(workers), None if population == "-" else population, folder)
        return
    load = os.getloadavg()[0]
    old = None if args.no_before else str(checkout(args.before))
    runs: dict[str, list[dict]] = {"before, 2 workers": [], "now, 2 workers": [], "now, 1 worker": []}
    for _ in range(args.rounds):
        if old is not None:
            runs["before, 2 workers"].append(timed(old, args.points, 2, None))
        runs["now, 2 workers"].append(timed(None, args.points, 2, None))
        runs["now, 1 worker"].append(timed(None, args.points, 1, None))
    if old is not None:
        shutil.rmtree(Path(old).parent, ignore_errors=True)
    med = {k: {m: statistics.median(r[m] for r in v) for m in ("wall", "cpu", "solves")} for k, v in runs.items() if v}
    print(f"{args.points}-point nominal sweep (caps, grid 48, 40 loads, empty cache, local cluster; "
          f"medians of {args.rounds}; load average {load:.2f} at the start)")
    for k, m in med.items():
        print(f"  {k:18s} {m['wall']:7.2f} s wall {m['cpu']:7.2f} s CPU  {m['solves']:6.0f} solves")
    rows = []
    now2, now1 = med["now, 2 workers"], med["now, 1 worker"]
    if "before, 2 workers" in med:
        b = med["before, 2 workers"]
        ratio = b["wall"] / now2["wall"]
        print(f"  before / now, 2 workers: {ratio:.2f}x wall, {b['cpu'] / now2['cpu']:.2f}x CPU")
        rows.append({"row": f"a {args.points}-point nominal sweep at grid 48 on 2 workers, against the code before "
                            f"({args.before}) in the same run", "script": "bench_map_speed.py", "today": "1x",
                     "now": f"{now2['wall']:.1f} s against {b['wall']:.1f} s wall ({now2['cpu']:.1f} against "
                            f"{b['cpu']:.1f} s CPU; CPU ratio {b['cpu'] / now2['cpu']:.2f}x)",
                     "ratio": ratio, "ratio_of": "before / now, wall", "goal": ">= 5x", "met": ratio >= 5,
                     "load": f"{load:.1f}"})
    ratio = now1["wall"] / now2["wall"]
    print(f"  1 worker / 2 workers (now): {ratio:.2f}x wall")
    rows.append({"row": f"2 workers against 1 on a {args.points}-point sweep", "script": "bench_map_speed.py",
                 "today": "2.00x", "now": f"{now1['wall']:.1f} s against {now2['wall']:.1f} s wall",
                 "ratio": ratio, "ratio_of": "1 worker / 2 workers, wall", "goal": ">= 1.8x, kept",
                 "met": ratio >= 1.8, "load": f"{load:.1f}"})
    out = {"runs": runs, "medians": med, "load_average_start": load, "issue34": rows}
    if args.population_points > 0:
        load_p = os.getloadavg()[0]
        pop = timed(None, args.population_points, 2, "adults")
        minutes = pop["wall"] * MAP_POINTS / pop["points"] / 60
        # on a shared machine the wall clock says how busy it was: the CPU over 2 cores is the
        # map's time with both cores to itself (the sweep's parallel efficiency taken as 1)
        cpu_minutes = pop["cpu"] * MAP_POINTS / pop["points"] / 2 / 60
        print(f"{pop['points']}-point `adults` sweep, 2 workers: {pop['wall']:.1f} s wall, {pop['cpu']:.1f} s CPU, "
              f"{pop['solves']} solves; {MAP_POINTS:,} points extrapolated: {minutes:.1f} min by its wall clock, "
              f"{cpu_minutes:.1f} min by its CPU on 2 free cores (load average {load_p:.2f})")
        out["population"] = {**pop, "map_minutes": minutes, "map_minutes_cpu": cpu_minutes, "load_average_start": load_p}
        rows.append({"row": f"{pop['points']}-point `adults` sweep on 2 workers, extrapolated to {MAP_POINTS:,} points",
                     "script": "bench_map_speed.py", "today": "~1.5 h",
                     "now": f"{minutes:.1f} min by the wall clock ({pop['wall']:.1f} s x {MAP_POINTS // pop['points']}), "
                            f"{cpu_minutes:.1f} min by the CPU on 2 free cores ({pop['cpu']:.1f} s CPU)",
                     "ratio": 90.0 / minutes, "ratio_of": "issue 34's 90 min / now (wall)", "goal": "<= 10 min",
                     "met": minutes <= 10, "load": f"{load_p:.1f}"})
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
