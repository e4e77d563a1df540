"""Running a prediction study: texture + materials + finger + loads -> areas, zones, friction.

:func:`run_study` chains the scales: ``E1* = finger.micro_modulus(material)`` (Eq. 3.4); for the
BEM a periodic unit cell of the texture is solved over the local pressures the pad produces
(:class:`~fingerpad.micro.bem.BEMUnitCell`, cached on disk), for Hertz the asperities are treated
one by one (:class:`~fingerpad.micro.hertz.HertzUnitCell`, Eqs. 3.1-3.6); both are coupled to the
pad by :func:`~fingerpad.coupling.predict_curve` (Eqs. 3.7, 3.11).
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..coupling import CurvePrediction, predict_curve
from ..errors import FingerpadError
from ..units import format_percent
from ..finger import Finger
from ..micro.hertz import HertzUnitCell, hertz_cell_for, supports_hertz
from ..textures import Texture
from .spec import Study
from .states import adhesive_states, load_notes, resolve_adhesive_cell, state_brackets, state_choices, texture_maker
from .states import pull_off_error as adhesive_pull_off_error
# the search of a load from its centre pressure and the load floor of an estimate, where callers found them before
from .states import _load_floor, load_at_centre_pressure  # noqa: F401

__all__ = ["P_HIGH", "P_LOW", "Prediction", "bem_pressure_range", "centre_state", "pad_layer_note", "prepare_bem_cell",
           "run_study"]

#: Local pressures solved on the BEM cell: [P_LOW * min(F/A_fr), P_HIGH * max(F/A_fr)]. The pad
#: pressure (Eq. 3.7) runs from 0 at the disc edge to 1.5 F/A_fr at the centre; below the lowest
#: computed node psi follows the power law of the two lowest nodes (asperity contact).
P_LOW, P_HIGH = 0.02, 1.5


@dataclass
class Prediction:
    """Result of :func:`run_study` (SI units).

    Attributes
    ----------
    study, texture
        The inputs and the built texture.
    reduced_modulus
        E1*, Pa (Eq. 3.4).
    bem, hertz
        Curves against load by the BEM unit cell and by per-asperity Hertz (``None`` if not run).
    cell, hertz_cell
        The unit-cell responses used.
    critical_load
        ``{"bem": F, "hertz": F}``: load (N) at which the pad centre reaches the transition
        (BEM: :func:`~fingerpad.coupling.critical_load`; Hertz: Eq. 3.6); ``None`` if that model
        did not run. Found wherever the cell's transition pressure puts it, whatever loads were
        asked for (``inf`` if the cell never reaches it).
    full_contact_load
        ``{"bem": F}``: load at which the centre reaches full contact (``inf`` if the cell does not
        reach full contact up to :data:`~fingerpad.micro.bem.STATE_SEARCH_CAP` E*).
    state_brackets
        For the BEM cell, per state (``transition``, ``full``): the bracket of the cell pressure
        (Pa), the loads (N) it maps to, its relative width, and the state's own grid and error
        estimate (``grid``, ``coarse_grid``, ``pressure_error``, ``load_error``, ``history``;
        :func:`fingerpad.micro.resolution.choose_state_grids`): the state pressures are chosen
        and estimated apart from the curve, so they do not depend on the loads asked for.
    resolution
        The BEM cell's grid and the estimated discretisation error of A_re/A_fr
        (:func:`fingerpad.micro.resolution.choose_grid`) and of the state pressures.
    directional
        With a sliding direction: the friction at that direction and across and along the
        asperities' long axis, their ratio, and the deflection model's flags
        (:func:`directional_friction`); ``None`` otherwise.
    zones
        The zone radii at :attr:`Study.zone_load`.
    pressure_range
        Local pressures (Pa) over which the BEM cell was prepared.
    timings
        ``{"cell": s, "coupling": s}``.
    notes
        Remarks (hexagonal spacing used by Hertz, model skipped, ...).
    """

    study: Study
    texture: Texture
    reduced_modulus: float
    bem: CurvePrediction | None
    hertz: CurvePrediction | None
    cell: Any
    hertz_cell: HertzUnitCell | None
    critical_load: dict[str, float | None]
    full_contact_load: dict[str, float | None]
    state_brackets: dict[str, Any]
    resolution: dict[str, Any] | None
    directional: dict[str, Any] | None
    zones: dict[str, Any]
    pressure_range: tuple[float, float]
    timings: dict[str, float]
    notes: list[str] = field(default_factory=list)
    #: With a work of adhesion: the adhesive cell's and pad's numbers (pull-off force and
    #: pressure, works of adhesion and separation, the threshold load; SI), ``None`` without.
    adhesion: dict[str, Any] | None = None

    @property
    def primary(self) -> CurvePrediction:
        """The BEM curve when computed, else the Hertz curve."""
        return self.bem if self.bem is not None else self.hertz  # type: ignore[return-value]

    @property
    def primary_model(self) -> str:
        return "bem" if self.bem is not None else "hertz"

    @property
    def primary_cell(self) -> Any:
        return self.cell if self.bem is not None else self.hertz_cell

    def states(self, which: str | None = None) -> list[str]:
        """Contact state at the pad centre for each load (``asperity``/``transition``/``full``)."""
        curve, cell = (self.hertz, self.hertz_cell) if which == "hertz" else (self.primary, self.primary_cell)
        assert curve is not None and cell is not None
        if getattr(cell, "adhesive", False):
            from ..micro.adhesive_pad import adhesive_pad  # the adhesive pad's centre (Eq. 3.17)

            centre = adhesive_pad(self.study.finger, cell).centre_pressure(curve.load, curve.ridge_area)
            return [centre_state(p, cell) for p in centre]
        return [centre_state(p, cell) for p in 1.5 * curve.load / curve.ridge_area]

    @property
    def unconverged(self) -> int:
        if self.cell is None or not getattr(self.cell, "points", None):
            return 0
        return sum(1 for row in self.cell.points.values() if not row.get("converged", True))


def centre_state(peak_pressure: float, cell: Any) -> str:
    """State of the contact at the pad centre for its pressure ``1.5 F/A_fr`` (Pa)."""
    pt, pf = float(cell.transition_pressure), float(cell.full_contact_pressure)
    if peak_pressure >= pf:
        return "full"
    if peak_pressure >= pt:
        return "transition"
    return "asperity"


#: A layered finger's pad modulus E_fp* and its skin's effective modulus at the pad's contact
#: scale may differ by this factor before a note says so.
PAD_LAYER_TOLERANCE = 1.5


def pad_layer_note(finger: Finger, load: float) -> str | None:
    """A note when a layered finger's pad modulus E_fp* disagrees with its skin.

    The pad (Hertz, Eq. 2.5) keeps E_fp*: its contact radius a (millimetres) is many layer
    thicknesses, so it feels the tissue under the stratum corneum. The layered skin's effective
    modulus at the pad's scale, ``E1* / K(t / a)`` (docs/model.md, "A layered finger through the
    scales"), should then be about E_fp*; ``None`` when it is within :data:`PAD_LAYER_TOLERANCE`
    or the skin is a half-space.
    """
    from ..contact.layered import effective_modulus

    layer = finger.layer
    if layer is None:
        return None
    a = float(np.sqrt(np.asarray(finger.gross_area(load), float) / math.pi))
    e_pad = float(effective_modulus(layer, 1.0 / a))
    ratio = e_pad / finger.modulus
    if 1 / PAD_LAYER_TOLERANCE <= ratio <= PAD_LAYER_TOLERANCE:
        return None
    return (f"layered skin: its effective modulus at the pad's contact radius ({a * 1e3:.3g} mm at {load:g} N) is "
            f"{e_pad / 1e3:.3g} kPa, the pad's E_fp* is {finger.modulus / 1e3:.3g} kPa: the pad (Eq. 2.5) keeps "
            "E_fp*; set the finger's modulus to the skin's for one skin through the scales")


def _threshold_pressures(finger: Finger, p_range: tuple[float, float]) -> tuple[float, float]:
    """The local pressures (Pa) a non-adhesive cell is prepared over for the threshold load's
    search (:data:`fingerpad.micro.adhesive_pad.THRESHOLD_RANGE`), with those of the study."""
    from ..micro.adhesive_pad import threshold_loads

    f = threshold_loads()
    p_mean = f / np.asarray(finger.ridge_area(f), dtype=float)
    return min(P_LOW * float(p_mean.min()), p_range[0]), max(P_HIGH * float(p_mean.max()), p_range[1])


def _adhesion_report(curve: CurvePrediction, finger: Finger, notes: list[str]) -> dict[str, Any]:
    """The adhesion block of a prediction (SI) and its notes."""
    info = dict(curve.adhesion or {})
    notes.extend(info.pop("notes", []))
    threshold = info.get("threshold_load")
    if threshold is not None:
        from ..micro.adhesive_pad import THRESHOLD_CHANGE, THRESHOLD_RANGE

        lo, hi = THRESHOLD_RANGE
        # a threshold outside the range searched is reported as that end and which side it lies on
        info["threshold_load_bound"] = "exact"
        if math.isnan(threshold):
            info["threshold_load"], info["threshold_load_bound"] = lo, "at most"
            notes.append(f"adhesion changes the real area by less than {100 * THRESHOLD_CHANGE:g} % down to {lo:g} N")
        elif math.isinf(threshold):
            info["threshold_load"], info["threshold_load_bound"] = hi, "at least"
            notes.append(f"adhesion changes the real area by more than {100 * THRESHOLD_CHANGE:g} % up to {hi:g} N "
                         "(the skin pulled onto the texture's base past the transition, not only the light touch)")
    if info.get("range_regularised"):
        from ..contact.interaction import TIP_PIXELS

        notes.append(f"adhesion: the range {finger.adhesion_range:.3g} m is below a pixel; it is solved with the "
                     f"range {info['adhesion_range_used']:.3g} m, whose cohesive zone spans a pixel, acting within "
                     f"{TIP_PIXELS} pixels of the contact (the JKR limit's cohesive zone): the contacts are JKR's; "
                     "where adhesion pulls the skin onto the texture's base from a distance (large w) the "
                     "transition is extrapolated to a vanishing pixel from the grid, its half and its quarter "
                     "(docs/model.md 6.6)"
                     if info.get("transition_pulled_in") else
                     "where adhesion pulls the skin into full contact (large w) the grid converges slowly "
                     "(docs/model.md 6.6)")
    return info


def _zones(study: Study, cell: Any, hertz_cell: Any) -> dict[str, Any]:
    """Zone radii of the ridge-contact disc at the zone load (primary cell; Hertz radius too)."""
    from ..coupling import couple

    if getattr(cell, "adhesive", False):
        return _adhesive_zones(study, cell)
    f = study.zone_load
    ar = float(study.finger.ridge_area(f))
    res = couple(f, ar, cell)
    out = {
        "load": f,
        "ridge_area": ar,
        "ridge_radius": float(res.ridge_radius),
        "transition_radius": float(res.transition_radius),
        "full_contact_radius": float(res.full_contact_radius),
        "mean_pressure": float(res.mean_pressure),
        "peak_pressure": float(res.peak_pressure),
        "area_ratio": float(res.area_ratio),
        "contact_state": centre_state(float(res.peak_pressure), cell),
        "hertz_transition_radius": None,
    }
    if hertz_cell is not None and hertz_cell is not cell:
        out["hertz_transition_radius"] = float(couple(f, ar, hertz_cell).transition_radius)
    return out


def _adhesive_zones(study: Study, cell: Any) -> dict[str, Any]:
    """:func:`_zones` with the adhesive pad (Eq. 3.17)."""
    from ..coupling import predict_curve
    from ..micro.adhesive_pad import adhesive_pad

    f = study.zone_load
    curve = predict_curve([f], study.finger, cell, reference=False)
    pad = adhesive_pad(study.finger, cell)
    ar = float(curve.ridge_area[0])
    peak = float(pad.centre_pressure(np.array([f]), np.array([ar]))[0])
    return {"load": f, "ridge_area": ar, "ridge_radius": float(curve.ridge_radius[0]),
            "transition_radius": float(curve.transition_radius[0]),
            "full_contact_radius": float(curve.full_contact_radius[0]), "mean_pressure": f / ar,
            "peak_pressure": peak, "area_ratio": float(curve.area_ratio[0]),
            "contact_state": centre_state(peak, cell), "hertz_transition_radius": None}


def bem_pressure_range(study: Study) -> tuple[float, float]:
    """The local pressures (Pa) the BEM cell of ``study`` is prepared over: those of every load
    asked for and of the zone map, from ``P_LOW`` times the lowest mean pressure F/A_fr to ``P_HIGH``
    times the highest (the pad's centre, Eq. 3.7)."""
    wanted = np.append(study.loads, study.zone_load)
    p_mean = wanted / np.asarray(study.finger.ridge_area(wanted), dtype=float)
    return P_LOW * float(p_mean.min()), P_HIGH * float(p_mean.max())


def prepare_bem_cell(study: Study) -> Any:
    """The BEM cell (and its half-grid companion) prepared as :func:`run_study` prepares them,
    without the prediction: a :class:`~fingerpad.micro.resolution.GridChoice` whose ``solves``
    counts the unit-cell solves this call added to the cache (0: it held them all). Its error
    estimate is NaN where the grid is given (not needed for the choice; :func:`run_study`
    reports it).

    Raises
    ------
    FingerpadError
        As :func:`run_study` for the same study.
    """
    study.check()
    tex = study.build_texture()
    choice = _resolved_cell(study, tex, study.reduced_modulus, bem_pressure_range(study), None, estimate=False)
    _, solves = state_choices(study, tex, study.reduced_modulus, choice)
    choice.solves += solves
    return choice


def _resolved_cell(study: Study, tex: Texture, e1: float, p_range: tuple[float, float],
                   progress: Callable[[int, int], None] | None, estimate: bool = True) -> Any:
    """The BEM cell on a grid chosen by the study's accuracy (or on the given grid).

    ``estimate=False``: where the grid does not depend on it (a given grid, a measured map), the
    error estimate is not computed (NaN): the coupling of the two cells is the larger part of a
    preparation that solves nothing."""
    from ..coupling import couple
    from ..micro.resolution import choose_grid

    loads = np.append(study.loads, study.zone_load)
    ridge = np.asarray(study.finger.ridge_area(loads), dtype=float)
    make = texture_maker(study)
    target = None if study.grid is not None or make is None else study.accuracy
    ratio = (lambda cell: couple(loads, ridge, cell).area_ratio) if estimate or target is not None else \
        (lambda cell: np.full(loads.size, np.nan))
    return choose_grid(
        make, tex, e1, p_range, ratio,
        target=target,
        cell_options={"tol": study.tol, "max_iter": study.max_iter, "cache": study.curve_cache(),
                      "layer": study.finger.layer},
        progress=progress,
    )


def _resolution_report(choice: Any, study: Study, states: dict[str, Any] | None = None) -> dict[str, Any]:
    from ..micro.resolution import estimate_method

    pressures = {k: v.error for k, v in states.items()} if states else choice.state_pressure_errors()
    return {
        "grid": list(choice.cell.texture.shape),
        "coarse_grid": list(choice.coarse.texture.shape) if choice.coarse is not None else None,
        "chosen": "given" if study.grid is not None else "automatic" if choice.target is not None else
        "the map's own (a measured map keeps its grid)",
        "target": choice.target,
        "area_ratio_error": choice.error,
        "transition_pressure_error": pressures["transition"],
        "full_contact_pressure_error": pressures["full"],
        "history": [{"grid": g, "area_ratio_error": e} for g, e in choice.history],
        "solves": choice.solves,
        "method": estimate_method(type(choice.cell), "transition" in choice.extrapolated),
    }


def directional_settings(finger: Finger, cell: Any, centre: Any) -> Any:
    """The deflection settings of ``predict --direction``: the ramps go as far as the coupling
    needs, past every fixed point (*) at the pad-centre pressures ``centre`` (Pa) for gains up to
    :data:`~fingerpad.micro.deflection.fixedpoint.GAIN_BOUND`
    (:func:`~fingerpad.micro.deflection.needed_shear`; issue 31: a ramp to the deflection
    command's default 1.5 was three times the work for a fixed point of 0.2)."""
    from ..micro.deflection import DeflectionSettings, needed_shear

    centre = np.asarray(centre, float)
    return DeflectionSettings(mu_max=needed_shear(centre, cell.contact_fraction(centre), finger.tau0, finger.alpha))


def directional_friction(study: Study, tex: Texture, cell: Any, notes: list[str],
                         notice: Callable[[str], None] | None = None,
                         on_free_core: Callable[[], None] | None = None) -> dict[str, Any]:
    """Directional friction of compliant ellipsoids or ridges (issue: Paper C's direction effect).

    The adhesive term follows the real area enlarged by the asperities' deflection under the
    local shear they carry (:class:`~fingerpad.micro.deflection.DirectionalCell`, the fixed point of
    the shear and the gain), the hysteresis term the elliptical Greenwood-Tabor factor (Eq. 2.4e,
    ellipsoids only); the flat reference stays isotropic. Computed at the study's direction and
    at the two principal directions (along and across the long axis), each section's ramp
    cached. Returns the curve at the study's direction (``curve``) and a report. ``notice`` and
    ``on_free_core``: see :func:`run_study`.
    """
    from ..coupling import predict_curve
    from ..materials import Materials
    from ..micro.deflection import DirectionalCell, directional_gains, texture_geometry
    from ..micro.deflection.hysteresis import geometry_hysteresis_factor

    finger = study.finger
    geometry = texture_geometry(tex)  # the family's deflection hook (checked before the cell was solved)
    # the study's material Poisson ratio, the same one its reduced modulus uses (default 0.35)
    materials = Materials(finger.skin_modulus, finger.skin_poisson, study.material_modulus,
                          study.material_poisson if study.material_poisson is not None else Materials.material_poisson)
    loads = study.loads
    centre = 1.5 * loads / np.asarray(finger.ridge_area(loads), float)
    p_range = (float(centre.min()), float(centre.max()))
    parallel, perpendicular = geometry.principal_directions()
    cache = study.curve_cache()
    cache_arg: Any = True if cache is None else (False if cache is False else str(cache.folder))

    names = ("direction", "parallel", "perpendicular")
    directions = [float(study.direction), float(parallel), float(perpendicular)]
    # the sections of the three directions (two distinct ones at most) and their pressure levels
    # solved together, in worker processes (issue 23); the numbers do not depend on the count
    settings = directional_settings(finger, cell, centre)
    # the deflection model's local shear fixed point is written for tau = tau0 + alpha p: the
    # finger's friction law gives it (a law of another form refuses)
    tau0, alpha = finger.friction.affine_shear()
    gains = dict(zip(names, directional_gains(geometry, materials, directions, p_range, tau0=tau0,
                                              alpha=alpha, settings=settings, cache=cache_arg,
                                              progress=notice, on_free_core=on_free_core)))

    def curve_at(name: str) -> tuple[Any, Any, float]:
        gain = gains[name]
        direction = float(gain.direction_deg)
        # The elliptical Greenwood-Tabor factor belongs to the compliant-asperity model: a rigid
        # texture keeps the isotropic friction exactly.
        factor = 1.0 if gain.is_identity else geometry_hysteresis_factor(geometry, direction)
        textured = finger.with_overrides(beta=min(1.0, finger.beta * factor))
        curve = predict_curve(loads, textured, DirectionalCell(cell, gain, tau0, alpha))
        reference = predict_curve(loads, finger, cell)  # the flat reference is isotropic
        curve = dataclasses.replace(curve, mu_ref=reference.mu_ref, mu_normalised=curve.mu / reference.mu_ref)
        return curve, gain, factor

    curves = {name: curve_at(name) for name in names}
    flagged = sorted({float(ramp.pressure) for _, gain, _ in curves.values()
                      for ramp in (getattr(gain, "ramps", []) or [])
                      if getattr(ramp, "buckled", False) or getattr(ramp, "stopped", False)})
    if flagged:
        notes.append(f"deflection model: shear ramps buckled or stopped at {flagged[0] / 1e3:.3g}-"
                     f"{flagged[-1] / 1e3:.3g} kPa (docs/deflection.md, 'Limits and doubts')")
    main, gain, factor = curves["direction"]
    mu_perp, mu_par = curves["perpendicular"][0].mu, curves["parallel"][0].mu

    def held(name: str) -> list[bool]:
        """Per load: the gain at the pad-centre pressure and the local shear is held (past the
        shear level the ramps reached), not computed there."""
        g = curves[name][1]
        if g.is_identity:
            return [False] * len(centre)
        cell_dir = DirectionalCell(cell, g, tau0, alpha)
        return [bool(v) for v in np.asarray(cell_dir.local_shear(np.asarray(centre, float)).saturated)]

    saturated = held("direction")
    held_par, held_perp = held("parallel"), held("perpendicular")
    if any(held_par) or any(held_perp):
        first = min(float(f) for f, a, b in zip(loads, held_par, held_perp, strict=True) if a or b)
        notes.append(f"deflection model: the gain is held (past the shear level its ramps reached) from {first:.3g} N "
                     "on; marked in the outputs (gain_held_*) and the friction figure")
    rigid = [c[1].reason for c in curves.values() if c[1].is_identity and c[1].reason]
    if rigid:
        notes.append(f"deflection model: gain 1 at some directions: {rigid[0]}")
    return {
        "curve": main,
        "direction": float(study.direction),
        "parallel_direction": parallel,
        "perpendicular_direction": perpendicular,
        "mu_parallel": np.asarray(mu_par, float),
        "mu_perpendicular": np.asarray(mu_perp, float),
        "mu_perpendicular_over_parallel": np.asarray(mu_perp, float) / np.asarray(mu_par, float),
        "area_ratio_parallel": np.asarray(curves["parallel"][0].area_ratio, float),
        "area_ratio_perpendicular": np.asarray(curves["perpendicular"][0].area_ratio, float),
        "hysteresis_factor": {k: v[2] for k, v in curves.items()},
        "gain_saturated": saturated,
        "gain_held_parallel": held_par,
        "gain_held_perpendicular": held_perp,
        "identity": bool(getattr(gain, "is_identity", False)),
    }


def run_study(study: Study, progress: Callable[[int, int], None] | None = None, *,
              notice: Callable[[str], None] | None = None,
              on_free_core: Callable[[], None] | None = None) -> Prediction:
    """Run the prediction of ``study`` (see the module docstring).

    Parameters
    ----------
    study
        The inputs.
    progress
        ``progress(i, n)`` after each unit-cell solve (BEM only; not called when cached).
    notice
        Short messages of the deflection ramps (with a direction, when not cached): which ramp
        is done, the longest work of such a prediction.
    on_free_core
        Called once when the deflection ramps' worker processes leave a core free (see
        :func:`fingerpad.micro.deflection.ramps.solve_sections`); not called otherwise.

    Raises
    ------
    FingerpadError
        Non-periodic texture for the BEM (suggests ``periodize``), Hertz on a texture that is not
        spherical caps, bad values.
    """
    study.check()
    tex = study.build_texture()
    if study.direction is not None:
        if study.finger.adhesive:
            raise FingerpadError("directional friction (--direction) with a work of adhesion is not modelled: "
                                 "drop one of them")
        # directional friction needs the family's deflection model: refuse before solving the cell
        from ..micro.deflection import texture_geometry

        texture_geometry(tex)
    finger = study.finger
    e1 = study.reduced_modulus
    loads = study.loads
    p_range = bem_pressure_range(study)
    notes: list[str] = []

    note = pad_layer_note(finger, float(np.max(loads)))
    if note:
        notes.append(note)
    run_hertz = study.model in ("hertz", "both") and supports_hertz(tex)
    if study.model == "both" and not run_hertz:
        notes.append(f"Hertz (Eqs. 3.1-3.6) needs an asperity radius: texture {tex.name!r} runs the BEM only")
    hertz_cell = None
    if run_hertz and finger.layer is not None:
        notes.append("Hertz (Eqs. 3.1-3.6) takes the skin as the half-space of its layer (E_1): right for asperity "
                     "contacts much smaller than the layer's thickness, the BEM cell has the layer")
    if run_hertz:
        hertz_cell, note = hertz_cell_for(tex, e1)
        if note:
            notes.append(note)

    cell = bem = hertz = plain = None
    directional: dict[str, Any] | None = None
    timings_extra: dict[str, float] = {}
    resolution: dict[str, Any] | None = None
    states: dict[str, Any] = {}
    pull_off_error = math.nan
    t_cell = t_coupling = 0.0
    if study.model in ("bem", "both"):
        t0 = time.perf_counter()
        if study.direction is not None:
            from ..micro.deflection.ramps import start_fork_server

            start_fork_server()  # the ramps' worker server starts beside the cell's solve
        choice = _resolved_cell(study, tex, e1, p_range, progress)
        states, state_solves = state_choices(study, tex, e1, choice)
        choice.solves += state_solves
        cell, tex = choice.cell, choice.cell.texture
        if not cell.flat:
            cell.adopt_states(states["transition"].cell, states["full"].cell)
        solves_before = 0
        if finger.adhesive:
            # the same texture without adhesion (A_re without it, over the threshold's loads too),
            # then the adhesive cell from its grid: the prediction's cell (its state brackets are
            # its own, so the plain cell's state grids are not reported for it)
            plain = cell
            plain.prepare(*_threshold_pressures(finger, p_range))
            solves_before = choice.solves
            choice = resolve_adhesive_cell(study, tex.shape[0], e1, progress)
            cell, tex = choice.cell, choice.cell.texture
            states = adhesive_states(choice, study.accuracy)
            pull_off_error = adhesive_pull_off_error(choice)
        resolution = _resolution_report(choice, study, states)
        resolution["solves"] += solves_before
        what = "A_re/A_fr (with adhesion)" if finger.adhesive else "A_re/A_fr"
        if study.grid is None and choice.met is False:
            notes.append(f"the estimated discretisation error of {what}, {format_percent(choice.error)} %, exceeds "
                         f"the target {100 * choice.target:g} % at the largest automatic grid")
        elif study.grid is not None and not math.isnan(choice.error) and choice.error > study.accuracy:
            notes.append(f"grid {study.grid}: estimated discretisation error of {what} {format_percent(choice.error)} % "
                         f"(above {100 * study.accuracy:g} %; leave the grid to the default to reach it)")
        elif choice.target is None and study.grid is None and not math.isnan(choice.error) \
                and choice.error > study.accuracy:
            notes.append(f"measured map at its own grid: A_re/A_fr changes by {format_percent(choice.error)} % from the map "
                         f"averaged 2 x 2 (pixel-scale roughness resolved by the pixels alone)")
        # (an adhesive cell's state pressures are its own, on its grid against the half grid)
        where = "the adhesive cell's grid" if finger.adhesive else "the largest grid for the state pressures"
        for name, label in (("transition", "transition"), ("full", "full-contact")):
            st = states[name]
            if st.met is False and math.isfinite(st.error):
                notes.append(f"the estimated error of the {label} pressure, {format_percent(st.error)} %, exceeds the target "
                             f"{100 * st.target:g} % at {where} ({st.cell.texture.shape[0]} points along x)")
        t_cell = time.perf_counter() - t0
        t0 = time.perf_counter()
        bem = predict_curve(loads, finger, cell, plain=plain if finger.adhesive else None)
        t_coupling += time.perf_counter() - t0
        if study.direction is not None:
            t0 = time.perf_counter()
            directional = directional_friction(study, tex, cell, notes, notice, on_free_core)
            bem = directional.pop("curve")
            timings_extra["deflection"] = time.perf_counter() - t0
        if cell.flat:
            notes.append("flat texture: full contact at any load (A_re = A_fr), no critical load")
    if hertz_cell is not None:
        t0 = time.perf_counter()
        hertz = predict_curve(loads, finger, hertz_cell)
        t_coupling += time.perf_counter() - t0

    crit: dict[str, float | None] = {
        "bem": bem.critical_load if bem is not None else None,
        "hertz": hertz.critical_load_hertz if hertz is not None else None,
    }
    full: dict[str, float | None] = {"bem": None}
    full["bem"], brackets = state_brackets(cell, states, finger)
    if cell is not None and not cell.flat:
        load_notes(cell, crit["bem"], full["bem"], notes)
    primary_cell = cell if cell is not None else hertz_cell
    adhesion = None
    if bem is not None and bem.adhesion is not None:
        adhesion = _adhesion_report(bem, finger, notes)
        adhesion["pull_off_force_error"] = pull_off_error
    pred = Prediction(
        study=study, texture=tex, reduced_modulus=e1, bem=bem, hertz=hertz, cell=cell, hertz_cell=hertz_cell,
        critical_load=crit, full_contact_load=full, state_brackets=brackets, resolution=resolution,
        directional=directional,
        zones=_zones(study, primary_cell, hertz_cell),
        pressure_range=p_range, timings={"cell": t_cell, "coupling": t_coupling, **timings_extra}, notes=notes,
        adhesion=adhesion,
    )
    if pred.unconverged:
        notes.append(f"{pred.unconverged} unit-cell solve(s) did not reach the tolerance {study.tol:g}")
    return pred

