"""Scanning a number field: its step, unit, limits and slider range, from the parameter's
declaration (:class:`fingerpad.params.Param`).

A number field of the explorer (a texture dimension, the material, the finger, the zone-map load)
can be stepped with the arrow keys (Up/Down one step, with Shift ten) and, for the texture's
dimensions and the load, dragged along a slider. Everything here is the server's: the page sends
"step n" or a slider position, and :func:`step_text` / :func:`slider_text` give the text the field
then holds, which the page validates as if typed (one rule, one place: ``Param.parse`` and
``study_from_dict``, the same messages).

* **Unit**: the engineering prefix of the parameter's typical value (its ``example``, else its
  default): ``um`` for a 175 um spacing, ``kPa`` for a 40 kPa pad modulus; none for ratios.
* **Step**: a tenth of the decade of that value (175 um: 10 um; 20 um: 1 um; 0.49: 0.01);
  angles 1 deg, counts 1.
* **Limits**: the declaration's bounds; a length, pressure or force without a declared lower
  bound is positive (no texture has a zero or negative dimension). Steps past a closed bound
  stop on it; steps onto or past an open one stop at the last step short of it.
* **Slider** (texture dimensions, the load): the typical value divided and multiplied by
  :data:`SLIDER_SPAN`, on the step's grid, inside the limits; the zone-map load's runs over the
  loads of the study.

Nothing here imports Panel.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Any

from ..errors import FingerpadError
from ..params import DIMENSIONAL, Param
from ..units import UNITS

__all__ = ["MAX_STEPS", "SLIDER_SPAN", "ZONE_LOAD", "Scan", "scan_for", "shown_unit", "slider_position", "slider_text",
           "step_text", "value_text"]

#: The zone-map load as the page steps it (the study reads ``zones_at`` as a force and refuses
#: one that is not positive: the same bound, and the study's message once stepped).
ZONE_LOAD = Param("zones_at", "force", "load of the zone map (default: the largest load)", None, low=0,
                  low_open=True, label="zone-map load")

#: The slider of a texture dimension runs from its typical value / SLIDER_SPAN to x SLIDER_SPAN.
SLIDER_SPAN = 4.0
#: Most steps one request may take (a held key sends the steps pressed while the last was shown).
MAX_STEPS = 1000
#: Longest text a step request may carry (what the page sends is untrusted).
MAX_TEXT = 200

# the prefixes a value is shown with, per dimension (symbol, SI per unit), largest first
_PREFIXES = {
    "length": ("m", "mm", "um", "nm"),
    "pressure": ("GPa", "MPa", "kPa", "Pa"),
    "force": ("kN", "N", "mN"),
    "surface energy": ("J/m2", "mJ/m2"),
}


@dataclass(frozen=True)
class Scan:
    """How a number field steps and slides.

    Attributes
    ----------
    param
        The declaration (kind, bounds) the field's text is read with.
    label
        How messages name the field.
    unit
        The unit the stepped text is written in (``"um"``, ``"kPa"``, ``"deg"``; ``""`` for
        ratios and counts); ``factor`` its SI value.
    step
        One step, in ``unit`` (Shift: ten).
    slider
        ``(start, end)`` of the slider in ``unit``, or ``None`` for no slider.
    """

    param: Param
    label: str
    unit: str
    factor: float
    step: float
    slider: tuple[float, float] | None = None

    @property
    def hint(self) -> str:
        """What the page shows under the field: the step and its unit."""
        unit = f" {shown_unit(self.unit)}" if self.unit else ""
        return f"↑↓ {_num(self.step)}{unit} (Shift ×10)"

    def limits(self) -> tuple[float | None, bool, float | None, bool]:
        """``(low, low_open, high, high_open)`` in SI: the declaration's, a dimension positive."""
        p = self.param
        low, low_open = p.low, p.low_open
        if low is None and p.kind in DIMENSIONAL:
            low, low_open = 0.0, True
        return low, low_open, p.high, p.high_open

    def read(self, text: str) -> float:
        """The SI value of the field's ``text`` as the field reads it (``Param.parse``);
        :class:`~fingerpad.errors.FingerpadError` if the field refuses it."""
        if not isinstance(text, str) or len(text) > MAX_TEXT:
            raise FingerpadError(f"{self.label}: not a value")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # implausible values are the field's to warn about
            value = self.param.parse(text.strip(), self.label)
        if self.param.kind == "angle":
            value = math.degrees(value)  # the angle's unit is degrees: steps are in degrees
        return float(value)

    def with_slider(self, start: float, end: float) -> Scan:
        """This scan with a slider over ``[start, end]`` (SI), on the step's grid, inside the limits."""
        lo, hi = _inside(self, start / self.factor, end / self.factor)
        return Scan(self.param, self.label, self.unit, self.factor, self.step, (lo, hi) if hi > lo else None)


def shown_unit(unit: str) -> str:
    """A unit as the page writes it (``µm`` for ``um``)."""
    return "µm" if unit == "um" else unit


def _num(value: float) -> str:
    """``value`` without float noise (0.1 + 0.2 -> ``0.3``; 12 significant digits)."""
    text = f"{value:.12g}"
    return "0" if text == "-0" else text


def _unit_for(dimension: str, value: float) -> tuple[str, float]:
    """The prefixed unit of ``dimension`` in which ``value`` (SI) reads as 1 to 999."""
    names = _PREFIXES[dimension]
    for name in names:
        if abs(value) >= UNITS[name][1]:
            return name, UNITS[name][1]
    return names[-1], UNITS[names[-1]][1]


def _reference(param: Param, fallback: float | None) -> float | None:
    """The parameter's typical value in SI: its example, else its default, else ``fallback``."""
    for candidate in (param.example, param.default):
        if candidate is None or isinstance(candidate, bool) or not isinstance(candidate, (int, float, str)):
            continue
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                value = float(param.parse(candidate, param.name) if isinstance(candidate, str) else candidate)
        except (FingerpadError, ValueError, TypeError):
            continue
        if math.isfinite(value) and value != 0:
            return abs(value)
    if fallback is not None:
        return fallback
    # a ratio without a typical value (a Poisson ratio defaulting to another): its upper bound
    return abs(float(param.high)) if param.high not in (None, 0) and math.isfinite(param.high) else None


def scan_for(param: Param, label: str, *, fallback: float | None = None, slider: bool = False) -> Scan | None:
    """The scan of a field read by ``param`` (``None``: not a number field: a choice, a size, a
    grid). ``fallback``: the typical value (SI) when the declaration has none; ``slider``: give
    the field a slider around its typical value."""
    kind = param.kind
    if kind in ("choice", "size", "grid"):
        return None
    if kind == "count":
        return Scan(param, label, "", 1.0, 1.0)
    if kind == "angle":
        return Scan(param, label, "deg", 1.0, 1.0)
    ref = _reference(param, fallback)
    if ref is None:
        return None
    if kind in DIMENSIONAL:
        unit, factor = _unit_for(param.dimension, ref)
    else:
        unit, factor = "", 1.0
    shown = ref / factor
    step = 10.0 ** (math.floor(math.log10(shown) + 1e-9) - 1)
    scan = Scan(param, label, unit, factor, step)
    return scan.with_slider(ref / SLIDER_SPAN, ref * SLIDER_SPAN) if slider else scan


def _inside(scan: Scan, lo: float, hi: float) -> tuple[float, float]:
    """``[lo, hi]`` (in the scan's unit) on the step's grid and inside the limits."""
    step = scan.step
    lo, hi = math.ceil(lo / step - 1e-9) * step, math.floor(hi / step + 1e-9) * step
    low, low_open, high, high_open = scan.limits()
    if low is not None:
        floor = low / scan.factor
        while lo < floor or (low_open and lo <= floor):
            lo += step
    if high is not None:
        ceil = high / scan.factor
        while hi > ceil or (high_open and hi >= ceil):
            hi -= step
    return float(_num(lo)), float(_num(hi))


def _write(scan: Scan, value: float) -> str:
    return _num(value) + scan.unit


def value_text(scan: Scan, value: float) -> str:
    """The field's text of the SI ``value`` in the scan's unit (angles: radians in, degrees out)."""
    return _write(scan, math.degrees(value) if scan.param.kind == "angle" else value / scan.factor)


def step_text(scan: Scan, text: str, steps: int) -> str:
    """The field's text after ``steps`` steps (negative: down) from ``text``.

    Raises
    ------
    FingerpadError
        The field refuses ``text`` (its message), or ``steps`` is not an integer in
        ``[-MAX_STEPS, MAX_STEPS]``: nothing is stepped.
    """
    if isinstance(steps, bool) or not isinstance(steps, int) or not -MAX_STEPS <= steps <= MAX_STEPS:
        raise FingerpadError(f"{scan.label}: not a number of steps")
    value = scan.read(text) / (1.0 if scan.param.kind == "angle" else scan.factor)
    new = float(_num(value + steps * scan.step))
    low, low_open, high, high_open = scan.limits()
    if scan.param.kind != "angle":
        # past a closed bound: on it; onto or past an open one: the last step short of it
        if low is not None and new * scan.factor <= low and (low_open or new * scan.factor < low):
            bound = low / scan.factor
            new = bound if not low_open else value - max(math.ceil((value - bound) / scan.step - 1e-9) - 1, 0) * scan.step
        if high is not None and new * scan.factor >= high and (high_open or new * scan.factor > high):
            bound = high / scan.factor
            new = bound if not high_open else value + max(math.ceil((bound - value) / scan.step - 1e-9) - 1, 0) * scan.step
        new = float(_num(new))
    return _write(scan, new)


def slider_text(scan: Scan, position: Any) -> str:
    """The field's text for the slider at ``position`` (in the scan's unit; what the page sends,
    untrusted): on the slider's range and the step's grid."""
    if scan.slider is None:
        raise FingerpadError(f"{scan.label}: no slider")
    if isinstance(position, bool) or not isinstance(position, (int, float)) or not math.isfinite(position):
        raise FingerpadError(f"{scan.label}: not a slider position")
    start, end = scan.slider
    value = min(max(float(position), start), end)
    value = start + round((value - start) / scan.step) * scan.step
    return _write(scan, min(max(float(_num(value)), start), end))


def slider_position(scan: Scan, text: str) -> float | None:
    """Where the slider stands for the field's ``text`` (``None``: the field refuses it)."""
    try:
        value = scan.read(text)
    except FingerpadError:
        return None
    return value / (1.0 if scan.param.kind == "angle" else scan.factor)
