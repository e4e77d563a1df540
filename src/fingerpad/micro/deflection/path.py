"""Path following of the section: the normal-load ramp at zero shear and the shear ramp under
tip-displacement control (see :mod:`.solve` for one Newton solve)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .contact import skin_compliance
from .solve import NoConvergence, SectionSolver, State



@dataclass
class Ramp:
    """Converged states along a path and how the path ended."""

    states: list[State]
    stopped: str | None = None  # why the path ended early (None: reached the target)
    cuts: int = 0
    #: ended by the wall-clock safety stop: depends on the machine's speed, never a result
    timed_out: bool = False


def follow_load(solver: SectionSolver, targets: np.ndarray, first: float | None = None,
                growth: float = 1.6, max_steps: int = 400, max_cuts: int = 12) -> Ramp:
    """Press the skin on at zero shear, through the increasing normal loads ``targets``.

    Load steps grow geometrically (factor ``growth``) from ``first`` and are halved when a step
    fails; every target is hit exactly. Returns the states at the targets.
    """
    targets = np.sort(np.asarray(targets, dtype=float))
    state = solver.initial_state()
    p = 0.0
    step = first if first is not None else targets[0] / 20.0
    out: list[State] = []
    cuts = 0
    ti = 0
    for _ in range(max_steps):
        trial_p = min(targets[ti], p + step) if p > 0 else min(targets[ti], step)
        guess = state.copy()
        if p == 0.0:  # first contact: lower the skin onto the tip
            guess.f[:] = 0.0
            apex = int(np.nonzero(solver.surface == solver.mesh.apex)[0][0])
            guess.f[apex] = trial_p
            xs = solver.positions(guess.v)[solver.surface]
            tiles = solver._tiles(xs)
            c = skin_compliance(xs[:, 0], tiles, solver.period, solver.skin)
            guess.z0 = float(xs[apex, 1] - c[apex, apex] * trial_p)
        try:
            state = solver.solve(trial_p, 0.0, guess)
        except NoConvergence:
            cuts += 1
            step *= 0.5
            if step < 1e-6 * targets[-1] or cuts > max_cuts:
                return Ramp(out, f"normal load stalled at {p:.4g} (step {step:.2g})", cuts)
            continue
        p = trial_p
        if math.isclose(p, targets[ti], rel_tol=1e-12):
            out.append(state)
            ti += 1
            if ti == targets.size:
                return Ramp(out, None, cuts)
        step = p * (growth - 1.0) if state.iterations <= 8 else step
    return Ramp(out, "too many normal-load steps", cuts)


def follow_shear(solver: SectionSolver, start: State, mu_max: float, dmu: float = 0.08,
                 largest_tip: float = 0.08, smallest_tip: float = 1e-4, tip_max: float | None = None,
                 check_stability: bool = True, max_steps: int = 300, max_cuts: int = 12,
                 time_limit: float | None = None) -> Ramp:
    """Shear the pressed section in full sliding, at constant normal load, until the shear level
    reaches ``mu_max`` (negative: sliding toward -x).

    Path following is by control of the tip's horizontal displacement (the shear level is then
    an unknown), so a maximum of the shear level -- where a load-controlled asperity would snap
    over -- is passed and reported rather than stalling the solve. Tip steps aim at shear
    increments ``dmu`` using the current slope, capped at ``largest_tip`` (units of r) and halved
    on failure; below ``smallest_tip``, after ``max_cuts`` failed steps in all or ``max_steps``
    steps (deterministic limits: the same on every machine) the ramp stops and says where --
    after one rescue per state (:func:`relag`: the last state re-converged under its own
    friction tiles, the steps retried from there with ``max_cuts`` more).
    ``time_limit`` (s, default off) is a user's safety stop only: a ramp it cuts is marked
    ``timed_out`` (its end depends on the machine's speed, so it is no result).

    Returns
    -------
    Ramp
        All converged states in path order (the first is ``start``).
    """
    import time

    t_start = time.perf_counter()
    load = start.load
    sign = 1.0 if mu_max >= 0 else -1.0
    target = abs(mu_max)
    tip_limit = tip_max if tip_max is not None else 2.0 * (solver.mesh.geometry.height + 1.0)
    if check_stability:
        start.info["min_eigenvalue"] = solver.min_eigenvalue(start)
    states = [start]
    cuts = 0
    # first step under load control gives the initial compliance d(tip)/d(mu)
    mu1 = min(target, 0.25 * dmu)
    first = None
    while True:
        try:
            first = solver.solve(load, sign * mu1, start.copy(), lag=start)
            break
        except NoConvergence:
            cuts += 1
            mu1 *= 0.5
            if mu1 < 1e-4:
                first = None
                break
    unstable = check_stability and start.info["min_eigenvalue"] < 0
    if first is not None and sign * first.info["tip_dx"] > 0 and not unstable:
        if check_stability:
            first.info["min_eigenvalue"] = solver.min_eigenvalue(first)
        states.append(first)
    else:
        # The pressed state is unstable (buckled under the normal load alone: the column would
        # fall over sideways without friction) or a small shear moved the tip against itself
        # (negative stiffness on that symmetric branch). Under load control the asperity snaps at
        # zero shear onto the branch folded toward the sliding direction; follow that branch by
        # prescribing the tip's displacement toward the sliding direction from the start: the
        # path's shear level then first falls below zero and comes back (reported as a limit
        # point at mu = 0), and a load-controlled ramp joins it where the shear exceeds zero.
        tip0 = largest_tip
        while True:
            try:
                first = solver.solve(load, 0.0, start.copy(), lag=start, tip=sign * tip0)
                break
            except NoConvergence as exc:
                cuts += 1
                tip0 *= 0.5
                if tip0 < smallest_tip:
                    return Ramp(states, f"lost convergence at mu = 0 ({exc})", cuts)
        if check_stability:
            first.info["min_eigenvalue"] = solver.min_eigenvalue(first)
        states.append(first)
    step = None
    allowed_cuts = max_cuts  # raised by each rescue (see relag), at most once per state
    for _ in range(max_steps):
        last = states[-1]
        mu_now = sign * last.shear  # along the sliding direction (negative past a buckled start)
        if mu_now >= target - 1e-9:
            return Ramp(states, None, cuts)
        tip_now = sign * last.info["tip_dx"]
        if time_limit is not None and time.perf_counter() - t_start > time_limit:
            return Ramp(states, f"INCOMPLETE: wall-clock time limit ({time_limit:.3g} s) hit at mu = {mu_now:.3g} "
                                f"(machine-dependent; not a result, not cached)", cuts, timed_out=True)
        # the guard is on the bending deflection (the tip relative to the asperity's base centre):
        # once folded flat, further shear is carried by the base layer, whose uniform shear
        # moves the tip on without bending the asperity any further
        if sign * last.info["deflection_dx"] > tip_limit:
            return Ramp(states, f"tip deflection limit reached at mu = {mu_now:.3g}", cuts)
        prev = states[-2]
        dtip = tip_now - sign * prev.info["tip_dx"]
        slope = (mu_now - sign * prev.shear) / dtip if dtip > 0 else 0.0  # d mu / d tip
        if step is None:
            step = largest_tip
        wanted = dmu / slope if slope > 1e-9 else largest_tip
        remaining = (target - mu_now) / slope if slope > 1e-9 else np.inf
        step = float(np.clip(min(wanted, 1.0001 * remaining, 2.0 * step), smallest_tip, largest_tip))
        # the steps start from `base`: the last state, or (after a rescue) the last state
        # re-converged under its own friction tiles (see relag)
        base, first_step = last, step
        while True:
            trial = tip_now + step
            a = step / dtip if dtip > 0 else 0.0
            guess = base.copy()
            guess.v = base.v + a * (last.v - prev.v)
            guess.z0 = base.z0 + a * (last.z0 - prev.z0)
            mu_guess = base.shear + a * (last.shear - prev.shear)
            try:
                state = solver.solve(load, mu_guess, guess, lag=last, tip=sign * trial)
                break
            except NoConvergence as exc:
                try:
                    state = solver.solve(load, base.shear, base.copy(), lag=last, tip=sign * trial)
                    break
                except NoConvergence:
                    cuts += 1
                    step *= 0.5
                    if step < smallest_tip or cuts > allowed_cuts:
                        # Before giving up: the trouble may not be the step at all but the jump
                        # of the lagged friction tiles (a node entering contact brings its whole
                        # tile into the tau0 part of the friction at once), which no step length
                        # makes smaller. Re-converge the last state at its own tip under the new
                        # tiles by continuation in them, and take the steps from there. Only here,
                        # where the ramp would stop, so ramps that got through are unchanged.
                        rescued = None if base is not last else relag(solver, prev, last)
                        if rescued is None:
                            return Ramp(states, f"lost convergence at mu = {mu_now:.3g} ({exc})", cuts)
                        base, step, allowed_cuts = rescued, first_step, cuts + max_cuts
        if check_stability:
            state.info["min_eigenvalue"] = solver.min_eigenvalue(state)
        states.append(state)
    return Ramp(states, "too many shear steps", cuts)


def relag(solver: SectionSolver, lag: State, last: State, smallest: float = 1.0 / 64.0) -> State | None:
    """``last`` (converged with the friction tiles of ``lag``) re-converged at its own tip under
    its own tiles, by continuation from the old tiles to the new ones; None if that fails.

    Why: the package law's friction traction uses the contact tiles of the previous converged
    state (:meth:`.solve.SectionSolver._friction_coefficients`). When a node with a long tile
    enters contact the tau0 share of the traction jumps onto it, so the next step's residual
    starts far off however short the step: on the slender ellipsoid section at 14.5 kPa (tip
    5.04 r, mu 1.46) a node of tile 0.70 r came in with a force of 0.0036 and the natural
    residual of ``last`` under the new tiles was 0.108 (1.8 % of the load; 1.3e-10 under the old
    ones), and every tip step, down to 1e-4 r, stagnated. The state returned here is only a start
    for the step (the path's states keep their one-step lag), so no answer depends on it.
    """
    load, tip = last.load, last.info["tip_dx"]
    old = np.where(lag.contact_mask, lag.tiles, 0.0)
    new = np.where(last.contact_mask, last.tiles, 0.0)
    s, ds, cur = 0.0, 0.5, last
    while s < 1.0:
        s_try = min(1.0, s + ds)
        mixed = last.copy()
        mixed.contact_mask = np.ones(new.size, dtype=bool)
        mixed.tiles = (1.0 - s_try) * old + s_try * new
        try:
            cur = solver.solve(load, cur.shear, cur.copy(), lag=mixed, tip=tip)
        except NoConvergence:
            ds *= 0.5
            if ds < smallest:
                return None
            continue
        s, ds = s_try, min(2.0 * ds, 1.0)
    return cur
