"""Deflection gain of the real contact area, per texture, material and sliding direction.

The section model (:mod:`.solve`, :mod:`.path`) gives, for one asperity section at a nominal
pressure p, the contact length ``L(mu)`` along a full-sliding shear ramp. The **deflection
gain** ``G(p, mu) = L(p, mu) / L(p, 0)`` is the factor by which sliding at the local shear level
mu (friction force over normal force of the cell) multiplies the real contact area of that cell;
it is the real-area multiplier of the adhesive term, Eq. 2.2. The section for a texture and a
direction is :func:`.section.section_for`; a rigid texture (no material modulus) or a section
the shear does not cross (ridges sliding along their length) gives ``G = 1`` exactly, without
solving. How the gain enters the friction -- the fixed point of the local shear it creates --
is :mod:`.fixedpoint`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from ...errors import FingerpadError
from .settings import DeflectionSettings, SectionMaterials
from .pressure_ramp import PressureRamp
from .ramps import SectionJob, solve_sections
from .section import EllipsoidGeometry, Geometry, RidgeGeometry, Section, section_for, texture_geometry

#: Bump when a change of the section model alters cached numbers.
MODEL_VERSION = 9  # 4: threshold pivoting and re-ordered sums in the Newton solve (round-off level); 5: Gauss-point fold contact;
# 6: no wall-clock limit in the key or the results (entries of 5 could hold ramps a slow machine cut short);
# 7: Newton solves caught in a limit cycle or stagnating fail early (issue 23: some ramps take other steps);
# 8: fold contact on the nearest closed base segment, its gap continuous (issue 31: ramps pass where the gap jumped);
#    levels rounded to three significant digits
# 9: a shear ramp about to stop first re-converges its last state under its own friction tiles
#    (path.relag; issue 31: ramps that stopped go on, ramps that came through are bit-identical)
#: The publications of the directional friction model (:mod:`fingerpad.references` keys): the
#: measured direction dependence it explains (the thesis' Paper C), the elliptical hysteresis term.
REFERENCES = ("sergachev2022", "greenwood1958")

__all__ = ["DeflectionSettings", "EllipsoidGeometry", "GainCurve", "MODEL_VERSION", "PressureRamp", "RidgeGeometry",
           "Section", "SectionMaterials", "as_dataset", "directional_gain", "directional_gains", "section_for", "solve_section",
           "texture_geometry"]


# ---------------------------------------------------------------------------------------------
# one section: shear ramps at a few pressures
# ---------------------------------------------------------------------------------------------


def solve_section(
    section: Section,
    materials: SectionMaterials,
    pressures: np.ndarray,
    tau0: float = 0.0,
    alpha: float = 1.0,
    settings: DeflectionSettings = DeflectionSettings(),
    progress: Callable[[str], None] | None = None,
    linear: bool = False,
) -> list[PressureRamp]:
    """Shear ramps of one section at the nominal pressures ``pressures`` (Pa), in this process.

    One normal-load ramp presses the skin on through all pressures at zero shear; from each,
    a tip-controlled shear ramp runs to ``settings.mu_max`` (or stops and says why). Several
    sections and levels at once, in worker processes: :func:`.ramps.solve_sections`.
    """
    if materials.texture_modulus is None:
        raise FingerpadError("a rigid texture does not deflect: its gain is exactly 1 (no section to solve)")
    p = tuple(float(v) for v in np.sort(np.asarray(pressures, dtype=float)))
    job = SectionJob(section, materials, p, float(tau0), float(alpha), settings, linear)
    return solve_sections([job], workers=1, progress=progress)[0]



# ---------------------------------------------------------------------------------------------
# the gain table
# ---------------------------------------------------------------------------------------------


@dataclass
class GainCurve:
    """Deflection gain ``G(p, mu)`` of the real contact area for one texture, material and
    sliding direction.

    Interpolation: linear in mu along each pressure level's load-controlled branch, held at
    the last computed value past the largest shear level reached (``saturated`` tells where),
    and linear in log p between levels; below the lowest level it goes linearly in p to 1 at
    p = 0 (the deflection vanishes with the load), above the highest it is held.

    Attributes
    ----------
    pressures
        Nominal pressures of the levels, Pa (empty: identity, G = 1).
    ramps
        The section's ramps (None for the identity).
    shear_factor
        Fraction of the shear level acting across the section (ridges: |cos direction|).
    direction_deg
        The direction, degrees from the texture's x axis.
    """

    pressures: np.ndarray
    ramps: list[PressureRamp] | None
    shear_factor: float = 1.0
    direction_deg: float = 0.0
    section: Section | None = None
    cache_key: str | None = None
    #: Why the gain is exactly 1 without a solve (identity curves only), in words.
    reason: str | None = None

    @classmethod
    def identity(cls, direction_deg: float = 0.0, reason: str = "rigid texture") -> GainCurve:
        """G = 1 everywhere, for the reason given (a rigid texture, no shear across the section)."""
        return cls(np.zeros(0), None, 1.0, direction_deg, reason=reason)

    @property
    def incomplete(self) -> bool:
        """Some ramp was cut by the wall-clock safety stop (see :class:`PressureRamp`)."""
        return any(r.incomplete for r in self.ramps or [])

    @property
    def is_identity(self) -> bool:
        return self.pressures.size == 0

    def mu_reached(self) -> np.ndarray:
        """Largest shear level reached at each pressure level (the table's validity)."""
        return np.array([r.mu_reached for r in self.ramps]) if self.ramps else np.zeros(0)

    def __call__(self, pressure: Any, mu: Any) -> np.ndarray:
        """Gain at nominal pressures ``pressure`` (Pa) and local shear levels ``mu`` (broadcast)."""
        p, m = np.broadcast_arrays(np.asarray(pressure, dtype=float), np.asarray(mu, dtype=float))
        if self.is_identity:
            return np.ones(p.shape)
        m_sec = np.abs(m) * self.shear_factor
        levels = [r.branch() for r in self.ramps]  # type: ignore[union-attr]
        vals = np.stack([np.interp(m_sec, mu_k, g_k) if mu_k.size else np.ones(m_sec.shape)
                         for mu_k, g_k in levels], axis=0)  # (levels, ...)
        lp = np.log(self.pressures)
        pp = np.maximum(p, 1e-300)
        out = np.empty(p.shape)
        below = pp <= self.pressures[0]
        out[below] = 1.0 + (vals[0][below] - 1.0) * pp[below] / self.pressures[0]
        if self.pressures.size == 1:
            out[~below] = vals[0][~below]
            return out
        x = np.clip(np.log(pp), lp[0], lp[-1])
        j = np.clip(np.searchsorted(lp, x) - 1, 0, lp.size - 2)
        w = (x - lp[j]) / (lp[j + 1] - lp[j])
        ii = np.indices(p.shape)
        v0 = vals[(j,) + tuple(ii)]
        v1 = vals[(j + 1,) + tuple(ii)]
        out[~below] = ((1 - w) * v0 + w * v1)[~below]
        return out

    def saturated(self, pressure: Any, mu: Any) -> np.ndarray:
        """True where the shear level lies beyond what the nearest pressure level reached."""
        p, m = np.broadcast_arrays(np.asarray(pressure, dtype=float), np.asarray(mu, dtype=float))
        if self.is_identity:
            return np.zeros(p.shape, dtype=bool)
        reach = self.mu_reached()
        k = np.argmin(np.abs(np.log(np.maximum(p, 1e-300))[..., None] - np.log(self.pressures)), axis=-1)
        return np.abs(m) * self.shear_factor > reach[k] + 1e-9

    def as_dict(self, surfaces: bool = False) -> dict[str, Any]:
        return {
            "direction_deg": self.direction_deg,
            "shear_factor": self.shear_factor,
            "section": asdict(self.section) if self.section else None,
            "pressures": self.pressures.tolist(),
            "ramps": [r.as_dict(surfaces) for r in self.ramps] if self.ramps else [],
            "cache_key": self.cache_key,
            "identity_reason": self.reason,
            "incomplete": self.incomplete,
        }


def _cache():
    """The package's content-keyed cache of unit-cell curves (:mod:`fingerpad.micro.cache`)."""
    from ..cache import CurveCache, content_key

    return CurveCache, content_key


def directional_gain(
    geometry: Geometry,
    materials: Any,
    direction_deg: float,
    pressure_range: tuple[float, float],
    tau0: float = 0.0,
    alpha: float = 1.0,
    settings: DeflectionSettings = DeflectionSettings(),
    cache: bool | str = True,
    progress: Callable[[str], None] | None = None,
    workers: int | None = None,
) -> GainCurve:
    """Deflection gain of the real contact area for sliding at ``direction_deg``.

    Parameters
    ----------
    geometry
        :class:`EllipsoidGeometry` or :class:`RidgeGeometry` (see :func:`texture_geometry`).
    materials
        :class:`fingerpad.materials.Materials` (or :class:`SectionMaterials`); a rigid
        texture (``material_modulus=None``) gives the identity without solving.
    direction_deg
        Sliding direction, degrees from the texture's x axis.
    pressure_range
        (lowest, highest) nominal cell pressure of interest, Pa (e.g. the pad-centre pressure
        ``1.5 F / A_fr`` at the smallest and largest load). ``settings.n_pressures`` levels are
        solved, log-spaced.
    tau0, alpha
        Shear strength of Eq. 2.3 (Pa, -): the shape of the friction traction ("package" law).
    settings
        :class:`DeflectionSettings`.
    cache
        True: the package cache folder; a path: that folder; False: no cache. Entries are keyed
        by the section (not the direction), so directions sharing a section share the solve.
    progress
        Called with a short message before each stage.
    workers
        Processes for the shear ramps of the levels (:func:`.ramps.solve_sections`; None: the
        cores available). The numbers do not depend on it.

    Returns
    -------
    GainCurve
    """
    return directional_gains(geometry, materials, [direction_deg], pressure_range, tau0, alpha, settings, cache,
                             progress, workers)[0]


def directional_gains(
    geometry: Geometry,
    materials: Any,
    directions: Sequence[float],
    pressure_range: tuple[float, float],
    tau0: float = 0.0,
    alpha: float = 1.0,
    settings: DeflectionSettings = DeflectionSettings(),
    cache: bool | str = True,
    progress: Callable[[str], None] | None = None,
    workers: int | None = None,
    on_free_core: Callable[[], None] | None = None,
) -> list[GainCurve]:
    """:func:`directional_gain` at several directions, the ramps of every section and level that
    is not cached solved together in ``workers`` processes (issue 23: the two principal sections'
    six shear ramps of ``predict --direction`` at once). A section shared by several directions
    is solved once, also without a cache. The curves are the same as one
    :func:`directional_gain` call per direction, bit for bit, whatever ``workers`` is.
    ``progress`` and ``on_free_core``: see :func:`.ramps.solve_sections` (neither is called
    when every section is cached).

    Returns
    -------
    list of GainCurve
        One per direction, in the order given.
    """
    mats = materials if isinstance(materials, SectionMaterials) else SectionMaterials.from_materials(materials)
    if settings.friction == "coulomb":
        tau0, alpha = 0.0, 1.0
    CurveCache, content_key = _cache()
    store = CurveCache(None if cache is True else cache) if cache else None
    curves: list[GainCurve | None] = []
    todo: dict[str, tuple[SectionJob, list[int]]] = {}  # content key -> (job, the directions it serves)
    for i, direction in enumerate(directions):
        section = section_for(geometry, direction)
        if mats.texture_modulus is None or section.shear_factor == 0.0:
            why = ("rigid texture (no material modulus): it does not deflect" if mats.texture_modulus is None else
                   "no shear across the section (sliding along the ridges): it does not deflect")
            curve = GainCurve.identity(float(direction), why)
            curve.section = section
            curves.append(curve)
            continue
        lo, hi = (float(v) for v in pressure_range)
        if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo <= hi):
            raise FingerpadError(f"pressure range must be 0 < low <= high, got {pressure_range!r}")
        n = int(settings.n_pressures) if hi > lo else 1
        pressures = level_pressures(lo, hi, n)
        numbers = np.array([section.half_width, section.height, section.period, section.load_per_pressure,
                            *pressures], dtype=float)
        key = content_key(numbers, kind="deflection", model=MODEL_VERSION, profile=section.profile,
                          materials=asdict(mats), tau0=float(tau0), alpha=float(alpha), settings=settings.key())
        hit = store.load(key).get("ramps") if store is not None else None
        if hit:
            ramps = [PressureRamp.from_dict(d) for d in hit]
            curves.append(GainCurve(pressures, ramps, section.shear_factor, float(direction), section, key))
            continue
        curves.append(None)
        if key not in todo:
            todo[key] = (SectionJob(section, mats, tuple(float(p) for p in pressures), float(tau0), float(alpha),
                                    settings), [])
        todo[key][1].append(i)
    if todo:
        solved = solve_sections([job for job, _ in todo.values()], workers=workers, progress=progress,
                                on_free_core=on_free_core)
        for (key, (job, users)), ramps in zip(todo.items(), solved):
            # A ramp cut by the wall-clock safety stop ended where the machine's speed let it: no
            # result, never stored (a later run, on any machine, solves it again).
            if store is not None and not any(r.incomplete for r in ramps):
                store.update(key, {"ramps": [r.as_dict(surfaces=True) for r in ramps]})
            for i in users:
                sec = job.section
                curves[i] = GainCurve(np.asarray(job.pressures), ramps, sec.shear_factor, float(directions[i]), sec,
                                      key if store is not None else None)
    return [c for c in curves if c is not None]


def level_pressures(low: float, high: float, n: int) -> np.ndarray:
    """The ``n`` pressure levels (Pa) of a gain table over [low, high]: log-spaced, each rounded to
    three significant digits (a level moves by at most 5e-3 of itself, far below the model's
    +-7 % mesh error), so that inputs a little apart -- a pressure 1e-6 off -- give the same
    levels, the same ramps and the same bits (issue 31: the README command's levels and the
    benchmark's, 1e-6 apart, stopped ramps at other places)."""
    raw = np.geomspace(low, high, n) if n > 1 else np.array([float(low)])
    return np.array([float(f"{p:.3g}") for p in raw])


def as_dataset(curves: list[GainCurve]) -> Any:
    """The ramps of several directions as an :class:`xarray.Dataset` (dims direction, pressure,
    step; NaN-padded), with the flags per direction and pressure, SI units in ``attrs``."""
    import xarray as xr

    dirs = [c.direction_deg for c in curves]
    pressures = sorted({float(p) for c in curves for p in c.pressures})
    steps = max([len(r.mu) for c in curves for r in (c.ramps or [])] + [1])
    shape = (len(dirs), max(1, len(pressures)), steps)
    names = {"mu": "1", "gain": "1", "contact_length": "m", "tip_dx": "m", "tip_dz": "m", "bend_dx": "m", "bend_dz": "m",
             "tangential_stiffness": "Pa", "fold_nodes": "1", "min_eigenvalue": "1"}
    data = {k: np.full(shape, np.nan) for k in names}
    flags = {k: np.full(shape[:2], np.nan) for k in ("fold_onset_mu", "limit_mu", "mu_reached", "buckled", "incomplete")}
    stopped = np.full(shape[:2], "", dtype=object)
    for i, c in enumerate(curves):
        for r in c.ramps or []:
            j = pressures.index(float(r.pressure))
            n = len(r.mu)
            for k in names:
                val = np.abs(r.mu) if k == "mu" else np.asarray(getattr(r, k))
                data[k][i, j, :val.size] = val[:n]
            flags["fold_onset_mu"][i, j] = r.fold_onset_mu
            flags["limit_mu"][i, j] = r.limit_mu
            flags["mu_reached"][i, j] = r.mu_reached
            flags["buckled"][i, j] = float(r.buckled)
            flags["incomplete"][i, j] = float(r.incomplete)
            stopped[i, j] = r.stopped or ""
    coords = {"direction": ("direction", np.asarray(dirs, dtype=float), {"units": "degree"}),
              "pressure": ("pressure", np.asarray(pressures or [np.nan], dtype=float), {"units": "Pa"})}
    variables = {k: (("direction", "pressure", "step"), v, {"units": names[k]}) for k, v in data.items()}
    variables.update({k: (("direction", "pressure"), v) for k, v in flags.items()})
    variables["incomplete"] = (("direction", "pressure"), variables["incomplete"][1],
                               {"long_name": "1: cut by the wall-clock safety stop (not a result)"})
    variables["stopped"] = (("direction", "pressure"), stopped.astype(str))
    return xr.Dataset(variables, coords=coords, attrs={"model": "fingerpad deflection section model",
                                                       "model_version": MODEL_VERSION})
