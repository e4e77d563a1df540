"""The population's share of a sweep (issues 22 and 34): a point with a population against the
same point without one, the members' coupling against its floor, and a real sweep with and
without the population, extrapolated to a 10,000-point design map.

Part 1, one texture (the default study's caps at ``--grid``, its cell cached first), 40
exploration loads, timed in this one process, alternating the sides, median of ``--repeat`` runs
(wall and CPU time of this process, the latter less sensitive to a shared machine's load):

* ``point``: :func:`fingerpad.design.evaluate.evaluate_point` without a population (the nominal);
* ``point+population``: the same with the population's members (the sweep's path);
* ``run_population``: :func:`fingerpad.population.run_population` (``predict --population``:
  the same member path, with its tables);
* ``members``: :func:`fingerpad.population.members.evaluate_members`, the members' step of a
  sweep point (their fingers made once, as a sweep keeps them);
* ``floor``: the same arithmetic in one NumPy expression, written out for the population's
  models (Hertz pad, constant ridge fraction, Eqs. 2.1-2.5, 3.7, 3.11): the cell's exact disc
  integral at every member's pressures, the friction, and the critical and full-contact loads
  in closed form (no root search at all: a stricter floor than the same search), the states;
  like ``members``, no quantiles.

Part 2 (``--sweep N``, 16 by default, 0 skips it): an N-point spacing x height map of caps at
grid 48 (``--sweep-grid``), run in this process (the sweep's plan on the in-process executor: the
work of one worker, no cluster), each side with an empty unit-cell cache, with and without
``--population``, the sides alternating for ``--sweep-rounds``. CPU seconds per point, their
ratio, and the 10,000-point map on 2 cores extrapolated from it (CPU per point x 10,000 / 2: a
perfect split over two workers, which issue 23 measured at 1.8-2.0x; a sample of N points of one
map, so the cells' cost per point of a larger map is assumed the same).

    python benchmarks/bench_population_sweep.py [--population adults] [--grid 32] [--repeat 5]
                                                [--sweep 16] [--sweep-grid 48] [--sweep-rounds 1]

Output: a table on stdout with the load average beside it, JSON in ``out/bench/population_sweep.json``
(its ``issue34`` rows are read by ``benchmarks/report.py``).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import statistics
import tempfile
import time
import warnings
from pathlib import Path

MAP_POINTS = 10_000
CORES = 2


def _median_times(sides: dict, repeat: int) -> tuple[dict, dict]:
    times: dict[str, list[float]] = {k: [] for k in sides}
    cpu: dict[str, list[float]] = {k: [] for k in sides}
    for _ in range(repeat):
        for name, fn in sides.items():
            t0, c0 = time.perf_counter(), time.process_time()
            fn()
            times[name].append(time.perf_counter() - t0)
            cpu[name].append(time.process_time() - c0)
    return ({k: statistics.median(v) for k, v in times.items()}, {k: statistics.median(v) for k, v in cpu.items()})


def point_part(args: argparse.Namespace) -> dict:
    import numpy as np

    from fingerpad.design.evaluate import evaluate_point
    from fingerpad.design.spec import sweep_from_dict
    from fingerpad.population import run_population
    from fingerpad.population.members import evaluate_members, member_fingers
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
    study = study_from_dict({**data, "loads": {"values": [float(f) for f in spec.loads]}})
    run_population(study, spec.population)  # the cell, over every member's p/E*, into the cache
    nominal = run_study(study)
    fingers, stack = member_fingers(nominal.study.finger, spec.members)
    evaluate_members(nominal, fingers, stack)

    # the floor's inputs, gathered once (a sweep's member set is made once too)
    cell = nominal.cell
    mat_nu = study.material_poisson if study.material_poisson is not None else 0.35
    e1 = np.array([f.micro_modulus(study.material_modulus, mat_nu) for f in fingers])
    col = {k: np.array([float(getattr(f, k)) for f in fingers])[:, None]
           for k in ("radius", "modulus", "tau0", "alpha", "beta")}
    frac = np.array([f.ridges.fraction for f in fingers])[:, None]
    factor = e1[:, None] / cell.modulus
    pt, pf = cell.transition_pressure * factor, cell.full_contact_pressure * factor
    loads = np.asarray(spec.loads, float)[None, :]

    def floor() -> None:
        r, e = col["radius"], col["modulus"]
        ridge = frac * math.pi * (3.0 * loads * r / (4.0 * e)) ** (2.0 / 3.0)  # Eq. 2.5 x A_fr/A_g
        peak = 1.5 * loads / ridge  # Eq. 3.7
        ratio = cell.disc_fraction((peak / factor).ravel()).reshape(peak.shape)  # Eq. 3.11
        hyst = col["beta"] * (9.0 / (128.0 * r)) ** (2.0 / 3.0) * np.cbrt(loads**4 / e)  # Eq. 2.4
        mu = (col["tau0"] * ratio * ridge + col["alpha"] * loads + hyst) / loads  # Eqs. 2.1-2.3
        mu_ref = (col["tau0"] * ridge + col["alpha"] * loads + hyst) / loads
        k = frac * math.pi * (3.0 * r / (4.0 * e)) ** (2.0 / 3.0) / 1.5  # 1.5 F / A_fr = F^(1/3) / k
        (mu / mu_ref, (pt * k) ** 3, (pf * k) ** 3, np.where(peak >= pf, 2, np.where(peak >= pt, 1, 0)))

    sides = {
        "point": lambda: evaluate_point(data, spec.loads, pressures),
        "point+population": lambda: evaluate_point(data, spec.loads, pressures, payload),
        "run_population": lambda: run_population(study, spec.population),
        "members": lambda: evaluate_members(nominal, fingers, stack),
        "floor": floor,
    }
    med, med_cpu = _median_times(sides, args.repeat)
    print(f"population {spec.population.name!r}: {len(spec.members)} members, 40 loads, grid {args.grid}, "
          f"cell cached (load average {os.getloadavg()[0]:.2f})")
    for name, t in med.items():
        print(f"  {name:18s} {t * 1e3:9.1f} ms wall {med_cpu[name] * 1e3:9.1f} ms CPU")
    ratios = {"point+population / point": med_cpu["point+population"] / med_cpu["point"],
              "members / floor": med_cpu["members"] / med_cpu["floor"],
              "run_population / members": med_cpu["run_population"] / med_cpu["members"]}
    print("  " + "; ".join(f"{k}: {v:.2f}x CPU" for k, v in ratios.items()))
    return {"wall_s": med, "cpu_s": med_cpu, "ratios_cpu": ratios, "load_average": os.getloadavg()[0]}


def sweep_part(args: argparse.Namespace) -> dict:
    import numpy as np

    from fingerpad.design.engine import SweepReport, execute_plan, sweep_pressures
    from fingerpad.design.executor import InProcessExecutor
    from fingerpad.design.plan import plan_sweep
    from fingerpad.design.spec import sweep_from_dict
    from fingerpad.design.store import SweepStore

    side = max(1, int(round(math.sqrt(args.sweep))))
    other = max(1, args.sweep // side)
    spacings = [f"{s:.1f}um" for s in np.linspace(150.0, 300.0, side)]
    heights = [f"{h:.2f}um" for h in np.linspace(8.0, 25.0, other)]
    root = Path(tempfile.mkdtemp(prefix="fingerpad-bench-popsweep-"))

    def run(population: str | None, tag: str) -> tuple[float, float]:
        folder = root / tag
        shutil.rmtree(folder, ignore_errors=True)
        folder.mkdir(parents=True)
        spec = sweep_from_dict({
            "texture": {"name": "caps", "radius": "100um", "height": "20um", "spacing": "175um",
                        "lattice": "hexagonal"},
            "material": {"modulus": "0.5GPa", "poisson": 0.4},
            "model": {"kind": "bem", "grid": args.sweep_grid, "cache": str(folder / "cache")},
            "sweep": {"loads": "0.1N:4N:40", "axes": {"spacing": spacings, "height": heights}},
        }, population=population)
        pressures = sweep_pressures(spec)
        store = SweepStore(folder / "s.zarr", spec, pressures)
        store.create()
        t0, c0 = time.perf_counter(), time.process_time()
        report = execute_plan(plan_sweep(spec), InProcessExecutor(), store, spec.loads, pressures,
                              SweepReport(points=spec.size), population=spec.population_payload())
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        if report.failures:
            raise SystemExit(f"sweep failed: {report.failures[:1]}")
        return wall, cpu

    n = len(spacings) * len(heights)
    got: dict[str, list[tuple[float, float]]] = {"nominal": [], "population": []}
    for r in range(args.sweep_rounds):
        got["nominal"].append(run(None, f"n{r}"))
        got["population"].append(run(args.population, f"p{r}"))
    shutil.rmtree(root, ignore_errors=True)
    cpu = {k: statistics.median(c for _, c in v) / n for k, v in got.items()}
    wall = {k: statistics.median(w for w, _ in v) / n for k, v in got.items()}
    minutes = cpu["population"] * MAP_POINTS / CORES / 60
    print(f"sweep of {n} points (spacing x height, grid {args.sweep_grid}, 40 loads), in this process, "
          f"empty cache each (load average {os.getloadavg()[0]:.2f})")
    for k in got:
        print(f"  {k:18s} {wall[k] * 1e3:9.0f} ms wall {cpu[k] * 1e3:9.0f} ms CPU per point")
    print(f"  population / nominal: {cpu['population'] / cpu['nominal']:.2f}x CPU; "
          f"{MAP_POINTS:,}-point map with {args.population!r} on {CORES} cores, extrapolated: "
          f"{minutes:.1f} min")
    return {"points": n, "grid": args.sweep_grid, "cpu_s_per_point": cpu, "wall_s_per_point": wall,
            "ratio_cpu": cpu["population"] / cpu["nominal"], "map_minutes_2_cores": minutes,
            "load_average": os.getloadavg()[0]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--population", default="adults")
    parser.add_argument("--grid", type=int, default=32)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--sweep", type=int, default=16, help="points of the sweep part (0: skip it)")
    parser.add_argument("--sweep-grid", type=int, default=48)
    parser.add_argument("--sweep-rounds", type=int, default=1)
    args = parser.parse_args()
    os.environ.setdefault("FINGERPAD_CACHE", tempfile.mkdtemp(prefix="fingerpad-bench-pop-"))
    warnings.simplefilter("ignore")
    from fingerpad.design.evaluate import limit_threads

    limit_threads()  # one thread per process, as a sweep's workers run
    out: dict = {"point": point_part(args)}
    p = out["point"]
    rows = [{"row": "members' coupling against its floor (the same arithmetic in one NumPy expression)",
             "script": "bench_population_sweep.py", "today": "not measured",
             "now": f"{p['cpu_s']['members'] * 1e3:.0f} ms CPU against {p['cpu_s']['floor'] * 1e3:.0f} ms "
                    f"({args.population}, 40 loads, grid {args.grid})",
             "ratio": p["ratios_cpu"]["members / floor"], "ratio_of": "members / floor, CPU", "goal": "<= 3x",
             "met": p["ratios_cpu"]["members / floor"] <= 3, "load": f"{p['load_average']:.1f}"}]
    if args.sweep > 0:
        out["sweep"] = w = sweep_part(args)
        rows.insert(0, {
            "row": f"a {w['points']}-point sweep with `{args.population}` against the same sweep without a population",
            "script": "bench_population_sweep.py", "today": "2.1x",
            "now": f"{w['cpu_s_per_point']['population'] * 1e3:.0f} against {w['cpu_s_per_point']['nominal'] * 1e3:.0f} "
                   f"ms CPU a point (grid {w['grid']}, in one process)",
            "ratio": w["ratio_cpu"], "ratio_of": "population / nominal, CPU", "goal": "<= 1.3x",
            "met": w["ratio_cpu"] <= 1.3, "load": f"{w['load_average']:.1f}"})
        rows.append({
            "row": f"`{args.population}` sweep of {w['points']} points extrapolated to {MAP_POINTS:,} points on "
                   f"{CORES} cores", "script": "bench_population_sweep.py", "today": "~1.5 h",
            "now": f"{w['map_minutes_2_cores']:.1f} min (CPU a point x {MAP_POINTS:,} / {CORES})",
            "ratio": 90.0 / w["map_minutes_2_cores"], "ratio_of": "issue 34's 90 min / now", "goal": "<= 10 min",
            "met": w["map_minutes_2_cores"] <= 10, "load": f"{w['load_average']:.1f}"})
    out["issue34"] = rows
    path = Path("out/bench/population_sweep.json")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
