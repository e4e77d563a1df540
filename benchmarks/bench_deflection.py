"""Benchmark of the deflection section model (issue 13: one direction's shear ramp of one
section in under a minute on the 2-core machine; cached repeats instant).

Prints, for the perpendicular section of a slender compliant ellipsoid (a x b x h = 45 x 135 x
90 um on a 300 um lattice; E_texture = E_skin = 0.3 MPa, nu 0.49, the package friction law) at one
nominal pressure (default 2 kPa): the mesh size, the time of the normal-load ramp and of the
shear ramp to mu = 1.5 (with and without the stability eigenvalue), Newton iterations, the time
per iteration, then the time of ``directional_gain`` cold and from the cache, measured in the
same run.

    python benchmarks/bench_deflection.py [--resolution 6] [--pressure 3kPa]
"""

from __future__ import annotations

import argparse
import tempfile
import time

from fingerpad.materials import Materials
from fingerpad.micro.deflection import DeflectionSettings, EllipsoidGeometry, directional_gain, section_for
from fingerpad.micro.deflection.gain import SectionMaterials
from fingerpad.micro.deflection.mesh import SectionGeometry, build_mesh
from fingerpad.micro.deflection.path import follow_load, follow_shear
from fingerpad.micro.deflection.solve import FrictionLaw, SectionSolver
from fingerpad.units import parse_positive


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--resolution", type=int, default=6)
    ap.add_argument("--pressure", default="2kPa")
    args = ap.parse_args()
    p = parse_positive(args.pressure, "pressure", name="--pressure")
    mats = Materials(skin_modulus=0.3e6, skin_poisson=0.49, material_modulus=0.3e6, material_poisson=0.49)
    geo = EllipsoidGeometry(45e-6, 135e-6, 90e-6, 300e-6, 300e-6)
    sec = section_for(geo, 0.0)
    sm = SectionMaterials.from_materials(mats)
    r, em = sec.half_width, 0.3e6  # texture modulus: the solver's stress unit
    mesh = build_mesh(SectionGeometry(sec.profile, sec.height / r, sec.period / r, sec.period / r), args.resolution)
    print(f"section: half-width {r * 1e6:.3g} um, height {sec.height * 1e6:.3g} um, period {sec.period * 1e6:.3g} um;"
          f" mesh {mesh.elements.shape[0]} Q2 elements, {mesh.n_nodes} nodes, {mesh.surface.size} contact candidates")
    for check in (False, True):
        solver = SectionSolver(mesh, 0.49, sm.skin_plane_modulus / em, FrictionLaw("package", 8.1e3 / em, 0.1),
                               fold_penalty=20.0)
        t0 = time.perf_counter()
        start = follow_load(solver, [p * sec.load_per_pressure / (em * r)]).states[-1]
        t1 = time.perf_counter()
        ramp = follow_shear(solver, start, 1.5, check_stability=check)
        t2 = time.perf_counter()
        its = sum(s.iterations for s in ramp.states[1:])
        print(f"stability check {'on ' if check else 'off'}: normal ramp {t1 - t0:6.2f} s, shear ramp {t2 - t1:6.2f} s "
              f"({len(ramp.states) - 1} steps, {ramp.cuts} cut, {its} Newton iterations, "
              f"{1e3 * (t2 - t1) / max(its, 1):.0f} ms/iteration), reached mu = {abs(ramp.states[-1].shear):.3g}"
              f"{'' if ramp.stopped is None else ' -- stopped: ' + ramp.stopped}")
    with tempfile.TemporaryDirectory() as folder:
        settings = DeflectionSettings(n_pressures=1, resolution=args.resolution)
        t0 = time.perf_counter()
        directional_gain(geo, mats, 0.0, (p, p), tau0=8.1e3, alpha=0.1, settings=settings, cache=folder)
        t1 = time.perf_counter()
        directional_gain(geo, mats, 0.0, (p, p), tau0=8.1e3, alpha=0.1, settings=settings, cache=folder)
        t2 = time.perf_counter()
    print(f"directional_gain, one direction, one pressure level: cold {t1 - t0:.2f} s, cached {1e3 * (t2 - t1):.1f} ms "
          f"(speed-up {(t1 - t0) / (t2 - t1):.0f}x)")


if __name__ == "__main__":
    main()
