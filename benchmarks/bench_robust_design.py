"""Benchmark of the design for a population (``fingerpad design --population``): the cost of one
candidate texture, in one run on this machine.

For the default texture (caps, BEM at the default grid, the unit cell cached after a first
prediction) and the ``adults`` population (1000 fingers), at one target load:

* the plain design's direct prediction of the nominal finger (``predict_candidate``);
* the search's screen of the whole population (the nominal prediction, then every finger read
  from the one cell at once: ``fingerpad.design.robust.screen_candidate``);
* the direct population prediction that every reported candidate gets (``run_population``:
  ``population_candidate``).

The screen's coverage equals the direct one (checked here too). The load average is printed
next to the times: the machine is shared.

Usage: ``.venv/bin/python benchmarks/bench_robust_design.py [--repeats 3] [--size 1000]``.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import shutil
import statistics
import tempfile
import time
from pathlib import Path

from fingerpad.design.inverse import DesignProblem, parse_target, predict_candidate
from fingerpad.design.inverse_design import free_axes
from fingerpad.design.robust import population_candidate, population_goal, screen_candidate
from fingerpad.study.spec import DEFAULT_STUDY


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3, help="repetitions of each timing (median reported)")
    ap.add_argument("--size", type=int, default=1000, help="fingers of the adults population")
    ap.add_argument("--out", default="out/bench/robust_design.json")
    args = ap.parse_args()

    cache = tempfile.mkdtemp(prefix="fingerpad-bench-cache-")
    try:
        base = {k: dict(v) for k, v in DEFAULT_STUDY.items()}
        base["model"] = {**base["model"], "kind": "bem", "cache": cache}
        problem = DesignProblem(base=base, axes=free_axes(["spacing=100um:400um"], "caps"),
                                targets=[parse_target("mu_rel=0.45@1N")], tolerance=0.3)
        goal = population_goal("adults", 0.9, None)
        goal = dataclasses.replace(goal, population=dataclasses.replace(goal.population, size=args.size))
        screen = screen_candidate(problem, goal)
        params = {"spacing": 175e-6}
        t = time.perf_counter()
        first = screen(problem, params)  # solves the cell over the fingers' pressures, tabulates the fingers
        cold = time.perf_counter() - t

        def timed(fn) -> tuple[float, object]:
            runs, out = [], None
            for _ in range(args.repeats):
                t = time.perf_counter()
                out = fn()
                runs.append(time.perf_counter() - t)
            return statistics.median(runs), out

        plain_s, _ = timed(lambda: predict_candidate(problem, params))
        screen_s, screened = timed(lambda: screen(problem, params))
        direct_s, direct = timed(lambda: population_candidate(problem, goal, params))
        load = os.getloadavg()
        result = {
            "fingers": args.size, "repeats": args.repeats, "load_average": load,
            "first_screen_s (cell solved, fingers tabulated)": cold,
            "plain_candidate_s": plain_s, "screen_candidate_s": screen_s, "direct_population_s": direct_s,
            "direct_over_screen": direct_s / screen_s, "screen_over_plain": screen_s / plain_s,
            "coverage_screen": screened.population["coverage"], "coverage_direct": direct.population["coverage"],
            "first_coverage": first.population["coverage"],
        }
        print(f"{args.size} fingers, load average {load[0]:.1f}; per candidate (cell cached, median of "
              f"{args.repeats}): plain {plain_s:.3f} s, screen {screen_s:.3f} s, direct run_population "
              f"{direct_s:.3f} s (direct / screen {direct_s / screen_s:.1f}x); first screen with the cell "
              f"solved {cold:.2f} s; coverage screen {result['coverage_screen']:.4g} = direct "
              f"{result['coverage_direct']:.4g}")
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(json.dumps(result, indent=2) + "\n", encoding="utf-8")
    finally:
        shutil.rmtree(cache, ignore_errors=True)


if __name__ == "__main__":
    main()
