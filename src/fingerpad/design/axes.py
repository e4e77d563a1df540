"""The axes of a sweep: which study value each one sets, its kind and unit, and its values.

An axis is named after what it changes:

* a parameter of the texture family (``spacing``, ``height``, ``radius``, ``semi_axis_x``,
  ``orientation``, ``lattice``, ...), or ``texture`` itself (the family);
* ``material_modulus``, ``material_poisson`` (the counter-surface, Eq. 3.4);
* ``direction``: the sliding direction (directional friction of compliant ellipsoids or ridges);
* ``finger`` (a preset) or a finger field (``skin_modulus``, ``skin_poisson``, ``tau0``,
  ``alpha``, ``beta``; ``finger.radius`` and ``finger.modulus`` for the pad, since ``radius``
  alone is the texture's).

Values are kept in SI (angles in radians) and written into the study as quantities with their
unit, so that the one validation of :func:`fingerpad.study.spec.study_from_dict` applies.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from ..errors import FingerpadError
from ..finger import FINGER_FIELDS, FINGER_PRESETS
from ..units import parse_quantity

__all__ = ["Axis", "resolve_axis"]

_SI_UNIT = {"length": "m", "pressure": "Pa", "force": "N", "angle": "rad", "none": ""}


@dataclass(frozen=True)
class Axis:
    """One swept quantity.

    Attributes
    ----------
    name
        The axis name as given (dimension name in the store).
    section, key
        Where the value goes in the study (``("texture", "spacing")``, ``("finger", "preset")``).
    kind
        ``length``, ``pressure``, ``angle``, ``none`` (a number), ``count`` or ``choice``.
    choices
        Allowed values of a ``choice`` axis.
    values
        The axis values: SI floats (angles in rad), integers or names.
    log
        Whether the values are log-spaced (map axes follow).
    """

    name: str
    section: str
    key: str
    kind: str
    choices: tuple[str, ...] = ()
    values: tuple[Any, ...] = ()
    log: bool = False

    @property
    def unit(self) -> str:
        return _SI_UNIT.get(self.kind, "")

    @property
    def numeric(self) -> bool:
        return self.kind not in ("choice",)

    def parse(self, value: Any, where: str) -> Any:
        """One value of this axis from the study file (a number in SI, a quantity with a unit, a name)."""
        if self.kind == "choice":
            text = str(value).strip().lower()
            if text not in self.choices:
                raise FingerpadError(f"{where}: {value!r} is not one of {', '.join(self.choices)}")
            return text
        if isinstance(value, bool):
            raise FingerpadError(f"{where}: expected a number, got {value!r}")
        if self.kind == "count":
            number = parse_quantity(value, "none", name=where)
            if not float(number).is_integer():
                raise FingerpadError(f"{where}: expected an integer, got {value!r}")
            return int(number)
        if self.kind == "angle":
            from ..textures.base import parse_angle

            return parse_angle(value, where)
        return parse_quantity(value, self.kind, name=where)

    def study_value(self, value: Any) -> Any:
        """``value`` as the study file would hold it (angles with their unit: a bare number
        there is in degrees)."""
        if self.kind == "angle":
            return f"{float(value)!r}rad"
        return value

    def label(self) -> str:
        """Axis label with unit for figures and tables, e.g. ``spacing (um)``."""
        scale = {"length": "um", "pressure": "kPa", "angle": "deg"}.get(self.kind)
        return f"{self.name} ({scale})" if scale else self.name

    def display(self, value: float) -> float:
        """An SI value in the unit of :meth:`label`."""
        factor = {"length": 1e6, "pressure": 1e-3, "angle": 180 / math.pi}.get(self.kind, 1.0)
        return float(value) * factor


def resolve_axis(name: str, texture_family: str | None) -> Axis:
    """The :class:`Axis` (without values) that ``name`` stands for.

    Raises
    ------
    FingerpadError
        For a name that is no texture parameter, material, finger preset or finger field,
        listing what can be swept.
    """
    from ..textures import registry

    families = registry()
    key = str(name).strip()
    if key == "texture":
        return Axis(key, "texture", "name", "choice", tuple(families))
    if key in ("material_modulus", "material.modulus"):
        return Axis(key, "material", "modulus", "pressure")
    if key in ("material_poisson", "material.poisson"):
        return Axis(key, "material", "poisson", "none")
    if key in ("direction", "model.direction"):
        return Axis(key, "model", "direction", "angle")
    if key in ("finger", "finger.preset"):
        return Axis(key, "finger", "preset", "choice", tuple(FINGER_PRESETS))
    if key.startswith("finger."):
        field = key.split(".", 1)[1]
        if field in FINGER_FIELDS:
            return Axis(key, "finger", field, FINGER_FIELDS[field])
    family = families.get(str(texture_family or "").lower())
    params = {p.name: p for p in family.user_params()} if family is not None else {}
    if key in params:
        p = params[key]
        kind = {"length": "length", "angle": "angle", "count": "count", "ratio": "none",
                "choice": "choice"}.get(p.kind)
        if kind is not None:
            return Axis(key, "texture", key, kind, p.choices)
    if key in FINGER_FIELDS and key not in ("radius", "modulus"):
        return Axis(key, "finger", key, FINGER_FIELDS[key])
    if family is None and texture_family is None:
        # a sweep over `texture` itself: the parameter belongs to some family
        for fam in families.values():
            for p in fam.user_params():
                if p.name == key and p.kind in ("length", "angle", "count", "ratio", "choice"):
                    kind = {"ratio": "none"}.get(p.kind, p.kind)
                    return Axis(key, "texture", key, kind, p.choices)
    known = sorted({*params, "texture", "material_modulus", "material_poisson", "finger", "direction",
                    *(f for f in FINGER_FIELDS if f not in ("radius", "modulus")), "finger.radius", "finger.modulus"})
    fam_text = f" of texture {family.name!r}" if family is not None else ""
    raise FingerpadError(f"[sweep] axis {name!r} is not a parameter{fam_text} nor a material or finger value "
                         f"(axes: {', '.join(known)})")
