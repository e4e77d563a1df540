"""A family of adhesive unit cells in the dimensionless adhesion ``w / (E* Lx)``, and each
member of a population read from it by interpolation (docs/population.md, "Adhesion").

The adhesive cell (:class:`~fingerpad.micro.adhesive_cell.AdhesiveUnitCell`) is modulus-free
and length-free *at a given* ``u = w / (E* Lx)`` (the range used is the resolved one, itself a
function of ``u`` and the pixel): members of a population whose skin modulus or work of
adhesion differ have different ``u`` and would each need a cell of their own (a continuation of
~120 solves, 15 s - 2 min). Instead the cells are solved at a few nodes of ``u`` only,

    u_k = 10^(k / m),   k integer,   m = NODES_PER_DECADE (or fewer, down to 1, so that the
                                       nodes over the members' range are at most MAX_FAMILY_CELLS)

a global grid, so that the same nodes (and the cache's cells) serve every population over the
same range, and each member's cell is interpolated between the two nodes around its ``u``,
linearly in ``ln u`` (weights ``1 - t``, ``t``):

* ``psi(q)`` at the member's ``q = p / E*`` from each node's ``psi`` read where ``q`` stands
  among the landmarks (:func:`morph`): the pull-off pressure, zero, the transition and
  full-contact pressures, so that psi's jump where the skin reaches the base stays one jump
  (0 below the member's pull-off pressure);
* the pull-off pressure, the work of separation (in units of ``E*`` and ``E* Lx``) and the
  transition and full-contact pressures (units of ``E*``) in ``ln``-``ln`` (linearly where one
  of them is 0 or infinite), as the nodes report them: a node whose transition was pulled in
  reports it extrapolated to a vanishing pixel, its psi jumping there, by the rule of a single
  prediction's cell (:meth:`AdhesiveFamily.prepare`, docs/model.md 6.6).

**More nodes where psi's jump moves fast** (:meth:`AdhesiveFamily.refine`): where two
neighbouring nodes' transition (or full-contact) pressures differ by more than
:data:`REFINE_RATIO`, the interval is halved in ``ln u`` (at most :data:`MAX_REFINE_LEVEL` times,
at most :data:`MAX_REFINED_CELLS` nodes more): the landmarks carry each node's jump to the
member's transition, but that transition itself is read between the nodes, and at strong
adhesion (the skin pulled into full contact, the transition falling towards zero load) it moves
several times over one global interval.

**The interpolation error** is estimated per member from the same nodes
(:mod:`fingerpad.population.adhesion`): quadratic interpolants through a third node, each of the
member's nodes left out, and across a change of regime each node alone. The family always has at
least three nodes for that reason. SI units.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..errors import FingerpadError

__all__ = ["MAX_FAMILY_CELLS", "NODES_PER_DECADE", "AdhesiveFamily", "InterpolatedAdhesiveCell", "family_nodes",
           "morph", "unit_work"]

#: Nodes of the family per decade of ``w / (E* Lx)``. Measured on adults-adhesive (grid 64,
#: examples/study.toml): 3 per decade (8 cells) left members 0.9-23 % off their own cells in A_re,
#: 6 per decade (14 cells) 0.1-3 %.
NODES_PER_DECADE = 6
#: Most cells of one family (each an adhesive cell of its own: 15 s at grid 128, ~1.5 min at 256
#: on one core); a wider range of ``u`` takes a coarser global grid (fewer nodes per decade).
MAX_FAMILY_CELLS = 16
#: Fewest nodes (the error estimate needs a third).
MIN_FAMILY_CELLS = 3
#: Refinement (:meth:`AdhesiveFamily.refine`): an interval of ``u`` is halved where its two nodes'
#: transition (or full-contact) pressures differ by more than this factor, ...
REFINE_RATIO = 1.2
#: ... at most this many times (the finest nodes 2^3 = 8 times as close as the global grid's) ...
MAX_REFINE_LEVEL = 3
#: ... adding at most this many cells to a family (so at most MAX_FAMILY_CELLS + MAX_REFINED_CELLS).
MAX_REFINED_CELLS = 8


def unit_work(work_of_adhesion: float, modulus: float, length: float) -> float:
    """``u = w / (E* Lx)`` (-) of a skin of reduced modulus ``modulus`` (Pa) with the work of
    adhesion ``work_of_adhesion`` (J/m^2) on a cell of length ``length`` (m)."""
    return float(work_of_adhesion) / (float(modulus) * float(length))


def family_nodes(u_min: float, u_max: float, per_decade: int | None = None,
                 cap: int | None = None) -> tuple[float, ...]:
    """The nodes ``10^(k/m)`` of ``u`` from the last at or below ``u_min`` to the first at or
    above ``u_max``: ``m = per_decade`` (default :data:`NODES_PER_DECADE`), lowered (to 1) until
    they are at most ``cap`` (default :data:`MAX_FAMILY_CELLS`), and extended upward to
    :data:`MIN_FAMILY_CELLS`.

    Raises
    ------
    FingerpadError
        Non-positive ``u``, or a range needing more than ``cap`` nodes even at one per decade.
    """
    per_decade = NODES_PER_DECADE if per_decade is None else per_decade
    cap = MAX_FAMILY_CELLS if cap is None else cap
    if not (0 < u_min <= u_max < math.inf):
        raise FingerpadError(f"adhesive family: w / (E* Lx) must be positive and finite, got {u_min!r}..{u_max!r}")
    if not 1 <= per_decade or cap < MIN_FAMILY_CELLS:
        raise FingerpadError(f"adhesive family: per_decade >= 1 and cap >= {MIN_FAMILY_CELLS} needed")
    for m in range(int(per_decade), 0, -1):
        # a u that is a node (to rounding) is its own bracket's end
        k0 = math.floor(math.log10(u_min) * m + 1e-9)
        k1 = math.ceil(math.log10(u_max) * m - 1e-9)
        k1 = max(k1, k0 + MIN_FAMILY_CELLS - 1)
        if k1 - k0 + 1 <= cap:
            return tuple(10.0 ** (k / m) for k in range(k0, k1 + 1))
    raise FingerpadError(f"adhesive family: w / (E* Lx) from {u_min:.3g} to {u_max:.3g} spans more than "
                         f"{cap - 1} decades; at most {cap} cells in one family")


def _interp_log(values: Sequence[float], weights: Sequence[float]) -> float:
    """``sum w_k v_k`` in ``ln`` where every value is positive and finite, linearly where one is 0,
    ``inf`` where one is infinite with a non-zero weight."""
    vals = [float(v) for v in values]
    live = [(v, w) for v, w in zip(vals, weights, strict=True) if w != 0]
    if any(math.isinf(v) for v, _ in live):
        return math.inf
    if all(v > 0 for v, _ in live):
        return math.exp(sum(w * math.log(v) for v, w in live))
    return max(0.0, sum(w * v for v, w in live))


def morph(q: np.ndarray, source: Sequence[float], target: Sequence[float]) -> np.ndarray:
    """Map pressures ``q`` so that the ascending landmarks ``source`` go to ``target`` (the same
    count, ``0`` among them, any negative one first): linearly below zero, in proportion from 0
    to the first positive landmark, linearly in ``ln`` between positive ones, in proportion
    above the last. Monotone; ``morph(morph(q, a, b), b, a) == q``."""
    q = np.asarray(q, dtype=float)
    src, dst = np.asarray(source, float), np.asarray(target, float)
    out = np.array(q, dtype=float)
    neg = q < 0
    if src[0] < 0:  # the pull-off: in proportion below zero
        out[neg] = q[neg] * (dst[0] / src[0])
    pos_s, pos_d = src[src > 0], dst[dst > 0]
    if pos_s.size:
        first = (q > 0) & (q <= pos_s[0])
        out[first] = q[first] * (pos_d[0] / pos_s[0])
        last = q > pos_s[-1]
        out[last] = q[last] * (pos_d[-1] / pos_s[-1])
        mid = (q > pos_s[0]) & (q <= pos_s[-1])
        if mid.any():
            out[mid] = np.exp(np.interp(np.log(q[mid]), np.log(pos_s), np.log(pos_d)))
    return out


class AdhesiveFamily:
    """Adhesive unit cells of one texture at the nodes :func:`family_nodes` of ``u = w / (E* Lx)``.

    Parameters
    ----------
    texture
        The periodic cell (its grid is the family's).
    nodes
        The values of ``u`` (-), ascending, at least :data:`MIN_FAMILY_CELLS`.
    options
        Settings of every cell (:class:`~fingerpad.micro.adhesive_cell.AdhesiveUnitCell`):
        ``law``, ``adhesion_range`` (m), ``tol``, ``max_iter``, ``cache``, ``rtol``, ``curve_tol``.
    """

    def __init__(self, texture: Any, nodes: Sequence[float], **options: Any) -> None:
        from .bem import periodic_cell

        self.nodes = tuple(float(u) for u in nodes)
        if len(self.nodes) < MIN_FAMILY_CELLS or any(b <= a for a, b in zip(self.nodes, self.nodes[1:])):
            raise FingerpadError(f"adhesive family: at least {MIN_FAMILY_CELLS} ascending nodes, got {self.nodes}")
        _, _, self.length = periodic_cell(texture, 1.0)
        # every cell at E* = 1 Pa: its pressures are in units of E*, its work of adhesion is u Lx
        self.options = dict(options)
        self.texture = texture
        self.cells = [self._new_cell(u) for u in self.nodes]
        self.flat = self.cells[0].flat
        self.solves = 0
        #: Nodes :meth:`refine` added, and the nodes' spacing in ``ln u`` before it (the global grid's).
        self.refined = 0
        self.spacing = min(math.log(b / a) for a, b in zip(self.nodes, self.nodes[1:]))

    def prepare(self, progress: Callable[[int, int], None] | None = None,
                make_texture: Callable[[int], Any] | None = None, refine: bool = False) -> "AdhesiveFamily":
        """Solve (or read from the cache) every node's cell; ``progress(done, total)`` after each.

        A node whose transition was pulled in reports it extrapolated to a vanishing pixel, as
        a single prediction's cell does (:func:`~fingerpad.micro.pull_in.adopt_extrapolated`,
        docs/model.md 6.6): its half and quarter grids are solved beside it (``make_texture(nx)``
        builds the texture at ``nx`` points along x; ``None``: the cell's heights block-averaged
        2 x 2, :func:`~fingerpad.micro.resolution.companion`). ``refine``: then add nodes where
        the neighbours' state pressures differ much (:meth:`refine`)."""
        for i in range(len(self.cells)):
            self._settle(i, make_texture)
            if progress is not None:
                progress(i + 1, len(self.cells))
        if refine:
            self.refine(progress, make_texture)
        return self

    def _new_cell(self, u: float) -> Any:
        """The (unprepared) cell of node ``u``, at ``E* = 1 Pa``."""
        from .adhesive_cell import AdhesiveUnitCell

        return AdhesiveUnitCell(self.texture, 1.0, work_of_adhesion=u * self.length, **self.options)

    def _settle(self, i: int, make_texture: Callable[[int], Any] | None) -> None:
        """Prepare node ``i``'s cell and its pulled-in companions; adopt the extrapolated transition."""
        from .adhesive_cell import AdhesiveUnitCell
        from .pull_in import adopt_extrapolated, pulled_in_companions

        u, cell = self.nodes[i], self.cells[i]
        if self.flat:
            return
        before = cell.solves
        cell.prepare()
        self.solves += cell.solves - before
        grid = int(cell.texture.shape[0])
        held: dict[int, Any] = {grid: cell}
        self.solves += pulled_in_companions(
            cell, make_texture,
            lambda t, u=u: AdhesiveUnitCell(t, 1.0, work_of_adhesion=u * self.length, **self.options).prepare(),
            held)
        adopt_extrapolated(held, grid)

    def jump(self, i: int) -> float:
        """How far the state pressures of nodes ``i`` and ``i + 1`` lie apart: the largest
        ``|ln(p_b / p_a)|`` of their reported transition and full-contact pressures (units of
        ``E*``; ``inf`` where one node has the state at a positive finite pressure and the other
        at zero load or never; 0 where neither has it at a positive finite pressure)."""
        out = 0.0
        for name in ("transition", "full"):
            a, b = (self.cells[k].reported_state_pressure(name) for k in (i, i + 1))
            finite = [0 < v < math.inf for v in (a, b)]
            if all(finite):
                out = max(out, abs(math.log(b / a)))
            elif any(finite):
                out = math.inf
        return out

    def refine(self, progress: Callable[[int, int], None] | None = None,
               make_texture: Callable[[int], Any] | None = None) -> "AdhesiveFamily":
        """Add nodes where the state pressures move fast with ``u`` (prepared family).

        Between two neighbouring nodes whose transition or full-contact pressures differ by more
        than the factor :data:`REFINE_RATIO` (:meth:`jump`), psi's jump moves far: a member's
        transition read between them carries a large error. The interval of the largest such
        difference is halved in ``ln u`` (its midpoint lies on the global grid of twice as many
        nodes per decade, so the cache's cells serve any population), again and again, until no
        interval is above the factor, or it was halved :data:`MAX_REFINE_LEVEL` times, or
        :data:`MAX_REFINED_CELLS` nodes were added (ties: the lower ``u`` first). Depends on the
        nodes' cells only: the same members give the same family on any machine."""
        if self.flat:
            return self
        base = self.spacing
        added = 0
        while added < MAX_REFINED_CELLS:
            best, at = math.log(REFINE_RATIO), None
            for i in range(len(self.nodes) - 1):
                level = round(math.log2(base / math.log(self.nodes[i + 1] / self.nodes[i])))
                jump = self.jump(i)
                if level < MAX_REFINE_LEVEL and jump > best:
                    best, at = jump, i
            if at is None:
                break
            u = math.sqrt(self.nodes[at] * self.nodes[at + 1])
            self.nodes = (*self.nodes[:at + 1], u, *self.nodes[at + 1:])
            self.cells.insert(at + 1, self._new_cell(u))
            self._settle(at + 1, make_texture)
            added += 1
            if progress is not None:
                progress(len(self.nodes), len(self.nodes))
        self.refined = added
        return self

    def _bracket(self, u: float) -> int:
        """Index ``j`` of the lower node of ``u``'s interval (``nodes[j] <= u <= nodes[j + 1]``)."""
        if not self.nodes[0] * (1 - 1e-9) <= u <= self.nodes[-1] * (1 + 1e-9):
            raise FingerpadError(f"adhesive family: w / (E* Lx) = {u:.4g} lies outside its nodes "
                                 f"{self.nodes[0]:.4g}..{self.nodes[-1]:.4g}")
        return min(max(int(np.searchsorted(self.nodes, u, side="right")) - 1, 0), len(self.nodes) - 2)

    def weights(self, u: float, order: str = "linear") -> dict[int, float]:
        """Interpolation weights ``{node index: weight}`` in ``ln u``: ``"linear"`` (the two nodes
        around ``u``), ``"below"`` / ``"above"`` (quadratic through them and the next node below
        or above; ``{}`` where there is none)."""
        j = self._bracket(u)
        x = math.log(u)
        if order == "linear":
            xa, xb = math.log(self.nodes[j]), math.log(self.nodes[j + 1])
            t = min(max((x - xa) / (xb - xa), 0.0), 1.0)
            return {j: 1.0 - t, j + 1: t}
        idx = (j - 1, j, j + 1) if order == "below" else (j, j + 1, j + 2)
        if idx[0] < 0 or idx[-1] >= len(self.nodes):
            return {}
        xs = [math.log(self.nodes[i]) for i in idx]
        return {i: math.prod((x - xs[b]) / (xs[a] - xs[b]) for b in range(3) if b != a) for a, i in enumerate(idx)}

    def cell_at(self, work_of_adhesion: float, modulus: float, order: str = "linear") -> "InterpolatedAdhesiveCell":
        """The interpolated cell of a skin of reduced modulus ``modulus`` (Pa) and work of adhesion
        ``work_of_adhesion`` (J/m^2) on this texture (prepared family)."""
        u = unit_work(work_of_adhesion, modulus, self.length)
        return InterpolatedAdhesiveCell(self, u, float(modulus), float(work_of_adhesion), self.weights(u, order))

    def describe(self) -> dict[str, Any]:
        """JSON-ready: the family's nodes and grid."""
        return {"unit_work_nodes": list(self.nodes), "cells": len(self.nodes), "refined_cells": self.refined,
                "grid": list(self.cells[0].texture.shape), "cell_length": self.length,
                "method": "linear in ln(w / (E* Lx)) between the two nodes around each member, psi read at the "
                          "member's pull-off, transition and full-contact pressures; nodes added where two "
                          f"neighbours' transitions differ by more than x{REFINE_RATIO:g}; error: the largest "
                          "relative change of A_re at any load to the quadratic interpolants through a third "
                          "node below or above and to each neighbouring node read from its neighbours"}


class InterpolatedAdhesiveCell:
    """A member's adhesive cell read from an :class:`AdhesiveFamily` (the module docstring):
    what the adhesive pad and the coupling read of an
    :class:`~fingerpad.micro.adhesive_cell.AdhesiveUnitCell`, at modulus ``modulus`` (Pa)."""

    #: Tells the coupling to take the adhesive pad (:func:`fingerpad.coupling.predict_curve`).
    adhesive = True
    flat = False

    def __init__(self, family: AdhesiveFamily, u: float, modulus: float, work_of_adhesion: float,
                 weights: dict[int, float]) -> None:
        if not weights:
            raise FingerpadError("interpolated adhesive cell: no weights")
        self.family, self.unit_work, self.modulus = family, u, modulus
        self.length = family.length
        self.work_of_adhesion = work_of_adhesion
        self.weights = weights
        self._cells = [(family.cells[i], w) for i, w in weights.items()]
        first = self._cells[0][0]
        self.REFERENCES = first.REFERENCES
        self.law = first.law
        self.texture = first.texture
        self._unit_pull_off = -_interp_log([-c.pull_off_pressure for c, _ in self._cells], list(weights.values()))
        self._unit_work_sep = _interp_log([c.work_of_separation for c, _ in self._cells], list(weights.values()))
        # the nodes' state pressures as they report them (a pulled-in transition extrapolated,
        # their psi jumping there: AdhesiveFamily.prepare)
        self._unit_states = {name: _interp_log([c.reported_state_pressure(name) for c, _ in self._cells],
                                               list(weights.values())) for name in ("transition", "full")}
        self._marks: tuple[list[float], list[list[float]]] | None = None

    def _landmarks(self) -> tuple[list[float], list[list[float]]]:
        """The pressures (units of E*) that the member and each node share: the pull-off, 0, the
        transition and full-contact pressures where every one of them has it positive and finite
        (computed once: the cell is immutable)."""
        if self._marks is None:
            self._marks = self._find_landmarks()
        return self._marks

    def _find_landmarks(self) -> tuple[list[float], list[list[float]]]:
        mine = [self._unit_pull_off, 0.0]
        theirs = [[c.pull_off_pressure, 0.0] for c, _ in self._cells]
        for name in ("transition", "full"):
            values = [self._unit_states[name], *(c.reported_state_pressure(name) for c, _ in self._cells)]
            if all(0 < v < math.inf for v in values) and all(v > row[-1] for v, row in
                                                              zip(values, [mine, *theirs], strict=True)):
                mine.append(values[0])
                for row, v in zip(theirs, values[1:], strict=True):
                    row.append(v)
        if not all(math.isfinite(v) for v in [mine[0], *(row[0] for row in theirs)]):  # a flat: no pull-off
            mine, theirs = mine[1:], [row[1:] for row in theirs]
        return mine, theirs

    def contact_fraction(self, p: "np.ndarray | float") -> np.ndarray:
        """psi(p) at mean pressure ``p`` (Pa): the nodes' psi, weighted, each read at the pressure
        that stands where ``p / E*`` stands among the member's pull-off, zero, transition and
        full-contact pressures (:func:`morph`: a jump of psi at the transition stays one jump,
        not two half jumps); 0 below the member's pull-off pressure."""
        q = np.asarray(p, dtype=float) / self.modulus
        mine, theirs = self._landmarks()
        out = np.zeros_like(q)
        for (cell, w), marks in zip(self._cells, theirs, strict=True):
            out = out + w * cell.contact_fraction(morph(q, mine, marks))  # the nodes' E* is 1 Pa
        return np.where(q < self._unit_pull_off, 0.0, np.clip(out, 0.0, 1.0))

    @property
    def pull_off_pressure(self) -> float:
        """The member's pull-off pressure (Pa, negative)."""
        return self._unit_pull_off * self.modulus

    @property
    def work_of_separation(self) -> float:
        """The member's work of separation (J/m^2)."""
        return self._unit_work_sep * self.modulus

    def own_state_pressure(self, name: str) -> float:
        """The member's transition or full-contact pressure (Pa)."""
        return self._unit_states[name] * self.modulus

    @property
    def transition_pressure(self) -> float:
        return self.own_state_pressure("transition")

    @property
    def full_contact_pressure(self) -> float:
        return self.own_state_pressure("full")

    @property
    def transition(self) -> tuple[float, float]:
        p = self.transition_pressure
        return (p, p)

    @property
    def full(self) -> tuple[float, float]:
        p = self.full_contact_pressure
        return (p, p)

    @property
    def zero_load_fraction(self) -> float:
        return float(self.contact_fraction(np.array([0.0]))[0])

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """Pressures (Pa) where psi has kinks: the member's landmarks and every node's kinks where
        the member reads them."""
        mine, theirs = self._landmarks()
        out = {0.0, self.pull_off_pressure, *(v * self.modulus for v in mine)}
        for (cell, _), marks in zip(self._cells, theirs, strict=True):
            kinks = np.array(cell.breakpoints, dtype=float)
            out |= {float(b) * self.modulus for b in morph(kinks, marks, mine) if math.isfinite(b)}
        return tuple(sorted(out))

    def describe(self) -> dict[str, Any]:
        """JSON-ready, as :meth:`~fingerpad.micro.adhesive_cell.AdhesiveUnitCell.describe` gives it, with the nodes."""
        return {"law": self.law.name, "work_of_adhesion": self.work_of_adhesion,
                "pull_off_pressure": self.pull_off_pressure, "work_of_separation": self.work_of_separation,
                "zero_load_contact_fraction": self.zero_load_fraction, "unit_work": self.unit_work,
                "family_nodes": [self.family.nodes[i] for i in self.weights]}
