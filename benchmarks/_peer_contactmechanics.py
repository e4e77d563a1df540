"""Peer worker: solve periodic contact cells with ContactMechanics (Pastewka group).

Run by ``benchmarks/bench_solver.py`` as a script in a child interpreter (the benchmark's own,
or ``--cm-python`` pointing at one that has ContactMechanics + SurfaceTopography), so that its
imports and threads stay out of the timed process::

      PYTHON benchmarks/_peer_contactmechanics.py JOB.json

  ``JOB.json`` holds ``{"heights": "h.npy", "size": [Lx, Ly], "modulus": E*, "tol": tol,
  "pressures": [p1, p2, ...], "maxiter": n}``; the heights (m) are read from the .npy next to
  it. One JSON object per line is written to stdout, one per pressure, in order; the pixel
  pressure fields (Pa) are saved next to the job as ``pressure_<i>.npy``.

This file imports neither fingerpad nor anything outside ContactMechanics/SurfaceTopography/NumPy,
so it runs in the peer's virtual environment unchanged.

Conventions of ContactMechanics 1.8 (checked against its source,
``ContactMechanics/Optimization/ConstrainedConjugateGradients.py`` and
``FFTElasticHalfSpace.py``):

* ``PeriodicFFTElasticHalfSpace(nb_grid_pts, young, physical_sizes)``: with the default
  ``poisson=0`` (and infinite thickness) ``young`` *is* the contact modulus E* (Johnson), so
  E* is passed unchanged.
* ``Topography(heights, physical_sizes, periodic=True)``: the heights are those of the *rigid*
  counter-surface, bumps pointing into the elastic body, i.e. exactly fingerpad's texture
  heights (no sign flip).
* The solver works with *pixel forces* (N), not pressures; ``external_force`` is the total
  compressive force on the cell, positive: ``mean_pressure * Lx * Ly``. The result's ``jac`` is
  the positive (compressive) force per pixel; contact = ``jac > 0``.
* Convergence (``constrained_conjugate_gradients``): all of rms and max penetration on the
  contact set and max displacement change per step < ``pentol`` (metres, absolute); max tensile
  pixel force < ``forcetol`` (newtons, absolute); relative change of the rigid surface position
  < ``thermotol``. To match fingerpad's relative KKT tolerance ``tol`` we pass
  ``pentol = tol * peak_to_valley`` (fingerpad's primal residual is the RMS gap error / PV) and
  ``forcetol = tol * mean_pressure * pixel_area`` (its dual residual is the RMS pressure error /
  mean pressure); ``thermotol`` keeps its default (1e-6). The CM criterion uses maxima where
  fingerpad uses RMS values, so at the same ``tol`` it is the stricter of the two.
* The q = 0 stiffness is a fill-in value (the lowest non-zero one); at fixed total force the
  rigid offset absorbs it, so it does not change the contact solution.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np


def solve_case(heights: np.ndarray, size: tuple[float, float], modulus: float, mean_pressure: float,
               tol: float, maxiter: int = 100000, keep_pressure: bool = False) -> dict:
    """Construct the CM system and solve at ``mean_pressure`` (Pa); the timing covers both.

    With ``keep_pressure`` the pixel pressure field (Pa) is returned under ``"_pressure"``.
    """
    from ContactMechanics import PeriodicFFTElasticHalfSpace  # noqa: PLC0415
    from ContactMechanics.Systems import NonSmoothContactSystem  # noqa: PLC0415
    from SurfaceTopography import Topography  # noqa: PLC0415

    lx, ly = float(size[0]), float(size[1])
    nx, ny = heights.shape
    pv = float(heights.max() - heights.min())
    pixel_area = lx * ly / (nx * ny)
    force = mean_pressure * lx * ly
    pentol = tol * pv
    forcetol = tol * mean_pressure * pixel_area
    t0 = time.perf_counter()
    topography = Topography(heights, (lx, ly), periodic=True)
    substrate = PeriodicFFTElasticHalfSpace((nx, ny), modulus, (lx, ly))
    system = NonSmoothContactSystem(substrate, topography)
    res = system.minimize_proxy(external_force=force, pentol=pentol, forcetol=forcetol, maxiter=maxiter)
    seconds = time.perf_counter() - t0
    f = np.asarray(res.jac)
    contact = f > 0
    out = {
        "mean_pressure": float(mean_pressure),
        "contact_fraction": float(np.count_nonzero(contact)) / contact.size,
        "mean_pressure_out": float(f.sum() / (lx * ly)),
        "seconds": seconds,
        "iterations": int(res.nit),
        "fft_pairs": int(res.nfev),
        "converged": bool(res.success),
        "message": str(res.message),
        "pentol": pentol,
        "forcetol": forcetol,
    }
    if keep_pressure:
        out["_pressure"] = f / pixel_area
    return out


def versions() -> dict:
    # The installed distributions' versions: the packages' own __version__ is computed by
    # `git describe` in the working directory, which names fingerpad's commit when run from here.
    from importlib.metadata import version  # noqa: PLC0415

    return {
        "ContactMechanics": version("ContactMechanics"),
        "SurfaceTopography": version("SurfaceTopography"),
        "numpy": np.__version__,
        "python": sys.version.split()[0],
        "executable": sys.executable,
    }


def main(argv: list[str]) -> int:
    if len(argv) == 2 and argv[1] == "--versions":
        print(json.dumps(versions()))
        return 0
    if len(argv) != 2:
        print("usage: _peer_contactmechanics.py JOB.json | --versions", file=sys.stderr)
        return 2
    job_path = Path(argv[1])
    job = json.loads(job_path.read_text())
    heights = np.load(job_path.parent / job["heights"])
    for i, p in enumerate(job["pressures"]):
        out = solve_case(heights, tuple(job["size"]), job["modulus"], p, job["tol"], job.get("maxiter", 100000),
                         keep_pressure=True)
        name = f"pressure_{i}.npy"
        np.save(job_path.parent / name, out.pop("_pressure"))
        out["pressure_file"] = name
        print(json.dumps(out), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
