"""An adhesive finger pad on an adhesive unit cell: JKR gross contact, its pressures over the ridge
disc, the real area, the pull-off force, and where adhesion matters (docs/model.md 7.6).

The pad adheres to a textured surface with an *effective* work of adhesion: the energy it costs
to pull a square metre of the pad's nominal contact apart. The skin touches the texture on the
ridges only (``A_fr / A_g`` of the nominal area) and, there, on the cell's real contacts, which
let go one after another as the cell is pulled apart from zero load; the cell's work of
separation ``W`` (:attr:`~fingerpad.micro.adhesive_cell.AdhesiveUnitCell.work_of_separation`)
counts exactly that, elastic energy released included. So

    w_pad = (A_fr / A_g) W                                                          (3.18)

with the ridge fraction taken at :data:`REFERENCE_LOAD` (the light touch where adhesion
matters; constant for the default finger's ridge model). On a flat, smooth reference ``W = w``.
The pad is then the JKR sphere of :mod:`fingerpad.macro.jkr` (the finger's ``R_fp``, ``E_fp*``
and ``w_pad``): its pull-off force is ``1.5 pi w_pad R_fp`` and its pressure over the ridge disc
(radius ``a_fr``) has the JKR profile

    p(r) = 1.5 (F_H / A_fr) s - (F_A / (2 A_fr)) / s,   s = sqrt(1 - r^2 / a_fr^2),   (3.17)

whose mean is ``(F_H - F_A) / A_fr = F / A_fr`` (Eq. 3.16 splits the load). The real area is the
cell's loading-branch psi over that disc (Eq. 3.11 with Eq. 3.17); where the edge's tension
exceeds the cell's pull-off pressure the cells have let go (psi = 0).

Only a Hertz pad (the default) becomes JKR: with another gross-area model (Dzidek, power laws)
the pad keeps its model and the adhesion acts at the micro scale alone (a note says so). SI units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import FingerpadError
from ..finger import Finger
from ..macro.hertz import HertzArea
from ..macro.jkr import JKRArea
from ..macro.pressure import adhesive_disc_average

__all__ = ["REFERENCE_LOAD", "THRESHOLD_CHANGE", "THRESHOLD_RANGE", "AdhesivePad", "adhesion_threshold", "adhesive_pad",
           "plain_real_area", "threshold_loads"]

#: The load (N) at which the ridge fraction of Eq. 3.18 is taken: light touch.
REFERENCE_LOAD = 0.1
#: Adhesion "matters" where it changes the real area by more than this fraction.
THRESHOLD_CHANGE = 0.10
#: The threshold load is looked for between these loads (N).
THRESHOLD_RANGE = (1e-3, 1e2)


@dataclass(frozen=True)
class AdhesivePad:
    """The pad of an adhesive finger on one texture: its effective work of adhesion and the JKR
    gross contact (``jkr``, or ``None`` when the finger's pad model is not Hertz).

    Attributes
    ----------
    finger
        The finger.
    cell
        The adhesive unit cell (:class:`~fingerpad.micro.adhesive_cell.AdhesiveUnitCell`).
    work_of_adhesion
        ``w_pad`` of Eq. 3.18, J/m^2.
    ridge_fraction
        ``A_fr / A_g`` at :data:`REFERENCE_LOAD`.
    jkr
        The JKR pad, or ``None`` (the finger's own pad model kept).
    notes
        Remarks for the prediction.
    """

    finger: Finger
    cell: Any
    work_of_adhesion: float
    ridge_fraction: float
    jkr: JKRArea | None
    notes: tuple[str, ...] = field(default=())

    @property
    def pull_off_force(self) -> float:
        """The finger's pull-off force (N, positive): JKR's ``1.5 pi w_pad R_fp`` (0 without a JKR pad)."""
        return self.jkr.pull_off_force if self.jkr is not None else 0.0

    def areas(self, loads: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(A_g, A_fr)`` (m^2) at loads (N, >= 0): the JKR gross area and the finger's ridge model on it."""
        f = np.asarray(loads, dtype=float)
        if self.jkr is None:
            return self.finger.areas_checked(f)
        gross = self.jkr.area_checked(f)
        ridges = self.finger.ridges
        core = getattr(ridges, "area_checked", None)
        args = np.broadcast_arrays(f, gross)
        return gross, np.asarray(core(*args) if core is not None else ridges.area(*args), dtype=float)

    def real_area(self, loads: np.ndarray, n_rings: int = 16) -> np.ndarray:
        """``A_re`` (m^2) per load (N, >= 0) of the adhesive pad on the adhesive cell."""
        _, ridge = self.areas(loads)
        return self.area_ratio(loads, ridge, n_rings) * ridge

    def pressure_coefficients(self, loads: np.ndarray, ridge_area: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(c_H, c_A)`` (Pa) of Eq. 3.17 per load: ``p(s) = c_H s - c_A / s`` over the ridge disc."""
        f = np.asarray(loads, dtype=float)
        if self.jkr is None:
            return 1.5 * f / ridge_area, np.zeros_like(f)
        f_h, f_a = self.jkr.pressure_parts(f)
        return 1.5 * f_h / ridge_area, 0.5 * f_a / ridge_area

    def area_ratio(self, loads: np.ndarray, ridge_area: np.ndarray, n_rings: int = 16) -> np.ndarray:
        """``A_re / A_fr`` per load: psi of the cell's loading branch averaged over the ridge disc
        under Eq. 3.17."""
        c_h, c_a = self.pressure_coefficients(loads, ridge_area)
        cell = self.cell
        breaks = (*cell.breakpoints, cell.transition_pressure, cell.full_contact_pressure)
        return np.array([adhesive_disc_average(cell.contact_fraction, h, a, breaks, floor=cell.pull_off_pressure,
                                               n_nodes=n_rings) for h, a in zip(c_h, c_a, strict=True)])

    def centre_pressure(self, loads: np.ndarray, ridge_area: np.ndarray) -> np.ndarray:
        """The pressure at the disc's centre, ``c_H - c_A`` (Pa)."""
        c_h, c_a = self.pressure_coefficients(loads, ridge_area)
        return c_h - c_a

    def zone_radius(self, loads: np.ndarray, ridge_area: np.ndarray, pressure: float) -> np.ndarray:
        """The radius (m) inside which the pad pressure exceeds ``pressure`` (Pa): 0 where it does nowhere."""
        c_h, c_a = self.pressure_coefficients(loads, ridge_area)
        a = np.sqrt(ridge_area / math.pi)
        if not math.isfinite(pressure):
            return np.zeros_like(a)
        with np.errstate(divide="ignore", invalid="ignore"):
            s = np.where(c_h > 0, (pressure + np.sqrt(pressure**2 + 4 * c_h * c_a)) / (2 * c_h), np.inf)
        return np.where(s < 1, a * np.sqrt(np.clip(1 - s**2, 0, None)), 0.0)

    def describe(self) -> dict[str, Any]:
        """JSON-ready: the pad's adhesion (SI)."""
        return {"pad_work_of_adhesion": self.work_of_adhesion, "ridge_fraction_at_reference_load": self.ridge_fraction,
                "reference_load": REFERENCE_LOAD, "pull_off_force": self.pull_off_force,
                "pad_model": "jkr" if self.jkr is not None else "the finger's own (no pad adhesion)"}


def adhesive_pad(finger: Finger, cell: Any) -> AdhesivePad:
    """The adhesive pad of ``finger`` on the texture of the adhesive ``cell`` (prepared), Eq. 3.18."""
    gross_model = finger.gross_model
    g_ref, fr_ref = finger.areas_checked(np.array([REFERENCE_LOAD]))
    fraction = float(fr_ref[0] / g_ref[0])
    w_pad = fraction * float(cell.work_of_separation)
    notes: list[str] = []
    if isinstance(gross_model, HertzArea):
        jkr = JKRArea(gross_model.radius, gross_model.modulus, w_pad)
    else:
        jkr = None
        notes.append(f"adhesion: the pad model {type(gross_model).__name__} is kept (JKR replaces Hertz only); "
                     "the adhesion acts at the micro scale, no pull-off force of the pad")
    return AdhesivePad(finger, cell, w_pad, fraction, jkr, tuple(notes))


def plain_real_area(finger: Finger, plain: Any, loads: np.ndarray, n_rings: int = 16) -> np.ndarray:
    """``A_re`` (m^2) per load of the same finger without adhesion: its own pad (Hertz) on the
    non-adhesive cell ``plain`` (Eq. 3.11)."""
    from ..macro.pressure import disc_average

    f = np.asarray(loads, dtype=float)
    _, ridge = finger.areas_checked(f)
    peak = 1.5 * f / ridge
    method = getattr(plain, "disc_fraction", None)
    if method is not None:
        ratio = np.asarray(method(peak), dtype=float)
    else:
        breaks = (plain.transition_pressure, plain.full_contact_pressure, *getattr(plain, "breakpoints", ()))
        ratio = disc_average(plain.contact_fraction, peak, breaks, n_nodes=n_rings)
    return ratio * ridge


def threshold_loads() -> np.ndarray:
    """The loads (N) the threshold of :func:`adhesion_threshold` is looked for at (a log grid of
    :data:`THRESHOLD_RANGE`, 12 per decade)."""
    lo, hi = THRESHOLD_RANGE
    return np.geomspace(lo, hi, int(round(12 * math.log10(hi / lo))) + 1)


def adhesion_threshold(pad: AdhesivePad, plain: Any, n_rings: int = 16) -> float:
    """The load (N) below which adhesion changes the real area by more than
    :data:`THRESHOLD_CHANGE`: the largest load in :data:`THRESHOLD_RANGE` where
    ``A_re(adhesive) / A_re(non-adhesive) - 1`` reaches it (the non-adhesive one from the finger's
    own pad on ``plain``, prepared over :func:`threshold_loads`' pressures). NaN if it does
    nowhere in the range (below its lowest load), ``inf`` if everywhere."""
    from scipy.optimize import brentq

    def change(f: np.ndarray) -> np.ndarray:
        return pad.real_area(f, n_rings) / plain_real_area(pad.finger, plain, f, n_rings) - 1.0

    grid = threshold_loads()
    values = change(grid)
    above = np.flatnonzero(values >= THRESHOLD_CHANGE)
    if above.size == 0:
        return math.nan
    i = int(above[-1])
    if i == grid.size - 1:
        return math.inf
    return float(brentq(lambda f: float(change(np.array([f]))[0]) - THRESHOLD_CHANGE, grid[i], grid[i + 1],
                        rtol=1e-6))
