"""What one shear ramp of a section gives, in SI units: :class:`PressureRamp`, and its
assembly from a finished ramp of the solver (:func:`to_ramp`).

Split from :mod:`.gain` so that :mod:`.ramps` (which runs the ramps, in worker processes) and
:mod:`.gain` (which tabulates their gains) both import it, neither importing the other back.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from .solve import SectionSolver

__all__ = ["PressureRamp", "to_ramp"]


@dataclass
class PressureRamp:
    """The shear ramp of one section at one nominal pressure (SI units, per unit depth).

    Attributes
    ----------
    pressure
        Nominal pressure p of the cell, Pa; ``load`` = P, the section load, N/m.
    mu, contact_length, gain, tip_dx, tip_dz, fold_nodes, min_eigenvalue
        Along the followed path (path order; mu may fall past a limit point). Lengths in m;
        ``min_eigenvalue`` is the stability index: +1 stable, -k with k unstable modes (the
        negative eigenvalues of the condensed symmetric tangent), NaN unknown.
    tangential_stiffness
        d(mu P)/d(tip_dx) along the path, N/m per m (Pa).
    bend_dx, bend_dz
        Tip displacement relative to the centre of the asperity's base (its bending
        deflection, without the uniform shear of the base layer), m.
    fold_onset_mu
        First shear level at which a flank touches the base (NaN: never).
    limit_mu
        Shear level of the first maximum of mu along the path (a snap-over under load control;
        NaN: none).
    buckled
        The state at zero shear is already unstable (buckling under the normal load alone).
    stopped
        Why the ramp ended before ``mu_max`` (None: it reached it).
    incomplete
        The ramp was cut by the wall-clock safety stop (``DeflectionSettings.time_limit``): where
        it ended depends on the machine's speed, so it is not a result (never cached).
    surfaces
        Deformed top surface (x, z) in m at every state, for figures.
    """

    pressure: float
    load: float
    mu: np.ndarray
    contact_length: np.ndarray
    gain: np.ndarray
    tip_dx: np.ndarray
    tip_dz: np.ndarray
    tangential_stiffness: np.ndarray
    fold_nodes: np.ndarray
    min_eigenvalue: np.ndarray
    skin_slope: np.ndarray
    fold_onset_mu: float
    limit_mu: float
    buckled: bool
    stopped: str | None
    surfaces: list[np.ndarray] = field(default_factory=list)
    contact: list[np.ndarray] = field(default_factory=list)
    bend_dx: np.ndarray = field(default_factory=lambda: np.zeros(0))
    bend_dz: np.ndarray = field(default_factory=lambda: np.zeros(0))
    incomplete: bool = False

    def _along(self) -> np.ndarray:
        """Shear level along the sliding direction of the ramp. Signed, not |mu|: past a buckled
        start the path's shear level first falls below zero (the folding column pushes the tip
        on) before it carries shear again."""
        return _sliding_sign(self.mu, self.tip_dx) * self.mu

    @property
    def mu_reached(self) -> float:
        return float(max(0.0, np.max(self._along()))) if self.mu.size else 0.0

    def branch(self) -> tuple[np.ndarray, np.ndarray]:
        """(mu, gain) on the branch a load-controlled ramp follows: the states whose shear level
        exceeds every earlier one (past a limit point the asperity snaps to the next state
        that carries more shear)."""
        mu = self._along()
        keep = (mu >= np.maximum.accumulate(mu) - 1e-12) & (mu >= 0)
        m, gn = mu[keep], self.gain[keep]
        m, idx = np.unique(m, return_index=True)
        return m, gn[idx]

    def as_dict(self, surfaces: bool = False) -> dict[str, Any]:
        out = {k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in asdict(self).items()
               if k not in ("surfaces", "contact")}
        if surfaces:
            out["surfaces"] = [s.tolist() for s in self.surfaces]
            out["contact"] = [c.tolist() for c in self.contact]
        return out

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> PressureRamp:
        arrays = ("mu", "contact_length", "gain", "tip_dx", "tip_dz", "tangential_stiffness", "fold_nodes",
                  "min_eigenvalue", "skin_slope", "bend_dx", "bend_dz")
        kw = {k: (np.asarray(v, dtype=float) if k in arrays else v) for k, v in data.items()
              if k not in ("surfaces", "contact")}
        kw["incomplete"] = bool(kw.get("incomplete", False))
        kw["surfaces"] = [np.asarray(s) for s in data.get("surfaces", [])]
        kw["contact"] = [np.asarray(c, dtype=bool) for c in data.get("contact", [])]
        return cls(**kw)


def _sliding_sign(mu: np.ndarray, tip_dx: np.ndarray) -> float:
    """+1 for a ramp sliding toward +x, -1 toward -x: the side the tip was moved to (the path
    prescribes the tip toward the sliding direction), else the sign of the shear levels. By the
    shear alone, a ramp from a buckled start that stopped before its shear came back above
    zero read as a ramp toward -x that had reached |mu| (0.25 at 20 kPa for h/a = 3)."""
    if tip_dx.size and np.all(np.isfinite(tip_dx)) and tip_dx[-1] != 0.0:
        return 1.0 if tip_dx[-1] > 0 else -1.0
    return -1.0 if mu.size and np.all(mu <= 0) else 1.0


def to_ramp(solver: SectionSolver, ramp: Any, pressure: float, load: float, r: float, em: float) -> PressureRamp:
    st = ramp.states
    info = lambda key: np.array([s.info.get(key, math.nan) for s in st], dtype=float)  # noqa: E731
    mu = np.array([s.shear for s in st])
    length = info("contact_length") * r
    gain = length / length[0]
    tip = info("tip_dx") * r
    q = mu * load
    with np.errstate(divide="ignore", invalid="ignore"):
        kt = np.gradient(q, tip) if len(st) > 2 else np.full(len(st), math.nan)
    fold = info("fold_nodes")
    onset = float(np.abs(mu)[np.argmax(fold > 0)]) if np.any(fold > 0) else math.nan
    amu = _sliding_sign(mu, tip) * mu  # along the sliding direction, signed (see PressureRamp)
    drops = np.nonzero(np.diff(amu) < -1e-9)[0]
    limit = float(amu[drops[0]]) if drops.size else math.nan
    eig = info("min_eigenvalue")
    surf, contact = [], []
    for s in st:
        x = solver.positions(s.v)[solver.surface] * r
        surf.append(x)
        contact.append(np.asarray(s.contact_mask, dtype=bool))
    return PressureRamp(
        pressure=float(pressure), load=float(load), mu=mu, contact_length=length, gain=gain,
        tip_dx=tip, tip_dz=info("tip_dz") * r, tangential_stiffness=kt, fold_nodes=fold, min_eigenvalue=eig,
        skin_slope=info("skin_slope"), fold_onset_mu=onset, limit_mu=limit,
        buckled=bool(np.isfinite(eig[0]) and eig[0] < 0), stopped=ramp.stopped, surfaces=surf, contact=contact,
        bend_dx=info("deflection_dx") * r, bend_dz=info("deflection_dz") * r,
    )
