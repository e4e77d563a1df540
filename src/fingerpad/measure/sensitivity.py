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
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ..errors import FingerpadError
from .models import Model, TextureGeometry, model_variant, texture_model


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
