"""A curve's tolerance against the accuracy the prediction reports (issue 23; docs/solver.md,
"The tolerance of a curve").

The unit-cell curves of 15 of ``examples/sweep.toml``'s cells (every other spacing and height,
grid 48 with its 24 companion) and of the default cell (``predict``'s accuracy choice), solved
with the nodes at several tolerances (every node cold since issue 31: a warm start made a node's
bits depend on the cache's history); each number the prediction reports is compared with every
solve at ``tol`` 1e-8 in units of the error estimate reported beside it: the grid's error for A_re/A_fr, mu and
psi relative (psi > 0.01), the state pressures' errors for those pressures and the critical and
full-contact loads, the interpolation error for psi absolute. Iterations are counted over every
solve; one thread, an empty cache per variant.

    python benchmarks/curve_tolerance.py [--out out/bench/curve_tolerance.json]
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
#: Nodes' tolerances (0: every node to ``tol``, the reference); 1e-7 is ``CURVE_TOL``.
VARIANTS = [0.0, 1e-7, 1e-6, 1e-5]
ERRORS = {"critical_load_bem": "transition_pressure_error", "transition_pressure": "transition_pressure_error",
          "full_contact_load": "full_contact_pressure_error", "full_contact_pressure": "full_contact_pressure_error"}
KEYS = ["area_ratio", "mu", "critical_load_bem", "full_contact_load", "transition_pressure", "full_contact_pressure",
        "psi"]


def cases() -> list[tuple[str, dict, np.ndarray]]:
    from fingerpad.design.spec import read_sweep_file, sweep_from_dict

    spec = sweep_from_dict(read_sweep_file(str(ROOT / "examples" / "sweep.toml")))
    out = [(f"sweep {i},{j}", spec.study_data(spec.assignment((i, j))), np.asarray(spec.loads, float))
           for i in range(0, spec.shape[0], 2) for j in range(0, spec.shape[1], 2)]
    default = {"texture": {"name": "caps", "radius": "100um", "height": "20um", "spacing": "175um",
                           "lattice": "hexagonal"}, "model": {"kind": "bem"}}
    return out + [("default", default, np.linspace(0.1, 4.0, 40))]


def run_variant(curve_tol: float, todo: list) -> dict:
    import fingerpad.study.run as srun
    from fingerpad.contact import HalfSpaceSolver
    from fingerpad.design.evaluate import evaluate_point
    from fingerpad.micro import bem

    os.environ["FINGERPAD_CACHE"] = tempfile.mkdtemp(prefix="fingerpad-bench-tol-")
    seen: dict = {}
    count = {"iterations": 0, "solves": 0}
    run_study, solve = srun.run_study, HalfSpaceSolver.solve_pressure

    def recording(study, progress=None):
        pred = run_study(study, progress)
        seen.update(res=pred.resolution or {}, interp=pred.primary_cell.interpolation_error)
        return pred

    def counted(self, p, initial=None):
        res = solve(self, p, initial)
        count["iterations"] += res.iterations
        count["solves"] += 1
        return res

    srun.run_study, HalfSpaceSolver.solve_pressure, bem.CURVE_TOL = recording, counted, curve_tol
    pressures = np.geomspace(1e2, 1e6, 30)
    out = {}
    try:
        for name, data, loads in todo:
            count.update(iterations=0, solves=0)
            t0 = time.process_time()
            point = evaluate_point(data, loads, pressures)
            out[name] = {**point, "res": dict(seen["res"]), "interp": seen["interp"], **count,
                         "cpu": time.process_time() - t0}
    finally:
        srun.run_study, HalfSpaceSolver.solve_pressure = run_study, solve
    return out


def compare(ref: dict, new: dict, names: list[str]) -> dict:
    worst = dict.fromkeys(KEYS + ["psi_absolute"], 0.0)
    for name in names:
        r, o = ref[name], new[name]
        if not r["valid"]:
            continue
        for k in KEYS:
            err = r["res"].get(ERRORS[k]) if k in ERRORS else r["grid_error"]
            a, b = np.asarray(o[k], float), np.asarray(r[k], float)
            with np.errstate(all="ignore"):
                rel = np.abs(a / b - 1)
            rel = rel[np.isfinite(rel) & ((b > 0.01) if k == "psi" else True)]
            if rel.size:
                worst[k] = max(worst[k], float(rel.max()) / err)
        diff = float(np.nanmax(np.abs(np.asarray(o["psi"], float) - np.asarray(r["psi"], float))))
        worst["psi_absolute"] = max(worst["psi_absolute"], diff / r["interp"])
    return {"iterations": sum(new[n]["iterations"] for n in names), "solves": sum(new[n]["solves"] for n in names),
            "cpu": sum(new[n]["cpu"] for n in names), "worst_over_error": worst}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "out" / "bench" / "curve_tolerance.json")
    args = parser.parse_args()
    from fingerpad.design.evaluate import limit_threads

    limit_threads()
    todo = cases()
    groups = {"sweep cells": [n for n, _, _ in todo if n != "default"], "default cell": ["default"]}
    runs = [run_variant(tol, todo) for tol in VARIANTS]
    report = {"load": Path("/proc/loadavg").read_text().split()[0], "rows": []}
    print(f"{'nodes to':>9s} {'cells':>12s} {'solves':>6s} {'iters':>6s} {'CPU s':>6s}  worst change / error")
    for tol, run in zip(VARIANTS, runs):
        for group, names in groups.items():
            row = compare(runs[0], run, names)
            report["rows"].append({"curve_tol": tol or "tol", "cells": group, **row})
            worst = " ".join(f"{k}={v:.4f}" for k, v in row["worst_over_error"].items())
            print(f"{tol or 1e-8:9.0e} {group:>12s} {row['solves']:6d} "
                  f"{row['iterations']:6d} {row['cpu']:6.2f}  {worst}")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()
