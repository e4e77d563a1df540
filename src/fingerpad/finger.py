"""The finger: one person's pad (macro), fingerprint ridges (meso) and skin/interface parameters.

The finger pad is a sphere of radius ``R_fp`` and reduced modulus ``E_fp*`` pressed on a flat
(docs/model.md, ch. 2.2.1); its gross contact ``A_g`` is covered in part by the fingerprint ridges,
whose contact ``A_fr`` (ch. 2.2.2) is the nominal area seen by the micro scale (ch. 3.2).

Two small interfaces, so that new models plug in without touching callers:

* :class:`GrossAreaModel` -- ``area(load) -> A_g``;
* :class:`RidgeAreaModel` -- ``area(load, gross_area) -> A_fr``.

A :class:`Finger` bundles one person's parameters; :data:`FINGER_PRESETS` holds named fingers.
SI units throughout (m, N, Pa).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .checks import ArrayLike, as_loads, scalar_out
from .contact.layered import Layer
from .errors import FingerpadError
from .macro import GROSS_MODELS, DzidekArea, GrossAreaModel, HertzArea, PowerLawArea, TwoRegimePowerLawArea
from .macro._base import PAD_MODULUS, PAD_RADIUS
from .macro.pressure import disc_average, pad_pressure
from .contact.interaction import INTERACTION_LAWS
from .friction import DEFAULT_LAW, FRICTION_LAWS, FrictionLaw, law_of
from .materials import DEFAULT_SKIN_MODULUS, DEFAULT_SKIN_POISSON, reduced_modulus
from .meso import (
    RIDGE_MODELS,
    CircularRidges,
    ConstantFractionRidges,
    FingerprintBEMRidges,
    PowerLawRidges,
    RidgeAreaModel,
    SinusoidalRidges,
)
from .params import Param, check_fields

#: The adhesion laws by name (the first the default) and the physical range of skin's adhesion (m):
#: an intermolecular distance, z0 ~ 0.3 nm (Tabor 1977).
ADHESION_LAWS = tuple(INTERACTION_LAWS)
ADHESION_RANGE = 0.3e-9

#: Skin structures: the homogeneous half-space of E_s (the default) or a layer on a substrate.
SKINS = ("half-space", "layered")
#: What a layered skin's layer rests on: the elastic tissue (E_2, nu_2) or a rigid base.
SKIN_BASES = ("elastic", "rigid", "rigid-frictionless")

#: The finger's own numeric fields, declared once (kind and unit, bounds, default, meaning): the
#: study file's ``[finger]`` keys, ``--finger-param NAME=VALUE``, the sweep axes of the finger,
#: the explorer's finger fields and ``fingerpad fingers`` are derived from them.
FINGER_PARAMS: tuple[Param, ...] = (
    PAD_RADIUS,
    PAD_MODULUS,
    Param("beta", "ratio", "viscoelastic hysteresis loss fraction, Eq. 2.4", 0.1, low=0, high=1,
          label="hysteresis loss fraction beta", symbol="beta"),
    Param("tau0", "pressure", "interfacial shear strength at zero pressure, Eq. 2.3", 8.1e3, low=0,
          label="shear strength tau0", symbol="tau0"),
    Param("alpha", "ratio", "pressure coefficient of the shear strength, Eq. 2.3", 0.1, low=0,
          label="pressure coefficient alpha", symbol="alpha"),
    Param("skin_modulus", "pressure", "micro-scale skin modulus E_s, Eq. 3.4 (thesis: 0.2-0.5 MPa)",
          DEFAULT_SKIN_MODULUS, low=0, low_open=True, label="skin modulus E_s", plausible="skin modulus",
          symbol="E_s"),
    Param("skin_poisson", "ratio", "skin Poisson ratio (docs/model.md: 0.48-0.5)", DEFAULT_SKIN_POISSON,
          low=-1, low_open=True, high=0.5, label="skin Poisson ratio", symbol="nu_s"),
    # A layered skin (docs/model.md, section 6.4 and "A layered finger"): the stratum corneum as an
    # elastic layer bonded to the tissue under it. The layer's modulus is then E_s (skin_modulus),
    # its Poisson ratio skin_poisson.
    Param("skin", "choice", "skin structure: half-space (homogeneous E_s) or layered (a layer on the tissue)",
          "half-space", SKINS, label="skin structure", symbol="skin"),
    Param("skin_layer_thickness", "length", "layered skin: thickness t of the outer layer (stratum corneum, "
          "thesis ch. 1.2: 0.2-0.35 mm); typed with a unit", None, low=0, low_open=True, high=10e-3, example="300um",
          label="skin layer thickness t", symbol="t", needs_unit=True),
    Param("skin_layer_modulus", "pressure", "layered skin: Young's modulus E_1 of the outer layer (it is E_s)",
          None, low=0, low_open=True, example="0.4MPa", label="skin layer modulus E_1",
          plausible="skin layer modulus", symbol="E_1"),
    Param("skin_substrate_modulus", "pressure", "layered skin: Young's modulus E_2 of the tissue under the layer",
          None, low=0, low_open=True, example="40kPa", label="skin substrate modulus E_2",
          plausible="skin substrate modulus", symbol="E_2"),
    Param("skin_substrate_poisson", "ratio", "layered skin: Poisson ratio nu_2 of the tissue (default: skin_poisson)",
          None, low=-1, low_open=True, high=0.5, label="skin substrate Poisson ratio", symbol="nu_2"),
    Param("skin_base", "choice", "layered skin: what the layer rests on: elastic (the tissue, E_2), rigid (bonded) "
          "or rigid-frictionless", "elastic", SKIN_BASES, label="skin layer base", symbol="base"),
    # Adhesion (docs/model.md 6.6, 7.6): the work of adhesion of the skin on the counter-surface
    # where they touch. 0 (the default) is the non-adhesive model, exactly. A dry finger's is at
    # most ~0.3-0.4 J/m^2 (an upper bound from a whole finger's 15 mN pull-off on smooth epoxy,
    # Spinner et al. 2016), none measurable on clean glass (Tiwari, Wang, Persson 2020).
    Param("work_of_adhesion", "surface energy", "work of adhesion w of skin on the texture's material "
          "(0: no adhesion; a dry finger's is at most ~0.3-0.4 J/m2, docs/model.md 6.6)", 0.0, low=0, high=10.0,
          example="0.05J/m2", label="work of adhesion w", symbol="w"),
    Param("adhesion_range", "length", "range rho of the adhesive interaction (physical: ~0.3 nm; regularised to "
          "the grid in the JKR limit, docs/model.md 6.6); typed with a unit", ADHESION_RANGE, low=0, low_open=True,
          high=1e-3, example="0.3nm", label="adhesion range rho", symbol="rho", needs_unit=True),
    Param("adhesion_law", "choice", "adhesive interaction law: exponential (smooth) or maugis (Maugis-Dugdale, a "
          "constant attraction within the range)", ADHESION_LAWS[0], ADHESION_LAWS, label="adhesion law",
          symbol="law"),
    # The friction law (fingerpad.friction: one file per law): the thesis's tau0 + alpha p_re
    # adhesion plus hysteresis reads tau0, alpha, beta and the pad's radius and modulus.
    Param("friction_law", "choice", "friction law (fingerpad.friction): thesis = adhesion (tau0 + alpha p) on A_re "
          "plus hysteresis, Eqs. 2.1-2.4", DEFAULT_LAW, tuple(FRICTION_LAWS), label="friction law",
          symbol="friction"),
)

#: The adhesion's fields (omitted from descriptions of a finger without adhesion).
ADHESION_FIELDS = ("work_of_adhesion", "adhesion_range", "adhesion_law")

#: ``--finger-param ridge_fraction=X``: the constant-fraction ridge model with ``A_fr / A_g = X``
#: (replaces the finger's ridge model; a population's members are named by it, issue 22). Not a
#: field of :class:`Finger` but the parameter of one ridge model, declared here beside the fields
#: for ``--finger-param`` (:mod:`fingerpad.study.overrides`) and populations.
RIDGE_FRACTION = Param("ridge_fraction", "ratio", "constant-fraction ridge model's A_fr/A_g (model.md: 10-70 %)",
                       0.5, low=0, low_open=True, high=1, label="ridge fraction A_fr/A_g", symbol="A_fr/A_g")
#: The fields that describe a layered skin's layer (``None`` on a half-space skin).
LAYER_FIELDS = ("skin_layer_thickness", "skin_layer_modulus", "skin_substrate_modulus", "skin_substrate_poisson")


def describe_skin(values: Mapping[str, Any]) -> str:
    """One line naming a layered skin from its fields in SI (``values``: a finger's
    :meth:`Finger.as_dict`, or solve's materials), e.g. ``"skin: layered, t 300 um, E_1 400 kPa
    on E_2 40 kPa"``; ``""`` for a half-space skin (tables stay as they were)."""
    if values.get("skin") != "layered":
        return ""
    by_name = {p.name: p for p in FINGER_PARAMS}

    def show(name: str) -> str:
        value = values.get(name)
        if value is None or isinstance(value, str):
            return str(value)
        return by_name[name].format(value)

    base = values.get("skin_base", "elastic")
    under = f"E_2 {show('skin_substrate_modulus')}" if base == "elastic" else f"a {base} base"
    return f"skin: layered, t {show('skin_layer_thickness')}, E_1 {show('skin_layer_modulus')} on {under}"


def skin_units() -> dict[str, str]:
    """The SI units of a layered skin's fields as outputs record them (``{"skin_layer_thickness":
    "m", "skin_layer_modulus": "Pa", ...}``), read from their declarations; outputs of a
    half-space skin do not carry them (their files stay as they were)."""
    by_name = {p.name: p for p in FINGER_PARAMS}
    return {n: by_name[n].unit for n in ("skin_modulus", "skin_poisson", *LAYER_FIELDS)}

#: Dimension of each declared finger field (derived from :data:`FINGER_PARAMS`).
FINGER_FIELDS: dict[str, str] = {p.name: p.dimension for p in FINGER_PARAMS}


def finger_param(name: str) -> Param:
    """The declaration of the finger field ``name``.

    Raises
    ------
    FingerpadError
        No finger field has that name (listing those there are).
    """
    found = next((p for p in FINGER_PARAMS if p.name == name), None)
    if found is None:
        raise FingerpadError(f"unknown finger parameter {name!r} (finger parameters: "
                             f"{', '.join(p.name for p in FINGER_PARAMS)})")
    return found


@dataclass(frozen=True)
class Finger:
    """One person's finger pad: macro, meso and interface parameters (SI units).

    Attributes
    ----------
    radius
        Equivalent pad radius R_fp, m (Eqs. 2.4, 2.5).
    modulus
        Pad reduced modulus E_fp*, Pa (Eqs. 2.4, 2.5).
    ridges
        Ridge-area model (:class:`RidgeAreaModel`).
    gross
        Gross-area model; ``None`` means Hertz (Eq. 2.5) with ``radius`` and ``modulus``. A model
        with its own ``radius``/``modulus`` (Hertz, Dzidek) must agree with the finger's.
    beta
        Viscoelastic hysteresis loss fraction, Eq. 2.4, in [0, 1].
    tau0
        Interfacial shear strength at zero pressure, Pa, Eq. 2.3.
    alpha
        Pressure coefficient of the shear strength, Eq. 2.3.
    skin_modulus
        Effective micro-scale skin modulus E_s, Pa (thesis: 0.2-0.5 MPa), used in Eq. 3.4.
    skin_poisson
        Skin Poisson ratio (docs/model.md: 0.48-0.5); the layer's nu_1 with a layered skin.
    skin
        ``"half-space"`` (the homogeneous skin of E_s, the default) or ``"layered"``: an elastic
        layer (stratum corneum) bonded to the tissue or to a rigid base (docs/model.md, 6.4).
    skin_layer_thickness, skin_layer_modulus
        Layered skin: the layer's thickness t (m) and Young's modulus E_1 (Pa). E_1 is the skin's
        modulus at short wavelengths, so ``skin_modulus`` is set to it (Eq. 3.4 uses E_1).
    skin_substrate_modulus, skin_substrate_poisson
        Layered skin on an elastic base: the tissue's E_2 (Pa) and nu_2 (default ``skin_poisson``).
    skin_base
        ``"elastic"`` (the tissue), ``"rigid"`` (bonded) or ``"rigid-frictionless"``.
    work_of_adhesion
        Work of adhesion w of the skin on the texture's material, J/m^2 (docs/model.md 6.6); 0,
        the default, is the non-adhesive model.
    adhesion_range
        Range rho of the interaction, m (physical ~0.3 nm; regularised to the grid in the JKR
        limit).
    adhesion_law
        ``"exponential"`` or ``"maugis"`` (Maugis-Dugdale).
    friction_law
        The friction law's name (:data:`fingerpad.friction.FRICTION_LAWS`; ``"thesis"``, Eqs.
        2.1-2.4); :attr:`friction` is the law built from this finger's fields.
    name, description
        Labels.
    """

    radius: float = 9e-3
    modulus: float = 40e3
    ridges: RidgeAreaModel = ConstantFractionRidges(0.5)
    gross: GrossAreaModel | None = None
    beta: float = 0.1
    tau0: float = 8.1e3
    alpha: float = 0.1
    skin_modulus: float = DEFAULT_SKIN_MODULUS
    skin_poisson: float = DEFAULT_SKIN_POISSON
    skin: str = "half-space"
    skin_layer_thickness: float | None = None
    skin_layer_modulus: float | None = None
    skin_substrate_modulus: float | None = None
    skin_substrate_poisson: float | None = None
    skin_base: str = "elastic"
    work_of_adhesion: float = 0.0
    adhesion_range: float = ADHESION_RANGE
    adhesion_law: str = ADHESION_LAWS[0]
    friction_law: str = DEFAULT_LAW
    name: str = "custom"
    description: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        check_fields(self, FINGER_PARAMS)
        self._check_skin()
        if not isinstance(self.ridges, RidgeAreaModel):
            raise FingerpadError(f"ridges must be a ridge-area model with area(load, gross_area), got {self.ridges!r}")
        if self.gross is not None:
            if not isinstance(self.gross, GrossAreaModel):
                raise FingerpadError(f"gross must be a gross-area model with area(load), got {self.gross!r}")
            # Eq. 2.4 uses R_fp and E_fp*: a Hertz-type gross model must not contradict them.
            for attr in ("radius", "modulus"):
                own = getattr(self.gross, attr, None)
                if own is not None and not math.isclose(own, getattr(self, attr), rel_tol=1e-12):
                    raise FingerpadError(
                        f"gross-area model {attr} {own:.6g} differs from the finger's {getattr(self, attr):.6g}"
                    )

    def _check_skin(self) -> None:
        """The layered skin's fields given exactly when the skin is layered; E_s := E_1; the ridge
        model told the layer (:meth:`layer`) when it has a use for it."""
        given = [n for n in LAYER_FIELDS if getattr(self, n) is not None]
        if self.skin == "half-space":
            if given or self.skin_base != "elastic":
                names = ", ".join(given or ["skin_base"])
                raise FingerpadError(f"{names}: a layer needs skin = layered (the skin is a half-space)")
            return
        rigid = self.skin_base != "elastic"
        need = ["skin_layer_thickness", "skin_layer_modulus", *(() if rigid else ("skin_substrate_modulus",))]
        missing = [n for n in need if getattr(self, n) is None]
        if missing:
            raise FingerpadError(f"a layered skin needs {', '.join(need)}: {', '.join(missing)} missing")
        extra = [n for n in ("skin_substrate_modulus", "skin_substrate_poisson") if rigid and getattr(self, n) is not None]
        if extra:
            raise FingerpadError(f"{', '.join(extra)}: the layer rests on a rigid base (skin_base = {self.skin_base})")
        # the layer is the skin's surface: its modulus is the micro scale's E_s (Eq. 3.4)
        object.__setattr__(self, "skin_modulus", self.skin_layer_modulus)
        with_layer = getattr(self.ridges, "with_layer", None)
        if with_layer is not None:
            object.__setattr__(self, "ridges", with_layer(self.layer))

    @property
    def layer(self) -> Layer | None:
        """The layered skin as a :class:`~fingerpad.contact.layered.Layer` (E_1 = E_s, nu_1 =
        nu_s); ``None`` for the half-space skin."""
        if self.skin == "half-space":
            return None
        rigid = self.skin_base != "elastic"
        nu2 = self.skin_substrate_poisson if self.skin_substrate_poisson is not None else self.skin_poisson
        return Layer(float(self.skin_layer_thickness), float(self.skin_layer_modulus), self.skin_poisson,  # type: ignore[arg-type]
                     math.inf if rigid else float(self.skin_substrate_modulus), nu2,  # type: ignore[arg-type]
                     "frictionless" if self.skin_base == "rigid-frictionless" else "bonded")

    @property
    def gross_model(self) -> GrossAreaModel:
        """The gross-area model in use (Hertz with R_fp, E_fp* unless ``gross`` is set)."""
        return self.gross if self.gross is not None else HertzArea(self.radius, self.modulus)

    def gross_area(self, load: ArrayLike) -> float | np.ndarray:
        """Gross contact area A_g (m^2)."""
        return self.gross_model.area(load)

    def ridge_area(self, load: ArrayLike) -> float | np.ndarray:
        """Ridge contact area A_fr (m^2); a callable of the load, as Eq. 3.6 needs."""
        return scalar_out(self.areas_checked(as_loads(load))[1])

    def areas_checked(self, load: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(A_g, A_fr)`` (m^2) at loads already checked (a float array >= 0, e.g. from
        :func:`fingerpad.checks.as_loads`): the path of the prediction job, which checks its
        loads once at its entry. The models' ``area_checked`` is used where they define it
        (every model of the package does); a model of one's own needs only ``area``."""
        gross = _model_area(self.gross_model, load)
        f, ag = np.broadcast_arrays(load, gross)
        return gross, _model_area(self.ridges, f, ag)

    def ridge_area_law(self) -> Callable[[Any], np.ndarray]:
        """``F -> A_fr(F)`` (m^2) on loads already checked, with the gross-area model built once:
        the numbers of :meth:`areas_checked`, for root finders that call it many times (the
        critical load of every member of a population)."""
        gross_model, ridges = self.gross_model, self.ridges

        def area(load: Any) -> np.ndarray:
            f = np.asarray(load, dtype=float)
            ag = _model_area(gross_model, f)
            # the same arrays without np.broadcast_arrays when the shapes agree (a root finder's
            # scalar load: most of the per-call cost was that function)
            if ag.shape != f.shape:
                f, ag = np.broadcast_arrays(f, ag)
            return _model_area(ridges, f, ag)

        return area

    def ridge_radius(self, load: ArrayLike) -> float | np.ndarray:
        """Radius of the ridge contact disc ``a_fr = sqrt(A_fr/pi)``, Eq. 3.7, m."""
        return scalar_out(np.sqrt(np.asarray(self.ridge_area(load)) / math.pi))

    def micro_modulus(self, material_modulus: float | None = None, material_poisson: float = 0.35) -> float:
        """Combined skin/texture modulus E1* (Pa), Eq. 3.4; ``None`` = rigid texture."""
        return reduced_modulus(self.skin_modulus, self.skin_poisson, material_modulus, material_poisson)

    def with_overrides(self, **kwargs: Any) -> Finger:
        """Return a copy with some fields replaced.

        Numeric fields also accept strings with units (``radius="9mm"``). Changing ``radius`` or
        ``modulus`` also updates a Hertz/Dzidek ``gross`` model so the two stay consistent.

        Raises
        ------
        FingerpadError
            For an unknown field name or an invalid value.
        """
        names = [f.name for f in dataclasses.fields(self)]
        unknown = sorted(set(kwargs) - set(names))
        if unknown:
            raise FingerpadError(f"unknown finger parameter(s) {', '.join(unknown)}; known: {', '.join(names)}")
        values = dict(kwargs)
        for par in FINGER_PARAMS:
            if isinstance(values.get(par.name), str):
                values[par.name] = par.parse(values[par.name], par.name)
        self._layered_overrides(values)
        gross = values.get("gross", self.gross)
        sync = {k: values[k] for k in ("radius", "modulus") if k in values}
        if sync and "gross" not in values and gross is not None and dataclasses.is_dataclass(gross):
            own = {k: v for k, v in sync.items() if hasattr(gross, k)}
            if own:
                try:
                    values["gross"] = dataclasses.replace(gross, **own)
                except TypeError as exc:
                    raise FingerpadError(f"bad finger parameter: {exc}") from None
        try:
            return dataclasses.replace(self, **values)
        except TypeError as exc:  # e.g. arithmetic on a wrong type inside a model
            raise FingerpadError(f"bad finger parameter: {exc}") from None

    def _layered_overrides(self, values: dict[str, Any]) -> None:
        """A layer's field given on a half-space finger makes the skin layered; on a layered skin
        E_s is the layer's modulus, so ``skin_modulus`` sets ``skin_layer_modulus`` (one value,
        given once)."""
        if "skin" not in values and self.skin == "half-space" and any(values.get(n) is not None for n in LAYER_FIELDS):
            values["skin"] = "layered"
        if values.get("skin") == "half-space" and self.skin == "layered":
            self._back_to_half_space(values)
        layered = values.get("skin", self.skin) == "layered"
        if layered and values.get("skin_modulus") is not None:
            e1 = values.get("skin_layer_modulus")
            if e1 is not None and not math.isclose(float(e1), float(values["skin_modulus"]), rel_tol=1e-12):
                raise FingerpadError("a layered skin's E_s is its layer's modulus: give skin_layer_modulus or "
                                     "skin_modulus, not both")
            values["skin_layer_modulus"] = values["skin_modulus"]

    def _back_to_half_space(self, values: dict[str, Any]) -> None:
        """``skin = half-space`` on a layered finger: its layer's fields are cleared (the skin is
        then the homogeneous half-space of the layer's modulus, ``skin_modulus`` = E_1, unless
        given); a layer field given in the same call is still refused by :meth:`_check_skin`.
        A ridge model that took its modulus from the layer (:meth:`with_layer`) cannot be turned
        back (its own modulus is gone): refused unless a ridge model is given with it."""
        for n in LAYER_FIELDS:
            values.setdefault(n, None)
        values.setdefault("skin_base", "elastic")
        if "ridges" not in values and hasattr(self.ridges, "with_layer"):
            raise FingerpadError(
                f"skin = half-space: the ridge model ({type(self.ridges).__name__}) of this layered finger "
                "took its modulus from the layer; give the ridge model again ([finger.ridges]) or start "
                "from a half-space preset")

    def as_dict(self) -> dict[str, Any]:
        """Flat description of the parameters (for file attributes)."""
        return {
            "name": self.name,
            "radius": self.radius,
            "modulus": self.modulus,
            "gross_model": repr(self.gross_model),
            "ridge_model": repr(self.ridges),
            "beta": self.beta,
            "tau0": self.tau0,
            "alpha": self.alpha,
            "skin_modulus": self.skin_modulus,
            "skin_poisson": self.skin_poisson,
            # the layer's keys only with a layer: a half-space finger's description is as it was
            **({} if self.skin == "half-space" else {
                "skin": self.skin, "skin_base": self.skin_base,
                **{n: getattr(self, n) for n in LAYER_FIELDS if getattr(self, n) is not None}}),
            # the adhesion's keys only with adhesion: a non-adhesive finger's description is as it was
            **({n: getattr(self, n) for n in ADHESION_FIELDS} if self.work_of_adhesion > 0 else {}),
            **({} if self.friction_law == DEFAULT_LAW else {"friction_law": self.friction_law}),
        }

    @property
    def friction(self) -> FrictionLaw:
        """The finger's friction law (:mod:`fingerpad.friction`) built from its fields."""
        return law_of(self)

    @property
    def adhesive(self) -> bool:
        """Whether the skin adheres (``work_of_adhesion > 0``)."""
        return self.work_of_adhesion > 0


# Default finger, values and sources (docs/model.md, "Macro", "Meso", "Friction", "Micro"):
#   R_fp = 9 mm        middle of the 7-11 mm equivalent pad radius;
#   E_fp* = 40 kPa     the typical value of the 10-100 kPa range;
#   ridges 50 %        constant fraction after Duvefelt;
#   E_s = 0.3 MPa      inside the 0.2-0.5 MPa micro-scale modulus found by the thesis;
#   nu_s = 0.49        skin Poisson ratio 0.48-0.5;
#   beta = 0.1         assumed: docs/model.md gives no value; friction is "mostly adhesive", so the
#                      hysteresis term is kept small (1.2 % of the load at 1 N);
#   alpha = 0.1        assumed small pressure coefficient (no value in docs/model.md);
#   tau0 = 8.1 kPa     calibrated to dry mu ~ 0.5 on smooth surfaces (docs/model.md): on a flat sample
#                      A_re = A_fr, so mu(F) = tau0 A_fr/F + alpha + beta (3/16) a/R_fp. At 1 N:
#                      a = (3 * 1 * 9e-3 / (4 * 40e3))^(1/3) = 5.53 mm, A_g = 95.9 mm^2,
#                      A_fr = 48.0 mm^2, beta (3/16) a/R = 0.0115, hence
#                      tau0 = (0.5 - 0.1 - 0.0115) / 48.0e-6 = 8.1e3 Pa  ->  mu(1 N) = 0.500.
_DEFAULT = Finger(name="default", description="typical dry finger: R_fp 9 mm, E* 40 kPa, 50 % ridges")

#: Named fingers. Values not listed in a preset's comment are those of "default"; tau0, alpha and
#: beta are kept (interface properties), so mu on a smooth flat at 1 N differs by person:
#: default 0.50, soft 1.24 (wet-like, docs/model.md: > 1), stiff 0.29, stiffening 0.45, ridged 0.50.
FINGER_PRESETS: dict[str, Finger] = {
    "default": _DEFAULT,
    # soft, large pad: the soft/large ends of the documented ranges (E* 10 kPa, R_fp 11 mm).
    "soft": _DEFAULT.with_overrides(
        name="soft", radius=11e-3, modulus=10e3,
        description="soft, large pad: R_fp 11 mm, E* 10 kPa (ends of the typical ranges)",
    ),
    # stiff, small pad: the stiff/small ends of the documented ranges (E* 100 kPa, R_fp 7 mm).
    "stiff": _DEFAULT.with_overrides(
        name="stiff", radius=7e-3, modulus=100e3,
        description="stiff, small pad: R_fp 7 mm, E* 100 kPa (ends of the typical ranges)",
    ),
    # Dzidek stiffening (Eqs. 2.6-2.7), C = 5: the largest C for which the strain estimate
    # eps = 0.2 a/R_fp stays inside eps < 1/C whenever a < R_fp; phi = 0.23 /N.
    "stiffening": _DEFAULT.with_overrides(
        name="stiffening", gross=DzidekArea(9e-3, 40e3, 5.0),
        description="default pad with Dzidek secant-modulus stiffening, C = 5, eta = 3",
    ),
    # Sinusoidal ridges: lambda_r = 0.45 mm (docs/model.md 0.4-0.5 mm), E* = 100 kPa (thesis Fig. 2.4
    # input); amplitude 30 um is assumed, chosen so that A_fr/A_g runs from ~30 % at 0.1 N to
    # ~73 % at 4 N on this pad, i.e. inside the documented 10-70 % range over the exploration loads.
    "ridged": _DEFAULT.with_overrides(
        name="ridged", ridges=SinusoidalRidges(wavelength=0.45e-3, modulus=100e3, amplitude=30e-6),
        description="default pad with sinusoidal (Westergaard) fingerprint ridges, 0.45 mm, 30 um",
    ),
    # One skin through the scales (docs/model.md 6.5): a stratum corneum of t = 0.3 mm (thesis
    # ch. 1.2: 0.2-0.35 mm) and E_1 = E_s = 0.3 MPa on tissue of E_2 = 30.4 kPa, i.e. E_2* =
    # 40 kPa = the pad's E_fp*. Textures up to ~0.4 mm then feel 0.3 MPa (what the thesis
    # recovered), the pad 40 kPa (what the pad measurements give).
    "layered": _DEFAULT.with_overrides(
        name="layered", skin_layer_thickness=0.3e-3, skin_layer_modulus=0.3e6,
        skin_substrate_modulus=40e3 * (1 - DEFAULT_SKIN_POISSON**2),
        description="default pad with a layered skin: stratum corneum 0.3 mm, E_1 0.3 MPa on tissue E_2* 40 kPa",
    ),
    # Adhesion (docs/model.md 6.6): every other preset has none (w = 0). A dry finger's work of
    # adhesion is at most ~0.24-0.40 J/m^2, an UPPER BOUND from a whole finger's 15 mN pull-off
    # on smooth epoxy (Spinner et al. 2016, R_fp 8-10 mm; JKR 1.5 pi w R gives 0.32-0.40, DMT
    # 2 pi w R 0.24-0.30), none measurable on clean glass (Tiwari, Wang, Persson 2020); no measured w of skin
    # on glass or polymers was found. 0.05 J/m^2 is an assumed moderate value inside that bound.
    "adhesive": _DEFAULT.with_overrides(
        name="adhesive", work_of_adhesion=0.05,
        description="default pad with adhesion: w 0.05 J/m2 (assumed; a dry finger's is at most ~0.3-0.4)",
    ),
}


def _model_area(model: Any, *arrays: np.ndarray) -> np.ndarray:
    """A model's area on checked arrays: its ``area_checked`` core where it has one (no second
    check of the same loads), else its public ``area``."""
    core = getattr(model, "area_checked", None)
    return np.asarray(core(*arrays) if core is not None else model.area(*arrays), dtype=float)


def get_finger(name: str) -> Finger:
    """Return the preset finger ``name`` (case-insensitive).

    Raises
    ------
    FingerpadError
        If there is no such preset; the message lists the presets.
    """
    key = str(name).strip().lower()
    if key not in FINGER_PRESETS:
        raise FingerpadError(f"unknown finger preset {name!r}; choose one of: {', '.join(FINGER_PRESETS)}")
    return FINGER_PRESETS[key]



__all__ = [
    "ADHESION_FIELDS",
    "ADHESION_LAWS",
    "ADHESION_RANGE",
    "FINGER_FIELDS",
    "FINGER_PARAMS",
    "FINGER_PRESETS",
    "RIDGE_FRACTION",
    "CircularRidges",
    "ConstantFractionRidges",
    "DzidekArea",
    "Finger",
    "FingerprintBEMRidges",
    "GrossAreaModel",
    "HertzArea",
    "LAYER_FIELDS",
    "describe_skin",
    "skin_units",
    "Layer",
    "PowerLawArea",
    "PowerLawRidges",
    "RidgeAreaModel",
    "SinusoidalRidges",
    "TwoRegimePowerLawArea",
    "disc_average",
    "finger_param",
    "get_finger",
    "model_from_spec",
    "pad_pressure",
]


def model_from_spec(
    kind: str, spec: Any, finger: Finger, name: str, context: Mapping[str, Any] | None = None
) -> GrossAreaModel | RidgeAreaModel:
    """A gross-area (``kind="gross"``) or ridge-area (``kind="ridges"``) model from a study value.

    ``spec`` is a model name (``"dzidek"``) or a table ``{model = "dzidek", stiffening = 5}`` whose
    other keys are the model's declared parameters (SI numbers or quantities with units). A model
    that inherits values (:attr:`fingerpad.params.Model.inherits`) gets the finger's
    (``finger.radius``, ``finger.modulus``) and the study's (``context``, e.g. ``loads.max``)
    unless given.

    Raises
    ------
    FingerpadError
        Unknown model or field, bad value (naming ``name``).
    """
    registry = GROSS_MODELS if kind == "gross" else RIDGE_MODELS
    table = {"model": spec} if isinstance(spec, str) else dict(spec) if isinstance(spec, dict) else None
    if table is None or not isinstance(table.get("model"), str):
        raise FingerpadError(f"{name}: expected a model name or a table with model = NAME "
                             f"(models: {', '.join(registry)})")
    model_name = table.pop("model").strip().lower().replace("-", "_")
    model = registry.get(model_name)
    if model is None:
        raise FingerpadError(f"{name}: unknown model {model_name!r} (models: {', '.join(registry)})")
    values = {"finger.radius": finger.radius, "finger.modulus": finger.modulus, **(context or {})}
    return model.build(table, where=name, context=values)
