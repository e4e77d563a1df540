"""A person's parameters that are not the finger's mechanics: the Weber fraction of friction.

The finger (:mod:`fingerpad.finger`) holds what decides contact and friction; a person also
judges what the finger feels. The one such parameter so far is the Weber fraction ``W`` of
friction, the relative friction difference a person tells apart in 75 % of forced choices
(:mod:`fingerpad.perception.discrimination`, Eq. P.3). It is declared here, below the study, the
populations and the perception models, so that each reads the one declaration:

* a study file's ``[perception] weber_fraction``, ``--weber-fraction``, the explorer's field and
  the Python API (:attr:`fingerpad.study.spec.Study.weber_fraction`) set it for the study's person;
* a population draws it (:data:`fingerpad.population.distributions.POPULATION_PARAMS`), e.g. with
  :data:`WEBER_SPREAD`, the spread of the built-in ``adults``;
* a value the user set and a population that draws it are refused together, with the message of
  every other such pair (:func:`fingerpad.population.rules.attach`).

Sources and what is measured or assumed: docs/perception.md, "Where the numbers come from".
"""

from __future__ import annotations

from typing import Any

from .params import Param

__all__ = ["PERSON_PARAMS", "WEBER_FRACTION", "WEBER_SPREAD"]

#: The Weber fraction of friction. Default 0.11: Gueorguiev et al. (J. R. Soc. Interface
#: 14:20170641, 2017) measured 0.11 in every condition for transient friction decreases (forced
#: choice); Sahli et al. (Sci. Rep. 10:15800, 2020) found friction differences of 0.035 at
#: mu 0.34-0.45 noticed (about 0.08-0.10 relative); Fehlberg et al. (LNCS 13235:21, 2022) about
#: 0.2 on micro-pillar samples in active touch.
WEBER_FRACTION = Param(
    "weber_fraction", "ratio",
    "relative friction difference a person tells apart in 75 % of forced choices (Weber fraction W, Eq. P.3)",
    0.11, low=0.0, low_open=True, high=2.0, example="0.11", label="Weber fraction W",
    symbol="W")

#: The spread of W over people, as a ``[population]`` entry. No study we found reports W
#: person by person, so the shape is ASSUMED: lognormal (W > 0, Weber fractions are compared as
#: ratios) with its median at Gueorguiev et al.'s 0.11 and sigma = ln(0.2 / 0.11) / 1.645 = 0.36,
#: so that the largest published value, Fehlberg et al.'s 0.2 on textured samples, is the 95th
#: percentile (the 5th is 0.061). Sahli et al.'s ~0.09 lies at the 29th percentile.
WEBER_SPREAD: dict[str, Any] = {"distribution": "lognormal", "median": 0.11, "sigma": 0.36}

#: Every parameter of a person that is not the finger's (a population may draw each).
PERSON_PARAMS: tuple[Param, ...] = (WEBER_FRACTION,)
