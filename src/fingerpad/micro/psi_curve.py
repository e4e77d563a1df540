"""Reading a unit cell's computed psi(p) nodes: the interpolant, the exact disc average of
Eq. 3.11 over it, its leave-one-out error, and the curve at another modulus (p/E* scaling).

Split from :mod:`fingerpad.micro.bem`, which solves and caches the nodes; this module only
reads them. :class:`InterpolatedCurve` is the reading half of
:class:`~fingerpad.micro.bem.BEMUnitCell`: it needs the cell's unit nodes ``_unit_points``
(pressures in units of E*), its transition bracket ``_transition``, ``flat``, ``modulus`` (E*,
Pa) and the three memo slots ``_interp``, ``_phi`` and ``_node_arrays``, emptied whenever the
nodes change.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import FingerpadError

__all__ = ["InterpolatedCurve", "ScaledResponse", "piecewise_pchip"]


class InterpolatedCurve:
    """psi(p) read from a cell's computed nodes (PCHIP in log p on each side of the transition
    kink, linear across its narrow bracket); see the module docstring for what it needs."""

    _unit_points: dict[float, dict[str, Any]]
    _transition: tuple[float, float] | None
    _interp: Any
    _phi: tuple[np.ndarray, np.ndarray, float] | None
    _node_arrays: tuple[np.ndarray, np.ndarray] | None
    flat: bool
    modulus: float

    def _nodes(self) -> tuple[np.ndarray, np.ndarray]:
        """The unit cell's nodes: pressures (units of E*) and psi (kept until the nodes change:
        every psi and disc fraction reads them, a model table some 2000 times)."""
        if self._node_arrays is None:
            ps = np.array(sorted(self._unit_points))
            psi = np.array([self._unit_points[p]["contact_fraction"] for p in ps])
            # A monotone curve by construction of the physics; enforce it against last-digit noise.
            self._node_arrays = (ps, np.maximum.accumulate(psi))
        return self._node_arrays

    def _pieces(self) -> list[np.ndarray]:
        """Index sets of the nodes on either side of the transition kink (PCHIP per piece)."""
        ps, _ = self._nodes()
        if self._transition is None or not math.isfinite(self._transition[1]):
            return [np.arange(ps.size)]
        lo, hi = self._transition
        left = np.flatnonzero(ps <= lo * (1 + 1e-12))
        right = np.flatnonzero(ps >= hi * (1 - 1e-12))
        return [piece for piece in (left, right) if piece.size]

    def _build(self) -> Any:
        ps, psi = self._nodes()
        if ps.size < 3:
            raise FingerpadError("unit cell not prepared: call prepare(p_min, p_max) first")
        # linear in log p across the (rtol-narrow) transition bracket, PCHIP on each side
        return piecewise_pchip(np.log(ps), psi, self._pieces())

    def contact_fraction(self, p: "np.ndarray | float") -> np.ndarray:
        """psi(p): real-to-nominal contact area fraction of the cell at mean pressure ``p`` (Pa).

        The unit cell's curve at ``p / E*``: a cell at k E* and pressure k p gives the same
        number (bit for bit when k is a power of two, when k p / k E* is exactly p / E*)."""
        p = np.asarray(p, dtype=float)
        if self.flat:
            return np.where(p > 0, 1.0, 0.0)
        p = p / self.modulus
        if self._interp is None:
            self._interp = self._build()
        ps, psi = self._nodes()
        out = np.zeros_like(p)
        pos = p > 0
        lp = np.log(np.where(pos, p, 1.0))
        inside = pos & (p >= ps[0]) & (p <= ps[-1])
        out[inside] = self._interp(lp[inside])
        low = pos & (p < ps[0])
        if np.any(low):
            slope = math.log(psi[1] / psi[0]) / math.log(ps[1] / ps[0]) if psi[0] > 0 else 2 / 3
            out[low] = psi[0] * (p[low] / ps[0]) ** slope
        high = p > ps[-1]
        if np.any(high):
            # Beyond the computed nodes: hold the last value (psi is non-decreasing and close to 1
            # past full contact); callers prepare the range they use.
            out[high] = psi[-1]
        return np.clip(out, 0.0, 1.0)

    def _antiderivative(self) -> tuple[np.ndarray, np.ndarray, float]:
        """``(nodes, Phi, slope)``: the nodes (Pa), ``Phi(p) = int_0^p psi(u) u du`` (Pa^2) at
        each of them, and the power ``m`` of psi below the first node (``psi0 (p/p0)^m``).

        Below the first node psi is that power law: ``Phi(p0) = psi0 p0^2 / (m + 2)``, exactly.
        Between two nodes the interpolant is one smooth piece (PCHIP or linear in ``x = log p``;
        every kink of the interpolant, the transition bracket's ends included, is a node), so
        ``int psi(e^x) e^{2x} dx`` over it takes :data:`_GAUSS` to round-off (the node spacing
        is well below one unit of ``x``)."""
        if self._phi is None:
            ps, psi = self._nodes()
            if ps.size < 3:
                raise FingerpadError("unit cell not prepared: call prepare(p_min, p_max) first")
            nodes = ps * self.modulus
            slope = math.log(psi[1] / psi[0]) / math.log(ps[1] / ps[0]) if psi[0] > 0 else 2 / 3
            first = float(self.contact_fraction(nodes[:1])[0]) * nodes[0] ** 2 / (slope + 2.0)
            pieces = self._log_gauss(np.log(nodes[:-1]), np.log(nodes[1:]))
            self._phi = (nodes, np.concatenate([[first], first + np.cumsum(pieces)]), slope)
        return self._phi

    def _log_gauss(self, xa: np.ndarray, xb: np.ndarray) -> np.ndarray:
        """``int_{xa}^{xb} psi(e^x) e^{2x} dx`` per entry, by :data:`_GAUSS` (each entry on its
        own: the sum runs point by point, so an entry's value does not depend on the others)."""
        x, w = _GAUSS
        half = 0.5 * (xb - xa)
        u = np.exp(xa[:, None] + half[:, None] * (x[None, :] + 1.0))
        f = np.asarray(self.contact_fraction(u), float) * u * u
        acc = np.zeros_like(xa)
        for k in range(x.size):  # a fixed order of summation, not a BLAS product (bit-stable)
            acc = acc + w[k] * f[:, k]
        return half * acc

    def disc_fraction(self, peak_pressure: "np.ndarray | float") -> np.ndarray:
        """``A_re / A_fr``: the mean of psi over a contact disc whose centre pressure is
        ``peak_pressure`` (Pa, positive), Eq. 3.11 with the pad pressure of Eq. 3.7.

        ``2 int_0^1 psi(P s) s ds = 2 Phi(P) / P^2`` with ``Phi(P) = int_0^P psi(u) u du`` of the
        interpolated curve: the table of :meth:`_antiderivative` at the nodes plus the piece from
        the node below ``P`` (Gauss-Legendre in log p), the power law below the first node and
        the held last value above the last node in closed form. Exact up to round-off for the
        piecewise interpolant (about 1e-15 relative against adaptive quadrature); every entry is
        computed on its own (a member's value does not depend on which others share the call).

        Returns
        -------
        ndarray
            One ratio per entry, shaped like ``peak_pressure``.
        """
        big_p = np.asarray(peak_pressure, dtype=float)
        if self.flat:
            return np.where(big_p > 0, 1.0, 0.0)
        shape = big_p.shape
        big_p = big_p.ravel()
        if not np.all(np.isfinite(big_p) & (big_p > 0)):
            raise FingerpadError("disc centre pressures must be finite and positive")
        nodes, phi, slope = self._antiderivative()
        out = np.empty_like(big_p)
        low = big_p < nodes[0]
        # psi = psi0 (p/p0)^m below the first node: 2 Phi/P^2 = 2 psi(P) / (m + 2)
        out[low] = 2.0 * self.contact_fraction(big_p[low]) / (slope + 2.0)
        high = big_p > nodes[-1]
        last = float(self.contact_fraction(nodes[-1:])[0])
        tail = phi[-1] + 0.5 * last * (big_p[high] - nodes[-1]) * (big_p[high] + nodes[-1])
        out[high] = 2.0 * tail / big_p[high] ** 2
        mid = ~low & ~high
        pm = big_p[mid]
        j = np.clip(np.searchsorted(nodes, pm, side="right") - 1, 0, nodes.size - 1)
        part = self._log_gauss(np.log(nodes[j]), np.log(pm))
        out[mid] = 2.0 * (phi[j] + part) / pm**2
        return out.reshape(shape)

    @property
    def interpolation_error(self) -> float:
        """Leave-one-out bound on the interpolation error of psi (absolute, interior nodes of
        each side of the transition): each node is predicted from its neighbours without it."""
        from scipy.interpolate import PchipInterpolator

        ps, psi = self._nodes()
        lp = np.log(ps)
        worst = math.nan
        for idx in self._pieces():
            for j in range(1, idx.size - 1):
                keep = np.delete(idx, j)
                f = PchipInterpolator(lp[keep], psi[keep])
                err = abs(float(f(lp[idx[j]])) - psi[idx[j]])
                worst = err if math.isnan(worst) else max(worst, err)
        return worst


def piecewise_pchip(x: np.ndarray, y: np.ndarray, pieces: list[np.ndarray]) -> Any:
    """``xq -> y(xq)``: PCHIP on each piece (index sets of the nodes ``x``, ``y``; pieces of fewer
    than two nodes are skipped), linear between the pieces (across a kink or a jump of psi)."""
    from scipy.interpolate import PchipInterpolator

    parts = [(x[idx[0]], x[idx[-1]], PchipInterpolator(x[idx], y[idx])) for idx in pieces if idx.size >= 2]

    def interp(xq: np.ndarray) -> np.ndarray:
        out = np.interp(xq, x, y)
        for a, b, f in parts:
            sel = (xq >= a) & (xq <= b)
            out[sel] = f(xq[sel])
        return out

    return interp


#: Gauss-Legendre rule (nodes, weights on [-1, 1]) per piece of the interpolated curve between
#: two nodes in :meth:`InterpolatedCurve.disc_fraction`: a piece is a cubic in log p times ``p^2``, and
#: 10 points integrate it to round-off at the node spacings of a prepared cell.
_GAUSS = np.polynomial.legendre.leggauss(10)


@dataclass(frozen=True)
class ScaledResponse:
    """A cell's psi(p) at another reduced modulus, without new solves.

    For a rigid (or E*-folded) texture on an elastic half-space the contact problem scales with
    p / E*: the contact fraction at modulus E* and pressure p equals the base curve's at
    ``p E*_base / E*``. So one computed curve serves every skin modulus, e.g. when fitting E_s to
    friction measurements.
    """

    base: InterpolatedCurve  # a prepared BEMUnitCell (which adds the state pressures)
    factor: float  # E*_new / E*_base

    def contact_fraction(self, p: "np.ndarray | float") -> np.ndarray:
        return self.base.contact_fraction(np.asarray(p, dtype=float) / self.factor)

    def disc_fraction(self, peak_pressure: "np.ndarray | float") -> np.ndarray:
        """``A_re / A_fr`` at centre pressure ``peak_pressure`` (Pa): the base cell's
        :meth:`InterpolatedCurve.disc_fraction` at ``peak / factor``."""
        return self.base.disc_fraction(np.asarray(peak_pressure, dtype=float) / self.factor)

    @property
    def transition_pressure(self) -> float:
        return self.base.transition_pressure * self.factor

    @property
    def full_contact_pressure(self) -> float:
        return self.base.full_contact_pressure * self.factor
