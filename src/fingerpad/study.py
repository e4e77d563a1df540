"""A prediction study: texture + materials + finger + loads -> areas, zones and friction vs load.

This is the package's main job (``fingerpad predict``). A :class:`Study` names

* the texture (a generator and its parameters, a height-map file, or a ready
  :class:`~fingerpad.textures.Texture`),
* the counter-surface material (Young's modulus and Poisson ratio; ``None`` = rigid),
* the finger (:class:`~fingerpad.finger.Finger`, whose ``skin_modulus``/``skin_poisson`` enter
  E1*, Eq. 3.4),
* the loads (N), the unit-cell model (``"bem"``, ``"hertz"`` or ``"both"``) and the numerics.

:func:`run_study` chains the scales: ``E1* = finger.micro_modulus(material)`` (Eq. 3.4); for the
BEM a periodic unit cell of the texture is solved over the local pressures the pad produces
(:class:`~fingerpad.unitcell.BEMUnitCell`, cached on disk), for Hertz the spherical caps are
treated one by one (:class:`~fingerpad.coupling.HertzUnitCell`, Eqs. 3.1-3.6); both are coupled to
the pad by :func:`~fingerpad.coupling.predict_curve` (Eq. 3.7 and MODEL.md [completion]).
:func:`write_outputs` writes ``predict.json``, ``predict.nc`` and three figures, all or none.

Study files (TOML, read with :func:`load_study_file`)::

    [texture]                 # a generator (see `fingerpad textures`) and its parameters ...
    name = "caps"
    radius = "100um"          # numbers are SI, strings may carry units
    height = "20um"
    spacing = "175um"
    lattice = "hexagonal"
    # ... or a height map: surface = "scan.npy", size = "400um,400um", height_unit = "um",
    #     periodic = false, periodize = true, fill_missing = false

    [material]                # counter-surface; omit the section for a rigid one
    modulus = "0.5GPa"        # or "rigid"
    poisson = 0.4

    [finger]
    preset = "default"        # see fingerpad.finger.FINGER_PRESETS
    skin_modulus = "0.3MPa"   # overrides: radius, modulus, beta, tau0, alpha, skin_modulus, skin_poisson

    [loads]
    range = "0.1N:4N:40"      # START:STOP:COUNT, or values = ["0.5N", 1, "2N"]
    log = true
    zones_at = "2N"           # load of the zone map (default: the largest load)

    [model]
    kind = "both"             # bem | hertz | both
    grid = 64                 # grid points along x of the cell (default: the generator's)
    tol = 1e-8
    max_iter = 5000
    cache = "~/.cache/fingerpad"   # folder of cached unit-cell curves; false: no cache

Unknown sections or keys are a :class:`~fingerpad.errors.FingerpadError` that names them.
Relative paths (``surface``, ``cache``) are taken relative to the study file.

SI units throughout (m, N, Pa).
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import os
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .coupling import CurvePrediction, HertzUnitCell, predict_curve
from .errors import FingerpadError
from .finger import _FIELD_DIMENSIONS, FINGER_PRESETS, Finger, get_finger
from .inputs import make_generated_texture, parse_size, read_surface_file
from .materials import check_modulus, check_poisson
from .textures import Texture
from .units import parse_quantity, parse_range

__all__ = [
    "DEFAULT_LOADS",
    "MODELS",
    "OUTPUT_FILES",
    "OUTPUT_UNITS",
    "Prediction",
    "Study",
    "TextureSpec",
    "hertz_cell_for",
    "load_study_file",
    "prediction_json",
    "read_study_file",
    "run_study",
    "study_from_dict",
    "write_outputs",
]

#: The study of `run-default` (also in examples/study.toml). A hot-embossed polyethylene foil:
#: E = 0.5 GPa, nu = 0.4 (MODEL.md: PE foil 0.2-1 GPa), with spherical-cap bumps R = 100 um,
#: h = 20 um on a hexagonal lattice of spacing 175 um (base diameter 120 um, gaps of 55 um):
#: dimensions a hot-embossing mould reproduces easily, at the ~160 um spacing where textures start
#: to be felt. With the default finger (E_s = 0.3 MPa, so E1* = 0.395 MPa) both critical loads fall
#: inside the 0.1-4 N exploration range -- Hertz (Eq. 3.6) about 0.18 N, the BEM about 1.1 N --
#: so the figures show the asperity, transition and (BEM) transition-zone growth states.
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
#: Loads when a study gives none: MODEL.md's exploration range 0.1-4 N, 40 log-spaced points.
DEFAULT_LOADS = "0.1N:4N:40"
#: Files written by :func:`write_outputs`, in order.
OUTPUT_FILES = ("predict.json", "predict.nc", "areas.png", "friction.png", "zones.png")
#: Local pressures solved on the BEM cell: [P_LOW * min(F/A_fr), P_HIGH * max(F/A_fr)]. The pad
#: pressure (Eq. 3.7) runs from 0 at the disc edge to 1.5 F/A_fr at the centre; below the lowest
#: computed node psi follows the power law of the two lowest nodes (asperity contact).
P_LOW, P_HIGH = 0.02, 1.5

# Keys of the study-file sections (texture: plus the generator's own parameters).
_TEXTURE_KEYS = ("name", "surface", "size", "height_unit", "periodic", "periodize", "fill_missing")
_SECTION_KEYS: dict[str, tuple[str, ...]] = {
    "texture": _TEXTURE_KEYS,
    "material": ("modulus", "poisson"),
    "finger": ("preset", *_FIELD_DIMENSIONS),
    "loads": ("range", "values", "log", "zones_at"),
    "model": ("kind", "grid", "tol", "max_iter", "cache"),
}


# =============================================================================================
# small parsers: TOML values (numbers = SI, strings may carry units) and command-line text alike
# =============================================================================================


def _quantity(value: Any, dimension: str, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise FingerpadError(f"{name}: expected a number or a quantity such as '1N', got {value!r}")
    return parse_quantity(value, dimension, name=name)


def _integer(value: Any, name: str, minimum: int = 1) -> int:
    if isinstance(value, bool):
        raise FingerpadError(f"{name}: expected an integer, got {value!r}")
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    if isinstance(value, str) and value.strip().lstrip("+").isdigit():
        value = int(value.strip())
    if not isinstance(value, int):
        raise FingerpadError(f"{name}: expected an integer, got {value!r}")
    if value < minimum:
        raise FingerpadError(f"{name}: must be at least {minimum}, got {value}")
    return value


def _boolean(value: Any, name: str) -> bool:
    if isinstance(value, bool):
        return value
    if isinstance(value, str) and value.strip().lower() in ("1", "true", "yes", "on", "0", "false", "no", "off"):
        return value.strip().lower() in ("1", "true", "yes", "on")
    raise FingerpadError(f"{name}: expected true or false, got {value!r}")


def _text(value: Any) -> str:
    """A TOML value as the text the command line would give (lists: comma-separated)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, (list, tuple)):
        return ",".join(_text(v) for v in value)
    return str(value)


def _positive_loads(values: Sequence[float], name: str) -> np.ndarray:
    arr = np.asarray(list(values), dtype=float).ravel()
    if arr.size == 0:
        raise FingerpadError(f"{name}: no loads given")
    if not np.all(np.isfinite(arr)):
        raise FingerpadError(f"{name}: loads must be finite")
    if np.any(arr <= 0):
        raise FingerpadError(f"{name}: loads must be positive, got {arr.min():.4g} N")
    return arr


def parse_loads(spec: Any, log: bool, name: str = "loads") -> np.ndarray:
    """Loads (N) from ``"START:STOP:COUNT"`` (log-spaced if ``log``), one quantity, or a list."""
    if isinstance(spec, (list, tuple, np.ndarray)):
        values = [_quantity(v, "force", name) for v in spec]
    elif isinstance(spec, str):
        values = parse_range(spec, "force", name=name, log=log)
    else:
        values = [_quantity(spec, "force", name)]
    return _positive_loads(values, name)


def _material(modulus: Any, poisson: Any, where: str) -> tuple[float | None, float | None]:
    """Counter-surface (E, nu); ``None`` modulus or ``"rigid"`` = rigid (then no Poisson ratio)."""
    rigid = modulus is None or (isinstance(modulus, str) and modulus.strip().lower() in ("rigid", "inf", "infinity"))
    if rigid:
        if poisson is not None:
            raise FingerpadError(f"{where}: a Poisson ratio needs a material modulus (the default material is rigid)")
        return None, None
    em = check_modulus(_quantity(modulus, "pressure", f"{where} modulus"), f"{where} modulus")
    num = 0.35 if poisson is None else check_poisson(_quantity(poisson, "none", f"{where} poisson"), f"{where} poisson")
    return em, num


# =============================================================================================
# the study
# =============================================================================================


@dataclass
class TextureSpec:
    """A texture to build: a generator with parameters, or a height-map file.

    Attributes
    ----------
    name
        Generator name (a key of :data:`fingerpad.textures.GENERATORS`), or ``None`` with ``surface``.
    params
        Generator parameters: SI numbers or strings with units (``"50um"``), as on the command line.
    surface
        Height-map file (see :func:`fingerpad.textures.read_surface`).
    size
        ``(Lx, Ly)`` in m, or text ``"200um,150um"``: the map size of a ``surface``, or the ``size``
        parameter of a generator that takes one (``flat``).
    height_unit
        Unit of the heights in a plain ``surface`` file (``"um"``, ...).
    periodic
        Take the ``surface`` map as one period of a periodic texture.
    periodize
        Mirror the ``surface`` map into a periodic cell (:func:`fingerpad.textures.periodize`).
    fill_missing
        Fill missing (NaN) points of the ``surface`` map.
    """

    name: str | None = None
    params: dict[str, Any] = field(default_factory=dict)
    surface: str | None = None
    size: Any = None
    height_unit: str | None = None
    periodic: bool | None = None
    periodize: bool = False
    fill_missing: bool = False

    def __post_init__(self) -> None:
        if (self.name is None) == (self.surface is None):
            raise FingerpadError("a texture needs exactly one of a generator name or a surface file")

    @property
    def source(self) -> dict[str, Any]:
        if self.surface is not None:
            return {"source": "file", "file": os.path.abspath(self.surface)}
        return {"source": "generator", "file": None}

    def _size(self) -> tuple[float, float] | None:
        if self.size is None:
            return None
        if isinstance(self.size, (tuple, list)) and all(isinstance(v, float) for v in self.size):
            return (float(self.size[0]), float(self.size[-1]))
        return parse_size(_text(self.size))

    def build(self, grid: int | None = None) -> Texture:
        """The :class:`~fingerpad.textures.Texture` (``grid``: points along x, generators only)."""
        size = self._size()
        if self.name is not None:
            for key, value in (("height_unit", self.height_unit), ("periodize", self.periodize),
                               ("fill_missing", self.fill_missing)):
                if value:
                    raise FingerpadError(f"texture {key.replace('_', '-')} applies to surface files only")
            extra: list[str] = []
            for key, value in self.params.items():
                extra += [f"--{key}", _text(value)]
            tex = make_generated_texture(self.name, extra, grid, size)
            if self.periodic is False:
                tex = dataclasses.replace(tex, periodic=False)
            return tex
        if self.params:
            raise FingerpadError(
                f"unknown texture key(s) {', '.join(sorted(self.params))} for a surface file "
                f"(known: {', '.join(_TEXTURE_KEYS)})"
            )
        if grid is not None:
            raise FingerpadError("the grid applies to generated textures; a surface file keeps its own grid")
        tex = read_surface_file(str(self.surface), size, self.height_unit, bool(self.periodic), self.fill_missing)
        if self.periodize:
            from .textures import periodize

            tex = periodize(tex)
        return tex


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
        ``"bem"`` (numerical unit cell), ``"hertz"`` (per-asperity Hertz, spherical caps only) or
        ``"both"``.
    grid
        Grid points along x of the generated cell (``None``: the generator's default).
    tol, max_iter
        Half-space solver settings.
    cache
        Folder of cached unit-cell curves; ``None``: ``$FINGERPAD_CACHE`` or ``~/.cache/fingerpad``;
        ``False``: no cache.
    zones_at
        Load (N) of the zone map; ``None``: the largest load (where most zones are present).
    source
        The study file, if any.
    """

    texture: TextureSpec | Texture
    material_modulus: float | None = None
    material_poisson: float | None = None
    finger: Finger = field(default_factory=lambda: FINGER_PRESETS["default"])
    loads: np.ndarray = field(default_factory=lambda: parse_loads(DEFAULT_LOADS, True))
    model: str = "both"
    grid: int | None = None
    tol: float = 1e-8
    max_iter: int = 5000
    cache: str | os.PathLike[str] | None | bool = None
    zones_at: float | None = None
    source: str | None = None
    _texture: Texture | None = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not isinstance(self.texture, (TextureSpec, Texture)):
            raise FingerpadError(f"texture must be a TextureSpec or a Texture, got {type(self.texture).__name__}")
        if not isinstance(self.finger, Finger):
            raise FingerpadError(f"finger must be a Finger, got {type(self.finger).__name__}")
        self.loads = _positive_loads(np.atleast_1d(np.asarray(self.loads, dtype=float)), "loads")
        if self.model not in MODELS:
            raise FingerpadError(f"model must be one of {', '.join(MODELS)}, got {self.model!r}")
        if self.material_modulus is None:
            if self.material_poisson is not None:
                raise FingerpadError("a material Poisson ratio needs a material modulus (rigid by default)")
        else:
            check_modulus(self.material_modulus, "material modulus")
            if self.material_poisson is None:
                self.material_poisson = 0.35
            check_poisson(self.material_poisson, "material Poisson ratio")
        if self.grid is not None:
            self.grid = _integer(self.grid, "grid", 4)
        if not (isinstance(self.tol, (int, float)) and 0 < self.tol < 1):
            raise FingerpadError(f"tol must lie in (0, 1), got {self.tol!r}")
        self.max_iter = _integer(self.max_iter, "max_iter")
        if self.zones_at is not None and not (math.isfinite(self.zones_at) and self.zones_at > 0):
            raise FingerpadError(f"zones_at must be a positive load, got {self.zones_at!r}")
        if isinstance(self.texture, Texture):
            self._texture = self.texture

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
        from .cache import CurveCache

        if self.cache is False:
            return False
        if self.cache is None or self.cache is True:
            return None
        return CurveCache(Path(os.fspath(self.cache)).expanduser())

    def check(self) -> None:
        """Cheap checks of the whole study before any solving (texture built, model applicable)."""
        tex = self.build_texture()
        if self.model in ("bem", "both") and not tex.periodic:
            what = f"surface {self.texture.surface!r}" if isinstance(self.texture, TextureSpec) and \
                self.texture.surface else f"texture {tex.name!r}"
            raise FingerpadError(
                f"the BEM unit cell needs a periodic texture, but {what} is a finite patch: "
                "if the map is one period give --periodic (periodic = true), else mirror it into a "
                "periodic cell with --periodize (periodize = true, fingerpad.textures.periodize)"
            )
        if self.model == "hertz" and not _is_caps(tex):
            raise FingerpadError(
                f"the Hertz model (Eqs. 3.1-3.6) is for spherical caps (texture 'caps') only; "
                f"texture {tex.name!r} needs --model bem"
            )
        self.reduced_modulus  # noqa: B018 -- validates the moduli


def _is_caps(tex: Texture) -> bool:
    return tex.name == "caps" and all(k in tex.params for k in ("radius", "height", "spacing"))


def hertz_cell_for(texture: Texture, reduced_modulus: float) -> tuple[HertzUnitCell, str | None]:
    """The per-asperity Hertz cell of a spherical-cap texture, and a note for a hexagonal lattice.

    Eq. 3.1 counts asperities on a square lattice (``N = A_fr / lambda^2``). A hexagonal lattice
    of nearest-neighbour spacing ``s`` has one asperity per ``(sqrt(3)/2) s^2``, so it is given the
    square spacing ``lambda = sqrt(sqrt(3)/2) s`` (0.9306 s) of the same asperity density.
    """
    if not _is_caps(texture):
        raise FingerpadError(f"the Hertz model needs a spherical-cap texture ('caps'), got {texture.name!r}")
    p = texture.params
    spacing = float(p["spacing"])
    note = None
    if str(p.get("lattice", "square")) == "hexagonal":
        lam = math.sqrt(math.sqrt(3.0) / 2.0) * spacing
        note = (f"Hertz: hexagonal lattice of spacing {spacing * 1e6:.4g} um taken as the square spacing "
                f"sqrt(sqrt(3)/2) x {spacing * 1e6:.4g} um = {lam * 1e6:.4g} um of the same asperity density (Eq. 3.1)")
    else:
        lam = spacing
    return HertzUnitCell(float(p["radius"]), float(p["height"]), lam, reduced_modulus), note


# ---------------------------------------------------------------------------------------------
# reading study files and merging flags
# ---------------------------------------------------------------------------------------------


def read_study_file(path: str | os.PathLike[str]) -> dict[str, dict[str, Any]]:
    """Read a TOML study file into its sections (keys checked, relative paths resolved).

    Raises
    ------
    FingerpadError
        Unreadable file, TOML syntax error, unknown section or key.
    """
    import tomllib

    p = Path(path)
    if not p.is_file():
        raise FingerpadError(f"cannot read study file {str(p)!r}: " + ("it is a directory" if p.is_dir() else "no such file"))
    try:
        with open(p, "rb") as fh:
            data = tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise FingerpadError(f"study file {str(p)!r}: {exc}") from None
    except OSError as exc:
        raise FingerpadError(f"cannot read study file {str(p)!r}: {exc.strerror or exc}") from None
    unknown = [k for k in data if k not in _SECTION_KEYS]
    if unknown:
        raise FingerpadError(
            f"study file {p.name!r}: unknown section(s) or key(s) {', '.join(sorted(unknown))} "
            f"(sections: {', '.join(f'[{s}]' for s in _SECTION_KEYS)})"
        )
    out: dict[str, dict[str, Any]] = {}
    for section, body in data.items():
        if not isinstance(body, dict):
            raise FingerpadError(f"study file {p.name!r}: {section!r} must be a [{section}] section")
        if section != "texture":  # texture: other keys are the generator's parameters, checked there
            bad = [k for k in body if k not in _SECTION_KEYS[section]]
            if bad:
                raise FingerpadError(
                    f"study file {p.name!r}: unknown key(s) in [{section}]: {', '.join(sorted(bad))} "
                    f"(known: {', '.join(_SECTION_KEYS[section])})"
                )
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


def _texture_spec(section: Mapping[str, Any], where: str) -> tuple[TextureSpec, int | None]:
    sec = dict(section)
    grid = sec.pop("grid", None)
    name, surface = sec.pop("name", None), sec.pop("surface", None)
    if (name is None) == (surface is None):
        raise FingerpadError(f"{where}: give exactly one of a texture name (generator) or a surface file")
    for key, value in (("name", name), ("surface", surface), ("height_unit", sec.get("height_unit"))):
        if value is not None and not isinstance(value, str):
            raise FingerpadError(f"{where} {key}: expected text, got {value!r}")
    spec = TextureSpec(
        name=name,
        surface=surface,
        size=sec.pop("size", None),
        height_unit=sec.pop("height_unit", None),
        periodic=None if sec.get("periodic") is None else _boolean(sec.pop("periodic"), f"{where} periodic"),
        periodize=_boolean(sec.pop("periodize", False), f"{where} periodize"),
        fill_missing=_boolean(sec.pop("fill_missing", False), f"{where} fill_missing"),
    )
    sec.pop("periodic", None)
    spec.params = {k.replace("-", "_"): v for k, v in sec.items()}
    return spec, (None if grid is None else _integer(grid, f"{where} grid", 4))


def study_from_dict(data: Mapping[str, Mapping[str, Any]]) -> Study:
    """Build a :class:`Study` from study-file sections (as :func:`read_study_file` returns them,
    possibly with command-line values merged in). Values: SI numbers or strings with units."""
    src = data.get("_source", {}).get("file")
    where = (lambda s: f"[{s}]") if src is None else (lambda s: f"{Path(src).name} [{s}]")
    unknown = [k for k in data if k not in _SECTION_KEYS and k != "_source"]
    if unknown:
        raise FingerpadError(f"unknown study section(s) {', '.join(sorted(unknown))}")
    for section, body in data.items():
        if section in ("texture", "_source"):
            continue
        bad = [k for k in body if k not in _SECTION_KEYS[section]]
        if bad:
            raise FingerpadError(f"{where(section)}: unknown key(s) {', '.join(sorted(bad))} "
                                 f"(known: {', '.join(_SECTION_KEYS[section])})")

    tex_sec = data.get("texture")
    if not tex_sec:
        raise FingerpadError("no texture given: use --texture NAME (with its --PARAM VALUE options), "
                             "--surface FILE, or a [texture] section in a study file")
    texture, tex_grid = _texture_spec(tex_sec, where("texture"))

    mat = data.get("material", {})
    em, num = _material(mat.get("modulus"), mat.get("poisson"), where("material"))

    fin = dict(data.get("finger", {}))
    preset = fin.pop("preset", "default")
    if not isinstance(preset, str):
        raise FingerpadError(f"{where('finger')} preset: expected a preset name, got {preset!r}")
    finger = get_finger(preset)
    if fin:
        for key, value in fin.items():
            if isinstance(value, bool) or not isinstance(value, (int, float, str)):
                raise FingerpadError(f"{where('finger')} {key}: expected a number or a quantity, got {value!r}")
        finger = finger.with_overrides(**fin)

    lsec = data.get("loads", {})
    log = _boolean(lsec.get("log", True if "range" not in lsec and "values" not in lsec else False),
                   f"{where('loads')} log")
    if "range" in lsec and "values" in lsec:
        raise FingerpadError(f"{where('loads')}: give range or values, not both")
    if "range" in lsec:
        loads = parse_loads(lsec["range"], log, f"{where('loads')} range")
    elif "values" in lsec:
        values = lsec["values"]
        loads = parse_loads(values if isinstance(values, (list, tuple, np.ndarray)) else [values], log,
                            f"{where('loads')} values")
    else:
        loads = parse_loads(DEFAULT_LOADS, True, "loads")
    zones_at = lsec.get("zones_at")
    zones_v = None if zones_at is None else _quantity(zones_at, "force", f"{where('loads')} zones_at")
    if zones_v is not None and zones_v <= 0:
        raise FingerpadError(f"{where('loads')} zones_at: must be a positive load, got {zones_at!r}")

    msec = data.get("model", {})
    kind = msec.get("kind", "both")
    if not (isinstance(kind, str) and kind.strip().lower() in MODELS):
        raise FingerpadError(f"{where('model')} kind: must be one of {', '.join(MODELS)}, got {kind!r}")
    grid = msec.get("grid")
    grid_v = None if grid is None else _integer(grid, f"{where('model')} grid", 4)
    if grid_v is not None and tex_grid is not None and grid_v != tex_grid:
        raise FingerpadError("give the grid once, in [model] (or --grid)")
    grid_v = grid_v if grid_v is not None else tex_grid
    tol = _quantity(msec.get("tol", 1e-8), "none", f"{where('model')} tol")
    if not 0 < tol < 1:
        raise FingerpadError(f"{where('model')} tol: must lie in (0, 1), got {tol!r}")
    max_iter = _integer(msec.get("max_iter", 5000), f"{where('model')} max_iter")
    cache = msec.get("cache")
    if isinstance(cache, bool):
        cache = None if cache else False
    elif cache is not None and not isinstance(cache, (str, os.PathLike)):
        raise FingerpadError(f"{where('model')} cache: expected a folder or false, got {cache!r}")

    return Study(
        texture=texture, material_modulus=em, material_poisson=num, finger=finger, loads=loads,
        model=kind.strip().lower(), grid=grid_v, tol=tol, max_iter=max_iter, cache=cache,
        zones_at=zones_v, source=src,
    )


def load_study_file(path: str | os.PathLike[str]) -> Study:
    """Read and check a TOML study file (see the module docstring); the texture is built lazily."""
    return study_from_dict(read_study_file(path))


# =============================================================================================
# running
# =============================================================================================


@dataclass
class Prediction:
    """Result of :func:`run_study` (SI units).

    Attributes
    ----------
    study, texture
        The inputs and the built texture.
    reduced_modulus
        E1*, Pa (Eq. 3.4).
    bem, hertz
        Curves against load by the BEM unit cell and by per-asperity Hertz (``None`` if not run).
    cell, hertz_cell
        The unit-cell responses used.
    critical_load
        ``{"bem": F, "hertz": F}``: load (N) at which the pad centre reaches the transition
        (BEM: :func:`~fingerpad.coupling.critical_load`; Hertz: Eq. 3.6); ``None`` if that model
        did not run, NaN if no solution in 1e-6 ... 1e3 N.
    full_contact_load
        ``{"bem": F}``: load at which the centre reaches full contact (NaN if never).
    zones
        The zone radii at :attr:`Study.zone_load`.
    pressure_range
        Local pressures (Pa) over which the BEM cell was prepared.
    timings
        ``{"cell": s, "coupling": s}``.
    notes
        Remarks (hexagonal spacing used by Hertz, model skipped, ...).
    """

    study: Study
    texture: Texture
    reduced_modulus: float
    bem: CurvePrediction | None
    hertz: CurvePrediction | None
    cell: Any
    hertz_cell: HertzUnitCell | None
    critical_load: dict[str, float | None]
    full_contact_load: dict[str, float | None]
    zones: dict[str, Any]
    pressure_range: tuple[float, float]
    timings: dict[str, float]
    notes: list[str] = field(default_factory=list)

    @property
    def primary(self) -> CurvePrediction:
        """The BEM curve when computed, else the Hertz curve."""
        return self.bem if self.bem is not None else self.hertz  # type: ignore[return-value]

    @property
    def primary_model(self) -> str:
        return "bem" if self.bem is not None else "hertz"

    @property
    def primary_cell(self) -> Any:
        return self.cell if self.bem is not None else self.hertz_cell

    def states(self, which: str | None = None) -> list[str]:
        """Contact state at the pad centre for each load (``asperity``/``transition``/``full``)."""
        curve, cell = (self.hertz, self.hertz_cell) if which == "hertz" else (self.primary, self.primary_cell)
        assert curve is not None and cell is not None
        return [centre_state(p, cell) for p in 1.5 * curve.load / curve.ridge_area]

    @property
    def unconverged(self) -> int:
        if self.cell is None or not getattr(self.cell, "points", None):
            return 0
        return sum(1 for row in self.cell.points.values() if not row.get("converged", True))


def centre_state(peak_pressure: float, cell: Any) -> str:
    """State of the contact at the pad centre for its pressure ``1.5 F/A_fr`` (Pa)."""
    pt, pf = float(cell.transition_pressure), float(cell.full_contact_pressure)
    if peak_pressure >= pf:
        return "full"
    if peak_pressure >= pt:
        return "transition"
    return "asperity"


def _load_at_centre_pressure(finger: Finger, pressure: float) -> float:
    """Load (N) at which the centre pressure ``1.5 F / A_fr(F)`` equals ``pressure`` (NaN if none)."""
    from scipy.optimize import brentq

    from .coupling import DEFAULT_LOAD_RANGE

    if not (math.isfinite(pressure) and pressure > 0):
        return math.nan
    lo, hi = DEFAULT_LOAD_RANGE

    def g(f: float) -> float:
        return 1.5 * f / float(finger.ridge_area(f)) - pressure

    try:
        if np.sign(g(lo)) == np.sign(g(hi)):
            return math.nan
        return float(brentq(g, lo, hi, rtol=1e-12))
    except (FingerpadError, ValueError):
        return math.nan


def _zones(study: Study, cell: Any, hertz_cell: Any) -> dict[str, Any]:
    """Zone radii of the ridge-contact disc at the zone load (primary cell; Hertz radius too)."""
    from .coupling import couple

    f = study.zone_load
    ar = float(study.finger.ridge_area(f))
    res = couple(f, ar, cell)
    out = {
        "load": f,
        "ridge_area": ar,
        "ridge_radius": float(res.ridge_radius),
        "transition_radius": float(res.transition_radius),
        "full_contact_radius": float(res.full_contact_radius),
        "mean_pressure": float(res.mean_pressure),
        "peak_pressure": float(res.peak_pressure),
        "area_ratio": float(res.area_ratio),
        "contact_state": centre_state(float(res.peak_pressure), cell),
        "hertz_transition_radius": None,
    }
    if hertz_cell is not None and hertz_cell is not cell:
        out["hertz_transition_radius"] = float(couple(f, ar, hertz_cell).transition_radius)
    return out


def run_study(study: Study, progress: Callable[[int, int], None] | None = None) -> Prediction:
    """Run the prediction of ``study`` (see the module docstring).

    Parameters
    ----------
    study
        The inputs.
    progress
        ``progress(i, n)`` after each unit-cell solve (BEM only; not called when cached).

    Raises
    ------
    FingerpadError
        Non-periodic texture for the BEM (suggests ``periodize``), Hertz on a texture that is not
        spherical caps, bad values.
    """
    from .unitcell import BEMUnitCell

    study.check()
    tex = study.build_texture()
    finger = study.finger
    e1 = study.reduced_modulus
    loads = study.loads
    p_mean = loads / np.asarray(finger.ridge_area(loads), dtype=float)
    p_range = (P_LOW * float(p_mean.min()), P_HIGH * float(p_mean.max()))
    notes: list[str] = []

    run_hertz = study.model in ("hertz", "both") and _is_caps(tex)
    if study.model == "both" and not run_hertz:
        notes.append(f"Hertz (Eqs. 3.1-3.6) applies to spherical caps only: texture {tex.name!r} runs the BEM only")
    hertz_cell = None
    if run_hertz:
        hertz_cell, note = hertz_cell_for(tex, e1)
        if note:
            notes.append(note)

    cell = bem = hertz = None
    t_cell = t_coupling = 0.0
    if study.model in ("bem", "both"):
        t0 = time.perf_counter()
        cell = BEMUnitCell(tex, e1, tol=study.tol, max_iter=study.max_iter, cache=study.curve_cache())
        cell.prepare(*p_range, progress=progress)
        t_cell = time.perf_counter() - t0
        t0 = time.perf_counter()
        bem = predict_curve(loads, finger, cell)
        t_coupling += time.perf_counter() - t0
        if cell.flat:
            notes.append("flat texture: full contact at any load (A_re = A_fr), no critical load")
    if hertz_cell is not None:
        t0 = time.perf_counter()
        hertz = predict_curve(loads, finger, hertz_cell)
        t_coupling += time.perf_counter() - t0

    crit: dict[str, float | None] = {
        "bem": bem.critical_load if bem is not None else None,
        "hertz": hertz.critical_load_hertz if hertz is not None else None,
    }
    full: dict[str, float | None] = {"bem": None}
    if cell is not None and not cell.flat:
        full["bem"] = _load_at_centre_pressure(finger, cell.full_contact_pressure)
    elif cell is not None:
        full["bem"] = 0.0
    primary_cell = cell if cell is not None else hertz_cell
    pred = Prediction(
        study=study, texture=tex, reduced_modulus=e1, bem=bem, hertz=hertz, cell=cell, hertz_cell=hertz_cell,
        critical_load=crit, full_contact_load=full, zones=_zones(study, primary_cell, hertz_cell),
        pressure_range=p_range, timings={"cell": t_cell, "coupling": t_coupling}, notes=notes,
    )
    if pred.unconverged:
        notes.append(f"{pred.unconverged} unit-cell solve(s) did not reach the tolerance {study.tol:g}")
    return pred


# =============================================================================================
# outputs
# =============================================================================================

#: Units of the quantities in predict.json / predict.nc.
OUTPUT_UNITS = {
    "load": "N", "critical_load": "N", "full_contact_load": "N",
    "gross_area": "m^2", "ridge_area": "m^2", "real_area": "m^2", "area_ratio": "1 (A_re / A_fr)",
    "ridge_radius": "m", "transition_radius": "m", "full_contact_radius": "m",
    "mu": "1", "mu_ref": "1", "mu_normalised": "1 (mu / mu_ref)",
    "transition_pressure": "Pa", "full_contact_pressure": "Pa", "pressure": "Pa", "modulus": "Pa",
    "interpolation_error": "1 (absolute error of psi)", "seconds": "s",
    "contact_state": "state at the pad centre: asperity, transition or full",
}


def prediction_json(pred: Prediction) -> dict[str, Any]:
    """The content of ``predict.json`` (SI units, listed in its ``units``; NaN and inf -> ``None``).

    * ``critical_load``: ``{"bem": F, "hertz": F}`` (N, ``None`` for a model not run);
      ``full_contact_load``: ``{"bem": F}``, load at which the pad centre reaches full contact;
    * ``model``: the model of ``results`` (``bem`` when run, else ``hertz``);
    * ``inputs``: texture (name, description, params, size, grid, periodic, source file),
      material, finger, E1* (``reduced_modulus``), loads, model, numerics, cache, zones_at;
    * ``cell``: the unit cell of ``results``: ``transition_pressure``, ``full_contact_pressure``
      (Pa), ``interpolation_error`` (of psi), ``grid``, ``nodes``, ``pressure_range`` (Pa),
      ``solves`` (done now; 0 when cached), ``cached``, ``unconverged``, ``seconds``;
      ``hertz_cell``: radius, height, (effective square) spacing, lattice spacing and lattice,
      critical asperity force (N) and transition pressure (Pa) of the Hertz cell;
    * ``zones``: zone radii (m) and centre state at ``inputs.zones_at``;
    * ``timings``: seconds for the unit cell and for the coupling; ``notes``: remarks;
    * ``results``: one entry per load with ``load``, ``gross_area``, ``ridge_area``,
      ``real_area``, ``area_ratio``, ``ridge_radius``, ``transition_radius``,
      ``full_contact_radius``, ``mu``, ``mu_ref``, ``mu_normalised``, ``contact_state`` (at the
      pad centre) and, for model ``both`` on caps, ``hertz``: ``real_area``, ``area_ratio``,
      ``transition_radius``, ``mu``, ``mu_normalised``, ``contact_state``.
    """
    from . import __version__
    from .io import to_jsonable
    from .textures import describe

    study, tex, cur = pred.study, pred.texture, pred.primary
    states = pred.states()
    hstates = pred.states("hertz") if pred.hertz is not None else None
    results = []
    for i in range(cur.load.size):
        row: dict[str, Any] = {
            "load": cur.load[i],
            "gross_area": cur.gross_area[i],
            "ridge_area": cur.ridge_area[i],
            "real_area": cur.real_area[i],
            "area_ratio": cur.area_ratio[i],
            "ridge_radius": cur.ridge_radius[i],
            "transition_radius": cur.transition_radius[i],
            "full_contact_radius": cur.full_contact_radius[i],
            "mu": cur.mu[i],
            "mu_ref": None if cur.mu_ref is None else cur.mu_ref[i],
            "mu_normalised": None if cur.mu_normalised is None else cur.mu_normalised[i],
            "contact_state": states[i],
        }
        if pred.bem is not None and pred.hertz is not None:
            h = pred.hertz
            row["hertz"] = {
                "real_area": h.real_area[i], "area_ratio": h.area_ratio[i],
                "transition_radius": h.transition_radius[i], "mu": h.mu[i],
                "mu_normalised": None if h.mu_normalised is None else h.mu_normalised[i],
                "contact_state": hstates[i] if hstates else None,
            }
        results.append(row)

    if pred.cell is not None:
        c = pred.cell
        cell = {
            "model": "bem",
            "transition_pressure": c.transition_pressure,
            "full_contact_pressure": c.full_contact_pressure,
            "interpolation_error": None if c.flat else c.interpolation_error,
            "grid": list(tex.shape),
            "nodes": len(c.points),
            "pressure_range": list(pred.pressure_range),
            "solves": c.solves,
            "cached": c.solves == 0,
            "unconverged": pred.unconverged,
            "seconds": pred.timings["cell"],
        }
    else:
        h = pred.hertz_cell
        assert h is not None
        cell = {
            "model": "hertz", "transition_pressure": h.transition_pressure,
            "full_contact_pressure": h.full_contact_pressure, "interpolation_error": None,
            "grid": None, "nodes": 0, "pressure_range": None, "solves": 0, "cached": False,
            "unconverged": 0, "seconds": pred.timings["cell"],
        }
    hertz_cell = None
    if pred.hertz_cell is not None:
        h = pred.hertz_cell
        hertz_cell = {"radius": h.radius, "height": h.height, "spacing": h.spacing,
                      "lattice_spacing": float(tex.params.get("spacing", h.spacing)),
                      "lattice": tex.params.get("lattice", "square"),
                      "critical_asperity_force": h.critical_force,
                      "transition_pressure": h.transition_pressure}
    texture = {
        "name": tex.name, "description": describe(tex), **study.texture_source,
        "params": dict(tex.params), "size": list(tex.size), "grid": list(tex.shape),
        "periodic": bool(tex.periodic),
    }
    inputs = {
        "study_file": study.source,
        "texture": texture,
        "material": {"modulus": study.material_modulus, "poisson": study.material_poisson,
                     "rigid": study.material_modulus is None},
        "finger": study.finger.as_dict(),
        "reduced_modulus": pred.reduced_modulus,
        "loads": list(study.loads),
        "model": study.model,
        "grid": study.grid,
        "tol": study.tol,
        "max_iter": study.max_iter,
        "cache": None if study.cache in (None, False, True) else os.fspath(study.cache),
        "zones_at": study.zone_load,
        "fingerpad_version": __version__,
    }
    payload = {
        "critical_load": dict(pred.critical_load),
        "full_contact_load": dict(pred.full_contact_load),
        "model": pred.primary_model,
        "units": OUTPUT_UNITS,
        "inputs": inputs,
        "cell": cell,
        "hertz_cell": hertz_cell,
        "zones": pred.zones,
        "timings": {"cell": pred.timings["cell"], "coupling": pred.timings["coupling"]},
        "notes": list(pred.notes),
        "results": results,
    }
    return to_jsonable(payload)


def prediction_dataset(pred: Prediction):
    """The :class:`xarray.Dataset` of ``predict.nc``: curves along ``load``, psi(p) along
    ``cell_pressure``; every variable has a ``units`` attribute, inputs are global attributes."""
    import xarray as xr

    from . import __version__
    from .io import flatten_attrs

    cur = pred.primary
    long = {
        "gross_area": "gross contact area A_g", "ridge_area": "ridge contact area A_fr",
        "real_area": "real contact area A_re", "area_ratio": "A_re / A_fr",
        "real_pressure": "mean real contact pressure F / A_re", "ridge_radius": "ridge contact radius a_fr",
        "transition_radius": "outer radius of the zone past the transition",
        "full_contact_radius": "outer radius of the full-contact zone",
        "mu": "friction coefficient on the texture", "mu_ref": "friction coefficient on the flat reference",
        "mu_normalised": "mu / mu_ref",
    }
    units = {"real_pressure": "Pa", "area_ratio": "1", "mu_normalised": "1", "mu": "1", "mu_ref": "1"}
    data: dict[str, Any] = {}

    def add(prefix: str, curve: CurvePrediction, names: Sequence[str], label: str) -> None:
        for name in names:
            value = getattr(curve, name)
            if value is None:
                continue
            u = units.get(name, OUTPUT_UNITS.get(name, "1")).split(" ")[0]
            data[prefix + name] = xr.Variable(("load",), np.asarray(value, float),
                                              {"units": u, "long_name": f"{long[name]} ({label})"})

    add("", cur, list(long), pred.primary_model)
    data["contact_state"] = xr.Variable(("load",), np.array(pred.states(), dtype=object),
                                        {"units": "1", "long_name": "contact state at the pad centre"})
    if pred.bem is not None and pred.hertz is not None:
        add("hertz_", pred.hertz, ["real_area", "area_ratio", "transition_radius", "mu", "mu_normalised"], "hertz")
        data["hertz_contact_state"] = xr.Variable(("load",), np.array(pred.states("hertz"), dtype=object),
                                                  {"units": "1", "long_name": "contact state at the pad centre (hertz)"})
    coords = {"load": xr.Variable("load", np.asarray(cur.load, float), {"units": "N", "long_name": "normal load"})}
    if pred.cell is not None and not pred.cell.flat:
        nodes = pred.cell.curve()
        coords["cell_pressure"] = xr.Variable("cell_pressure", nodes["pressure"],
                                              {"units": "Pa", "long_name": "mean nominal pressure on the unit cell"})
        data["cell_contact_fraction"] = xr.Variable(("cell_pressure",), nodes["contact_fraction"],
                                                    {"units": "1", "long_name": "psi: real-to-nominal area fraction of the cell (BEM nodes)"})
        data["cell_mean_gap"] = xr.Variable(("cell_pressure",), nodes["mean_gap"], {"units": "m", "long_name": "mean gap"})
        data["cell_max_pressure"] = xr.Variable(("cell_pressure",), nodes["max_pressure"],
                                                {"units": "Pa", "long_name": "largest local pressure"})
        data["cell_contact_state"] = xr.Variable(("cell_pressure",), np.array([str(s) for s in nodes["contact_state"]], dtype=object),
                                                 {"units": "1", "long_name": "contact state of the cell"})
    elif pred.hertz_cell is not None:
        ps = np.geomspace(*pred.pressure_range, 49)
        coords["cell_pressure"] = xr.Variable("cell_pressure", ps, {"units": "Pa", "long_name": "mean nominal pressure on the unit cell"})
        data["cell_contact_fraction"] = xr.Variable(("cell_pressure",), pred.hertz_cell.contact_fraction(ps),
                                                    {"units": "1", "long_name": "psi of the Hertz cell (analytic, sampled)"})
    payload = prediction_json(pred)
    attrs = {"title": "fingerpad prediction: areas and friction against load", "Conventions": "CF-1.8",
             "source": f"fingerpad {__version__}", "units_system": "SI"}
    attrs.update(flatten_attrs({
        "model": payload["model"],
        "critical_load": payload["critical_load"], "full_contact_load": payload["full_contact_load"],
        "cell": {k: v for k, v in payload["cell"].items()},
        "inputs": {k: v for k, v in payload["inputs"].items() if k != "loads"},
        "notes": payload["notes"],
    }))
    return xr.Dataset(data, coords=coords, attrs=attrs)


# ---------------------------------------------------------------------------------------------
# figures (matplotlib Figure + Agg canvas; fixed margins: a layout engine costs seconds)
# ---------------------------------------------------------------------------------------------

_STATE_FILL = {"asperity": "#dbe9f6", "transition": "#fde3c8", "full": "#f7c9c9"}


def _state_ranges(pred: Prediction) -> list[tuple[str, float, float]]:
    """Load intervals of the centre states within the plotted load range."""
    lo, hi = float(pred.primary.load.min()), float(pred.primary.load.max())
    fc = pred.critical_load[pred.primary_model]
    ff = pred.full_contact_load.get(pred.primary_model)
    fc = 0.0 if pred.cell is not None and pred.cell.flat else fc
    edges = [("asperity", 0.0), ("transition", fc if fc is not None and math.isfinite(fc) else math.inf),
             ("full", ff if ff is not None and math.isfinite(ff) else math.inf)]
    out = []
    for k, (state, start) in enumerate(edges):
        end = edges[k + 1][1] if k + 1 < len(edges) else math.inf
        a, b = max(start, lo), min(end, hi)
        if b > a:
            out.append((state, a, b))
    return out


def _shade(ax: Any, pred: Prediction) -> None:
    for state, a, b in _state_ranges(pred):
        ax.axvspan(a, b, color=_STATE_FILL[state], alpha=0.8, lw=0, zorder=0, label=f"centre: {state}")


def _mark_critical(ax: Any, pred: Prediction) -> None:
    lo, hi = float(pred.primary.load.min()), float(pred.primary.load.max())
    for model, style in (("bem", "-"), ("hertz", "--")):
        f = pred.critical_load.get(model)
        if f is not None and math.isfinite(f) and lo <= f <= hi:
            ax.axvline(f, color="k", ls=style, lw=0.9, label=f"F_crit {model} = {f:.3g} N")


def _load_axis(ax: Any, f: np.ndarray) -> None:
    """Log load axis (for ranges over 5x) with plain tick labels at 1-2-5 steps."""
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter

    lo, hi = float(f.min()), float(f.max())
    ax.set_xlim(lo, hi)
    if not (lo > 0 and hi / lo > 5):
        return
    ax.set_xscale("log")
    nice = [m * 10.0**k for k in range(-4, 5) for m in (1, 2, 5)]
    ticks = [t for t in nice if lo * (1 - 1e-9) <= t <= hi * (1 + 1e-9)]
    if ticks and hi / ticks[-1] > 1.5:
        ticks.append(hi)
    if ticks and ticks[0] / lo > 1.5:
        ticks.insert(0, lo)
    if len(ticks) >= 2:
        ax.xaxis.set_major_locator(FixedLocator(ticks))
        ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.xaxis.set_minor_formatter(NullFormatter())


def figure_areas(pred: Prediction):
    from matplotlib.figure import Figure

    cur = pred.primary
    f = cur.load
    fig = Figure(figsize=(7.0, 5.0))
    fig.subplots_adjust(left=0.12, right=0.97, bottom=0.11, top=0.9)
    ax = fig.subplots()
    ax.plot(f, cur.gross_area * 1e6, "k-", label="gross A_g")
    ax.plot(f, cur.ridge_area * 1e6, "-", color="tab:green", label="ridge A_fr")
    ax.plot(f, cur.real_area * 1e6, "-", color="tab:red", lw=2, label=f"real A_re ({pred.primary_model})")
    if pred.bem is not None and pred.hertz is not None:
        ax.plot(f, pred.hertz.real_area * 1e6, "--", color="tab:red", label="real A_re (hertz)")
    _mark_critical(ax, pred)
    _load_axis(ax, f)
    ax.set_yscale("log")
    ax.set_xlabel("normal load F (N)")
    ax.set_ylabel("contact area (mm²)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small", loc="lower right")
    ax.set_title(f"Contact areas: {pred.texture.name}, E1* = {pred.reduced_modulus / 1e3:.4g} kPa, "
                 f"finger {pred.study.finger.name}", fontsize="medium")
    return fig


def figure_friction(pred: Prediction):
    from matplotlib.figure import Figure

    cur = pred.primary
    f = cur.load
    fig = Figure(figsize=(12.0, 4.8))
    fig.subplots_adjust(left=0.065, right=0.985, bottom=0.12, top=0.88, wspace=0.22)
    ax_mu, ax_n = fig.subplots(1, 2)
    for ax in (ax_mu, ax_n):
        _shade(ax, pred)
        _mark_critical(ax, pred)
    ax_mu.plot(f, cur.mu, "-", color="tab:red", lw=2, label=f"texture ({pred.primary_model})")
    if cur.mu_ref is not None:
        ax_mu.plot(f, cur.mu_ref, "-", color="k", label="flat reference")
    if cur.mu_normalised is not None:
        ax_n.plot(f, cur.mu_normalised, "-", color="tab:red", lw=2, label=pred.primary_model)
    if pred.bem is not None and pred.hertz is not None:
        ax_mu.plot(f, pred.hertz.mu, "--", color="tab:red", label="texture (hertz)")
        if pred.hertz.mu_normalised is not None:
            ax_n.plot(f, pred.hertz.mu_normalised, "--", color="tab:red", label="hertz")
    ax_mu.set_ylabel("friction coefficient μ (-)")
    ax_n.set_ylabel("μ / μ_ref = A_re,tex / A_re,ref (-)")
    ax_n.set_ylim(0, max(1.05, float(np.nanmax(cur.mu_normalised)) * 1.05 if cur.mu_normalised is not None else 1.05))
    ax_mu.set_title("friction against load (shaded: contact state at the pad centre)", fontsize="medium")
    ax_n.set_title("normalised friction", fontsize="medium")
    for ax in (ax_mu, ax_n):
        _load_axis(ax, f)
        ax.set_xlabel("normal load F (N)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize="small")
    fig.suptitle(f"{pred.texture.name} on finger {pred.study.finger.name}, E1* = {pred.reduced_modulus / 1e3:.4g} kPa")
    return fig


def figure_zones(pred: Prediction):
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle

    from .finger import pad_pressure
    from .plotting import STATE_COLOURS

    z = pred.zones
    a, at, af = z["ridge_radius"], z["transition_radius"], z["full_contact_radius"]
    fig = Figure(figsize=(11.5, 5.0))
    fig.subplots_adjust(left=0.06, right=0.935, bottom=0.12, top=0.86, wspace=0.22)
    ax_map, ax_r = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1, 1.3]})
    from matplotlib.colors import to_rgb

    s = 1e3
    for radius, inner, state in ((a, at, "asperity"), (at, af, "transition"), (af, 0.0, "full")):
        if radius > 0:
            pale = tuple(1.0 - 0.55 * (1.0 - c) for c in to_rgb(STATE_COLOURS[state]))
            span = f"{inner * s:.3g} < r < {radius * s:.3g} mm" if inner > 0 else f"r < {radius * s:.3g} mm"
            ax_map.add_patch(Circle((0, 0), radius * s, color=pale, lw=0, label=f"{state}: {span}"))
            ax_map.add_patch(Circle((0, 0), radius * s, fill=False, color="k", lw=0.8))
    ht = z.get("hertz_transition_radius")
    if ht:
        ax_map.add_patch(Circle((0, 0), ht * s, fill=False, color="k", ls="--", lw=1.2,
                                label=f"hertz transition: r < {ht * s:.3g} mm"))
    for radius, ang in ((a, 60), (at, 30), (af, 0)):
        if radius > 0:
            t = math.radians(ang)
            ax_map.annotate(f"{radius * s:.3g} mm", (radius * s * math.cos(t), radius * s * math.sin(t)),
                            xytext=(4, 4), textcoords="offset points", fontsize="small")
    lim = 1.15 * a * s
    ax_map.set_xlim(-lim, lim)
    ax_map.set_ylim(-lim, lim)
    ax_map.set_aspect("equal")
    ax_map.set_xlabel("x (mm)")
    ax_map.set_ylabel("y (mm)")
    ax_map.legend(fontsize="small", loc="upper left")
    ax_map.set_title(f"ridge contact disc at F = {z['load']:.3g} N", fontsize="medium")

    r = np.linspace(0, a, 300)
    p = np.asarray(pad_pressure(r, z["load"], z["ridge_area"]), float)
    cell = pred.primary_cell
    psi = np.asarray(cell.contact_fraction(p), float)
    for lo, hi, state in ((at, a, "asperity"), (af, at, "transition"), (0, af, "full")):
        if hi > lo:
            ax_r.axvspan(lo * s, hi * s, color=_STATE_FILL[state], alpha=0.8, lw=0)
    ax_r.plot(r * s, p / 1e3, "k-", label="pad pressure p(r) (Eq. 3.7)")
    ax_r.set_xlabel("radius r (mm)")
    ax_r.set_ylabel("pressure (kPa)")
    ax2 = ax_r.twinx()
    ax2.plot(r * s, psi, "-", color="tab:red", label=f"ψ(p(r)) ({pred.primary_model})")
    ax2.set_ylim(0, 1.02)
    ax2.set_ylabel("local real-area fraction ψ (-)")
    ax_r.set_xlim(0, a * s)
    ax_r.set_ylim(bottom=0)
    h1, l1 = ax_r.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax_r.legend(h1 + h2, l1 + l2, fontsize="small", loc="lower left")
    ax_r.set_title(f"A_re/A_fr = {z['area_ratio']:.3g}, centre: {z['contact_state']}", fontsize="medium")
    fig.suptitle(f"Contact zones of {pred.texture.name} ({pred.primary_model}), finger {pred.study.finger.name}")
    return fig


def write_outputs(pred: Prediction, out_dir: str | os.PathLike[str], *, dpi: int = 110) -> list[Path]:
    """Write :data:`OUTPUT_FILES` into ``out_dir`` (created if missing): all of them or none.

    Every file is first written under a hidden temporary name in ``out_dir`` and the set is moved
    into place only when all are complete.
    """
    import json

    from . import io as fio

    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise FingerpadError(f"output {str(out)!r} exists and is not a directory")
    created = not out.exists()
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise FingerpadError(f"cannot create output directory {str(out)!r}: {exc.strerror or exc}") from None
    if not os.access(out, os.W_OK):
        raise FingerpadError(f"output directory {str(out)!r} is not writable")
    staging = fio.Staging()
    paths = [out / name for name in OUTPUT_FILES]
    try:
        text = json.dumps(prediction_json(pred), indent=2) + "\n"
        staging.stage(str(paths[0]), lambda tmp: fio.write_text(tmp, text))
        ds = prediction_dataset(pred)
        staging.stage(str(paths[1]), lambda tmp: fio.to_netcdf(ds, tmp))
        for path, maker in zip(paths[2:], (figure_areas, figure_friction, figure_zones), strict=True):
            fig = maker(pred)
            staging.stage(str(path), lambda tmp, fig=fig: fio.atomic_write(tmp, lambda t: fig.savefig(t, format="png", dpi=dpi)))
        staging.commit()
    except BaseException:
        staging.discard()
        if created:
            with contextlib.suppress(OSError):
                out.rmdir()
        raise
    return paths

