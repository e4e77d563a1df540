"""Where a sweep point's time goes (issue 34): a sweep run in this process, its CPU time charged
to parts.

The sweep of ``bench_map_speed.py`` (caps, spacing x height, grid 48, 40 loads; ``--population``
for the members) planned and run as ``fingerpad sweep`` runs it (``plan_sweep``,
``execute_plan``, a fresh store, an empty unit-cell cache), but by the in-process executor, so
that one process sees every part: no Dask here (its overhead is the difference between
``bench_map_speed.py``'s CPU a point and this one's). The functions below are wrapped so that
each moment of CPU time is charged to the innermost part running (a solve inside a cell's
preparation inside the grid choice is a solve):

* cell solves: the contact solves of the unit cells (``HalfSpaceSolver._solve``);
* cell planning: the rest of ``BEMUnitCell.prepare``/``prepare_states`` (nodes, state search,
  cache reads and writes);
* grid choice and coupling: the rest of ``choose_grid`` (the psi interpolants, the couplings of
  the error estimate);
* members: the members' cells and loads (``member_cells``, ``predict_fingers``,
  ``evaluate_members``) less their solves;
* store writes: ``SweepStore.write``;
* the rest: the studies' set-up, the prediction's other numbers, the plan.

The cell solves are then told apart by what they are for, the innermost of: the grid nodes
(the state search's among them), the
refinement nodes, the state brackets' bisection; other (none of these around the solve).

    python benchmarks/profile_sweep.py [--points 16] [--population adults]

Prints the CPU time, the solves and the table of parts. Measures, changes nothing.
"""

from __future__ import annotations

import argparse
import functools
import os
import shutil
import sys
import tempfile
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

#: The parts: a name and the functions (module, qualified name) whose CPU time it is charged.
PARTS = [
    ("cell solves", [("fingerpad.contact.solver", "HalfSpaceSolver._solve")]),
    ("cell planning", [("fingerpad.micro.bem", "BEMUnitCell.prepare"), ("fingerpad.micro.bem", "BEMUnitCell.prepare_states")]),
    ("grid choice and coupling", [("fingerpad.micro.resolution", "choose_grid")]),
    ("members", [("fingerpad.population.members", "member_cells"), ("fingerpad.population.members", "predict_fingers"),
                 ("fingerpad.population.members", "evaluate_members")]),
    ("store writes", [("fingerpad.design.store", "SweepStore.write")]),
]
#: What a cell's solves are for: the solves inside these are told apart (the innermost counts);
#: their own time outside the solves stays with the part around them.
SOLVE_KINDS = [
    ("grid nodes", ("fingerpad.micro.bem", "BEMUnitCell.prepare")),  # its solves outside the two below
    ("refinement nodes", ("fingerpad.micro.bem", "BEMUnitCell._refine")),
    ("state brackets", ("fingerpad.micro.bem", "BEMUnitCell._bracket_state")),
]


class Charges:
    """CPU seconds by part, each moment charged to the innermost part running; a cell's solves by
    the innermost kind of solve around them (:data:`SOLVE_KINDS`), with their count."""

    def __init__(self) -> None:
        self.seconds: dict[str, float] = {name: 0.0 for name, _ in PARTS}
        self.seconds["the rest"] = 0.0
        self.kinds: dict[str, list[float]] = {}
        self.stack = ["the rest"]
        self.kind_stack = ["other"]
        self.mark = time.process_time()

    def switch(self, push: str | None) -> None:
        now = time.process_time()
        top = self.stack[-1]
        self.seconds[top] += now - self.mark
        if top == "cell solves":
            self.kinds.setdefault(self.kind_stack[-1], [0.0, 0])[0] += now - self.mark
        self.mark = now
        if push is None:
            self.stack.pop()
            return
        if push == "cell solves" and top != "cell solves":
            self.kinds.setdefault(self.kind_stack[-1], [0.0, 0])[1] += 1
        self.stack.append(push)

    def wrap(self, part: str, fn):
        @functools.wraps(fn)
        def wrapped(*args, **kwargs):
            self.switch(part)
            try:
                return fn(*args, **kwargs)
            finally:
                self.switch(None)
        return wrapped

    def mark_kind(self, kind: str, fn):
        @functools.wraps(fn)
        def wrapped(*args, **kwargs):
            self.kind_stack.append(kind)
            try:
                return fn(*args, **kwargs)
            finally:
                self.kind_stack.pop()
        return wrapped


def instrument(charges: Charges) -> None:
    """Wrap the parts' functions where they are defined and wherever a loaded fingerpad module
    imported them by name."""
    import importlib

    for kind, (module, qualname) in SOLVE_KINDS:
        cls_name, attr = qualname.split(".")
        cls = getattr(importlib.import_module(module), cls_name)
        setattr(cls, attr, charges.mark_kind(kind, getattr(cls, attr)))
    for part, targets in PARTS:
        for module, qualname in targets:
            mod = importlib.import_module(module)
            if "." in qualname:
                cls_name, attr = qualname.split(".")
                cls = getattr(mod, cls_name)
                setattr(cls, attr, charges.wrap(part, getattr(cls, attr)))
                continue
            original = getattr(mod, qualname)
            wrapped = charges.wrap(part, original)
            for other in list(sys.modules.values()):
                if getattr(other, "__name__", "").startswith("fingerpad") and getattr(other, qualname, None) is original:
                    setattr(other, qualname, wrapped)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=16)
    parser.add_argument("--population", default=None, help="a population preset (e.g. adults)")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    from bench_map_speed import spec as sweep_spec
    from fingerpad.design.engine import SweepReport, execute_plan, sweep_pressures
    from fingerpad.design.executor import InProcessExecutor
    from fingerpad.design.plan import plan_sweep
    from fingerpad.design.store import SweepStore

    folder = Path(tempfile.mkdtemp(prefix="profile-sweep-"))
    spec = sweep_spec(args.points, str(folder / "cache"), args.population)
    pressures = sweep_pressures(spec)
    store = SweepStore(folder / "s.zarr", spec, pressures)
    store.create()
    import fingerpad.population.members  # noqa: F401  (loaded before the wrapping: its names are wrapped)
    import fingerpad.study.run  # noqa: F401

    charges = Charges()
    instrument(charges)
    cpu = time.process_time()
    charges.mark = cpu
    report = execute_plan(plan_sweep(spec), InProcessExecutor(), store, spec.loads, pressures,
                          SweepReport(points=spec.size), population=spec.population_payload())
    charges.switch(None)
    cpu = time.process_time() - cpu
    load = os.getloadavg()
    print(f"{report.computed} points, {report.solves} solves, {cpu:.2f} s CPU ({cpu / max(report.computed, 1) * 1e3:.0f} ms "
          f"a point), load average {load[0]:.1f} {load[1]:.1f} {load[2]:.1f}")
    print(f"{'part':26s} {'CPU s':>7s} {'share':>6s}")
    for name, v in charges.seconds.items():
        print(f"{name:26s} {v:7.2f} {v / cpu:6.0%}")
    print(f"\n{'cell solves by kind':26s} {'CPU s':>7s} {'share':>6s} {'solves':>7s}")
    for kind, (v, n) in sorted(charges.kinds.items(), key=lambda kv: -kv[1][0]):
        print(f"{kind:26s} {v:7.2f} {v / cpu:6.0%} {n:7d}")
    shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
