"""Correlated parameters of a population: a Gaussian copula on the quasi-random points (issue 22).

A ``[population]`` table may name pairs of its parameters with a rank correlation::

    correlations = [["radius", "modulus", 0.3], ["skin_modulus", "tau0", -0.2]]

Each coefficient is **Spearman's rank correlation** rho_S of the pair. Rank correlation does not
change when a parameter is mapped through its own distribution, so the declared value holds
whatever the marginals (uniform, lognormal, a list of values ...), and the marginals stay exactly
as declared: the unit-cube points ``u`` of the quasi-random sequence are mapped to standard
normals ``z = Phi^-1(u)``, mixed by the Cholesky factor ``L`` of the normal correlation matrix
``R`` (``z' = z L^T``, each column again standard normal) and mapped back, ``u' = Phi(z')``; every
column of ``u'`` is uniform, and each parameter's inverse distribution function is applied to its
column as without correlations. For a Gaussian copula the normal correlation that gives a rank
correlation rho_S is ``r = 2 sin(pi rho_S / 6)`` (Kruskal 1958), which is what ``R`` holds.

``R`` must be a correlation matrix: symmetric, unit diagonal, ``|r| <= 1`` and positive
definite (a perfect correlation, ``|rho_S| = 1``, is singular and refused: use one parameter
and derive the other).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..errors import FingerpadError

__all__ = ["Correlation", "correlate", "normal_correlation_matrix", "parse_correlations"]

#: One declared pair: (name, name, Spearman rank correlation).
Correlation = tuple[str, str, float]

#: The publications of the correlated sampling (:mod:`fingerpad.references` keys): the rank to
#: normal correlation ``r = 2 sin(pi RHO / 6)``.
REFERENCES = ("kruskal1958",)


def parse_correlations(value: Any, names: Sequence[str], where: str) -> tuple[Correlation, ...]:
    """The ``correlations`` entry of a ``[population]`` table, checked.

    Parameters
    ----------
    value
        A list of ``[name, name, rho_S]`` triples.
    names
        The parameters the table gives a distribution (a correlation names two of them).
    where
        The table's name for messages.

    Raises
    ------
    FingerpadError
        Not a list of triples, a name without a distribution, a pair of a name with itself or
        given twice, a coefficient outside [-1, 1], or a matrix that is not positive definite.
    """
    w = f"{where} correlations"
    if not isinstance(value, list):
        raise FingerpadError(f"{w}: expected a list of [name, name, coefficient], e.g. "
                             "[[\"radius\", \"modulus\", 0.3]]")
    out: list[Correlation] = []
    seen: set[frozenset[str]] = set()
    for item in value:
        if not (isinstance(item, list) and len(item) == 3 and all(isinstance(n, str) for n in item[:2])):
            raise FingerpadError(f"{w}: each entry must be [name, name, coefficient], got {item!r}")
        a, b, r = item[0].strip(), item[1].strip(), item[2]
        for n in (a, b):
            if n not in names:
                raise FingerpadError(f"{w}: {n!r} has no distribution in the table "
                                     f"(correlate two of: {', '.join(names) or 'none'})")
        if a == b:
            raise FingerpadError(f"{w}: {a!r} is paired with itself")
        if frozenset((a, b)) in seen:
            raise FingerpadError(f"{w}: the pair {a!r}, {b!r} is given twice")
        seen.add(frozenset((a, b)))
        if isinstance(r, bool) or not isinstance(r, (int, float)) or not math.isfinite(r) or not -1 <= r <= 1:
            raise FingerpadError(f"{w}: the coefficient of {a!r}, {b!r} must be a number in [-1, 1], got {r!r}")
        out.append((a, b, float(r)))
    if out:
        normal_correlation_matrix(out, names, w)  # refuses a matrix that is not positive definite
    return tuple(out)


def normal_correlation_matrix(pairs: Sequence[Correlation], names: Sequence[str], where: str) -> np.ndarray:
    """The Gaussian copula's correlation matrix over ``names`` (unlisted pairs 0), from rank
    correlations: ``r = 2 sin(pi rho_S / 6)``.

    Raises
    ------
    FingerpadError
        When the matrix is not positive definite (no joint distribution has these correlations).
    """
    index = {n: i for i, n in enumerate(names)}
    corr = np.eye(len(names))
    for a, b, rho in pairs:
        corr[index[a], index[b]] = corr[index[b], index[a]] = 2 * math.sin(math.pi * rho / 6)
    smallest = float(np.linalg.eigvalsh(corr)[0]) if len(names) else 1.0
    if not smallest > 1e-10:
        raise FingerpadError(f"{where}: the correlations are not a valid correlation matrix (not positive definite, "
                             f"smallest eigenvalue {smallest:.3g}): no population has them all; weaken some "
                             "(a perfect correlation, +-1, is refused too: derive one parameter from the other)")
    return corr


def correlate(u: np.ndarray, pairs: Sequence[Correlation], names: Sequence[str]) -> np.ndarray:
    """Unit-cube points ``u`` (members x parameters, columns in the order of ``names``) with the
    Gaussian copula of ``pairs`` laid on them; every column stays uniform on (0, 1)."""
    if not pairs:
        return u
    from scipy import stats

    chol = np.linalg.cholesky(normal_correlation_matrix(pairs, names, "correlations"))
    z = stats.norm.ppf(np.clip(u, 1e-12, 1 - 1e-12))
    return stats.norm.cdf(z @ chol.T)
