"""The adhesive unit cell: psi(p) of a periodic texture cell whose skin adheres (docs/model.md 6.6).

With an attractive interaction (:mod:`fingerpad.contact.interaction`) the contact of a cell
depends on its history: the skin pressed on follows the *loading branch*; pressed into full
contact and pulled back it may stay in contact down to a tension the loading branch never
reaches (the *unloading branch*, adhesive hysteresis); pulled beyond its *pull-off pressure* it
lifts off. The cell therefore computes each branch as one continuation, every solve started from
the previous one in a fixed order, so that its numbers depend on nothing but the cell:

* the loading branch: a solve at zero mean pressure from the skin resting on the highest point
  (:func:`fingerpad.contact.adhesive.solve_adhesive`), then up through the nodes ``p_k / E* =
  10^(k/12)`` of the global grid from ``1e-2 w / (E* Lx)`` until full contact (or
  :data:`~fingerpad.micro.bem.STATE_SEARCH_CAP` E*), steep steps of psi bisected, the transition
  and full-contact pressures bracketed to ``rtol`` on the way;
* the tensile part of the loading branch: from the zero-load state the mean gap is raised in
  steps of a quarter of the interaction's range until the skin has let go; the least mean
  pressure met is the pull-off pressure, the area under the curve the *work of separation* ``W``
  of the cell (J/m^2 of nominal area: the energy it costs to pull one square metre of the
  textured interface apart from zero load, ``W = w`` on a flat);
* the unloading branch (on request, :meth:`AdhesiveUnitCell.unloading`): down from the top of the
  loading branch through the same nodes to zero, then pulled apart as above.

What is solved and cached is the modulus-free, length-free unit cell, as for the non-adhesive
cell (docs/solver.md, "One curve for every modulus and every scale"): with every length over Lx
and pressures over E*, the contact depends on the adhesion only through ``w / (E* Lx)`` and
``rho / Lx``, which join the cache key. A cell at another modulus with the same ``w / E*`` is
served from the same entry; another ``w / E*`` is another cell.

The range: skin's physical range (a nanometre) is far below a pixel, and its Tabor parameter on
micrometre asperities is 1e3-1e4, the JKR limit, whose results do not depend on the range. The
range used is therefore the larger of the given one and the one whose cohesive zone spans
:data:`~fingerpad.contact.interaction.COHESIVE_PIXELS` pixels
(:func:`~fingerpad.contact.interaction.resolved_range`): it shrinks with the pixel, and the
grid's error estimate (:mod:`fingerpad.micro.resolution`) measures both together. A range so
regularised acts within :data:`~fingerpad.contact.interaction.TIP_PIXELS` pixels of the contact
only (the JKR limit's cohesive zone; no attraction reaching out of contact). Where the caps'
contacts pull the skin onto the texture's base from a distance (:attr:`AdhesiveUnitCell.pulled_in`:
the jump comes when their edges are 2.5-3 pixels short of the base, about three ranges of gap),
the transition's error is of orders 1 and 3/2 in the pixel, and the prediction reports it
extrapolated from the grid, its half and its quarter, estimated with the eighth
(:func:`fingerpad.micro.pull_in.adopt_extrapolated`, :meth:`AdhesiveUnitCell.adopt_pressure`),
its psi(p) jumping there (docs/model.md 6.6, "The curve with the reported transition"). SI units.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from ..contact import ContactResult, HalfSpaceSolver
from ..contact.interaction import TIP_PIXELS, make_interaction, resolved_range
from ..contact.layered import Layer
from ..errors import FingerpadError
from .bem import DEFAULT_RTOL, MAX_PSI_STEP, STATE_SEARCH_CAP
from .layered_cell import _round, unit_layer
from .loadcurve import Progress
from .psi_curve import piecewise_pchip
from .pull_apart import SEPARATION_STEP, pull_apart
from .reported_curve import jump_shift, shifted_fraction
from .unit_key import POINTS_PER_DECADE, unit_cell_key, unit_texture

if TYPE_CHECKING:
    from ..textures import Texture
    from .cache import CurveCache

def _with_gap(res: ContactResult, gap: np.ndarray) -> ContactResult:
    """``res`` with another gap field: a start for the adhesive solver (which starts from the gap)."""
    from dataclasses import replace

    return replace(res, gap=gap)


__all__ = ["AdhesiveUnitCell", "adhesion_key", "pull_apart"]

#: The loading branch starts its node grid at this fraction of ``w / Lx`` (below, psi is its
#: zero-load value to within its interpolation error).
LOW_NODE = 1e-2
#: Most extra solves bisecting steep steps of one branch.
MAX_REFINE = 40
#: Version of what an adhesive cell stores (part of its key). 3: the loading branch stores the
#: base's gap just below the transition (``transition_gap``, :attr:`AdhesiveUnitCell.pulled_in`).
ADHESIVE_CELL_VERSION = 3
#: The base is *pulled in* (docs/model.md 6.6, "Convergence past the transition") when the skin's
#: least gap over the texture's base, at the last solution below the transition, exceeds this
#: many ranges: the regularised attraction closed it from a distance, not the loading.
PULL_IN_RANGES = 1.0


def adhesion_key(law: str, work: float, range_: float) -> dict[str, Any]:
    """What a unit cell's adhesion adds to its cache key: the law, ``w / (E* Lx)`` and
    ``rho / Lx`` (the unit interaction's numbers), rounded like the unit layer's ratios."""
    return {"adhesion": {"law": law, "work": _round(work), "range": _round(range_),
                         "version": ADHESIVE_CELL_VERSION}}


class AdhesiveUnitCell:
    """psi(p) of a periodic cell with adhesion: the loading branch from its pull-off pressure up,
    the pull-off pressure, the work of separation and (on request) the unloading branch.

    Implements the ``UnitCellResponse`` protocol of :mod:`fingerpad.micro.response` on the
    loading branch (``contact_fraction`` is 0 below the pull-off pressure: the skin has let go).

    Parameters
    ----------
    texture
        Periodic unit cell.
    modulus
        Reduced modulus E* (Pa), Eq. 3.4.
    work_of_adhesion
        w (J/m^2), positive.
    adhesion_range
        The physical range rho (m); the range used is the larger of it and the resolved one
        (module docstring). ``None``: :data:`fingerpad.finger.ADHESION_RANGE` (0.3 nm, below a
        pixel on every grid the cells use).
    law
        ``"exponential"`` (default) or ``"maugis"`` (:data:`fingerpad.finger.ADHESION_LAWS`).
    tol, max_iter, cache, rtol, layer
        As for :class:`~fingerpad.micro.bem.BEMUnitCell`.
    """

    #: Tells the coupling to take the adhesive pad (:func:`fingerpad.coupling.predict_curve`).
    adhesive = True
    #: Order of convergence in the pixel of what the cell gives (docs/model.md 6.6, "Convergence
    #: past the transition"): the range follows the pixel (``rho ~ dx^(1/2)``), so Maugis's
    #: parameter of the caps' contacts grows only as ``dx^(-1/2)`` and what depends on it (the
    #: adhesion-driven jump into full contact at large ``w``) converges at order 1/2: on the
    #: default cell at ``w`` 0.3 J/m^2 the transition's change per grid doubling shrinks by 0.67.
    #: The grid's error estimate scales the change from the half grid by ``1 / (2^q - 1)``
    #: (:func:`fingerpad.micro.resolution.order_factor`). A transition the attraction pulled in
    #: (:attr:`pulled_in`) is instead extrapolated with the orders 1 and 3/2 removed and estimated
    #: against the next order's limit (:func:`fingerpad.micro.pull_in.extrapolated_states`).
    convergence_order = 0.5

    def __init__(
        self,
        texture: "Texture",
        modulus: float,
        *,
        work_of_adhesion: float,
        adhesion_range: float | None = None,
        law: str = "exponential",
        tol: float = 1e-8,
        max_iter: int = 5000,
        cache: "CurveCache | None | bool" = None,
        rtol: float = DEFAULT_RTOL,
        layer: Layer | None = None,
        curve_tol: float | None = None,
    ) -> None:
        from .bem import CURVE_TOL, periodic_cell
        from .cache import CurveCache

        self.texture, self.modulus, self.length = periodic_cell(texture, modulus)
        w = float(work_of_adhesion)
        if not (math.isfinite(w) and w > 0):
            raise FingerpadError(f"work of adhesion must be a positive number of J/m^2, got {work_of_adhesion!r}")
        from ..finger import ADHESION_RANGE

        rho = ADHESION_RANGE if adhesion_range is None else float(adhesion_range)
        if not (math.isfinite(rho) and rho > 0):
            raise FingerpadError(f"adhesion range must be a positive number of metres, got {adhesion_range!r}")
        self.work_of_adhesion = w
        self.physical_range = rho
        self.unit = unit_texture(texture)
        nx = self.unit.shape[0]
        unit_work = _round(w / (self.modulus * self.length))
        # the range used: the physical one, or the resolved one where that is longer (the JKR limit)
        resolved = resolved_range(unit_work, 1.0, 1.0 / nx)
        unit_range = _round(max(rho / self.length, resolved))
        regularised = unit_range > rho / self.length
        # a regularised range acts at the contact's edge only (docs/model.md 6.6)
        self.law = make_interaction(law, unit_work, unit_range, TIP_PIXELS if regularised else 0)
        #: The publications of this model (:mod:`fingerpad.references` keys): the solver of its
        #: nodes, adhesive contact with the gap as the unknown, the JKR limit, the Maugis-Dugdale law.
        self.REFERENCES = ("polonsky1999", "rey2017", "johnson1971") + (("maugis1992",) if law == "maugis" else ())
        #: The range the solves use (m): ``max(adhesion_range, resolved range)``.
        self.adhesion_range = unit_range * self.length
        self.regularised = regularised
        self.layer = layer
        self.unit_layer = unit_layer(layer, self.modulus, self.length)
        self.tol, self.max_iter, self.rtol = tol, max_iter, rtol
        curve_tol = CURVE_TOL if curve_tol is None else float(curve_tol)
        self.curve_tol = curve_tol
        self.node_tol = max(float(tol), curve_tol)
        self.solver = HalfSpaceSolver(self.unit, 1.0, layer=self.unit_layer, tol=self.node_tol, max_iter=max_iter,
                                      interaction=self.law, kernels="compiled")
        self.cache = CurveCache() if cache is None else (cache or None)
        extra = {} if self.node_tol == float(tol) else {"node_tol": self.node_tol}
        self.key = unit_cell_key(self.unit, tol=tol, max_iter=max_iter, rtol=rtol, layer=self.unit_layer,
                                 arithmetic=self.solver.arithmetic,
                                 **adhesion_key(self.law.name, unit_work, unit_range), **extra)
        self.flat = texture.peak_to_valley <= 0
        self.solves = 0
        self._entry: dict[str, Any] = {}
        self._adopted: dict[str, float] = {}  # state pressures reported instead of the own (Pa)
        self._shift_memo: tuple[Any, tuple[float, ...] | None] | None = None
        self._interp: Any = None
        self._progress: tuple[Progress | None, int, int] = (None, 0, 0)
        if self.cache is not None:
            self._entry = self.cache.load(self.key)

    # ---------------------------------------------------------------- computing

    def prepare(self, p_min: float = 0.0, p_max: float = 0.0, progress: Progress | None = None) -> "AdhesiveUnitCell":
        """Compute (or read from the cache) the loading branch, the pull-off pressure and the work
        of separation. The branch is computed whole, whatever the range: it is one continuation
        (the arguments are accepted for the interface of the non-adhesive cell)."""
        if self._entry.get("loading") is not None:
            return self
        self._progress = (progress, 0, 40)
        loading = self._load_up()
        pulled = self._pull_apart(loading.pop("_zero"))
        entry = {"loading": loading, "separation": pulled}
        self._entry = entry
        if self.cache is not None:
            self._entry = self.cache.update(self.key, entry)
        self._progress = (None, 0, 0)
        self._interp = None
        return self

    def unloading(self) -> dict[str, Any]:
        """The unloading branch: ``pressure`` (Pa), ``contact_fraction`` from the top of the
        loading branch down to zero, then the pull-apart from there (``pull_off_pressure``, Pa;
        ``work_of_separation``, J/m^2). Computed on first request and cached."""
        self.prepare()
        if self._entry.get("unloading") is None:
            rows: dict[str, Any] = {}
            res = self._top_start()
            for p in sorted(self._loading_nodes(), reverse=True):
                if p <= 0:
                    continue
                res = self._solve(p, res)
                rows[repr(p)] = self._row(res)
            res = self._solve(0.0, res)
            rows[repr(0.0)] = self._row(res)
            pulled = self._pull_apart(res)
            entry = {"unloading": {"points": rows, "separation": pulled}}
            self._entry = self.cache.update(self.key, entry) if self.cache is not None else {**self._entry, **entry}
        return self._branch_si(self._entry["unloading"])

    def _solve(self, p: float, initial: ContactResult | None) -> ContactResult:
        with warnings.catch_warnings():
            # an unconverged node is recorded as such (converged: False in its row)
            warnings.filterwarnings("ignore", message="contact solve did not converge", category=RuntimeWarning)
            res = self.solver.solve_pressure(p, initial=initial)
        self.solves += 1
        callback, done, total = self._progress
        if callback is not None:
            done += 1
            total = max(total, done + 1)
            callback(done, total)
            self._progress = (callback, done, total)
        return res

    @staticmethod
    def _row(res: ContactResult) -> dict[str, Any]:
        return {"contact_fraction": res.contact_fraction, "mean_gap": res.mean_gap, "max_pressure": res.max_pressure,
                "mean_pressure": res.mean_pressure, "contact_state": res.contact_state,
                "converged": res.converged, "iterations": res.iterations}

    def _load_up(self) -> dict[str, Any]:
        """The loading branch (unit pressures): zero, then the global nodes upward to full contact,
        steep steps bisected, the state changes bracketed; each solve from the highest one below."""
        zero = self._solve(0.0, None)
        points: dict[float, dict[str, Any]] = {0.0: self._row(zero)}
        k = math.floor(math.log10(LOW_NODE * self.law.work) * POINTS_PER_DECADE)
        k_cap = math.floor(math.log10(STATE_SEARCH_CAP) * POINTS_PER_DECADE)
        reached = {"transition": lambda st: st != "asperity", "full": lambda st: st == "full"}
        brackets: dict[str, list[float] | None] = {name: ([0.0, 0.0] if test(zero.contact_state) else None)
                                                    for name, test in reached.items()}
        lo_p, lo = 0.0, zero
        transition_gap = None  # the base's least gap below the transition (unit lengths)
        budget = [MAX_REFINE]
        top, top_p = zero, 0.0
        while k <= k_cap and brackets["full"] is None:
            p = 10 ** (k / POINTS_PER_DECADE)
            res = self._solve(p, lo)
            points[p] = self._row(res)
            below_p, below = self._refine(points, lo_p, lo, p, res, budget)
            if below_p != lo_p:
                res = self._solve(p, below)  # the node again, from the nearest state below it
                points[p] = self._row(res)
            for name, test in reached.items():
                if brackets[name] is None and test(res.contact_state):
                    brackets[name], last = self._bracket(points, below_p, below, p, test)
                    if name == "transition":
                        transition_gap = self._base_gap(last)
            lo_p, lo = p, res
            top, top_p = res, p
            k += 1
        self._top = (top_p, top)
        return {"points": {repr(q): row for q, row in sorted(points.items())}, "transition": brackets["transition"],
                "full": brackets["full"], "_zero": zero, "top": top_p,
                "transition_gap": transition_gap}

    def _refine(self, points: dict[float, dict[str, Any]], lo_p: float, lo: ContactResult, hi_p: float,
                hi: ContactResult, budget: list[int]) -> tuple[float, ContactResult]:
        """Bisect a step of psi steeper than MAX_PSI_STEP between the solutions at ``lo_p`` and
        ``hi_p`` (units of E*), each trial from the highest solution below it; returns the
        highest solution below ``hi_p`` reached."""
        while budget[0] > 0 and hi.contact_fraction - lo.contact_fraction > MAX_PSI_STEP and \
                (lo_p == 0 or hi_p / lo_p > 1 + 2 * self.rtol):
            mid = math.sqrt(lo_p * hi_p) if lo_p > 0 else 0.5 * hi_p
            res = self._solve(mid, lo)
            budget[0] -= 1
            points[mid] = self._row(res)
            if res.contact_fraction - lo.contact_fraction > MAX_PSI_STEP:
                hi_p, hi = mid, res  # the steep part lies below the middle
            else:
                lo_p, lo = mid, res
        return lo_p, lo

    def _base_gap(self, res: ContactResult) -> float | None:
        """The skin's least gap over the texture's base in ``res`` (unit lengths; ``None``: no base)."""
        base = np.asarray(self.solver.base, dtype=bool)
        return float(np.min(res.gap[base])) if base.any() else None

    def _bracket(self, points: dict[float, dict[str, Any]], lo_p: float, lo: ContactResult, hi_p: float,
                 reached: Callable[[str], bool]) -> tuple[list[float], ContactResult]:
        """``[lo, hi]`` (units of E*) around the state change between the solution ``lo`` (not
        reached) and the node ``hi_p`` (reached), narrowed to ``rtol`` by bisection from below;
        and the last solution below the change."""
        # the refined nodes between may already hold the change
        inside = sorted(q for q in points if lo_p < q < hi_p and reached(str(points[q]["contact_state"])))
        if inside:
            hi_p = inside[0]
        while lo_p > 0 and (hi_p - lo_p) / hi_p > self.rtol:
            mid = math.sqrt(lo_p * hi_p)
            res = self._solve(mid, lo)
            if reached(res.contact_state):
                hi_p = mid
            else:
                lo_p, lo = mid, res
        return [lo_p, hi_p], lo

    def _top_start(self) -> ContactResult:
        """The state at the top of the loading branch: kept from :meth:`prepare` in this process,
        else a full contact (a zero gap, where the branch ended in full contact) or a solve at the
        top pressure."""
        top_p = float(self._entry["loading"]["top"])
        kept = getattr(self, "_top", None)
        if kept is not None and kept[0] == top_p:
            return kept[1]
        res = self._solve(top_p, None)
        if self._entry["loading"].get("full") is not None:
            return self._solve(top_p, _with_gap(res, np.zeros_like(res.gap)))
        return res

    def _pull_apart(self, start: ContactResult) -> dict[str, Any]:
        """:func:`pull_apart` of the unit cell from ``start`` (units of E* and Lx)."""
        out = pull_apart(self.solver, start, SEPARATION_STEP * self.law.range)
        self.solves += out["solves"]
        return out

    # ---------------------------------------------------------------- reading

    def _loading_nodes(self) -> list[float]:
        return sorted(float(p) for p in self._entry["loading"]["points"])

    def _nodes(self) -> tuple[np.ndarray, np.ndarray]:
        """The loading branch's nodes (units of E*), tensile part included, and psi."""
        self._need()
        pts = self._entry["loading"]["points"]
        sep = self._entry["separation"]
        ps = [float(p) for p in pts] + [float(p) for p in sep["pressure"][1:]]
        psi = [float(r["contact_fraction"]) for r in pts.values()] + [float(f) for f in sep["contact_fraction"][1:]]
        order = np.argsort(ps, kind="stable")
        p_arr, psi_arr = np.asarray(ps)[order], np.asarray(psi)[order]
        keep = np.concatenate([[True], np.diff(p_arr) > 0])  # a repeated pressure: its first node
        return p_arr[keep], np.maximum.accumulate(psi_arr[keep])

    def _need(self) -> None:
        if self._entry.get("loading") is None and not self.flat:
            raise FingerpadError("adhesive unit cell not prepared: call prepare() first")

    def _build(self) -> Any:
        ps, psi = self._nodes()
        scale = LOW_NODE * self.law.work
        x = np.arcsinh(ps / scale)  # linear near zero, logarithmic far from it, both signs
        # pieces split at steps of psi that stayed steep (jumps of the branch: linear across)
        cuts = np.flatnonzero(np.diff(psi) > MAX_PSI_STEP)
        interp = piecewise_pchip(x, psi, np.split(np.arange(ps.size), cuts + 1))
        return interp, scale, ps[0], ps[-1], psi[-1]

    def contact_fraction(self, p: "np.ndarray | float") -> np.ndarray:
        """psi(p) on the loading branch at mean pressure ``p`` (Pa, any sign): 0 below the
        pull-off pressure, the last node's value above the top of the branch. Where the cell
        reports an adopted transition (:meth:`adopt_pressure`), its jump stands there
        (:meth:`_shifted`)."""
        p = np.asarray(p, dtype=float)
        if self.flat:
            return np.where(p >= self.pull_off_pressure, 1.0, 0.0)
        shift = self._shift()
        if shift is None:
            return self._own_fraction(p / self.modulus)
        return self._shifted(p / self.modulus, shift)

    def _own_fraction(self, q: np.ndarray) -> np.ndarray:
        """psi of the cell's own loading branch at unit pressures ``q`` (p / E*)."""
        if self._interp is None:
            self._interp = self._build()
        interp, scale, lo, hi, last = self._interp
        out = np.zeros_like(q)
        inside = (q >= lo) & (q <= hi)
        out[inside] = interp(np.arcsinh(q[inside] / scale))
        out[q > hi] = last
        return np.clip(out, 0.0, 1.0)

    # ---------------------------------------------------------------- the numbers of the cell

    @property
    def pull_off_pressure(self) -> float:
        """The least mean pressure (Pa, negative) the cell holds from zero load: the loading
        branch's pull-off."""
        if self.flat:
            return -math.inf
        self._need()
        return float(self._entry["separation"]["pull_off"]) * self.modulus

    @property
    def work_of_separation(self) -> float:
        """The work (J/m^2 of the cell's nominal area) to pull the cell apart from zero load."""
        if self.flat:
            return self.work_of_adhesion
        self._need()
        return float(self._entry["separation"]["work"]) * self.modulus * self.length

    @property
    def zero_load_fraction(self) -> float:
        """psi at zero load on the loading branch."""
        return float(self.contact_fraction(np.array([0.0]))[0])

    def _state_pressure(self, name: str) -> float:
        if self.flat:
            return 0.0
        self._need()
        if name in self._adopted:
            return self._adopted[name]
        return self.own_state_pressure(name)

    def reported_state_pressure(self, name: str) -> float:
        """Pressure (Pa) of state ``name`` as the cell reports it: adopted
        (:meth:`adopt_pressure`), else its own."""
        return self._state_pressure(name)

    def own_state_pressure(self, name: str) -> float:
        """Pressure (Pa) of state ``name`` (``"transition"`` or ``"full"``) on this cell's own
        loading branch, whatever it adopted (:meth:`adopt_pressure`): the geometric middle of its
        bracket, as :meth:`fingerpad.micro.bem.BEMUnitCell.own_state_pressure` gives it for the
        grid-convergence estimate of the state pressures."""
        if self.flat:
            return 0.0
        self._need()
        bracket = self._entry["loading"][name]
        if bracket is None:
            return math.inf
        lo, hi = bracket
        return 0.0 if hi <= 0 else self.modulus * math.sqrt(lo * hi) if lo > 0 else self.modulus * hi

    @property
    def pulled_in(self) -> bool:
        """Whether the loading branch reached the texture's base by the attraction pulling it in
        from more than :data:`PULL_IN_RANGES` ranges (the base's least gap at the last solution
        below the transition): then the transition pressure carries an error of first order in
        the pixel, the contact's edge stopping a fixed number of pixels short of the base
        (docs/model.md 6.6, "Convergence past the transition"). False where the base was touched
        by the loading itself, at zero load, or never."""
        if self.flat:
            return False
        self._need()
        gap = self._entry["loading"].get("transition_gap")
        return gap is not None and gap > PULL_IN_RANGES * self.law.range

    @property
    def pull_in_ranges(self) -> float:
        """The base's least gap at the last solution below the transition, in ranges of the
        attraction (what :attr:`pulled_in` compares with :data:`PULL_IN_RANGES`; NaN on a flat
        cell or where the branch met no base): followed from grid to grid, it says whether the
        pull-in holds as the pixel shrinks (docs/model.md 6.6.1)."""
        if self.flat:
            return math.nan
        self._need()
        gap = self._entry["loading"].get("transition_gap")
        return math.nan if gap is None else float(gap) / self.law.range

    def adopt_pressure(self, name: str, pressure: float | None) -> None:
        """Report ``pressure`` (Pa) as this cell's pressure of state ``name`` (its zones, critical
        and full-contact loads): the transition extrapolated to a vanishing pixel from this grid
        and the half grid's (:func:`fingerpad.micro.pull_in.adopt_extrapolated`); ``None``
        reports the cell's own again. psi(p) then jumps there too (:meth:`_shifted`: one
        transition per prediction); the brackets and the stored nodes stay the cell's own."""
        if name not in ("transition", "full"):
            raise FingerpadError(f"adopt_pressure: no state {name!r}")
        if pressure is None:
            self._adopted.pop(name, None)
        else:
            self._adopted[name] = float(pressure)

    def _shift(self) -> tuple[float, ...] | None:
        """Where psi's jump moves to (unit pressures, p / E*), ``None`` where the cell reports its
        own transition: ``(a, b, fb, t, f, slope)``, the branch's last node below its own jump
        ``a`` and the first at or past it ``b``, the first node at or past its own full contact
        ``fb``, the reported transition ``t`` and full contact ``f`` (at least ``t``), and the
        branch's mean slope ``d psi / d ln p`` below ``a`` (:func:`~.reported_curve.jump_shift`). Kept per
        adopted pressures (the coupling reads psi many times)."""
        key = (tuple(sorted(self._adopted.items())), self._entry.get("loading") is not None)
        if self._shift_memo is None or self._shift_memo[0] != key:
            self._shift_memo = (key, self._find_shift())
        return self._shift_memo[1]

    def _find_shift(self) -> tuple[float, ...] | None:
        if "transition" not in self._adopted or self._entry.get("loading", {}).get("transition") is None:
            return None
        ps, _ = self._nodes()
        return jump_shift(ps, self._own_fraction, self._entry["loading"], self._adopted["transition"] / self.modulus,
                          self.own_state_pressure("transition") / self.modulus,
                          self._state_pressure("full") / self.modulus)

    def _shifted(self, q: np.ndarray, shift: tuple[float, ...]) -> np.ndarray:
        """psi with its jump at the reported transition (:func:`~.reported_curve.shifted_fraction`)."""
        return shifted_fraction(q, shift, self._own_fraction)

    @property
    def transition_pressure(self) -> float:
        """Mean pressure (Pa) at which the loading branch first touches the texture's base
        (0 when adhesion alone brings it there; inf if not up to the cap)."""
        return self._state_pressure("transition")

    @property
    def full_contact_pressure(self) -> float:
        """Mean pressure (Pa) from which the loading branch is in full contact (0: at zero load)."""
        return self._state_pressure("full")

    @property
    def transition(self) -> tuple[float, float] | None:
        b = self._entry.get("loading", {}).get("transition")
        return None if b is None else (b[0] * self.modulus, b[1] * self.modulus)

    @property
    def full(self) -> tuple[float, float] | None:
        b = self._entry.get("loading", {}).get("full")
        return None if b is None else (b[0] * self.modulus, math.inf if b[1] is None else b[1] * self.modulus)

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """Pressures (Pa) where psi has kinks: zero, the pull-off, the ends of jumps."""
        if self.flat:
            return ()
        ps, psi = self._nodes()
        jumps = np.flatnonzero(np.diff(psi) > MAX_PSI_STEP)
        out = {0.0, float(ps[0])} | {float(ps[i]) for i in jumps} | {float(ps[i + 1]) for i in jumps}
        shift = self._shift()
        if shift is not None:
            # the own kinks below the continued branch, its ends, and those past the jump carried back
            a, b, fb, t, f, _ = shift
            past = np.array(sorted(v for v in out if v >= b), dtype=float)
            back = np.where(past > fb, past * (f / fb),
                            t * (f / t) ** (np.log(past / b) / math.log(fb / b)) if fb > b else t)
            out = {v for v in out if v <= a} | {a, t, f} | {float(v) for v in np.atleast_1d(back)}
        return tuple(sorted(v * self.modulus for v in out))

    @property
    def points(self) -> dict[float, dict[str, Any]]:
        """The loading branch's nodes at this modulus and size: pressure (Pa) -> row (SI)."""
        self._need()
        e, lx = self.modulus, self.length
        return {float(q) * e: {**row, "mean_gap": row["mean_gap"] * lx, "max_pressure": row["max_pressure"] * e,
                               "mean_pressure": row["mean_pressure"] * e}
                for q, row in self._entry["loading"]["points"].items()}

    def _branch_si(self, branch: dict[str, Any]) -> dict[str, Any]:
        e, lx = self.modulus, self.length
        ps = sorted((float(q), row) for q, row in branch["points"].items())
        sep = branch["separation"]
        return {"pressure": np.array([q * e for q, _ in ps]),
                "contact_fraction": np.array([row["contact_fraction"] for _, row in ps]),
                "pull_off_pressure": float(sep["pull_off"]) * e, "work_of_separation": float(sep["work"]) * e * lx}

    def curve(self) -> dict[str, np.ndarray]:
        """The loading branch's nodes, its tensile part (the pull-apart up to the pull-off)
        included: pressure (Pa), contact_fraction, mean_gap (m), max_pressure (Pa), contact_state."""
        self._need()
        e, lx = self.modulus, self.length
        rows = [(float(q), r["contact_fraction"], r["mean_gap"], r["max_pressure"], r["contact_state"])
                for q, r in self._entry["loading"]["points"].items()]
        sep = self._entry["separation"]
        rows += list(zip(sep["pressure"][1:], sep["contact_fraction"][1:], sep["mean_gap"][1:],
                         sep["max_pressure"][1:], sep["contact_state"][1:], strict=True))
        rows.sort(key=lambda r: r[0])
        return {"pressure": np.array([r[0] for r in rows]) * e,
                "contact_fraction": np.array([r[1] for r in rows], dtype=float),
                "mean_gap": np.array([r[2] for r in rows], dtype=float) * lx,
                "max_pressure": np.array([r[3] for r in rows], dtype=float) * e,
                "contact_state": np.array([str(r[4]) for r in rows], dtype=object)}

    def for_skin(self, modulus: float, layer: Layer | None,
                 p_range: tuple[float, float] | None = None) -> "AdhesiveUnitCell":
        """This texture's adhesive cell for another skin (reduced modulus ``modulus``, Pa, and
        ``layer``): ``w / E*`` changes with the modulus, so it is another unit cell (made with
        this one's settings and cache, prepared)."""
        return self._like(self.texture, modulus, layer).prepare()

    def sibling(self, texture: "Texture") -> "AdhesiveUnitCell":
        """The adhesive cell of another map of this texture (another grid: the estimates' coarser
        companions), with this cell's skin, adhesion, settings and cache; not prepared."""
        return self._like(texture, self.modulus, self.layer)

    def _like(self, texture: "Texture", modulus: float, layer: Layer | None) -> "AdhesiveUnitCell":
        return AdhesiveUnitCell(texture, modulus, work_of_adhesion=self.work_of_adhesion,
                                adhesion_range=self.physical_range, law=self.law.name, tol=self.tol,
                                max_iter=self.max_iter, cache=self.cache if self.cache is not None else False,
                                rtol=self.rtol, layer=layer, curve_tol=self.curve_tol)

    @property
    def interpolation_error(self) -> float:
        """Leave-one-out bound on the interpolation error of psi (absolute, interior nodes)."""
        from scipy.interpolate import PchipInterpolator

        ps, psi = self._nodes()
        x = np.arcsinh(ps / (LOW_NODE * self.law.work))
        cuts = np.flatnonzero(np.diff(psi) > MAX_PSI_STEP)
        worst = 0.0
        for idx in np.split(np.arange(ps.size), cuts + 1):
            for j in range(1, idx.size - 1):
                keep = np.delete(idx, j)
                worst = max(worst, abs(float(PchipInterpolator(x[keep], psi[keep])(x[idx[j]])) - psi[idx[j]]))
        return worst

    def describe(self) -> dict[str, Any]:
        """JSON-ready: the adhesion of this cell (SI) and what it gives."""
        return {"law": self.law.name, "work_of_adhesion": self.work_of_adhesion,
                "adhesion_range": self.physical_range, "adhesion_range_used": self.adhesion_range,
                "range_regularised": bool(self.regularised),
                "pull_off_pressure": self.pull_off_pressure, "work_of_separation": self.work_of_separation,
                "zero_load_contact_fraction": self.zero_load_fraction, "transition_pulled_in": self.pulled_in}
