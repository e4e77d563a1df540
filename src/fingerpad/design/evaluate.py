"""One sweep point, or one chunk of points: the direct prediction of ``predict``, reduced to the
numbers a design map needs. Functions here run in Dask workers: plain data in, plain data out.

Per point (docs/model.md, design map): critical loads (BEM, Hertz where it applies), the
full-contact load, the cell's transition and full-contact pressures, psi on the sweep's common
pressure grid, and at each exploration load the contact state at the pad centre, A_re/A_fr,
mu, mu_ref and mu/mu_ref. With a population of fingers (``population``: the members and the
quantile levels), also per point the quantiles of the members' A_re/A_fr, mu, mu_ref and
mu/mu_ref at each load and of their critical and full-contact loads, the probability of each
contact state at the pad centre, the fraction of members in asperity contact over the whole
range, the fraction telling the texture from the flat reference and each member's own mu at each
load (:func:`fingerpad.population.members.evaluate_members`: one cell, every member at its
own E*). A point that cannot exist (overlapping asperities, a grid too small)
is returned invalid with its reason; an unconverged cell is flagged; neither raises.
"""

from __future__ import annotations

import math
import os
import time
import warnings
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ..errors import FingerpadError, SetupError, one_line

__all__ = ["POINT_MODULES", "STATE_CODES", "cell_key", "evaluate_chunk", "evaluate_point", "limit_threads",
           "prepare_cell", "prepare_shared_cell"]

#: Pixels the texture's smallest lateral feature must span for a point to be valid: below two
#: (the sampling limit) the feature is not in the height map at all, and the cell solves a
#: nearly flat surface (A_re/A_fr near 1 with a tiny error estimate) that is no result for it.
#: ``predict`` warns from 8 pixels (textures.geometry.WARN_PIXELS); a sweep records the point
#: as one that cannot be computed on its grid.
MIN_FEATURE_PIXELS = 2.0

#: The modules a point imports on its first prediction. Their call sites import them late (the
#: commands' start-up does not pay for them); a sweep imports them before it forks its local
#: workers, which then inherit them instead of each importing them for its first point
#: (~0.2-0.25 s of CPU per worker, measured for issue 23: a tenth of a 16-point sweep).
POINT_MODULES = ("fingerpad.study.run", "fingerpad.micro.resolution", "fingerpad.micro.cache", "scipy.interpolate",
                 "scipy.optimize", "fingerpad.contact.kernels_numba")

#: Contact state at the pad centre, as stored.
STATE_CODES = {"asperity": 0, "transition": 1, "full": 2}

_SCALARS = ("critical_load_bem", "critical_load_hertz", "full_contact_load", "transition_pressure",
            "full_contact_pressure", "grid_error", "grid", "seconds")
_PER_LOAD = ("area_ratio", "mu", "mu_ref", "mu_rel", "mu_perp_over_par")
#: Per-load member quantities banded per point (store name: MemberValues attribute).
POPULATION_BANDS = {"band_area_ratio": "area_ratio", "band_mu": "mu", "band_mu_ref": "mu_ref",
                    "band_mu_rel": "mu_normalised"}
#: Member loads banded per point.
POPULATION_LOAD_BANDS = {"band_critical_load": "critical_load", "band_full_contact_load": "full_contact_load"}


def limit_threads() -> None:
    """One thread per worker for BLAS and FFTs: the sweep's parallelism is its workers."""
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS",
                "FINGERPAD_FFT_WORKERS"):
        os.environ[var] = "1"
    try:
        from threadpoolctl import threadpool_limits

        threadpool_limits(1)
    except ImportError:  # pragma: no cover - threadpoolctl comes with scipy's stack
        pass


def _study(data: Mapping[str, Any]) -> Any:
    from ..study.spec import study_from_dict

    return study_from_dict(data)


def cell_key(data: Mapping[str, Any]) -> str | None:
    """What identifies a point's unit cell (the texture's shape and the numerics); ``None``
    for a point that cannot exist or runs no BEM cell. Neither the moduli nor the texture's scale
    enter: the cell is stored in p/E* and lengths over the cell length
    (:func:`fingerpad.micro.bem.unit_cell_key`), so points that differ only in them share it."""
    from ..micro.bem import DEFAULT_RTOL, unit_cell_key, unit_layer

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            study = _study(data)
            if study.model == "hertz":
                return None
            tex = study.build_texture()
        if not tex.periodic:
            return None
        # a layered skin's cell is one per thickness over Lx and moduli over E* (a half-space: none)
        layer = unit_layer(study.finger.layer, study.reduced_modulus, float(tex.size[0]))
        return unit_cell_key(tex, tol=study.tol, max_iter=study.max_iter, rtol=DEFAULT_RTOL, grid=study.grid,
                             accuracy=study.accuracy, layer=layer)
    except FingerpadError:
        return None


def prepare_cell(data: Mapping[str, Any], loads: Sequence[float], pressures: Sequence[float],
                 population: Mapping[str, Any] | None = None,
                 index: tuple[int, ...] | None = None,
                 sharing: Sequence[Mapping[str, Any]] = ()) -> dict[str, Any]:
    """Solve (or find in the cache) the unit cell of one point, by predicting that point.

    Run once per distinct cell before the other points that share it, so that a sweep solves
    each cell once (they then read it from the on-disk cache of ``predict``). ``sharing``: the
    study data of every point of the sweep that shares this cell, in the order of their indices
    (this point among them); with more than one, the cell is first prepared for all of them
    (:func:`prepare_shared_cell`), so that the chunks find every node in the cache instead of
    solving the same nodes side by side. Returns the number of solves (0: the cache had the cell), the seconds, and the
    point's own result with its ``index``: its chunk takes that result instead of predicting the
    point a second time.
    """
    limit_threads()
    t0 = time.perf_counter()
    solves = prepare_shared_cell(sharing, loads, population) if len(sharing) > 1 else 0
    result = evaluate_point(data, loads, pressures, population)
    result["solves"] = int(result["solves"]) + solves
    return {"solves": result["solves"], "seconds": time.perf_counter() - t0, "valid": result["valid"],
            "index": None if index is None else tuple(index), "result": result}


def prepare_shared_cell(sharing: Sequence[Mapping[str, Any]], loads: Sequence[float],
                        population: Mapping[str, Any] | None = None) -> int:
    """Prepare the unit cell that the points ``sharing`` share (a modulus axis: one cell in p/E*)
    over what every one of them asks for, before any of them is predicted; returns the solves.

    Each point's preparation is the one its prediction makes (:func:`~fingerpad.study.run.prepare_bem_cell`,
    with a population the members' cells, :func:`~fingerpad.population.members.member_cells`), in
    the order given, once. Then every point's own preparation finds its nodes in the cache and
    solves none. This is for speed only: a point's numbers are those of its own prediction on
    any cache (a cell's curve uses the nodes of the ranges it is prepared over, and a node's
    value is a function of its pressure alone, :meth:`~fingerpad.micro.bem.BEMUnitCell.prepare`),
    whatever order the chunks run in. Points that cannot exist are skipped, as their prediction
    stores them invalid.
    """
    from ..micro.bem import BEMUnitCell
    from ..population.members import member_cells, member_fingers
    from ..study.run import prepare_bem_cell

    points = []
    for data in sharing:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                study = _point_study(data, loads)
                _check_resolved(study)
                fingers = None if population is None else member_fingers(study.finger, population["members"])
        except SetupError:
            raise
        except FingerpadError:
            continue
        if study.model != "hertz":
            points.append((study, fingers))
    solves = 0
    for study, fingers in points:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                choice = prepare_bem_cell(study)
                solves += choice.solves
                if fingers is not None and fingers[0]:
                    cell = choice.cell
                    before = cell.solves
                    own = member_cells(study, cell, fingers[0], stack=fingers[1])
                    solves += cell.solves - before + sum(c.solves for c in own if isinstance(c, BEMUnitCell))
        except SetupError:
            raise
        except FingerpadError:  # as the point's prediction will say (stored invalid)
            continue
    return solves


def evaluate_point(data: Mapping[str, Any], loads: Sequence[float], pressures: Sequence[float],
                   population: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """The design-map numbers of one point (see the module docstring); never raises for a
    point that cannot exist: ``valid`` is False and ``reason`` says why. A
    :class:`~fingerpad.errors.SetupError` (a bad FFT setting on this worker, say) is raised: it
    says nothing about the point.

    ``population``: ``{"members": [{name: value (SI)}, ...], "quantiles": [levels]}`` (what
    :meth:`~fingerpad.design.spec.SweepSpec.population_payload` gives), or ``None``."""
    from ..study.run import run_study

    loads = np.asarray(loads, float)
    pressures = np.asarray(pressures, float)
    out: dict[str, Any] = {k: math.nan for k in _SCALARS}
    out.update({k: np.full(loads.size, np.nan) for k in _PER_LOAD})
    out.update(valid=False, reason="", converged=False, solves=0, psi=np.full(pressures.size, np.nan),
               contact_state=np.full(loads.size, -1, dtype=np.int8))
    if population is not None:
        nq = len(population["quantiles"])
        out.update({k: np.full((nq, loads.size), np.nan) for k in POPULATION_BANDS})
        out.update({k: np.full(nq, np.nan) for k in POPULATION_LOAD_BANDS})
        out.update(state_probability=np.full((len(STATE_CODES), loads.size), np.nan),
                   asperity_over_range=math.nan, tell_flat=np.full(loads.size, np.nan),
                   mu_members=np.full((len(population["members"]), loads.size), np.nan))
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            study = _point_study(data, loads)
            _check_resolved(study)
            pred = run_study(study)
    except SetupError:
        raise  # the machine's settings, not this point: the chunk fails and a rerun retries it
    except FingerpadError as exc:
        out["reason"] = one_line(str(exc))[:500]
        out["seconds"] = time.perf_counter() - t0
        return out
    cur = pred.primary
    out.update(
        valid=True,
        converged=pred.unconverged == 0,
        critical_load_bem=_num(pred.critical_load.get("bem")),
        critical_load_hertz=_num(pred.critical_load.get("hertz")),
        full_contact_load=_num(pred.full_contact_load.get("bem")),
        area_ratio=np.asarray(cur.area_ratio, float),
        mu=np.asarray(cur.mu, float),
        mu_ref=np.asarray(cur.mu_ref, float) if cur.mu_ref is not None else np.full(loads.size, np.nan),
        mu_rel=np.asarray(cur.mu_normalised, float) if cur.mu_normalised is not None else np.full(loads.size, np.nan),
        contact_state=np.array([STATE_CODES[s] for s in pred.states()], dtype=np.int8),
    )
    if pred.directional is not None:
        out["mu_perp_over_par"] = np.asarray(pred.directional["mu_perpendicular_over_parallel"], float)
    cell = pred.primary_cell
    out["transition_pressure"] = _num(getattr(cell, "transition_pressure", None))
    out["full_contact_pressure"] = _num(getattr(cell, "full_contact_pressure", None))
    out["psi"] = np.asarray(cell.contact_fraction(pressures), float)
    if pred.resolution is not None:
        out["grid_error"] = _num(pred.resolution.get("area_ratio_error"))
        out["grid"] = float(pred.resolution["grid"][0])
        out["solves"] = int(pred.resolution.get("solves", 0))
    if population is not None:
        try:
            bands = _population_bands(pred, population)
            out["solves"] = int(out["solves"]) + bands.pop("solves_population")
            out.update(bands)
        except FingerpadError as exc:  # a member this point's finger cannot take
            out.update(valid=False, reason=one_line(f"population: {exc}")[:500])
    out["seconds"] = time.perf_counter() - t0
    return out


def _population_bands(pred: Any, population: Mapping[str, Any]) -> dict[str, Any]:
    """The population's numbers at one point (see the module docstring); the extra unit-cell
    solves the members' wider p/E* range needs are counted in ``solves``."""
    from ..population.members import evaluate_members, member_fingers, member_quantiles

    levels = [float(q) for q in population["quantiles"]]
    cell = pred.cell
    before = int(getattr(cell, "solves", 0) or 0) if cell is not None else 0
    fingers, stack = member_fingers(pred.study.finger, population["members"])
    values = evaluate_members(pred, fingers, stack)
    after = int(getattr(cell, "solves", 0) or 0) if cell is not None else 0
    out: dict[str, Any] = {name: member_quantiles(getattr(values, attr), levels)
                           for name, attr in POPULATION_BANDS.items()}
    out.update({name: member_quantiles(getattr(values, attr), levels, drop_nan=True)
                for name, attr in POPULATION_LOAD_BANDS.items()})
    out["state_probability"] = np.array([np.mean(values.states == code, axis=0) for code in STATE_CODES.values()])
    out["asperity_over_range"] = float(np.mean(np.all(values.states == STATE_CODES["asperity"], axis=1)))
    # who tells the texture from the flat reference by friction (docs/perception.md, Eqs. P.1-P.3)
    from ..perception.compare import member_weber
    from ..perception.discrimination import p_correct, summarise

    weber = member_weber(pred.study, population["members"])  # a member's own W where the population draws it
    out["tell_flat"] = summarise(p_correct(values.mu, values.mu_ref, weber[:, None]))["fraction"]
    # each member's own mu: who tells the texture from any reference, later (design-map --tell-apart REF)
    out["mu_members"] = np.asarray(values.mu, float)
    out["solves_population"] = after - before
    return out


def _point_study(data: Mapping[str, Any], loads: np.ndarray | Sequence[float]) -> Any:
    """The study of a sweep point: its data at the sweep's exploration ``loads`` (N)."""
    data = {k: dict(v) for k, v in data.items()}
    data.setdefault("loads", {}).pop("range", None)
    data["loads"]["values"] = [float(f) for f in loads]
    data["loads"].pop("zones_at", None)
    return _study(data)


def _check_resolved(study: Any) -> None:
    """Refuse a texture whose smallest feature spans fewer than :data:`MIN_FEATURE_PIXELS` pixels.

    Raises
    ------
    FingerpadError
        ``grid too small: ...``, naming the feature, its size, the pixel and the grid.
    """
    from ..textures import registry
    from ..textures.geometry import fmt_length

    tex = study.build_texture()
    fam = registry().get(tex.family or "")
    if fam is None or fam.features is None:
        return
    feature, _ = fam.features(tex)
    nx, ny = tex.shape
    pixel = max(tex.spacing)
    if not feature >= MIN_FEATURE_PIXELS * pixel:
        raise FingerpadError(f"grid too small: the texture's smallest feature ({fmt_length(feature)}) spans "
                             f"{feature / pixel:.2g} pixels of {fmt_length(pixel)} on the {nx} x {ny} cell "
                             f"(at least {MIN_FEATURE_PIXELS:g} needed): a finer grid, or a smaller cell")


def evaluate_chunk(items: Sequence[tuple[tuple[int, ...], dict[str, Any]]], loads: Sequence[float],
                   pressures: Sequence[float], population: Mapping[str, Any] | None = None,
                   known: Mapping[tuple[int, ...], dict[str, Any]] | None = None,
                   ) -> list[tuple[tuple[int, ...], dict[str, Any]]]:
    """:func:`evaluate_point` for the points of one chunk, ``[(index, study data), ...]``.

    ``known`` maps indices already predicted (by :func:`prepare_cell`) to their results: those
    are taken as they are, with ``solves`` 0 (the cell task counted them)."""
    limit_threads()
    known = known or {}
    out = []
    for index, data in items:
        done = known.get(tuple(index))
        out.append((index, {**done, "solves": 0} if done is not None else
                    evaluate_point(data, loads, pressures, population)))
    return out


def _num(value: Any) -> float:
    if value is None:
        return math.nan
    try:
        return float(value)
    except (TypeError, ValueError):
        return math.nan
