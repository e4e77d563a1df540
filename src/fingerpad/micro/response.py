"""What the coupling needs from a unit cell of the texture: psi(p) and its state pressures.

:class:`UnitCellResponse` is the protocol every micro-scale model implements (the BEM cell
:class:`fingerpad.micro.bem.BEMUnitCell`, the analytic :class:`fingerpad.micro.hertz.HertzUnitCell`,
the test cell :class:`PowerLawUnitCell`). The helpers here check a response and solve for the
load at which a pad quantity reaches a cell pressure.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np

from ..checks import positive
from ..errors import FingerpadError

__all__ = ["DEFAULT_LOAD_RANGE", "PowerLawUnitCell", "RidgeArea", "UnitCellResponse", "area_function",
           "check_cell", "checked_psi", "solve_load"]

#: Load bracket (N) searched for critical and full-contact loads. Far wider than the 0.1-4 N of
#: touch on purpose: a load is found wherever the cell's state pressure puts it, and a load
#: beyond what a finger exerts is reported as such, not as "none".
DEFAULT_LOAD_RANGE = (1e-9, 1e9)

#: A ridge contact area: a constant (m^2) or a callable of the load ``F -> A_fr(F)``.
RidgeArea = float | Callable[[float], float]


def area_function(ridge_area: RidgeArea) -> Callable[[float], float]:
    """Turn a constant or a callable ``A_fr(F)`` into a checked scalar callable."""
    if callable(ridge_area):
        def area(f: float) -> float:
            value = float(np.asarray(ridge_area(f)))  # type: ignore[operator]
            if not (math.isfinite(value) and value > 0):
                raise FingerpadError(f"ridge area A_fr({f:.4g} N) = {value!r} is not a positive area")
            return value

        return area
    const = positive(ridge_area, "ridge area")
    return lambda f: const


def solve_load(
    residual: Callable[[float], float],
    load_range: tuple[float, float],
    what: str,
    detail: Callable[[float, float], str],
) -> float:
    """Root of ``residual`` in ``load_range`` by Brent's method, or a FingerpadError."""
    lo, hi = (float(x) for x in load_range)
    if not (0 < lo < hi and math.isfinite(hi)):
        raise FingerpadError(f"load range must satisfy 0 < low < high, got {load_range!r}")
    g_lo, g_hi = residual(lo), residual(hi)
    if g_lo == 0:
        return lo
    if g_hi == 0:
        return hi
    if np.sign(g_lo) == np.sign(g_hi):
        raise FingerpadError(f"no {what} between {lo:.3g} N and {hi:.3g} N: {detail(lo, hi)}")
    from scipy.optimize import brentq  # here, not at the top: scipy.optimize takes ~0.3 s to import

    # Relative tolerance at the float limit: tests compare with Eq. 3.6 to ~1e-12.
    return float(brentq(residual, lo, hi, xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=500))


@runtime_checkable
class UnitCellResponse(Protocol):
    """Response of one periodic texture unit cell to a nominal mean pressure.

    Attributes
    ----------
    transition_pressure
        Local nominal mean pressure (Pa) at which the skin first touches the texture's base.
    full_contact_pressure
        Pressure (Pa) from which the skin follows the whole texture (``psi`` constant); may be
        ``inf``.

    Both may be plain attributes or read-only properties.

    Notes
    -----
    An implementation may also define ``breakpoints``: a sequence of further pressures where
    ``psi`` has kinks; :func:`couple` splits its quadrature there for accuracy.
    """

    @property
    def transition_pressure(self) -> float: ...

    @property
    def full_contact_pressure(self) -> float: ...

    def contact_fraction(self, p: np.ndarray) -> np.ndarray:
        """psi(p): real-to-nominal area fraction of the cell at nominal mean pressure ``p`` (Pa)."""
        ...



@dataclass(frozen=True)
class PowerLawUnitCell:
    """Test cell ``psi = min(1, c p^m)``.

    Full contact at ``p_full = c^(-1/m)``; the transition at ``transition`` (Pa, default
    ``p_full``).

    Attributes
    ----------
    coefficient
        c, Pa^-m.
    exponent
        m.
    transition
        Transition pressure, Pa, or ``None`` for ``p_full``.
    """

    coefficient: float
    exponent: float
    transition: float | None = None

    def __post_init__(self) -> None:
        positive(self.coefficient, "coefficient c")
        positive(self.exponent, "exponent m")
        if self.transition is not None:
            t = positive(self.transition, "transition pressure")
            if t > self.full_contact_pressure:
                raise FingerpadError("transition pressure must not exceed the full-contact pressure")

    @property
    def full_contact_pressure(self) -> float:
        """``c^(-1/m)``, where psi reaches 1, Pa."""
        return self.coefficient ** (-1.0 / self.exponent)

    @property
    def transition_pressure(self) -> float:
        return self.full_contact_pressure if self.transition is None else float(self.transition)

    def contact_fraction(self, p: np.ndarray) -> np.ndarray:
        pp = np.clip(np.asarray(p, dtype=float), 0.0, None)
        return np.minimum(self.coefficient * pp**self.exponent, 1.0)


#: Classes that define every member of :class:`UnitCellResponse` themselves: their instances
#: pass the protocol's isinstance check, which costs ~20 us per call (a population checks a
#: cell per member, twice).
_CELL_TYPES: set[type] = set()


def _is_cell(cell: Any) -> bool:
    """``isinstance(cell, UnitCellResponse)``, remembered per class when the class itself has
    the protocol's members."""
    kind = type(cell)
    if kind in _CELL_TYPES:
        return True
    ok = isinstance(cell, UnitCellResponse)
    if ok and all(hasattr(kind, name) for name in ("contact_fraction", "transition_pressure", "full_contact_pressure")):
        _CELL_TYPES.add(kind)
    return ok


def check_cell(cell: Any) -> tuple[float, float, tuple[float, ...]]:
    """Transition and full-contact pressures of ``cell`` (Pa) and the kinks of its psi, checked."""
    if not _is_cell(cell):
        raise FingerpadError(
            f"{type(cell).__name__} is not a unit-cell response (needs contact_fraction, "
            "transition_pressure, full_contact_pressure)"
        )
    pt, pf = float(cell.transition_pressure), float(cell.full_contact_pressure)
    # 0 is allowed: a flat cell (BEMUnitCell on a flat texture) is in full contact at any pressure.
    if not (pt >= 0 and pf >= 0) or math.isnan(pt) or math.isnan(pf):
        raise FingerpadError(f"unit cell pressures must not be negative (transition {pt!r}, full {pf!r})")
    if pf < pt:
        raise FingerpadError(f"unit cell full-contact pressure {pf:.4g} Pa is below its transition {pt:.4g} Pa")
    extra = tuple(float(b) for b in getattr(cell, "breakpoints", ()) or ())
    return pt, pf, (pt, pf, *extra)


def checked_psi(cell: UnitCellResponse) -> Callable[[np.ndarray], np.ndarray]:
    """``cell.contact_fraction`` wrapped so that a bad array is a FingerpadError, not a wrong number."""
    def psi(p: np.ndarray) -> np.ndarray:
        out = np.asarray(cell.contact_fraction(p), dtype=float)
        if out.shape != np.shape(p) or not np.all(np.isfinite(out)):
            raise FingerpadError(f"{type(cell).__name__}.contact_fraction returned a bad array")
        if np.any(out < -1e-9) or np.any(out > 1.0 + 1e-9):
            raise FingerpadError(f"{type(cell).__name__}.contact_fraction returned values outside [0, 1]")
        return np.clip(out, 0.0, 1.0)

    return psi


# ---------------------------------------------------------------------------------------------
# coupling
# ---------------------------------------------------------------------------------------------

