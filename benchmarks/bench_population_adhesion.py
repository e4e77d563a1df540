"""A population with adhesion: the family of adhesive cells against a cell of its own per member,
in one run (issue 33; docs/benchmarks.md, "Population with adhesion").

The README's caps (examples/study.toml) at one grid, 3 loads (0.1, 0.3, 1 N), the preset
``adults-adhesive`` (``--size`` members; or ``--population adults --work-of-adhesion 0.3``: every
member at one w), a fresh cache: the nominal prediction, the family's cells, the members on it
(their curves and error estimates), then ``--direct`` members (spread over the members' u) each
on an adhesive cell of its own, reported as a single prediction reports it (a pulled-in
transition extrapolated from its half and quarter grids, docs/model.md 6.6), to measure what one
costs and how far the interpolated member lies from it (A_re, mu and the pull-off force, beside
the estimates).

    python benchmarks/bench_population_adhesion.py [--grid 64] [--size 1000] [--direct 4]
        [--population adults-adhesive] [--work-of-adhesion W] [--out out/bench/population_adhesion.json]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
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
    parser.add_argument("--population", default="adults-adhesive")
    parser.add_argument("--work-of-adhesion", type=float, default=None, help="J/m2, the study finger's (every member's)")
    parser.add_argument("--out", default="out/bench/population_adhesion.json")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    import numpy as np

    from fingerpad.coupling import predict_curve
    from fingerpad.micro.adhesive_cell import AdhesiveUnitCell
    from fingerpad.micro.cache import CurveCache
    from fingerpad.micro.resolution import adopt_extrapolated, pulled_in_companions
    from fingerpad.population.rules import attach
    from fingerpad.population.run import run_population
    from fingerpad.population.sources import load_population
    from fingerpad.study.spec import load_study_file
    from fingerpad.study.states import texture_maker

    root = Path(__file__).resolve().parents[1]
    with tempfile.TemporaryDirectory() as tmp:
        study = dataclasses.replace(load_study_file(root / "examples" / "study.toml"), model="bem", grid=args.grid,
                                    loads=np.array([0.1, 0.3, 1.0]), cache=tmp)
        if args.work_of_adhesion is not None:
            study = dataclasses.replace(study, finger=study.finger.with_overrides(work_of_adhesion=args.work_of_adhesion))
        population = dataclasses.replace(load_population(args.population), size=args.size)
        plan = attach(study, population)
        t0 = time.perf_counter()
        result = run_population(plan)
        total = time.perf_counter() - t0
        adh = result.adhesion
        us = np.array([c.unit_work for c in adh.cells])
        picks = [int(np.argmin(np.abs(us - q))) for q in np.quantile(us, np.linspace(0.05, 0.95, args.direct))]
        rows, direct_seconds = [], 0.0
        make = texture_maker(study)
        for i in picks:
            f = plan.fingers[i]
            e = f.micro_modulus(study.material_modulus, study.material_poisson)
            t1 = time.perf_counter()
            options = {"work_of_adhesion": f.work_of_adhesion, "adhesion_range": f.adhesion_range,
                       "law": f.adhesion_law, "tol": study.tol, "max_iter": study.max_iter,
                       "cache": CurveCache(Path(tmp) / "direct")}
            own = AdhesiveUnitCell(result.nominal.cell.texture, e, **options).prepare()
            # reported as a single prediction reports it (study.states.resolve_adhesive_cell)
            held = {int(own.texture.shape[0]): own}
            pulled_in_companions(own, make, lambda t, e=e, o=options: AdhesiveUnitCell(t, e, **o).prepare(), held)
            adopt_extrapolated(held, int(own.texture.shape[0]))
            d = predict_curve(study.loads, f, own)
            direct_seconds += time.perf_counter() - t1
            c = result.curves[i]
            rows.append({"member": i, "unit_work": float(us[i]), "work_of_adhesion": f.work_of_adhesion,
                         "real_area_off": float(np.max(np.abs(np.asarray(c.real_area) / d.real_area - 1))),
                         "real_area_estimate": float(adh.interpolation_error[i]),
                         "mu_off": float(np.max(np.abs(np.asarray(c.mu) / d.mu - 1))),
                         "pull_off_off": float(abs(c.adhesion["pull_off_force"] / d.adhesion["pull_off_force"] - 1)),
                         "pull_off_estimate": float(adh.pull_off_error[i]),
                         "transition_off": float(adh.cells[i].transition_pressure / own.transition_pressure - 1)
                         if 0 < own.transition_pressure < math.inf else math.nan})
    per_cell = direct_seconds / len(picks)
    report = {
        "grid": args.grid, "members": args.size, "population": args.population,
        "work_of_adhesion": args.work_of_adhesion, "family_nodes": list(adh.family.nodes),
        "critical_load_quartiles": [float(v) for v in np.nanquantile(result.critical_load, [0.25, 0.5, 0.75])],
        "mu_median": [float(v) for v in np.median([c.mu for c in result.curves], axis=0)], "loads": [0.1, 0.3, 1.0], "load_average": os.getloadavg()[0],
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
              f"{100 * r['pull_off_off']:.2g} % (estimate {100 * r['pull_off_estimate']:.2g} %), transition "
              f"{100 * r['transition_off']:+.2g} %")


if __name__ == "__main__":
    main()
