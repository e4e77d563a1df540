"""Peer worker: solve periodic contact cells with tamaas' ``PolonskyKeerRey`` (tamaas >= 2.9).

Run by ``benchmarks/bench_solver.py`` as a script in a child interpreter (the benchmark's own,
or ``--tamaas-python``), so that tamaas' C++ progress lines can be read from its stdout::

    PYTHON benchmarks/_peer_tamaas.py JOB.json
    PYTHON benchmarks/_peer_tamaas.py --versions

``JOB.json`` holds ``{"heights": "h.npy", "size": [Lx, Ly], "modulus": E*, "tol": tol,
"pressures": [p1, p2, ...], "maxiter": n}``; the heights (m) are read from the .npy next to it.
One JSON object per line (prefixed ``RESULT``) is written to stdout per pressure, in order; the
pixel pressure fields (Pa) are saved next to the job as ``tamaas_pressure_<i>.npy``.

Conventions of tamaas 2.9 (checked on a cell solved by both codes: same contact set):

* ``ModelFactory.createModel(model_type.basic_2d, [Lx, Ly], [nx, ny])`` with ``E = E*`` and
  ``nu = 0``, so that tamaas' ``E* = E / (1 - nu^2)`` is fingerpad's reduced modulus;
* the surface is the rigid counter-surface, peaks toward the elastic body (fingerpad's heights
  unchanged); ``solve(p)`` imposes the mean pressure ``p`` (Pa); ``model.traction`` is the
  pressure field (Pa);
* ``PolonskyKeerRey(model, surface, tol, pressure, pressure)``: the primal (pressure) Polonsky-Keer
  conjugate gradient at a fixed mean pressure. Its stopping test is tamaas' own (a relative
  complementarity error); ``tol`` is passed unchanged and the benchmark reports the residual
  of the returned field in fingerpad's own metric beside the contact fractions.
* tamaas prints ``iteration  energy  error`` lines on stderr every ``dump_freq``
  iterations and once at the end; with ``dump_freq = 1000`` that is the first and the closing
  line (the final iteration count), which the benchmark reads.

The timing covers the model and solver construction and the solve (not the imports).
This file imports neither fingerpad nor anything outside tamaas and NumPy.
"""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

import numpy as np


def versions() -> dict:
    import tamaas  # noqa: PLC0415

    return {
        "tamaas": getattr(tamaas, "__version__", "?"),
        "numpy": np.__version__,
        "python": sys.version.split()[0],
        "executable": sys.executable,
        "OMP_NUM_THREADS": os.environ.get("OMP_NUM_THREADS"),
    }


def solve_case(heights: np.ndarray, size: tuple[float, float], modulus: float, mean_pressure: float, tol: float,
               maxiter: int = 100000) -> tuple[dict, np.ndarray]:
    import tamaas as tm  # noqa: PLC0415

    nx, ny = heights.shape
    t0 = time.perf_counter()
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [float(size[0]), float(size[1])], [nx, ny])
    model.E = float(modulus)
    model.nu = 0.0
    solver = tm.PolonskyKeerRey(model, np.ascontiguousarray(heights, dtype=float), float(tol),
                                tm.PolonskyKeerRey.pressure, tm.PolonskyKeerRey.pressure)
    solver.max_iter = int(maxiter)
    solver.dump_freq = 1000
    sys.stdout.flush()
    error = solver.solve(float(mean_pressure))
    seconds = time.perf_counter() - t0
    p = np.array(model.traction, dtype=float).reshape(nx, ny)
    contact = p > 0
    return {
        "mean_pressure": float(mean_pressure),
        "mean_pressure_out": float(p.mean()),
        "contact_fraction": float(np.count_nonzero(contact)) / contact.size,
        "seconds": seconds,
        "error": float(error),
        "converged": bool(error < tol),
    }, p


def main(argv: list[str]) -> int:
    if len(argv) == 2 and argv[1] == "--versions":
        print("RESULT " + json.dumps(versions()))
        return 0
    if len(argv) != 2:
        print("usage: _peer_tamaas.py JOB.json | --versions", file=sys.stderr)
        return 2
    job_path = Path(argv[1])
    job = json.loads(job_path.read_text())
    heights = np.load(job_path.parent / job["heights"])
    for i, pm in enumerate(job["pressures"]):
        out, p = solve_case(heights, tuple(job["size"]), job["modulus"], pm, job["tol"], job.get("maxiter", 100000))
        name = f"tamaas_pressure_{i}.npy"
        np.save(job_path.parent / name, p)
        out["pressure_file"] = name
        sys.stdout.flush()
        print("RESULT " + json.dumps(out), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
