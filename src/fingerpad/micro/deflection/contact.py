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

import functools
import math

import numpy as np

from .mesh import SectionMesh


def tile_jacobian(xs: np.ndarray) -> np.ndarray:
    """d tile_i / d xs_n (m, m, 2) of :func:`tile_lengths`: each tile is a weighted sum of
    segment lengths, and a segment's length moves with its ends along its direction."""
    m = xs.shape[0]
    diff = np.diff(xs, axis=0)
    seg = np.hypot(diff[:, 0], diff[:, 1])
    e = diff / np.maximum(seg, 1e-300)[:, None]
    w = _tile_weights(m)
    out = np.zeros((m, m, 2))
    out[:, 1:, :] += w[:, :, None] * e[None, :, :]
    out[:, :-1, :] -= w[:, :, None] * e[None, :, :]
    return out


@functools.lru_cache(maxsize=8)
def _tile_weights(m: int) -> np.ndarray:
    """d tile_i / d seg_k (m, m - 1) of :func:`tile_lengths`: constants of the node count, built
    once per count (read-only) instead of by a Python loop at every Newton iteration."""
    w = np.zeros((m, m - 1))
    for k in range(m - 1):
        f = k // 2  # the face of segment k: nodes 2f, 2f + 1, 2f + 2
        w[2 * f + 1, k] += 2.0 / 3.0
        w[2 * f, k] += 1.0 / 6.0
        w[2 * f + 2, k] += 1.0 / 6.0
    w.flags.writeable = False
    return w


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
    x: np.ndarray, tiles: np.ndarray, period: float, modulus: float, derivative: bool = False,
    tile_derivative: bool = False,
) -> np.ndarray | tuple[np.ndarray, np.ndarray] | tuple[np.ndarray, np.ndarray, np.ndarray]:
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
    tile_derivative
        With ``derivative``, also return dC_ij/dt_j, the change with node j's tile (its spreading
        width), which moves with the surface nodes' positions (:func:`tile_jacobian`).
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

    dx = k * (dlog + 0.5 * (dsmooth(d - g) + dsmooth(d + g)))
    if not tile_derivative:
        return comp, dx
    # d mean_log / dt = (ln|hi| + ln|lo|) / (2 t) - mean_log / t (the antiderivative's ends move by
    # +-1/2 each); the Gauss points of the smooth part sit at d -+ t / (2 sqrt 3)
    with np.errstate(divide="ignore", invalid="ignore"):
        ends = 0.5 * (np.log(np.abs(hi)) + np.log(np.abs(lo)))
    ends = np.where(np.isfinite(ends), ends, 0.0)
    dt = k * ((ends - mean_log) / tiles[None, :] + 0.5 * (dsmooth(d + g) - dsmooth(d - g)) / (2.0 * math.sqrt(3.0)))
    return comp, dx, dt


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


def normal_gap(s: np.ndarray, p: np.ndarray, q: np.ndarray,
               hessian: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Signed distance of points s from the lines through segments p -> q (normal rotated +90 deg
    from q - p, i.e. upward for a segment running toward +x), with gradient (n, 6) and Hessian
    (n, 6, 6) over (s, p, q); ``hessian=False``: None for the Hessian (the distance and gradient
    are the same numbers, bit for bit)."""
    d, r = q - p, s - p
    c = d[:, 0] * r[:, 1] - d[:, 1] * r[:, 0]
    ell = np.hypot(d[:, 0], d[:, 1])
    gc = np.einsum("ni,ij->nj", np.einsum("ni,ij->nj", d, _J), _R) + np.einsum("ni,ij->nj", np.einsum("ni,ji->nj", r, _J), _D)
    gl = np.einsum("ni,ij->nj", d / ell[:, None], _D)
    e1 = ell[:, None]
    g = c / ell
    grad = gc / e1 - c[:, None] * gl / e1**2
    if not hessian:
        return g, grad, None
    hl_d = (np.eye(2)[None] - d[:, :, None] * d[:, None, :] / ell[:, None, None] ** 2) / ell[:, None, None]
    hl = np.einsum("ai,nab,bj->nij", _D, hl_d, _D)
    e2, e3 = ell[:, None, None] ** 2, ell[:, None, None] ** 3
    outer = gc[:, :, None] * gl[:, None, :]
    hess = (_HC[None] / ell[:, None, None] - (outer + np.swapaxes(outer, 1, 2)) / e2
            - c[:, None, None] * hl / e2 + 2.0 * c[:, None, None] * gl[:, :, None] * gl[:, None, :] / e3)
    return g, grad, hess


def segment_gap(s: np.ndarray, p: np.ndarray, q: np.ndarray,
                hessian: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Signed distance of points s from the closed segments p -> q, with gradient (n, 6) and
    Hessian (n, 6, 6) over (s, p, q): the distance from the segment's line (:func:`normal_gap`)
    where the point projects inside the segment, from the nearer end point past an end, signed
    by the side of the line. The distance and its gradient are continuous across the ends (at an
    end the vector from the end point is the line's normal), so a point moving from a segment's
    side to its end, or paired with the next segment where both are as near, sees no jump.
    ``hessian=False``: None for the Hessian (the rest unchanged, bit for bit)."""
    g, grad, hess = normal_gap(s, p, q, hessian)
    d = q - p
    t = np.einsum("ni,ni->n", s - p, d) / np.einsum("ni,ni->n", d, d)
    for cols, sel in ((slice(2, 4), t < 0.0), (slice(4, 6), t > 1.0)):
        if not np.any(sel):
            continue
        r = s[sel] - (p if cols.start == 2 else q)[sel]
        dist = np.maximum(np.hypot(r[:, 0], r[:, 1]), 1e-300)
        sign = np.where(g[sel] < 0, -1.0, 1.0)
        u = r / dist[:, None]
        gr = np.zeros((u.shape[0], 6))
        gr[:, 0:2], gr[:, cols] = sign[:, None] * u, -sign[:, None] * u
        g[sel], grad[sel] = sign * dist, gr
        if hess is None:
            continue
        h = (np.eye(2)[None] - u[:, :, None] * u[:, None, :]) / dist[:, None, None] * sign[:, None, None]
        he = np.zeros((u.shape[0], 6, 6))
        he[:, 0:2, 0:2], he[:, cols, cols], he[:, 0:2, cols], he[:, cols, 0:2] = h, h, -h, -h
        hess[sel] = he
    return g, grad, hess


class FoldContact:
    """Penalty contact of the asperity's flanks on the free base surface (fold-over).

    Flank points on base segments: the contact points are the 3 Gauss points of every Q2 face of
    the flank (interpolated by the face's shape functions, weighted by their share of the face's
    reference length -- the slave side of a segment-to-segment contact), each tested against the
    deformed base segment (chord between consecutive surface nodes) it projects into
    (the nearest closed segment), with the signed distance to that segment (:func:`segment_gap`). Energy
    ``k/2 w g^2`` for ``g < 0``, frictionless (texture on texture); the weights are scaled so that
    the penalty per unit length is that of one node per half face (``k`` per node spacing). The
    normal gap matters: where a folding flank closes the corner at its foot, the base next to the
    foot is pulled down and steep, and a vertical gap would misjudge the penetration there.

    Why Gauss points, not nodes: node-to-segment with one penalty per Q2 node loads a face's
    corner nodes as much as its mid-side node; on a folded-flat flank the corners lifted off
    while the mid-side nodes chattered in and out of contact (a spurious surface mode), and the
    Newton iteration stalled near the foot. Measured on the slender section's 26.8 kPa ramp:
    nodes, pairs frozen per solve: mu 0.20; Gauss points: 0.40; nodes re-paired at every
    iteration: 0.18; Gauss points re-paired at every iteration: 1.5 (its target).

    The base of each side runs on over the other side's periodic image, so a flank folded past
    the period edge lies on the neighbouring cell's base (``chains``).

    Why the nearest *closed* segment (``MODEL_VERSION`` 8, issue 31): up to 7 a point kept its
    segment while its projection stayed within a quarter segment past the segment's ends and was
    measured from the segment's *line* there; where the base bends (pulled down next to a foot)
    the line's distance and the next segment's differ, so the gap jumped when the point changed
    segment, and the Newton iteration cycled between the two (the README ellipsoids' along
    section at 26.8 kPa, tip-controlled, could not pass mu = 0.0625 at any step size). The
    distance to the closed segment is continuous, and so is the nearest of them.
    """

    def __init__(self, mesh: SectionMesh, stiffness: float, foot_gap: float = 0.0, points: str = "gauss") -> None:
        prof = mesh.surface[mesh.on_asperity]
        # the feet are shared with the base. ``foot_gap`` (units of r, along the profile) leaves
        # out flank points that close to a foot (in effect a small fillet at the crease); tried at
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
        # ``points``: "gauss" (default) or "nodes", the node-to-segment contact of MODEL_VERSION <= 4
        # (kept for comparison; it stalls in the closing crease, see the class docstring)
        if points == "nodes":
            # node-to-segment: every flank node with unit weight
            far = (s > foot_gap) & (s < s[-1] - foot_gap)
            self.point_nodes = prof[far][:, None]
            self.point_shape = np.ones((int(far.sum()), 1))
            self.weights = np.ones(int(far.sum()))
        elif points == "gauss":
            # contact points at the 3 Gauss points of every Q2 face of the flank, interpolated
            # by the face's shape functions, weighted by their share of the reference face
            # length (the slave side of a segment-to-segment contact). Scaled so that a face
            # carries the penalty of its two nodes under node-to-segment, i.e. the same
            # penalty per unit length
            g = np.array([0.5 - 0.5 * math.sqrt(0.6), 0.5, 0.5 + 0.5 * math.sqrt(0.6)])
            gw = np.array([5.0, 8.0, 5.0]) / 18.0
            shape = np.column_stack([(1 - g) * (1 - 2 * g), 4 * g * (1 - g), g * (2 * g - 1)])
            dshape = np.column_stack([4 * g - 3, 4 - 8 * g, 4 * g - 1])
            faces = np.column_stack([prof[0:-1:2], prof[1::2], prof[2::2]])
            xf = mesh.nodes[faces]  # (faces, 3, 2)
            jac = np.hypot(*np.einsum("ga,fad->fgd", dshape, xf).transpose(2, 0, 1))  # (faces, 3)
            sf = s[0:-1:2]
            # arc position of each point (approximately: Gauss abscissae of the face's arc)
            sp_ = sf[:, None] + g[None, :] * (s[2::2] - sf)[:, None]
            far = ((sp_ > foot_gap) & (sp_ < s[-1] - foot_gap)).ravel()
            ell = s[-1] / (prof.size - 1)  # reference node spacing along the flank
            self.point_nodes = np.repeat(faces, 3, axis=0)[far]
            self.point_shape = np.tile(shape, (faces.shape[0], 1))[far]
            self.weights = (gw[None, :] * jac / ell).ravel()[far]
        else:
            raise ValueError(f"points must be 'gauss' or 'nodes', got {points!r}")
        bases = []
        for side in (mesh.right_base, mesh.left_base):
            xb = mesh.nodes[side]
            sb = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(xb, axis=0).T))])
            bases.append(side[sb >= (1.05 * rho if rho > 0 else 0.0)])
        right, left = bases
        lam = mesh.geometry.period
        # master chains running toward +x. A flank folded far enough crosses the period edge and
        # lies on the base of the neighbouring cell: the right chain runs from the right foot to
        # the edge and on over the left base's periodic image (+lambda) to the neighbour's foot,
        # the left chain over the right base's image (-lambda) and the left base to the left
        # foot. Each entry: (node ids, x offsets); the edge node and its image are one point.
        # Past the neighbour's foot each chain runs on up the neighbour's flank (the asperity's
        # other flank, one period over) to its apex: where the base between two asperities is
        # narrow (the README ellipsoids' along section: 30 um of base, less than one element)
        # a flank pressed over its foot meets the neighbour's flank, and a point that slid past
        # the chain's end found no surface there (MODEL_VERSION 8, issue 31). Not with a fillet,
        # whose arc is left out of the chains.
        # (the flank's lower half: where two flanks meet in a valley; not its top, which a flank
        # pressed over its foot does not reach)
        apex = int(np.nonzero(prof == mesh.apex)[0][0])
        half = apex // 2 if rho <= 0 else 0
        up_left = prof[1:1 + half]  # from past the left foot up the lower half of the flank
        down_right = prof[prof.size - 1 - half:-1]  # down the right flank's lower half to before its foot
        self.chains = [
            (np.concatenate([right, left[::-1][1:], up_left]),
             np.concatenate([np.zeros(right.size), np.full(left.size - 1 + up_left.size, lam)])),
            (np.concatenate([down_right, right[:-1], left[::-1]]),
             np.concatenate([np.full(down_right.size + right.size - 1, -lam), np.zeros(left.size)])),
        ]
        # per contact point, the map T of its face's node positions and a segment's two end
        # points onto (s, p, q) that :meth:`evaluate` applies (the same entries, built once)
        na = self.point_nodes.shape[1]
        t = np.zeros((self.point_nodes.shape[0], 6, 2 * (na + 2)))
        eye = np.eye(2)
        for j in range(na):
            t[:, 0:2, 2 * j:2 * j + 2] = self.point_shape[:, j][:, None, None] * eye
        t[:, 2:4, 2 * na:2 * na + 2] = eye
        t[:, 4:6, 2 * na + 2:2 * na + 4] = eye
        t.flags.writeable = False
        self._chain_rule = t
        # the chains' offsets as (x, 0) rows once, not stacked again per call (the same sums)
        self._shifts = [np.column_stack([shift, np.zeros(shift.size)]) for _, shift in self.chains]
        self.k = float(stiffness)

    @property
    def slaves(self) -> np.ndarray:
        """Flank nodes taking part in the fold contact."""
        return np.unique(self.point_nodes)

    def points(self, x: np.ndarray) -> np.ndarray:
        """Current positions of the flank's contact points (n, 2)."""
        return np.einsum("pa,pad->pd", self.point_shape, x[self.point_nodes])

    def _segments(self, x: np.ndarray, chain: int, seg: np.ndarray | None = None
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Node ids (a, b) and current end points (p, q) of a chain's segments (all, or ``seg``)."""
        nodes, _ = self.chains[chain]
        shift = self._shifts[chain]  # (x offset, 0) per chain node
        ia = np.arange(nodes.size - 1) if seg is None else seg
        a, b = nodes[ia], nodes[ia + 1]
        p = x[a] + shift[ia]
        q = x[b] + shift[ia + 1]
        return a, b, p, q

    def pair(self, x: np.ndarray) -> list[np.ndarray]:
        """Per chain, the base segment nearest each flank point as a closed segment (within one
        segment length of it), or -1 (re-paired at every Newton iteration)."""
        xs = self.points(x)
        out = []
        for chain in range(len(self.chains)):
            _, _, p, q = self._segments(x, chain)
            d = q - p
            ell2 = np.einsum("ij,ij->i", d, d)
            r = xs[:, None, :] - p[None, :, :]
            t = np.clip(np.einsum("nsi,si->ns", r, d) / ell2[None, :], 0.0, 1.0)
            off = r - t[..., None] * d[None, :, :]
            dist = np.hypot(off[..., 0], off[..., 1])
            score = np.where(dist < np.sqrt(ell2)[None, :], dist, np.inf)
            seg = np.argmin(score, axis=1)
            seg[~np.isfinite(score[np.arange(xs.shape[0]), seg])] = -1
            out.append(seg)
        return out

    def update_pairs(self, x: np.ndarray, old: list[np.ndarray]) -> list[np.ndarray]:
        """The pairs at ``x`` (:meth:`pair`; ``old`` is not needed: the nearest closed segment
        changes continuously, so no hysteresis is kept against chatter)."""
        return self.pair(x)

    def evaluate(self, x: np.ndarray, pairs: list[np.ndarray] | None = None,
                 tangent: bool = True) -> tuple[np.ndarray, list, int, float]:
        """Active gaps and their derivatives for the given point-segment ``pairs`` (fresh
        closest-point pairs if None).

        Returns
        -------
        gaps, terms, n_active, min_gap
            ``terms`` is a list of (dof ids (a, n), gradients (a, n), gaps (a,), Hessians
            (a, n, n), weights (a,)) per chain, over the positions of the point's face nodes and
            the segment's two nodes (n = 10 for Gauss points); the force is ``k w g grad`` and
            the stiffness ``k w (grad grad^T + g hess)`` (the second term is of the size of the
            contact force, not of the penetration: Newton needs it). ``n_active``: contact points
            in contact. ``tangent=False``: None for the Hessians (a line search's merit and a
            converged state's report need the gaps and forces only; the rest is the same, bit
            for bit, without the Hessians' work).
        """
        if pairs is None:
            pairs = self.pair(x)
        xs = self.points(x)
        terms = []
        gaps_all = []
        min_gap = np.inf
        for chain, seg in enumerate(pairs):
            idx = np.nonzero(seg >= 0)[0]
            if idx.size == 0:
                continue
            a, b, p, q = self._segments(x, chain, seg[idx])
            g, grad, hess = segment_gap(xs[idx], p, q, tangent)
            min_gap = min(min_gap, float(g.min()))
            act = g < 0
            if not np.any(act):
                continue
            pts = idx[act]
            nodes = np.column_stack([self.point_nodes[pts], a[act], b[act]])  # (a, na + 2)
            dofs = np.stack([2 * nodes, 2 * nodes + 1], axis=2).reshape(nodes.shape[0], -1)
            # chain rule through the point's interpolation s = sum_a N_a x_a: T maps the
            # (na + 2) node positions onto (s, p, q)
            t = self._chain_rule[pts]
            gr = np.einsum("ni,nij->nj", grad[act], t)
            he = None if hess is None else np.einsum("nki,nkl,nlj->nij", t, hess[act], t)
            terms.append((dofs, gr, g[act], he, self.weights[pts]))
            gaps_all.append(g[act])
        n_act = int(sum(t[0].shape[0] for t in terms))  # contact points in contact
        return np.concatenate(gaps_all) if gaps_all else np.zeros(0), terms, n_act, min_gap
