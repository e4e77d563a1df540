"""The per-point population work of a sweep (issue 22): a point with a population against the
same point without one, and the sweep's member step against run_population.

One texture (the default study's caps at a fixed grid, its cell cached first), 40 exploration
loads. Timed in this one process, alternating the sides, median of ``--repeat`` runs (wall and
CPU time of this process, the latter less sensitive to a shared machine's load):

* ``point``: :func:`fingerpad.design.evaluate.evaluate_point` without a population (the nominal);
* ``point+population``: the same with the population's members (the sweep's path);
* ``run_population``: :func:`fingerpad.population.run_population` (``predict --population``);
* ``batch``: :func:`fingerpad.population.members.evaluate_members` (what the sweep runs; the same
  member path as run_population since pop-unify, without its tables and sensitivity).

    python benchmarks/bench_population_sweep.py [--population adults] [--grid 32] [--repeat 5]
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
import warnings


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--population", default="adults")
    parser.add_argument("--grid", type=int, default=32)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    os.environ.setdefault("FINGERPAD_CACHE", tempfile.mkdtemp(prefix="fingerpad-bench-pop-"))
    warnings.simplefilter("ignore")

    from fingerpad.design.spec import sweep_from_dict
    from fingerpad.design.evaluate import evaluate_point
    from fingerpad.population import run_population
    from fingerpad.population.members import evaluate_members
    from fingerpad.population.members import member_finger
    from fingerpad.study.run import run_study
    from fingerpad.study.spec import study_from_dict

    base = {"texture": {"name": "caps", "radius": "100um", "height": "20um", "spacing": "175um",
                        "lattice": "hexagonal"},
            "material": {"modulus": "0.5GPa", "poisson": 0.4}, "model": {"kind": "bem", "grid": args.grid}}
    spec = sweep_from_dict({**base, "sweep": {"loads": "0.1N:4N:40", "axes": {"height": ["20um"]}}},
                           population=args.population)
    data = spec.study_data(spec.assignment((0,)))
    pressures = [1e3, 1e4]
    payload = spec.population_payload()
    study_data = {**data, "loads": {"values": [float(f) for f in spec.loads]}}
    study = study_from_dict(study_data)
    run_population(study, spec.population)  # the cell, over every member's p/E*, into the cache

    def batch() -> None:
        nominal = run_study(study)
        evaluate_members(nominal, [member_finger(nominal.study.finger, m) for m in spec.members])

    sides = {
        "point": lambda: evaluate_point(data, spec.loads, pressures),
        "point+population": lambda: evaluate_point(data, spec.loads, pressures, payload),
        "run_population": lambda: run_population(study, spec.population),
        "batch": batch,
    }
    times: dict[str, list[float]] = {k: [] for k in sides}
    cpu: dict[str, list[float]] = {k: [] for k in sides}
    for _ in range(args.repeat):
        for name, fn in sides.items():
            t0, c0 = time.perf_counter(), time.process_time()
            fn()
            times[name].append(time.perf_counter() - t0)
            cpu[name].append(time.process_time() - c0)
    med = {k: statistics.median(v) for k, v in times.items()}
    med_cpu = {k: statistics.median(v) for k, v in cpu.items()}
    print(f"population {spec.population.name!r}: {len(spec.members)} members, 40 loads, grid {args.grid} "
          f"(load average {os.getloadavg()[0]:.2f})")
    for name, t in med.items():
        print(f"  {name:18s} {t * 1e3:9.1f} ms wall {med_cpu[name] * 1e3:9.1f} ms CPU")
    print(f"  point+population / point: {med['point+population'] / med['point']:.1f}x wall, "
          f"{med_cpu['point+population'] / med_cpu['point']:.1f}x CPU; "
          f"run_population / batch: {med_cpu['run_population'] / med_cpu['batch']:.1f}x CPU")


if __name__ == "__main__":
    main()
