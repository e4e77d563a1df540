"""Telling two surfaces apart by their friction: a two-alternative forced-choice model on ln(mu).

A person compares the friction of surface A with that of surface B. Each judgement reads the
logarithm of the friction coefficient with Gaussian noise of standard deviation ``sigma``, so the
difference of two readings has the spread ``sqrt(2) sigma`` and the probability of a correct
forced choice is (docs/perception.md, Eqs. P.1-P.3)

* ``d' = |ln mu_A - ln mu_B| / sigma``                                              (P.1)
* ``P = Phi(d' / sqrt 2)``                                                          (P.2)
* ``sigma = ln(1 + W) / (sqrt 2 Phi^-1(0.75)) = ln(1 + W) / 0.9539``                (P.3)

with ``Phi`` the standard normal distribution function. ``W`` is the person's Weber fraction:
a relative friction difference ``W`` (``mu_B = (1 + W) mu_A``) is told apart in 75 % of the
choices, the usual threshold of a forced-choice experiment. A person *tells A from B* when
``P >= 0.75``, i.e. when ``|ln(mu_A / mu_B)| >= ln(1 + W)``.

Only the ratio of the two coefficients enters (Weber's law, which Gueorguiev et al. 2017 found
for friction changes): the model is symmetric in A and B, gives ``P = 1/2`` for identical
surfaces, grows monotonically with ``|ln(mu_A / mu_B)|``, and as ``W -> 0`` any difference is
felt. SI units; every function accepts arrays (members x loads) and broadcasts.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from statistics import NormalDist
from typing import Any

import numpy as np

from ..params import Param

__all__ = ["THRESHOLD", "WEBER_FRACTION", "Z75", "discriminates", "log_ratio_threshold", "noise_sd",
           "p_correct", "summarise"]

#: The publications this module rests on (:mod:`fingerpad.references`).
REFERENCES = ("gueorguiev2017", "sahli2020", "fehlberg2022")

#: The 75 % point of the standard normal distribution, Phi^-1(0.75) = 0.6745 (Eq. P.3).
Z75: float = NormalDist().inv_cdf(0.75)

#: Proportion correct at which a person counts as telling two surfaces apart.
THRESHOLD = 0.75

#: The Weber fraction of friction, a parameter of the person (not of the finger's mechanics):
#: declared once here; the command line (``--weber-fraction``), study files and populations read
#: it through this declaration. Default 0.11: Gueorguiev et al. (J. R. Soc. Interface 14:20170641,
#: 2017) measured 0.11 in every condition for transient friction decreases (forced choice);
#: Sahli et al. (Sci. Rep. 10:15800, 2020) found friction differences of 0.035 at mu 0.34-0.45
#: noticed (about 0.08-0.10 relative); Fehlberg et al. (LNCS 13235:21, 2022) about 0.2 on
#: micro-pillar samples in active touch. docs/perception.md, "Where the numbers come from".
WEBER_FRACTION = Param(
    "weber_fraction", "ratio",
    "relative friction difference a person tells apart in 75 % of forced choices (Weber fraction W, Eq. P.3)",
    0.11, low=0.0, low_open=True, high=2.0, example="0.11", label="Weber fraction W", symbol="W")


def log_ratio_threshold(weber: Any) -> Any:
    """``ln(1 + W)``: the ``|ln(mu_A / mu_B)|`` a person of Weber fraction ``W`` tells apart in
    75 % of forced choices (Eq. P.3)."""
    return np.log1p(np.asarray(weber, float))


def noise_sd(weber: Any) -> Any:
    """``sigma = ln(1 + W) / (sqrt 2 Phi^-1(0.75))``, the judgement noise on ln(mu) (Eq. P.3)."""
    return log_ratio_threshold(weber) / (math.sqrt(2.0) * Z75)


def p_correct(mu_a: Any, mu_b: Any, weber: Any) -> np.ndarray:
    """Probability of a correct forced choice between friction ``mu_a`` and ``mu_b`` (Eqs. P.1-P.2).

    Parameters
    ----------
    mu_a, mu_b
        Friction coefficients (positive), broadcast together (e.g. members x loads).
    weber
        Weber fraction(s) W > 0 (one per member: shape ``(members, 1)`` against members x loads).
        ``W = 0`` is the limit of a perfect observer: 1 for any difference, 1/2 for none.

    Returns
    -------
    numpy.ndarray
        P in [1/2, 1]; exactly 1/2 where ``mu_a == mu_b``.
    """
    from scipy.special import ndtr

    a = np.asarray(mu_a, float)
    b = np.asarray(mu_b, float)
    w = np.asarray(weber, float)
    diff = np.abs(np.log(a) - np.log(b))
    sd = noise_sd(w)
    with np.errstate(divide="ignore", invalid="ignore"):
        d = diff / sd  # Eq. P.1 (sd = 0: inf for a difference, NaN for none)
    p = ndtr(d / math.sqrt(2.0))  # Eq. P.2
    return np.where(diff == 0, 0.5, np.where(np.isnan(d) & (diff > 0), 1.0, p))


def discriminates(p: Any) -> np.ndarray:
    """Whether each P reaches :data:`THRESHOLD` (the person tells the surfaces apart)."""
    return np.asarray(p, float) >= THRESHOLD


def summarise(p: Any) -> Mapping[str, Any]:
    """Per load (the last axis), from the members' P (members x loads): ``fraction`` telling the
    surfaces apart and ``p_correct_median``. The reported numbers are these, recomputed from the
    reported member arrays by the same two lines (``tests/perception``)."""
    arr = np.atleast_2d(np.asarray(p, float))
    return {"fraction": np.mean(discriminates(arr), axis=0), "p_correct_median": np.median(arr, axis=0)}
