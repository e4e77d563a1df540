"""Design for perception: ``feels-different-from=REF@LOAD`` and ``feels-like=REF@LOAD`` targets.

A candidate texture *feels different* from the reference surface REF (a study file, or ``flat``)
to a finger when that person tells the two apart by friction at the load, ``P >= 0.75`` in a
forced choice (:mod:`fingerpad.perception.discrimination`, Eqs. P.1-P.3); it *feels like* REF when
``P < 0.75``. With ``--coverage C`` (and a population) the target is met when at least the
fraction ``C`` of the fingers meet it: ``feels-different-from`` with ``C = 0.9`` is a texture
that 90 % tell apart from REF, ``feels-like`` with ``C = 0.9`` one that at most 10 % tell apart.
Without a population the study's finger alone decides. Friction targets combine with them: a
finger meets the design when it meets every target.

REF is predicted once, directly, on the same fingers (REF's texture, material and numerics, the
design study's finger; every member of the population, by
:func:`fingerpad.population.run.run_population`), at the targets' loads. A member's *margin*
is ``m = |ln(mu / mu_REF)| / ln(1 + W)``: it tells the two apart exactly when ``m >= 1``. The
search's score of a member for such a target is 0 when it meets it and ``(shortfall + tolerance)^2``
otherwise (shortfall ``1 - m`` or ``m - 1``), so that, as for a friction target, a member's score
lies within ``tolerance^2`` exactly when it meets the target (:mod:`fingerpad.design.robust`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import FingerpadError

__all__ = ["KINDS", "PerceptionTarget", "check_goal", "describe", "is_perception", "member_verdicts",
           "parse_perception_target", "reference_friction"]

#: The perception targets and what they ask.
KINDS = {"feels-different-from": "at least the coverage of the fingers tell it from REF",
         "feels-like": "at most 1 - coverage of the fingers tell it from REF"}


@dataclass(frozen=True)
class PerceptionTarget:
    """``quantity`` (a key of :data:`KINDS`) against the surface ``reference`` (a study file or
    ``"flat"``) at ``load`` (N)."""

    quantity: str
    reference: str
    load: float

    def __str__(self) -> str:
        return f"{self.quantity}={self.reference}@{self.load:g}N"

    @property
    def different(self) -> bool:
        return self.quantity == "feels-different-from"


def parse_perception_target(name: str, reference: str, load: str, text: str) -> PerceptionTarget:
    """A :class:`PerceptionTarget` from the parts of ``--target NAME=REF@LOAD`` (``text`` for
    messages); REF must be ``flat`` or an existing study file."""
    from pathlib import Path

    from ..units import parse_positive

    ref = reference.strip()
    if ref.lower() != "flat" and not Path(ref).is_file():
        raise FingerpadError(f"--target {text!r}: the reference {ref!r} is neither 'flat' nor a study file")
    return PerceptionTarget(name, "flat" if ref.lower() == "flat" else ref,
                            parse_positive(load, "force", name="--target"))


def reference_friction(targets: Sequence[Any], base: Mapping[str, Any], population: Any,
                       weber: np.ndarray) -> dict[str, np.ndarray | None]:
    """Each perception target's reference friction per member at its load (``None`` for ``flat``:
    each candidate's own ``mu_ref``), by a direct prediction of REF on the design study's fingers
    (``population``'s members, or the study's finger alone: one row)."""
    from ..study.spec import load_study_file, study_from_dict

    study = study_from_dict({k: dict(v) for k, v in base.items()})
    out: dict[str, np.ndarray | None] = {}
    for t in targets:
        if not isinstance(t, PerceptionTarget):
            continue
        if t.reference == "flat":
            out[str(t)] = None
            continue
        ref = load_study_file(t.reference)
        ref = dataclasses.replace(ref, finger=study.finger, loads=np.array([t.load]), zones_at=None,
                                  fixed=dict(study.fixed))
        if population is not None:
            from ..population.run import run_population

            out[str(t)] = run_population(ref, population).values("mu")[:, 0]
        else:
            from ..study.run import run_study

            out[str(t)] = np.asarray(run_study(ref).primary.mu, float)[:1]
        if out[str(t)].shape[0] != weber.shape[0]:  # pragma: no cover - the same members by construction
            raise FingerpadError("reference and design have different members")
    return out


def member_verdicts(target: PerceptionTarget, mu: np.ndarray, mu_ref_own: np.ndarray,
                    reference: np.ndarray | None, weber: np.ndarray, tolerance: float) -> dict[str, np.ndarray]:
    """Per member for one target: ``p_correct`` (Eqs. P.1-P.3), ``ok`` (meets the target),
    ``score`` (0 if it does, else ``(shortfall + tolerance)^2``).

    ``mu``: the candidate's friction per member at the target's load; ``mu_ref_own``: the
    members' flat-reference friction there (the reference when REF is ``flat``);
    ``reference``: REF's friction per member (``None`` for ``flat``)."""
    from ..perception.discrimination import discriminates, log_ratio_threshold, p_correct

    ref = np.asarray(mu_ref_own if reference is None else reference, float)
    mu = np.asarray(mu, float)
    w = np.asarray(weber, float)
    p = p_correct(mu, ref, w)
    tells = discriminates(p)
    ok = tells if target.different else ~tells
    margin = np.abs(np.log(mu) - np.log(ref)) / log_ratio_threshold(w)
    shortfall = np.maximum(1.0 - margin, 0.0) if target.different else np.maximum(margin - 1.0, 0.0)
    score = np.where(ok, 0.0, (shortfall + tolerance) ** 2)
    return {"p_correct": p, "ok": ok, "score": score}


def describe(target: PerceptionTarget) -> str:
    """The target in words, for tables."""
    return f"{'tell it from' if target.different else 'cannot tell it from'} {target.reference} at {target.load:g} N"


def is_perception(target: Any) -> bool:
    return isinstance(target, PerceptionTarget)


def check_goal(targets: Sequence[Any], goal: Any, from_sweep: Any) -> None:
    """Refuse what a perception target cannot be designed with, before any prediction."""
    if not any(is_perception(t) for t in targets):
        return
    names = ", ".join(str(t) for t in targets if is_perception(t))
    if goal is not None and goal.quantile is not None:
        raise FingerpadError(f"--target {names}: a perception target counts the fingers who tell the textures "
                             "apart; use --coverage C, not --quantile")
    if from_sweep is not None:
        raise FingerpadError(f"--target {names} with --from-sweep: a sweep's candidates are chosen by the "
                             "friction of its study's finger, not by who tells them from the reference; drop "
                             "--from-sweep (the optimisation predicts directly)")

