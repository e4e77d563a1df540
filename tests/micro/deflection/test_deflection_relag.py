"""The rescue of a shear ramp whose step fails for a jump of the lagged friction tiles, not for
its length (issue 31): :func:`relag` re-converges the last state at its own tip under its own
tiles, and the step then starts from there (the slow test in test_deflection_highshear.py is
the ramp that needed it: it stopped at mu 1.46 of 1.5 without)."""

from __future__ import annotations

import numpy as np

from fingerpad.micro.deflection.mesh import SectionGeometry, build_mesh
from fingerpad.micro.deflection.path import follow_load, follow_shear, relag
from fingerpad.micro.deflection.solve import FrictionLaw, SectionSolver


def _merit(solver, state, lag):
    """Natural residual of ``state`` under the friction tiles of ``lag``, relative to the load."""
    a0, b0 = solver._friction_coefficients(state.load, 1.0, lag)
    tip_dof = int(solver.red[2 * solver.mesh.apex])
    return solver._trial_merit(state.v, state.f, state.z0, state.shear, state.load, a0, b0,
                               state.info["pairs"], state.info["tip_dx"], tip_dof) / state.load


def test_relag_reconverges_the_last_state_under_its_own_tiles():
    mesh = build_mesh(SectionGeometry("ellipse", 2.0, 5.0, 2.0), resolution=3)
    solver = SectionSolver(mesh, 0.49, 1.33, FrictionLaw("package", tau0=0.3, alpha=0.1))
    start = follow_load(solver, [0.2]).states[-1]
    ramp = follow_shear(solver, start, 0.6, check_stability=False, max_steps=8)
    assert ramp.stopped is None or "too many" in ramp.stopped
    # a pair of steps over which the contact tiles changed: the last state is converged under
    # the previous state's tiles, not under its own
    k = max(range(2, len(ramp.states)), key=lambda i: np.abs(
        np.where(ramp.states[i].contact_mask, ramp.states[i].tiles, 0.0)
        - np.where(ramp.states[i - 1].contact_mask, ramp.states[i - 1].tiles, 0.0)).sum())
    prev, last = ramp.states[k - 1], ramp.states[k]
    assert _merit(solver, last, prev) < 1e-7
    assert _merit(solver, last, last) > 1e-5
    out = relag(solver, prev, last)
    assert out is not None
    # the same tip, now in equilibrium under the last state's own tiles
    assert abs(out.info["tip_dx"] - last.info["tip_dx"]) < 1e-8
    assert _merit(solver, out, last) < 1e-7
    # ... and it is that problem's solution: the direct solve (where it converges) agrees
    direct = solver.solve(last.load, last.shear, last.copy(), lag=last, tip=last.info["tip_dx"])
    assert abs(direct.shear - out.shear) < 1e-7
    np.testing.assert_allclose(direct.v, out.v, atol=1e-7)
