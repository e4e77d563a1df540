"""Benchmark of the deflection section model (issue 13: one direction's shear ramp of one
section in under a minute on the 2-core machine; cached repeats instant).

The slender compliant ellipsoid (a x b x h = 45 x 135 x 90 um on a 300 um lattice; E_texture =
E_skin = 0.3 MPa, nu 0.49, the package friction law tau0 = 8.1 kPa, alpha = 0.1), sheared across
its short axis (direction 0: the slender section, h/r = 2).

Default (``--levels``): the pressure levels ``predict --direction`` solves for the default load
range (0.1-4 N: pad-centre pressures 14.5, 26.8, 49.6 kPa), one normal-load ramp through them,
then per level the shear ramp to mu = 1.5 with the stability index: seconds per ramp, the
shear level reached and why the ramp stopped, and the worst case (the issue's figure).

``--pressure P``: the detailed single-level view -- mesh size, normal ramp, the shear ramp with and
without the stability eigenvalue, Newton iterations and time per iteration, then
``directional_gain`` cold and from the cache.

    python benchmarks/bench_deflection.py [--resolution 6] [--fillet 0.1] [--pressure 3kPa]
"""

from __future__ import annotations

import argparse
import tempfile
import time

import numpy as np

from fingerpad.materials import Materials
from fingerpad.micro.deflection import DeflectionSettings, EllipsoidGeometry, directional_gain, section_for
from fingerpad.micro.deflection.gain import SectionMaterials
from fingerpad.micro.deflection.mesh import SectionGeometry, build_mesh
from fingerpad.micro.deflection.path import follow_load, follow_shear
from fingerpad.micro.deflection.solve import FrictionLaw, SectionSolver
from fingerpad.units import parse_positive

#: pad-centre pressures 1.5 F / A_fr of the default finger at 0.1 N and 4 N, Pa (what
#: ``predict --direction`` passes to ``directional_gain`` for the default loads)
DEFAULT_RANGE = (14514.7, 49639.7)

MATS = Materials(skin_modulus=0.3e6, skin_poisson=0.49, material_modulus=0.3e6, material_poisson=0.49)
GEO = EllipsoidGeometry(45e-6, 135e-6, 90e-6, 300e-6, 300e-6)


def _setup(resolution: int, fillet: float | None, settings: DeflectionSettings):
    sec = section_for(GEO, 0.0)
    sm = SectionMaterials.from_materials(MATS)
    r, em = sec.half_width, 0.3e6  # texture modulus: the solver's stress unit
    kw = {} if fillet is None else {"fillet": fillet}
    mesh = build_mesh(SectionGeometry(sec.profile, sec.height / r, sec.period / r, sec.period / r, **kw), resolution)
    solver = SectionSolver(mesh, 0.49, sm.skin_plane_modulus / em, FrictionLaw("package", 8.1e3 / em, 0.1),
                           fold_penalty=settings.fold_penalty)
    return sec, r, em, mesh, solver


def levels(resolution: int, fillet: float | None) -> None:
    settings = DeflectionSettings(resolution=resolution)
    sec, r, em, mesh, solver = _setup(resolution, fillet, settings)
    pressures = np.geomspace(*DEFAULT_RANGE, settings.n_pressures)
    print(f"slender section h/r = {sec.height / r:.3g}, period {sec.period / r:.3g} r; mesh {mesh.elements.shape[0]} Q2 "
          f"elements, {mesh.n_nodes} nodes; fillet {mesh.geometry.fillet if hasattr(mesh.geometry, 'fillet') else 0} r")
    t0 = time.perf_counter()
    ramp0 = follow_load(solver, pressures * sec.load_per_pressure / (em * r))
    print(f"normal-load ramp through {pressures.size} levels: {time.perf_counter() - t0:.2f} s"
          f"{'' if ramp0.stopped is None else ' -- stopped: ' + ramp0.stopped}")
    worst = 0.0
    for p, start in zip(pressures, ramp0.states):
        t1 = time.perf_counter()
        ramp = follow_shear(solver, start, settings.mu_max, check_stability=settings.check_stability,
                            time_limit=settings.time_limit)
        dt = time.perf_counter() - t1
        worst = max(worst, dt)
        st = ramp.states
        mu = np.array([s.shear for s in st])
        gain = st[-1].info["contact_length"] / st[0].info["contact_length"]
        eig = [s.info.get("min_eigenvalue", np.nan) for s in st]
        print(f"  p = {p / 1e3:5.1f} kPa: {dt:6.1f} s, {len(st) - 1:3d} steps, {ramp.cuts:2d} cuts, "
              f"mu reached {max(0.0, mu.max()):.3g} (last {mu[-1]:+.3g}), gain at the end {gain:.3f}, buckled under the normal load: {eig[0] < 0}, stability index min {np.nanmin(eig):+.0f}"
              f"{' (reached mu_max)' if ramp.stopped is None else ' -- stopped: ' + ramp.stopped}")
    print(f"worst case: {worst:.1f} s per ramp (target: under 60 s)")


def single(resolution: int, fillet: float | None, p: float) -> None:
    settings = DeflectionSettings(resolution=resolution)
    sec, r, em, mesh, _ = _setup(resolution, fillet, settings)
    print(f"section: half-width {r * 1e6:.3g} um, height {sec.height * 1e6:.3g} um, period {sec.period * 1e6:.3g} um;"
          f" mesh {mesh.elements.shape[0]} Q2 elements, {mesh.n_nodes} nodes, {mesh.surface.size} contact candidates")
    for check in (False, True):
        solver = _setup(resolution, fillet, settings)[-1]
        t0 = time.perf_counter()
        start = follow_load(solver, [p * sec.load_per_pressure / (em * r)]).states[-1]
        t1 = time.perf_counter()
        ramp = follow_shear(solver, start, 1.5, check_stability=check, time_limit=settings.time_limit)
        t2 = time.perf_counter()
        its = sum(s.iterations for s in ramp.states[1:])
        print(f"stability check {'on ' if check else 'off'}: normal ramp {t1 - t0:6.2f} s, shear ramp {t2 - t1:6.2f} s "
              f"({len(ramp.states) - 1} steps, {ramp.cuts} cut, {its} Newton iterations, "
              f"{1e3 * (t2 - t1) / max(its, 1):.0f} ms/iteration), reached mu = {abs(ramp.states[-1].shear):.3g}"
              f"{'' if ramp.stopped is None else ' -- stopped: ' + ramp.stopped}")
    with tempfile.TemporaryDirectory() as folder:
        settings = DeflectionSettings(n_pressures=1, resolution=resolution)
        t0 = time.perf_counter()
        directional_gain(GEO, MATS, 0.0, (p, p), tau0=8.1e3, alpha=0.1, settings=settings, cache=folder)
        t1 = time.perf_counter()
        directional_gain(GEO, MATS, 0.0, (p, p), tau0=8.1e3, alpha=0.1, settings=settings, cache=folder)
        t2 = time.perf_counter()
    print(f"directional_gain, one direction, one pressure level: cold {t1 - t0:.2f} s, cached {1e3 * (t2 - t1):.1f} ms "
          f"(speed-up {(t1 - t0) / (t2 - t1):.0f}x)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--resolution", type=int, default=6)
    ap.add_argument("--fillet", type=float, default=None, help="foot fillet radius, units of the half-width r")
    ap.add_argument("--pressure", default=None, help="one pressure level in detail instead of the default levels")
    args = ap.parse_args()
    if args.pressure is None:
        levels(args.resolution, args.fillet)
    else:
        single(args.resolution, args.fillet, parse_positive(args.pressure, "pressure", name="--pressure"))


if __name__ == "__main__":
    main()
