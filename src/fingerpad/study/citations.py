"""The publications of the methods a prediction or a solve used, from what each method declares.

Every model class declares its publications (``REFERENCES``, :mod:`fingerpad.references` keys),
so do the friction law (:mod:`fingerpad.friction`), the solver
(:func:`~fingerpad.contact.solver.solver_references`), the deflection model, the sensitivity
indices and the correlated sampling (a population result names its own); this module gathers those of the methods a run's inputs
select (:func:`fingerpad.coupling.model_references` those of the model). The result depends on
the inputs only: a unit cell read from the cache cites the solver that made it.
"""

from __future__ import annotations

from typing import Any

from ..coupling import model_references
from ..references import keys_of

__all__ = ["prediction_references", "solve_references"]


def solve_references(texture: Any, layer: Any = None, adhesion: Any = None) -> tuple[str, ...]:
    """A contact solve of ``texture`` (periodic cell or measured map), with a layered skin or not,
    adhesive or not (``adhesion``: the solve job's, with its ``adhesion_law``)."""
    from ..contact.solver import solver_references

    adhesive: tuple[str, ...] = () if adhesion is None else (
        ("rey2017", "johnson1971") + (("maugis1992",) if adhesion.get("adhesion_law") == "maugis" else ()))
    return keys_of(solver_references(bool(texture.periodic), layer is not None), adhesive)


def prediction_references(pred: Any, population: Any = None) -> tuple[str, ...]:
    """A prediction (:class:`~fingerpad.study.run.Prediction`) and, when given, a result that
    names its own publications by ``references()``, such as the population result it is the
    nominal of (its correlated sampling, its sensitivity indices; the members vary the nominal
    finger's parameters, not its models: :meth:`fingerpad.population.run.PopulationResult.references`)."""
    sources: list[Any] = [model_references(pred.study.finger, pred.cell, pred.hertz_cell)]
    if pred.cell is not None:  # the solver that made the BEM cell's nodes (a unit cell is periodic)
        from ..contact.solver import solver_references

        sources.append(solver_references(True, pred.study.finger.layer is not None))
    if pred.directional is not None:
        from ..micro.deflection import gain

        sources.append(gain)
    if population is not None:  # the population names its own (study/ imports nothing of it)
        sources.append(population.references())
    return keys_of(*sources)
