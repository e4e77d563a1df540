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
from ..coupling.members import predict_members
from ..errors import FingerpadError
from ..finger import FINGER_FIELDS, LAYER_FIELDS, Finger
from ..meso import ConstantFractionRidges
from ..micro.bem import BEMUnitCell
from ..study.run import P_HIGH, P_LOW, Prediction, load_at_centre_pressure

__all__ = ["STATES", "MemberValues", "evaluate_members", "member_cells", "member_finger",
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


def member_full_contact_loads(fingers: Sequence[Finger], pressures: Sequence[float]) -> np.ndarray:
    """Per finger, the load (N) at which its pad-centre pressure ``1.5 F / A_fr(F)`` reaches its
    cell's full-contact pressure ``pressures[i]`` (Pa): :func:`~fingerpad.study.run.load_at_centre_pressure`
    with the finger's area law called directly (``inf`` for an infinite pressure, NaN if none)."""
    return np.array([load_at_centre_pressure(finger, float(p), ridge_area=finger.ridge_area_law())
                     for finger, p in zip(fingers, pressures, strict=True)], dtype=float)


def _member_moduli(study: Any, fingers: Sequence[Finger]) -> list[float]:
    """Each finger's reduced modulus E1* (Pa) on the study's texture material (Eq. 3.4)."""
    mat_nu = study.material_poisson if study.material_poisson is not None else 0.35
    return [f.micro_modulus(study.material_modulus, mat_nu) for f in fingers]


def member_cells(study: Any, cell: BEMUnitCell, fingers: Sequence[Finger],
                 progress: Callable[[int, int], None] | None = None) -> list[Any]:
    """The BEM cell of each finger on the study's (prepared) ``cell``, prepared over what that
    finger's loads ask for: ``cell`` itself over the union of the fingers' pressures in units of
    E* (no solve when that lies inside what is cached), read at each finger's E1*; a layered
    finger whose thickness or moduli ratio differ from the study's (another unit layer) on a cell
    of its own (:meth:`~fingerpad.micro.bem.BEMUnitCell.for_skin`), prepared over its pressures.

    A sweep's cell task calls this for every point sharing a cell before any of them is
    predicted (:func:`fingerpad.design.evaluate.prepare_shared_cell`): :func:`predict_fingers`
    then solves nothing. ``progress(done, total)`` after each layered finger's cell (a cell of its
    own takes seconds to solve). Returns one response per finger."""
    loads = study.loads
    moduli = _member_moduli(study, fingers)
    if not cell.flat:
        # the pressures every finger asks for, in units of E*: one prepare covers them all
        lo, hi = math.inf, 0.0
        for f, e in zip(fingers, moduli, strict=True):
            p = loads / np.asarray(f.ridge_area(loads), float)
            lo, hi = min(lo, P_LOW * float(p.min()) / e), max(hi, P_HIGH * float(p.max()) / e)
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


#: Why a population (or a robust design) with a work of adhesion is refused.
ADHESION_REFUSED = (
    "a population of fingers with a work of adhesion: not supported yet. Each member's w / E* makes "
    "its own adhesive unit cell (a continuation of ~120 solves, ~15 s at grid 128), not one cell read at "
    "every member's modulus; predict single fingers with --work-of-adhesion (docs/model.md 6.6)")


def predict_fingers(nominal: Prediction, fingers: Sequence[Finger], *, full_contact: bool = True,
                    progress: Callable[[int, int], None] | None = None,
                    stats: dict[str, int] | None = None) -> tuple[
        list[CurvePrediction], np.ndarray, np.ndarray, list[list[str]]]:
    """Every finger on the texture of a study already predicted (``nominal``, its cell reused).

    The BEM cell is prepared over the union of the fingers' pressures in units of E* (no solve
    when that lies inside what is cached: psi depends on p/E* only) and read at each finger's E1*
    (Eq. 3.4); with the Hertz model each finger gets its own per-asperity cell (no solve).
    ``full_contact=False`` skips the search of the full-contact loads (NaN then; the robust
    design's screen does not use them). ``progress``: as for :func:`member_cells`; ``stats``, if
    given, gets ``own_cells`` (members on a BEM cell of their own) and ``solves`` (unit-cell
    solves the members added, 0 when the cache held them).

    Returns
    -------
    curves, critical_load, full_contact_load, states
        Per finger: its :class:`~fingerpad.coupling.CurvePrediction`, its critical and
        full-contact loads (N; ``inf`` if never reached, full contact NaN for Hertz) and the
        contact state at the pad centre at each load.
    """
    if nominal.adhesion is not None or any(f.adhesive for f in fingers):
        raise FingerpadError(ADHESION_REFUSED)
    from ..micro.hertz import hertz_cell_for

    study = nominal.study
    moduli = _member_moduli(study, fingers)
    loads = study.loads
    cell = nominal.cell
    if nominal.bem is not None:
        before = int(getattr(cell, "solves", 0) or 0)
        cells = member_cells(study, cell, fingers, progress)
        own = {i for i, c in enumerate(cells) if isinstance(c, BEMUnitCell)}
        if stats is not None:
            stats["own_cells"] = len(own)
            stats["solves"] = int(getattr(cell, "solves", 0) or 0) - before + sum(int(cells[i].solves) for i in own)
        shared = [i for i in range(len(fingers)) if i not in own]
        curves = [None] * len(fingers)
        if shared:
            done = predict_members(loads, [fingers[i] for i in shared], cell, [moduli[i] for i in shared])
            for i, curve in zip(shared, done, strict=True):
                curves[i] = curve
        for i in sorted(own):
            curves[i] = predict_curve(loads, fingers[i], cells[i])
        crit = [c.critical_load for c in curves]
        if cell.flat:
            full = np.zeros(len(fingers))
        elif full_contact:
            full = member_full_contact_loads(fingers, [c.full_contact_pressure for c in cells])
        else:
            full = np.full(len(fingers), math.nan)
    else:
        cells = [hertz_cell_for(nominal.texture, e)[0] for e in moduli]
        curves = predict_members(loads, fingers, cells)
        crit = [c.critical_load_hertz if c.critical_load_hertz is not None else math.nan for c in curves]
        full = np.full(len(fingers), math.nan)
    # centre_state's comparisons (peak >= pf: full, >= pt: transition), on arrays
    peak = np.array([1.5 * curve.load / curve.ridge_area for curve in curves])
    pt = np.array([[float(c.transition_pressure)] for c in cells])
    pf = np.array([[float(c.full_contact_pressure)] for c in cells])
    codes = np.where(peak >= pf, 2, np.where(peak >= pt, 1, 0))
    states = [[STATES[k] for k in row] for row in codes.tolist()]
    return curves, np.asarray(crit, float), np.asarray(full, float), states


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


def evaluate_members(nominal: Prediction, fingers: Sequence[Finger]) -> MemberValues:
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

    Returns
    -------
    MemberValues
    """
    curves, crit, full, states = predict_fingers(nominal, fingers)
    codes = {s: i for i, s in enumerate(STATES)}

    def rows(name: str) -> np.ndarray:
        return np.array([np.asarray(getattr(c, name), float) for c in curves])

    return MemberValues(rows("area_ratio"), rows("mu"), rows("mu_ref"), rows("mu_normalised"), crit, full,
                        np.array([[codes[s] for s in row] for row in states], dtype=np.int8))


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
    lower = np.quantile(v, q, axis=0, method="lower")
    upper = np.quantile(v, q, axis=0, method="higher")
    pos = q * (v.shape[0] - 1)
    frac = (pos - np.floor(pos)).reshape((q.size,) + (1,) * (v.ndim - 1))
    fix = np.isnan(res) & ~np.isnan(lower) & ~np.isnan(upper)
    repl = np.where(lower == upper, lower, np.where(frac > 0, upper, lower))
    return np.where(fix, repl, res)
