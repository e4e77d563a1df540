"""A prediction study: texture + materials + finger + loads -> areas, zones and friction vs load.

This is the package's main job (``fingerpad predict``). A :class:`Study` names

* the texture (a generator and its parameters, a height-map file, or a ready
  :class:`~fingerpad.textures.Texture`),
* the counter-surface material (Young's modulus and Poisson ratio; ``None`` = rigid),
* the finger (:class:`~fingerpad.finger.Finger`, whose ``skin_modulus``/``skin_poisson`` enter
  E1*, Eq. 3.4),
* the loads (N), the unit-cell model (``"bem"``, ``"hertz"`` or ``"both"``) and the numerics.

This module reads and checks a study, once, whether it comes from a TOML file, from command-line
flags laid over it (:mod:`fingerpad.study.overrides`), or from Python; :mod:`.run` runs it and
:mod:`.outputs` writes its results.

Study files (TOML, read with :func:`load_study_file`)::

    [texture]                 # a generator (see `fingerpad textures`) and its parameters ...
    name = "caps"
    radius = "100um"          # numbers are SI, strings may carry units
    height = "20um"
    spacing = "175um"
    lattice = "hexagonal"
    # ... or a height map: surface = "scan.npy", size = "400um,400um", height_unit = "um",
    #     periodic = false, periodize = true, fill_missing = false,
    #     pixel_size = "2um" (instead of size), base_quantile = 0.01

    [material]                # counter-surface; omit the section for a rigid one
    modulus = "0.5GPa"        # or "rigid"
    poisson = 0.4

    [finger]
    preset = "default"        # see `fingerpad fingers`
    skin_modulus = "0.3MPa"   # overrides: radius, modulus, beta, tau0, alpha, skin_modulus, skin_poisson
    gross = "dzidek"          # pad (gross-area) model by name, or a table (fingerpad.macro.GROSS_MODELS):
    # gross = { model = "dzidek", stiffening = 5 }
    ridges = { model = "sinusoidal", wavelength = "0.45mm", amplitude = "30um", modulus = "100kPa" }
    # ridges = { model = "fingerprint_bem", height = "30um" }   # BEM on a fingerprint (slow)

    [loads]
    range = "0.1N:4N:40"      # START:STOP:COUNT (or a list of them), or values = ["0.5N", 1, "2N"]
    log = true                # spacing of ranges; default true (log-spaced)
    zones_at = "2N"           # load of the zone map (default: the largest load)

    [model]
    kind = "both"             # bem | hertz | both
    grid = 64                 # grid points along x of the cell (default: chosen by accuracy)
    accuracy = 0.02           # target of the estimated error of A_re/A_fr when the grid is automatic
    direction = 90            # sliding direction (deg from x): directional friction of compliant
                              # ellipsoids or ridges (docs/deflection.md); omit for isotropic
    tol = 1e-8
    max_iter = 5000
    cache = "~/.cache/fingerpad"   # folder of cached unit-cell curves; false: no cache

    [perception]              # the person, beyond the finger's mechanics (fingerpad.person)
    weber_fraction = 0.11     # Weber fraction W of friction (docs/perception.md); default 0.11

Unknown sections or keys are a :class:`~fingerpad.errors.FingerpadError` that names them.
Relative paths (``surface``, ``cache``) are taken relative to the study file.

SI units throughout (m, N, Pa).
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FingerpadError
from ..finger import FINGER_FIELDS, FINGER_PRESETS, Finger, finger_param, get_finger, model_from_spec
from ..materials import check_modulus, check_poisson
from ..person import PERSON_PARAMS, WEBER_FRACTION
from ..plausibility import check_plausible
from ..textures import MAX_GRID, Texture
from .texture import TEXTURE_KEYS, TextureSpec
from .values import boolean, integer, material, parse_loads, positive_loads, quantity

__all__ = [
    "DEFAULT_GRID",
    "DEFAULT_LOADS",
    "DEFAULT_STUDY",
    "MODELS",
    "SECTION_KEYS",
    "Study",
    "TextureSpec",
    "load_study_file",
    "parse_loads",
    "read_study_file",
    "study_from_dict",
]

#: The study of `run-default` (also in examples/study.toml). A hot-embossed polyethylene foil:
#: E = 0.5 GPa, nu = 0.4 (PE foil 0.2-1 GPa), with spherical-cap bumps R = 100 um, h = 20 um on a
#: hexagonal lattice of spacing 175 um (base diameter 120 um, gaps of 55 um): dimensions a
#: hot-embossing mould reproduces easily, at the ~160 um spacing where textures start to be felt.
#: With the default finger (E_s = 0.3 MPa, so E1* = 0.395 MPa) both critical loads fall inside the
#: 0.1-4 N exploration range -- Hertz (Eq. 3.6) about 0.18 N, the BEM about 1.1 N -- so the figures
#: show the asperity, transition and (BEM) transition-zone growth states.
DEFAULT_STUDY: dict[str, dict[str, Any]] = {
    "texture": {"name": "caps", "radius": "100um", "height": "20um", "spacing": "175um", "lattice": "hexagonal"},
    "material": {"modulus": "0.5GPa", "poisson": 0.4},
    "finger": {"preset": "default"},
    "loads": {"range": "0.1N:4N:40", "log": True},
    "model": {"kind": "both"},
}
#: Grid of the default unit cell (points along x; the hexagonal cell has 1.73x as many along y).
DEFAULT_GRID = "64"

MODELS = ("bem", "hertz", "both")
#: Loads when a study gives none: the exploration range 0.1-4 N, 40 log-spaced points.
DEFAULT_LOADS = "0.1N:4N:40"

# Keys of the study-file sections (texture: plus the generator's own parameters).
SECTION_KEYS: dict[str, tuple[str, ...]] = {
    "texture": TEXTURE_KEYS,
    "material": ("modulus", "poisson"),
    "finger": ("preset", "gross", "ridges", *FINGER_FIELDS),
    "loads": ("range", "values", "log", "zones_at"),
    "model": ("kind", "grid", "accuracy", "tol", "max_iter", "cache", "direction"),
    "perception": tuple(p.name for p in PERSON_PARAMS),
}


# =============================================================================================
# the study
# =============================================================================================


@dataclass
class Study:
    """Everything a prediction needs (SI units).

    Attributes
    ----------
    texture
        A :class:`TextureSpec` (built with ``grid`` by :meth:`build_texture`) or a ready texture.
    material_modulus, material_poisson
        Counter-surface Young's modulus (Pa) and Poisson ratio; ``None`` modulus = rigid.
    finger
        The finger (skin modulus and Poisson ratio included).
    loads
        Normal loads, N (positive, 1-D).
    model
        ``"bem"`` (numerical unit cell), ``"hertz"`` (per-asperity Hertz, textures with an
        asperity radius) or ``"both"``.
    grid
        Grid points along x of the generated cell (``None``: chosen by ``accuracy``, starting from
        the generator's default).
    accuracy
        Target of the estimated relative discretisation error of A_re/A_fr when the grid is
        chosen automatically (default 0.02); with a given grid the error is only reported.
    direction
        Sliding direction, degrees from the texture's x axis, for directional friction of
        compliant ellipsoids and ridges (:mod:`fingerpad.micro.deflection`); ``None``: the
        isotropic model.
    tol, max_iter
        Half-space solver settings (a unit-cell curve's nodes stop at ``max(tol, CURVE_TOL)``,
        :data:`fingerpad.micro.bem.CURVE_TOL`; its state brackets at ``tol``).
    cache
        Folder of cached unit-cell curves; ``None``: ``$FINGERPAD_CACHE`` or ``~/.cache/fingerpad``;
        ``False``: no cache.
    zones_at
        Load (N) of the zone map; ``None``: the largest load (where most zones are present).
    source
        The study file, if any.
    weber_fraction
        The person's Weber fraction W of friction (:data:`fingerpad.person.WEBER_FRACTION`;
        ``[perception] weber_fraction``, ``--weber-fraction``); ``None``: not given, so the
        default 0.11 or, with a population that draws it, each member's own. A value given is
        one the user fixed (:attr:`fixed`).
    fixed
        The finger values the user gave explicitly (a study file's ``[finger]`` key, a flag, a
        field typed in the explorer), by parameter name: how the user named each (``--skin-modulus``,
        ``study.toml [finger] tau0``). A population refuses to draw them
        (:func:`fingerpad.population.rules.attach`); ``ridge_fraction`` stands for a
        constant-fraction ridge model given; ``weber_fraction`` a person's W given.
    """

    texture: TextureSpec | Texture
    material_modulus: float | None = None
    material_poisson: float | None = None
    finger: Finger = field(default_factory=lambda: FINGER_PRESETS["default"])
    loads: np.ndarray = field(default_factory=lambda: parse_loads(DEFAULT_LOADS, True))
    model: str = "both"
    grid: int | None = None
    accuracy: float = 0.02
    direction: float | None = None
    tol: float = 1e-8
    max_iter: int = 5000
    cache: str | os.PathLike[str] | None | bool = None
    zones_at: float | None = None
    source: str | None = None
    weber_fraction: float | None = None
    fixed: dict[str, str] = field(default_factory=dict, repr=False, compare=False)
    _texture: Texture | None = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not isinstance(self.texture, (TextureSpec, Texture)):
            raise FingerpadError(f"texture must be a TextureSpec or a Texture, got {type(self.texture).__name__}")
        if not isinstance(self.finger, Finger):
            raise FingerpadError(f"finger must be a Finger, got {type(self.finger).__name__}")
        self.loads = positive_loads(np.atleast_1d(np.asarray(self.loads, dtype=float)), "loads")
        if self.model not in MODELS:
            raise FingerpadError(f"model must be one of {', '.join(MODELS)}, got {self.model!r}")
        if self.material_modulus is None:
            if self.material_poisson is not None:
                raise FingerpadError("material Poisson ratio: a Poisson ratio is given, but it needs a material "
                                     "modulus (the default material is rigid)")
        else:
            check_modulus(self.material_modulus, "material modulus")
            if self.material_poisson is None:
                self.material_poisson = 0.35
            check_poisson(self.material_poisson, "material Poisson ratio")
        if self.grid is not None:
            self.grid = integer(self.grid, "grid", 4, MAX_GRID)
        if not (isinstance(self.accuracy, (int, float)) and 0 < self.accuracy < 1):
            raise FingerpadError(f"accuracy must lie in (0, 1), got {self.accuracy!r}")
        if not (isinstance(self.tol, (int, float)) and 0 < self.tol < 1):
            raise FingerpadError(f"tol must lie in (0, 1), got {self.tol!r}")
        from ..contact.solver import MAX_ITER

        self.max_iter = integer(self.max_iter, "max_iter", 1, MAX_ITER)
        if self.zones_at is not None and not (math.isfinite(self.zones_at) and self.zones_at > 0):
            raise FingerpadError(f"zones_at must be a positive load, got {self.zones_at!r}")
        if isinstance(self.texture, Texture):
            self._texture = self.texture
        if self.weber_fraction is not None:
            self.weber_fraction = WEBER_FRACTION.check(self.weber_fraction, "weber_fraction")
            # a W given is fixed, however it came (a file, a flag, Python): no population draws over it
            self.fixed = {"weber_fraction": "weber_fraction", **self.fixed}

    @property
    def weber(self) -> float:
        """The person's Weber fraction W: the one given, else :data:`fingerpad.person.WEBER_FRACTION`'s
        default."""
        return WEBER_FRACTION.default if self.weber_fraction is None else float(self.weber_fraction)

    @property
    def reduced_modulus(self) -> float:
        """E1* (Pa), Eq. 3.4, from the finger's skin and the material."""
        return self.finger.micro_modulus(self.material_modulus, self.material_poisson or 0.35)

    @property
    def zone_load(self) -> float:
        """The load (N) of the zone map."""
        if self.zones_at is not None:
            return float(self.zones_at)
        return float(self.loads.max())

    @property
    def texture_source(self) -> dict[str, Any]:
        if isinstance(self.texture, TextureSpec):
            return self.texture.source
        return {"source": "texture", "file": None}

    def build_texture(self) -> Texture:
        """Build (once) and return the texture."""
        if self._texture is None:
            self._texture = self.texture.build(self.grid)  # type: ignore[union-attr]
        return self._texture

    def curve_cache(self) -> Any:
        from ..micro.cache import CurveCache

        if self.cache is False:
            return False
        if self.cache is None or self.cache is True:
            return None
        return CurveCache(Path(os.fspath(self.cache)).expanduser())

    def check(self) -> None:
        """Cheap checks of the whole study before any solving (texture built, model applicable)."""
        from ..micro.hertz import hertz_cell_for

        tex = self.build_texture()
        if self.model in ("bem", "both") and not tex.periodic:
            what = f"surface {self.texture.surface!r}" if isinstance(self.texture, TextureSpec) and \
                self.texture.surface else f"texture {tex.name!r}"
            raise FingerpadError(
                f"the BEM unit cell needs a periodic texture, but {what} is a finite patch: "
                "if the map is one period give --periodic (periodic = true), else mirror it into a "
                "periodic cell with --periodize (periodize = true, fingerpad.textures.periodize)"
            )
        if self.model == "hertz":
            hertz_cell_for(tex, self.reduced_modulus)  # raises for textures without an asperity radius
        self.reduced_modulus  # noqa: B018 -- validates the moduli


# ---------------------------------------------------------------------------------------------
# reading study files
# ---------------------------------------------------------------------------------------------


def read_study_file(path: str | os.PathLike[str], extra_sections: tuple[str, ...] = ()) -> dict[str, dict[str, Any]]:
    """Read a TOML study file into its sections (keys checked, relative paths resolved).

    ``extra_sections`` are further tables the caller reads itself (``sweep`` for
    ``fingerpad sweep``); they are returned unchecked.

    Raises
    ------
    FingerpadError
        Unreadable file, not a TOML text, TOML syntax error (:func:`fingerpad.io.read_toml`),
        unknown section or key.
    """
    from ..io import read_toml

    p = Path(path)
    data = read_toml(p, "study file")
    unknown = [k for k in data if k not in SECTION_KEYS and k not in extra_sections]
    if unknown:
        hint = " ([sweep] tables are read by `fingerpad sweep`)" if "sweep" in unknown else ""
        raise FingerpadError(
            f"study file {p.name!r}: unknown section(s) or key(s) {', '.join(sorted(unknown))} "
            f"(sections: {', '.join(f'[{s}]' for s in SECTION_KEYS)}){hint}"
        )
    out: dict[str, dict[str, Any]] = {}
    for section, body in data.items():
        if section in extra_sections:
            out[section] = body
            continue
        if not isinstance(body, dict):
            raise FingerpadError(f"study file {p.name!r}: {section!r} must be a [{section}] section")
        out[section] = dict(body)
    base = p.resolve().parent
    tex = out.get("texture", {})
    if isinstance(tex.get("surface"), str):
        tex["surface"] = str(base / Path(tex["surface"]).expanduser())
    model = out.get("model", {})
    if isinstance(model.get("cache"), str):
        model["cache"] = str(base / Path(model["cache"]).expanduser())
    out["_source"] = {"file": str(p)}
    return out


class _Names:
    """How to name a study value in an error message: the command-line flag that set it, or the
    study file's section and key."""

    def __init__(self, source: str | None, labels: Mapping[tuple[str, str], str] | None) -> None:
        self.prefix = f"{Path(source).name} " if source else ""
        self.labels = dict(labels or {})

    def __call__(self, section: str, key: str | None = None) -> str:
        if key is not None and (section, key) in self.labels:
            return self.labels[(section, key)]
        return f"{self.prefix}[{section}]" + (f" {key}" if key else "")


def _texture_spec(section: Mapping[str, Any], name: _Names) -> tuple[TextureSpec, int | None]:
    sec = dict(section)
    grid = sec.pop("grid", None)
    fam, surface = sec.pop("name", None), sec.pop("surface", None)
    if (fam is None) == (surface is None):
        raise FingerpadError(f"{name('texture')}: give exactly one of a texture name (generator) or a surface file")
    for key, value in (("name", fam), ("surface", surface), ("height_unit", sec.get("height_unit"))):
        if value is not None and not isinstance(value, str):
            raise FingerpadError(f"{name('texture', key)}: expected text, got {value!r}")
    periodic = sec.pop("periodic", None)
    spec = TextureSpec(
        name=fam,
        surface=surface,
        size=sec.pop("size", None),
        height_unit=sec.pop("height_unit", None),
        periodic=None if periodic is None else boolean(periodic, name("texture", "periodic")),
        periodize=boolean(sec.pop("periodize", False), name("texture", "periodize")),
        fill_missing=boolean(sec.pop("fill_missing", False), name("texture", "fill_missing")),
        pixel_size=sec.pop("pixel_size", None),
        base_quantile=None if sec.get("base_quantile") is None else
        quantity(sec.pop("base_quantile"), "none", name("texture", "base_quantile")),
        labels={k: name("texture", k) for k in TEXTURE_KEYS},
    )
    spec.params = {k.replace("-", "_"): v for k, v in sec.items()}
    spec.labels.update({k: name("texture", k) for k in spec.params})
    return spec, (None if grid is None else integer(grid, name("texture", "grid"), 4, MAX_GRID))


def _finger(section: Mapping[str, Any], name: _Names, context: Mapping[str, Any]) -> Finger:
    fin = dict(section)
    preset = fin.pop("preset", "default")
    if not isinstance(preset, str):
        raise FingerpadError(f"{name('finger', 'preset')}: expected a preset name, got {preset!r}")
    finger = get_finger(preset)
    gross, ridges = fin.pop("gross", None), fin.pop("ridges", None)
    values: dict[str, Any] = {}
    for key, value in fin.items():
        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            raise FingerpadError(f"{name('finger', key)}: expected a number or a quantity, got {value!r}")
        # the declaration reads the value (unit, bounds, a forgotten unit warned about)
        values[key] = finger_param(key).parse(value, name("finger", key))
    if values:
        finger = finger.with_overrides(**values)
    models: dict[str, Any] = {}
    if gross is not None:
        models["gross"] = model_from_spec("gross", gross, finger, name("finger", "gross"), context)
    if ridges is not None:
        models["ridges"] = model_from_spec("ridges", ridges, finger, name("finger", "ridges"), context)
    return finger.with_overrides(**models) if models else finger


def study_from_dict(
    data: Mapping[str, Mapping[str, Any]], labels: Mapping[tuple[str, str], str] | None = None
) -> Study:
    """Build and check a :class:`Study` from study-file sections (as :func:`read_study_file` returns
    them, possibly with command-line values laid over them by :mod:`fingerpad.study.overrides`).

    Values are SI numbers or strings with units. This is the one place where a study's values are
    validated; ``labels`` maps ``(section, key)`` to the command-line flag that set the value, so
    that messages name what the user typed.

    Raises
    ------
    FingerpadError
        Naming the offending value.
    """
    if not isinstance(data, Mapping):
        raise FingerpadError(f"a study is a mapping of sections ({', '.join(SECTION_KEYS)}) to their values, "
                             f"got {type(data).__name__}")
    source = data.get("_source", {})
    src = source.get("file") if isinstance(source, Mapping) else None
    name = _Names(src, labels)
    unknown = [k for k in data if k not in SECTION_KEYS and k != "_source"]
    if unknown:
        raise FingerpadError(f"unknown study section(s) {', '.join(sorted(map(str, unknown)))}")
    for section, body in data.items():
        if section == "_source":
            continue
        if not isinstance(body, Mapping):
            raise FingerpadError(f"{name(section)}: must be a table of values (a mapping), got {type(body).__name__}")
        if section == "texture":
            continue
        bad = [k for k in body if k not in SECTION_KEYS[section]]
        if bad:
            raise FingerpadError(f"{name(section, bad[0])}: unknown key(s) in [{section}]: {', '.join(sorted(bad))} "
                                 f"(known: {', '.join(SECTION_KEYS[section])})")

    tex_sec = data.get("texture")
    if not tex_sec:
        raise FingerpadError("no texture given: use --texture NAME (with its --PARAM VALUE options), "
                             "--surface FILE, or a [texture] section in a study file")
    texture, tex_grid = _texture_spec(tex_sec, name)

    mat = data.get("material", {})
    em, num = material(mat.get("modulus"), mat.get("poisson"), name("material", "modulus"), name("material", "poisson"))
    if em is not None:
        check_plausible(em, "material modulus", name("material", "modulus"))

    lsec = data.get("loads", {})
    # One rule: ranges are log-spaced unless the study (file or --linear) says otherwise.
    log = boolean(lsec.get("log", True), name("loads", "log"))
    if "range" in lsec and "values" in lsec:
        raise FingerpadError(f"{name('loads')}: give range or values, not both")
    if "range" in lsec:
        loads = parse_loads(lsec["range"], log, name("loads", "range"))
    elif "values" in lsec:
        values = lsec["values"]
        loads = parse_loads(values if isinstance(values, (list, tuple, np.ndarray)) else [values], log,
                            name("loads", "values"))
    else:
        loads = parse_loads(DEFAULT_LOADS, True, "loads")
    for value in (float(loads.min()), float(loads.max())):
        check_plausible(value, "load", name("loads", "range" if "range" in lsec else "values"))
    # after the loads: a ridge model may take the largest load (the BEM fingerprint's patch)
    finger = _finger(data.get("finger", {}), name, {"loads.max": float(loads.max())})

    zones_at = lsec.get("zones_at")
    zones_v = None if zones_at is None else quantity(zones_at, "force", name("loads", "zones_at"))
    if zones_v is not None and zones_v <= 0:
        raise FingerpadError(f"{name('loads', 'zones_at')}: must be a positive load, got {zones_at!r}")

    msec = data.get("model", {})
    kind = msec.get("kind", "both")
    if not (isinstance(kind, str) and kind.strip().lower() in MODELS):
        raise FingerpadError(f"{name('model', 'kind')}: must be one of {', '.join(MODELS)}, got {kind!r}")
    grid = msec.get("grid")
    grid_v = None if grid is None else integer(grid, name("model", "grid"), 4, MAX_GRID)
    if grid_v is not None and tex_grid is not None and grid_v != tex_grid:
        raise FingerpadError("give the grid once, in [model] (or --grid)")
    grid_v = grid_v if grid_v is not None else tex_grid
    accuracy = quantity(msec.get("accuracy", 0.02), "none", name("model", "accuracy"))
    if not 0 < accuracy < 1:
        raise FingerpadError(f"{name('model', 'accuracy')}: must lie in (0, 1), e.g. 0.02 for 2 %, got {accuracy!r}")
    direction = None
    if msec.get("direction") is not None:
        from ..textures.base import parse_angle

        direction = math.degrees(parse_angle(msec["direction"], name("model", "direction")))
    tol = quantity(msec.get("tol", 1e-8), "none", name("model", "tol"))
    if not 0 < tol < 1:
        raise FingerpadError(f"{name('model', 'tol')}: must lie in (0, 1), got {tol!r}")
    from ..contact.solver import MAX_ITER

    max_iter = integer(msec.get("max_iter", 5000), name("model", "max_iter"), 1, MAX_ITER)
    cache = msec.get("cache")
    if isinstance(cache, bool):
        cache = None if cache else False
    elif cache is not None and not isinstance(cache, (str, os.PathLike)):
        raise FingerpadError(f"{name('model', 'cache')}: expected a folder or false, got {cache!r}")

    weber, fixed = None, _fixed_finger_values(data.get("finger", {}), name)
    psec = data.get("perception", {})
    if psec.get("weber_fraction") is not None:
        weber = WEBER_FRACTION.parse(psec["weber_fraction"], name("perception", "weber_fraction"))
        fixed["weber_fraction"] = name("perception", "weber_fraction")

    return Study(
        texture=texture, material_modulus=em, material_poisson=num, finger=finger, loads=loads,
        model=kind.strip().lower(), grid=grid_v, accuracy=accuracy, direction=direction, tol=tol, max_iter=max_iter, cache=cache,
        zones_at=zones_v, source=src, weber_fraction=weber, fixed=fixed,
    )


def _fixed_finger_values(section: Mapping[str, Any], name: _Names) -> dict[str, str]:
    """The finger values given explicitly (see :attr:`Study.fixed`), by how the user named them."""
    fixed = {key: name("finger", key) for key in section if key in FINGER_FIELDS}
    ridges = section.get("ridges")
    if isinstance(ridges, Mapping) and str(ridges.get("model", "")).strip().lower() == "constant_fraction":
        fixed["ridge_fraction"] = name("finger", "ridges")
    return fixed


def load_study_file(path: str | os.PathLike[str]) -> Study:
    """Read and check a TOML study file (see the module docstring); the texture is built lazily."""
    return study_from_dict(read_study_file(path))
