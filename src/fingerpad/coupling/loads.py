"""Many fingers' pad areas as one, and the load at which each finger's pad centre reaches a
pressure: :class:`FingerStack` and :func:`centre_loads` (issue 34).

:func:`centre_loads` is the package's one solver of ``1.5 F / A_fr(F) = p`` (Eq. 3.7 at the pad
centre; Eq. 3.6 generalised to any unit cell) for a finger: a prediction's critical load
(:func:`~fingerpad.coupling.predict_curve`) and full-contact load
(:func:`~fingerpad.study.states.load_at_centre_pressure`) take it for one finger, a population's
members (:mod:`.members`) for all of them at once, and since each finger's iterates are
elementwise a member's load is the bits of the same finger predicted alone. SI units (m, N, Pa).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..checks import ArrayLike
from ..errors import FingerpadError
from ..finger import Finger, _model_area
from ..micro.response import DEFAULT_LOAD_RANGE

__all__ = ["LOAD_RTOL", "MAX_TRIALS", "FingerStack", "centre_loads"]

#: Relative accuracy of the loads :func:`centre_loads` finds (critical and full-contact loads):
#: its search stops within a few 1e-15 of the root in log F; the tests hold it to this against
#: Brent's method per finger (:func:`~fingerpad.coupling.critical_load`) and closed forms
#: (Monte Carlo errors of a population's bands are ~1e-2).
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


class FingerStack:
    """Many fingers' pad and ridge areas as one: :meth:`Finger.areas_checked` of each finger on
    its row of a ``(fingers, ...)`` load array, to the bit. Fingers whose gross-area and ridge
    models are of one class that declares ``STACKS`` are evaluated together with their differing
    fields as column arrays; any other finger on its own row (its own models, as
    :meth:`Finger.ridge_area_law`)."""

    def __init__(self, fingers: Sequence[Finger]) -> None:
        self.fingers = list(fingers)
        self._gross: list[Any] | None = None  # Finger.gross_model builds (and checks) a model per call: once
        self._models: dict[int, tuple[Any, Any] | None] = {}

    def __len__(self) -> int:
        return len(self.fingers)

    def _stacked(self, ndim: int) -> tuple[Any, Any] | None:
        if ndim not in self._models:
            if self._gross is None:
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
            gross = _model_area(models[0], f)
            ff, ag = (f, gross) if gross.shape == f.shape else np.broadcast_arrays(f, gross)
            return gross, _model_area(models[1], ff, ag)
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
    regula falsi with the Illinois weighting, each trial kept at least ``tol = 4 eps max(|u|, 1)``
    inside the bracket, a bisection after two trials in a row that did not halve it, until the
    bracket is at most ``2 tol`` wide; the end with the smaller ``|h|`` is the root. Each
    finger's iterates are elementwise, so its load does not depend on the others in the stack
    (the same bits alone or in any company). Agrees with :func:`~fingerpad.coupling.critical_load`
    (Brent's method) to :data:`LOAD_RTOL` (tests).
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

    def areas(f: np.ndarray) -> np.ndarray:
        try:
            return sub.ridge_area(f)
        except FingerpadError:
            # a model that cannot give an area at some trial load (a fingerprint patch too small
            # for 1e9 N, say): finger by finger, NaN for the ones that fail (no load for them, as
            # a single finger's search reports it)
            out = np.full(f.shape, np.nan)
            for i in range(f.shape[0]):
                try:
                    out[i] = sub.subset([i]).ridge_area(f[i:i + 1])[0]
                except FingerpadError:
                    pass
            return out

    def h(u: np.ndarray) -> np.ndarray:
        f = np.exp(u)
        with np.errstate(divide="ignore", invalid="ignore"):
            area = areas(f)
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
