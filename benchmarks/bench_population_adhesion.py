"""A population with adhesion: the family of adhesive cells against a cell of its own per member,
in one run (issue 33; docs/benchmarks.md, "Population with adhesion").

The README's caps (examples/study.toml) at one grid, 3 loads (0.1, 0.3, 1 N), the preset
``adults-adhesive`` (``--size`` members), a fresh cache: the nominal prediction, the family's
cells, the members on it (their curves and error estimates), then ``--direct`` members (spread
over the members' u) each on an adhesive cell of its own, to measure what one costs and how far
the interpolated member lies from it (A_re, mu and the pull-off force, beside the estimates).

    python benchmarks/bench_population_adhesion.py [--grid 64] [--size 1000] [--direct 4] [--out out/bench/population_adhesion.json]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import tempfile
import time
import warnings
from pathlib import Path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", type=int, default=64)
    parser.add_argument("--size", type=int, default=1000)
    parser.add_argument("--direct", type=int, default=4)
    parser.add_argument("--out", default="out/bench/population_adhesion.json")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    import numpy as np

    from fingerpad.coupling import predict_curve
    from fingerpad.micro.adhesive_cell import AdhesiveUnitCell
    from fingerpad.micro.cache import CurveCache
    from fingerpad.population.rules import attach
    from fingerpad.population.run import run_population
    from fingerpad.population.sources import load_population
    from fingerpad.study.spec import load_study_file

    root = Path(__file__).resolve().parents[1]
    with tempfile.TemporaryDirectory() as tmp:
        study = dataclasses.replace(load_study_file(root / "examples" / "study.toml"), model="bem", grid=args.grid,
                                    loads=np.array([0.1, 0.3, 1.0]), cache=tmp)
        population = dataclasses.replace(load_population("adults-adhesive"), size=args.size)
        plan = attach(study, population)
        t0 = time.perf_counter()
        result = run_population(plan)
        total = time.perf_counter() - t0
        adh = result.adhesion
        us = np.array([c.unit_work for c in adh.cells])
        picks = [int(np.argmin(np.abs(us - q))) for q in np.quantile(us, np.linspace(0.05, 0.95, args.direct))]
        rows, direct_seconds = [], 0.0
        for i in picks:
            f = plan.fingers[i]
            e = f.micro_modulus(study.material_modulus, study.material_poisson)
            t1 = time.perf_counter()
            own = AdhesiveUnitCell(result.nominal.cell.texture, e, work_of_adhesion=f.work_of_adhesion, tol=study.tol,
                                   max_iter=study.max_iter, cache=CurveCache(Path(tmp) / "direct")).prepare()
            d = predict_curve(study.loads, f, own)
            direct_seconds += time.perf_counter() - t1
            c = result.curves[i]
            rows.append({"member": i, "unit_work": float(us[i]), "work_of_adhesion": f.work_of_adhesion,
                         "real_area_off": float(np.max(np.abs(np.asarray(c.real_area) / d.real_area - 1))),
                         "real_area_estimate": float(adh.interpolation_error[i]),
                         "mu_off": float(np.max(np.abs(np.asarray(c.mu) / d.mu - 1))),
                         "pull_off_off": float(abs(c.adhesion["pull_off_force"] / d.adhesion["pull_off_force"] - 1)),
                         "pull_off_estimate": float(adh.pull_off_error[i])})
    per_cell = direct_seconds / len(picks)
    report = {
        "grid": args.grid, "members": args.size, "loads": [0.1, 0.3, 1.0], "load_average": os.getloadavg()[0],
        "family_cells": len(adh.family.nodes), "family_solves": adh.family.solves,
        "population_seconds": total, "nominal_seconds": float(sum(result.nominal.timings.values())),
        "direct_cell_seconds_each": per_cell,
        "direct_all_members_seconds_extrapolated": per_cell * args.size,
        "ratio_direct_over_population": per_cell * args.size / total,
        "estimate_median": float(np.median(adh.interpolation_error)),
        "estimate_max": float(np.max(adh.interpolation_error)),
        "members_checked": rows,
    }
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(report, indent=1))
    print(json.dumps({k: v for k, v in report.items() if k != "members_checked"}, indent=1))
    for r in rows:
        print(f"member {r['member']:4d} u {r['unit_work']:.3g}: A_re {100 * r['real_area_off']:.2g} % off "
              f"(estimate {100 * r['real_area_estimate']:.2g} %), mu {100 * r['mu_off']:.2g} %, pull-off "
              f"{100 * r['pull_off_off']:.2g} % (estimate {100 * r['pull_off_estimate']:.2g} %)")


if __name__ == "__main__":
    main()
