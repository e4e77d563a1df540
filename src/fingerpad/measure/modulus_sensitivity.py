"""How much E_s rests on assumptions: the micro-model and the friction parameters.

The model fit of E_s draws on the level of mu/mu_ref, and that level is set by the assumed
interface parameters (tau0, alpha of Eq. 2.3, beta of Eq. 2.4) and the ridge fraction
(A_fr / A_g, ch. 2.2.2) as much as by E_s; and the BEM and Hertz unit cells give E_s some
20-25 % apart on the same data. So every E_s is refitted

* with the other micro-model (BEM <-> Hertz, asperity tops only), and
* with each friction parameter at the ends of a plausible range, the others kept:
  tau0 x 0.5 and x 2 (dry to wet skin, docs/model.md: mu ~ 0.5 dry, > 1 wet), alpha and beta
  x 0.5 and x 2 (both assumed, no value in docs/model.md), ridge fraction 0.3 and 0.7 (docs/model.md:
  10-70 % of the gross area; the default is 0.5).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from ..errors import FingerpadError
from .micro_models import Model, ModelTable, TextureGeometry, model_variant, texture_model

if TYPE_CHECKING:
    from .modulus import ModulusFit


@dataclass(frozen=True)
class Perturbation:
    """One refit: ``parameter`` set to ``value`` (its display), by ``apply(finger) -> finger``."""

    parameter: str
    value: str
    apply: Callable[[Any], Any]


def _scaled(name: str, factor: float) -> Perturbation:
    return Perturbation(name, f"x{factor:g}", lambda f: f.with_overrides(**{name: getattr(f, name) * factor}))


def _ridge_fraction(fraction: float) -> Perturbation:
    def apply(f: Any) -> Any:
        from ..meso.constant_fraction import ConstantFractionRidges

        if not isinstance(f.ridges, ConstantFractionRidges):
            raise FingerpadError("the finger's ridge model is not a constant fraction")
        return f.with_overrides(ridges=ConstantFractionRidges(fraction))

    return Perturbation("ridge_fraction", f"{fraction:g}", apply)


#: The friction-parameter refits (see the module doc for the ranges).
PERTURBATIONS: tuple[Perturbation, ...] = (
    _scaled("tau0", 0.5), _scaled("tau0", 2.0),
    _scaled("alpha", 0.5), _scaled("alpha", 2.0),
    _scaled("beta", 0.5), _scaled("beta", 2.0),
    _ridge_fraction(0.3), _ridge_fraction(0.7),
)


def other_micro_model(geometry: TextureGeometry, finger: Any) -> tuple[str, Model]:
    """The other unit-cell model of ``geometry``: Hertz for BEM, BEM for Hertz."""
    other = "hertz" if geometry.micro_model == "bem" else "bem"
    geom = dataclasses.replace(geometry, micro_model=other, full_contact_ratio=None)
    return other, texture_model(geom, finger)


def perturbed_models(model: Model, finger: Any) -> dict[tuple[str, str], Model]:
    """``(parameter, value) -> model`` for every perturbation that applies to ``finger``."""
    out = {}
    for p in PERTURBATIONS:
        try:
            out[(p.parameter, p.value)] = model_variant(model, p.apply(finger))
        except FingerpadError:
            continue  # e.g. ridge fraction of a finger whose ridges are not a constant fraction
    return out


@dataclass
class Variants:
    """Model tables of one texture: the other micro-model and the friction-parameter refits,
    keyed by ``(parameter, value)`` (``("micro_model", "hertz")``, ``("tau0", "x0.5")`` ...)."""

    tables: dict[tuple[str, str], ModelTable] = field(default_factory=dict)


def variant_tables(geom: TextureGeometry | None, model: Model, finger: Any,
                   load_range: tuple[float, float], bounds: tuple[float, float]) -> Variants:
    """The other micro-model's table and every friction-parameter refit's (those a texture or
    model cannot describe are left out)."""
    out = Variants()
    if geom is not None:
        try:
            name, other = other_micro_model(geom, finger)
            out.tables[("micro_model", name)] = ModelTable(other, load_range, bounds)
        except FingerpadError:
            pass  # the other model cannot describe this texture: no comparison
    for key, mdl in perturbed_models(model, finger).items():
        try:
            out.tables[key] = ModelTable(mdl, load_range, bounds)
        except FingerpadError:
            continue
    return out


def sensitivity_rows(base: ModulusFit, refits: list[tuple[str, str, Any]], keys: dict[str, Any]
                      ) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    """Run every refit ``(parameter, value, fit())``; rows of the sensitivity table and the
    summary columns (the other micro-model's E_s, the range over the friction parameters)."""
    rows: list[dict[str, Any]] = []
    summary: dict[str, Any] = {}
    friction = []
    for parameter, value, refit in refits:
        try:
            mf = refit()
        except FingerpadError as exc:
            rows.append({**keys, "parameter": parameter, "value": value, "skin_modulus": math.nan,
                         "ratio": math.nan, "determined": False, "note": str(exc)})
            continue
        ratio = mf.skin_modulus / base.skin_modulus if base.skin_modulus > 0 else math.nan
        rows.append({**keys, "parameter": parameter, "value": value, "skin_modulus": mf.skin_modulus,
                     "ratio": ratio, "determined": mf.determined, "note": mf.note})
        if parameter == "micro_model":
            summary.update(skin_modulus_other_model=value, skin_modulus_other=mf.skin_modulus,
                           skin_modulus_other_determined=mf.determined)
        elif mf.determined:
            friction.append(mf.skin_modulus)
    if friction:
        summary.update(skin_modulus_sens_low=float(min(friction + [base.skin_modulus])),
                       skin_modulus_sens_high=float(max(friction + [base.skin_modulus])))
    return rows, summary
