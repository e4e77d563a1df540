"""A population of adhesive fingers on one texture: one family of adhesive cells, each member
read from it (docs/population.md, "Adhesion").

Each member's adhesive cell depends on its ``u = w / (E1* Lx)`` (its work of adhesion over its
reduced modulus on the texture's material and the cell length), so the members cannot share one
cell read at their moduli as non-adhesive members do. The family
(:class:`~fingerpad.micro.adhesive_family.AdhesiveFamily`) solves cells at a few global nodes of
``u`` over the members' range (at most :data:`~fingerpad.micro.adhesive_family.MAX_FAMILY_CELLS`),
on the grid of the nominal prediction's cell, and every member's curve is
:func:`~fingerpad.coupling.predict_curve` on its interpolated cell, with its estimated
interpolation error of the real area ``A_re`` (and so of ``mu``) beside it. SI units.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..coupling import CurvePrediction, predict_curve
from ..errors import FingerpadError
from ..finger import Finger
from ..micro.adhesive_family import REFINE_RATIO, AdhesiveFamily, family_nodes, unit_work

__all__ = ["ADHESION_MIXED", "AdhesiveMembers", "member_family", "predict_adhesive_members"]

#: Why a population of which some members adhere and some do not is refused.
ADHESION_MIXED = (
    "a population in which some members have a work of adhesion and others none: the adhesive and the "
    "non-adhesive model are two models (JKR pad, adhesive cells), not two values of one; draw work_of_adhesion "
    "above 0 for every member (e.g. low = 0.01J/m2), or leave it out of the population")

#: How many families :func:`member_family` keeps in this process (a sweep's points and the
#: Sobol indices reuse the one of their members; with the curve cache off it would be solved again).
FAMILIES_KEPT = 2
_families: dict[Any, AdhesiveFamily] = {}


@dataclass
class AdhesiveMembers:
    """The members of an adhesive population on one texture (SI units).

    Attributes
    ----------
    curves
        Each member's :class:`~fingerpad.coupling.CurvePrediction` on its interpolated cell.
    cells
        Each member's :class:`~fingerpad.micro.adhesive_family.InterpolatedAdhesiveCell`.
    interpolation_error
        ``(members,)``: the estimated relative interpolation error of the member's ``A_re``
        (the largest over its loads).
    pull_off_force
        ``(members,)``, N: each member's pull-off force.
    family
        The :class:`~fingerpad.micro.adhesive_family.AdhesiveFamily`.
    pull_off_error
        ``(members,)``: the estimated relative interpolation error of the member's pull-off force
        (that of its cell's work of separation, Eq. 3.18).
    """

    curves: list[CurvePrediction]
    cells: list[Any]
    interpolation_error: np.ndarray
    pull_off_force: np.ndarray
    family: AdhesiveFamily
    pull_off_error: np.ndarray

    def describe(self) -> dict[str, Any]:
        """The ``adhesion`` entry of a population's JSON."""
        err = self.interpolation_error
        return {**self.family.describe(), "family_solves": self.family.solves,
                "interpolation_error_max": float(np.max(err)) if err.size else math.nan,
                "interpolation_error_median": float(np.median(err)) if err.size else math.nan,
                "pull_off_force_error_max": float(np.max(self.pull_off_error)) if err.size else math.nan}


def member_family(study: Any, cell: Any, fingers: Sequence[Finger], moduli: Sequence[float],
                  progress: Callable[[int, int], None] | None = None) -> AdhesiveFamily:
    """The prepared family of adhesive cells for ``fingers`` (reduced moduli ``moduli``, Pa) on the
    texture of the study's prepared ``cell`` (its grid), with the study's solver settings and the
    study finger's adhesion range and law.

    Raises
    ------
    FingerpadError
        A finger without adhesion among them (:data:`ADHESION_MIXED`).
    """
    from ..micro.bem import periodic_cell
    from ..study.states import texture_maker

    if any(not f.adhesive for f in fingers):
        raise FingerpadError(ADHESION_MIXED)
    _, _, length = periodic_cell(cell.texture, 1.0)
    us = [unit_work(f.work_of_adhesion, e, length) for f, e in zip(fingers, moduli, strict=True)]
    nodes = family_nodes(min(us), max(us))
    finger = study.finger
    options = {"law": finger.adhesion_law, "adhesion_range": finger.adhesion_range, "tol": study.tol,
               "max_iter": study.max_iter, "cache": study.curve_cache()}
    family = AdhesiveFamily(cell.texture, nodes, **options)
    key = (tuple(c.key for c in family.cells), finger.adhesion_law, finger.adhesion_range)
    kept = _families.get(key)
    if kept is not None:
        kept.solves = 0  # nothing solved for this call
        if progress is not None:
            progress(len(nodes), len(nodes))
        return kept
    # pulled-in nodes extrapolated as a single prediction's cell (study.states, docs/model.md 6.6);
    # more nodes where the transition moves fast with u (AdhesiveFamily.refine)
    family.prepare(progress, texture_maker(study), refine=True)
    while len(_families) >= FAMILIES_KEPT:
        del _families[next(iter(_families))]
    _families[key] = family
    return family


def predict_adhesive_members(study: Any, cell: Any, fingers: Sequence[Finger], moduli: Sequence[float],
                             progress: Callable[[int, int], None] | None = None,
                             estimate: bool = True) -> AdhesiveMembers:
    """Every adhesive finger on the texture of the study's prepared ``cell``: the family
    (:func:`member_family`), each member's interpolated cell and its
    :func:`~fingerpad.coupling.predict_curve` (the adhesive pad, Eqs. 3.15-3.18), and the
    estimated interpolation error of its ``A_re`` (``estimate=False``: NaN, skipped)."""
    family = member_family(study, cell, fingers, moduli, progress)
    loads = np.asarray(study.loads, dtype=float)
    cells, curves, errors, pull_off = [], [], [], []
    for f, e in zip(fingers, moduli, strict=True):
        member = family.cell_at(f.work_of_adhesion, e)
        curve = predict_curve(loads, f, member)
        cells.append(member)
        curves.append(curve)
        pull_off.append(float(curve.adhesion["pull_off_force"]) if curve.adhesion else 0.0)
        if not estimate:
            errors.append((math.nan, math.nan))
            continue
        errors.append(_interpolation_error(family, f, e, np.asarray(curve.real_area, float), loads))
    err = np.asarray(errors, float).reshape(-1, 2)
    return AdhesiveMembers(curves, cells, err[:, 0], np.asarray(pull_off, float), family, err[:, 1])


def _relative(a: np.ndarray, b: np.ndarray) -> float:
    """The largest ``|a / b - 1|``: how far ``a`` lies from ``b`` taken as the truth (0 where both
    are 0, inf where only ``b`` is)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(b > 0, np.abs(a / np.where(b > 0, b, 1.0) - 1.0), np.where(a > 0, math.inf, 0.0))
    return float(np.max(rel)) if rel.size else 0.0


def _regime(family: AdhesiveFamily, i: int) -> bool:
    """Whether node ``i``'s cell is held in full contact by adhesion alone (full contact at p <= 0)."""
    return bool(family.cells[i].full_contact_pressure <= 0)


def _interpolation_error(family: AdhesiveFamily, finger: Finger, modulus: float, ratio: np.ndarray,
                         loads: np.ndarray) -> tuple[float, float]:
    """The estimated relative error of a member's interpolated real area ``A_re`` (``ratio`` at
    ``loads``): the largest of (a) its change to the quadratic interpolants through a third node
    below or above (the leading term of the linear interpolation's error) and (b) at each of the
    member's two nodes that has neighbours on both sides, the change of that node's own
    ``A_re`` (the member's finger with the node's ``w / (E* Lx)``) when the node is left out
    and read from its neighbours instead (twice the spacing: an upper estimate of the smooth
    part, and the nodes' own scatter, which (a) does not see). Returns it and the same estimate of
    the work of separation (the pull-off force's relative error: Eq. 3.18 is linear in it)."""
    from ..micro.adhesive_family import InterpolatedAdhesiveCell
    from ..micro.adhesive_pad import adhesive_pad

    def real_area(f: Finger, cell: Any) -> np.ndarray:
        # A_re, not A_re/A_fr: the pad's ridge area moves with the work of separation (Eq. 3.18)
        return adhesive_pad(f, cell).real_area(loads)

    u = unit_work(finger.work_of_adhesion, modulus, family.length)
    pair = list(family.weights(u))
    regime = {_regime(family, i) for i in pair}
    # (the stencil's nodes share the member's regime, the change of A_re, of the work of separation)
    found: list[tuple[bool, float, float]] = []
    work = family.cell_at(finger.work_of_adhesion, modulus).work_of_separation
    for order in ("below", "above"):
        weights = family.weights(u, order)
        if weights:
            alt = InterpolatedAdhesiveCell(family, u, modulus, finger.work_of_adhesion, weights)
            found.append(({_regime(family, i) for i in weights} == regime,
                          _relative(ratio, real_area(finger, alt)), abs(work / alt.work_of_separation - 1)))
    for i in pair:
        if 0 < i < len(family.nodes) - 1:
            w_node = family.nodes[i] * modulus * family.length
            at_node = finger.with_overrides(work_of_adhesion=w_node)
            exact = InterpolatedAdhesiveCell(family, family.nodes[i], modulus, w_node, {i: 1.0})
            # the node from its neighbours, linearly in ln u (equally spaced: half each), across twice
            # the spacing: not scaled down to the member's spacing (measured: the nodes' own scatter at
            # a coarse grid, 0.5-1 % of A_re at grid 32, does not shrink with the spacing)
            t = _between(family.nodes, i)
            left_out = InterpolatedAdhesiveCell(family, family.nodes[i], modulus, w_node, {i - 1: 1 - t, i + 1: t})
            # on a refined family (AdhesiveFamily.refine) the neighbours may lie closer than the
            # member's nodes: the change is scaled up to the member's spacing (the leading error of
            # linear interpolation, t (1 - t) H^2 / 2 f'', is h^2 / 2 f'' on equal spacings h),
            # never down (1 on the global grid)
            scale = _spacing_scale(family.nodes, i, pair)
            found.append(({_regime(family, i - 1), _regime(family, i + 1)} == regime,
                          scale * _relative(real_area(at_node, left_out), real_area(at_node, exact)),
                          scale * abs(left_out.work_of_separation / exact.work_of_separation - 1)))
    if len(regime) > 1 or _unresolved_jump(family, min(pair)):
        # the member's nodes straddle a change of regime, a jump in u: its value is either side's,
        # so the change to each node alone (read at the member's u) counts too (the work of
        # separation, smooth in u, only across a change of regime)
        for i in pair:
            alone = InterpolatedAdhesiveCell(family, u, modulus, finger.work_of_adhesion, {i: 1.0})
            found.append((True, _relative(ratio, real_area(finger, alone)),
                          abs(work / alone.work_of_separation - 1) if len(regime) > 1 else 0.0))
    # a stencil across a change of regime (adhesion alone holding full contact at zero load: psi = 1
    # at every p >= 0) tells nothing of a member's interval inside one regime; where the member's
    # two nodes straddle it, or no stencil stays inside, every stencil counts
    inside = [(a, b) for ok, a, b in found if ok] if len(regime) == 1 else []
    counted = inside or [(a, b) for _, a, b in found]
    return max(a for a, _ in counted), max(max(b for _, b in counted), _work_scatter(family, regime))


def _work_scatter(family: AdhesiveFamily, regime: set[bool]) -> float:
    """The scatter of the nodes' work of separation over the whole family (inside the member's
    regime): the largest change of a node's ``W`` read from its two neighbours. The pull-apart's
    steps make ``W(u)`` zigzag from node to node by a few tenths of a percent (measured at grid 64:
    -0.7 to +0.9 %), which the two nodes next to a member need not show."""
    w = [c.work_of_separation / u for c, u in zip(family.cells, family.nodes, strict=True)]
    worst = 0.0
    for i in range(1, len(w) - 1):
        if {_regime(family, j) for j in (i - 1, i, i + 1)} == regime:
            t = _between(family.nodes, i)
            worst = max(worst, abs(w[i - 1] ** (1 - t) * w[i + 1] ** t / w[i] - 1) if t != 0.5
                        else abs(math.sqrt(w[i - 1] * w[i + 1]) / w[i] - 1))
    return worst


def _unresolved_jump(family: AdhesiveFamily, j: int) -> bool:
    """Whether the state pressures of nodes ``j`` and ``j + 1`` still differ by more than the
    refinement's factor (it stopped at its level or its cap) *and* change in ``ln u`` more than
    twice as fast as in each neighbouring interval: a step between the two nodes rather than the
    curvature the other stencils see (measured on the README caps at grid 64, w 0.3 J/m2: the
    reported transition falls x1.4 within 1/24 decade of u where the extrapolation from the half
    grids changes form, and x2.2 within 1/48 where the half grid stops being pulled in). A member
    there may take either node's A_re."""
    def slope(k: int) -> float:
        return family.jump(k) / math.log(family.nodes[k + 1] / family.nodes[k])

    if family.jump(j) <= math.log(REFINE_RATIO):
        return False
    around = [slope(k) for k in (j - 1, j + 1) if 0 <= k < len(family.nodes) - 1]
    return not around or slope(j) > 2 * max(around)


def _spacing_scale(nodes: Sequence[float], i: int, pair: Sequence[int]) -> float:
    """How much wider (squared) the member's interval ``pair`` is than the spacings around node
    ``i`` in ``ln u``: ``max(1, h^2 / (h_1 h_2))``, exactly 1 where they are equal."""
    h1, h2 = math.log(nodes[i] / nodes[i - 1]), math.log(nodes[i + 1] / nodes[i])
    h = math.log(nodes[max(pair)] / nodes[min(pair)])
    scale = h * h / (h1 * h2)
    return scale if scale > 1 + 1e-9 else 1.0


def _between(nodes: Sequence[float], i: int) -> float:
    """Where node ``i`` lies between its neighbours in ``ln u`` (0.5 on the global grid; a refined
    family's nodes (:meth:`~fingerpad.micro.adhesive_family.AdhesiveFamily.refine`) need not be)."""
    t = math.log(nodes[i] / nodes[i - 1]) / math.log(nodes[i + 1] / nodes[i - 1])
    return 0.5 if abs(t - 0.5) < 1e-9 else t
