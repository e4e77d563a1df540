"""Many fingers on one texture at once: the package's one member path (issue 22, "a population
must not cost a population of BEM solves"), used by ``predict --population``
(:func:`~fingerpad.study.population.run_population`), the sensitivity analysis, sweeps with a
population (:func:`~fingerpad.study.members.evaluate_members`) and the robust design's screen
(:class:`fingerpad.design.robust.MemberTable`).

:func:`predict_members` gives, for each finger, the :class:`~fingerpad.coupling.CurvePrediction`
that :func:`~fingerpad.coupling.predict_curve` gives for that finger on ``cell.at_modulus(E1*)``
(the one unit cell read at the member's modulus by p/E* scaling), to the bit: the same pad
pressures (Eq. 3.7), the same exact integral of the cell's interpolated psi (Eq. 3.11,
:func:`~fingerpad.coupling.disc_ratio`: the antiderivative tabulated at the cell's nodes, one
Gauss-Legendre piece per member and load, each entry computed on its own), the same friction
(Eqs. 2.1-2.4) and the same root finder for the critical load, with each finger's area law
built once (:meth:`~fingerpad.finger.Finger.ridge_area_law`). The members go through in blocks
(:data:`BLOCK`), one call of the cell's integral per block.

:func:`predict_fingers` runs a study's fingers on its already-solved cell (the cell prepared
once over their pressures), :func:`member_full_contact_loads` their full-contact loads,
:func:`evaluate_members` packs them as arrays and :func:`member_quantiles` takes quantiles over
members that keep ``inf`` (a load never reached). SI units (m, N, Pa).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..checks import ArrayLike, as_loads
from ..coupling import CurvePrediction, critical_load, disc_ratio, predict_curve
from ..errors import FingerpadError
from ..finger import Finger
from ..friction import mu_checked
from ..micro.bem import BEMUnitCell
from ..micro.response import check_cell
from .run import P_HIGH, P_LOW, Prediction, load_at_centre_pressure

__all__ = ["STATES", "MemberValues", "evaluate_members", "member_cells", "member_full_contact_loads",
           "member_quantiles", "predict_fingers", "predict_members"]

#: Contact states at the pad centre, in the order of their codes (0, 1, 2).
STATES: tuple[str, ...] = ("asperity", "transition", "full")

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
    ``p_zone`` is infinite); :func:`fingerpad.coupling._zone_radius` row by row."""
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
        bit (``tests/study/test_members.py``).
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


def member_full_contact_loads(fingers: Sequence[Finger], pressures: Sequence[float]) -> np.ndarray:
    """Per finger, the load (N) at which its pad-centre pressure ``1.5 F / A_fr(F)`` reaches its
    cell's full-contact pressure ``pressures[i]`` (Pa): :func:`~fingerpad.study.run.load_at_centre_pressure`
    with the finger's area law called directly (``inf`` for an infinite pressure, NaN if none)."""
    return np.array([load_at_centre_pressure(finger, float(p), ridge_area=_area_of(finger))
                     for finger, p in zip(fingers, pressures, strict=True)], dtype=float)


def _member_moduli(study: Any, fingers: Sequence[Finger]) -> list[float]:
    """Each finger's reduced modulus E1* (Pa) on the study's texture material (Eq. 3.4)."""
    mat_nu = study.material_poisson if study.material_poisson is not None else 0.35
    return [f.micro_modulus(study.material_modulus, mat_nu) for f in fingers]


def member_cells(study: Any, cell: BEMUnitCell, fingers: Sequence[Finger]) -> list[Any]:
    """The BEM cell of each finger on the study's (prepared) ``cell``, prepared over what that
    finger's loads ask for: ``cell`` itself over the union of the fingers' pressures in units of
    E* (no solve when that lies inside what is cached), read at each finger's E1*; a layered
    finger whose thickness or moduli ratio differ from the study's (another unit layer) on a cell
    of its own (:meth:`~fingerpad.micro.bem.BEMUnitCell.for_skin`), prepared over its pressures.

    A sweep's cell task calls this for every point sharing a cell before any of them is
    predicted (:func:`fingerpad.design.evaluate.prepare_shared_cell`): :func:`predict_fingers`
    then solves nothing. Returns one response per finger."""
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
    for f, e in zip(fingers, moduli, strict=True):
        if f.layer is None and cell.layer is None:
            cells.append(cell.at_modulus(e))
            continue
        p = loads / np.asarray(f.ridge_area(loads), float)
        cells.append(cell.for_skin(e, f.layer, (P_LOW * float(p.min()), P_HIGH * float(p.max()))))
    return cells


#: Why a population (or a robust design) with a work of adhesion is refused.
ADHESION_REFUSED = (
    "a population of fingers with a work of adhesion: not supported yet. Each member's w / E* makes "
    "its own adhesive unit cell (a continuation of ~120 solves, ~15 s at grid 128), not one cell read at "
    "every member's modulus; predict single fingers with --work-of-adhesion (docs/model.md 6.6)")


def predict_fingers(nominal: Prediction, fingers: Sequence[Finger], *, full_contact: bool = True) -> tuple[
        list[CurvePrediction], np.ndarray, np.ndarray, list[list[str]]]:
    """Every finger on the texture of a study already predicted (``nominal``, its cell reused).

    The BEM cell is prepared over the union of the fingers' pressures in units of E* (no solve
    when that lies inside what is cached: psi depends on p/E* only) and read at each finger's E1*
    (Eq. 3.4); with the Hertz model each finger gets its own per-asperity cell (no solve).
    ``full_contact=False`` skips the search of the full-contact loads (NaN then; the robust
    design's screen does not use them).

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
        cells = member_cells(study, cell, fingers)
        own = {i for i, c in enumerate(cells) if isinstance(c, BEMUnitCell)}
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
        The members' fingers (:func:`fingerpad.study.population.member_finger`).

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
