"""Cost of a layered unit cell against the homogeneous one, measured in one run (docs/model.md 6.4).

The default study's cell (caps R 100 um, h 20 um, hexagonal spacing 175 um) at grid N, solved
(1) cold (no initial guess, operators already built) at three mean pressures (p / E* = 0.003, 0.03, 0.3: asperity contact, past the
transition, near full contact), and (2) prepared as the BEM unit cell of a prediction (every
node and both state brackets, no cache), for three skins:

* homogeneous E_s = 0.3 MPa;
* the layered finger of docs/model.md 6.5: stratum corneum t = 0.3 mm, E_1 = 0.3 MPa on tissue
  E_2 = 30.4 kPa (nu 0.49);
* a hard case: t = spacing / 10 = 17.5 um, E_1 = 10 E_2.

Each measurement alternates homogeneous and layered runs (median of ``--reps``) so that the
machine's load falls on both sides; the ratios are what to read, with the load average printed.

    python benchmarks/bench_layered.py [--grid 128] [--reps 3]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
import warnings

import fingerpad as fp
from fingerpad.contact import HalfSpaceSolver, Layer
from fingerpad.micro import BEMUnitCell

NU = 0.49
E1 = 0.3e6
E_STAR = E1 / (1 - NU**2)
SKINS = {
    "homogeneous": None,
    "layered t 0.3 mm, E1/E2 = 10": Layer(0.3e-3, E1, NU, E1 / 9.87, NU),
    "layered t 17.5 um, E1/E2 = 10": Layer(17.5e-6, E1, NU, E1 / 10, NU),
}


def texture(grid: int):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fp.make_texture("caps", radius=100e-6, height=20e-6, spacing=175e-6, lattice="hexagonal", grid=grid)


def solve_once(tex, layer, p: float) -> tuple[float, int]:
    """One cold solve (no initial guess) on a solver whose operators are built (a first solve at
    another pressure builds the kernel, the preconditioner and the coarse levels: not timed)."""
    solver = HalfSpaceSolver(tex, E_STAR, layer=layer, tol=1e-8)
    solver.solve_pressure(0.1 * E_STAR)
    t0 = time.perf_counter()
    res = solver.solve_pressure(p * E_STAR)
    return time.perf_counter() - t0, int(res.iterations)


def prepare_once(tex, layer) -> tuple[float, int, int]:
    cell = BEMUnitCell(tex, E_STAR, cache=False, layer=layer)
    t0 = time.perf_counter()
    cell.prepare(0.02 * 4e3, 1.5 * 40e3)
    iters = sum(int(row["iterations"]) for row in cell._unit_points.values())
    return time.perf_counter() - t0, cell.solves, iters


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--grid", type=int, default=128)
    ap.add_argument("--reps", type=int, default=3)
    args = ap.parse_args()
    tex = texture(args.grid)
    print(f"grid {tex.shape[0]}x{tex.shape[1]}, load average {os.getloadavg()[0]:.2f} at the start\n")
    print("| skin | p/E* | iterations | s per solve | ms per iteration | per iteration vs homogeneous |")
    print("|---|---|---|---|---|---|")
    for p in (0.003, 0.03, 0.3):
        runs: dict[str, list[tuple[float, int]]] = {k: [] for k in SKINS}
        for _ in range(args.reps):
            for name, layer in SKINS.items():  # alternated: the load falls on every skin
                runs[name].append(solve_once(tex, layer, p))
        base = statistics.median(t / max(n, 1) for t, n in runs["homogeneous"])
        for name in SKINS:
            t = statistics.median(r[0] for r in runs[name])
            n = runs[name][0][1]
            per = statistics.median(r[0] / max(r[1], 1) for r in runs[name])
            print(f"| {name} | {p:g} | {n} | {t:.3f} | {1e3 * per:.2f} | {per / base:.2f} |")
    print("\n| skin | cell solves | iterations (sum) | s to prepare | vs homogeneous |")
    print("|---|---|---|---|---|")
    cells: dict[str, list[tuple[float, int, int]]] = {k: [] for k in SKINS}
    for _ in range(max(1, args.reps // 2)):
        for name, layer in SKINS.items():
            cells[name].append(prepare_once(tex, layer))
    base = statistics.median(r[0] for r in cells["homogeneous"])
    for name in SKINS:
        t = statistics.median(r[0] for r in cells[name])
        _, solves, iters = cells[name][0]
        print(f"| {name} | {solves} | {iters} | {t:.2f} | {t / base:.2f} |")
    print(f"\nload average {os.getloadavg()[0]:.2f} at the end")


if __name__ == "__main__":
    main()
