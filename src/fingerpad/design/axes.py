"""The axes of a sweep: which study value each one sets, its kind and unit, and its values.

An axis is named after what it changes:

* a parameter of the texture family (``spacing``, ``height``, ``radius``, ``semi_axis_x``,
  ``orientation``, ``lattice``, ...), or ``texture`` itself (the family);
* ``material_modulus``, ``material_poisson`` (the counter-surface, Eq. 3.4);
* ``direction``: the sliding direction (directional friction of compliant ellipsoids or ridges);
* ``finger`` (a preset) or a finger field (``skin_modulus``, ``skin_poisson``, ``tau0``,
  ``alpha``, ``beta``; ``finger.radius`` and ``finger.modulus`` for the pad, since ``radius``
  alone is the texture's).

Each axis carries the declaration of what it sets (:class:`fingerpad.params.Param`: the texture
family's parameter, the finger's field, the material's value), which reads its values with the same
units and bounds, and the same messages, as the study file and the command line. In a sweep
study file a length, pressure or force without a unit is refused (``spacing = 7`` would be 7 m):
:meth:`Axis.parse` with ``require_unit=True``.

Values are kept in SI (angles in radians) and written into the study as quantities with their
unit, so that the one validation of :func:`fingerpad.study.spec.study_from_dict` applies.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from ..errors import FingerpadError
from ..finger import FINGER_PARAMS, FINGER_PRESETS
from ..materials import MATERIAL_MODULUS, MATERIAL_POISSON
from ..params import Param

__all__ = ["Axis", "resolve_axis"]

_SI_UNIT = {"length": "m", "pressure": "Pa", "force": "N", "angle": "rad", "none": "", "surface energy": "J/m2"}


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
    param
        The declaration of the value the axis sets (``None`` for the texture family and the
        finger preset, which are names).
    """

    name: str
    section: str
    key: str
    kind: str
    choices: tuple[str, ...] = ()
    values: tuple[Any, ...] = ()
    log: bool = False
    param: Param | None = None

    @property
    def unit(self) -> str:
        return _SI_UNIT.get(self.kind, "")

    @property
    def numeric(self) -> bool:
        return self.kind not in ("choice",)

    def parse(self, value: Any, where: str, *, require_unit: bool = False) -> Any:
        """One value of this axis (a number in SI, a quantity with a unit, a name), read by the
        axis's declaration (its units and bounds). With ``require_unit`` a length, pressure or
        force without a unit is refused (sweep study files)."""
        if self.param is None:  # the family or the finger preset: a name
            text = str(value).strip().lower()
            if text not in self.choices:
                raise FingerpadError(f"{where}: {value!r} is not one of {', '.join(self.choices)}")
            return text
        return self.param.parse(value, where, require_unit=require_unit)

    @property
    def dimensional(self) -> bool:
        """Whether a bare number of this axis is a physical quantity (refused without a unit)."""
        return self.param is not None and self.param.dimensional

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


_KIND = {"length": "length", "pressure": "pressure", "force": "force", "angle": "angle", "count": "count",
         "ratio": "none", "choice": "choice", "surface energy": "surface energy"}

#: The sliding direction (``[model] direction``), degrees from the texture's x axis.
_DIRECTION = Param("direction", "angle", "sliding direction, from the texture's x axis", None)


def _axis(name: str, section: str, key: str, param: Param) -> Axis:
    return Axis(name, section, key, _KIND[param.kind], param.choices, param=param)


def resolve_axis(name: str, texture_family: str | None, where: str = "[sweep] axis") -> Axis:
    """The :class:`Axis` (without values) that ``name`` stands for; ``where`` names what gave it
    in messages (``[sweep] axis``, ``--vary``).

    Raises
    ------
    FingerpadError
        For a name that is no texture parameter, material, finger preset or finger field,
        listing what can be swept.
    """
    from ..textures import registry

    families = registry()
    finger = {p.name: p for p in FINGER_PARAMS}
    key = str(name).strip()
    if key == "texture":
        return Axis(key, "texture", "name", "choice", tuple(families))
    if key in ("material_modulus", "material.modulus"):
        return _axis(key, "material", "modulus", MATERIAL_MODULUS)
    if key in ("material_poisson", "material.poisson"):
        return _axis(key, "material", "poisson", MATERIAL_POISSON)
    if key in ("direction", "model.direction"):
        return _axis(key, "model", "direction", _DIRECTION)
    if key in ("finger", "finger.preset"):
        return Axis(key, "finger", "preset", "choice", tuple(FINGER_PRESETS))
    if key.startswith("finger."):
        field = key.split(".", 1)[1]
        if field in finger:
            return _axis(key, "finger", field, finger[field])
    family = families.get(str(texture_family or "").lower())
    params = {p.name: p for p in family.user_params()} if family is not None else {}
    if key in params and params[key].kind in _KIND:
        return _axis(key, "texture", key, params[key])
    if key in finger and key not in ("radius", "modulus"):
        return _axis(key, "finger", key, finger[key])
    if family is None and texture_family is None:
        # a sweep over `texture` itself: the parameter belongs to some family
        for fam in families.values():
            for p in fam.user_params():
                if p.name == key and p.kind in _KIND:
                    return _axis(key, "texture", key, p)
    known = sorted({*params, "texture", "material_modulus", "material_poisson", "finger", "direction",
                    *(f for f in finger if f not in ("radius", "modulus")), "finger.radius", "finger.modulus"})
    fam_text = f" of texture {family.name!r}" if family is not None else ""
    raise FingerpadError(f"{where} {name!r} is not a parameter{fam_text} nor a material or finger value "
                         f"(axes: {', '.join(known)})")
