"""Structured Q2 meshes of one asperity section on its base layer (plane strain).

The section is one period of a 2-D texture: a base layer ``-t_b <= z <= 0`` of width ``lambda``
(the period along the section, x in ``[-lambda/2, lambda/2]``) carrying one asperity whose
profile ``z = f(x)`` spans ``|x| <= r`` (half-width r, height h).

Why this mesh: the asperity of an ellipsoid meets its base with a *vertical* flank, and the
asperity folds about that foot under shear. A transfinite (Coons) patch with its two lower
corners at the feet gives right-angled, well-shaped elements exactly there, and nodes placed
evenly along the profile by arc length follow both flanks and the tip. The base is a tensor grid
that shares the patch's chord nodes and grows geometrically away from the feet and downward.
Nine-node quadrilaterals (Q2) follow the curved profile and, with selective reduced
integration of the volumetric energy (see :mod:`.hyperelastic`), do not lock for nearly
incompressible materials.

All lengths here are *dimensionless*, in units of the half-width r (the solver scales back).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import FingerpadError
from .fillet import FILLET_ELEMENT, fillet_feet

#: Profiles the mesher supports: a semi-ellipse (section of an ellipsoid) and a circular-arc
#: segment (circular ridge). Both meet the base at a finite angle, which the patch needs.
PROFILES = ("ellipse", "circular")


@dataclass(frozen=True)
class SectionGeometry:
    """Dimensionless geometry of one section (lengths in units of the half-width r).

    Attributes
    ----------
    profile
        ``"ellipse"`` (``z = h sqrt(1 - x^2)``) or ``"circular"`` (arc segment of chord 2 and
        height h <= 1).
    height
        Asperity height h / r.
    period
        Section period lambda / r (>= 2).
    base_thickness
        Base layer thickness t_b / r.
    fillet
        Radius of the concave fillet rounding each foot (the corner between the flank and the
        base), units of r; 0: a sharp corner. Moulded asperities have rounded feet; the fillet
        also keeps a folding flank from closing a sharp crease at its foot (see :mod:`.fillet`).
    """

    profile: str
    height: float
    period: float
    base_thickness: float
    fillet: float = 0.0

    def __post_init__(self) -> None:
        if self.profile not in PROFILES:
            raise FingerpadError(f"deflection model: profile must be one of {', '.join(PROFILES)}, got {self.profile!r}")
        if not (self.height > 0 and math.isfinite(self.height)):
            raise FingerpadError("deflection model: the asperity height must be positive")
        if self.profile == "circular" and self.height > 1.0 + 1e-9:
            raise FingerpadError("deflection model: a circular-arc ridge cannot be higher than half its width")
        if not self.period >= 2.0 - 1e-9:
            raise FingerpadError("deflection model: the asperity is wider than its period (neighbours overlap)")
        if not self.base_thickness > 0:
            raise FingerpadError("deflection model: the base thickness must be positive")
        if not (0.0 <= self.fillet <= 0.3 and math.isfinite(self.fillet)):
            raise FingerpadError("deflection model: the foot fillet radius must lie in [0, 0.3] half-widths")
        if self.fillet > 0 and self.period - 2.0 < 2.0 * self.fillet:
            raise FingerpadError("deflection model: no room for the foot fillets between neighbouring asperities")

    def dense_profile(self, n: int = 8001) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Points (x, z) along the profile from the left foot to the right foot and their
        cumulative arc length s."""
        h = self.height
        if self.profile == "ellipse":
            # parameter phi from pi to 0, clustered toward the feet where the flank is steep
            t = np.linspace(0.0, 1.0, n)
            phi = math.pi * (1.0 - t)
            x, z = np.cos(phi), h * np.sin(phi)
        else:
            rc = (1.0 + h * h) / (2.0 * h)
            psi0 = math.asin(min(1.0, 1.0 / rc))
            psi = np.linspace(-psi0, psi0, n)
            x, z = rc * np.sin(psi), h - rc + rc * np.cos(psi)
            z = np.maximum(z, 0.0)
        s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(x), np.diff(z)))])
        return x, z, s


@dataclass(frozen=True)
class SectionMesh:
    """A Q2 mesh of one section and the sets the solver needs.

    Attributes
    ----------
    nodes
        (n, 2) reference coordinates (x, z), units of r.
    elements
        (e, 9) node ids; local node ``3 b + a`` sits at reference ``(xi, eta) = (a - 1, b - 1)``.
    surface
        Node ids of the top surface in order from ``x = -lambda/2`` to ``+lambda/2`` (corner,
        mid-side, corner, ...: an odd count, faces are consecutive triples).
    on_asperity
        Boolean mask over ``surface``: nodes of the asperity profile (feet included).
    left_base, right_base
        Node ids of the free base surface on each side, ordered away from the foot (foot first).
    periodic
        (k, 2) pairs (left, right) of nodes tied by periodicity.
    bottom
        Node ids of the clamped bottom.
    apex
        Node id of the asperity tip (x = 0 on the profile).
    """

    nodes: np.ndarray
    elements: np.ndarray
    surface: np.ndarray
    on_asperity: np.ndarray
    left_base: np.ndarray
    right_base: np.ndarray
    periodic: np.ndarray
    bottom: np.ndarray
    apex: int
    geometry: SectionGeometry

    @property
    def n_nodes(self) -> int:
        return int(self.nodes.shape[0])


def _graded(length: float, first: float, growth: float) -> np.ndarray:
    """Element sizes growing geometrically from ``first`` whose sum is exactly ``length``."""
    if length <= 1e-12:
        return np.zeros(0)
    sizes: list[float] = []
    total, size = 0.0, first
    while total + 0.5 * size < length:
        sizes.append(size)
        total += size
        size *= growth
    if not sizes:
        sizes = [length]
    arr = np.asarray(sizes)
    return arr * (length / arr.sum())


def _capped(length: float, first: float, growth: float, cap: float) -> np.ndarray:
    """Element sizes growing geometrically from ``first`` up to ``cap`` (then uniform), scaled
    so that their sum is exactly ``length``."""
    sizes: list[float] = []
    total, size = 0.0, min(first, cap)
    while total + 0.5 * size < length:
        sizes.append(size)
        total += size
        size = min(size * growth, cap)
    if not sizes:
        sizes = [length]
    arr = np.asarray(sizes)
    return arr * (length / arr.sum())


def _with_midpoints(edges: np.ndarray) -> np.ndarray:
    """Element edge coordinates -> Q2 node coordinates (edges and midpoints)."""
    out = np.empty(2 * edges.size - 1)
    out[0::2] = edges
    out[1::2] = 0.5 * (edges[:-1] + edges[1:])
    return out


def build_mesh(geometry: SectionGeometry, resolution: int = 8, growth: float = 1.3) -> SectionMesh:
    """Mesh one section with Q2 elements.

    Parameters
    ----------
    geometry
        The dimensionless section.
    resolution
        Elements per half-width along the profile (the element size is about ``r/resolution``).
    growth
        Geometric growth of the base elements away from the feet and downward.

    Returns
    -------
    SectionMesh
    """
    if resolution < 2:
        raise FingerpadError("deflection model: resolution must be at least 2 elements per half-width")
    g = geometry
    delta = 1.0 / resolution
    px, pz, ps = g.dense_profile()
    total = float(ps[-1])
    # split the profile into left side / top / right side at x = -+cos(pi/4) (the 45 deg points
    # of a semicircle): the feet become right-angled patch corners.
    xc = math.cos(math.pi / 4.0)
    s_side = float(np.interp(-xc, px, ps))
    s_top = total - 2.0 * s_side
    if g.fillet > 0:
        # a fillet needs elements smaller than itself at the feet: graded toward the feet along
        # the chord (and with it the profile's top) and up the flanks, capped at the uniform size
        first = min(delta, FILLET_ELEMENT * g.fillet)
        chord_el0 = 2.0 / max(2, int(math.ceil(s_top / delta)))
        half = _capped(1.0, first, growth, chord_el0)
        u_edges = np.concatenate([[0.0], np.cumsum(np.concatenate([half, half[::-1]]))]) / 2.0
        v_edges = np.concatenate([[0.0], np.cumsum(_capped(s_side, first, growth, delta))]) / s_side
    else:
        u_edges = np.linspace(0.0, 1.0, max(2, int(math.ceil(s_top / delta))) + 1)
        v_edges = np.linspace(0.0, 1.0, max(1, int(math.ceil(s_side / delta))) + 1)
    u_edges[-1], v_edges[-1] = 1.0, 1.0
    n_xi, n_eta = u_edges.size - 1, v_edges.size - 1

    def on_profile(s: np.ndarray) -> np.ndarray:
        return np.column_stack([np.interp(s, ps, px), np.interp(s, ps, pz)])

    u = _with_midpoints(u_edges)  # Q2 node parameters (edges and midpoints)
    v = _with_midpoints(v_edges)
    bottom = np.column_stack([-1.0 + 2.0 * u, np.zeros_like(u)])
    top = on_profile(s_side + u * s_top)
    left = on_profile(v * s_side)
    right = on_profile(total - v * s_side)
    # transfinite interpolation X(u, v)
    U, V = np.meshgrid(u, v, indexing="ij")
    U3, V3 = U[..., None], V[..., None]
    patch = (
        (1 - V3) * bottom[:, None, :] + V3 * top[:, None, :]
        + (1 - U3) * left[None, :, :] + U3 * right[None, :, :]
        - ((1 - U3) * (1 - V3) * bottom[0] + U3 * (1 - V3) * bottom[-1]
           + (1 - U3) * V3 * top[0] + U3 * V3 * top[-1])
    )

    # base columns: outside widths graded from the chord element width, mirrored left/right
    chord_el = 2.0 * float(u_edges[1])  # the chord's element next to the foot
    outside = _graded(0.5 * g.period - 1.0, chord_el, growth)
    right_edges = 1.0 + np.concatenate([[0.0], np.cumsum(outside)])
    chord_edges = -1.0 + 2.0 * u_edges
    x_edges = np.concatenate([-right_edges[::-1], chord_edges[1:-1], right_edges])
    z_sizes = _graded(g.base_thickness, min(chord_el, delta), growth)[::-1]  # fine at the top
    z_edges = np.concatenate([[-g.base_thickness], -g.base_thickness + np.cumsum(z_sizes)])
    z_edges[-1] = 0.0
    xs, zs = _with_midpoints(x_edges), _with_midpoints(z_edges)
    nbx, nbz = xs.size, zs.size
    base_id = np.arange(nbx * nbz).reshape(nbx, nbz)
    bx, bz = np.meshgrid(xs, zs, indexing="ij")
    nodes = [np.column_stack([bx.ravel(), bz.ravel()])]

    # asperity nodes: row v = 0 is the base's top row on the chord
    i0 = 2 * outside.size  # node column of the left foot
    asp_id = np.empty((2 * n_xi + 1, 2 * n_eta + 1), dtype=np.int64)
    asp_id[:, 0] = base_id[i0:i0 + 2 * n_xi + 1, -1]
    n_new = (2 * n_xi + 1) * (2 * n_eta)
    asp_id[:, 1:] = nbx * nbz + np.arange(n_new).reshape(2 * n_xi + 1, 2 * n_eta)
    nodes.append(patch[:, 1:, :].reshape(-1, 2))
    coords = np.vstack(nodes)
    # the chord row of the patch equals the base row there (both exactly -1 + 2u); check anyway
    if not np.allclose(coords[asp_id[:, 0]], patch[:, 0, :], atol=1e-12):
        raise RuntimeError("mesh: the asperity chord does not match the base nodes")

    a, b = np.meshgrid(np.arange(3), np.arange(3), indexing="xy")
    la, lb = a.ravel(), b.ravel()  # local node k = 3 b + a
    elems = []
    for ids, nx, nz in ((base_id, (nbx - 1) // 2, (nbz - 1) // 2), (asp_id, n_xi, n_eta)):
        ex, ez = np.meshgrid(np.arange(nx), np.arange(nz), indexing="ij")
        ex, ez = ex.ravel(), ez.ravel()
        elems.append(ids[2 * ex[:, None] + la[None, :], 2 * ez[:, None] + lb[None, :]])
    elements = np.vstack(elems)

    top_row = base_id[:, -1]
    left_surface = top_row[: i0 + 1]  # up to and including the left foot
    right_surface = top_row[i0 + 2 * n_xi:]  # from the right foot
    profile_nodes = np.concatenate([asp_id[0, :], asp_id[1:, -1], asp_id[-1, -2::-1]])
    surface = np.concatenate([left_surface[:-1], profile_nodes, right_surface[1:]])
    on_asp = np.zeros(surface.size, dtype=bool)
    on_asp[left_surface.size - 1: left_surface.size - 1 + profile_nodes.size] = True
    periodic = np.column_stack([base_id[0, :], base_id[-1, :]])
    if g.fillet > 0:
        coords = fillet_feet(coords, elements, profile_nodes, left_surface[::-1], right_surface,
                             np.concatenate([base_id[:, 0], base_id[0, :], base_id[-1, :]]), g.fillet)
    return SectionMesh(
        nodes=coords,
        elements=elements,
        surface=surface,
        on_asperity=on_asp,
        left_base=left_surface[::-1].copy(),
        right_base=right_surface.copy(),
        periodic=periodic,
        bottom=base_id[:, 0].copy(),
        apex=int(asp_id[n_xi, -1]),
        geometry=g,
    )
