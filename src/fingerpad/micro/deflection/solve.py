"""Newton solver of one section in full sliding (path following: :mod:`.path`).

Unknowns: the texture's nodal displacements (periodic sides, clamped bottom), the skin contact
force ``f_i`` (per unit depth) at every top-surface node, and the skin's rigid position ``Z0``.
Equations::

    f_int(u) + f_fold(u) - f_ext(f) = 0          (texture equilibrium)
    Z0 + sum_j C_ij f_j - z_i(u) = 0   (i in contact)      f_i = 0   (i free)
    sum_i f_i = P                                (normal load per unit depth, load control)

with the contact set chosen by the primal-dual active-set rule ``f_i - c g_i > 0`` (a semi-smooth
Newton method for the complementarity ``f >= 0, g >= 0, f g = 0``), recomputed at every
iteration together with the geometric non-linearity, until both the residuals and the set are
stationary. Sliding is full (the skin slides over every contact point), so the friction load is
not a state variable: node i receives the tangential force ``t_i`` in the sliding direction:

* ``coulomb``: ``t_i = mu f_i``;
* ``package`` (Eq. 2.3 shape, ``tau = tau0 + alpha p``): ``t_i = mu P (tau0 l_i + alpha f_i) /
  (tau0 L + alpha P)`` with l_i the contact tiles and L the contact length; the tiles are taken
  from the previous converged step (one step lag), the total is exactly ``mu P`` at every step.

The shear level mu (= friction force / normal force of the section) is prescribed, or, with the
tip's horizontal displacement prescribed instead, an unknown (:mod:`.path` follows the shear
path that way, past limit points). Newton steps are cut to keep every element un-inverted and
backtracked on the natural residual of the complementarity problem. The stability of
each converged state is checked by the inertia of the symmetric part of the tangent condensed
onto the displacements (skin contact as its exact compliance, Z0 free): a negative eigenvalue
marks a state past a bifurcation (buckling).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ...errors import FingerpadError
from .contact import FoldContact, contact_length, skin_compliance, tile_jacobian, tile_lengths
from .hyperelastic import Solid, csr_slots, summed
from .mesh import SectionMesh

FRICTION_LAWS = ("package", "coulomb")


@dataclass(frozen=True)
class FrictionLaw:
    """Shape of the sliding friction traction on the contact (dimensionless stresses).

    ``kind="package"``: ``tau = tau0 + alpha p`` (Eq. 2.3) scaled to the shear level;
    ``kind="coulomb"``: ``tau = mu p``.
    """

    kind: str = "package"
    tau0: float = 0.0
    alpha: float = 1.0

    def __post_init__(self) -> None:
        if self.kind not in FRICTION_LAWS:
            raise FingerpadError(f"friction law must be one of {', '.join(FRICTION_LAWS)}, got {self.kind!r}")
        if self.tau0 < 0 or self.alpha < 0 or (self.kind == "package" and self.tau0 + self.alpha <= 0):
            raise FingerpadError("friction law: tau0 and alpha must be non-negative and not both zero")


@dataclass
class State:
    """A converged (or trial) state of the section."""

    v: np.ndarray
    f: np.ndarray
    z0: float
    load: float = 0.0
    shear: float = 0.0
    iterations: int = 0
    contact_mask: np.ndarray | None = None
    tiles: np.ndarray | None = None
    info: dict = field(default_factory=dict)

    def copy(self) -> State:
        return State(self.v.copy(), self.f.copy(), self.z0, self.load, self.shear, self.iterations,
                     None if self.contact_mask is None else self.contact_mask.copy(),
                     None if self.tiles is None else self.tiles.copy(), dict(self.info))


class NoConvergence(RuntimeError):
    """A Newton solve did not converge (the caller cuts the step)."""


#: relative agreement of the natural residuals that marks a Newton limit cycle (see
#: :func:`_limit_cycle`): in issue 23's six ramps (README ellipsoids, 370 solves) the failed
#: solves that cycled repeated to 1.2e-6 or closer, the closest near-repeat in a solve that went
#: on to converge differed by 1.6e-2; 1e-4 lies between them with a factor ~100 either side
CYCLE_RTOL = 1e-4


def _limit_cycle(merits: list[float], max_period: int = 4) -> int:
    """The period (1-``max_period``) with which the last two natural residuals repeat the ones a
    period earlier, each to ``CYCLE_RTOL``; 0 if none does."""
    k = len(merits) - 1
    for p in range(1, max_period + 1):
        if k - p - 1 < 0:
            break
        if all(abs(merits[k - j] - merits[k - j - p]) <= CYCLE_RTOL * merits[k - j] for j in (0, 1)):
            return p
    return 0


#: a Newton solve that has run ``STALL_AFTER`` iterations and whose natural residual did not
#: fall below ``STALL_FACTOR`` x its best before in the last ``STALL_WINDOW`` ones fails
#: (:func:`_stagnates`; chosen on issue 23's six ramps of the README ellipsoids: the failed
#: solves' CPU 36 -> 20 s after the limit-cycle check, 18 of 240 converging solves cut instead)
STALL_WINDOW, STALL_AFTER, STALL_FACTOR = 6, 10, 0.5


def _stagnates(merits: list[float]) -> bool:
    """True when the last ``STALL_WINDOW`` natural residuals of at least ``STALL_AFTER`` all stay
    above ``STALL_FACTOR`` times the smallest one before them."""
    n = len(merits)
    if n < STALL_AFTER or n <= STALL_WINDOW:
        return False
    return min(merits[-STALL_WINDOW:]) > STALL_FACTOR * min(merits[:-STALL_WINDOW])


class SectionSolver:
    """Finite-strain section of a compliant asperity on its base, pressed and sheared by the skin.

    All quantities are dimensionless: lengths in units of the asperity half-width r, stresses in
    units of the texture's Young's modulus E_m (forces per unit depth in E_m r).

    Parameters
    ----------
    mesh
        The section mesh.
    texture_poisson
        Poisson ratio of the texture (capped at 0.499: nu = 0.5 is treated as nearly
        incompressible with kappa = 500 mu).
    skin_modulus
        Plane-strain skin modulus ``E_s* / E_m``.
    friction
        Friction law shape.
    linear
        Small-strain solid (the linear reference).
    fold_penalty
        Penalty stiffness of the flank-on-base contact, in units of E_m.
    """

    def __init__(
        self,
        mesh: SectionMesh,
        texture_poisson: float,
        skin_modulus: float,
        friction: FrictionLaw = FrictionLaw(),
        linear: bool = False,
        fold_penalty: float = 200.0,
        rtol: float = 1e-8,
    ) -> None:
        nu = min(float(texture_poisson), 0.499)
        self.mesh = mesh
        self.solid = Solid(mesh, 1.0 / (2.0 * (1.0 + nu)), 1.0 / (3.0 * (1.0 - 2.0 * nu)), linear=linear)
        self.skin = float(skin_modulus)
        self.friction = friction
        self.fold = FoldContact(mesh, fold_penalty)
        self.rtol = float(rtol)
        self.period = mesh.geometry.period
        nd = self.solid.ndof
        # dof map: periodic right side -> left side, bottom clamped
        owner = np.arange(mesh.n_nodes)
        owner[mesh.periodic[:, 1]] = mesh.periodic[:, 0]
        fixed = np.zeros(mesh.n_nodes, dtype=bool)
        fixed[mesh.bottom] = True
        fixed = fixed | fixed[owner]
        free_nodes = np.unique(owner[~fixed])
        node_index = -np.ones(mesh.n_nodes, dtype=np.int64)
        node_index[free_nodes] = np.arange(free_nodes.size)
        red = -np.ones(nd, dtype=np.int64)
        ni = node_index[owner]
        for c in range(2):
            red[c::2] = np.where(ni >= 0, 2 * ni + c, -1)
        self.red = red
        self.nred = 2 * free_nodes.size
        keep = red >= 0
        self.M = sp.csr_matrix((np.ones(int(keep.sum())), (np.nonzero(keep)[0], red[keep])), shape=(nd, self.nred))
        # its transpose once (the same matrix ``M.T`` gives; building that view cost 0.5 ms a call)
        self.MT = self.M.T
        # M and M^T on vectors as a gather and a bincount (see :meth:`displacement`, :meth:`reduce`)
        self._kept = np.nonzero(keep)[0]
        self._kept_red = red[keep]
        self.surface = mesh.surface
        self.m = mesh.surface.size
        self.base_centre = int(np.argmin(np.hypot(mesh.nodes[:, 0], mesh.nodes[:, 1])))
        self.zred = red[2 * self.surface + 1]
        self.xred = red[2 * self.surface]
        self._kr_map = None  # reduced stiffness pattern (see _reduced_stiffness)

    # ------------------------------------------------------------------ helpers
    def displacement(self, v: np.ndarray) -> np.ndarray:
        """``M @ v``, the same floats: SciPy's product adds ``1.0 * v_j`` to a zero per row, i.e.
        ``0.0 + v_j`` (which turns -0.0 into +0.0), done here as a gather without the sparse
        product's Python (~20 us a call, several calls per Newton iteration)."""
        u = np.zeros(self.solid.ndof)
        u[self._kept] = v[self._kept_red]
        u += 0.0
        return u

    def reduce(self, r: np.ndarray) -> np.ndarray:
        """``M^T @ r``, the same floats: SciPy's product adds each dof's ``1.0 * r_i`` to its
        reduced dof in increasing dof order, starting from zero, as the bincount does."""
        return np.bincount(self._kept_red, weights=r[self._kept], minlength=self.nred)

    def positions(self, v: np.ndarray) -> np.ndarray:
        return self.mesh.nodes + self.displacement(v).reshape(-1, 2)

    def initial_state(self) -> State:
        return State(np.zeros(self.nred), np.zeros(self.m), float(self.mesh.nodes[self.mesh.apex, 1]))

    def _friction_coefficients(self, load: float, shear: float, lag: State | None) -> tuple[float, np.ndarray]:
        """(c_f, t0): tangential nodal force ``t_i = c_f f_i + t0_i``."""
        law = self.friction
        if law.kind == "coulomb" or shear == 0.0:
            return shear, np.zeros(self.m)
        if lag is not None and lag.contact_mask is not None and np.any(lag.contact_mask):
            tiles = np.where(lag.contact_mask, lag.tiles, 0.0)
        else:  # no contact yet: tiles of the nodes carrying load
            tiles = np.zeros(self.m)
        length = float(tiles.sum())
        denom = law.tau0 * length + law.alpha * load
        if denom <= 0:
            return shear, np.zeros(self.m)
        return shear * load * law.alpha / denom, shear * load * law.tau0 * tiles / denom

    # ------------------------------------------------------------------ Newton
    def solve(self, load: float, shear: float, guess: State, lag: State | None = None, max_iter: int = 25,
              tip: float | None = None) -> State:
        """Converge the state at normal load ``load`` and shear level ``shear`` from ``guess``.

        With ``tip`` the horizontal displacement of the asperity tip is prescribed instead and
        the shear level is an unknown (``shear`` is its first guess): this control passes limit
        points of the shear level, where load control would snap.

        Raises
        ------
        NoConvergence
            When the residuals or the contact set do not settle, or elements invert.
        """
        a0, b0 = self._friction_coefficients(load, 1.0, lag)  # t_i = mu (a0 f_i + b0_i)
        mu = float(shear)
        tip_dof = int(self.red[2 * self.mesh.apex])
        v, f, z0 = guess.v.copy(), guess.f.copy(), float(guess.z0)
        surf, m, nred = self.surface, self.m, self.nred
        scale_f = max(load, 1e-12)
        prev_active = None
        if self.solid.min_jacobian(self.displacement(v)) <= 0:  # e.g. an extrapolated guess
            raise NoConvergence("inverted elements in the first guess")
        pairs = self.fold.pair(self.positions(v))
        repairs = 0
        history: list[float] = []  # relative equilibrium residuals with an unchanged active set
        merits: list[float] = []  # the natural residual at every iteration (limit-cycle check)
        for it in range(1, max_iter + 1):
            x = self.positions(v)
            if it > 1:
                # re-pair at every iteration (keeping a pair while its projection stays near its
                # segment): a flank point unpaired at the start would otherwise slide under a
                # short base segment unresisted and be found deep in the base at convergence
                pairs = self.fold.update_pairs(x, pairs)
            xs = x[surf]
            tiles = self._tiles(xs)
            comp, dcomp, dtile = skin_compliance(xs[:, 0], tiles, self.period, self.skin, derivative=True,
                                                 tile_derivative=True)
            gap = z0 + comp @ f - xs[:, 1]
            active = f - self.skin * gap > 0
            active[-1] = False  # the periodic image of the first surface node carries no force
            if not np.any(active):
                active[np.argmax(xs[:, 1] + 0.0 * gap)] = True
            u = self.displacement(v)
            fint, kmat = self.solid.assemble(u)
            fold_f, fold_k, _ = self._fold(x, pairs)
            fext = np.zeros(self.solid.ndof)
            cf, t0 = mu * a0, mu * b0
            fext[2 * surf] = cf * f + t0
            fext[2 * surf + 1] = -f
            r_u = self.reduce(fint + fold_f - fext)
            r_c = np.where(active, gap, f)
            r_z = f.sum() - load
            r_t = (v[tip_dof] - tip) if tip is not None else 0.0
            res_u = float(np.linalg.norm(r_u))
            res_g = float(np.max(np.abs(gap[active])))
            merit = self._merit(r_u, f, gap, r_z, r_t)
            same = prev_active is not None and np.array_equal(active, prev_active)
            history = history + [res_u / scale_f] if same else []
            # The round-off floor: a texture far stiffer than the skin (E_m >~ 100 E_s) strains by
            # ~1e-6, and F = I + grad u keeps only ~10 digits of the strain, so the equilibrium
            # residual stalls near 1e-6 of the load, above rtol (the 1 GPa ellipsoids never got
            # pressed on). Accept a residual that has stalled -- no halving over three iterations
            # with the same active set -- once it is below 1e-5 of the load: a state exact to
            # that is exact for every reported digit. Converging solves never get here.
            stalled = (len(history) >= 4 and history[-1] <= 1e-5 and history[-1] > 0.5 * history[-4])
            if (same and (res_u <= self.rtol * scale_f or stalled)
                    and res_g <= self.rtol and abs(r_z) <= self.rtol * scale_f and abs(r_t) <= self.rtol):
                fresh = self.fold.update_pairs(x, pairs)
                if repairs < 4 and any(np.any((fn != fo) & ((fn >= 0) | (fo >= 0))) for fn, fo in zip(fresh, pairs)):
                    # converged on stale slave-segment pairs: re-pair and iterate on
                    _, _, n_old, _ = self.fold.evaluate(x, pairs, tangent=False)
                    _, _, n_new, _ = self.fold.evaluate(x, fresh, tangent=False)
                    if n_old or n_new:
                        pairs, repairs, prev_active = fresh, repairs + 1, None
                        continue
                state = State(v, f, z0, load, mu, it - 1)
                state.info["pairs"] = pairs
                self._finish(state, xs, tiles, comp, gap, mu * a0, mu * b0)
                return state
            prev_active = active
            merits.append(merit)
            if res_u > 1e-5 * scale_f and _stagnates(merits):
                # No real progress for STALL_WINDOW iterations this late: in issue 23's ramps such
                # solves wandered at residuals of 1e-4 to 1e-1 until max_iter (a crease closing,
                # the contact edge hopping), and a cut step is cheaper than waiting. The few
                # solves that would have converged after such a stretch (18 of 240 there) are
                # cut too: the ramp then takes smaller steps through the same equilibria.
                raise NoConvergence(f"no convergence: the Newton iteration stagnates (no halving of the "
                                    f"residual in {STALL_WINDOW} iterations)")
            period = _limit_cycle(merits) if res_u > 1e-5 * scale_f else 0
            if period:
                # Newton caught in a limit cycle: the same residuals come back every `period`
                # iterations (typically a Gauss point of the fold contact and its neighbour
                # taking turns at a closed crease). Such a solve never converged in the
                # remaining iterations of any ramp measured (issue 23: 42 of 130 failed solves of
                # the README's ellipsoids, none of 240 converged ones), so it fails now instead of
                # at max_iter. Below 1e-5 of the load the round-off-floor acceptance above decides.
                raise NoConvergence(f"no convergence: the Newton iteration cycles (period {period})")
            # Jacobian, block rows (u, contact, load[, tip]) x columns (v, f, Z0[, mu]), as one COO
            kr = self._reduced_stiffness(kmat, fold_k)
            # its entries in storage order, as ``tocoo`` lists them (rows expanded from indptr)
            kr_rows = np.repeat(np.arange(nred, dtype=kr.indices.dtype), np.diff(kr.indptr))
            ai = np.nonzero(active)[0]
            xr, okx = self.xred, self.xred >= 0
            # d r_u / d f: the friction (c_f on x) and the skin pressure (-1 on z)
            e_rows = np.concatenate([self.xred, self.zred])
            e_vals = -np.concatenate([np.full(m, cf), -np.ones(m)])
            e_cols = np.concatenate([np.arange(m), np.arange(m)])
            ok = e_rows >= 0
            # d gap_i / d u: -1 on z_i, and the skin lift's dependence on the x positions
            dlift = dcomp * f[None, :]
            dlift = (np.diag(dlift.sum(axis=1)) - dlift)[ai]
            # ... and through the tiles, which move with every surface node (x and z). Without it
            # the tangent was not exact: Newton converged linearly and, where a flank pressed on
            # its neighbour, cycled (issue 31)
            tj = self._tile_jacobian(xs)  # (m, m, 2)
            dtl = np.einsum("ij,jnc->inc", (dtile * f[None, :])[ai], tj)  # (active, m, 2)
            tl_rows = np.repeat(nred + ai, 2 * m)
            tl_cols = np.tile(np.stack([self.xred, self.zred], axis=1).ravel(), ai.size)
            tl_vals = dtl.reshape(ai.size, 2 * m).ravel()
            tl_ok = (tl_cols >= 0) & (tl_vals != 0.0)
            # d gap_i / d f (active rows: the compliance) and d f_i / d f_i = 1 (free rows)
            free = np.nonzero(~active)[0]
            ca = comp[ai]
            nz = ca != 0.0
            parts_r = [kr_rows, e_rows[ok], tl_rows[tl_ok],
                       nred + ai, np.repeat(nred + ai, int(okx.sum())),
                       nred + np.repeat(ai, m)[nz.ravel()], nred + free,
                       nred + ai,  # d gap_i / d Z0
                       np.full(m, nred + m)]  # the load equation: sum f
            parts_c = [kr.indices, nred + e_cols[ok], tl_cols[tl_ok],
                       self.zred[ai], np.tile(xr[okx], ai.size),
                       nred + np.tile(np.arange(m), ai.size)[nz.ravel()], nred + free,
                       np.full(ai.size, nred + m),
                       nred + np.arange(m)]
            parts_v = [kr.data, e_vals[ok], tl_vals[tl_ok],
                       -np.ones(ai.size), dlift[:, okx].ravel(),
                       ca[nz], np.ones(free.size),
                       np.ones(ai.size),
                       np.ones(m)]
            rhs = [r_u, r_c, [r_z]]
            size = nred + m + 1
            if tip is not None:  # unknown mu: its column d(-f_ext)/d mu and the tip equation
                dmu = np.zeros(self.solid.ndof)
                dmu[2 * surf] = a0 * f + b0
                col = -self.reduce(dmu)
                nzc = np.nonzero(col)[0]
                parts_r += [nzc, [size]]
                parts_c += [np.full(nzc.size, size), [tip_dof]]
                parts_v += [col[nzc], [1.0]]
                rhs.append([r_t])
                size += 1
            jac = summed(np.concatenate(parts_v), np.concatenate(parts_r), np.concatenate(parts_c), (size, size))
            rhs = -np.concatenate(rhs)
            try:  # SuperLU, threshold partial pivoting (the diagonal unless 10x below the column maximum)
                dy = spla.splu(jac, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.1).solve(rhs)
            except RuntimeError:  # singular factor
                raise NoConvergence("singular Jacobian") from None
            if not np.all(np.isfinite(dy)):
                raise NoConvergence("singular Jacobian")
            dv, df, dz0 = dy[:nred], dy[nred:nred + m], float(dy[nred + m])
            dmu_ = float(dy[-1]) if tip is not None else 0.0
            step = 1.0
            for _ in range(8):  # keep every element un-inverted
                if self.solid.min_jacobian(self.displacement(v + step * dv)) > 0.02:
                    break
                step *= 0.5
            else:
                raise NoConvergence("elements invert")
            # backtracking on the natural residual of the complementarity problem (a merit that
            # the semi-smooth Newton step decreases near a solution): without it the iteration
            # can run away where a flank closes a crease onto the base
            best = None
            for _ in range(4):
                trial = (v + step * dv, f + step * df, z0 + step * dz0, mu + step * dmu_)
                m_trial = self._trial_merit(*trial, load, a0, b0, pairs, tip, tip_dof)
                if best is None or m_trial < best[0]:
                    best = (m_trial, trial)
                if m_trial <= (1.0 - 1e-4 * step) * merit:
                    break
                step *= 0.5
            v, f, z0, mu = best[1]
        raise NoConvergence(f"no convergence in {max_iter} iterations")

    def _reduced_stiffness(self, kmat: sp.csr_matrix, fold_k: sp.csr_matrix | None) -> sp.csr_matrix:
        """``M^T (K + K_fold) M`` on the reduced displacements. M only selects and merges dofs
        (periodic sides, clamped bottom), so the solid's part is a bincount of K's values into the
        reduced pattern, computed once (K's pattern is fixed)."""
        if self._kr_map is None:
            indptr_k, indices_k = self.solid.pattern
            rows = np.repeat(np.arange(self.solid.ndof), np.diff(indptr_k))
            rr, cc = self.red[rows], self.red[indices_k]
            valid = (rr >= 0) & (cc >= 0)
            self._kr_map = (valid, *csr_slots(rr[valid], cc[valid], self.nred))
        valid, slot, indices, indptr = self._kr_map
        nnz = indices.size
        if kmat.nnz != valid.size:  # not the solid's fixed pattern (should not happen): the general product
            kr = self.MT @ (kmat @ self.M)
        else:
            kr = sp.csr_matrix((np.bincount(slot, weights=kmat.data[valid], minlength=nnz), indices, indptr),
                               shape=(self.nred, self.nred))
            kr.has_sorted_indices = True
        if fold_k is not None and fold_k.nnz:
            kr = kr + self.MT @ (fold_k @ self.M)
        return kr

    def _merit(self, r_u: np.ndarray, f: np.ndarray, gap: np.ndarray, r_z: float, r_t: float) -> float:
        """Norm of the natural residual: equilibrium, ``min(f, c g)`` per contact candidate (force
        units), the load and the tip equations."""
        phi = np.minimum(f, self.skin * gap)[:-1]
        return float(math.sqrt(r_u @ r_u + phi @ phi + r_z * r_z + (self.skin * r_t) ** 2))

    def _trial_merit(self, v: np.ndarray, f: np.ndarray, z0: float, mu: float, load: float, a0: float,
                     b0: np.ndarray, pairs: list[np.ndarray], tip: float | None, tip_dof: int) -> float:
        x = self.positions(v)
        xs = x[self.surface]
        comp = skin_compliance(xs[:, 0], self._tiles(xs), self.period, self.skin)
        gap = z0 + comp @ f - xs[:, 1]
        if self.solid.min_jacobian(self.displacement(v)) <= 0:
            return math.inf  # an inverted element: no state
        fint, _ = self.solid.assemble(self.displacement(v), tangent=False)
        fold_f, _, _ = self._fold(x, pairs, tangent=False)
        fext = np.zeros(self.solid.ndof)
        fext[2 * self.surface] = mu * (a0 * f + b0)
        fext[2 * self.surface + 1] = -f
        r_u = self.reduce(fint + fold_f - fext)
        r_t = (v[tip_dof] - tip) if tip is not None else 0.0
        out = self._merit(r_u, f, gap, f.sum() - load, r_t)
        return out if math.isfinite(out) else math.inf

    def _tile_jacobian(self, xs: np.ndarray) -> np.ndarray:
        """d tiles / d xs of :meth:`_tiles` (m, m, 2): the last node's half tile goes to the first."""
        tj = tile_jacobian(xs)
        tj[0] += tj[-1]
        return tj

    def _tiles(self, xs: np.ndarray) -> np.ndarray:
        """Tiles of the surface nodes; the last node is the periodic image of the first, which
        takes both half tiles (the last one is never a contact candidate)."""
        tiles = tile_lengths(xs)
        tiles[0] += tiles[-1]
        return tiles

    def _fold(self, x: np.ndarray, pairs: list[np.ndarray] | None = None,
              tangent: bool = True) -> tuple[np.ndarray, sp.csr_matrix | None, int]:
        _, terms, n_act, _ = self.fold.evaluate(x, pairs, tangent)
        nd = self.solid.ndof
        force = np.zeros(nd)
        if not terms:
            return force, sp.csr_matrix((nd, nd)) if tangent else None, 0
        rows, cols, vals = [], [], []
        k = self.fold.k
        for dofs, grad, g, hess, w in terms:
            kw = k * w
            nd_t = dofs.shape[1]
            np.add.at(force, dofs.ravel(), (kw[:, None] * g[:, None] * grad).ravel())
            if not tangent:
                continue
            rows.append(np.repeat(dofs, nd_t, axis=1).ravel())
            cols.append(np.tile(dofs, (1, nd_t)).ravel())
            vals.append((kw[:, None, None] * (grad[:, :, None] * grad[:, None, :] + g[:, None, None] * hess)).ravel())
        if not tangent:
            return force, None, n_act
        kf = summed(np.concatenate(vals), np.concatenate(rows), np.concatenate(cols), (nd, nd), "csr")
        return force, kf, n_act

    def _finish(self, state: State, xs: np.ndarray, tiles: np.ndarray, comp: np.ndarray, gap: np.ndarray,
                cf: float, t0: np.ndarray) -> None:
        indicator = (state.f - self.skin * gap) / tiles
        indicator[-1] = indicator[0]  # the same point (periodic image)
        mask = indicator > 0
        pressure = np.where(mask, state.f / tiles, 0.0)
        pressure[-1] = pressure[0]
        gap = gap.copy()
        gap[-1] = gap[0]
        arc, proj = contact_length(xs, indicator, pressure, np.where(mask, 0.0, gap))
        x = self.positions(state.v)
        gaps, _, n_fold, min_fold = self.fold.evaluate(x, tangent=False)
        apex = self.mesh.apex
        u = self.displacement(state.v).reshape(-1, 2)
        # skin surface slope (validity of the half-space): lift differences over the contact
        lift = comp @ state.f
        order = np.argsort(xs[:, 0])
        dxs = np.diff(xs[order, 0])
        slope = np.abs(np.diff(lift[order])) / np.maximum(dxs, 1e-9)
        state.contact_mask = mask
        state.tiles = tiles
        state.info = {**state.info,
            "contact_length": arc,
            "contact_length_projected": proj,
            "tip_dx": float(u[apex, 0]),
            "tip_dz": float(u[apex, 1]),
            # bending deflection: the tip relative to the middle of the asperity's base, i.e.
            # without the uniform shear of the base layer
            "deflection_dx": float(u[apex, 0] - u[self.base_centre, 0]),
            "deflection_dz": float(u[apex, 1] - u[self.base_centre, 1]),
            "fold_nodes": n_fold,
            "fold_gap": float(min_fold) if math.isfinite(min_fold) else float("nan"),
            "friction_force": float(np.sum(cf * state.f + t0)),
            "skin_slope": float(np.max(slope[dxs > 1e-6])) if np.any(dxs > 1e-6) else 0.0,
            "contact_nodes": int(mask.sum()),
        }

    # ------------------------------------------------------------------ stability
    def condensed_tangent(self, state: State) -> sp.csr_matrix:
        """Symmetric part of the tangent on the reduced displacements at a converged state, with
        the skin contact condensed in through its exact compliance (Z0 free, load controlled):
        ``K + D^T (C^-1 - C^-1 1 (1^T C^-1 1)^-1 1^T C^-1) D`` over the contact nodes."""
        u = self.displacement(state.v)
        _, kmat = self.solid.assemble(u)
        x = self.positions(state.v)
        _, fold_k, _ = self._fold(x, state.info.get("pairs"))
        kr = self._reduced_stiffness(kmat, fold_k)
        kr = 0.5 * (kr + kr.T)
        act = np.nonzero(state.contact_mask & (state.f > 0))[0]
        if act.size:
            xs = x[self.surface]
            tiles = self._tiles(xs)
            ca = skin_compliance(xs[act, 0], tiles[act], self.period, self.skin)
            ca = 0.5 * (ca + ca.T)
            ci = np.linalg.inv(ca)
            one = np.ones(act.size)
            w = ci @ one
            stiff = ci - np.outer(w, w) / float(one @ w)
            zr = self.zred[act]
            ok = zr >= 0
            zr, stiff = zr[ok], stiff[np.ix_(ok, ok)]
            rr, cc = np.meshgrid(zr, zr, indexing="ij")
            kr = kr + sp.csr_matrix((stiff.ravel(), (rr.ravel(), cc.ravel())), shape=kr.shape)
        return kr

    def min_eigenvalue(self, state: State) -> float:
        """Stability of a converged state: minus the number of negative eigenvalues of the
        symmetric part of the tangent condensed on the displacements (skin contact replaced by
        its exact compliance with Z0 free), or +1 when there is none (stable).

        By Sylvester's law of inertia the count equals the number of negative pivots of a
        symmetric LDL^T factorisation, which one sparse LU without off-diagonal pivoting gives
        (far cheaper than an eigenvalue near a nearly singular shift). NaN if the factorisation
        pivoted off the diagonal (no count).
        """
        kr = self.condensed_tangent(state)
        try:
            lu = spla.splu(kr.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                           options={"SymmetricMode": True})
        except RuntimeError:  # exactly singular: on a bifurcation
            return 0.0
        if not np.array_equal(lu.perm_r, lu.perm_c):
            return float("nan")
        negative = int(np.count_nonzero(lu.U.diagonal() < 0))
        return 1.0 if negative == 0 else -float(negative)
