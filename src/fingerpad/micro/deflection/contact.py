"""Contact operators of the section model: the skin as a periodic elastic half-space, the
surface tiles of Q2 faces, the fold-over (flank on base) penalty and the contact length.

Skin (why a half-space): the package's unit-cell models (BEM, Hertz, Eq. 3.4) treat the skin as
a linear elastic half-space of plane-strain modulus ``E_s* = E_s / (1 - nu_s^2)``; using the
same skin here makes the zero-shear limit reproduce Hertz with the combined modulus E1*
(Eq. 3.4) and keeps one skin model across the package. The skin's strains at the micro scale are
small next to those of a folding asperity, so its geometric non-linearity is the smaller error;
the half-space's own assumption (a nearly flat skin surface) is reported through the largest
slope of the deflected skin surface. Contact with the skin is enforced in the vertical
(normal-to-skin) direction at every top-surface node of the texture -- both flanks, the tip,
a folded flank and the base between asperities -- so an overhang (a folded flank) is shadowed by
the material above it.

Periodic line-load Green's function (plane strain, zero mean over the period lambda): a line
load f per unit depth at x = 0 and its periodic images lift the skin surface by::

    w(x) = -(2 f / (pi E_s*)) ln|2 sin(pi x / lambda)|

(from ``w_k = 2 p_k / (E_s* |k|)`` for each Fourier mode). Each surface node carries its force
spread uniformly over its tile, so the influence coefficients are tile averages of ``w``; the
log singularity is integrated exactly.
"""

from __future__ import annotations

import math

import numpy as np

from .mesh import SectionMesh


def tile_lengths(xs: np.ndarray) -> np.ndarray:
    """Tributary (tile) length of each ordered surface node of Q2 faces (current lengths).

    Faces are the consecutive triples (corner, mid-side, corner); Simpson's weights give the
    mid-side node 2/3 of its face and each corner 1/6 of each adjacent face, so that a uniform
    pressure times the tiles is the consistent Q2 nodal force and the tiles cover the surface.
    """
    seg = np.hypot(np.diff(xs[:, 0]), np.diff(xs[:, 1]))
    face = seg[0::2] + seg[1::2]
    tiles = np.zeros(xs.shape[0])
    tiles[1::2] = 2.0 / 3.0 * face
    tiles[0:-1:2] += face / 6.0
    tiles[2::2] += face / 6.0
    return tiles


def _log_antiderivative(y: np.ndarray) -> np.ndarray:
    ay = np.abs(y)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where(ay > 0, y * np.log(np.where(ay > 0, ay, 1.0)) - y, 0.0)
    return out


def skin_compliance(
    x: np.ndarray, tiles: np.ndarray, period: float, modulus: float, derivative: bool = False
) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """Influence matrix C (m, m): the skin lift at node i per unit force of node j.

    Parameters
    ----------
    x
        Current x positions of the surface nodes.
    tiles
        Their tile lengths (spreading width of each nodal force).
    period
        Period lambda of the section.
    modulus
        Plane-strain skin modulus E_s*.
    derivative
        Also return dC_ij/dx_i (= -dC_ij/dx_j at fixed tiles), for the Newton tangent.
    """
    d = x[:, None] - x[None, :]
    d = d - period * np.round(d / period)
    half = 0.5 * tiles[None, :]
    lo, hi = d - half, d + half
    mean_log = (_log_antiderivative(hi) - _log_antiderivative(lo)) / tiles[None, :]
    # smooth remainder ln(sin(pi y/L)/(pi y/L)) by two-point Gauss over the tile
    g = half / math.sqrt(3.0)
    smooth = 0.5 * (np.log(np.sinc((d - g) / period)) + np.log(np.sinc((d + g) / period)))
    k = -(2.0 / (math.pi * modulus))
    comp = k * (mean_log + math.log(2.0 * math.pi / period) + smooth)
    if not derivative:
        return comp
    with np.errstate(divide="ignore"):
        dlog = (np.log(np.abs(hi)) - np.log(np.abs(lo))) / tiles[None, :]

    def dsmooth(y: np.ndarray) -> np.ndarray:  # d/dy ln(sin(pi y/L)/(pi y/L))
        t = math.pi * y / period
        small = np.abs(t) < 1e-6
        ts = np.where(small, 1.0, t)
        return np.where(small, -t / 3.0, (ts / np.tan(ts) - 1.0) / np.where(small, 1.0, y))

    return comp, k * (dlog + 0.5 * (dsmooth(d - g) + dsmooth(d + g)))


def contact_length(xs: np.ndarray, indicator: np.ndarray, pressure: np.ndarray | None = None,
                   gap: np.ndarray | None = None) -> tuple[float, float]:
    """Contact length along the surface polyline through the ordered surface nodes.

    Each contact edge lies between an active node (indicator > 0) and its inactive neighbour.
    It is placed by the asymptotics of a smooth contact edge -- the pressure falls like the
    square root of the distance inside, the gap grows like its 3/2 power outside -- i.e. by
    extrapolating ``p^2`` from the two nodes inside and ``g^(2/3)`` from the two nodes outside
    and averaging; where those nodes are missing, by the zero of the linearly interpolated
    indicator. Without ``pressure`` and ``gap`` only the indicator is used.

    Returns
    -------
    (arc, projected)
        Length along the deformed surface and its projection on x.
    """
    seg = np.hypot(np.diff(xs[:, 0]), np.diff(xs[:, 1]))
    s = np.concatenate([[0.0], np.cumsum(seg)])
    act = indicator > 0
    n = act.size
    # contact intervals [start, end] in arc length
    starts, ends = [], []
    for k in range(n - 1):
        if act[k] == act[k + 1]:
            continue
        i_in, i_out = (k, k + 1) if act[k] else (k + 1, k)
        step = i_out - i_in  # +1: edge to the right of the contact
        q_in, q_out = indicator[i_in], indicator[i_out]
        lin = s[i_in] + (s[i_out] - s[i_in]) * q_in / (q_in - q_out)
        est = []
        if pressure is not None and gap is not None:
            j_in, j_out = i_in - step, i_out + step
            if 0 <= j_in < n and act[j_in] and pressure[j_in] > pressure[i_in] > 0:
                p1, p2 = pressure[i_in] ** 2, pressure[j_in] ** 2
                est.append(s[i_in] + (s[i_in] - s[j_in]) * p1 / (p2 - p1))
            if 0 <= j_out < n and not act[j_out] and gap[j_out] > gap[i_out] >= 0:
                g1, g2 = gap[i_out] ** (2.0 / 3.0), gap[j_out] ** (2.0 / 3.0)
                est.append(s[i_out] - (s[j_out] - s[i_out]) * g1 / (g2 - g1))
        edge = float(np.mean(est)) if est else lin
        lo, hi = min(s[i_in], s[i_out]), max(s[i_in], s[i_out])
        edge = min(max(edge, lo), hi)
        (ends if step > 0 else starts).append(edge)
    if act[0]:
        starts.insert(0, s[0])
    if act[-1]:
        ends.append(s[-1])
    arc = float(sum(e - b for b, e in zip(sorted(starts), sorted(ends))))
    # projection: map the arc-length intervals to x through the polyline
    proj = 0.0
    for b, e in zip(sorted(starts), sorted(ends)):
        proj += float(abs(np.interp(e, s, xs[:, 0]) - np.interp(b, s, xs[:, 0])))
    return arc, proj


_J = np.array([[0.0, 1.0], [-1.0, 0.0]])
# variables v = (s_x, s_z, p_x, p_z, q_x, q_z); d = q - p = D v, r = s - p = R v
_D = np.hstack([np.zeros((2, 2)), -np.eye(2), np.eye(2)])
_R = np.hstack([np.eye(2), -np.eye(2), np.zeros((2, 2))])
_HC = _D.T @ _J @ _R + _R.T @ _J.T @ _D  # Hessian of c = d . (J r) (constant)


def normal_gap(s: np.ndarray, p: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Signed distance of points s from the lines through segments p -> q (normal rotated +90 deg
    from q - p, i.e. upward for a segment running toward +x), with gradient (n, 6) and Hessian
    (n, 6, 6) over (s, p, q)."""
    d, r = q - p, s - p
    c = d[:, 0] * r[:, 1] - d[:, 1] * r[:, 0]
    ell = np.hypot(d[:, 0], d[:, 1])
    gc = np.einsum("ni,ij->nj", np.einsum("ni,ij->nj", d, _J), _R) + np.einsum("ni,ij->nj", np.einsum("ni,ji->nj", r, _J), _D)
    gl = np.einsum("ni,ij->nj", d / ell[:, None], _D)
    hl_d = (np.eye(2)[None] - d[:, :, None] * d[:, None, :] / ell[:, None, None] ** 2) / ell[:, None, None]
    hl = np.einsum("ai,nab,bj->nij", _D, hl_d, _D)
    e1, e2, e3 = ell[:, None], ell[:, None, None] ** 2, ell[:, None, None] ** 3
    g = c / ell
    grad = gc / e1 - c[:, None] * gl / e1**2
    outer = gc[:, :, None] * gl[:, None, :]
    hess = (_HC[None] / ell[:, None, None] - (outer + np.swapaxes(outer, 1, 2)) / e2
            - c[:, None, None] * hl / e2 + 2.0 * c[:, None, None] * gl[:, :, None] * gl[:, None, :] / e3)
    return g, grad, hess


class FoldContact:
    """Penalty contact of the asperity's flanks on the free base surface (fold-over).

    Node-to-segment: each flank node is tested against the deformed base segment of the same
    side it projects into (closest-point projection), with the signed normal distance to that
    segment's line. Energy ``k/2 g^2`` for ``g < 0``, frictionless (texture on texture). The normal gap
    matters: where a folding flank closes the corner at its foot, the base next to the foot is
    pulled down and steep, and a vertical gap would misjudge the penetration there.
    """

    def __init__(self, mesh: SectionMesh, stiffness: float, foot_gap: float = 0.0) -> None:
        prof = mesh.surface[mesh.on_asperity]
        # the feet are shared with the base. ``foot_gap`` (units of r, along the profile) leaves
        # out flank nodes that close to a foot (in effect a small fillet at the crease); tried at
        # 0.15 r it made the closing crease converge worse, hence 0 by default
        xp = mesh.nodes[prof]
        s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(xp, axis=0).T))])
        rho = mesh.geometry.fillet
        if rho > 0:
            # a filleted foot is one smooth surface from the base onto the flank: a node of it
            # lies within a segment length of its neighbouring segments' lines, and pairing them
            # would be spurious self-contact of a smooth surface (it fired at zero shear). The
            # fillet arc (its tangent length, about rho, on each leg) is left out of the fold
            # contact on both sides; the folded flank meets the base beyond it.
            foot_gap = max(foot_gap, 1.05 * rho)
        far = (s > foot_gap) & (s < s[-1] - foot_gap)
        self.slaves = prof[far]
        self.sides = []
        for side in (mesh.right_base, mesh.left_base):
            xb = mesh.nodes[side]
            sb = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(xb, axis=0).T))])
            self.sides.append(side[sb >= (1.05 * rho if rho > 0 else 0.0)])
        self.k = float(stiffness)

    def pair(self, x: np.ndarray) -> list[np.ndarray]:
        """Closest-point projection: per side, the base segment each flank node projects into
        with the smallest |distance| (within one segment length of it), or -1."""
        xs = x[self.slaves]
        out = []
        for side, sign in zip(self.sides, (1.0, -1.0)):
            a, b = (side[:-1], side[1:]) if sign > 0 else (side[1:], side[:-1])
            p, q = x[a], x[b]
            d = q - p
            ell2 = np.einsum("ij,ij->i", d, d)
            r = xs[:, None, :] - p[None, :, :]
            t = np.einsum("nsi,si->ns", r, d) / ell2[None, :]
            dist = (d[None, :, 0] * r[..., 1] - d[None, :, 1] * r[..., 0]) / np.sqrt(ell2)[None, :]
            ok = (t >= 0.0) & (t <= 1.0) & (np.abs(dist) < np.sqrt(ell2)[None, :])
            score = np.where(ok, np.abs(dist), np.inf)
            seg = np.argmin(score, axis=1)
            seg[~np.isfinite(score[np.arange(xs.shape[0]), seg])] = -1
            out.append(seg)
        return out

    def update_pairs(self, x: np.ndarray, old: list[np.ndarray], tolerance: float = 0.25) -> list[np.ndarray]:
        """Re-pair after convergence: a slave keeps its segment while its projection stays within
        ``tolerance`` (in segment lengths) of it -- near a kink of the base the line of the old
        segment is as good a surface as the next one, and hopping to it would kick the Newton
        iteration off a converged state -- and takes its fresh closest-point pair otherwise."""
        fresh = self.pair(x)
        xs = x[self.slaves]
        out = []
        for side, sign, seg_old, seg_new in zip(self.sides, (1.0, -1.0), old, fresh):
            a, b = (side[:-1], side[1:]) if sign > 0 else (side[1:], side[:-1])
            keep = seg_old >= 0
            merged = seg_new.copy()
            if np.any(keep):
                sg = seg_old[keep]
                p, q = x[a[sg]], x[b[sg]]
                d = q - p
                t = np.einsum("ij,ij->i", xs[keep] - p, d) / np.einsum("ij,ij->i", d, d)
                stay = (t >= -tolerance) & (t <= 1.0 + tolerance)
                idx = np.nonzero(keep)[0]
                merged[idx[stay]] = sg[stay]
            out.append(merged)
        return out

    def evaluate(self, x: np.ndarray, pairs: list[np.ndarray] | None = None) -> tuple[np.ndarray, list, int, float]:
        """Active gaps and their derivatives for the given slave-segment ``pairs`` (fresh
        closest-point pairs if None). The solver freezes the pairs during a Newton solve -- a
        flank lying node over node on the base would otherwise hop between segments at their
        kinks and the iteration chatter -- and re-pairs at convergence.

        Returns
        -------
        gaps, terms, n_active, min_gap
            ``terms`` is a list of (dof ids (a, 6), gradients (a, 6), gaps (a,), Hessians
            (a, 6, 6)) per side, variables ordered (x_s, z_s, p_x, p_z, q_x, q_z); the force is
            ``k g grad`` and the stiffness ``k (grad grad^T + g hess)`` (the second term is of
            the size of the contact force, not of the penetration: Newton needs it).
        """
        if pairs is None:
            pairs = self.pair(x)
        xs = x[self.slaves]
        terms = []
        gaps_all = []
        min_gap = np.inf
        for side, sign, seg in zip(self.sides, (1.0, -1.0), pairs):
            a, b = (side[:-1], side[1:]) if sign > 0 else (side[1:], side[:-1])
            idx = np.nonzero(seg >= 0)[0]
            if idx.size == 0:
                continue
            sg = seg[idx]
            g, grad, hess = normal_gap(xs[idx], x[a[sg]], x[b[sg]])
            min_gap = min(min_gap, float(g.min()))
            act = g < 0
            if not np.any(act):
                continue
            s_node, n_p, n_q = self.slaves[idx[act]], a[sg[act]], b[sg[act]]
            dofs = np.column_stack([2 * s_node, 2 * s_node + 1, 2 * n_p, 2 * n_p + 1, 2 * n_q, 2 * n_q + 1])
            terms.append((dofs, grad[act], g[act], hess[act]))
            gaps_all.append(g[act])
        n_act = int(sum(t[0].shape[0] for t in terms))
        return np.concatenate(gaps_all) if gaps_all else np.zeros(0), terms, n_act, min_gap
