"""The adhesive fixed point and the directional unit cell.

The shear level an asperity feels is the friction it transmits, which depends on the contact
area the deflection gain enlarges. At nominal pressure p with the undeflected real-area fraction
psi(p) (the unit cell's, BEM or Hertz) the local adhesive friction, Eqs. 2.2-2.3 with
``tau = tau0 + alpha p / (psi G)``, is ``q = tau0 psi G + alpha p``, so the local shear level
solves::

    mu = tau0 psi(p) G(p, mu) / p + alpha + mu_extra                                  (*)

(``mu_extra``: an optional extra shear carried by the interface, e.g. the hysteresis share
F_def / F). :func:`solve_local_shear` finds the least root of (*) by the monotone iteration
from ``G = 1`` (the state reached when the friction builds up from zero; G is taken
non-decreasing in mu along the followed branch), and :class:`DirectionalCell` wraps any unit
cell so that its ``contact_fraction(p)`` is ``min(psi G, psi_max)``: the coupling's integrals
(Eq. 3.7 and [completion]) then give the directional ``A_re`` and ``F_adh = tau0 A_re + alpha F``
unchanged. In code::

    gain = directional_gain(texture_geometry(texture), materials, direction_deg=90.0,
                            pressure_range=(p_lo, p_hi), tau0=finger.tau0, alpha=finger.alpha)
    cell_dir = DirectionalCell(cell, gain, tau0=finger.tau0, alpha=finger.alpha)
    prediction = predict_curve(loads, finger, cell_dir)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .gain import GainCurve


@dataclass(frozen=True)
class LocalShear:
    """Solution of the local fixed point (*) at each nominal pressure (arrays).

    ``mu``: local shear level; ``gain``: G(p, mu); ``converged``: the iteration settled;
    ``saturated``: mu lies beyond the shear computed for the gain table (gain held).
    """

    mu: np.ndarray
    gain: np.ndarray
    converged: np.ndarray
    saturated: np.ndarray


def solve_local_shear(
    pressure: Any, psi: Any, gain: GainCurve, tau0: float, alpha: float, mu_extra: Any = 0.0,
    tol: float = 1e-10, max_iter: int = 200,
) -> LocalShear:
    """Solve ``mu = tau0 psi G(p, mu) / p + alpha + mu_extra`` (the docstring's (*)) at every p.

    Monotone fixed-point iteration from ``G = 1``: with G non-decreasing in mu it climbs to the
    least root, the state reached as friction builds up from zero. Where ``p = 0`` (or psi = 0)
    the adhesive term vanishes and ``mu = alpha + mu_extra``, ``G = 1``.
    """
    p, ps, mx = np.broadcast_arrays(np.asarray(pressure, dtype=float), np.asarray(psi, dtype=float),
                                    np.asarray(mu_extra, dtype=float))
    with np.errstate(divide="ignore", invalid="ignore"):
        coef = np.where(p > 0, tau0 * ps / np.where(p > 0, p, 1.0), 0.0)
    g = np.ones(p.shape)
    mu = coef * g + alpha + mx
    conv = np.zeros(p.shape, dtype=bool)
    for _ in range(max_iter):
        g_new = np.where(p > 0, gain(p, mu), 1.0)
        mu_new = coef * g_new + alpha + mx
        conv = np.abs(mu_new - mu) <= tol * np.maximum(1.0, np.abs(mu_new))
        mu, g = mu_new, g_new
        if np.all(conv):
            break
    g = np.where(p > 0, gain(p, mu), 1.0)
    return LocalShear(mu, g, conv, gain.saturated(p, mu) & (p > 0))


class DirectionalCell:
    """A unit cell whose real-area fraction includes the deflection gain at the local shear.

    ``contact_fraction(p) = min(psi(p) G(p, mu(p)), psi_max)`` with mu(p) from
    :func:`solve_local_shear`; every other attribute (transition and full-contact pressures,
    breakpoints, ...) is the wrapped cell's. With an identity gain it returns the wrapped
    cell's psi exactly.

    Parameters
    ----------
    cell
        Any unit-cell response (BEM or Hertz): ``contact_fraction(p) -> psi``.
    gain
        :class:`GainCurve` of the texture, material and direction.
    tau0, alpha
        The finger's Eq. 2.3 constants.
    mu_extra
        Extra shear level carried by the interface (e.g. the hysteresis share), default 0.
    max_fraction
        Upper bound of the real-area fraction (default: the cell's psi at its full-contact
        pressure, else 1).
    """

    def __init__(self, cell: Any, gain: GainCurve, tau0: float, alpha: float, mu_extra: float = 0.0,
                 max_fraction: float | None = None) -> None:
        self._cell = cell
        self.gain = gain
        self.tau0 = float(tau0)
        self.alpha = float(alpha)
        self.mu_extra = float(mu_extra)
        if max_fraction is None:
            try:
                pf = float(cell.full_contact_pressure)
                max_fraction = float(np.asarray(cell.contact_fraction(np.array([pf])))[0]) if math.isfinite(pf) else 1.0
            except Exception:  # noqa: BLE001 -- a cell without a finite full-contact pressure
                max_fraction = 1.0
        self.max_fraction = float(max_fraction)

    #: What the wrapped cell computes from its own psi(p), which this cell's psi replaces: not
    #: passed on. ``disc_fraction`` is the exact disc average of a BEM cell's interpolated psi;
    #: passed on, the coupling integrated the undeflected psi and the gain never entered
    #: (issue 31: ``predict --direction`` gave equal real areas across and along, the friction
    #: ratio 1.02-1.07 being the hysteresis factor alone). The coupling integrates this cell's
    #: psi itself (graded quadrature split at the state pressures).
    NOT_PASSED_ON = frozenset({"disc_fraction", "at_modulus", "for_skin", "interpolation_error", "curve", "points"})

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_") or (name in DirectionalCell.NOT_PASSED_ON and not self.gain.is_identity):
            # (an identity gain keeps the wrapped cell's psi exactly, and so its exact integrals)
            raise AttributeError(f"DirectionalCell has no {name!r} (the wrapped cell's would ignore the gain)")
        return getattr(self._cell, name)

    def local_shear(self, p: np.ndarray) -> LocalShear:
        psi = np.asarray(self._cell.contact_fraction(np.asarray(p, dtype=float)), dtype=float)
        return solve_local_shear(p, psi, self.gain, self.tau0, self.alpha, self.mu_extra)

    def contact_fraction(self, p: np.ndarray) -> np.ndarray:
        pp = np.asarray(p, dtype=float)
        psi = np.asarray(self._cell.contact_fraction(pp), dtype=float)
        if self.gain.is_identity:
            return psi
        sol = solve_local_shear(pp, psi, self.gain, self.tau0, self.alpha, self.mu_extra)
        return np.minimum(psi * sol.gain, np.maximum(self.max_fraction, psi))


#: A bound of the deflection gain for the shear a coupling needs (:func:`needed_shear`): the
#: largest gains computed are 2.4-2.6 (h = 3a ellipsoids across, buckled at 6.3 kPa,
#: docs/deflection.md); a gain beyond the bound leaves the fixed point past the ramps' reach,
#: which the outputs then mark as held.
GAIN_BOUND = 3.0
#: The shear a coupling needs is rounded up to a multiple of this (so that inputs a little apart
#: give the same target, hence the same ramps).
SHEAR_STEP = 0.05


def needed_shear(pressure: Any, psi: Any, tau0: float, alpha: float, mu_extra: float = 0.0,
                 gain_bound: float = GAIN_BOUND, step: float = SHEAR_STEP) -> float:
    """The shear level the ramps of a coupling must reach: the largest right-hand side of (*)
    over the nominal pressures ``pressure`` (Pa; psi the cell's there) with the gain at
    ``gain_bound``, ``max tau0 psi G_max / p + alpha + mu_extra``, rounded up to a multiple of
    ``step`` and kept in [step, 5]. Every fixed point at those pressures lies below it (for
    gains up to the bound), so ramps that reach it hold no gain there; a ramp to 1.5 for a
    fixed point of 0.2 is three times the work (issue 31)."""
    p = np.asarray(pressure, dtype=float).ravel()
    ps = np.asarray(psi, dtype=float).ravel()
    ok = (p > 0) & np.isfinite(p) & np.isfinite(ps)
    top = float(np.max(tau0 * ps[ok] / p[ok])) if np.any(ok) else 0.0
    need = top * float(gain_bound) + float(alpha) + float(mu_extra)
    return float(min(5.0, max(step, step * math.ceil(need / step - 1e-9))))


__all__ = ["GAIN_BOUND", "DirectionalCell", "LocalShear", "needed_shear", "solve_local_shear"]
