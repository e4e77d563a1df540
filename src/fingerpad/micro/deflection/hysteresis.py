"""Elliptical (direction-dependent) generalisation of the Greenwood-Tabor hysteresis term, Eq. 2.4.

Derivation
----------
Greenwood and Tabor take the hysteresis friction as the loss fraction beta of the elastic work
fed into the material ahead of the moving contact per unit sliding distance. For a Hertz
contact of semi-axes ``a_x, a_y`` under the gap ``z = x^2/(2 R_x) + y^2/(2 R_y)`` the pressure is
``p = p0 sqrt(1 - x^2/a_x^2 - y^2/a_y^2)``, ``p0 = 3F/(2 pi a_x a_y)``, and the surface inside the
contact is displaced by ``w = delta - x^2/(2R_x) - y^2/(2R_y)``. Sliding along the unit vector
``e = (cos t, sin t)``, the material is being loaded where ``-dw/ds = n . r > 0`` with
``n = (cos t / R_x, sin t / R_y)``, and the work rate per unit distance there is::

    W' = int_{n.r > 0} p (n . r) dA

With ``x = a_x u, y = a_y v`` this is ``a_x a_y p0 |m| int_{half disc} sqrt(1 - rho^2) rho cos(phi)
dA = a_x a_y p0 |m| pi/8`` where ``m = (a_x cos t / R_x, a_y sin t / R_y)``, hence::

    F_def(t) = beta (3/16) F sqrt((a_x cos t / R_x)^2 + (a_y sin t / R_y)^2)          (2.4e)

For ``R_x = R_y = R`` (``a_x = a_y = a``) it is ``beta (3/16) a F / R``, exactly Eq. 2.4 whatever the
direction. The semi-axes follow from Hertz's elliptical contact (:func:`hertz_ellipse`).

Direction factor for a texture
------------------------------
The pad-scale Eq. 2.4 is isotropic (the pad is a sphere). A texture of ellipsoidal asperities
makes the asperity-scale contacts elliptical; :func:`hysteresis_direction_factor` is the ratio of
Eq. 2.4e for one asperity tip (radii ``R_x = a^2/h``, ``R_y = b^2/h``) to the same force on the
sphere of Hertz's equivalent radius ``sqrt(R_x R_y)``. It does not depend on the load (both scale
as ``F^(1/3)``), is exactly 1 for a circular asperity and for a rigid or flat texture, and is what
the coupling multiplies the hysteresis term by when a direction is given. Using an asperity-scale
anisotropy on the pad-scale term is a modelling choice (docs/deflection.md says why and what it
leaves out); parallel ridges have no elliptical contact and get the factor 1.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

from ...errors import FingerpadError


def _ratio(m: float) -> float:
    """B/A of Hertz's gap coefficients for eccentricity^2 = m (a along the flatter axis)."""
    k, e = ellipk(m), ellipe(m)
    return float((e / (1.0 - m) - k) / (k - e))


def hertz_ellipse(load: float, radius_x: float, radius_y: float, modulus: float) -> tuple[float, float]:
    """Semi-axes (a_x, a_y) of the Hertz contact of a body with principal radii R_x, R_y (m) on
    a flat, under the load F (N), with the combined modulus E* (Pa).

    Hertz's elliptical solution (eccentricity ``e^2 = 1 - b^2/a^2`` of the larger semi-axis a,
    which lies along the larger radius): ``B/A = ((a^2/b^2) E(e) - K(e)) / (K(e) - E(e))`` with
    ``A = 1/(2 R_major-axis)``, and ``a^3 = 3 F (K - E) / (2 pi E* e^2 A)``. Circular limit:
    ``a = (3 F R / (4 E*))^(1/3)``.
    """
    for v, name in ((load, "load"), (radius_x, "radius_x"), (radius_y, "radius_y"), (modulus, "modulus")):
        if not (math.isfinite(v) and v > 0):
            raise FingerpadError(f"hertz_ellipse: {name} must be positive and finite, got {v!r}")
    big, small = max(radius_x, radius_y), min(radius_x, radius_y)
    ratio = big / small  # = B/A with A = 1/(2 big)
    if ratio < 1.0 + 1e-5:  # below: circular to 1e-5 (the series in e^2 is ill-conditioned)
        a = (3.0 * load * big / (4.0 * modulus)) ** (1.0 / 3.0)
        return a, a
    m = brentq(lambda mm: _ratio(mm) - ratio, 1e-6, 1.0 - 1e-12, xtol=1e-16, rtol=1e-13)
    k, e = ellipk(m), ellipe(m)
    a = (3.0 * load * (k - e) * 2.0 * big / (2.0 * math.pi * modulus * m)) ** (1.0 / 3.0)
    b = a * math.sqrt(1.0 - m)
    return (a, b) if radius_x >= radius_y else (b, a)


def elliptical_hysteresis_force(
    load: float | np.ndarray, radius_x: float, radius_y: float, modulus: float, beta: float, direction: float
) -> float | np.ndarray:
    """Greenwood-Tabor hysteresis friction of an elliptical Hertz contact sliding at ``direction``
    (radians from x), Eq. 2.4e, N.

    ``F_def = beta (3/16) F sqrt((a_x cos t / R_x)^2 + (a_y sin t / R_y)^2)``; equals Eq. 2.4
    (:func:`fingerpad.friction.hysteresis_force`) when ``radius_x == radius_y``.
    """
    if not (beta >= 0 and math.isfinite(beta)):
        raise FingerpadError("hysteresis needs a non-negative beta")
    f = np.asarray(load, dtype=float)
    if np.any(f < 0) or not np.all(np.isfinite(f)):
        raise FingerpadError("load must be finite and non-negative")
    ax, ay = hertz_ellipse(1.0, radius_x, radius_y, modulus)  # semi-axes scale as F^(1/3)
    m = math.hypot(ax * math.cos(direction) / radius_x, ay * math.sin(direction) / radius_y)
    out = beta * 3.0 / 16.0 * f * np.cbrt(f) * m
    return float(out) if out.ndim == 0 else out


def hysteresis_direction_factor(semi_axis_x: float, semi_axis_y: float, height: float, direction: float) -> float:
    """Anisotropy of the asperity-scale hysteresis of half-ellipsoid asperities, Eq. 2.4e.

    Ratio of Eq. 2.4e for the asperity tip (radii ``R_x = a^2/h``, ``R_y = b^2/h``, sliding at
    ``direction`` radians from the a axis) to Eq. 2.4 for the sphere of the equivalent radius
    ``sqrt(R_x R_y)`` at the same load and modulus (both scale as F^(1/3), so the ratio is a
    number of the shape alone). Exactly 1 for ``a == b``.
    """
    for v, name in ((semi_axis_x, "semi_axis_x"), (semi_axis_y, "semi_axis_y"), (height, "height")):
        if not (math.isfinite(v) and v > 0):
            raise FingerpadError(f"{name} must be positive, got {v!r}")
    if semi_axis_x == semi_axis_y:
        return 1.0
    return _tip_factor(semi_axis_x**2 / height, semi_axis_y**2 / height, direction)


def geometry_hysteresis_factor(geometry: object, direction_deg: float) -> float:
    """:func:`hysteresis_direction_factor` of a compliant-asperity geometry (the texture family's
    ``deflection`` hook) sliding at ``direction_deg`` (degrees from x): 1 where its tip contact is
    not elliptical (``tip_radii()`` is ``None``, e.g. parallel ridges)."""
    radii = geometry.tip_radii()  # type: ignore[attr-defined]
    if radii is None:
        return 1.0
    rx, ry, orientation = radii
    return 1.0 if rx == ry else _tip_factor(rx, ry, math.radians(direction_deg) - orientation)


def _tip_factor(rx: float, ry: float, direction: float) -> float:
    """Eq. 2.4e for a tip of principal radii ``rx, ry`` sliding at ``direction`` (radians from the
    ``rx`` axis) over Eq. 2.4 for the sphere of radius ``sqrt(rx ry)``."""
    ax, ay = hertz_ellipse(1.0, rx, ry, 1.0)
    req = math.sqrt(rx * ry)
    aeq = (3.0 * req / 4.0) ** (1.0 / 3.0)
    return math.hypot(ax * math.cos(direction) / rx, ay * math.sin(direction) / ry) / (aeq / req)
