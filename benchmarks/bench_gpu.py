"""The contact solver on a GPU array namespace against NumPy on the CPU, in one run.

Run (on a machine with a CUDA GPU and CuPy and/or PyTorch; CI has neither, and this is not a
test)::

    .venv/bin/python benchmarks/bench_gpu.py                       # 1024^2, 2048^2, 4096^2
    .venv/bin/python benchmarks/bench_gpu.py --grids 1024 --reps 3

The cell is the issue-12 one of ``bench_solver.py`` (one spherical cap, R 50 um, h 10 um, in a
periodic 100 um cell, E* 0.3 MPa, tol 1e-8) at the mid load (15 kPa, 35 % contact). For each
grid and namespace: the median seconds of ``--reps`` cold solves (a fresh solver each, after one
warm-up solve that is not counted: GPU kernel compilation, FFT plans), iterations, and the
contact fraction and pressure difference against the NumPy solve. Namespaces: ``numpy`` (the
default CPU path: NumPy kernels, ducc0 or SciPy FFTs on all cores), ``cupy`` and ``torch``
(through ``array_api_compat``), each where it imports and sees a device.

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


def namespaces() -> dict[str, tuple[Any, Any]]:
    """name -> (array namespace, synchronise()) for every namespace usable here."""
    out: dict[str, tuple[Any, Any]] = {"numpy": (np, lambda: None)}
    try:
        import cupy as cp  # noqa: PLC0415

        if cp.cuda.runtime.getDeviceCount() > 0:
            out["cupy"] = (cp, lambda: cp.cuda.Device().synchronize())
    except Exception as exc:  # noqa: BLE001 - no CuPy or no driver: the row is left out
        log(f"cupy left out: {exc}")
    try:
        import torch  # noqa: PLC0415
        from array_api_compat import torch as xtorch  # noqa: PLC0415

        if torch.cuda.is_available():
            torch.set_default_device("cuda")
            out["torch"] = (xtorch, torch.cuda.synchronize)
    except Exception as exc:  # noqa: BLE001
        log(f"torch left out: {exc}")
    return out


def device_name() -> str | None:
    try:
        import torch  # noqa: PLC0415

        return torch.cuda.get_device_name(0) if torch.cuda.is_available() else None
    except Exception:  # noqa: BLE001
        return None


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--grids", default="1024,2048,4096", help="comma-separated grid sizes")
    ap.add_argument("--reps", type=int, default=3, help="timed solves per case (median)")
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help="JSON report")
    args = ap.parse_args(argv)
    grids = [int(g) for g in args.grids.split(",")]

    from fingerpad.contact import HalfSpaceSolver  # noqa: PLC0415
    from fingerpad.textures import spherical_caps  # noqa: PLC0415

    xps = namespaces()
    rows = []
    for g in grids:
        tex = spherical_caps(radius=RADIUS, height=HEIGHT, spacing=SPACING, lattice="square", grid=g)
        ref = None
        for name, (xp, sync) in xps.items():
            def solve():
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    s = HalfSpaceSolver(tex, MODULUS, tol=TOL, xp=None if name == "numpy" else xp)
                    t0 = time.perf_counter()
                    r = s.solve_pressure(PRESSURE)
                    sync()
                    return time.perf_counter() - t0, r

            solve()  # warm-up: kernels, plans
            times, res = [], None
            for _ in range(args.reps):
                t, res = solve()
                times.append(t)
            row = {"grid": g, "xp": name, "seconds": statistics.median(times), "iterations": res.iterations,
                   "converged": res.converged, "contact_fraction": res.contact_fraction, "fft": s_fft(name, xp)}
            if ref is None:
                ref = (row["seconds"], res)
            else:
                row["speed-up"] = ref[0] / row["seconds"]
                row["d_contact_fraction"] = abs(res.contact_fraction - ref[1].contact_fraction)
                row["max_dp_rel"] = float(np.abs(res.pressure - ref[1].pressure).max() / ref[1].max_pressure)
            rows.append(row)
            log(f"{g}^2 {name}: {row['seconds']:.3f} s, {res.iterations} it, contact {res.contact_fraction:.5f}")
    report = {"date": time.strftime("%Y-%m-%d"), "cpu_cores": os.cpu_count(), "platform": platform.platform(),
              "gpu": device_name(), "rows": rows}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=2))
    print(f"GPU: {report['gpu']}; CPU cores: {report['cpu_cores']}\n")
    print("| grid | namespace | FFT | iterations | seconds | speed-up vs NumPy | Δ contact fraction | max Δp / p_max |")
    print("|---|---|---|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['grid']}² | {r['xp']} | {r['fft']} | {r['iterations']} | {r['seconds']:.3f} | "
              f"{r.get('speed-up', 1.0):.1f}x | {r.get('d_contact_fraction', 0.0):.2g} | {r.get('max_dp_rel', 0.0):.2g} |")
    return 0


def s_fft(name: str, xp: Any) -> str:
    from fingerpad.contact.greens import Backend  # noqa: PLC0415

    return Backend(None if name == "numpy" else xp).fft


if __name__ == "__main__":
    sys.exit(main())
