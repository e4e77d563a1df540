"""The same sweep on an external Dask scheduler with N local workers: how it scales with N; and
the sweep's plan timed on its own.

First the plan (:func:`fingerpad.design.plan.plan_sweep`: every point's study and cell key, the
cell and chunk tasks; no cluster, no solve) of a ``--plan-points`` sweep (10,000 by default, 100 x
100 over spacing and height): wall and CPU seconds, per point. Then the grid sweep of ``bench_sweep.py`` (caps, spacing x height, grid 48, 20 loads; ``--points``,
64 by default) run by ``fingerpad sweep --scheduler`` against a ``dask scheduler`` started for
the purpose on 127.0.0.1, with ``dask worker --nworkers N --nthreads 1`` (for N in
``--workers``, 1 and 2 by default; 4-16 where a larger machine is lent), each N with an empty
unit-cell cache and a fresh store; and, for comparison, the same sweep on the LocalCluster the
command starts itself (``--workers N``). The scheduler and its workers are started and have
joined before the command's clock starts (a user's cluster is up before the sweep); the
command's wall seconds count its own start-up, planning, the tasks and the store. The sides
alternate, ``--rounds`` times (1 by default); medians are reported, with the speed-up of N
workers over one on each side and the load average before each run.

    python benchmarks/bench_sweep_scheduler.py [--points 64] [--workers 1,2] [--rounds 1] [--grid 48]
        [--plan-points 10000]

Output: a table on stdout (Markdown, for docs/benchmarks.md), JSON in
``out/bench/sweep_scheduler.json`` (its ``issue34`` row is read by ``benchmarks/report.py``).
"""

from __future__ import annotations

import argparse
import json
import os
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_sweep import STUDY  # noqa: E402 - the same sweep as bench_sweep.py

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_OUT = ROOT / "out" / "bench" / "sweep_scheduler.json"
_COMMAND = "import sys; from fingerpad.cli import main; sys.argv[0] = 'fingerpad'; sys.exit(main())"
#: Seconds to wait for the scheduler and its workers to come up.
START_TIMEOUT = 120.0


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _env(cache: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["FINGERPAD_CACHE"] = str(cache)
    return env


class ExternalCluster:
    """``dask scheduler`` and ``dask worker --nworkers N`` as subprocesses on 127.0.0.1."""

    def __init__(self, workers: int, folder: Path, cache: Path) -> None:
        dask = str(Path(sys.executable).parent / "dask")
        port = _free_port()
        self.address = f"tcp://127.0.0.1:{port}"
        log = (folder / f"cluster-{workers}.log").open("w")
        self.procs = [subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port", str(port),
                                        "--no-dashboard"], stdout=log, stderr=log, env=_env(cache))]
        self.procs.append(subprocess.Popen([dask, "worker", self.address, "--nworkers", str(workers), "--nthreads", "1",
                                            "--no-dashboard", "--memory-limit", "0"],
                                           stdout=log, stderr=log, env=_env(cache)))
        self._wait(workers)

    def _wait(self, workers: int) -> None:
        from distributed import Client

        deadline = time.monotonic() + START_TIMEOUT
        while True:
            try:
                with Client(self.address, timeout=5, set_as_default=False) as client:
                    client.wait_for_workers(workers, timeout=max(deadline - time.monotonic(), 1))
                    return
            except OSError:
                if time.monotonic() > deadline:
                    self.close()
                    raise
                time.sleep(0.5)

    def close(self) -> None:
        for proc in reversed(self.procs):
            proc.terminate()
        for proc in reversed(self.procs):
            try:
                proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()


def sweep(study: Path, store: Path, cache: Path, *, scheduler: str | None = None, workers: int | None = None
          ) -> dict[str, float]:
    """``fingerpad sweep`` in a subprocess: its wall seconds, and the load average before."""
    args = [sys.executable, "-c", _COMMAND, "sweep", str(study), "--out", str(store)]
    args += ["--scheduler", scheduler] if scheduler else ["--workers", str(workers)]
    load = os.getloadavg()[0]
    t = time.perf_counter()
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=_env(cache))
    return {"seconds": time.perf_counter() - t, "load_before": load}


def time_plan(points: int, grid: int) -> dict[str, float]:
    """Wall and CPU seconds of planning a near-square ``points`` sweep of the study above."""
    import tomllib

    from fingerpad.design.plan import plan_sweep
    from fingerpad.design.spec import sweep_from_dict

    side = max(2, round(points ** 0.5))
    spec = sweep_from_dict(tomllib.loads(STUDY.format(grid=grid, n_spacing=side, n_height=side)))
    plan_sweep(sweep_from_dict(tomllib.loads(STUDY.format(grid=grid, n_spacing=2, n_height=2))))  # imports
    t, c = time.perf_counter(), time.process_time()
    plan = plan_sweep(spec)
    wall, cpu = time.perf_counter() - t, time.process_time() - c
    return {"points": spec.size, "cells": len(plan.cells), "chunks": len(plan.chunks), "wall_s": wall, "cpu_s": cpu,
            "load": os.getloadavg()[0]}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=64, help="points of the sweep (a near-square grid)")
    parser.add_argument("--grid", type=int, default=48, help="grid points along x of each cell")
    parser.add_argument("--workers", default="1,2", help="numbers of workers, comma-separated (default 1,2)")
    parser.add_argument("--rounds", type=int, default=1, help="alternating rounds (medians reported)")
    parser.add_argument("--plan-points", type=int, default=10000, help="points of the sweep whose plan is timed")
    parser.add_argument("--json", type=Path, default=DEFAULT_OUT, help="JSON report")
    args = parser.parse_args(argv)
    plan = time_plan(args.plan_points, args.grid)
    print(f"plan of a {plan['points']}-point sweep (grid {args.grid}; {plan['cells']} cells, {plan['chunks']} chunks): "
          f"{plan['wall_s']:.2f} s wall, {plan['cpu_s']:.2f} s CPU, {1e3 * plan['cpu_s'] / plan['points']:.2f} ms of "
          f"CPU per point (load average {plan['load']:.1f})")
    counts = [int(n) for n in args.workers.split(",") if n.strip()]
    n_spacing = max(2, round(args.points ** 0.5))
    n_height = max(1, args.points // n_spacing)
    points = n_spacing * n_height
    runs: dict[str, dict[int, list[dict[str, float]]]] = {"external": {n: [] for n in counts},
                                                         "local": {n: [] for n in counts}}
    with tempfile.TemporaryDirectory(prefix="fingerpad-bench-scheduler-") as tmp:
        folder = Path(tmp)
        study = folder / "study.toml"
        study.write_text(STUDY.format(grid=args.grid, n_spacing=n_spacing, n_height=n_height))
        warm = folder / "warm.toml"  # untimed: the first imports of this interpreter, from disk
        warm.write_text(STUDY.format(grid=args.grid, n_spacing=2, n_height=2))
        sweep(warm, folder / "warm.zarr", folder / "cache-warm", workers=1)
        k = 0
        for r in range(args.rounds):
            for n in counts:
                for side in (("external", "local") if r % 2 == 0 else ("local", "external")):
                    k += 1
                    cache, store = folder / f"cache-{k}", folder / f"store-{k}.zarr"
                    if side == "local":
                        runs[side][n].append(sweep(study, store, cache, workers=n))
                        continue
                    cluster = ExternalCluster(n, folder, cache)
                    try:
                        runs[side][n].append(sweep(study, store, cache, scheduler=cluster.address))
                    finally:
                        cluster.close()
    med = {side: {n: statistics.median(r["seconds"] for r in rs) for n, rs in by_n.items()}
           for side, by_n in runs.items()}
    print(f"sweep of {points} points (caps, grid {args.grid}, 20 loads), empty cache each run; {os.cpu_count()} "
          f"CPU(s), medians of {args.rounds} round(s)")
    print("| workers | external scheduler: seconds | points/min | speed-up over 1 | LocalCluster: seconds | "
          "points/min | speed-up over 1 | load before (ext / local) |")
    print("|---:|---:|---:|---:|---:|---:|---:|---|")
    base = {side: med[side].get(1, med[side][counts[0]]) for side in med}
    for n in counts:
        ext, loc = med["external"][n], med["local"][n]
        loads = "/".join(", ".join(f"{r['load_before']:.1f}" for r in runs[side][n]) for side in ("external", "local"))
        print(f"| {n} | {ext:.1f} | {60 * points / ext:.0f} | {base['external'] / ext:.2f}x | {loc:.1f} | "
              f"{60 * points / loc:.0f} | {base['local'] / loc:.2f}x | {loads} |")
    row = {"row": "the same sweep on an external scheduler with N local workers, N = "
                  + ", ".join(map(str, counts)), "script": "bench_sweep_scheduler.py", "today": "-",
           "now": "; ".join(f"N={n}: {med['external'][n]:.1f} s ({base['external'] / med['external'][n]:.2f}x over 1; "
                            f"LocalCluster {med['local'][n]:.1f} s)" for n in counts),
           "ratio": base["external"] / med["external"][counts[-1]], "ratio_of": f"1 worker / {counts[-1]} workers",
           "goal": "a scaling table in docs/benchmarks.md", "met": True,
           "load": ", ".join(f"{r['load_before']:.1f}" for by_n in runs.values() for rs in by_n.values() for r in rs)}
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps({"date": time.strftime("%Y-%m-%dT%H:%M:%S"), "cores": os.cpu_count(),
                                     "points": points, "grid": args.grid, "runs": runs, "plan": plan, "issue34": [row]},
                                    indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
