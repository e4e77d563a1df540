"""High shear on slender sections: rounded feet (mesh) and ramps that start from a buckled state."""

from __future__ import annotations

import numpy as np
import pytest

from fingerpad.micro.deflection.gain import DeflectionSettings, SectionMaterials, solve_section
from fingerpad.micro.deflection.mesh import SectionGeometry, build_mesh
from fingerpad.micro.deflection.path import follow_load, follow_shear
from fingerpad.micro.deflection.section import EllipsoidGeometry, section_for
from fingerpad.micro.deflection.solve import FrictionLaw, SectionSolver


def _area(mesh) -> float:
    """Area of the meshed section from the element corner polygons (shoelace over Q2 edges
    split at the mid-side nodes)."""
    total = 0.0
    for e in mesh.elements:
        ring = mesh.nodes[e[[0, 1, 2, 5, 8, 7, 6, 3]]]
        x, z = ring[:, 0], ring[:, 1]
        total += 0.5 * float(np.dot(x, np.roll(z, -1)) - np.dot(z, np.roll(x, -1)))
    return total


@pytest.mark.parametrize("rho", [0.1, 0.2])
def test_fillet_rounds_the_feet_tangentially(rho):
    sharp = build_mesh(SectionGeometry("ellipse", 2.0, 6.0, 3.0), resolution=4)
    mesh = build_mesh(SectionGeometry("ellipse", 2.0, 6.0, 3.0, fillet=rho), resolution=4)
    surf = mesh.nodes[mesh.surface]
    # the surface near the left foot lies on the arc of radius rho centred at (-1 - rho, rho)
    centre = np.array([-1.0 - rho, rho])
    dist = np.linalg.norm(surf - centre, axis=1)
    near = (surf[:, 0] > -1.0 - rho + 1e-9) & (surf[:, 0] < -1.0 + 1e-9) & (surf[:, 1] < rho - 1e-9)
    assert np.count_nonzero(near) >= 3
    np.testing.assert_allclose(dist[near], rho, rtol=0.05)  # the flank leans slightly
    # mirror symmetric; the surface turns by less than 40 deg per node interval at the foot,
    # where the sharp mesh turns by 90 deg; material is added, not removed
    np.testing.assert_allclose(np.sort(surf[:, 0]), np.sort(-surf[:, 0]), atol=1e-9)
    for m, largest in ((sharp, 89.0), (mesh, 40.0)):
        seg = np.diff(m.nodes[m.surface], axis=0)
        ang = np.degrees(np.abs(np.diff(np.unwrap(np.arctan2(seg[:, 1], seg[:, 0])))))
        foot = int(np.nonzero(m.on_asperity)[0][0])
        turn = ang[foot - 3:foot + 2].max()
        assert (turn > largest) if m is sharp else (turn < largest)
    assert 0 < _area(mesh) - _area(sharp) < 2 * rho**2


@pytest.mark.slow  # ~26 s of ramps (make test-slow)
def test_a_buckled_start_folds_toward_the_sliding_direction():
    """A slender column pressed until it is unstable at zero shear (buckled without friction):
    the shear ramp follows the branch folded toward the sliding direction -- the tip moves that
    way from the first step -- and the shear level first falls below zero (a limit point at
    mu = 0 under load control) before it carries shear again."""
    mesh = build_mesh(SectionGeometry("ellipse", 3.0, 4.0, 4.0), resolution=3)
    solver = SectionSolver(mesh, 0.49, 1.33, FrictionLaw("coulomb"), fold_penalty=20.0)
    start = follow_load(solver, [0.3]).states[-1]
    for sign in (1.0, -1.0):
        ramp = follow_shear(solver, start, sign * 0.3, check_stability=True, max_steps=60)
        assert start.info["min_eigenvalue"] < 0
        tips = np.array([sign * s.info["tip_dx"] for s in ramp.states])
        mus = np.array([sign * s.shear for s in ramp.states])
        assert np.all(np.diff(tips) > 0)
        assert mus[1] < 0  # the buckled column pushes on: negative shear holds it
        assert ramp.stopped is None and mus[-1] >= 0.3 - 1e-9


@pytest.mark.slow
def test_slender_ellipsoid_section_reaches_high_shear_at_the_lowest_default_pressure():
    """The issue's slender case (45 x 135 x 90 um ellipsoids, 300 um lattice, E 0.3 MPa both,
    nu 0.49, short-axis section) at the lowest pressure level of predict's default load range
    (14.5 kPa): the ramp reaches mu 1.5 with more contact than at zero shear (it stalled at
    mu 1.43 before the path followed the shear level with its sign)."""
    mats = SectionMaterials(0.3e6, 0.49, 0.3e6, 0.49)
    sec = section_for(EllipsoidGeometry(45e-6, 135e-6, 90e-6, 300e-6, 300e-6), 0.0)
    # no time limit: the ramp's end must not depend on the machine's speed (max_steps bounds it)
    (ramp,) = solve_section(sec, mats, np.array([14514.7]), tau0=8.1e3, alpha=0.1,
                            settings=DeflectionSettings())
    assert ramp.stopped is None and ramp.mu_reached >= 1.5 - 1e-9
    mu, gain = ramp.branch()
    assert mu[0] == 0.0 and np.all(np.diff(mu) > 0)
    assert np.interp(1.0, mu, gain) > 1.1
