"""Plane-strain, nearly incompressible neo-Hookean solid on Q2 elements.

Strain energy per unit reference volume (F the 3-D deformation gradient with ``F33 = 1``,
``J = det F``, ``I1 = tr(F^T F)``)::

    W(F) = mu/2 (J^(-2/3) I1 - 3) + kappa/4 (J^2 - 1 - 2 ln J)

The isochoric part is the standard compressible neo-Hookean split; the volumetric function
``U(J) = kappa/4 (J^2 - 1 - 2 ln J)`` grows without bound as ``J -> 0`` (an element cannot be
squeezed to nothing) and has ``U''(1) = kappa``, so the small-strain limit is linear elasticity
with Young's modulus E and Poisson ratio nu (``mu = E/(2(1+nu))``, ``kappa = E/(3(1-2nu))``).

Selective reduced integration: the isochoric energy is integrated with 3x3 Gauss points and
the volumetric energy with 2x2. The discrete energy is still a well-defined function of the
nodal displacements, so the tangent below is its exact (symmetric) Hessian, and the reduced
volumetric rule removes volumetric locking of Q2 elements at nu -> 0.5 (it acts like a
discontinuous bilinear pressure).

``linear=True`` replaces W by its small-strain quadratic limit (same split, same quadrature):
the reference "small-strain solution" the validation compares with.

Everything is vectorised over elements and quadrature points (no Python loop per element).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .mesh import SectionMesh

_G3 = (np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)]), np.array([5.0, 8.0, 5.0]) / 9.0)
_G2 = (np.array([-1.0, 1.0]) / np.sqrt(3.0), np.array([1.0, 1.0]))


def _lagrange2(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """1-D quadratic Lagrange functions on nodes (-1, 0, 1) and their derivatives at t."""
    n = np.stack([0.5 * t * (t - 1.0), 1.0 - t * t, 0.5 * t * (t + 1.0)], axis=-1)
    d = np.stack([t - 0.5, -2.0 * t, t + 0.5], axis=-1)
    return n, d


def _reference_gradients(rule: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """dN/d(xi, eta) (nq, 9, 2) and weights (nq,) of the Q2 element on a tensor Gauss rule."""
    pts, w = rule
    xi, eta = np.meshgrid(pts, pts, indexing="ij")
    wq = np.outer(w, w).ravel()
    nx, dx = _lagrange2(xi.ravel())
    ny, dy = _lagrange2(eta.ravel())
    a, b = np.meshgrid(np.arange(3), np.arange(3), indexing="xy")
    la, lb = a.ravel(), b.ravel()
    grad = np.stack([dx[:, la] * ny[:, lb], nx[:, la] * dy[:, lb]], axis=-1)
    return grad, wq


@dataclass
class _Rule:
    grad: np.ndarray  # (e, q, 9, 2) dN/dX in the reference configuration
    wdet: np.ndarray  # (e, q) weight * det(dX/dxi)
    bmat: np.ndarray | None = None  # (e, q, 4, 18): dF_iJ / du_(k,i'), constant (total Lagrangian)

    def __post_init__(self) -> None:
        e, q = self.wdet.shape
        b = np.zeros((e, q, 2, 2, 9, 2))
        for i in range(2):
            b[:, :, i, :, :, i] = np.swapaxes(self.grad, -1, -2)
        self.bmat = b.reshape(e, q, 4, 18)


def _physical(nodes: np.ndarray, elements: np.ndarray, rule: tuple[np.ndarray, np.ndarray]) -> _Rule:
    gref, wq = _reference_gradients(rule)
    xe = nodes[elements]  # (e, 9, 2)
    jac = np.einsum("eki,qkj->eqij", xe, gref)  # dX_i/dxi_j
    det = jac[..., 0, 0] * jac[..., 1, 1] - jac[..., 0, 1] * jac[..., 1, 0]
    if np.any(det <= 0):
        raise RuntimeError("mesh: an element has a non-positive Jacobian")
    inv = np.empty_like(jac)
    inv[..., 0, 0], inv[..., 1, 1] = jac[..., 1, 1] / det, jac[..., 0, 0] / det
    inv[..., 0, 1], inv[..., 1, 0] = -jac[..., 0, 1] / det, -jac[..., 1, 0] / det
    grad = np.einsum("qkj,eqji->eqki", gref, inv)
    return _Rule(grad, wq[None, :] * det)


def _inverse_transpose(f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    det = f[..., 0, 0] * f[..., 1, 1] - f[..., 0, 1] * f[..., 1, 0]
    h = np.empty_like(f)
    h[..., 0, 0], h[..., 1, 1] = f[..., 1, 1] / det, f[..., 0, 0] / det
    h[..., 0, 1], h[..., 1, 0] = -f[..., 1, 0] / det, -f[..., 0, 1] / det
    return det, h


_I2 = np.eye(2)
_DELTA4 = np.einsum("ik,jl->ijkl", _I2, _I2)  # d_ik d_JL
_SWAP4 = np.einsum("il,jk->ijkl", _I2, _I2)  # d_iL d_kJ
_TRACE4 = np.einsum("ij,kl->ijkl", _I2, _I2)  # d_iJ d_kL


def _outer(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a_ij b_kl`` (..., 2, 2, 2, 2): one product per entry, the numbers einsum gave, by
    broadcasting (no einsum parsing and general loop per call)."""
    return a[..., :, :, None, None] * b[..., None, None, :, :]


def _outer_swapped(h: np.ndarray) -> np.ndarray:
    """``h_il h_kj`` (..., 2, 2, 2, 2), as :func:`_outer`."""
    return h[..., :, None, None, :] * np.swapaxes(h, -1, -2)[..., None, :, :, None]


def isochoric(f: np.ndarray, mu: float, linear: bool = False,
              tangent: bool = True, stress: bool = True) -> tuple[np.ndarray | None, np.ndarray | None]:
    """First Piola stress and tangent dP/dF of ``mu/2 (J^-2/3 I1 - 3)`` (plane strain);
    ``tangent=False`` returns the stress only (None for the tangent), ``stress=False`` the
    tangent only (None for the stress: :meth:`Solid.assemble` already holds it)."""
    if linear:
        a = mu * (_DELTA4 + _SWAP4 - 2.0 / 3.0 * _TRACE4)
        return np.einsum("ijkl,...kl->...ij", a, f - _I2), np.broadcast_to(a, f.shape[:-2] + (2, 2, 2, 2))
    det, h = _inverse_transpose(f)
    i1 = np.einsum("...ij,...ij->...", f, f) + 1.0
    c = mu * det ** (-2.0 / 3.0)
    p = c[..., None, None] * (f - (i1 / 3.0)[..., None, None] * h) if stress else None
    if not tangent:
        return p, None
    # c (d_ik d_JL - 2/3 (F_iJ H_kL + F_kL H_iJ) + 2/9 I1 H_iJ H_kL + I1/3 H_iL H_kJ), each
    # product and sum in that order (the numbers of the one expression it was), in place: the
    # 16 entries per Gauss point go through four arrays instead of eleven
    i1_ = i1[..., None, None, None, None]
    fh = _outer(f, h)
    a = fh + np.swapaxes(np.swapaxes(fh, -4, -2), -3, -1)
    a *= 2.0 / 3.0
    np.subtract(_DELTA4, a, out=a)
    hh = _outer(h, h)
    hh *= 2.0 / 9.0 * i1_
    a += hh
    hs = _outer_swapped(h)
    hs *= i1_ / 3.0
    a += hs
    a *= c[..., None, None, None, None]
    return p, a


def volumetric(f: np.ndarray, kappa: float, linear: bool = False,
               tangent: bool = True, stress: bool = True) -> tuple[np.ndarray | None, np.ndarray | None]:
    """First Piola stress and tangent of ``U(J) = kappa/4 (J^2 - 1 - 2 ln J)``;
    ``tangent=False`` returns the stress only (None for the tangent), ``stress=False`` the
    tangent only (None for the stress)."""
    if linear:
        a = kappa * _TRACE4
        return np.einsum("ijkl,...kl->...ij", a, f - _I2), np.broadcast_to(a, f.shape[:-2] + (2, 2, 2, 2))
    det, h = _inverse_transpose(f)
    d1 = 0.5 * kappa * (det - 1.0 / det)  # U'
    d2 = 0.5 * kappa * (1.0 + 1.0 / det**2)  # U''
    p = (d1 * det)[..., None, None] * h if stress else None
    if not tangent:
        return p, None
    # (U'' J^2 + U' J) H_iJ H_kL - U' J H_iL H_kJ, in place (the same products, in that order)
    a = _outer(h, h)
    a *= (d2 * det**2 + d1 * det)[..., None, None, None, None]
    hs = _outer_swapped(h)
    hs *= (d1 * det)[..., None, None, None, None]
    a -= hs
    return p, a


def csr_slots(rows: np.ndarray, cols: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """CSR pattern of an ``n x n`` matrix with entries at (``rows``, ``cols``), repeats summed.

    Returns ``slot`` (the position of each entry in the CSR data, so that the data is
    ``np.bincount(slot, weights=values)``), ``indices`` and ``indptr`` (sorted columns).
    """
    key = np.asarray(rows, dtype=np.int64) * n + cols
    uniq, slot = np.unique(key, return_inverse=True)
    indices = (uniq % n).astype(np.int32)
    indptr = np.searchsorted(uniq // n, np.arange(n + 1)).astype(np.int32)
    return slot, indices, indptr


def summed(values: np.ndarray, rows: np.ndarray, cols: np.ndarray, shape: tuple[int, int],
           fmt: str = "csc") -> sp.csc_matrix | sp.csr_matrix:
    """``sp.csc_matrix((values, (rows, cols)), shape=shape)`` (``fmt="csr"``: ``sp.csr_matrix``),
    the same matrix to the bit, without the constructor's checks and copies (a Newton
    iteration's Jacobian: ~1e5 entries, 0.5-3 ms of Python around 1.5 ms of work).

    It runs SciPy's own compiled steps on the same arrays in the same order: the COO entries
    bucketed by column (row) in their input order, each column's rows sorted, repeats summed in
    the order the sort left them (which decides the last bit of an entry with three or more
    terms). Where those routines are not importable, the constructor itself."""
    cls = sp.csc_matrix if fmt == "csc" else sp.csr_matrix
    try:
        from scipy.sparse._sparsetools import coo_tocsr, csr_sort_indices, csr_sum_duplicates
    except ImportError:  # pragma: no cover - a SciPy without them: the public path
        return cls((values, (rows, cols)), shape=shape)
    n_rows, n_cols = int(shape[0]), int(shape[1])
    major, minor, n_major, n_minor = (cols, rows, n_cols, n_rows) if fmt == "csc" else (rows, cols, n_rows, n_cols)
    nnz = int(values.size)
    # the index type the constructor picks (int32 unless a dimension or the count needs more)
    idx = np.int32 if max(n_rows, n_cols, nnz) < np.iinfo(np.int32).max else np.int64
    indptr = np.empty(n_major + 1, dtype=idx)
    indices = np.empty(nnz, dtype=idx)
    data = np.empty(nnz, dtype=np.float64)
    coo_tocsr(n_major, n_minor, nnz, major.astype(idx, copy=False), minor.astype(idx, copy=False),
              values.astype(np.float64, copy=False), indptr, indices, data)
    csr_sort_indices(n_major, indptr, indices, data)
    csr_sum_duplicates(n_major, n_minor, indptr, indices, data)
    end = int(indptr[-1])
    out = cls((data[:end], indices[:end], indptr), shape=(n_rows, n_cols), copy=False)
    out.has_canonical_format = True
    return out


class Solid:
    """Internal forces and tangent stiffness of the meshed section.

    Parameters
    ----------
    mesh
        The section mesh (dimensionless lengths).
    shear_modulus, bulk_modulus
        mu and kappa in the solver's stress unit.
    linear
        Small-strain kinematics and material (the linear reference solution).
    """

    def __init__(self, mesh: SectionMesh, shear_modulus: float, bulk_modulus: float, linear: bool = False) -> None:
        self.mesh = mesh
        self.mu = float(shear_modulus)
        self.kappa = float(bulk_modulus)
        self.linear = bool(linear)
        self.full = _physical(mesh.nodes, mesh.elements, _G3)
        self.reduced = _physical(mesh.nodes, mesh.elements, _G2)
        conn = mesh.elements
        self.edofs = (2 * conn[:, :, None] + np.arange(2)[None, None, :]).reshape(conn.shape[0], 18)
        self.ndof = 2 * mesh.n_nodes
        rows = np.repeat(self.edofs, 18, axis=1).ravel()
        cols = np.tile(self.edofs, (1, 18)).ravel()
        # the stiffness pattern once: CSR slot of every element-matrix entry (sorted columns), so
        # that assembling is one weighted bincount into the slots
        self._slot, self._indices, self._indptr = csr_slots(rows, cols, self.ndof)
        # B^T of each rule (full, reduced) with the quadrature points stacked: (e, 18, 4 q), for
        # one batched product
        self._bt = tuple(np.ascontiguousarray(np.swapaxes(rule.bmat, -1, -2).transpose(0, 2, 1, 3).reshape(
            rule.bmat.shape[0], 18, -1)) for rule in (self.full, self.reduced))
        self._memo: list[dict] = []

    @property
    def pattern(self) -> tuple[np.ndarray, np.ndarray]:
        """CSR ``(indptr, indices)`` of the stiffness :meth:`assemble` returns (fixed by the mesh)."""
        return self._indptr, self._indices

    def deformation_gradients(self, u: np.ndarray, rule: _Rule) -> np.ndarray:
        ue = u.reshape(-1, 2)[self.mesh.elements]  # (e, 9, 2)
        return _I2 + np.matmul(np.swapaxes(ue, 1, 2)[:, None], rule.grad)  # sum_k u_ki dN_k/dX_j

    def _kinematics(self, u: np.ndarray) -> dict:
        """Deformation gradients of both rules at ``u`` (and, once computed, the internal force,
        the stiffness and the smallest J there), memoised for the last few displacement fields: the Newton
        iteration asks for the same state up to four times (element-inversion check, line-search
        merit, next iteration's tangent), and the values are the same arrays each time."""
        for entry in self._memo:
            if np.array_equal(entry["u"], u):
                return entry
        entry = {"u": np.array(u, dtype=float, copy=True),
                 "f": tuple(self.deformation_gradients(u, rule) for rule in (self.full, self.reduced))}
        self._memo.insert(0, entry)
        del self._memo[4:]
        return entry

    def min_jacobian(self, u: np.ndarray) -> float:
        """Smallest J over all quadrature points (<= 0 means an inverted element)."""
        entry = self._kinematics(u)
        if "jmin" not in entry:
            jmin = np.inf
            for f in entry["f"]:
                jmin = min(jmin, float(np.min(f[..., 0, 0] * f[..., 1, 1] - f[..., 0, 1] * f[..., 1, 0])))
            entry["jmin"] = jmin
        return entry["jmin"]

    def assemble(self, u: np.ndarray, tangent: bool = True) -> tuple[np.ndarray, sp.csr_matrix | None]:
        """Internal force vector (ndof,) and, with ``tangent``, the stiffness (ndof x ndof)."""
        entry = self._kinematics(u)
        known = entry.get("fint")
        if known is not None and not tangent:
            return known.copy(), None
        if known is not None and "k" in entry:
            # a converged state's tangent again (its stability check, a re-paired iteration)
            return known.copy(), entry["k"].copy()
        ne = self.edofs.shape[0]
        fe = np.zeros((ne, 18)) if known is None else None
        ke = np.zeros((ne, 18, 18)) if tangent else None
        for f, rule, bt, law, modulus in zip(entry["f"], (self.full, self.reduced), self._bt,
                                             (isochoric, volumetric), (self.mu, self.kappa)):
            # the stress only where the force is not known yet (a line search's merit computed
            # it at this state, and the tangent follows there)
            p, a = law(f, modulus, self.linear, tangent=tangent, stress=known is None)
            # bt (e, 18, 4 q): sum over q and the stress components at once
            if known is None:
                pw = p.reshape(ne, -1) * np.repeat(rule.wdet, 4, axis=1)
                fe += np.matmul(bt, pw[..., None])[..., 0]
            if tangent:
                nq = rule.wdet.shape[1]
                aw = a.reshape(ne, nq, 4, 4) * rule.wdet[..., None, None]
                ke += np.matmul(bt, np.matmul(aw, rule.bmat).reshape(ne, 4 * nq, 18))
        if known is None:
            fint = np.bincount(self.edofs.ravel(), weights=fe.ravel(), minlength=self.ndof)
            entry["fint"] = fint.copy()
        else:
            fint = known.copy()
        if not tangent:
            return fint, None
        data = np.bincount(self._slot, weights=ke.reshape(-1), minlength=self._indices.size)
        k = sp.csr_matrix((data, self._indices, self._indptr), shape=(self.ndof, self.ndof))
        k.has_sorted_indices = True
        entry["k"] = k.copy()
        return fint, k
