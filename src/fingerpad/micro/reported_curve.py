"""psi(p) of an adhesive cell with its jump at the reported transition (docs/model.md 6.6, "The
curve with the reported transition").

Where a cell reports a transition other than its grid's own (a pulled-in transition extrapolated
to a vanishing pixel, :func:`fingerpad.micro.pull_in.adopt_extrapolated`), its psi(p) must
jump there too, so that the zones, the critical load and ``A_re`` of one prediction agree. What
the grid gets wrong is where the jump comes, not the branch below it, which is grid-converged:
the own branch is kept below its jump, continued at its slope up to the reported transition, and
the part past the jump carried onto the reported pressures. Pressures here are unit pressures,
``p / E*``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from .unit_key import POINTS_PER_DECADE

__all__ = ["CONTINUATION_SPAN", "jump_shift", "shifted_fraction"]

#: The continued branch takes the own branch's mean slope ``d psi / d ln p`` from this factor
#: below its last node before its jump ``a`` up to the node spacing below ``a``: away from the
#: precursor of the grid's own (early) jump, where the branch steepens. On the default cell at
#: ``w`` 0.3 J/m^2 the branch's slope is 0.06-0.10 from 7 to 15 kPa and 0.13-0.33 over the last
#: 10 % before the own jump on grid 256 (the same on 64 and 128); over the last node spacing the
#: continuation ran 1.5 % above grid 512's own branch at 20 kPa (0.414 against 0.408), over
#: ``[a / 2, a / 1.21]`` it meets it (0.4076), and the continued grids 128 and 256 then agree in
#: A_re/A_fr at 0.3 N within 0.2 % instead of 1.9 % (docs/model.md 6.6, "The curve with the
#: reported transition").
CONTINUATION_SPAN = 2.0


def jump_shift(nodes: np.ndarray, own_fraction: Callable[[np.ndarray], np.ndarray], loading: dict[str, Any],
               reported: float, own: float, full: float) -> tuple[float, ...] | None:
    """Where psi's jump moves to: ``(a, b, fb, t, f, slope)`` (unit pressures), or ``None`` where
    there is nothing to move.

    ``nodes``: the loading branch's node pressures; ``own_fraction``: the grid's own psi at unit
    pressures; ``loading``: the branch's stored brackets (``transition``, ``full``: ``(low,
    high)``); ``reported``, ``own``: the reported and the grid's own transition; ``full``: the
    reported full contact (``inf`` without one). Returns the branch's last node below its own jump
    ``a`` and the first at or past it ``b``, the first node at or past its own full contact
    ``fb``, the reported transition ``t`` and full contact ``f`` (at least ``t``), and the
    branch's mean slope ``d psi / d ln p`` from ``a / CONTINUATION_SPAN`` to the node spacing
    below ``a`` (:data:`CONTINUATION_SPAN`; from the first positive node where that lies higher)."""
    t = reported
    lo, hi = loading["transition"]
    if lo <= 0 or t <= 0 or t == own:
        return None
    ps = nodes
    a = float(ps[ps <= lo].max())
    b = float(ps[ps >= hi].min()) if (ps >= hi).any() else float(ps[-1])
    own_full = loading.get("full")
    fb = float(ps[ps >= own_full[1]].min()) \
        if own_full is not None and own_full[1] is not None and (ps >= own_full[1]).any() else float(ps[-1])
    f = max(full, t)
    if not math.isfinite(f):  # no full contact on the branch: the part past the jump in proportion
        f, fb = t, b
    step = 10.0 ** (1.0 / POINTS_PER_DECADE)
    top = a / step
    low = max(a / CONTINUATION_SPAN, float(ps[ps > 0].min()) if (ps > 0).any() else top)
    if low >= top:  # too few nodes below the jump for the span: the last node spacing
        low, top = a / step, a
    below = own_fraction(np.array([low, top]))
    slope = max(float(below[1] - below[0]) / math.log(top / low), 0.0)
    return a, b, max(fb, b), t, f, slope


def shifted_fraction(q: np.ndarray, shift: tuple[float, ...],
                     own_fraction: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """psi at unit pressures ``q`` with its jump at the reported transition: the own branch below
    its last node ``a`` before its jump; from there to the reported transition ``t`` the branch
    continued at its slope over the node spacing below ``a`` (linearly in ln p, at most the value
    past the jump); from ``t`` the part past the own jump, ``[t, f]`` carried onto ``[b, fb]``
    linearly in ln p and in proportion above ``f`` (``shift`` from :func:`jump_shift`)."""
    a, b, fb, t, f, slope = shift
    q = np.asarray(q, dtype=float)
    out = own_fraction(np.minimum(q, a))
    cont = (q > a) & (q < t)
    if cont.any():
        after = float(own_fraction(np.array([b]))[0])
        out[cont] = np.minimum(out[cont] + slope * np.log(q[cont] / a), after)
    past = q >= t
    if past.any():
        own = np.where(q[past] > f, q[past] * (fb / f), b)
        if f > t:
            inside = q[past] <= f
            frac = np.log(np.maximum(q[past], t) / t) / math.log(f / t)
            own = np.where(inside, b * (fb / b) ** frac, own)
        out[past] = own_fraction(own)
    return out
