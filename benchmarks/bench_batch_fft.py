"""What a stack of unit-cell solves would buy, and what it would cost in bits (issue 34).

A grid-48 cell solve is ~7-9 preconditioned conjugate-gradient iterations of five small FFTs and
~40 element-wise NumPy calls each: most of its time is the per-call cost, which a stack of
problems, ``(nodes, n, n)``, would spread. Two questions decide whether the solves may be run
so (docs/benchmarks.md, "A design map's wait"):

1. **Cost**: one slice's share of a transform or an element-wise product in a stack of ``k``
   against the same call on the slice alone, for the grids of a sweep (48 and its companion 24).
2. **Bits**: whether a slice's transform in a stack has the bits of the transform of that slice
   alone, and whether they depend on the slice's place in the stack or on the stack's size (a
   node's stored value must be a function of its pressure alone, never of what else a run
   solved beside it), for each FFT engine the package can use: ducc0 (the default), SciPy's
   and NumPy's pocketfft.

    python benchmarks/bench_batch_fft.py [--grids 48,24] [--stacks 1,2,3,8,32] [--repeat 2000]

Output: two tables on stdout, JSON in ``out/bench/batch_fft.json``. Nothing here changes a
stored number; the solver does not use stacks (yet).
"""

from __future__ import annotations

import argparse
import json
import os
import timeit
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_OUT = ROOT / "out" / "bench" / "batch_fft.json"


def engines() -> dict:
    """Real 2-D forward transforms over the last two axes, by engine (one thread each, as a
    sweep's workers run them)."""
    import scipy.fft as sfft

    out = {"numpy": lambda a: np.fft.rfft2(a, axes=(-2, -1)),
           "scipy": lambda a: sfft.rfft2(a, axes=(-2, -1), workers=1)}
    try:
        import ducc0.fft as dfft

        out["ducc0"] = lambda a: dfft.r2c(a, axes=(a.ndim - 2, a.ndim - 1), nthreads=1)
    except ImportError:
        pass
    return out


def bits(fwd, n: int, stacks: list[int], rng: np.random.Generator) -> dict:
    """For each stack size ``k``: how many of its slices have the bits of the slice transformed
    alone, and how many those of the same slice in a stack of 32 at place 0 (the 'stacked'
    bits), the slice under test put at every place in turn among random others."""
    x = rng.random((n, n))
    alone = fwd(x)
    big = rng.random((32, n, n))
    big[0] = x
    stacked = fwd(big)[0]
    rows = {}
    for k in stacks:
        same_alone = same_stacked = 0
        for place in range(k):
            st = rng.random((k, n, n))
            st[place] = x
            y = fwd(st)[place]
            same_alone += bool(np.array_equal(y, alone))
            same_stacked += bool(np.array_equal(y, stacked))
        rows[k] = {"places": k, "as_alone": same_alone, "as_stacked": same_stacked}
    rel = float(np.max(np.abs(stacked - alone)) / np.max(np.abs(alone)))
    return {"stacks": rows, "max_rel_difference": rel}


def cost(n: int, stacks: list[int], repeat: int, rng: np.random.Generator) -> dict:
    """Microseconds per slice of a forward transform (float64) by each engine, of ducc0's
    float32 forward and float64 inverse transforms and of an element-wise product into a
    buffer: on a stack of ``k`` against ``k`` calls on single slices (the best of 5 rounds)."""
    try:
        import ducc0.fft as dfft
    except ImportError:  # the "fast" extra is not installed: the other engines only
        dfft = None

    out = {}
    forward = engines()
    for k in stacks:
        x = rng.random((k, n, n))
        buf = np.empty_like(x)
        ops = {f"{name} r2c": (lambda f=f: f(x), lambda i, f=f: f(x[i])) for name, f in forward.items()}
        if dfft is not None:
            x32 = x.astype(np.float32)
            xh = dfft.r2c(x, axes=(1, 2))
            ops["ducc0 r2c f32"] = (lambda: dfft.r2c(x32, axes=(1, 2)), lambda i: dfft.r2c(x32[i], axes=(0, 1)))
            ops["ducc0 c2r"] = (lambda: dfft.c2r(xh, axes=(1, 2), lastsize=n, forward=False, inorm=2),
                                lambda i: dfft.c2r(xh[i], axes=(0, 1), lastsize=n, forward=False, inorm=2))
        ops["multiply"] = (lambda: np.multiply(x, x, out=buf), lambda i: np.multiply(x[i], x[i], out=buf[i]))
        row = {}
        number = max(1, repeat // k)
        for name, (stack, single) in ops.items():
            t_stack = min(timeit.repeat(stack, number=number, repeat=5)) / number / k * 1e6
            t_single = min(timeit.repeat(lambda single=single: [single(i) for i in range(k)], number=number,
                                         repeat=5)) / number / k * 1e6
            row[name] = {"stacked_us": t_stack, "alone_us": t_single}
        out[k] = row
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", default="48,24")
    parser.add_argument("--stacks", default="1,2,3,8,32")
    parser.add_argument("--repeat", type=int, default=2000, help="transforms timed per case")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT)
    args = parser.parse_args()
    grids = [int(g) for g in args.grids.split(",")]
    stacks = [int(k) for k in args.stacks.split(",")]
    rng = np.random.default_rng(34)
    load = os.getloadavg()
    report = {"load_average": load, "bits": {}, "cost": {}}
    print(f"load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")
    print("\nbits: slices of a stack of k whose forward transform has the bits of the slice alone / "
          "of the slice in a stack of 32")
    for name, fwd in engines().items():
        for n in grids:
            b = bits(fwd, n, stacks, rng)
            report["bits"][f"{name} {n}"] = b
            cells = "  ".join(f"k={k}: {r['as_alone']}/{r['as_stacked']} of {k}" for k, r in b["stacks"].items())
            print(f"{name:6s} {n:3d}  {cells}  (largest difference {b['max_rel_difference']:.1e} of the largest mode)")
    print("\ncost, us per slice: stacked / alone (the best of 5 rounds)")
    for n in grids:
        c = cost(n, stacks, args.repeat, rng)
        report["cost"][n] = c
        for k, row in c.items():
            for op, v in row.items():
                print(f"grid {n:3d}  k={k:2d}  {op:14s} {v['stacked_us']:6.1f} / {v['alone_us']:6.1f}")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=1, default=str))
    print(f"\nwrote {args.out}")


if __name__ == "__main__":
    main()
