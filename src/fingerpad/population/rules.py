"""Every rule about combining a population of fingers with a study, in one place.

The library (:func:`~.run.run_population`, the sweeps' :func:`fingerpad.design.spec.sweep_from_dict`,
:func:`fingerpad.design.inverse_design.design_textures`), the command line (``predict``, ``sweep``,
``design``) and the explorer all call :func:`attach`, and so accept and refuse the same things
with the same message:

1. **Which population.** ``--population`` (a preset, a TOML file, an ``analyse`` folder), a
   table or a :class:`~.distributions.Population`; else the study file's own ``[population]``
   table (named after the study file); none at all is no population.
2. **A value the user fixed is never drawn over.** A finger value given explicitly (a flag such
   as ``--skin-modulus``, ``--finger-param``, a study file's ``[finger]`` key, a value typed in
   the explorer: :attr:`fingerpad.study.spec.Study.fixed`), a swept axis or a designed ``--vary``
   (``fixed`` of :func:`attach`) is refused when the population draws that parameter: every member
   would silently get another value. The one exception is the layer's thickness and moduli of a
   layered finger given in the study: they are how a layered skin is declared at all (with a
   half-space preset); the population then draws its own values for every member, and a note
   says so.
3. **No sliding direction** (:data:`DIRECTION_REFUSED` says why). **Adhesion** (a work of
   adhesion on the study's finger or drawn by the population, :func:`adhesion_rules`): every
   member adheres or none does (:data:`~.adhesion.ADHESION_MIXED`), on a half-space skin
   (:data:`ADHESION_LAYERED`), with the study's adhesion range (:data:`ADHESION_RANGE_DRAWN`);
   the members' cells are then interpolated from one family of adhesive cells (a note says so).
4. **Quantile levels** (:func:`quantile_levels`): numbers in [0, 1], each once, ascending, at most
   :data:`MAX_QUANTILES`; they need a population.
5. **Sobol indices** (:func:`sensitivity_samples`): they need a population whose parameters are
   drawn (not a measured panel) with a spread, and a design of at most
   :data:`~.distributions.MAX_MEMBERS` fingers (:func:`.sobol.check_design`).
6. **Every member's finger** is made before anything is solved (its bounds, a ridge fraction on
   the constant-fraction ridge model, layer values on a layered finger:
   :func:`~.members.member_finger`), and members far outside the plausible range of their
   parameter are warned about, as a flag's value is (:func:`fingerpad.plausibility.check_plausible_range`).
7. **What the numbers will not show** is said before the work: an empty table, a Hertz model that
   does not see the layer, a layered cell per member, a panel too small for the outer bands.

A parameter of a person that is not the finger's is declared once, in
:data:`~.distributions.POPULATION_PARAMS`, and a study records whether the user fixed it in
:attr:`~fingerpad.study.spec.Study.fixed`; nothing here changes for it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import FingerpadError
from ..finger import LAYER_FIELDS, Finger
from ..study.spec import Study
from .distributions import Population, members_plausible, population_from_table
from .adhesion import ADHESION_MIXED
from .members import member_finger
from .sources import load_population

__all__ = ["ADHESION_LAYERED", "ADHESION_RANGE_DRAWN", "DEFAULT_QUANTILES", "DIRECTION_REFUSED", "MAX_QUANTILES",
           "PopulationStudy", "RIDGE_FRACTION_NOTE", "adhesion_rules", "attach", "quantile_levels", "refuse_fixed", "resolve_population", "sensitivity_samples"]

#: Quantiles reported by default.
DEFAULT_QUANTILES: tuple[float, ...] = (0.05, 0.25, 0.5, 0.75, 0.95)
#: Most quantile levels one prediction reports (every percentile and both ends): each is a column
#: of every band in the CSV tables and the stores.
MAX_QUANTILES = 101
#: Why a population and a sliding direction are refused together, and what to do instead.
DIRECTION_REFUSED = (
    "a population of fingers with a sliding direction is not supported. The directional friction comes from "
    "the deflection of the compliant features under each finger's own shear (its E_s, tau0 and alpha), so every "
    "member would need its own directional ramps (a population of solves, not one cell); run the population "
    "without the direction for the bands, then predict --direction for the members of interest with their "
    "--finger-param values (population.members in the JSON)")
#: The population's dominant assumption, said wherever its ridge fraction has a spread (issue 31).
RIDGE_FRACTION_NOTE = ("population: each member's ridge fraction (A_fr/A_g) is one number over every load -- an "
                       "assumption: the literature gives 10-70 % over loads, changing with load in opposite directions "
                       "in different studies, and no law per person; it drives much of the spread (--sensitivity)")
#: Why a population of adhesive fingers with a layered skin is refused.
ADHESION_LAYERED = (
    "a population of adhesive fingers with a layered skin: not supported. The members' adhesive cells are read "
    "from one family in w / (E* Lx), and a layered cell also depends on each member's layer over E* (a family "
    "of more dimensions); predict single layered fingers with --work-of-adhesion, or the population on a "
    "half-space skin")
#: Why a population that draws the adhesion range is refused.
ADHESION_RANGE_DRAWN = (
    "population adhesion_range: not drawn per member. The members' adhesive cells are read from one family in "
    "w / (E* Lx) with the study's range (a physical range below a pixel is replaced by the resolved one, "
    "docs/model.md 6.6); set adhesion_range on the study's finger")
#: The note of a population with adhesion (rule 7), said before its family is solved.
ADHESION_NOTE = ("population: adhesion: each member's adhesive cell is interpolated from one family of at most {cells} "
                 "adhesive cells in w / (E* Lx) (and {more} more where the transition moves fast) on the nominal cell's grid (each cell ~15 s at grid 128, ~1.5 min at "
                 "256 on one core, or read from the cache); each member's A_re carries its estimated "
                 "interpolation error (population.adhesion in the JSON)")
#: The layer values that declare a layered skin on a half-space preset (rule 2's exception).
DECLARING_LAYER = ("skin_layer_thickness", "skin_layer_modulus", "skin_substrate_modulus")
#: Fewest members for which the default outer bands (5 % and 95 %) are more than the panel's
#: extremes: below it a measured panel's bands are noted as its range.
FEW_MEMBERS = 20


@dataclass(frozen=True)
class PopulationStudy:
    """A population attached to a study, every rule checked (SI units): what
    :func:`~.run.run_population` runs.

    Attributes
    ----------
    study
        The study (its finger is the nominal one).
    population
        The population.
    members
        Each member's parameters (SI), drawn once.
    fingers
        Each member's :class:`~fingerpad.finger.Finger` (the study's finger with the member's values).
    quantiles
        The quantile levels reported, ascending.
    sensitivity
        The base samples N of the Sobol indices, or ``None``.
    notes
        What the numbers will not show, said before any work (rule 7).
    """

    study: Study
    population: Population
    members: tuple[dict[str, float], ...]
    fingers: tuple[Finger, ...]
    quantiles: tuple[float, ...]
    sensitivity: int | None = None
    notes: tuple[str, ...] = ()


def quantile_levels(value: str | Sequence[float] | None, where: str = "--quantiles") -> tuple[float, ...]:
    """The quantile levels asked for: ``"0.1,0.5,0.9"`` or numbers; ``None`` gives
    :data:`DEFAULT_QUANTILES`. Ascending and once each (the bands run from the first level to the
    last, and a repeated level would give two CSV columns of one name).

    Raises
    ------
    FingerpadError
        Not numbers, a level outside [0, 1], none, or more than :data:`MAX_QUANTILES`.
    """
    if value is None:
        return DEFAULT_QUANTILES
    items: list[Any] = value.split(",") if isinstance(value, str) else list(value)
    try:
        levels = [float(q) for q in items]
    except (TypeError, ValueError):
        raise FingerpadError(f"{where}: expected numbers in [0, 1] separated by commas, got {value!r}") from None
    if not levels or any(not 0 <= q <= 1 for q in levels):  # NaN fails both
        raise FingerpadError(f"{where}: each must lie in [0, 1], got {value!r}")
    unique = tuple(sorted(set(levels)))
    if len(unique) > MAX_QUANTILES:
        raise FingerpadError(f"{where}: {len(unique)} levels; at most {MAX_QUANTILES} (every percentile)")
    return unique


def resolve_population(population: Population | Mapping[str, Any] | str | Path | None, study: Study | None = None,
                       table: Mapping[str, Any] | None = None) -> Population | None:
    """Rule 1: the population asked for, or the study file's own ``[population]`` ``table`` when
    none is named, or ``None``. A table in a file (the study's) needs units on its lengths and
    pressures; one built in Python takes SI numbers, as a sweep's sections do."""
    if isinstance(population, Population):
        return population
    if isinstance(population, Mapping):
        return population_from_table(population)
    if population is not None:
        return load_population(population)
    if table is None:
        return None
    source = getattr(study, "source", None)
    name = Path(source).name if source else "custom"
    return population_from_table(table, where=f"{name} [population]" if source else "[population]", name=name,
                                 require_units=source is not None)


def sensitivity_samples(value: bool | int | str | None, population: Population | None) -> int | None:
    """Rule 5: the base samples N of the Sobol indices (``True``: the default, an integer or its
    text: that N; ``None`` or ``False``: none), checked against the population.

    Raises
    ------
    FingerpadError
        No population, a measured panel, no parameter with a spread, N below 2 or a design of more
        than :data:`~.distributions.MAX_MEMBERS` fingers.
    """
    if value is None or value is False:
        return None
    if population is None:
        raise FingerpadError("--sensitivity needs a population (--population or a [population] table)")
    from ..units import parse_int
    from .sobol import DEFAULT_SAMPLES, check_design

    samples = DEFAULT_SAMPLES if value is True else parse_int(value, "--sensitivity-samples", minimum=2)
    check_design(population, samples)
    return samples


def refuse_fixed(population: Population, study: Study, fixed: Mapping[str, str] | None = None) -> list[str]:
    """Rule 2 (a value the user fixed is never drawn over), also for a value fixed after the
    population was attached (a Weber fraction typed beside a population's result); returns the
    notes of its exception."""
    notes = []
    fixed = fixed or {}
    declaring = study.finger.skin == "layered"
    given = {**study.fixed, **fixed}
    for name, label in given.items():
        if name not in population.distributions:
            continue
        if declaring and name in DECLARING_LAYER and name in study.fixed and name not in fixed:
            notes.append(f"population: {label} declares the layered skin; the population {population.name!r} draws "
                         f"{name} for every member")
            continue
        raise FingerpadError(f"{label}: the population {population.name!r} draws {name} for every finger, which "
                             f"would override the value given here; drop it here or take {name} out of the "
                             "population")
    return notes


def _notes(population: Population, study: Study, quantiles: Sequence[float]) -> list[str]:
    """Rule 7."""
    notes = list(population.notes)
    if not population.distributions and not population.measured:
        notes.append(f"population {population.name!r}: its table draws no parameter, so its {population.size} "
                     "members are copies of the study's finger")
    if "ridge_fraction" in population.distributions and population.distributions["ridge_fraction"].spread:
        notes.append(RIDGE_FRACTION_NOTE)
    if study.model == "both":
        notes.append("population: the BEM curves only (model both)")
    # Hertz (Eqs. 3.1-3.6) sees a layered skin as the half-space of its layer: a spread of the
    # layer's thickness or the tissue under it changes no member's curve, which must be said.
    unseen = [n for n in ("skin_layer_thickness", "skin_substrate_modulus", "skin_substrate_poisson")
              if n in population.distributions]
    if study.model == "hertz" and unseen:
        notes.append(f"population: the Hertz model takes each member's skin as the half-space of its layer, so "
                     f"the spread of {', '.join(unseen)} does not enter its curves; --model bem has the layer")
    # A layered cell is scale-free only at fixed proportions (t / L, E_1 / E*, E_2 / E*, the
    # Poisson ratios): a member that changes any of them is a BEM cell of its own, a cost that
    # grows with the population (1-2 s a member on 2 cores) and is said before it is paid.
    varied = [n for n in ("skin_modulus", "skin_poisson", *LAYER_FIELDS) if n in population.distributions]
    if study.finger.skin == "layered" and study.model != "hertz" and varied:
        notes.append(f"population: a layered skin whose {', '.join(varied)} varies gives each such member a BEM "
                     "unit cell of its own (solved or read from the cache), not one cell for all")
    if study.model != "hertz" and (study.finger.adhesive or "work_of_adhesion" in population.distributions):
        from ..micro.adhesive_family import MAX_FAMILY_CELLS, MAX_REFINED_CELLS

        notes.append(ADHESION_NOTE.format(cells=MAX_FAMILY_CELLS, more=MAX_REFINED_CELLS))
    n = len(population.measured) or population.size
    outer = [q for q in quantiles if min(q, 1 - q) * n < 1]
    if population.measured and n < FEW_MEMBERS and outer:
        shown = ", ".join(f"{100 * q:g} %" for q in outer)
        people = "1 person" if n == 1 else f"{n} people"
        notes.append(f"population {population.name!r}: {people}; the {shown} bands lie beyond what {people} "
                     f"{'shows' if n == 1 else 'show'} (fewer than one person outside them): they are the range of "
                     "the panel, not of the population it was drawn from")
    return notes


def adhesion_rules(population: Population, study: Study, fingers: Sequence[Finger]) -> None:
    """Rule 3's adhesion: every member adheres or none, on a half-space skin, with the study's
    range (the family of :mod:`fingerpad.micro.adhesive_family` is one-dimensional in
    ``w / (E* Lx)``). Nothing to check when no finger adheres.

    Raises
    ------
    FingerpadError
        :data:`~.adhesion.ADHESION_MIXED`, :data:`ADHESION_LAYERED` or :data:`ADHESION_RANGE_DRAWN`.
    """
    adhesive = [f.adhesive for f in fingers]
    if not study.finger.adhesive and not any(adhesive):
        return
    if not all(adhesive):
        raise FingerpadError(ADHESION_MIXED)
    if "adhesion_range" in population.distributions:
        raise FingerpadError(ADHESION_RANGE_DRAWN)
    if study.model != "hertz" and (study.finger.skin == "layered" or any(f.layer is not None for f in fingers)):
        raise FingerpadError(ADHESION_LAYERED)


def attach(study: Study, population: Population | Mapping[str, Any] | str | Path | None = None, *,
           table: Mapping[str, Any] | None = None, quantiles: str | Sequence[float] | None = None,
           sensitivity: bool | int | str | None = None, fixed: Mapping[str, str] | None = None,
           axes: Sequence[str] = ()) -> PopulationStudy | None:
    """Attach a population to ``study``, every rule of the module docstring checked, before any
    work; ``None`` without a population.

    Parameters
    ----------
    study
        The checked study (:func:`fingerpad.study.spec.study_from_dict`); its
        :attr:`~fingerpad.study.spec.Study.fixed` names the finger values the user gave.
    population
        A preset name, a TOML file, an ``analyse`` folder, a table (SI numbers) or a
        :class:`~.distributions.Population`; ``None``: ``table``, if any.
    table
        The study file's own ``[population]`` table (with units, as in a file).
    quantiles
        The quantile levels (:func:`quantile_levels`); ``None``: :data:`DEFAULT_QUANTILES`.
    sensitivity
        The Sobol indices' base samples (:func:`sensitivity_samples`).
    fixed
        Further values the caller fixes: ``{parameter: how the user named it}``, e.g. a sweep's
        finger axes (``{"tau0": "[sweep.axes] tau0"}``) or a design's ``--vary``.
    axes
        The names of a sweep's other axes (a ``direction`` axis is refused).

    Raises
    ------
    FingerpadError
        The message of the rule broken.
    """
    pop = resolve_population(population, study, table)
    if pop is None:
        if quantiles is not None:
            raise FingerpadError("--quantiles needs a population (--population or a [population] table)")
        sensitivity_samples(sensitivity, None)
        return None
    levels = quantile_levels(quantiles)
    samples = sensitivity_samples(sensitivity, pop)
    if "direction" in axes:
        raise FingerpadError(f"[sweep.axes] direction: {DIRECTION_REFUSED}")
    if study.direction is not None:
        raise FingerpadError(f"--direction ([model] direction) with --population: {DIRECTION_REFUSED}")
    notes = refuse_fixed(pop, study, fixed)
    members = pop.sample()
    fingers = tuple(member_finger(study.finger, m) for m in members)  # bounds checked before any solve
    adhesion_rules(pop, study, fingers)
    members_plausible(pop, members)
    notes += _notes(pop, study, levels)
    return PopulationStudy(study, pop, tuple(members), fingers, levels, samples, tuple(dict.fromkeys(notes)))

