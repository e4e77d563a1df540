"""Many fingers on one unit cell at once: the vectorised twin of
:func:`~fingerpad.coupling.predict_curve` (issue 22, "a population must not cost a population of
BEM solves").

:func:`predict_members` gives, for each finger, the :class:`~.curve.CurvePrediction` that
:func:`~.curve.predict_curve` gives for that finger on ``cell.at_modulus(E1*)`` (the one unit
cell read at the member's modulus by p/E* scaling), to the bit: the same pad pressures
(Eq. 3.7), the same exact integral of the cell's interpolated psi (Eq. 3.11,
:func:`~.curve.disc_ratio`: the antiderivative tabulated at the cell's nodes, one Gauss-Legendre
piece per member and load, each entry computed on its own), the same friction (Eqs. 2.1-2.4)
and the same root finder for the critical load, with each finger's area law built once
(:meth:`~fingerpad.finger.Finger.ridge_area_law`). The members go through in blocks
(:data:`BLOCK`), one call of the cell's integral per block. An equation changed in
:mod:`.curve` is changed here too (``tests/coupling/test_members.py`` compares the two bit for
bit). SI units (m, N, Pa).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..checks import ArrayLike, as_loads
from ..errors import FingerpadError
from ..finger import Finger
from ..friction import mu_checked
from ..micro.response import check_cell
from .curve import CurvePrediction, critical_load, disc_ratio, predict_curve

__all__ = ["BLOCK", "predict_members"]

#: Members per NumPy block (10 psi evaluations per member and load: 100 k pressures per block
#: at 40 loads, bounded memory).
BLOCK = 256


def _area_of(finger: Finger) -> Callable[[float], Any]:
    """``F -> A_fr(F)`` for a root finder: :meth:`Finger.ridge_area_law`, the numbers of
    :meth:`Finger.ridge_area` without its per-call checks and model construction (the root finder
    stays inside positive loads; :func:`fingerpad.micro.response.area_function` checks each area)."""
    return finger.ridge_area_law()


def _zone_radius(a: np.ndarray, peak: np.ndarray, p_zone: np.ndarray) -> np.ndarray:
    """Per row, the radius inside which the pad pressure exceeds that row's ``p_zone`` (0 where
    ``p_zone`` is infinite); :func:`.curve._zone_radius` row by row."""
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(peak > 0, p_zone / peak, np.inf)
    radius = a * np.sqrt(np.clip(1.0 - ratio**2, 0.0, None))
    return np.where(np.isfinite(p_zone), radius, 0.0)


def _block(f: np.ndarray, fingers: Sequence[Finger], cells: Sequence[Any], base: Any, factors: np.ndarray,
           reference: bool) -> list[CurvePrediction]:
    """The curves of one block of members, each on ``base`` read at its ``factors[i]``."""
    n, m = len(fingers), f.size
    areas = [finger.areas_checked(f) for finger in fingers]
    gross = np.array([g for g, _ in areas])
    ridge = np.array([r for _, r in areas])
    if np.any(ridge <= 0):
        raise FingerpadError("the finger's ridge contact area must be positive at every load")
    states = [check_cell(c) for c in cells]
    pt = np.repeat([s[0] for s in states], m)
    pf = np.repeat([s[1] for s in states], m)
    ff = np.tile(f, n)
    ar = ridge.ravel()
    p_mean = ff / ar
    peak = 1.5 * p_mean
    a = np.sqrt(ar / math.pi)
    # what predict_curve on cell.at_modulus(E) computes (ScaledResponse.disc_fraction reads the
    # base at peak / factor), for every member and load in one call; each entry on its own
    ratio = disc_ratio(base, peak / np.repeat(factors, m))
    real = ratio * ar
    with np.errstate(divide="ignore"):
        p_re = np.where(real > 0, ff / np.where(real > 0, real, 1.0), np.inf)
    t_radius, f_radius = _zone_radius(a, peak, pt), _zone_radius(a, peak, pf)
    out = []
    for i, (finger, cell) in enumerate(zip(fingers, cells, strict=True)):
        rows = slice(i * m, (i + 1) * m)
        real_i = real[rows]
        mu = mu_checked(f, real_i, finger)
        mu_ref = mu_norm = None
        if reference:
            mu_ref = mu_checked(f, ridge[i], finger)
            mu_norm = mu / mu_ref
        if math.isinf(float(cell.transition_pressure)):
            f_crit = math.inf
        else:
            try:
                f_crit = critical_load(cell, _area_of(finger))
            except FingerpadError:
                f_crit = math.nan
        out.append(CurvePrediction(
            load=f, gross_area=gross[i], ridge_area=ridge[i], real_area=real_i, area_ratio=ratio[rows],
            real_pressure=p_re[rows], ridge_radius=a[rows], transition_radius=t_radius[rows],
            full_contact_radius=f_radius[rows], centre_past_transition=peak[rows] >= pt[rows], mu=mu,
            mu_ref=mu_ref, mu_normalised=mu_norm, critical_load=f_crit, critical_load_hertz=None,
        ))
    return out


def predict_members(
    loads: ArrayLike, fingers: Sequence[Finger], cell: Any, moduli: Sequence[float] | None = None, *,
    reference: bool = True, n_rings: int = 16,
) -> list[CurvePrediction]:
    """Areas and friction of many fingers on one texture (see the module docstring).

    Parameters
    ----------
    loads
        Normal loads, N (positive; flattened to 1-D), the same for every finger.
    fingers
        The members' :class:`~fingerpad.finger.Finger`.
    cell
        A :class:`~fingerpad.micro.bem.BEMUnitCell` prepared over the members' pressures (read at
        each member's modulus), or any unit-cell response (then the same cell for every finger,
        ``moduli`` not given), or a sequence of responses, one per finger (e.g. per-member
        :class:`~fingerpad.micro.hertz.HertzUnitCell`); the last two run
        :func:`~fingerpad.coupling.predict_curve` per finger.
    moduli
        Each member's E1*, Pa (Eq. 3.4), with a BEM ``cell``.
    reference, n_rings
        As for :func:`~fingerpad.coupling.predict_curve`.

    Returns
    -------
    list of CurvePrediction
        One per finger, equal to ``predict_curve(loads, finger, cell.at_modulus(E1*))``, bit for
        bit (``tests/coupling/test_members.py``).
    """
    if moduli is None or not hasattr(cell, "at_modulus"):
        cells = list(cell) if isinstance(cell, Sequence) else [cell] * len(fingers)
        if len(cells) != len(fingers):
            raise FingerpadError(f"{len(cells)} unit cells for {len(fingers)} fingers")
        return [predict_curve(loads, finger, c, reference=reference, n_rings=n_rings)
                for finger, c in zip(fingers, cells, strict=True)]
    if len(moduli) != len(fingers):
        raise FingerpadError(f"{len(moduli)} moduli for {len(fingers)} fingers")
    f = as_loads(loads, "loads", strict=True).ravel()
    if f.size == 0:
        raise FingerpadError("no loads given")
    if int(n_rings) < 2:
        raise FingerpadError(f"n_rings must be at least 2, got {n_rings!r}")
    cells = [cell.at_modulus(float(e)) for e in moduli]
    factors = np.array([c.factor for c in cells], dtype=float)
    curves: list[CurvePrediction] = []
    for start in range(0, len(fingers), BLOCK):
        part = slice(start, start + BLOCK)
        curves.extend(_block(f, list(fingers[part]), cells[part], cell, factors[part], reference))
    return curves  # type: ignore[return-value]
