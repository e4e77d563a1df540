"""Friction of the finger pad: the friction laws, the flat reference, power-law fits (thesis ch. 2.1).

A friction law turns the load and the real contact area into a friction force. Each law is one
file of this package declaring ``LAWS = (LawSpec(...),)`` (:class:`~._base.LawSpec`: its name, how
it is built from a finger's fields); this package finds them (:data:`FRICTION_LAWS`) and a finger
names its law (``[finger] friction_law``, :attr:`fingerpad.finger.Finger.friction`). Every user
asks the finger's law: the coupling (:func:`mu_checked`), the members' coupling of a population,
the deflection model of compliant asperities (:meth:`~._base.FrictionLaw.affine_shear`), the flat
reference. Laws:

* :mod:`.thesis` - the thesis's law: adhesion ``(tau0 + alpha p_re) A_re`` plus Greenwood-Tabor
  hysteresis, Eqs. 2.1-2.4 (the default, ``"thesis"``).

Helpers: :mod:`._base` (the protocol), :mod:`.power_law` (``mu = k F^(n-1)`` fits,
:func:`fit_power_law`). The functions below keep the thesis's equations callable with explicit
parameters (:func:`shear_strength`, :func:`adhesion_force`, :func:`hysteresis_force`) and apply a
finger's law (:func:`friction_force`, :func:`friction_coefficient`, ...).

SI units (m, N, Pa). Load arguments accept floats or arrays.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..checks import ArrayLike, as_loads, scalar_out
from ..errors import FingerpadError
from ._base import FrictionLaw, LawSpec
from .power_law import PowerLaw, PowerLawFit, fit_inputs, fit_power_law
from .thesis import adhesion_term, hysteresis_term

if TYPE_CHECKING:
    from ..finger import Finger

#: Modules of this package that declare no law.
HELPER_MODULES = frozenset({"power_law"})

#: Friction laws by name (``[finger] friction_law``), filled by :func:`discover_laws`.
FRICTION_LAWS: dict[str, LawSpec] = {}


def discover_laws() -> dict[str, LawSpec]:
    """Find the laws declared by this package's files (``LAWS`` of each module, helpers
    excepted) and fill :data:`FRICTION_LAWS`; run on import.

    Raises
    ------
    fingerpad.discover.DiscoveryError
        A module that declares no ``LAWS``.
    """
    from ..discover import fill_registry

    return fill_registry(FRICTION_LAWS, __name__, __path__, "LAWS", LawSpec, skip=HELPER_MODULES,
                         what="friction law")


discover_laws()

#: The default law (the thesis's).
DEFAULT_LAW = "thesis"
#: The publications of the default law (:mod:`fingerpad.references` keys; each law declares its
#: own as ``REFERENCES``, which the outputs cite through :attr:`fingerpad.finger.Finger.friction`).
REFERENCES = ("greenwood1958",)


def law_of(finger: Any) -> FrictionLaw:
    """The friction law a finger names (``finger.friction_law``), built from its fields."""
    name = getattr(finger, "friction_law", DEFAULT_LAW)
    spec = FRICTION_LAWS.get(name)
    if spec is None:
        raise FingerpadError(f"unknown friction law {name!r}; choose one of: {', '.join(FRICTION_LAWS)}")
    return spec.build(finger)


def _areas(value: ArrayLike, name: str) -> np.ndarray:
    arr = as_loads(value, name)
    if np.any(arr <= 0):
        raise FingerpadError(f"{name} must be positive")
    return arr


def shear_strength(real_pressure: ArrayLike, tau0: float, alpha: float) -> float | np.ndarray:
    """Interfacial shear strength ``tau = tau0 + alpha p_re``, Eq. 2.3 (Pa)."""
    p = as_loads(real_pressure, "real contact pressure")
    return scalar_out(tau0 + alpha * p)


def adhesion_force(load: ArrayLike, real_area: ArrayLike, tau0: float, alpha: float) -> float | np.ndarray:
    """Adhesive friction ``F_adh = tau A_re``, Eqs. 2.2-2.3 (N).

    With ``p_re = F / A_re`` the pressure term integrates to ``alpha F`` whatever the area, so
    ``F_adh = tau0 A_re + alpha F``.

    Parameters
    ----------
    load
        Normal load F, N.
    real_area
        Real contact area A_re, m^2.
    tau0, alpha
        Shear strength at zero pressure (Pa) and its pressure coefficient.
    """
    return scalar_out(adhesion_term(as_loads(load, strict=True), _areas(real_area, "real contact area"), tau0, alpha))


def hysteresis_force(load: ArrayLike, radius: float, modulus: float, beta: float) -> float | np.ndarray:
    """Viscoelastic hysteresis friction (Greenwood-Tabor), Eq. 2.4 (N).

    ``F_def = beta (9 / (128 R))^(2/3) (F^4 / E0*)^(1/3)``, identical to
    ``beta (3/16) a F / R`` with the Hertz contact radius ``a = (3 F R / (4 E0*))^(1/3)``.

    Parameters
    ----------
    load
        Normal load F, N.
    radius
        Pad radius R_fp, m.
    modulus
        Pad reduced modulus E0* (= E_fp*), Pa.
    beta
        Viscoelastic loss fraction.
    """
    if not (radius > 0 and modulus > 0 and beta >= 0):
        raise FingerpadError("hysteresis needs a positive radius and modulus and a non-negative beta")
    return scalar_out(hysteresis_term(as_loads(load), radius, modulus, beta))


def friction_force(load: ArrayLike, real_area: ArrayLike, finger: Finger) -> float | np.ndarray:
    """Total friction force ``F_f`` (N), Eq. 2.1, by ``finger``'s law."""
    return scalar_out(law_of(finger).friction(as_loads(load, strict=True), _areas(real_area, "real contact area")))


def friction_coefficient(load: ArrayLike, real_area: ArrayLike, finger: Finger) -> float | np.ndarray:
    """Friction coefficient ``mu = F_f / F`` (Eq. 2.1 over the load)."""
    f = as_loads(load, strict=True)
    return scalar_out(law_of(finger).friction(f, _areas(real_area, "real contact area")) / f)


def reference_real_area(load: ArrayLike, finger: Finger) -> float | np.ndarray:
    """Real contact area on the flat reference sample: the skin fully touches a smooth flat, so
    ``A_re,ref = A_fr`` (the ridge contact)."""
    return finger.ridge_area(as_loads(load, strict=True))


def reference_friction_coefficient(load: ArrayLike, finger: Finger) -> float | np.ndarray:
    """``mu_ref(F)`` on the flat reference sample of the same material."""
    f = as_loads(load, strict=True)
    return scalar_out(mu_checked(f, finger.areas_checked(f)[1], finger))  # A_re,ref = A_fr


def mu_checked(f: np.ndarray, real_area: np.ndarray, finger: Finger) -> np.ndarray:
    """``mu = F_f / F`` by the finger's law on loads (> 0) and real areas already checked: the
    path of :func:`fingerpad.coupling.predict_curve` and the members' coupling, which check their
    loads once at their entry."""
    return law_of(finger).friction(f, real_area) / f


def mu_stacked(f: np.ndarray, real_area: np.ndarray, fingers: Any) -> np.ndarray:
    """:func:`mu_checked` of many fingers at once (``f``, ``real_area``: ``(fingers, loads)``
    arrays, row ``i`` that of ``fingers[i]``), each entry the bits of ``mu_checked`` of its finger:
    fingers whose laws are all of one class with a ``friction_of_many`` (the thesis's law) in one
    evaluation, any others row by row by their own law."""
    laws = [law_of(finger) for finger in fingers]
    kind = type(laws[0]) if laws else None
    many = getattr(kind, "friction_of_many", None)
    if many is not None and all(type(law) is kind for law in laws):
        return many(laws, f, real_area) / f
    return np.array([law.friction(f[i], real_area[i]) / f[i] for i, law in enumerate(laws)])


def normalised_friction(mu_texture: ArrayLike, mu_reference: ArrayLike) -> float | np.ndarray:
    """``mu_tex / mu_ref`` (docs/model.md "Normalisation").

    With the same shear strength on both samples and negligible hysteresis this equals
    ``A_re,tex / A_re,ref``, so the person's unknown ridge-area function cancels.
    """
    mt = np.asarray(mu_texture, dtype=float)
    mr = np.asarray(mu_reference, dtype=float)
    if not (np.all(np.isfinite(mt)) and np.all(np.isfinite(mr))) or np.any(mr <= 0):
        raise FingerpadError("normalisation needs finite friction coefficients and a positive reference")
    return scalar_out(mt / mr)


__all__ = [
    "DEFAULT_LAW",
    "REFERENCES",
    "FRICTION_LAWS",
    "FrictionLaw",
    "LawSpec",
    "PowerLaw",
    "PowerLawFit",
    "adhesion_force",
    "discover_laws",
    "fit_inputs",
    "fit_power_law",
    "friction_coefficient",
    "friction_force",
    "hysteresis_force",
    "law_of",
    "mu_checked",
    "mu_stacked",
    "normalised_friction",
    "reference_friction_coefficient",
    "reference_real_area",
    "shear_strength",
]
