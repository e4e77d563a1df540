"""A population's members on one texture: the package's one member path (issue 22, "a population
must not cost a population of BEM solves"), used by ``predict --population``
(:func:`~fingerpad.population.run.run_population`), the Sobol indices, sweeps with a population
(:func:`~fingerpad.population.members.evaluate_members`) and the robust design's screen
(:class:`fingerpad.design.robust.MemberTable`).

:func:`member_finger` makes a member's finger from the study's; :func:`member_cells` prepares
the study's unit cell once over what every member asks for; :func:`predict_fingers` then runs
the members on it through the coupling's vectorised twin of ``predict_curve``
(:func:`fingerpad.coupling.members.predict_members`), :func:`member_full_contact_loads` gives
their full-contact loads, :func:`evaluate_members` packs them as arrays and
:func:`member_quantiles` takes quantiles over members that keep ``inf`` (a load never reached).
SI units (m, N, Pa).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..coupling import CurvePrediction, predict_curve
from ..coupling.loads import FingerStack, centre_loads
from ..coupling.members import MemberCurves, member_curves, predict_members
from ..errors import FingerpadError
from ..finger import FINGER_FIELDS, LAYER_FIELDS, Finger
from ..meso import ConstantFractionRidges
from ..micro.bem import BEMUnitCell
from ..study.run import P_HIGH, P_LOW, Prediction

__all__ = ["STATES", "MemberValues", "evaluate_members", "member_cells", "member_finger", "member_fingers",
           "member_full_contact_loads", "member_quantiles", "predict_fingers"]

#: Contact states at the pad centre, in the order of their codes (0, 1, 2).
STATES: tuple[str, ...] = ("asperity", "transition", "full")


def member_finger(finger: Finger, params: Mapping[str, float]) -> Finger:
    """The study's finger with a member's parameters (SI): the finger's own fields, and the ridge
    fraction as a constant-fraction ridge model; a parameter of the person that is not the
    finger's (declared in :data:`~.distributions.POPULATION_PARAMS`) is left to whoever reads it."""
    values = {k: v for k, v in params.items() if k in FINGER_FIELDS}
    if "ridge_fraction" in params:
        if not isinstance(finger.ridges, ConstantFractionRidges):
            raise FingerpadError("population ridge_fraction: the study's finger must use the constant-fraction "
                                 f"ridge model, not {type(finger.ridges).__name__}")
        values["ridges"] = ConstantFractionRidges(params["ridge_fraction"])
    layered = sorted(set(values) & set(LAYER_FIELDS))
    if layered and finger.skin != "layered":
        # Said in the population's terms: the finger's own check ("a layered skin needs ...
        # missing") names fields the user never asked the population for.
        raise FingerpadError(f"population {', '.join(layered)}: the study's finger has a half-space skin; a "
                             "population of layered skins needs a layered finger (--finger layered, or the "
                             "[finger] keys skin_layer_thickness, skin_layer_modulus, skin_substrate_modulus)")
    return finger.with_overrides(**values) if values else finger


#: How many (finger, members) pairs :func:`member_fingers` keeps (a sweep's points share one).
MEMBER_SETS_KEPT = 4
_member_sets: dict[Any, tuple[tuple[Finger, ...], FingerStack]] = {}


def member_fingers(finger: Finger, members: Sequence[Mapping[str, float]]) -> tuple[tuple[Finger, ...], FingerStack]:
    """``[member_finger(finger, m) for m in members]`` and their :class:`~fingerpad.coupling.members.FingerStack`,
    kept for the last :data:`MEMBER_SETS_KEPT` pairs asked (keyed by the finger and the members'
    values): a sweep's points with one finger share its members, and building 1,000 checked
    fingers took longer than coupling them. The fingers are immutable and equal to fresh ones,
    so what is kept changes no number."""
    key = (finger, tuple(tuple(sorted(m.items())) for m in members))
    found = _member_sets.get(key)
    if found is None:
        fingers = tuple(member_finger(finger, m) for m in members)
        found = (fingers, FingerStack(fingers))
        while len(_member_sets) >= MEMBER_SETS_KEPT:
            del _member_sets[next(iter(_member_sets))]
        _member_sets[key] = found
    return found


def member_full_contact_loads(fingers: Sequence[Finger], pressures: Sequence[float],
                              stack: FingerStack | None = None) -> np.ndarray:
    """Per finger, the load (N) at which its pad-centre pressure ``1.5 F / A_fr(F)`` reaches its
    cell's full-contact pressure ``pressures[i]`` (Pa), all fingers in one search
    (:func:`~fingerpad.coupling.loads.centre_loads`; ``inf`` for an infinite pressure, NaN if
    none): :func:`~fingerpad.study.states.load_at_centre_pressure` of each finger, bit for bit.
    ``stack``: the fingers' stack if one is at hand."""
    return centre_loads(FingerStack(fingers) if stack is None else stack, np.asarray(pressures, dtype=float))


def _member_moduli(study: Any, fingers: Sequence[Finger]) -> list[float]:
    """Each finger's reduced modulus E1* (Pa) on the study's texture material (Eq. 3.4)."""
    mat_nu = study.material_poisson if study.material_poisson is not None else 0.35
    return [f.micro_modulus(study.material_modulus, mat_nu) for f in fingers]


def member_cells(study: Any, cell: BEMUnitCell, fingers: Sequence[Finger],
                 progress: Callable[[int, int], None] | None = None,
                 stack: FingerStack | None = None) -> list[Any]:
    """The BEM cell of each finger on the study's (prepared) ``cell``, prepared over what that
    finger's loads ask for: ``cell`` itself over the union of the fingers' pressures in units of
    E* (no solve when that lies inside what is cached), read at each finger's E1*; a layered
    finger whose thickness or moduli ratio differ from the study's (another unit layer) on a cell
    of its own (:meth:`~fingerpad.micro.bem.BEMUnitCell.for_skin`), prepared over its pressures.

    A sweep's cell task calls this for every point sharing a cell before any of them is
    predicted (:func:`fingerpad.design.evaluate.prepare_shared_cell`): :func:`predict_fingers`
    then solves nothing. ``progress(done, total)`` after each layered finger's cell (a cell of its
    own takes seconds to solve); ``stack``: the fingers' :class:`~fingerpad.coupling.members.FingerStack`
    if one is at hand. Returns one response per finger."""
    loads = study.loads
    moduli = _member_moduli(study, fingers)
    if getattr(cell, "adhesive", False) or any(f.adhesive for f in fingers):
        from .adhesion import member_family  # adhesive members: one family of cells, each interpolated

        family = member_family(study, cell, fingers, moduli, progress)
        return [family.cell_at(f.work_of_adhesion, e) for f, e in zip(fingers, moduli, strict=True)]
    if not cell.flat:
        # the pressures every finger asks for, in units of E*: one prepare covers them all
        # every finger's A_fr at the loads in one evaluation (FingerStack: each row the bits of
        # finger.ridge_area(loads))
        f_rows = np.tile(np.asarray(loads, dtype=float), (len(fingers), 1))
        p_rows = f_rows / (FingerStack(fingers) if stack is None else stack).ridge_area(f_rows)
        # per finger the same product and quotient a loop over the fingers took, in one pass
        # (1,000 members: ~10 ms a sweep point of Python, issue 34); fmin/fmax from inf/0 skip a
        # finger whose row holds a NaN, as the loop's min()/max() did
        e = np.asarray(moduli, dtype=float)
        lo = float(np.fmin.reduce(P_LOW * p_rows.min(axis=1) / e, initial=math.inf))
        hi = float(np.fmax.reduce(P_HIGH * p_rows.max(axis=1) / e, initial=0.0))
        cell.prepare(lo * cell.modulus, hi * cell.modulus)
    cells: list[Any] = []
    layered = sum(1 for f in fingers if not (f.layer is None and cell.layer is None))
    done = 0
    for f, e in zip(fingers, moduli, strict=True):
        if f.layer is None and cell.layer is None:
            cells.append(cell.at_modulus(e))
            continue
        p = loads / np.asarray(f.ridge_area(loads), float)
        cells.append(cell.for_skin(e, f.layer, (P_LOW * float(p.min()), P_HIGH * float(p.max()))))
        done += 1
        if progress is not None:
            progress(done, layered)
    return cells


def _predict_codes(nominal: Prediction, fingers: Sequence[Finger], *, full_contact: bool = True,
                    progress: Callable[[int, int], None] | None = None,
                    stats: dict[str, Any] | None = None, stack: FingerStack | None = None) -> tuple[
        _Rows, np.ndarray, np.ndarray, np.ndarray]:
    """:func:`predict_fingers` with the curves as rows of arrays and the centre states as their
    codes, ``(members, loads)`` int8."""
    from ..micro.hertz import hertz_cell_for

    study = nominal.study
    moduli = _member_moduli(study, fingers)
    loads = study.loads
    cell = nominal.cell
    if nominal.bem is not None and (nominal.adhesion is not None or any(f.adhesive for f in fingers)):
        return _adhesive_codes(nominal, fingers, moduli, full_contact, progress, stats)
    if nominal.bem is not None:
        before = int(getattr(cell, "solves", 0) or 0)
        stack = FingerStack(fingers) if stack is None else stack
        cells = member_cells(study, cell, fingers, progress, stack)
        own = {i for i, c in enumerate(cells) if isinstance(c, BEMUnitCell)}
        if stats is not None:
            stats["own_cells"] = len(own)
            stats["solves"] = int(getattr(cell, "solves", 0) or 0) - before + sum(int(cells[i].solves) for i in own)
        shared = [i for i in range(len(fingers)) if i not in own]
        table: MemberCurves | None = None
        curves: list[Any] | None = None
        if not own:  # every member on the one cell: arrays throughout
            table = member_curves(loads, stack, cell, moduli)
            crit = table.critical_load
        else:
            curves = [None] * len(fingers)
            if shared:
                done = predict_members(loads, [fingers[i] for i in shared], cell, [moduli[i] for i in shared],
                                       stack=stack.subset(shared))
                for i, curve in zip(shared, done, strict=True):
                    curves[i] = curve
            for i in sorted(own):
                curves[i] = predict_curve(loads, fingers[i], cells[i])
            crit = [c.critical_load for c in curves]
        if cell.flat:
            full = np.zeros(len(fingers))
        elif full_contact:
            full = member_full_contact_loads(fingers, [c.full_contact_pressure for c in cells], stack)
        else:
            full = np.full(len(fingers), math.nan)
    else:
        cells = [hertz_cell_for(nominal.texture, e)[0] for e in moduli]
        curves = predict_members(loads, fingers, cells)
        table = None
        crit = [c.critical_load_hertz if c.critical_load_hertz is not None else math.nan for c in curves]
        full = np.full(len(fingers), math.nan)
    # centre_state's comparisons (peak >= pf: full, >= pt: transition), on arrays
    if table is not None:
        peak = 1.5 * table.load / table.rows["ridge_area"]
    else:
        peak = np.array([1.5 * curve.load / curve.ridge_area for curve in curves])  # type: ignore[union-attr]
    pt = np.array([[float(c.transition_pressure)] for c in cells])
    pf = np.array([[float(c.full_contact_pressure)] for c in cells])
    codes = np.where(peak >= pf, 2, np.where(peak >= pt, 1, 0)).astype(np.int8)
    return _Rows(table, curves), np.asarray(crit, float), np.asarray(full, float), codes


class _Rows:
    """The members' curves, as the arrays of :func:`~fingerpad.coupling.members.member_curves`
    (all members on one cell) or as a list (members on cells of their own, Hertz cells)."""

    def __init__(self, table: MemberCurves | None, curves: list[Any] | None) -> None:
        self.table, self._curves = table, curves

    def curves(self) -> list[CurvePrediction]:
        return self._curves if self._curves is not None else self.table.curves()  # type: ignore[union-attr]

    def rows(self, name: str) -> np.ndarray:
        """``(members, loads)`` array of a per-load field."""
        if self.table is not None:
            return np.asarray(self.table.rows[name], float)
        return np.array([np.asarray(getattr(c, name), float) for c in self._curves])  # type: ignore[union-attr]


def _adhesive_codes(nominal: Prediction, fingers: Sequence[Finger], moduli: Sequence[float], full_contact: bool,
                    progress: Callable[[int, int], None] | None, stats: dict[str, Any] | None) -> tuple[
        _Rows, np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_predict_codes` of adhesive members: each on its cell interpolated from one family
    (:func:`~.adhesion.predict_adhesive_members`); the critical and full-contact loads and the
    centre states from the adhesive pad's centre pressure (Eq. 3.17), as a prediction takes them."""
    from ..micro.adhesive_pad import adhesive_pad
    from ..study.states import centre_load
    from .adhesion import predict_adhesive_members

    study = nominal.study
    done = predict_adhesive_members(study, nominal.cell, fingers, moduli, progress)
    if stats is not None:
        stats["own_cells"] = 0
        stats["solves"] = done.family.solves
        stats["adhesion"] = done
    loads = np.asarray(study.loads, dtype=float)
    crit = np.array([c.critical_load for c in done.curves], float)
    full = np.array([centre_load(f, c)(c.full_contact_pressure) if full_contact else math.nan
                     for f, c in zip(fingers, done.cells, strict=True)], float)
    codes = np.zeros((len(fingers), loads.size), np.int8)
    for i, (f, c, curve) in enumerate(zip(fingers, done.cells, done.curves, strict=True)):
        centre = adhesive_pad(f, c).centre_pressure(loads, curve.ridge_area)
        codes[i] = np.where(centre >= c.full_contact_pressure, 2, np.where(centre >= c.transition_pressure, 1, 0))
    return _Rows(None, done.curves), crit, full, codes


def predict_fingers(nominal: Prediction, fingers: Sequence[Finger], *, full_contact: bool = True,
                    progress: Callable[[int, int], None] | None = None,
                    stats: dict[str, Any] | None = None, stack: FingerStack | None = None) -> tuple[
        list[CurvePrediction], np.ndarray, np.ndarray, list[list[str]]]:
    """Every finger on the texture of a study already predicted (``nominal``, its cell reused).

    The BEM cell is prepared over the union of the fingers' pressures in units of E* (no solve
    when that lies inside what is cached: psi depends on p/E* only) and read at each finger's E1*
    (Eq. 3.4); with the Hertz model each finger gets its own per-asperity cell (no solve).
    Adhesive fingers (with the BEM) are each read from one family of adhesive cells
    (:func:`~.adhesion.predict_adhesive_members`; ``progress`` after each of its cells, ``stats``
    gets ``adhesion``, their :class:`~.adhesion.AdhesiveMembers`). ``full_contact=False`` skips the search of the full-contact loads (NaN then; the robust
    design's screen does not use them). ``progress``: as for :func:`member_cells`; ``stats``, if
    given, gets ``own_cells`` (members on a BEM cell of their own) and ``solves`` (unit-cell
    solves the members added, 0 when the cache held them); ``stack``: the fingers' stack if one
    is at hand (:func:`member_fingers`).

    Returns
    -------
    curves, critical_load, full_contact_load, states
        Per finger: its :class:`~fingerpad.coupling.CurvePrediction` (equal to
        :func:`~fingerpad.coupling.predict_curve`'s, bit for bit), its critical and full-contact
        loads (N; ``inf`` if never reached, full contact NaN for Hertz; all members' in one
        search, :func:`~fingerpad.coupling.loads.centre_loads`, the one a prediction takes) and
        the contact state at the pad centre at each load.
    """
    rows, crit, full, codes = _predict_codes(nominal, fingers, full_contact=full_contact, progress=progress,
                                             stats=stats, stack=stack)
    return rows.curves(), crit, full, [[STATES[k] for k in row] for row in codes.tolist()]


@dataclass
class MemberValues:
    """Each member's numbers on one texture (arrays, members first; SI units).

    Attributes
    ----------
    area_ratio, mu, mu_ref, mu_normalised
        ``(members, loads)``: A_re/A_fr, mu (Eq. 2.1), mu on the flat reference, mu/mu_ref.
    critical_load, full_contact_load
        ``(members,)``, N: the load at which the pad centre reaches the member's transition and
        full contact (``inf`` never; NaN none in :data:`~fingerpad.micro.response.DEFAULT_LOAD_RANGE`; full contact NaN
        with the Hertz cell, 0 on a flat texture).
    states
        ``(members, loads)`` int8 codes of :data:`STATES` at the pad centre.
    """

    area_ratio: np.ndarray
    mu: np.ndarray
    mu_ref: np.ndarray
    mu_normalised: np.ndarray
    critical_load: np.ndarray
    full_contact_load: np.ndarray
    states: np.ndarray


def evaluate_members(nominal: Prediction, fingers: Sequence[Finger], stack: FingerStack | None = None) -> MemberValues:
    """The members' numbers on the nominal prediction's texture as arrays (a sweep point's
    population): :func:`predict_fingers`, so every member's numbers are those of a plain
    :func:`~fingerpad.coupling.predict_curve` of that member, bit for bit.

    Parameters
    ----------
    nominal
        The study's :class:`~fingerpad.study.run.Prediction` (its cell is reused; the BEM cell is
        prepared over the members' pressures, solving only what they add).
    fingers
        The members' fingers (:func:`member_finger`).
    stack
        Their :class:`~fingerpad.coupling.members.FingerStack` if one is at hand (:func:`member_fingers`).

    Returns
    -------
    MemberValues
    """
    table, crit, full, codes = _predict_codes(nominal, fingers, stack=stack)
    return MemberValues(table.rows("area_ratio"), table.rows("mu"), table.rows("mu_ref"), table.rows("mu_normalised"),
                        crit, full, codes)


def member_quantiles(values: np.ndarray, levels: Sequence[float], drop_nan: bool = False) -> np.ndarray:
    """Quantiles (numpy's default linear interpolation) of ``values`` along its first axis,
    one row per level; infinite values are kept as such (numpy gives NaN between two infinities:
    here the quantile between two infinite members is ``inf``). ``drop_nan``: members with NaN
    are left out per column (a load that none reaches); all NaN gives NaN."""
    v = np.asarray(values, float)
    q = np.asarray(levels, float)
    if drop_nan:
        cols = v.reshape(v.shape[0], -1)
        res = np.full((q.size, cols.shape[1]), np.nan)
        for c in range(cols.shape[1]):
            finite = cols[~np.isnan(cols[:, c]), c]
            if finite.size:
                res[:, c] = member_quantiles(finite, q)
        return res.reshape((q.size, *v.shape[1:]))
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # inf - inf inside numpy's interpolation
        res = np.quantile(v, q, axis=0)
    if not np.isnan(res).any():  # nothing to mend (the two quantiles below cost as much again)
        return res
    lower = np.quantile(v, q, axis=0, method="lower")
    upper = np.quantile(v, q, axis=0, method="higher")
    pos = q * (v.shape[0] - 1)
    frac = (pos - np.floor(pos)).reshape((q.size,) + (1,) * (v.ndim - 1))
    fix = np.isnan(res) & ~np.isnan(lower) & ~np.isnan(upper)
    repl = np.where(lower == upper, lower, np.where(frac > 0, upper, lower))
    return np.where(fix, repl, res)
