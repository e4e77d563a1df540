"""One deflection job: a texture family's parameters in, the gain curves of several directions out.

This is what ``fingerpad deflection`` runs (the command parses, calls :func:`run_deflection`
once, prints :meth:`DeflectionResult.lines` and writes :meth:`DeflectionResult.document` and
:meth:`DeflectionResult.dataset`), and what a script calls for the same numbers::

    result = run_deflection("ellipsoids", {"semi_axis_x": "45um", "semi_axis_y": "135um",
                            "height": "90um", "spacing_x": "300um", "spacing_y": "300um"},
                            SectionMaterials(0.3e6, 0.35, 0.3e6, 0.49), directions=(0, 90),
                            pressure_range=(2e3, 2e4), tau0=8.1e3, alpha=0.1)

The texture is built by its own family (:class:`fingerpad.textures.TextureFamily`), so every
check of its geometry (overlapping asperities, a circular ridge higher than half its width) is
the texture's own; the family's ``deflection`` hook turns its parameters into the section
geometry. A family without that hook is refused before any solving.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import asdict, dataclass, fields
from typing import Any

import numpy as np

from ...errors import FingerpadError
from .gain import MODEL_VERSION, DeflectionSettings, GainCurve, SectionMaterials, as_dataset, directional_gains
from .section import Geometry, deflection_hook

#: Shear levels of the printed and stored gain table.
TABLE_MU = (0.3, 0.6, 1.0, 1.5)


@dataclass
class DeflectionResult:
    """The gain curves of one texture, material and friction law at several directions (SI).

    Attributes
    ----------
    texture
        Family name.
    params
        The built texture's parameters (SI, radians for angles).
    geometry
        The section geometry from the family's ``deflection`` hook.
    materials, tau0, alpha, settings
        The inputs (Pa, Pa, -, :class:`DeflectionSettings`).
    curves
        One :class:`GainCurve` per direction, in the order asked.
    """

    texture: str
    params: dict[str, Any]
    geometry: Geometry
    materials: SectionMaterials
    tau0: float
    alpha: float
    settings: DeflectionSettings
    curves: list[GainCurve]

    @property
    def incomplete(self) -> bool:
        """Some ramp was cut by the wall-clock safety stop: the numbers are not a result."""
        return any(c.incomplete for c in self.curves)

    def gain_table(self, mus: Sequence[float] = TABLE_MU) -> list[dict[str, Any]]:
        """Per direction and pressure level: the gain at the shear levels ``mus`` and whether each
        is *held* (past the largest shear level the ramp reached: the last computed value,
        not a computed one)."""
        rows = []
        for c in self.curves:
            for r in c.ramps or []:
                g = [float(c(r.pressure, m)) for m in mus]
                held = [bool(c.saturated(r.pressure, m)) for m in mus]
                rows.append({"direction_deg": c.direction_deg, "pressure": float(r.pressure), "mu": list(mus),
                             "gain": g, "held": held, "mu_reached": r.mu_reached, "incomplete": r.incomplete})
        return rows

    def lines(self, mus: Sequence[float] = TABLE_MU) -> list[str]:
        """The report as text lines of at most 80 columns: per direction the gains (``*``: held
        past the shear level reached), the ramp's flags and why a ramp stopped."""
        out = []
        table = self.gain_table(mus)
        for c in self.curves:
            head = f"direction {c.direction_deg:g} deg"
            if c.is_identity:
                out.append(f"{head}: gain 1, {c.reason}")
                continue
            s = c.section
            out.append(f"{head}: half-width {s.half_width * 1e6:.4g} um, height {s.height * 1e6:.4g} um, "
                       f"period {s.period * 1e6:.4g} um, shear factor {c.shear_factor:.3g}")
            out.append("  p (kPa)  " + "  ".join(f"G(mu={m:g})" for m in mus) + "  mu reached")
            for row in (t for t in table if t["direction_deg"] == c.direction_deg):
                cells = "  ".join(f"{g:8.3f}{'*' if h else ' '}" for g, h in zip(row["gain"], row["held"]))
                flag = "  INCOMPLETE" if row["incomplete"] else ""
                out.append(f"  {row['pressure'] / 1e3:7.3g}  {cells}  {row['mu_reached']:10.3g}{flag}")
            if any(any(t["held"]) for t in table if t["direction_deg"] == c.direction_deg):
                out.append("  * held: past the shear level the ramp reached (the last computed gain)")
            out.append("  p (kPa)  bend@max (um)  k_t0 (kPa)  fold@mu  limit@mu  buckled")
            for r in c.ramps or []:
                kt0 = r.tangential_stiffness[1] if r.tangential_stiffness.size > 1 else math.nan
                tip = r.bend_dx[-1] * 1e6 if r.bend_dx.size else math.nan
                out.append(f"  {r.pressure / 1e3:7.3g}  {tip:13.3g}  {kt0 / 1e3:10.3g}  {r.fold_onset_mu:7.3g}  "
                           f"{r.limit_mu:8.3g}  {r.buckled}")
            for r in c.ramps or []:
                if r.stopped:
                    out += [f"  the ramp at {r.pressure / 1e3:.3g} kPa stopped:", f"    {r.stopped}"]
        if self.incomplete:
            out.append("INCOMPLETE: the wall-clock time limit cut a ramp; these numbers depend on the machine's "
                       "speed, are not cached and are no result (rerun without --time-limit)")
        return out

    def document(self) -> dict[str, Any]:
        """JSON-ready document (SI units; NaN as None is the writer's business)."""
        return {
            "texture": self.texture,
            "params": self.params,
            "geometry": {f.name: getattr(self.geometry, f.name) for f in fields(self.geometry)}
            if hasattr(self.geometry, "__dataclass_fields__") else repr(self.geometry),
            "materials": asdict(self.materials), "tau0": self.tau0, "alpha": self.alpha,
            "settings": asdict(self.settings),
            "model_version": MODEL_VERSION,
            "incomplete": self.incomplete,
            "units": "SI (m, Pa, N/m per unit depth); directions in degrees",
            "gain_table": self.gain_table(),
            "gain_table_note": "held: past the largest shear level the ramp reached, the last computed gain "
                               "(not computed there)",
            "directions": [c.as_dict() for c in self.curves],
        }

    def dataset(self, mus: Sequence[float] = TABLE_MU) -> Any:
        """:func:`.gain.as_dataset` with the gain table and its held flags (dims direction,
        pressure, table_mu) and the ``incomplete`` flag in the attributes."""
        ds = as_dataset(self.curves)
        pressures = [float(p) for p in ds["pressure"].values]
        gain = np.full((len(self.curves), len(pressures), len(mus)), np.nan)
        held = np.zeros(gain.shape, dtype=np.int8)
        for i, c in enumerate(self.curves):
            for j, p in enumerate(pressures):
                if not math.isfinite(p):
                    continue
                gain[i, j] = [float(c(p, m)) for m in mus]
                held[i, j] = [bool(c.saturated(p, m)) for m in mus]
        ds = ds.assign_coords(table_mu=("table_mu", np.asarray(mus, float), {"units": "1"}))
        ds["table_gain"] = (("direction", "pressure", "table_mu"), gain,
                            {"units": "1", "long_name": "deflection gain G(p, mu) of the table"})
        ds["table_gain_held"] = (("direction", "pressure", "table_mu"), held,
                                 {"units": "1", "long_name": "1: held past the shear level the ramp reached"})
        ds.attrs["incomplete"] = int(self.incomplete)
        ds.attrs["texture"] = self.texture
        return ds


def run_deflection(
    texture: str,
    params: Mapping[str, Any],
    materials: Any,
    directions: Sequence[float] = (0.0, 90.0),
    pressure_range: tuple[float, float] = (5e3, 4e4),
    tau0: float = 0.0,
    alpha: float = 1.0,
    settings: DeflectionSettings = DeflectionSettings(),
    cache: bool | str = True,
    progress: Callable[[str], None] | None = None,
    label: Callable[[Any], str] | None = None,
    workers: int | None = None,
) -> DeflectionResult:
    """Gain curves of the texture ``texture`` (a registered family with a ``deflection`` hook).

    Parameters
    ----------
    texture
        Family name (``ellipsoids``, ``ridges``, or any family registered with a hook).
    params
        The family's parameters by keyword name, as text with units (``"45um"``) or SI numbers.
    materials
        :class:`SectionMaterials` or :class:`fingerpad.materials.Materials`.
    directions
        Sliding directions, degrees from the texture's x axis.
    pressure_range
        (lowest, highest) nominal cell pressure, Pa.
    tau0, alpha
        Eq. 2.3 shape of the friction traction (Pa, -); ignored with Coulomb friction.
    settings, cache, progress
        As :func:`.gain.directional_gain`; ``progress`` also gets ``"directions D1, D2 deg"``.
    label
        How to name a parameter in messages (default: its command-line option).
    workers
        Processes for the shear ramps (None: the cores available, or
        ``FINGERPAD_DEFLECTION_WORKERS``; 1: this process). The numbers do not depend on it.

    Raises
    ------
    FingerpadError
        A family without a deflection model, the texture's own checks, bad values.
    """
    from ...textures.base import get_family

    hook = deflection_hook(texture)  # before anything else: a family without the model is refused
    family = get_family(texture)
    tau0, alpha = float(tau0), float(alpha)
    if not (math.isfinite(tau0) and tau0 >= 0):
        raise FingerpadError(f"tau0 must be a finite non-negative stress, got {tau0!r}")
    if not (math.isfinite(alpha) and 0 <= alpha <= 10):
        raise FingerpadError(f"alpha must lie in [0, 10], got {alpha!r}")
    dirs = [float(d) for d in directions]
    if not dirs or not all(math.isfinite(d) for d in dirs):
        raise FingerpadError("directions must be finite angles in degrees")
    lo, hi = (float(v) for v in pressure_range)
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo <= hi):
        raise FingerpadError(f"pressure range must be 0 < low <= high, got {pressure_range!r}")
    mats = materials if isinstance(materials, SectionMaterials) else SectionMaterials.from_materials(materials)
    built = family.build(params, label=label)  # the texture's own checks (overlap, ...)
    geometry = hook(built.params)
    for d in dirs:  # every section is checked before the first is solved
        geometry.section(d)
    if progress:
        progress("directions " + ", ".join(f"{d:g}" for d in dirs) + " deg")
    # every direction's section and level at once, in worker processes (the numbers do not depend
    # on their count: :mod:`.ramps`)
    curves = directional_gains(geometry, mats, dirs, (lo, hi), tau0=tau0, alpha=alpha, settings=settings,
                               cache=cache, progress=progress, workers=workers)
    return DeflectionResult(family.name, dict(built.params), geometry, mats, tau0, alpha, settings, curves)


__all__ = ["TABLE_MU", "DeflectionResult", "run_deflection"]
