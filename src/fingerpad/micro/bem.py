"""The numerical (BEM) unit cell: psi(p) of a periodic texture cell from the half-space solver.

This is the micro scale of the model done numerically (thesis ch. 3.2 and the coupling of
Eq. 3.11): the unit cell of the texture is solved at the local pressures the pad produces, and
the computed curve psi(p) is interpolated for the coupling integral. Curves are cached on disk
(:mod:`fingerpad.micro.cache`), keyed by content, so every prediction on the same cell reuses them.

One curve serves every modulus and every size (docs/solver.md, "One curve for every modulus and
every scale"): the rigid texture on a linear elastic half-space has a contact fraction that
depends on p/E* only, and a texture scaled uniformly in all its lengths has the same psi(p).
So the cell solved and stored is the *unit cell*: the heights divided by the cell's length Lx,
at unit modulus, with pressures in units of E* and lengths in units of Lx. Its key holds
neither E* nor Lx.

A layered skin (:class:`~fingerpad.contact.layered.Layer`) keeps both scalings when they are
applied to the layer too: psi is then a function of p/E* at fixed t/Lx, E_1/E*, E_2/E* and
Poisson ratios (docs/solver.md, "A layered cell"). The unit cell's layer (:func:`unit_layer`)
holds those numbers and joins the key; a half-space cell's key is as it always was.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Callable, ClassVar

import numpy as np

from ..contact import ContactResult, HalfSpaceSolver
from ..contact.layered import Layer
from ..errors import FingerpadError
from .layered_cell import layer_key, unit_layer
from .loadcurve import Progress, bisect_state
from .psi_curve import InterpolatedCurve, ScaledResponse
from .unit_key import POINTS_PER_DECADE, unit_cell_key, unit_texture

if TYPE_CHECKING:
    from ..textures import Texture
    from .cache import CurveCache

__all__ = ["CURVE_TOL", "POINTS_PER_DECADE", "BEMUnitCell", "ScaledResponse", "layer_key", "unit_cell_key", "unit_layer", "unit_texture"]


# --------------------------------------------------------------------------------------------
# Numerical unit-cell response for the coupling (Eq. 3.11 of docs/model.md)
# --------------------------------------------------------------------------------------------

#: Adjacent nodes of psi(p) differ by at most this much (steep stretches get extra nodes) ...
MAX_PSI_STEP = 0.04
#: ... using at most this many extra solves per prepare().
MAX_REFINE_SOLVES = 40
#: Relative width of the state-pressure brackets (part of the cache key).
DEFAULT_RTOL = 1e-3
#: The curve's nodes are solved to at most this tolerance (the solver's residual, docs/solver.md
#: section 5), looser than a single solve's default 1e-8: on examples/sweep.toml's cells (grid 48)
#: and the default cell every reported number moves by under 1/100 of the discretisation error
#: the prediction reports, for ~18 % fewer iterations with the refinement's warm starts (measured,
#: docs/solver.md, "The tolerance of a curve"; 1e-6 moved psi by up to 0.15 of its error, 1e-5 by
#: 2x). The state brackets' bisection keeps the cell's own ``tol``.
CURVE_TOL = 1e-7
#: The state pressures are searched up to this multiple of E*: the mean strain of the skin is then
#: of order one and linear elasticity no longer describes it; a state not reached is "beyond".
STATE_SEARCH_CAP = 10.0


def periodic_cell(texture: "Texture", modulus: float) -> tuple["Texture", float, float]:
    """A unit cell's texture (checked periodic), reduced modulus E* (Pa, checked) and length Lx
    (m): what every unit-cell response starts from."""
    from ..materials import check_modulus

    if not texture.periodic:
        raise FingerpadError("a unit-cell response needs a periodic texture (use --periodic or periodize)")
    return texture, check_modulus(modulus, "reduced modulus E*"), float(texture.size[0])


def _grid_pressure(k: int) -> float:
    """Node ``k`` of the global grid of normalised pressures, ``p / E* = 10**(k / POINTS_PER_DECADE)``."""
    return 10 ** (k / POINTS_PER_DECADE)


def valid_entry(entry: dict[str, Any]) -> bool:
    """Whether a cache entry holds what :class:`BEMUnitCell` writes (nodes: a pressure in units
    of E* -> its solve's numbers; state brackets: two numbers or none). A file edited by hand or
    written by something else is refused whole (and computed again) rather than read into a
    traceback or, worse, into the curve."""
    import numbers

    def number(v: Any) -> bool:
        return isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v)

    points = entry.get("points", {})
    if not isinstance(points, dict):
        return False
    for p, row in points.items():
        try:
            q = float(p)
        except (TypeError, ValueError):
            return False
        if not (math.isfinite(q) and q > 0 and isinstance(row, dict)):
            return False
        if not (all(number(row.get(k)) for k in ("contact_fraction", "mean_gap", "max_pressure"))
                and 0 <= row["contact_fraction"] <= 1 and isinstance(row.get("contact_state"), str)
                and isinstance(row.get("converged"), bool) and isinstance(row.get("iterations"), int)):
            return False
    for key in ("transition", "full"):  # [lo, hi] in units of E* (hi inf: beyond the search's cap)
        bracket = entry.get(key)
        if bracket is not None and not (isinstance(bracket, list) and len(bracket) == 2
                                        and number(bracket[0]) and bracket[0] >= 0
                                        and (number(bracket[1]) or bracket[1] == math.inf)
                                        and bracket[0] <= bracket[1]):
            return False
    return True


def _past_asperity(state: str) -> bool:
    """The transition is reached: the skin touches the texture's base level."""
    return state != "asperity"


def _in_full(state: str) -> bool:
    """Full contact is reached: at most 1 % of the cell out of contact."""
    return state == "full"


class BEMUnitCell(InterpolatedCurve):
    """The unit cell's real-to-nominal area fraction psi(p) from the half-space solver.

    Implements the ``UnitCellResponse`` protocol of :mod:`fingerpad.micro.response`: call
    :meth:`prepare` with the range of local pressures the pad produces, then
    :meth:`contact_fraction` interpolates the computed curve (PCHIP in log p, monotone, no
    overshoot) and :attr:`interpolation_error` bounds the interpolation error by leave-one-out.
    Below the lowest computed pressure psi follows the power law of the two lowest points
    (Hertz-like asperity contact); above the highest node it keeps that node's value.

    What is solved and cached is the modulus-free, length-free *unit cell*
    (:func:`unit_texture`, unit modulus): nodes, state brackets and mean gaps are stored in units
    of E* and of the cell length Lx, and this object presents them in Pa and m for its own
    ``modulus`` and ``texture``. A cell at another modulus, or of a uniformly scaled texture,
    finds the same cache entry, so it solves only nodes its pressure range adds (in p/E*).

    Parameters
    ----------
    texture
        Periodic unit cell.
    modulus
        Reduced modulus E* (Pa), Eq. 3.4.
    tol, max_iter
        Solver settings (part of the cache key).
    cache
        A :class:`~fingerpad.micro.cache.CurveCache`, ``None`` for the default folder, ``False`` for none.
    rtol
        Relative width of the transition and full-contact pressure brackets.
    full_rtol
        Relative width of the full-contact bracket where it differs from ``rtol`` (``None``: ``rtol``;
        part of the key when it differs). The half-grid companion of an estimate takes 1e-2
        (:data:`~fingerpad.micro.resolution.COMPANION_OPTIONS`): a full-contact pressure's grid
        error is some 4-35 % where the transition's is 0.1-1.5 % (grid 48, measured).
    layer
        A layered skin (:class:`~fingerpad.contact.layered.Layer`, SI); ``modulus`` is then the
        pair's E* at short wavelengths (the layer's E1* with a rigid texture, Eq. 3.4).
        ``None``: the homogeneous half-space.
    curve_tol
        The curve's nodes are solved to ``max(tol, curve_tol)``, the state brackets' bisection to
        ``tol`` (part of the cache key). ``None``: :data:`CURVE_TOL`; ``0``: every solve to ``tol``.
    psi_step
        The refinement bisects intervals whose psi step exceeds this (``None``:
        :data:`MAX_PSI_STEP`); the half-grid companion of an error estimate takes 0.06
        (:data:`~fingerpad.micro.resolution.COMPANION_OPTIONS`). Not part of the key: a node's
        value is a function of its pressure alone, whichever curve uses it.
    """

    #: The publications of this model (:mod:`fingerpad.references` keys; the contact solver of its nodes).
    REFERENCES: ClassVar[tuple[str, ...]] = ("polonsky1999",)

    def __init__(
        self,
        texture: "Texture",
        modulus: float,
        *,
        tol: float = 1e-8,
        max_iter: int = 5000,
        cache: "CurveCache | None | bool" = None,
        rtol: float = DEFAULT_RTOL,
        layer: Layer | None = None,
        curve_tol: float | None = None,
        psi_step: float | None = None,
        full_rtol: float | None = None,
    ) -> None:
        from .cache import CurveCache

        #: The cell's length Lx (m): the unit of the stored lengths.
        self.texture, self.modulus, self.length = periodic_cell(texture, modulus)
        self.unit = unit_texture(texture)
        if layer is not None and not isinstance(layer, Layer):
            raise FingerpadError("layer must be a fingerpad.contact.layered.Layer or None")
        self.layer = layer
        #: The layer of the unit cell: thickness over Lx, moduli over E* (None: a half-space).
        self.unit_layer = unit_layer(layer, self.modulus, self.length)
        #: The solver of the unit cell (unit modulus, lengths over Lx): its pressures are p / E*.
        # a curve is many solves: the compiled loops where Numba is installed, whatever the grid
        self.solver = HalfSpaceSolver(self.unit, 1.0, layer=self.unit_layer, tol=tol, max_iter=max_iter,
                                      kernels="compiled")
        self.rtol = rtol
        self.full_rtol = float(rtol if full_rtol is None else full_rtol)
        if not (0 < self.full_rtol < 1):
            raise FingerpadError(f"full_rtol must lie in (0, 1), got {full_rtol!r}")
        self.tol, self.max_iter = tol, max_iter
        curve_tol = CURVE_TOL if curve_tol is None else float(curve_tol)
        if not (0 <= curve_tol < 1):
            raise FingerpadError(f"curve_tol must lie in [0, 1), got {curve_tol!r}")
        self.curve_tol = curve_tol
        psi_step = MAX_PSI_STEP if psi_step is None else float(psi_step)
        if not (0 < psi_step < 1):
            raise FingerpadError(f"psi_step must lie in (0, 1), got {psi_step!r}")
        self.psi_step = psi_step
        #: Tolerance of the curve's node solves (the bisection of the state brackets uses ``tol``).
        self.node_tol = max(float(tol), curve_tol)
        self.cache = CurveCache() if cache is None else (cache or None)
        # a node tolerance other than tol joins the key (curves of either never mix in one entry)
        extra: dict[str, float] = {} if self.node_tol == float(tol) else {"node_tol": self.node_tol}
        if self.full_rtol != rtol:  # a full-contact bracket of its own width: another entry
            extra["full_rtol"] = self.full_rtol
        self.key = unit_cell_key(self.unit, tol=tol, max_iter=max_iter, rtol=rtol, layer=self.unit_layer,
                                 arithmetic=self.solver.arithmetic, **extra)
        # every node known (the cache's and those solved here: p / E* -> row in units of E* and Lx)
        # and the nodes this cell's curve uses (the canonical nodes of the ranges prepared: see
        # prepare()); the state brackets (p / E*)
        self._known: dict[float, dict[str, Any]] = {}
        self._unit_points: dict[float, dict[str, Any]] = {}
        self._transition: tuple[float, float] | None = None
        self._full: tuple[float, float] | None = None
        #: State brackets (p / E*) reported instead of the cell's own (:meth:`adopt_states`)
        self._reported: dict[str, tuple[float, float]] = {}
        self._points: dict[float, dict[str, Any]] | None = None
        self.flat = texture.peak_to_valley <= 0
        self.solves = 0
        self._interp = None
        self._phi: tuple[np.ndarray, np.ndarray, float] | None = None
        self._node_arrays: tuple[np.ndarray, np.ndarray] | None = None
        self._progress: tuple[Progress | None, int, int] = (None, 0, 0)
        #: What prepare() computed and has not yet written to the cache (None outside prepare()).
        self._pending: dict[str, Any] | None = None
        if self.cache is not None:
            self._absorb(self.cache.load(self.key, valid_entry))

    # ---------------------------------------------------------------- cache plumbing

    def _absorb(self, entry: dict[str, Any]) -> None:
        # Known nodes only: which of them the curve uses is decided by the ranges prepared
        # (prepare), never by what the cache happens to hold (issue 31).
        for p, row in entry.get("points", {}).items():
            self._known[float(p)] = row
        if entry.get("transition"):
            self._transition = tuple(entry["transition"])  # type: ignore[assignment]
        if "full" in entry and entry["full"] is not None:
            self._full = tuple(entry["full"])  # type: ignore[assignment]

    def _use(self, p: float) -> None:
        """Make the known node at ``p`` (units of E*) a node of this cell's curve."""
        key, row = self._lookup(p)
        if row is None:
            raise FingerpadError(f"internal: no computed node at p/E* = {p!r}")
        if key not in self._unit_points:
            self._unit_points[key] = row
            self._interp = None
            self._phi = None
            self._node_arrays = None
            self._points = None

    @property
    def points(self) -> dict[float, dict[str, Any]]:
        """The nodes of this cell's curve at its modulus and size: pressure (Pa) -> ``contact_fraction``,
        ``mean_gap`` (m), ``max_pressure`` (Pa), ``contact_state``, ``converged``, ``iterations``."""
        if self._points is None:
            e, lx = self.modulus, self.length
            self._points = {q * e: {**row, "mean_gap": row["mean_gap"] * lx, "max_pressure": row["max_pressure"] * e}
                            for q, row in self._unit_points.items()}
        return self._points

    def _bracket(self, name: str, own: bool = False) -> tuple[float, float] | None:
        """The unit bracket (p / E*) of state ``name``: the adopted one unless ``own``."""
        if not own and name in self._reported:
            return self._reported[name]
        return self._transition if name == "transition" else self._full

    @property
    def transition(self) -> tuple[float, float] | None:
        """Bracket [lo, hi] (Pa) of the transition pressure (``None`` before :meth:`prepare`);
        the adopted one after :meth:`adopt_states`."""
        b = self._bracket("transition")
        return None if b is None else (b[0] * self.modulus, b[1] * self.modulus)

    @property
    def full(self) -> tuple[float, float] | None:
        """Bracket [lo, hi] (Pa) of the full-contact pressure (``None`` before :meth:`prepare`);
        the adopted one after :meth:`adopt_states`."""
        b = self._bracket("full")
        return None if b is None else (b[0] * self.modulus, b[1] * self.modulus)

    def adopt_states(self, transition: "BEMUnitCell", full: "BEMUnitCell") -> None:
        """Report the transition bracket of ``transition`` and the full-contact bracket of
        ``full`` -- cells of the same texture on the grids chosen for those states
        (:func:`fingerpad.micro.resolution.choose_state_grids`) -- as this cell's (its zones,
        critical and full-contact loads). The curve psi(p) stays this cell's own, kinks at its
        own brackets included (they are within the state's reported error of the adopted ones)."""
        for name, other in (("transition", transition), ("full", full)):
            if other.unit_layer != self.unit_layer:
                raise FingerpadError("adopt_states: a cell of another skin")
            if other.modulus != self.modulus:
                raise FingerpadError("adopt_states: a cell at another modulus")
            bracket = other._bracket(name, own=True)
            if bracket is None:
                raise FingerpadError("adopt_states: the other cell is not prepared")
            if other is self:
                self._reported.pop(name, None)
            else:
                self._reported[name] = tuple(bracket)  # type: ignore[assignment]

    def own_state_pressure(self, name: str) -> float:
        """This cell's own pressure (Pa) of state ``name`` (``"transition"`` or ``"full"``),
        whatever it adopted: the geometric middle of its bracket (inf beyond the search cap)."""
        if self.flat:
            return 0.0
        b = self._bracket(name, own=True)
        if b is None:
            raise FingerpadError("unit cell not prepared: call prepare(p_min, p_max) first")
        return math.inf if math.isinf(b[1]) else self.modulus * math.sqrt(b[0] * b[1])

    def _store(self, new_points: dict[float, dict[str, Any]], **extra: Any) -> None:
        payload: dict[str, Any] = {"points": {repr(p): row for p, row in new_points.items()}, **extra}
        self._absorb(payload)
        if self.cache is None:
            return
        if self._pending is None:
            self._absorb(self.cache.update(self.key, payload, valid_entry))
            return
        # Inside prepare(): held until its end, then written in one update (see _flush).
        for k, v in payload.items():
            if isinstance(v, dict):
                self._pending.setdefault(k, {}).update(v)
            else:
                self._pending[k] = v

    def _flush(self) -> None:
        """Write what :meth:`prepare` computed into the cache in one locked update.

        Writing after every node re-read and re-wrote the whole entry each time: in a sweep at
        grid 48 that was ~35 updates per point and about 40 % of a point's time (profiled,
        issue 23). The merged entry (with what other processes added meanwhile) is absorbed, as
        each update's was before; the values are the same floats (JSON round-trips them)."""
        pending, self._pending = self._pending, None
        if pending and self.cache is not None:
            self._absorb(self.cache.update(self.key, pending, valid_entry))

    @staticmethod
    def _row(res: ContactResult) -> dict[str, Any]:
        # a unit-cell solve: pressures in units of E*, lengths in units of Lx
        return {
            "contact_fraction": res.contact_fraction, "mean_gap": res.mean_gap,
            "max_pressure": res.max_pressure, "contact_state": res.contact_state,
            "converged": res.converged, "iterations": res.iterations,
        }

    # ---------------------------------------------------------------- computing

    def prepare(self, p_min: float, p_max: float, progress: Progress | None = None) -> "BEMUnitCell":
        """Make sure psi(p) is computed over [p_min, p_max] Pa, and the state pressures.

        The transition and full-contact pressures are bracketed to ``rtol`` wherever they lie,
        not only inside the range: first on the global node grid (deterministic, so the result
        does not depend on the range asked for or on what the cache holds), then by geometric
        bisection. A state not reached by :data:`STATE_SEARCH_CAP` times E* is recorded as lying
        beyond it. The bisection's solves inside the range become nodes of the curve, so the kinks
        of psi at the state changes are resolved.

        The curve's nodes are a function of the ranges prepared on this object alone, not of what
        the cache held before (issue 31): the global grid nodes covering the range, the state
        brackets' bisection inside it, and the refinement of those; a node the cache holds is
        used where it is one of them, and a node's value is a function of its pressure alone
        (grid and refinement nodes are solved cold, a bracket's bisection from the bracket's
        own lower grid node), so a cached node has the very bits a solve would give.
        """
        if self.flat:
            return self
        if not (0 < p_min <= p_max and math.isfinite(p_max)):
            raise FingerpadError(f"bad pressure range [{p_min!r}, {p_max!r}]")
        self._pending = {}
        try:
            return self._prepare(p_min / self.modulus, p_max / self.modulus, progress)
        finally:
            self._flush()  # also after an error or Ctrl-C: the solves done are kept, as before

    def _prepare(self, p_min: float, p_max: float, progress: Progress | None) -> "BEMUnitCell":
        """:meth:`prepare` on the unit cell's pressures (units of E*)."""
        k0 = math.floor(math.log10(p_min) * POINTS_PER_DECADE) - 1
        k1 = math.ceil(math.log10(p_max) * POINTS_PER_DECADE) + 1
        todo = [k for k in range(k0, k1 + 1) if self._node(_grid_pressure(k)) is None]
        per_bracket = int(math.ceil(math.log2(math.log(10 ** (1 / POINTS_PER_DECADE)) / self.rtol))) + 1
        self._progress = (progress, 0, len(todo) + 2 * (per_bracket + 4))
        new: dict[float, dict[str, Any]] = {}
        for k in todo:
            # cold: a warm start from the node below would make the node's last bits depend on
            # which nodes this run solved (those the cache lacked), i.e. on the cache's history
            self._solve_node(_grid_pressure(k), None, new)
        if new:
            self._store(new)
        for k in range(k0, k1 + 1):
            self._use(_grid_pressure(k))
        self.prepare_states(k1)
        for name, bracket, reached in (("transition", self._transition, _past_asperity),
                                       ("full", self._full, _in_full)):
            for p in self._bracket_nodes(bracket, reached, k0, k1, self.state_rtol(name)):
                self._use(p)
        self._refine(p_min, p_max)
        self._progress = (None, 0, 0)
        return self

    def prepare_states(self, k_start: int | None = None) -> "BEMUnitCell":
        """Bracket the transition and full-contact pressures (to ``rtol``) without the curve: the
        state search on the global grid (from node ``k_start``; by default the one nearest the
        texture's pressure scale E* h / Lx, a number of the texture alone), then the bisection.
        The brackets do not depend on ``k_start`` (see :meth:`_bracket_state`). Returns self."""
        if self.flat or (self._transition is not None and self._full is not None):
            return self
        if k_start is None:
            scale = max(float(self.unit.peak_to_valley), 1e-12)  # E* h / Lx in units of E*
            k_start = round(math.log10(scale) * POINTS_PER_DECADE)
        outer = self._pending is None
        if outer:
            self._pending = {}
        try:
            if self._transition is None:
                self._store({}, transition=self._bracket_state(_past_asperity, k_start, self.rtol))
            if self._full is None:
                self._store({}, full=self._bracket_state(_in_full, k_start, self.full_rtol))
        finally:
            if outer:
                self._flush()
        return self

    def state_rtol(self, name: str) -> float:
        """The relative width to which state ``name``'s bracket is bisected."""
        return self.full_rtol if name == "full" else self.rtol

    def _bracket_nodes(self, bracket: tuple[float, float] | None, reached: Callable[[str], bool],
                       k0: int, k1: int, rtol: float) -> list[float]:
        """The nodes of a state bracket's bisection (units of E*) when its grid interval lies in
        the grid nodes ``k0..k1``: the bisection replayed from the known nodes' states (the same
        floats as when it ran), so that the curve takes the same nodes whether the bracket was
        computed now or read from the cache. Empty for a bracket at zero or beyond the cap."""
        if bracket is None or not (math.isfinite(bracket[1]) and bracket[0] > 0):
            return []
        k = math.ceil(math.log10(bracket[1]) * POINTS_PER_DECADE - 1e-6)
        lo, hi = _grid_pressure(k - 1), _grid_pressure(k)
        if not (k0 < k <= k1 and lo <= bracket[0] * (1 + 1e-12) and bracket[1] <= hi * (1 + 1e-12)):
            return []
        out = [lo, hi]
        while (hi - lo) / hi > rtol:
            mid = math.sqrt(lo * hi)
            row = self._node(mid)
            if row is None:  # not the bisection that made the bracket (should not happen)
                break
            out.append(mid)
            if reached(str(row["contact_state"])):
                hi = mid
            else:
                lo = mid
        return out

    def _refine(self, p_min: float, p_max: float) -> None:
        """Add nodes where psi rises steeply (just past the transition the skin floods the base):
        bisect (in log p) every interval inside the range whose psi step exceeds ``psi_step``
        (the range in units of E*, like the nodes), at most MAX_REFINE_SOLVES nodes per call.
        The intervals are those of the curve's own nodes, so the nodes added are too; a node
        is solved cold (its value a function of its pressure alone) unless the cache has it."""
        for _ in range(MAX_REFINE_SOLVES):
            ps, psi = self._nodes()
            steps = np.diff(psi)
            ok = (ps[1:] >= p_min) & (ps[:-1] <= p_max) & (ps[1:] / ps[:-1] > 1 + 2 * self.rtol)
            bad = np.flatnonzero(ok & (steps > self.psi_step))
            if bad.size == 0:
                break
            i = int(bad[np.argmax(steps[bad])])
            p = math.sqrt(ps[i] * ps[i + 1])
            if self._node(p) is None:
                new: dict[float, dict[str, Any]] = {}
                self._solve_node(p, None, new)
                self._store(new)
            self._use(p)

    def _solve_node(self, p: float, initial: ContactResult | None, sink: dict[float, dict[str, Any]],
                    tol: float | None = None) -> ContactResult:
        # a node of the curve to node_tol; the state bisection passes the cell's own tol
        self.solver.tol = self.node_tol if tol is None else tol
        res = self.solver.solve_pressure(p, initial=initial)
        sink[p] = self._row(res)
        self.solves += 1
        callback, done, total = self._progress
        if callback is not None:
            done += 1
            callback(done, max(total, done))
            self._progress = (callback, done, total)
        return res

    def _lookup(self, p: float) -> tuple[float, dict[str, Any] | None]:
        """``(key, row)`` of the known node at pressure ``p`` (units of E*); ``(p, None)`` if none."""
        row = self._known.get(p)
        if row is not None:
            return p, row
        return next(((q, r) for q, r in self._known.items() if math.isclose(p, q, rel_tol=1e-9)), (p, None))

    def _node(self, p: float) -> dict[str, Any] | None:
        """The computed node of the unit cell at pressure ``p`` (units of E*), if any is known."""
        return self._lookup(p)[1]

    def _state_at(self, k: int, sink: dict[float, dict[str, Any]]) -> str:
        """Contact state at global grid node ``k`` (solved if not yet computed)."""
        p = _grid_pressure(k)
        row = self._node(p) or sink.get(p)
        if row is None:
            self._solve_node(p, None, sink)
            row = sink[p]
        return str(row["contact_state"])

    def _bracket_state(self, reached: Callable[[str], bool], k_start: int, rtol: float) -> list[float]:
        """Bracket [lo, hi] (units of E*) of the pressure where ``reached(state)`` starts.

        Step 1 finds the first global grid node ``k`` with the state reached, by an exponential
        then binary search on the integers: the nodes and their states are the same whatever
        range was asked for, so the bracket is too. Step 2 bisects [p_{k-1}, p_k] geometrically
        to ``rtol`` (relative). Returns ``[p_cap, inf]`` when the state is not reached up to the cap.
        """
        new: dict[float, dict[str, Any]] = {}
        k_cap = math.floor(math.log10(STATE_SEARCH_CAP) * POINTS_PER_DECADE)
        k_floor = math.floor(math.log10(1e-9) * POINTS_PER_DECADE)
        k_start = min(max(k_start, k_floor), k_cap)
        if reached(self._state_at(k_start, new)):
            hi, step = k_start, 1
            while True:  # down until not reached
                lo = max(hi - step, k_floor)
                if not reached(self._state_at(lo, new)):
                    break
                if lo == k_floor:
                    # reached at any pressure worth solving (a nearly flat cell, or a recessed part
                    # under 1 % of the cell for "full"): the state starts at zero pressure
                    self._store(new)
                    return [0.0, _grid_pressure(k_floor)]
                hi, step = lo, 2 * step
        else:
            lo, step = k_start, 1
            while True:  # up until reached
                hi = min(lo + step, k_cap)
                if reached(self._state_at(hi, new)):
                    break
                if hi == k_cap:
                    self._store(new)
                    return [_grid_pressure(k_cap), math.inf]
                lo, step = hi, 2 * step
        while hi - lo > 1:  # the first reached node: binary search on the integers
            mid = (lo + hi) // 2
            if reached(self._state_at(mid, new)):
                hi = mid
            else:
                lo = mid
        p_lo, p_hi = _grid_pressure(lo), _grid_pressure(hi)
        lo_res = self._solve_node(p_lo, None, {}, self.tol)  # warm start for the bisection (already a node)
        self.solves -= 1  # a re-solve of a known node for its fields, not a new point
        p_lo, p_hi = bisect_state(lambda p, init: self._solve_node(p, init, new, self.tol), p_lo, p_hi, lo_res, reached,
                                  rtol, max_solves=200)
        self._store(new)
        return [p_lo, p_hi]

    # ---------------------------------------------------------------- UnitCellResponse

    @property
    def transition_pressure(self) -> float:
        """Mean cell pressure (Pa) at which the skin first touches the texture's base (geometric
        middle of a bracket of relative width ``rtol``; inf if beyond :data:`STATE_SEARCH_CAP` E*)."""
        if self.flat:
            return 0.0
        b = self._bracket("transition")
        if b is None:
            raise FingerpadError("unit cell not prepared: call prepare(p_min, p_max) first")
        lo, hi = b
        return math.inf if math.isinf(hi) else self.modulus * math.sqrt(lo * hi)

    @property
    def full_contact_pressure(self) -> float:
        """Mean cell pressure (Pa) from which the skin follows the whole texture: at most
        :data:`~fingerpad.contact.result.FULL_CONTACT_TOL` of the cell out of contact (geometric middle
        of a bracket of relative width ``rtol``; inf if beyond :data:`STATE_SEARCH_CAP` E*)."""
        if self.flat:
            return 0.0
        b = self._bracket("full")
        if b is None:
            raise FingerpadError("unit cell not prepared: call prepare(p_min, p_max) first")
        lo, hi = b
        return math.inf if math.isinf(hi) else self.modulus * math.sqrt(lo * hi)

    def at_modulus(self, modulus: float) -> "ScaledResponse":
        """psi(p) of this cell at reduced modulus ``modulus`` (Pa), by p/E* scaling (no solves).

        With a layer, the layer's moduli are taken scaled by the same factor (the scaling holds
        for the whole body); :meth:`for_skin` checks that and solves another cell when not."""
        if not (math.isfinite(modulus) and modulus > 0):
            raise FingerpadError(f"modulus must be positive, got {modulus!r}")
        return ScaledResponse(self, modulus / self.modulus)

    def for_skin(self, modulus: float, layer: Layer | None,
                 p_range: tuple[float, float] | None = None) -> "ScaledResponse | BEMUnitCell":
        """psi(p) of this texture cell for another skin: reduced modulus ``modulus`` (Pa) and
        ``layer``. The same unit cell (same unit layer) is read at the new modulus without a
        solve (:meth:`at_modulus`); another unit layer (a thickness or modulus ratio of its own)
        is another cell, made with this one's settings and cache and prepared over ``p_range``
        (Pa) when given."""
        if layer is None and self.layer is None:
            return self.at_modulus(modulus)
        if layer is not None and unit_layer(layer, modulus, self.length) == self.unit_layer:
            return self.at_modulus(modulus)
        cell = BEMUnitCell(self.texture, modulus, tol=self.tol, max_iter=self.max_iter, cache=self.cache if self.cache is not None else False,
                           rtol=self.rtol, layer=layer, curve_tol=self.curve_tol,
                           psi_step=self.psi_step, full_rtol=self.full_rtol)
        if p_range is not None:
            cell.prepare(*p_range)
        return cell

    def curve(self) -> dict[str, np.ndarray]:
        """The computed nodes: pressure (Pa), contact_fraction, mean_gap (m), max_pressure (Pa)."""
        points = self.points
        ps = np.array(sorted(points))
        return {
            "pressure": ps,
            "contact_fraction": np.array([points[p]["contact_fraction"] for p in ps]),
            "mean_gap": np.array([points[p]["mean_gap"] for p in ps]),
            "max_pressure": np.array([points[p]["max_pressure"] for p in ps]),
            "contact_state": np.array([points[p]["contact_state"] for p in ps]),
        }
