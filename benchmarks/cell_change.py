"""How far a change of the unit cell's solves moves what the prediction reports, against the error
estimate reported beside each number, and how far it moves the estimates themselves: the code
before and this code in one run (issue 34: the half-grid companion of an estimate prepared with
fewer nodes, docs/solver.md "The companion of an estimate").

The cases and the comparison are those of ``curve_tolerance.py``: 15 of ``examples/sweep.toml``'s
cells (grid 48 with its 24 companion, 40 loads) and the default cell (``predict``'s accuracy
choice), each predicted in a fresh process on an empty cache, one thread, with the code before
(``--before REV``, main by default: its ``src/`` from ``git archive``, first on ``PYTHONPATH``)
and with this code. Printed per group of cells: solves, iterations (every solve, coarse levels
included), CPU seconds, and the largest change of each reported number in units of its error
estimate (the grid's error for A_re/A_fr, mu and psi relative where psi > 0.01; the state
pressures' errors for those pressures and the critical and full-contact loads; the
interpolation error for psi absolute), then the estimates' own change, ``new / before`` of the
grid's error of A_re/A_fr and of the two state pressures' errors (smallest and largest over the
cells), and the grid each cell ended on where it differs.

``--companion JSON`` tries another plan of the companion on this code's side (the options
``fingerpad.micro.resolution.COMPANION_OPTIONS`` holds, e.g. ``'{"psi_step": 0.08}'``), ``--bem
JSON`` other values of ``fingerpad.micro.bem``'s constants there (e.g. ``'{"MAX_PSI_STEP": 0.06}'``).

    python benchmarks/cell_change.py [--before main] [--companion JSON] [--bem JSON]
                                     [--out out/bench/cell_change.json]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from bench_map_speed import checkout  # noqa: E402
from curve_tolerance import compare  # noqa: E402


def _plain(value: Any) -> Any:
    # not fingerpad.encode.to_jsonable: this runs under the checkout compared against (--before),
    # whose package may predate it; non-finite floats stay floats (json writes them)
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    return value


def dump(path: str) -> None:
    """Predict every case with the fingerpad this interpreter imports; write the results as JSON."""
    import warnings

    warnings.simplefilter("ignore")
    from curve_tolerance import cases, run_variant

    from fingerpad.design.evaluate import limit_threads
    from fingerpad.micro import bem, resolution
    from fingerpad.micro.bem import CURVE_TOL

    limit_threads()
    for name, value in json.loads(os.environ.get("CELL_CHANGE_BEM") or "{}").items():  # --bem
        setattr(bem, name, value)
    if os.environ.get("CELL_CHANGE_COMPANION"):  # --companion
        resolution.COMPANION_OPTIONS.clear()
        resolution.COMPANION_OPTIONS.update(json.loads(os.environ["CELL_CHANGE_COMPANION"]))
    Path(path).write_text(json.dumps(_plain(run_variant(CURVE_TOL, cases()))))


def side(python_path: str | None, variant: dict[str, str] | None = None) -> dict:
    """The results of one side, predicted in a fresh process (``python_path`` first on the path;
    ``variant``: environment variables of a variant, :func:`dump` reads them)."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("CELL_CHANGE_")}
    env.update(variant or {})
    if python_path:
        env["PYTHONPATH"] = python_path + os.pathsep + env.get("PYTHONPATH", "")
    with tempfile.TemporaryDirectory(prefix="fingerpad-cell-change-") as folder:
        out = Path(folder) / "points.json"
        subprocess.run([sys.executable, __file__, "--dump", str(out)], env=env, check=True)
        return json.loads(out.read_text())


ESTIMATES = {"area_ratio_error": ("grid_error", None),
             "transition_pressure_error": ("res", "transition_pressure_error"),
             "full_contact_pressure_error": ("res", "full_contact_pressure_error")}


def estimate_change(before: dict, now: dict, names: list[str]) -> dict:
    """The smallest and largest ``now / before`` of each error estimate over the cells (finite
    ones), and the cells whose grid changed (an automatic choice follows its estimate)."""
    ratio: dict[str, list[float]] = {}
    grids = {}
    for name in names:
        b, n = before[name], now[name]
        if b.get("grid") != n.get("grid") and not (np.isnan(b.get("grid", 0.0)) and np.isnan(n.get("grid", 0.0))):
            grids[name] = (b.get("grid"), n.get("grid"))
        for key, (slot, sub) in ESTIMATES.items():
            x, y = (b[slot], n[slot]) if sub is None else (b[slot].get(sub), n[slot].get(sub))
            if x is None or y is None or not (np.isfinite(x) and np.isfinite(y)) or x == 0:
                continue
            r = ratio.setdefault(key, [np.inf, -np.inf])
            r[0], r[1] = min(r[0], y / x), max(r[1], y / x)
    return {"ratio": ratio, "grids": grids}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", default="main", help="the git revision of the code before")
    parser.add_argument("--out", type=Path, default=HERE.parent / "out" / "bench" / "cell_change.json")
    parser.add_argument("--companion", help="the companion's options on this code's side (JSON)")
    parser.add_argument("--bem", help="values of fingerpad.micro.bem's constants on this code's side (JSON)")
    parser.add_argument("--dump", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.dump:
        dump(args.dump)
        return
    old_src = checkout(args.before)
    try:
        before = side(str(old_src))
    finally:
        import shutil

        shutil.rmtree(old_src.parent, ignore_errors=True)
    variant = {"CELL_CHANGE_COMPANION": args.companion or "", "CELL_CHANGE_BEM": args.bem or ""}
    now = side(None, variant)
    names = list(before)
    groups = {"sweep cells": [n for n in names if n != "default"], "default cell": ["default"]}
    report: dict[str, Any] = {"load": os.getloadavg()[0], "before": args.before, "rows": []}
    print(f"{'code':>7s} {'cells':>12s} {'solves':>6s} {'iters':>6s} {'CPU s':>6s}  worst change / error "
          f"(load average {report['load']:.2f})")
    for label, run in (("before", before), ("now", now)):
        for group, members in groups.items():
            row = compare(before, run, members)
            report["rows"].append({"code": label, "cells": group, **row})
            worst = " ".join(f"{k}={v:.4f}" for k, v in row["worst_over_error"].items())
            print(f"{label:>7s} {group:>12s} {row['solves']:6d} {row['iterations']:6d} {row['cpu']:6.2f}  {worst}")
    report["estimates"] = estimate_change(before, now, names)
    report["cells"] = {name: {side: {"grid_error": run[name].get("grid_error"), **{
        k: run[name]["res"].get(k) for k in ("transition_pressure_error", "full_contact_pressure_error")}}
        for side, run in (("before", before), ("now", now))} for name in names}
    for key, (lo, hi) in report["estimates"]["ratio"].items():
        print(f"estimate {key:28s} now / before: {lo:.3f} .. {hi:.3f}")
    for name, (g0, g1) in report["estimates"]["grids"].items():
        print(f"grid changed: {name}: {g0} -> {g1}")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()
