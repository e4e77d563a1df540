"""Many fingers on one unit cell at once: the vectorised twin of
:func:`~fingerpad.coupling.predict_curve` (issue 22, "a population must not cost a population of
BEM solves"; issue 34, "1,000 members x 40 loads well under 50 ms").

:func:`predict_members` gives, for each finger, the :class:`~.curve.CurvePrediction` that
:func:`~.curve.predict_curve` gives for that finger on ``cell.at_modulus(E1*)`` (the one unit
cell read at the member's modulus by p/E* scaling): the same pad areas (Eqs. 2.5-2.7, every
member's models evaluated as one, :class:`FingerStack`), pad pressures (Eq. 3.7), the same exact
integral of the cell's interpolated psi (Eq. 3.11, :func:`~.curve.disc_ratio`, each entry
computed on its own) and the same friction (Eqs. 2.1-2.4, :func:`fingerpad.friction.mu_stacked`),
bit for bit. The critical loads (the pad centre at the cell's transition, Eq. 3.6 generalised)
are found for all members together by one bracketed root search (:func:`centre_loads`) that
agrees with :func:`~.curve.critical_load`'s Brent search per finger to :data:`LOAD_RTOL`; the
members' full-contact loads take the same search. The members go through in blocks
(:data:`BLOCK`). An equation changed in :mod:`.curve` is changed here too
(``tests/coupling/test_members.py`` compares the two). SI units (m, N, Pa).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..checks import ArrayLike, as_loads
from ..errors import FingerpadError
from ..finger import Finger
from ..friction import mu_stacked
from ..micro.response import DEFAULT_LOAD_RANGE, check_cell
from .curve import CurvePrediction, disc_ratio, predict_curve

__all__ = ["BLOCK", "LOAD_RTOL", "FingerStack", "MemberCurves", "centre_loads", "member_curves", "predict_members"]

#: Members per NumPy block (10 psi evaluations per member and load: 100 k pressures per block
#: at 40 loads, bounded memory).
BLOCK = 1024

#: Relative accuracy of the loads :func:`centre_loads` finds (critical and full-contact loads):
#: its search stops within a few 1e-15 of the root in log F; the tests hold the members' loads
#: to this against each member's own Brent search (Monte Carlo errors of a population's bands
#: are ~1e-2).
LOAD_RTOL = 1e-12

#: Trials of :func:`centre_loads` at most (bisection alone needs ~60 over its bracket).
MAX_TRIALS = 200


def _stacked_model(models: Sequence[Any], ndim: int) -> Any | None:
    """One model of the members' common class with each field that differs between them a
    column array (shape ``(n,) + (1,) * (ndim - 1)``), a field they share kept as it is (so its
    field-only arithmetic stays the scalar arithmetic of one model); ``None`` where the class does
    not declare ``STACKS`` (``area_checked`` elementwise in its fields) or a field is not a number."""
    cls = type(models[0])
    if not getattr(cls, "STACKS", False) or not dataclasses.is_dataclass(cls):
        return None
    if any(type(m) is not cls for m in models):
        return None
    stacked = object.__new__(cls)  # the members' own models checked every field already
    for field in dataclasses.fields(cls):
        values = [getattr(m, field.name) for m in models]
        first = values[0]
        if all(v == first and type(v) is type(first) for v in values):
            value = first
        elif all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
            value = np.array(values, dtype=float).reshape(-1, *([1] * (ndim - 1)))
        else:
            return None
        object.__setattr__(stacked, field.name, value)
    return stacked


def _area(model: Any, *arrays: np.ndarray) -> np.ndarray:
    """:func:`fingerpad.finger._model_area` (its ``area_checked`` core where it has one)."""
    core = getattr(model, "area_checked", None)
    return np.asarray(core(*arrays) if core is not None else model.area(*arrays), dtype=float)


class FingerStack:
    """Many fingers' pad and ridge areas as one: :meth:`Finger.areas_checked` of each finger on
    its row of a ``(fingers, ...)`` load array, to the bit. Fingers whose gross-area and ridge
    models are of one class that declares ``STACKS`` are evaluated together with their differing
    fields as column arrays; any other finger on its own row (its own models, as
    :meth:`Finger.ridge_area_law`)."""

    def __init__(self, fingers: Sequence[Finger]) -> None:
        self.fingers = list(fingers)
        self._models: dict[int, tuple[Any, Any] | None] = {}

    def __len__(self) -> int:
        return len(self.fingers)

    def _stacked(self, ndim: int) -> tuple[Any, Any] | None:
        if ndim not in self._models:
            if not self._models:  # Finger.gross_model builds (and checks) a model per call: once
                self._gross = [f.gross_model for f in self.fingers]
            gross = _stacked_model(self._gross, ndim)
            ridges = _stacked_model([f.ridges for f in self.fingers], ndim) if gross is not None else None
            self._models[ndim] = None if ridges is None else (gross, ridges)
        return self._models[ndim]

    def subset(self, rows: Sequence[int] | np.ndarray) -> FingerStack:
        """The stack of the fingers at ``rows`` (in that order)."""
        return FingerStack([self.fingers[int(i)] for i in rows])

    def areas(self, load: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(A_g, A_fr)`` (m^2) at checked loads ``load`` of shape ``(fingers, ...)``, C-ordered."""
        f = np.ascontiguousarray(load, dtype=float)
        if f.shape[0] != len(self.fingers):
            raise FingerpadError(f"{f.shape[0]} rows of loads for {len(self.fingers)} fingers")
        models = self._stacked(f.ndim)
        if models is not None:
            gross = _area(models[0], f)
            ff, ag = (f, gross) if gross.shape == f.shape else np.broadcast_arrays(f, gross)
            return gross, _area(models[1], ff, ag)
        gross = np.empty_like(f)
        ridge = np.empty_like(f)
        for i, finger in enumerate(self.fingers):
            gross[i], ridge[i] = finger.areas_checked(f[i])
        return gross, ridge

    def ridge_area(self, load: np.ndarray) -> np.ndarray:
        """A_fr (m^2) at ``load`` (shape ``(fingers, ...)``)."""
        return self.areas(load)[1]


def centre_loads(stack: FingerStack, pressures: ArrayLike,
                 load_range: tuple[float, float] = DEFAULT_LOAD_RANGE) -> np.ndarray:
    """Per finger of ``stack``, the load F (N) at which its pad-centre pressure ``1.5 F / A_fr(F)``
    (Eq. 3.7) reaches ``pressures[i]`` (Pa): Eq. 3.6 generalised, for all fingers in one search.

    ``inf`` for an infinite pressure; NaN for a pressure that is not positive, for no crossing in
    ``load_range`` (the centre pressure on the same side at both ends) and where a trial load
    gives an area that is not positive. The search runs in ``u = ln F`` on
    ``h(u) = ln(1.5 F / A_fr(F)) - ln p`` (a straight line for power-law areas such as Hertz's):
    regula falsi with the Illinois weighting, each trial kept at least a tolerance inside the
    bracket, bisection when a step would not halve it within three trials, until the bracket is
    narrower than ``4 eps max(|u|, 1)``; the end with the smaller ``|h|`` is the root. Each
    finger's iterates are elementwise, so its load does not depend on the others in the stack
    (the same bits alone or in any company). Agrees with :func:`~.curve.critical_load` (Brent per
    finger) to :data:`LOAD_RTOL` (tests).
    """
    p = np.asarray(pressures, dtype=float).ravel()
    n = len(stack)
    if p.size != n:
        raise FingerpadError(f"{p.size} pressures for {n} fingers")
    lo_f, hi_f = (float(x) for x in load_range)
    if not (0 < lo_f < hi_f and math.isfinite(hi_f)):
        raise FingerpadError(f"load range must satisfy 0 < low < high, got {load_range!r}")
    out = np.full(n, np.nan)
    out[np.isinf(p) & (p > 0)] = math.inf
    todo = np.flatnonzero(np.isfinite(p) & (p > 0))
    if todo.size == 0:
        return out
    sub = stack if todo.size == n else stack.subset(todo)
    log_p = np.log(p[todo])

    def h(u: np.ndarray) -> np.ndarray:
        f = np.exp(u)
        with np.errstate(divide="ignore", invalid="ignore"):
            area = sub.ridge_area(f)
            value = np.log(1.5 * f / area) - log_p
        return np.where(np.isfinite(area) & (area > 0), value, np.nan)

    a = np.full(todo.size, math.log(lo_f))
    b = np.full(todo.size, math.log(hi_f))
    ha, hb = h(a), h(b)
    res = np.full(todo.size, np.nan)
    res[hb == 0] = b[hb == 0]
    res[ha == 0] = a[ha == 0]
    live = np.isfinite(ha) & np.isfinite(hb) & (ha != 0) & (hb != 0) & (np.sign(ha) != np.sign(hb))
    wa, wb = ha.copy(), hb.copy()  # the residuals the secant uses (Illinois-weighted)
    kept = np.zeros(todo.size, dtype=np.int8)  # +1: a replaced last time, -1: b
    stale = np.zeros(todo.size, dtype=np.int8)  # trials in a row that did not halve the bracket
    eps4 = 4 * np.finfo(float).eps
    for _ in range(MAX_TRIALS):
        tol = eps4 * np.maximum(np.maximum(np.abs(a), np.abs(b)), 1.0)
        width = b - a
        done = live & (width <= 2 * tol)
        res[done] = np.where(np.abs(ha) <= np.abs(hb), a, b)[done]
        live &= ~done
        if not live.any():
            break
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            u = b - wb * (b - a) / (wb - wa)
        u = np.where(np.isfinite(u) & (stale < 2), u, 0.5 * (a + b))
        u = np.where(live, np.clip(u, a + tol, b - tol), a)
        hu = h(u)
        bad = live & ~np.isfinite(hu)
        hit = live & (hu == 0)
        res[hit] = u[hit]
        live &= ~(bad | hit)
        left = live & (np.sign(hu) == np.sign(ha))  # the root lies in (u, b): u is the new a
        right = live & ~left
        # Illinois: the end kept a second time in a row has its secant residual halved
        wb = np.where(left & (kept == 1), 0.5 * wb, wb)
        wa = np.where(right & (kept == -1), 0.5 * wa, wa)
        a, ha, wa = np.where(left, u, a), np.where(left, hu, ha), np.where(left, hu, wa)
        b, hb, wb = np.where(right, u, b), np.where(right, hu, hb), np.where(right, hu, wb)
        kept = np.where(left, 1, np.where(right, -1, kept)).astype(np.int8)
        stale = np.where(live & (b - a > 0.5 * width), stale + 1, 0).astype(np.int8)
    if live.any():  # MAX_TRIALS without converging (bisection bounds it far below): the midpoint
        res[live] = 0.5 * (a + b)[live]
    out[todo] = np.exp(res)
    return out


def _zone_radius(a: np.ndarray, peak: np.ndarray, p_zone: np.ndarray) -> np.ndarray:
    """Per row, the radius inside which the pad pressure exceeds that row's ``p_zone`` (0 where
    ``p_zone`` is infinite); :func:`.curve._zone_radius` row by row."""
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(peak > 0, p_zone / peak, np.inf)
    radius = a * np.sqrt(np.clip(1.0 - ratio**2, 0.0, None))
    return np.where(np.isfinite(p_zone), radius, 0.0)


@dataclasses.dataclass(frozen=True)
class MemberCurves:
    """Many fingers' :class:`~.curve.CurvePrediction` as ``(members, loads)`` arrays (row ``i``
    that of finger ``i``; ``load`` 1-D, ``critical_load`` per member): what :func:`member_curves`
    computes, :meth:`curve` one member's prediction (views of the rows)."""

    load: np.ndarray
    gross_area: np.ndarray
    ridge_area: np.ndarray
    real_area: np.ndarray
    area_ratio: np.ndarray
    real_pressure: np.ndarray
    ridge_radius: np.ndarray
    transition_radius: np.ndarray
    full_contact_radius: np.ndarray
    centre_past_transition: np.ndarray
    mu: np.ndarray
    mu_ref: np.ndarray | None
    mu_normalised: np.ndarray | None
    critical_load: np.ndarray

    def __len__(self) -> int:
        return int(self.ridge_area.shape[0])

    def curve(self, i: int) -> CurvePrediction:
        """Member ``i``'s prediction."""
        return CurvePrediction(
            load=self.load, gross_area=self.gross_area[i], ridge_area=self.ridge_area[i],
            real_area=self.real_area[i], area_ratio=self.area_ratio[i], real_pressure=self.real_pressure[i],
            ridge_radius=self.ridge_radius[i], transition_radius=self.transition_radius[i],
            full_contact_radius=self.full_contact_radius[i], centre_past_transition=self.centre_past_transition[i],
            mu=self.mu[i], mu_ref=None if self.mu_ref is None else self.mu_ref[i],
            mu_normalised=None if self.mu_normalised is None else self.mu_normalised[i],
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
    mu_ref = mu_norm = None
    if reference:
        mu_ref = mu_stacked(ff, ridge, fingers)
        mu_norm = mu / mu_ref
    # the critical loads of every member in one search (inf: a cell that never reaches its
    # transition; NaN: no crossing in the load range, as predict_curve reports them)
    crit = centre_loads(stack, np.where(np.isinf(pt_m), np.nan, pt_m))
    crit[np.isinf(pt_m)] = math.inf
    return MemberCurves(f, gross, ridge, real, ratio, p_re, a, _zone_radius(a, peak, pt), _zone_radius(a, peak, pf),
                        peak >= pt, mu, mu_ref, mu_norm, crit)


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
    joined = {}
    for field in dataclasses.fields(MemberCurves):
        values = [getattr(p, field.name) for p in parts]
        joined[field.name] = values[0] if field.name == "load" or values[0] is None else np.concatenate(values)
    return MemberCurves(**joined)


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
        bit, the critical load to :data:`LOAD_RTOL` (``tests/coupling/test_members.py``).
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
