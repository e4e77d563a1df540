"""Two surfaces on the same fingers: who tells them apart, what each vibrates at, rough or smooth.

:func:`compare` predicts surface A and surface B (another texture, a measured map, or the flat
reference ``"flat"``) for the same fingers, at the same loads: the study's finger, or every
member of a population (the same members for both surfaces, drawn once). Per load it gives each
surface's friction, each member's probability of telling them apart in a forced choice
(:mod:`.discrimination`, Eqs. P.1-P.3), the fraction of members who do (``P >= 0.75``) and the
median ``P``; per surface the vibration frequencies and receptor channels at the stroke speeds
and directions and an amplitude estimate (:mod:`.vibration`), and the roughness regime per load
(:mod:`.roughness`). The friction numbers are those of ``fingerpad predict`` (``--population``)
for each surface: nothing here solves anything but the amplitude's one cell per load.

B is taken under A's fingers and loads: its study file gives its texture, material and numerics;
a ``[finger]`` of its own that differs from A's is replaced by A's, with a note.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FingerpadError
from .discrimination import WEBER_FRACTION, p_correct
from .result import Comparison, Surface
from .roughness import regime
from .vibration import Periods, amplitude, fingerprint_period, periods

__all__ = ["DEFAULT_DIRECTIONS", "DEFAULT_SPEEDS", "FLAT", "MAX_DIRECTIONS", "MAX_SPEEDS", "Comparison", "Surface",
           "against_flat", "assemble", "check_directions", "check_speeds", "compare", "member_weber", "parse_directions", "parse_weber",
           "parse_speeds", "surface_verdicts", "with_weber"]

#: The name of the flat reference as surface B.
FLAT = "flat"
#: Stroke speeds of active touch, m/s: 20-100 mm/s (the band the issue reports; typical
#: exploration, Greenspon et al. 2019 measured 10-160 mm/s).
DEFAULT_SPEEDS = (0.02, 0.1)
#: Stroke directions, degrees from the texture's x axis: along x and along y.
DEFAULT_DIRECTIONS = (0.0, 90.0)
#: Caps on what a user may list.
MAX_SPEEDS, MAX_DIRECTIONS = 16, 16


def check_speeds(speeds: Sequence[float]) -> tuple[float, ...]:
    """Stroke speeds (m/s), checked: 1 to :data:`MAX_SPEEDS` positive finite values, sorted."""
    values = tuple(sorted(float(v) for v in speeds))
    if not values or len(values) > MAX_SPEEDS:
        raise FingerpadError(f"--speed: give 1 to {MAX_SPEEDS} stroke speeds, got {len(values)}")
    if not all(math.isfinite(v) and v > 0 for v in values):
        raise FingerpadError(f"--speed: stroke speeds must be positive, got {list(speeds)}")
    return values


def check_directions(directions: Sequence[float]) -> tuple[float, ...]:
    """Stroke directions (degrees), checked: 1 to :data:`MAX_DIRECTIONS` finite values, in order."""
    values = tuple(float(v) for v in directions)
    if not values or len(values) > MAX_DIRECTIONS:
        raise FingerpadError(f"--directions: give 1 to {MAX_DIRECTIONS} stroke directions, got {len(values)}")
    if not all(math.isfinite(v) for v in values):
        raise FingerpadError(f"--directions: directions must be finite angles, got {list(directions)}")
    return values


def parse_speeds(text: str | None) -> tuple[float, ...]:
    """Stroke speeds from text (``--speed``, the explorer's field): one speed, ``LOW:HIGH`` (the
    two ends of a band) or ``START:STOP:COUNT``, m/s with unit suffixes (``20mm/s:100mm/s``);
    ``None``: :data:`DEFAULT_SPEEDS`."""
    from ..units import parse_positive, parse_range

    if text is None:
        return DEFAULT_SPEEDS
    parts = str(text).split(":")
    if len(parts) == 2:
        values = [parse_positive(p, "speed", name="--speed") for p in parts]
    else:
        values = parse_range(text, "speed", name="--speed", max_count=MAX_SPEEDS)
    return check_speeds(values)


def parse_directions(text: str | None) -> tuple[float, ...]:
    """Stroke directions from text (``--directions 0,90``): angles in degrees, or with ``deg`` or
    ``rad``; ``None``: :data:`DEFAULT_DIRECTIONS`."""
    from ..params import parse_angle

    if text is None:
        return DEFAULT_DIRECTIONS
    items = str(text).split(",")
    if any(not t.strip() for t in items):
        raise FingerpadError(f"--directions: expected angles separated by commas, got {text!r}")
    return check_directions([math.degrees(parse_angle(t, "--directions")) for t in items])


def _label(study: Any, default: str) -> str:
    return Path(study.source).stem if getattr(study, "source", None) else default


def _under_fingers_of(b: Any, a: Any, notes: list[str]) -> Any:
    """B with A's finger and loads (its texture, material and numerics kept)."""
    if b.finger != a.finger:
        notes.append(f"B's finger ({getattr(b.finger, 'name', 'its own')}) replaced by A's: both surfaces are "
                     "compared on the same fingers")
    # A's fixed values too: B's own [finger] keys are replaced, so they fix nothing
    return dataclasses.replace(b, finger=a.finger, loads=np.asarray(a.loads, float), zones_at=None,
                               fixed=dict(a.fixed))


def _spacing(per: Sequence[Periods]) -> float:
    """The shortest finite period of a texture along the stroke directions (its spacing)."""
    finite = [p.fundamental for p in per if math.isfinite(p.fundamental)]
    return min(finite) if finite else math.inf


def surface_verdicts(pred: Any, directions: Sequence[float], notes: list[str], amplitudes: bool = True) -> tuple[
        list[Periods], np.ndarray | None, list[dict[str, Any]]]:
    """One surface's periods along ``directions``, its amplitude estimate per load (m p-p; the
    unit cell solved at the mean ridge pressure ``F / A_fr`` of the nominal finger; ``None``
    without ``amplitudes``) and its roughness regime per load; for a measured map, no periods and
    no amplitude (a note says so)."""
    states = pred.states()
    surface = Surface("", pred)
    if surface.flat:
        return [], np.zeros(len(states)), [regime(math.inf, s) for s in states]
    if not surface.lattice:
        notes.append(f"{describe_short(pred)}: a measured map has no lattice period: its vibration and "
                     "roughness regime are not estimated")
        return [], None, [{"verdict": "not estimated (measured map)", "state": s, "scale": None} for s in states]
    tex = pred.texture
    per = [periods(tex, d) for d in directions]
    # the spacing of the roughness verdicts: the shortest period along the cell's own axes
    axes = [periods(tex, d) for d in (0.0, 90.0)]
    spacing = _spacing(axes)
    if not amplitudes:
        return per, None, [regime(spacing, s) for s in states]
    study = pred.study
    loads = np.asarray(study.loads, float)
    pressures = loads / np.asarray(study.finger.ridge_area(loads), float)
    amp = amplitude(tex, pred.reduced_modulus, pressures, layer=study.finger.layer, tol=max(study.tol, 1e-7),
                    max_iter=study.max_iter)
    return per, amp, [regime(spacing, s) for s in states]


def describe_short(pred: Any) -> str:
    tex = pred.texture
    return str(tex.name or tex.family or "texture")


def parse_weber(weber: Any, label: str = "--weber-fraction") -> float | None:
    """A Weber fraction W given by a user (a number, or text such as ``"0.15"``), read and checked
    through :data:`fingerpad.person.WEBER_FRACTION`'s declaration; ``None`` stays ``None``."""
    if weber is None:
        return None
    return float(WEBER_FRACTION.parse(weber, label) if isinstance(weber, str) else WEBER_FRACTION.check(weber, label))


def with_weber(study: Any, weber: Any, label: str = "--weber-fraction") -> Any:
    """``study`` with its person's Weber fraction set to ``weber`` (a number, or text read through
    :data:`fingerpad.person.WEBER_FRACTION`'s declaration; ``None``: ``study`` as it is). The value
    is one the user fixed, named ``label``: a population that draws W is then refused with it
    (:func:`fingerpad.population.rules.attach`)."""
    value = parse_weber(weber, label)
    if value is None:
        return study
    return dataclasses.replace(study, weber_fraction=value, fixed={**study.fixed, "weber_fraction": label})


def member_weber(study: Any, members: Sequence[Mapping[str, float]] | None = None) -> np.ndarray:
    """Every finger's Weber fraction W: a member's own where its population draws W, else the
    study's person's (:attr:`fingerpad.study.spec.Study.weber`: the value given, or 0.11). One
    value without ``members`` (the study's finger)."""
    own = study.weber
    if not members:
        return np.array([own])
    return np.array([float(m.get("weber_fraction", own)) for m in members])


def compare(a: Any, b: Any, *, population: Any = None, table: Any = None, speeds: Sequence[float] = DEFAULT_SPEEDS,
            directions: Sequence[float] = DEFAULT_DIRECTIONS, weber: Any = None,
            notice: Callable[[str], None] | None = None) -> Comparison:
    """Compare surface ``a`` with ``b`` on the same fingers (see the module docstring).

    Parameters
    ----------
    a
        A :class:`~fingerpad.study.spec.Study`: the texture, material, finger and loads.
    b
        Another study (its texture, material and numerics; A's finger and loads), or
        ``"flat"``: the flat reference, ``A_re = A_fr`` (every finger's ``mu_ref``).
    population
        A population as :func:`fingerpad.population.rules.attach` takes it (a preset name, a
        file, a table, a :class:`~fingerpad.population.distributions.Population`), or ``None``
        for the study's finger (or A's own ``table``).
    table
        A's study file's own ``[population]`` table, if any (with units, as in a file).
    speeds
        Stroke speeds, m/s (default 20 and 100 mm/s).
    directions
        Stroke directions, degrees from the texture's x axis (default 0 and 90).
    weber
        The person's Weber fraction W, fixed for every finger (:func:`with_weber`; a population
        that draws W is then refused); ``None``: A's study's (``[perception] weber_fraction``),
        else each member's own where the population draws it, else 0.11.
    notice
        Called with a short text before each prediction.

    Raises
    ------
    FingerpadError
        Bad speeds, directions or Weber fraction (checked before any prediction); what
        ``predict`` refuses for either study.
    """
    from ..study.run import run_study

    speeds = check_speeds(speeds)
    directions = check_directions(directions)
    a = with_weber(a, weber)
    notes: list[str] = []
    flat_b = isinstance(b, str)
    if flat_b and b.strip().lower() != FLAT:
        raise FingerpadError(f"surface B {b!r}: a study file or {FLAT!r} (the flat reference)")
    b_study = None if flat_b else _under_fingers_of(b, a, notes)
    label_a = _label(a, "A")
    label_b = FLAT if flat_b else _label(b, "B")
    if label_b == label_a:
        label_a, label_b = f"A:{label_a}", f"B:{label_b}"
    say = notice or (lambda text: None)
    from ..population.rules import attach

    plan = attach(a, population, table=table)  # every rule of a population on a study, before any work
    members = None if plan is None else [dict(m) for m in plan.members]
    w = member_weber(a, members)
    if plan is not None:
        from ..population.run import run_population

        population = plan.population
        say(f"{label_a}: {len(members)} fingers of {population.name!r}")
        ra = run_population(plan)
        notes.extend(ra.notes)
        pred_a, mu_a = ra.nominal, ra.values("mu")
        if flat_b:
            pred_b, mu_b = None, ra.values("mu_ref")
        else:
            say(f"{label_b}: the same {len(members)} fingers")
            rb = run_population(attach(b_study, population))
            pred_b, mu_b = rb.nominal, rb.values("mu")
    else:
        say(f"{label_a}: the study's finger")
        pred_a = run_study(a)
        mu_a = np.asarray(pred_a.primary.mu, float)[None, :]
        if flat_b:
            pred_b, mu_b = None, np.asarray(pred_a.primary.mu_ref, float)[None, :]
        else:
            say(f"{label_b}: the study's finger")
            pred_b = run_study(b_study)
            mu_b = np.asarray(pred_b.primary.mu, float)[None, :]
    return assemble(Surface(label_a, pred_a), Surface(label_b, pred_b), mu_a, mu_b, w, members=members,
                    population=population, speeds=speeds, directions=directions, notes=notes, notice=say)


def against_flat(pred: Any, result: Any = None, *, speeds: Sequence[float] = DEFAULT_SPEEDS,
                 directions: Sequence[float] = DEFAULT_DIRECTIONS, weber: Any = None,
                 amplitudes: bool = True) -> Comparison:
    """The single-texture verdicts of ``predict --perception``: the prediction ``pred`` (and the
    population's ``result``, :class:`~fingerpad.population.run.PopulationResult`) against the
    flat reference, from the numbers already predicted (every finger's ``mu`` and ``mu_ref``; with
    ``result``, its nominal prediction stands for ``pred``);
    only the amplitude estimate solves the cell (once per load; ``amplitudes=False``: none, the
    explorer's quick view). ``weber``: the person's W fixed for every finger (:func:`with_weber`;
    refused with a population that draws W); ``None``: the study's, or each member's own."""
    speeds = check_speeds(speeds)
    directions = check_directions(directions)
    if result is not None:  # the population's own nominal prediction: the same loads as its members
        pred = result.nominal
        mu_a, mu_b, members, population = result.values("mu"), result.values("mu_ref"), result.members, \
            result.population
    else:
        curve = pred.primary
        mu_a, mu_b = np.asarray(curve.mu, float)[None, :], np.asarray(curve.mu_ref, float)[None, :]
        members, population = None, None
    study = with_weber(pred.study, weber)
    if population is not None and weber is not None:  # the population was attached without it: the rule now
        from ..population.rules import refuse_fixed

        refuse_fixed(population, study)
    w = member_weber(study, members)
    return assemble(Surface(_label(pred.study, "texture"), pred), Surface(FLAT, None), mu_a, mu_b, w,
                    members=members, population=population, speeds=speeds, directions=directions, notes=[],
                    amplitudes=amplitudes)


def assemble(a: Surface, b: Surface, mu_a: np.ndarray, mu_b: np.ndarray, weber: np.ndarray, *,
             members: list[dict[str, float]] | None, population: Any, speeds: tuple[float, ...],
             directions: tuple[float, ...], notes: list[str],
             notice: Callable[[str], None] | None = None, amplitudes: bool = True) -> Comparison:
    """The :class:`Comparison` of two predicted surfaces: each member's P (Eqs. P.1-P.3) from its
    friction on both, and each surface's periods, amplitude and roughness regime."""
    say = notice or (lambda text: None)
    loads = np.asarray(a.prediction.study.loads, float)
    p = p_correct(mu_a, mu_b, np.asarray(weber, float)[:, None])
    per: dict[str, list[Periods]] = {}
    amp: dict[str, np.ndarray | None] = {}
    regimes: dict[str, list[dict[str, Any]]] = {}
    for surface in (a, b):
        if surface.prediction is None:
            per[surface.label], amp[surface.label] = [], np.zeros(loads.size)
            regimes[surface.label] = [regime(math.inf, "full") for _ in loads]
            continue
        say(f"{surface.label}: vibration amplitude")
        per[surface.label], amp[surface.label], regimes[surface.label] = surface_verdicts(
            surface.prediction, directions, notes, amplitudes)
    pop = None if population is None else {"name": population.name, "size": len(members or []),
                                           "seed": population.seed, "method": population.method}
    from ..references import keys_of
    from ..study.citations import prediction_references
    from . import discrimination, roughness, vibration

    sources: list[Any] = [discrimination, vibration, roughness]
    sources += [prediction_references(s.prediction) for s in (a, b) if s.prediction is not None]
    if getattr(population, "correlations", ()):
        from ..population import correlations

        sources.append(correlations)
    return Comparison(a=a, b=b, loads=loads, weber=np.asarray(weber, float), mu_a=mu_a, mu_b=mu_b, p=p,
                      members=members, population=pop, speeds=speeds, directions=directions, periods=per,
                      amplitude=amp, regimes=regimes, ridge_period=fingerprint_period(a.prediction.study.finger),
                      notes=notes, references=keys_of(*sources))
