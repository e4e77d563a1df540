"""Micro-scale models of the normalised friction mu_tex/mu_ref against load and skin modulus (BEM, Hertz)."""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FingerpadError
from ..units import parse_quantity
from .columns import ColumnSpec, column_key
from .importers.text import read_text_rows

#: A micro-scale model of the normalised friction: ``model(loads, skin_modulus) -> mu_tex/mu_ref``.
Model = Callable[[np.ndarray, float], np.ndarray]



@dataclass(frozen=True)
class TextureGeometry:
    """A spherical-cap bump texture (square lattice) and its material, SI units.

    ``material_modulus=None`` means a rigid counter-surface. ``micro_model`` picks the unit-cell
    model: ``"bem"`` (default, :func:`bem_texture_model`: the half-space solver through the
    asperity, transition and full-contact states) or ``"hertz"`` (:func:`hertz_texture_model`,
    docs/model.md 3.1-3.6, asperity tops only). ``full_contact_ratio`` (Hertz only) adds the empirical
    :class:`BaseContactCell` growth past the transition.
    """

    radius: float
    height: float
    spacing: float
    material_modulus: float | None = None
    material_poisson: float = 0.35
    full_contact_ratio: float | None = None
    micro_model: str = "bem"

    def __post_init__(self) -> None:
        if self.micro_model not in ("bem", "hertz"):
            raise FingerpadError(f"micro model must be 'bem' or 'hertz', got {self.micro_model!r}")
        if self.full_contact_ratio is not None and self.micro_model != "hertz":
            raise FingerpadError("full_contact_ratio applies to the 'hertz' micro model only")
        for name in ("radius", "height", "spacing"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise FingerpadError(f"texture {name} must be a positive length, got {value!r}")
        if self.material_modulus is not None and not self.material_modulus > 0:
            raise FingerpadError(f"material modulus must be positive, got {self.material_modulus!r}")
        if self.full_contact_ratio is not None and not self.full_contact_ratio > 1:
            raise FingerpadError(f"full_contact_ratio must exceed 1, got {self.full_contact_ratio!r}")


#: The columns of a sample table (docs/measurements.md).
SAMPLE_COLUMNS = ("sample", "radius", "height", "spacing", "material_modulus", "material_poisson", "micro_model",
                  "full_contact_ratio")


def read_textures(path: str | os.PathLike[str]) -> dict[str, TextureGeometry | None]:
    """Read a sample table (CSV): ``sample, radius, height, spacing`` and optional
    ``material_modulus``, ``material_poisson``, ``micro_model`` (bem/hertz), ``full_contact_ratio``.

    Values may carry units (``50um``, ``0.5GPa``). A sample with empty geometry is flat.

    Raises
    ------
    FingerpadError
        Naming the file and row for a missing column or a bad value.
    """
    p = Path(path)
    header, rows = read_text_rows(p, ColumnSpec())
    keys = [column_key(h) for h in header]
    if "sample" not in keys:
        raise FingerpadError(f"{p}: sample table lacks a 'sample' column (columns: {', '.join(header)})")
    # a column this table does not have is a mistake (a manifest named instead, a misspelt
    # 'radius'), not something to ignore: its samples would be read as flat
    unknown = [h for h, k in zip(header, keys, strict=True) if k not in SAMPLE_COLUMNS]
    if unknown:
        raise FingerpadError(f"{p}: unknown column(s) {', '.join(map(repr, unknown))} in a sample table (columns: "
                             f"{', '.join(SAMPLE_COLUMNS)}; docs/measurements.md)")
    out: dict[str, TextureGeometry | None] = {}
    for line, cells in rows:
        rec = {k: (cells[i].strip() if i < len(cells) else "") for i, k in enumerate(keys)}
        name = rec["sample"]
        if not name:
            raise FingerpadError(f"{p}, row {line}: empty sample name")
        if name in out:
            raise FingerpadError(f"{p}, row {line}: sample {name!r} is given twice")
        geom = [rec.get(k, "") for k in ("radius", "height", "spacing")]
        if not any(geom):
            out[name] = None
            continue
        try:
            if not all(geom):
                raise FingerpadError("radius, height and spacing must all be given (or none, for a flat sample)")
            em = rec.get("material_modulus", "")
            out[name] = TextureGeometry(
                radius=parse_quantity(geom[0], "length", name="radius"),
                height=parse_quantity(geom[1], "length", name="height"),
                spacing=parse_quantity(geom[2], "length", name="spacing"),
                material_modulus=parse_quantity(em, "pressure", name="material_modulus") if em else None,
                material_poisson=float(rec.get("material_poisson") or 0.35),
                full_contact_ratio=float(rec["full_contact_ratio"]) if rec.get("full_contact_ratio") else None,
                micro_model=rec.get("micro_model") or ("hertz" if rec.get("full_contact_ratio") else "bem"),
            )
        except (FingerpadError, ValueError) as exc:
            raise FingerpadError(f"{p}, row {line}: {exc}") from None
    return out


def resolve_finger(finger: Any) -> Any:
    from ..finger import Finger, get_finger

    if finger is None:
        return get_finger("default")
    if isinstance(finger, Finger):
        return finger
    return get_finger(str(finger))


@dataclass(frozen=True)
class BaseContactCell:
    """A Hertzian bump cell extended past the transition by contact spreading over the base.

    :class:`fingerpad.micro.hertz.HertzUnitCell` follows the asperity tops only (Hertz cannot
    follow the skin onto the base, docs/model.md 3.1). Measured friction, however, changes trend at
    the transition because the skin starts to touch the base (docs/model.md "Using it"). This
    phenomenological cell keeps Hertz below the transition pressure ``p_t`` and lets psi rise
    from ``psi_t = psi_Hertz(p_t)`` to 1 linearly in ``log p`` up to full contact at
    ``full_contact_ratio * p_t``, which steepens ``d log psi / d log p`` at ``p_t`` from 2/3
    to ``(1 - psi_t) / (psi_t ln ratio)``.

    Attributes
    ----------
    hertz
        The asperity-contact cell.
    full_contact_ratio
        ``p_full / p_t`` (> 1).
    """

    hertz: Any
    full_contact_ratio: float = 4.0

    def __post_init__(self) -> None:
        if not (isinstance(self.full_contact_ratio, (int, float)) and self.full_contact_ratio > 1):
            raise FingerpadError(f"full-contact ratio must exceed 1, got {self.full_contact_ratio!r}")

    @property
    def transition_pressure(self) -> float:
        """Pressure at which the skin touches the base, Pa (Hertz, Eq. 3.3)."""
        return float(self.hertz.transition_pressure)

    @property
    def full_contact_pressure(self) -> float:
        """``full_contact_ratio * p_t``, Pa."""
        return self.full_contact_ratio * self.transition_pressure

    @property
    def breakpoints(self) -> tuple[float, ...]:
        return tuple(getattr(self.hertz, "breakpoints", ()))

    def contact_fraction(self, p: np.ndarray) -> np.ndarray:
        """psi(p): Hertz below ``p_t``, log-linear growth to 1 between ``p_t`` and ``p_full``."""
        pp = np.clip(np.asarray(p, dtype=float), 0.0, None)
        pt = self.transition_pressure
        psi_t = float(self.hertz.contact_fraction(np.array(pt)))
        below = np.asarray(self.hertz.contact_fraction(pp), dtype=float)
        with np.errstate(divide="ignore"):
            grow = psi_t + (1.0 - psi_t) * np.log(np.maximum(pp, pt) / pt) / math.log(self.full_contact_ratio)
        return np.where(pp < pt, below, np.clip(np.maximum(grow, below), 0.0, 1.0))


def hertz_texture_model(
    radius: float,
    height: float,
    spacing: float,
    finger: Any = None,
    material_modulus: float | None = None,
    *,
    material_poisson: float = 0.35,
    full_contact_ratio: float | None = None,
    n_rings: int = 6,
) -> Model:
    """Default normalised-friction model: Hertzian bumps under the finger's ridge contact.

    Built on :mod:`fingerpad.coupling`: for a trial skin modulus E_s the finger (a preset name,
    a :class:`fingerpad.finger.Finger` or ``None`` for the default) gets ``skin_modulus=E_s``,
    the unit cell :class:`fingerpad.micro.hertz.HertzUnitCell` gets ``E1*`` from Eq. 3.4, and
    :func:`fingerpad.coupling.predict_curve` gives ``mu_normalised`` (adhesion, pressure term
    and hysteresis included, so not exactly the area ratio).

    Parameters
    ----------
    radius, height, spacing
        Cap radius R, height h and lattice spacing lambda of the bumps, m.
    finger
        Preset name, :class:`fingerpad.finger.Finger`, or ``None`` (default finger).
    material_modulus, material_poisson
        Counter-surface elasticity (``None`` = rigid), Eq. 3.4.
    full_contact_ratio
        ``None``: pure Hertz (asperity tops only, no change of trend at the transition).
        A number > 1: :class:`BaseContactCell` -- contact spreads over the base past the
        transition and is full at this multiple of the transition pressure.
    n_rings
        Quadrature density of :func:`fingerpad.coupling.couple`; 6 keeps the relative error
        far below measurement noise at a third of the cost of the default 16 (a fit calls the
        model some fifty times).

    Returns
    -------
    callable
        ``model(loads, skin_modulus) -> mu_normalised`` (1-D ndarray like ``loads``), with
        attributes ``geometry`` and ``finger``.
    """
    from .. import coupling
    from ..micro.hertz import HertzUnitCell

    geometry = TextureGeometry(radius, height, spacing, material_modulus, material_poisson, full_contact_ratio, "hertz")
    base = resolve_finger(finger)

    def model(loads: np.ndarray, skin_modulus: float) -> np.ndarray:
        f = base.with_overrides(skin_modulus=float(skin_modulus))
        cell: Any = HertzUnitCell.for_finger(
            f, radius=geometry.radius, height=geometry.height, spacing=geometry.spacing,
            material_modulus=geometry.material_modulus, material_poisson=geometry.material_poisson,
        )
        if geometry.full_contact_ratio is not None:
            cell = BaseContactCell(cell, geometry.full_contact_ratio)
        # the friction alone: a fit reads no critical load
        curve = coupling.predict_curve(np.asarray(loads, dtype=float), f, cell, n_rings=n_rings,
                                       critical_loads=False)
        return np.asarray(curve.mu_normalised, dtype=float)

    model.geometry = geometry  # type: ignore[attr-defined]
    model.finger = base  # type: ignore[attr-defined]
    model.variant = lambda other: hertz_texture_model(  # type: ignore[attr-defined]
        radius, height, spacing, other, material_modulus, material_poisson=material_poisson,
        full_contact_ratio=full_contact_ratio, n_rings=n_rings)
    return model


def model_variant(model: Model, finger: Any) -> Model:
    """The same micro-model (same texture, same computed BEM cell) for another finger.

    Used for the sensitivity of E_s to the friction parameters (tau0, alpha, beta) and the
    ridge fraction, which enter through the finger.

    Raises
    ------
    FingerpadError
        For a model that was not built by :func:`bem_texture_model` or :func:`hertz_texture_model`.
    """
    make = getattr(model, "variant", None)
    if make is None:
        raise FingerpadError("this model cannot be rebuilt for another finger (not a fingerpad micro-model)")
    return make(resolve_finger(finger))


def bem_texture_model(
    radius: float,
    height: float,
    spacing: float,
    finger: Any = None,
    material_modulus: float | None = None,
    *,
    material_poisson: float = 0.35,
    grid: int = 64,
    modulus_range: tuple[float, float] = (0.05e6, 5e6),
    load_range: tuple[float, float] = (0.01, 20.0),
    cache: Any = None,
    n_rings: int = 6,
) -> Model:
    """Normalised-friction model with the numerical unit cell (the model of ``fingerpad predict``).

    One :class:`fingerpad.micro.bem.BEMUnitCell` of the cap texture is computed (or read from the
    cache) at the finger's own E1*, over the local pressures that loads in ``load_range`` produce
    for any skin modulus in ``modulus_range``; every trial E_s then reuses it by the p/E* scaling
    of the contact problem (:meth:`~fingerpad.micro.bem.BEMUnitCell.at_modulus`), so a fit costs
    no further solves. Unlike the Hertz cell it covers the transition and full contact, which is
    where the change of trend in friction comes from.

    Parameters
    ----------
    radius, height, spacing
        Cap radius R, height h and square-lattice spacing lambda, m.
    finger
        Preset name, :class:`fingerpad.finger.Finger`, or ``None`` (default finger).
    material_modulus, material_poisson
        Counter-surface elasticity (``None`` = rigid), Eq. 3.4.
    grid
        Unit-cell grid points per side.
    modulus_range, load_range
        Skin moduli (Pa) and loads (N) the model must answer for.
    cache
        Passed to :class:`~fingerpad.micro.bem.BEMUnitCell` (``None``: default cache folder).

    Returns
    -------
    callable
        ``model(loads, skin_modulus) -> mu_normalised``, with ``geometry``, ``finger`` and ``cell``.
    """
    from ..micro.bem import BEMUnitCell
    from ..textures import spherical_caps

    geometry = TextureGeometry(radius, height, spacing, material_modulus, material_poisson)
    base = resolve_finger(finger)
    lo_e, hi_e = (float(v) for v in modulus_range)
    lo_f, hi_f = (float(v) for v in load_range)
    if not (0 < lo_e < hi_e and 0 < lo_f < hi_f):
        raise FingerpadError("modulus_range and load_range must be increasing positive pairs")

    def e1(skin_modulus: float) -> float:
        return float(base.with_overrides(skin_modulus=skin_modulus).micro_modulus(material_modulus, material_poisson))

    e_ref = e1(base.skin_modulus)
    texture = spherical_caps(radius=radius, height=height, spacing=spacing, grid=grid)
    cell = BEMUnitCell(texture, e_ref, cache=cache)
    return _bem_model(cell, geometry, base, (lo_e, hi_e), (lo_f, hi_f), n_rings)


def _bem_model(cell: Any, geometry: TextureGeometry, finger: Any, modulus_range: tuple[float, float],
               load_range: tuple[float, float], n_rings: int) -> Model:
    """The BEM model of a computed cell for ``finger``: the cell is prepared over the local
    pressures this finger's ridge area gives (reusing every node already solved)."""
    from .. import coupling

    mm, mp = geometry.material_modulus, geometry.material_poisson

    def e1(skin_modulus: float) -> float:
        return float(finger.with_overrides(skin_modulus=skin_modulus).micro_modulus(mm, mp))

    e_ref = float(cell.modulus)
    lo_f, hi_f = load_range
    ridge = np.asarray(finger.ridge_area(np.array([lo_f, hi_f])), dtype=float)
    p_lo, p_hi = 0.02 * lo_f / ridge[0], 1.5 * hi_f / ridge[1]
    cell.prepare(p_lo * e_ref / e1(modulus_range[1]), p_hi * e_ref / e1(modulus_range[0]))

    def model(loads: np.ndarray, skin_modulus: float) -> np.ndarray:
        f = finger.with_overrides(skin_modulus=float(skin_modulus))
        scaled = cell.at_modulus(float(f.micro_modulus(mm, mp)))
        curve = coupling.predict_curve(np.asarray(loads, dtype=float), f, scaled, n_rings=n_rings,
                                       critical_loads=False)
        return np.asarray(curve.mu_normalised, dtype=float)

    model.geometry = geometry  # type: ignore[attr-defined]
    model.finger = finger  # type: ignore[attr-defined]
    model.cell = cell  # type: ignore[attr-defined]
    model.variant = lambda other: _bem_model(cell, geometry, other, modulus_range, load_range,  # type: ignore[attr-defined]
                                             n_rings)
    return model


def texture_model(geometry: TextureGeometry, finger: Any = None) -> Model:
    """The normalised-friction model that ``geometry.micro_model`` names."""
    if geometry.micro_model == "bem":
        return bem_texture_model(
            geometry.radius, geometry.height, geometry.spacing, finger, geometry.material_modulus,
            material_poisson=geometry.material_poisson,
        )
    return hertz_texture_model(
        geometry.radius, geometry.height, geometry.spacing, finger, geometry.material_modulus,
        material_poisson=geometry.material_poisson, full_contact_ratio=geometry.full_contact_ratio,
    )


@dataclass(frozen=True)
class ModelLabel:
    """What a detached :class:`ModelTable` keeps of its model: its texture geometry (``None``
    for a model without one), which names the micro-model in a fit's result. Not a model: it
    computes nothing."""

    geometry: TextureGeometry | None = None


class ModelTable:
    """A model tabulated on a grid of skin moduli and loads, interpolated in between.

    The model (a disc integral per load) is the costly part of a fit; tabulating it once per
    texture -- ``n_moduli`` log-spaced E_s in ``bounds`` times ``n_loads`` log-spaced loads in
    ``load_range`` -- makes every fit, profile and participant that shares the texture nearly
    free. Interpolation: cubic spline in ``log E_s``, linear in ``log F`` of ``log model``.

    Parameters
    ----------
    model
        ``model(loads, skin_modulus) -> mu_normalised``.
    load_range
        (lowest, highest) load to cover, N.
    bounds
        (lowest, highest) skin modulus, Pa.
    n_loads, n_moduli
        Grid sizes.

    Raises
    ------
    FingerpadError
        For bad ranges, or a model returning the wrong shape, non-finite or non-positive values.
    """

    def __init__(
        self,
        model: Model,
        load_range: tuple[float, float],
        bounds: tuple[float, float] = (2e4, 2e7),
        *,
        n_loads: int = 32,
        n_moduli: int = 49,
    ) -> None:
        from scipy.interpolate import CubicSpline

        lo, hi = (float(v) for v in load_range)
        e_lo, e_hi = (float(v) for v in bounds)
        if not (0 < e_lo < e_hi and math.isfinite(e_hi)):
            raise FingerpadError(f"modulus bounds must satisfy 0 < low < high, got {bounds!r}")
        if not (0 < lo <= hi and math.isfinite(hi)):
            raise FingerpadError(f"load range must be positive, got {load_range!r}")
        if hi <= lo * 1.001:  # a single load: widen a little so interpolation is defined
            lo, hi = lo / 1.01, hi * 1.01
        self.model = model
        self.bounds = (e_lo, e_hi)
        self.loads = np.geomspace(lo, hi, int(n_loads))
        self.log_moduli = np.linspace(math.log(e_lo), math.log(e_hi), int(n_moduli))
        rows = []
        for le in self.log_moduli:
            curve = np.asarray(model(self.loads, math.exp(le)), dtype=float)
            if curve.shape != self.loads.shape or not np.all(np.isfinite(curve)) or np.any(curve <= 0):
                raise FingerpadError(
                    f"model returned {curve.shape} values for {self.loads.size} loads at "
                    f"E_s = {math.exp(le):.4g} Pa (need positive finite values)"
                )
            rows.append(np.log(curve))
        self.table = np.array(rows)
        self._spline = CubicSpline(self.log_moduli, self.table, axis=0)
        self._rows: dict[tuple[Any, ...], np.ndarray] = {}

    def detached(self) -> ModelTable:
        """The table without its model: what it holds, for another process (a model may be a
        closure, which does not pickle); calling it interpolates as before. The model's
        ``geometry`` stays (:class:`ModelLabel`): it names the micro-model of a fit."""
        import copy

        table = copy.copy(self)
        table.model = ModelLabel(getattr(self.model, "geometry", None))  # type: ignore[assignment]
        table._rows = {}
        return table

    def log_rows(self, log_moduli: np.ndarray) -> np.ndarray:
        """``log model`` at the table's loads (columns) for each ``log E_s`` of ``log_moduli``
        (rows, clipped to the table's range): the spline's rows. The last few scans asked for are
        kept: every E_s fit on this table starts from the same coarse scan."""
        scan = np.asarray(log_moduli, dtype=float)
        key = (scan.shape, scan.tobytes())
        rows = self._rows.get(key)
        if rows is None:
            rows = self._spline(np.clip(scan, self.log_moduli[0], self.log_moduli[-1]))
            rows.flags.writeable = False
            if len(self._rows) >= 4:
                self._rows.pop(next(iter(self._rows)))
            self._rows[key] = rows
        return rows

    def covers(self, loads: np.ndarray) -> bool:
        """Whether ``loads`` lie inside the tabulated range."""
        return bool(np.min(loads) >= self.loads[0] * (1 - 1e-9) and np.max(loads) <= self.loads[-1] * (1 + 1e-9))

    def log_predict(self, loads: np.ndarray, log_modulus: float) -> np.ndarray:
        """``log model(loads, exp(log_modulus))`` by interpolation."""
        row = self._spline(float(np.clip(log_modulus, self.log_moduli[0], self.log_moduli[-1])))
        return np.interp(np.log(loads), np.log(self.loads), row)

    def __call__(self, loads: np.ndarray, skin_modulus: float) -> np.ndarray:
        """Interpolated ``model(loads, skin_modulus)``."""
        return np.exp(self.log_predict(np.asarray(loads, dtype=float), math.log(skin_modulus)))
