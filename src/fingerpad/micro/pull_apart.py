"""The skin pulled off an adhesive contact, step by step (docs/model.md 6.6): the pull-off
pressure of load control and the work of separation of a unit cell, from a converged adhesive
solution. Used by :class:`~fingerpad.micro.adhesive_cell.AdhesiveUnitCell` (its unloading
branch) and the cell job of ``fingerpad solve`` (its pull-off pressure). SI units, or the
solver's.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from ..contact import ContactResult, HalfSpaceSolver

__all__ = ["MAX_SEPARATION_SOLVES", "PULL_CHANGE", "SEPARATION_STEP", "pull_apart"]

#: Mean-gap steps of the pull-apart, in ranges.
SEPARATION_STEP = 0.25
#: Most solves of one pull-apart (the step doubles every 100 solves past 200).
MAX_SEPARATION_SOLVES = 600
#: A pull-apart step is halved where the mean pressure changes by more than this fraction of the
#: largest tension (:func:`pull_apart`).
PULL_CHANGE = 0.2


def pull_apart(solver: HalfSpaceSolver, start: ContactResult, step: float) -> dict[str, Any]:
    """The skin pulled off ``solver``'s texture from ``start`` (an adhesive solution): its mean gap
    raised (its approach lowered) step by step, each solve from the last, until no pixel touches
    and the tension has fallen below 1e-3 of the largest met.

    The step starts at 1/16 of ``step`` (m, the solver's units; a contact takes tension at almost
    no displacement) and doubles up to it; it is halved (down to 1/16 of it) where the tension
    drops by more than :data:`PULL_CHANGE` of the largest met between two solves, where contacts
    snap off, so that the work integral is resolved there. At most
    :data:`MAX_SEPARATION_SOLVES` solves; the step doubles every 100 solves past 200, and grows
    by half each solve once no pixel touches (the attraction's smooth tail).

    Returns ``pull_off`` (the least mean pressure, <= 0: the pull-off pressure of load control),
    ``work`` (the area under ``-p`` against the approach, trapezoids: the work of separation per
    unit area, snap-offs' losses included), the tensile branch up to the least pressure
    (``pressure``, ``contact_fraction``, ``mean_gap``, ``max_pressure``, ``contact_state``),
    ``let_go`` and ``solves``; in the solver's units."""

    def row(d: float, r: ContactResult) -> tuple:
        return (d, r.mean_pressure, r.contact_fraction, r.mean_gap, r.max_pressure, r.contact_state)

    d = start.approach
    res = start
    curve = [row(d, start)]
    least = 0.0
    h = step / 16.0  # the first pull: a contact holds tension at almost no displacement
    solves = 0
    while solves < MAX_SEPARATION_SOLVES:
        if solves >= 200 and solves % 100 == 0:
            step *= 2.0
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message="contact solve did not converge", category=RuntimeWarning)
            trial = solver.solve_approach(d - h, initial=res)
        solves += 1
        # a snap: the tension drops (contacts let go) by much in one step: resolve it from the
        # same start with half the step (while it grows, the tension changes smoothly)
        if trial.mean_pressure - res.mean_pressure > PULL_CHANGE * abs(least) > 0 and h > step / 16.0:
            h /= 2.0
            continue
        d, res = d - h, trial
        curve.append(row(d, res))
        least = min(least, res.mean_pressure)
        if res.contact_fraction == 0 and abs(res.mean_pressure) <= 1e-3 * abs(least):
            break
        # out of contact the attraction's tail decays smoothly: longer steps there
        h = 1.5 * h if res.contact_fraction == 0 else min(2.0 * h, step)
    ds = np.array([c[0] for c in curve])
    ps = np.array([c[1] for c in curve])
    fr = np.array([c[2] for c in curve])
    i = int(np.argmin(ps))
    # the work of separation: int -p d(approach) from the start to the let-go, trapezoids after
    # the first step, which takes its end's tension (the start's pressure is a contact's reaction,
    # not a point of the separation curve: a closed contact takes tension at no displacement)
    mids = 0.5 * (ps[1:] + ps[:-1])
    if mids.size:
        mids[0] = ps[1]
    work = float(np.sum(-mids * (ds[:-1] - ds[1:])))
    return {"pull_off": float(min(ps[i], 0.0)), "work": work, "pressure": ps[: i + 1].tolist(),
            "contact_fraction": fr[: i + 1].tolist(), "mean_gap": [c[3] for c in curve[: i + 1]],
            "max_pressure": [c[4] for c in curve[: i + 1]], "contact_state": [c[5] for c in curve[: i + 1]],
            "let_go": bool(fr[-1] == 0), "solves": solves}
