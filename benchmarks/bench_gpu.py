"""The contact solver on a GPU array namespace against NumPy on the CPU, in one run.

Run (on a machine with a CUDA GPU and CuPy and/or PyTorch; CI has neither, and this is not a
test)::

    .venv/bin/python benchmarks/bench_gpu.py                       # 1024^2, 2048^2, 4096^2
    .venv/bin/python benchmarks/bench_gpu.py --grids 1024 --reps 3

The cell is the issue-12 one of ``bench_solver.py`` (one spherical cap, R 50 um, h 10 um, in a
periodic 100 um cell, E* 0.3 MPa, tol 1e-8) at the mid load (15 kPa, 35 % contact). For each
grid and namespace: the median seconds of ``--reps`` cold solves (a fresh solver each, after one
warm-up solve that is not counted: GPU kernel compilation, FFT plans), iterations, and the
contact fraction and pressure difference against the NumPy solve. Namespaces (``--xp``):
``numpy`` (the default CPU path: ``kernels="auto"``, ducc0 or SciPy FFTs on all cores; it runs
first, before any GPU library is imported), ``cupy`` and ``torch`` (PyTorch through
``array_api_compat``), each where it imports and sees a CUDA device (left out otherwise, with
the reason on stderr).

Output: a Markdown table on stdout, JSON in ``out/bench/gpu.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
DEFAULT_OUT = HERE.parent / "out" / "bench" / "gpu.json"
RADIUS, HEIGHT, SPACING, MODULUS, PRESSURE, TOL = 50e-6, 10e-6, 100e-6, 0.3e6, 15e3, 1e-8


def log(msg: str) -> None:
    print(f"[bench {time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


def namespace(name: str) -> tuple[Any, Any] | None:
    """(array namespace, synchronise()) of ``name``, or None (with the reason on stderr) where it
    does not import or sees no CUDA device. Imported only when its rows run, so that the NumPy
    rows run before any GPU library is loaded."""
    if name == "numpy":
        return np, lambda: None
    try:
        if name == "cupy":
            import cupy as cp  # noqa: PLC0415

            if cp.cuda.runtime.getDeviceCount() > 0:
                return cp, lambda: cp.cuda.Device().synchronize()
        else:
            import torch  # noqa: PLC0415
            from array_api_compat import torch as xtorch  # noqa: PLC0415

            if torch.cuda.is_available():
                torch.set_default_device("cuda")
                return xtorch, torch.cuda.synchronize
        log(f"{name} left out: no CUDA device")
    except Exception as exc:  # noqa: BLE001 - not installed, no driver: the rows are left out
        log(f"{name} left out: {exc}")
    return None


def device_name() -> str | None:
    """The CUDA device's name, from whichever GPU library imported; None without one."""
    for probe in (lambda: __import__("torch").cuda.get_device_name(0),
                  lambda: __import__("cupy").cuda.runtime.getDeviceProperties(0)["name"].decode()):
        try:
            return probe()
        except Exception:  # noqa: BLE001 - that library is missing or sees no device
            continue
    return None


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--grids", default="1024,2048,4096", help="comma-separated grid sizes (default: %(default)s)")
    ap.add_argument("--xp", default="numpy,cupy,torch", help="namespaces, NumPy first (default: %(default)s)")
    ap.add_argument("--reps", type=int, default=3, help="timed solves per case, median (default: %(default)s)")
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help="JSON report (default: out/bench/gpu.json)")
    args = ap.parse_args(argv)
    try:
        grids = [int(g) for g in args.grids.split(",")]
    except ValueError:
        ap.error(f"--grids must be whole numbers separated by commas, got {args.grids!r}")
    if any(g < 64 for g in grids):
        ap.error("--grids: use at least 64 points per axis")
    names = [x.strip() for x in args.xp.split(",")]
    if unknown := set(names) - {"numpy", "cupy", "torch"}:
        ap.error(f"--xp: unknown namespace(s) {sorted(unknown)}: choose among numpy, cupy, torch")
    if args.reps < 1:
        ap.error("--reps must be at least 1")

    from fingerpad.contact import HalfSpaceSolver  # noqa: PLC0415
    from fingerpad.textures import spherical_caps  # noqa: PLC0415

    texs = {g: spherical_caps(radius=RADIUS, height=HEIGHT, spacing=SPACING, lattice="square", grid=g) for g in grids}
    rows, refs = [], {}
    for name in sorted(names, key=lambda x: x != "numpy"):
        ns = namespace(name)
        if ns is None:
            continue
        xp, sync = ns
        for g in grids:
            def solve():
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    s = HalfSpaceSolver(texs[g], MODULUS, tol=TOL, xp=None if name == "numpy" else xp)
                    t0 = time.perf_counter()
                    r = s.solve_pressure(PRESSURE)
                    sync()
                    return time.perf_counter() - t0, r, s.backend.fft

            solve()  # warm-up: kernels, plans
            times, res, fft = [], None, ""
            for _ in range(args.reps):
                t, res, fft = solve()
                times.append(t)
            row = {"grid": g, "xp": name, "seconds": statistics.median(times), "iterations": res.iterations,
                   "converged": res.converged, "contact_fraction": res.contact_fraction, "fft": fft}
            if g not in refs:
                refs[g] = (row["seconds"], res)
            else:
                row["speed-up"] = refs[g][0] / row["seconds"]
                row["d_contact_fraction"] = abs(res.contact_fraction - refs[g][1].contact_fraction)
                row["max_dp_rel"] = float(np.abs(res.pressure - refs[g][1].pressure).max() / refs[g][1].max_pressure)
            rows.append(row)
            log(f"{g}^2 {name}: {row['seconds']:.3f} s, {res.iterations} it, contact {res.contact_fraction:.5f}")
    report = {"date": time.strftime("%Y-%m-%d"), "cpu_cores": os.cpu_count(), "platform": platform.platform(),
              "gpu": device_name(), "rows": rows}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=2))
    print(f"GPU: {report['gpu'] or 'none (no CUDA device: NumPy rows only)'}; CPU cores: {report['cpu_cores']}\n")
    print("| grid | namespace | FFT | iterations | seconds | speed-up vs NumPy | Δ contact fraction | max Δp / p_max |")
    print("|---|---|---|---:|---:|---:|---:|---:|")
    for r in sorted(rows, key=lambda r: r["grid"]):
        print(f"| {r['grid']}² | {r['xp']} | {r['fft']} | {r['iterations']} | {r['seconds']:.3f} | "
              f"{r.get('speed-up', 1.0):.1f}x | {r.get('d_contact_fraction', 0.0):.2g} | {r.get('max_dp_rel', 0.0):.2g} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
