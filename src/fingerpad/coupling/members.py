"""Many fingers on one unit cell at once: the vectorised twin of
:func:`~fingerpad.coupling.predict_curve` (issue 22, "a population must not cost a population of
BEM solves"; issue 34, all members' loads in one search).

:func:`member_curves` (as arrays) and :func:`predict_members` (one
:class:`~.curve.CurvePrediction` per finger) give, for each finger, what
:func:`~.curve.predict_curve` gives for that finger on ``cell.at_modulus(E1*)`` (the one unit
cell read at the member's modulus by p/E* scaling), bit for bit: the same pad areas (Eqs.
2.5-2.7, every member's models evaluated as one, :class:`~.loads.FingerStack`), pad pressures
(Eq. 3.7), the same exact integral of the cell's interpolated psi (Eq. 3.11,
:func:`~.curve.disc_ratio`, each entry computed on its own), the same friction (Eqs. 2.1-2.4,
:func:`fingerpad.friction.mu_stacked`) and the same search of the critical loads
(:func:`~.loads.centre_loads`, all members at once). The members go through in blocks
(:data:`BLOCK`). An equation changed in :mod:`.curve` is changed here too
(``tests/coupling/test_members.py`` compares the two). SI units (m, N, Pa).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..checks import ArrayLike, as_loads
from ..errors import FingerpadError
from ..finger import Finger
from ..friction import mu_stacked
from ..micro.response import check_cell
from .curve import CurvePrediction, disc_ratio, predict_curve
from .loads import FingerStack, centre_loads

__all__ = ["BLOCK", "MemberCurves", "member_curves", "predict_members"]

#: Members per NumPy block (10 psi evaluations per member and load: 100 k pressures per block
#: at 40 loads, bounded memory).
BLOCK = 1024

def _zone_radius(a: np.ndarray, peak: np.ndarray, p_zone: np.ndarray) -> np.ndarray:
    """Per row, the radius inside which the pad pressure exceeds that row's ``p_zone`` (0 where
    ``p_zone`` is infinite); :func:`.curve._zone_radius` row by row."""
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(peak > 0, p_zone / peak, np.inf)
    radius = a * np.sqrt(np.clip(1.0 - ratio**2, 0.0, None))
    return np.where(np.isfinite(p_zone), radius, 0.0)


@dataclasses.dataclass(frozen=True)
class MemberCurves:
    """Many fingers' :class:`~.curve.CurvePrediction` as arrays: what :func:`member_curves`
    computes; :meth:`curve` is one member's prediction (views of its rows).

    Attributes
    ----------
    load
        The loads, N (1-D).
    rows
        Every per-load field of :class:`~.curve.CurvePrediction` by its name, a ``(members,
        loads)`` array, row ``i`` that of finger ``i`` (``mu_ref`` and ``mu_normalised`` absent
        without a reference).
    critical_load
        Per member, N.
    """

    load: np.ndarray
    rows: dict[str, np.ndarray]
    critical_load: np.ndarray

    def __len__(self) -> int:
        return int(self.critical_load.shape[0])

    def curve(self, i: int) -> CurvePrediction:
        """Member ``i``'s prediction."""
        row = {name: values[i] for name, values in self.rows.items()}
        return CurvePrediction(load=self.load, **{"mu_ref": None, "mu_normalised": None, **row},
                               critical_load=float(self.critical_load[i]), critical_load_hertz=None)

    def curves(self) -> list[CurvePrediction]:
        """Every member's prediction, in order."""
        return [self.curve(i) for i in range(len(self))]


def _block(f: np.ndarray, stack: FingerStack, base: Any, factors: np.ndarray, reference: bool) -> MemberCurves:
    """The curves of one block of members, each on ``base`` read at its ``factors[i]``."""
    fingers = stack.fingers
    n, m = len(fingers), f.size
    ff = np.tile(f, (n, 1))
    gross, ridge = stack.areas(ff)
    if np.any(ridge <= 0):
        raise FingerpadError("the finger's ridge contact area must be positive at every load")
    # ScaledResponse's state pressures (base x factor), each checked as check_cell checks it
    pt_base, pf_base, _ = check_cell(base)
    pt_m, pf_m = pt_base * factors, pf_base * factors
    pt, pf = pt_m[:, None], pf_m[:, None]
    p_mean = ff / ridge
    peak = 1.5 * p_mean
    a = np.sqrt(ridge / math.pi)
    # what predict_curve on cell.at_modulus(E) computes (ScaledResponse.disc_fraction reads the
    # base at peak / factor), for every member and load in one call; each entry on its own
    ratio = disc_ratio(base, (peak / factors[:, None]).ravel()).reshape(n, m)
    real = ratio * ridge
    with np.errstate(divide="ignore"):
        p_re = np.where(real > 0, ff / np.where(real > 0, real, 1.0), np.inf)
    mu = mu_stacked(ff, real, fingers)
    # the critical loads of every member in one search, predict_curve's (inf: a cell that never
    # reaches its transition; NaN: none in the load range, or a flat cell's 0 Pa)
    crit = centre_loads(stack, pt_m)
    rows = {"gross_area": gross, "ridge_area": ridge, "real_area": real, "area_ratio": ratio, "real_pressure": p_re,
            "ridge_radius": a, "transition_radius": _zone_radius(a, peak, pt),
            "full_contact_radius": _zone_radius(a, peak, pf), "centre_past_transition": peak >= pt, "mu": mu}
    if reference:  # on the flat the real area is the ridge area
        rows["mu_ref"] = mu_stacked(ff, ridge, fingers)
        rows["mu_normalised"] = mu / rows["mu_ref"]
    return MemberCurves(f, rows, crit)


def member_curves(loads: ArrayLike, stack: FingerStack, cell: Any, moduli: ArrayLike, *,
                  reference: bool = True) -> MemberCurves:
    """:func:`predict_members` on a BEM ``cell`` as arrays (see there): every member of
    ``stack`` on ``cell`` read at its E1* ``moduli[i]`` (Pa), in blocks of :data:`BLOCK`."""
    f = as_loads(loads, "loads", strict=True).ravel()
    if f.size == 0:
        raise FingerpadError("no loads given")
    e = np.asarray(moduli, dtype=float).ravel()
    if e.size != len(stack):
        raise FingerpadError(f"{e.size} moduli for {len(stack)} fingers")
    # cell.at_modulus(E).factor for every member (and its check)
    factors = np.array([cell.at_modulus(float(x)).factor for x in e], dtype=float)
    parts = []
    for start in range(0, len(stack), BLOCK):
        stop = min(start + BLOCK, len(stack))
        block = stack if (start, stop) == (0, len(stack)) else stack.subset(range(start, stop))
        parts.append(_block(f, block, cell, factors[start:stop], reference))
    if len(parts) == 1:
        return parts[0]
    return MemberCurves(f, {name: np.concatenate([p.rows[name] for p in parts]) for name in parts[0].rows},
                        np.concatenate([p.critical_load for p in parts]))


def predict_members(
    loads: ArrayLike, fingers: Sequence[Finger], cell: Any, moduli: Sequence[float] | None = None, *,
    reference: bool = True, n_rings: int = 16, stack: FingerStack | None = None,
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
    stack
        The fingers' :class:`FingerStack` if the caller has one (its models are built once).

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
    if int(n_rings) < 2:
        raise FingerpadError(f"n_rings must be at least 2, got {n_rings!r}")
    whole = FingerStack(fingers) if stack is None else stack
    if len(whole) != len(fingers):
        raise FingerpadError(f"a stack of {len(whole)} fingers for {len(fingers)} fingers")
    return member_curves(loads, whole, cell, moduli, reference=reference).curves()
