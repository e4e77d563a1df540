"""Rounded feet: a concave circular fillet where an asperity's flank meets its base.

Why: an ellipsoid's flank meets its base at a right angle, a sharp re-entrant corner. Under a
large shear the flank folds over about that corner, the corner closes into a crease and the
node-to-segment fold contact acts between the first flank nodes and the first base segments --
adjacent, short and rotating with the crease -- where the Newton iteration stopped converging.
Moulded asperities do not have sharp feet (the mould's cavity edge is rounded), so the mesh
rounds each foot with a fillet of radius ``rho`` (units of the half-width r), tangent to the base
and to the flank, so that the fold rolls over a smooth surface and the flank meets the base
away from the foot. Measured on the slender ellipsoid section (docs/deflection.md, "Limits and
doubts"), it did *not* help: at 26.8 kPa the ramp stalled earlier (mu -0.03 at rho = 0.15 r
against 0.2-0.27 with the sharp foot), so it is opt-in (``SectionGeometry.fillet``, default 0).

How: the mesh is built for the sharp profile (with elements graded toward the feet, see
:func:`.mesh.build_mesh`), then *morphed*: the surface nodes within the tangent length of a foot
are moved onto the fillet arc (keeping their order and their share of the arc by distance from
the foot), and the interior nodes near the foot follow by a discrete harmonic (graph Laplacian)
extension of that displacement, with every node farther than a few radii fixed. The added
material is the fillet's own area, ``(1 - pi/4) rho^2`` per foot for a right-angled corner.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

#: Size of the elements at a filleted foot, as a fraction of the fillet radius (the arc then
#: spans about four element edges, eight Q2 node intervals, on each side of the foot).
FILLET_ELEMENT = 1.0

#: Interior nodes farther than this many fillet radii from a foot do not move.
_REACH = 4.0


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def fillet_feet(coords: np.ndarray, elements: np.ndarray, profile: np.ndarray, left_base: np.ndarray,
                right_base: np.ndarray, fixed: np.ndarray, rho: float) -> np.ndarray:
    """Round both feet of a sharp-footed section mesh with fillets of radius ``rho``.

    Parameters
    ----------
    coords
        (n, 2) node coordinates, units of r.
    elements
        (e, 9) Q2 connectivity.
    profile
        Profile node ids from the left foot over the tip to the right foot.
    left_base, right_base
        Base surface node ids of each side, ordered away from its foot (foot first).
    fixed
        Node ids that must not move (bottom and periodic sides).
    rho
        Fillet radius, units of r.

    Returns
    -------
    numpy.ndarray
        The morphed coordinates (a new array).
    """
    x = coords.copy()
    target: dict[int, np.ndarray] = {}
    for flank_ids, base_ids in ((profile, left_base), (profile[::-1], right_base)):
        foot = coords[flank_ids[0]]
        # corner directions: along the base away from the asperity, and up the flank (the
        # flank's chord over the tangent length: the profile is nearly straight at that scale)
        e_b = _unit(coords[base_ids[1]] - foot)
        s_f = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(coords[flank_ids], axis=0), axis=1))])
        s_b = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(coords[base_ids], axis=0), axis=1))])
        # tangent length d = rho / tan(gamma/2), gamma the corner's opening angle on the air side
        probe = np.array([np.interp(rho, s_f, coords[flank_ids, 0]), np.interp(rho, s_f, coords[flank_ids, 1])])
        e_f = _unit(probe - foot)
        gamma = math.acos(float(np.clip(e_b @ e_f, -1.0, 1.0)))
        d = rho / math.tan(0.5 * gamma)
        centre = foot + (rho / math.sin(0.5 * gamma)) * _unit(e_b + e_f)
        a0 = foot + d * e_b - centre  # radius vectors to the two tangent points
        a1 = foot + d * e_f - centre
        sweep = math.atan2(a0[0] * a1[1] - a0[1] * a1[0], a0 @ a1)

        def on_arc(sigma: np.ndarray) -> np.ndarray:
            # sigma 0 at the base's tangent point, 1 at the flank's: rotate a0 by sigma * sweep
            c, s = np.cos(sigma * sweep), np.sin(sigma * sweep)
            return centre + np.column_stack([c * a0[0] - s * a0[1], s * a0[0] + c * a0[1]])

        # nodes within the tangent length share the arc by their distance from the foot (the
        # sharp corner's two legs, 2 d long, are laid onto the arc proportionally)
        nb = base_ids[(s_b < d) & (s_b > 0)]
        nf = flank_ids[(s_f < d) & (s_f > 0)]
        sig_b = 0.5 - 0.5 * s_b[(s_b < d) & (s_b > 0)] / d
        sig_f = 0.5 + 0.5 * s_f[(s_f < d) & (s_f > 0)] / d
        for ids, sig in ((nb, sig_b), (nf, sig_f), (flank_ids[:1], np.array([0.5]))):
            for i, p in zip(ids, on_arc(sig)):
                target[int(i)] = p
    moved = np.array(sorted(target))
    disp = np.zeros_like(x)
    disp[moved] = np.array([target[i] for i in moved]) - coords[moved]
    # harmonic extension into the nodes near the feet: graph Laplacian of the element cliques
    n = x.shape[0]
    feet = coords[[profile[0], profile[-1]]]
    near = np.min(np.linalg.norm(coords[:, None, :] - feet[None], axis=2), axis=1) < _REACH * rho
    free = near.copy()
    free[moved] = False
    free[fixed] = False
    rows = np.repeat(elements, 9, axis=1).ravel()
    cols = np.tile(elements, (1, 9)).ravel()
    adj = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(n, n))
    adj.setdiag(0.0)
    adj.eliminate_zeros()
    adj.data[:] = 1.0
    lap = sp.diags(np.asarray(adj.sum(axis=1)).ravel()) - adj
    fi = np.nonzero(free)[0]
    if fi.size:
        rhs = -(lap[fi][:, ~free] @ disp[~free])
        disp[fi] = spla.spsolve(lap[fi][:, fi].tocsc(), rhs).reshape(-1, 2)
    return x + disp
