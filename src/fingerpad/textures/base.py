"""The texture data type, declared generator parameters and the registry of texture families.

A texture *family* (spherical caps, ridges, ...) lives in one file of this package that defines
``FAMILIES = (TextureFamily(...),)``: the generator function, its parameters declared with their
kind and unit (:class:`Param`, the package's one parameter declaration,
:class:`fingerpad.params.Param`), and, where it applies, the asperity seen by the per-asperity
Hertz model. :mod:`fingerpad.textures` collects every such file, so a new texture is added by
adding one file. The command line and study files read parameter values through the declared
kinds (``--orientation 30`` is 30 degrees, ``--radius 50um`` a length), never by guessing from
names.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, Protocol, runtime_checkable

import lazy_loader

# NumPy loads on first use: listing the texture families (`fingerpad textures`) must start fast.
np = lazy_loader.load("numpy")

from ..errors import FingerpadError
from ..params import KINDS, REQUIRED, parse_angle  # noqa: F401 -- re-exported by fingerpad.textures
from ..params import Param as _Param
from .geometry import fmt_length, parse_size


@dataclass(frozen=True, eq=False)
class Texture:
    """A height map over a rectangle of known physical size.

    Attributes
    ----------
    heights
        2-D float array (nx, ny), metres, z positive toward the skin.
    size
        (Lx, Ly) physical size of the map, metres.
    periodic
        True for a unit cell of a periodic texture; False for a finite patch (measured map,
        single asperity), solved with zero-padded linear convolution.
    name
        Generator or file name.
    params
        Generator parameters in SI units (recorded as NetCDF attributes).
    family
        Name of the :class:`TextureFamily` that generated the map (``None`` for measured maps
        and hand-made arrays); it says which analytic models (e.g. the Hertz cell) apply.
    base_level
        Height (m) at or below which a pixel belongs to the texture's base (the level whose
        touching starts the *transition* state). ``None``: the lowest level itself (within
        1e-6 of the peak-to-valley height), right for generated maps; measured maps set it from
        their height distribution (:func:`~fingerpad.textures.read_surface`, ``base_quantile``),
        since on a noisy base the single lowest pixel is never touched.
    """

    heights: np.ndarray
    size: tuple[float, float]
    periodic: bool = True
    name: str = "custom"
    params: dict[str, Any] = field(default_factory=dict)
    family: str | None = None
    base_level: float | None = None

    def __post_init__(self) -> None:
        h = np.asarray(self.heights, dtype=float)
        if h.ndim == 1:
            h = h[:, None]
        if h.ndim != 2:
            raise FingerpadError(f"texture {self.name!r}: height map must be 2-D, got shape {h.shape}")
        if h.size == 0:
            raise FingerpadError(f"texture {self.name!r}: empty height map")
        if not np.all(np.isfinite(h)):
            bad = int(np.count_nonzero(~np.isfinite(h)))
            raise FingerpadError(f"texture {self.name!r}: height map holds {bad} NaN or infinite values")
        lx, ly = (float(s) for s in self.size)
        if not (math.isfinite(lx) and math.isfinite(ly) and lx > 0 and ly > 0):
            raise FingerpadError(f"texture {self.name!r}: size must be positive, got {self.size!r}")
        object.__setattr__(self, "heights", h)
        object.__setattr__(self, "size", (lx, ly))

    @property
    def shape(self) -> tuple[int, int]:
        return self.heights.shape  # type: ignore[return-value]

    @property
    def spacing(self) -> tuple[float, float]:
        """Grid spacing (dx, dy), metres."""
        return self.size[0] / self.shape[0], self.size[1] / self.shape[1]

    @property
    def area(self) -> float:
        """Nominal (projected) area of the map, m^2."""
        return self.size[0] * self.size[1]

    @property
    def peak_to_valley(self) -> float:
        return float(self.heights.max() - self.heights.min())

    def base_mask(self) -> np.ndarray:
        """Boolean (nx, ny) mask of the pixels of the base level (see ``base_level``)."""
        return base_mask(self)

    def coordinates(self) -> tuple[np.ndarray, np.ndarray]:
        """1-D pixel coordinates x (nx,) and y (ny,), metres."""
        dx, dy = self.spacing
        return np.arange(self.shape[0]) * dx, np.arange(self.shape[1]) * dy


# ------------------------------------------------------------------------------------------------
# Declared parameters
# ------------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Param(_Param):
    """A declared parameter of a texture generator: a :class:`fingerpad.params.Param` whose
    lengths read from user input are warned about outside the range of texture lengths
    (10 nm - 10 mm, a forgotten unit). Same fields, same positional order."""

    plausible: str | None = "texture length"

    def parse_size(self, value: Any, label: str) -> tuple[float, float]:
        """A texture's size: a number (square), a pair, or ``"Lx,Ly"`` text, m."""
        return parse_size(value, label)


# ------------------------------------------------------------------------------------------------
# Families and their registry
# ------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class HertzAsperity:
    """What the per-asperity Hertz model (Eqs. 3.1-3.6) needs from a texture (SI units).

    ``spacing`` is the square-lattice spacing of Eq. 3.1 (for other lattices, the square
    spacing of the same asperity density); ``note`` says how it was obtained, if not directly.
    """

    radius: float
    height: float
    spacing: float
    lattice_spacing: float
    lattice: str = "square"
    note: str | None = None


# ------------------------------------------------------------------------------------------------
# What the compliant-asperity (deflection) model needs of a family: its asperity section
# ------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Section:
    """One asperity section in SI units and how the cell's nominal pressure loads it.

    ``load_per_pressure``: P / p (m), the section's normal load per unit depth per nominal
    pressure. ``shear_factor``: the fraction of the shear level acting in the section's plane.
    """

    profile: str
    half_width: float
    height: float
    period: float
    load_per_pressure: float
    shear_factor: float = 1.0


@runtime_checkable
class Geometry(Protocol):
    """What the deflection model needs of a texture's asperities (returned by the texture
    family's ``deflection`` hook, :attr:`TextureFamily.deflection`).

    ``section(direction_deg)``: the :class:`Section` sheared when sliding at that direction;
    ``principal_directions()``: (parallel, perpendicular) directions in degrees;
    ``tip_radii()``: the asperity tip's principal radii of curvature (m) and the direction of the
    first (radians from x), or ``None`` where the tip contact is not elliptical (the hysteresis
    factor is then 1). Fields are SI and read by ``dataclasses.fields`` for outputs.
    """

    def section(self, direction_deg: float) -> Section: ...

    def principal_directions(self) -> tuple[float, float]: ...

    def tip_radii(self) -> tuple[float, float, float] | None: ...


def section_radians(direction_deg: float) -> float:
    """Radians of a sliding direction given in degrees (finite)."""
    if not math.isfinite(direction_deg):
        raise FingerpadError("direction must be a finite angle in degrees")
    return math.radians(direction_deg)



@dataclass(frozen=True)
class TextureFamily:
    """A texture generator with its declared parameters.

    Attributes
    ----------
    name
        Name on the command line and in study files (``--texture caps``).
    generator
        Function of keyword arguments returning a periodic :class:`Texture`.
    params
        Declared parameters, in the generator's keyword names.
    summary
        One line for ``fingerpad textures``.
    hertz
        ``hertz(texture) -> HertzAsperity``, for families whose asperities the per-asperity
        Hertz model (Eqs. 3.1-3.6) describes (an asperity radius and height); ``None`` otherwise.
    features
        ``features(texture) -> (lateral size, height)`` in m: the smallest lateral size of a
        feature (a cap's base diameter, a ridge's width) and its height, for manufacturing
        limits (minimum feature, aspect ratio) in inverse design; ``None`` if not declared.
    deflection
        ``deflection(params) -> geometry`` from the texture's ``params`` (SI) to the asperity
        geometry of the compliant-asperity model (:class:`Geometry`:
        its section per sliding direction), for families that model supports; ``None`` otherwise.
    """

    name: str
    generator: Callable[..., Texture]
    params: tuple[Param, ...]
    summary: str
    hertz: Callable[[Texture], HertzAsperity] | None = None
    features: Callable[[Texture], tuple[float, float]] | None = None
    deflection: Callable[[Mapping[str, Any]], Any] | None = None

    def param(self, name: str) -> Param | None:
        return next((p for p in self.params if p.name == name), None)

    @property
    def grid_param(self) -> Param | None:
        return next((p for p in self.params if p.kind == "grid"), None)

    def user_params(self) -> tuple[Param, ...]:
        """Parameters given as ``--NAME VALUE`` (not the grid, which is ``--grid``)."""
        return tuple(p for p in self.params if p.kind != "grid")

    def build(
        self,
        values: Mapping[str, Any],
        *,
        grid: int | None = None,
        size: Any = None,
        label: Callable[[Param], str] | None = None,
    ) -> Texture:
        """Generate the texture from user values (text or study-file values), read through the
        declared kinds.

        Parameters
        ----------
        values
            Parameter values by keyword name (``semi_axis_x``), as text or numbers.
        grid
            Grid points along x (``--grid``), or ``None`` for the family's default.
        size
            The ``size`` parameter of families that take one (``flat``).
        label
            How to name a parameter in messages (default: its option, ``--radius``).

        Raises
        ------
        FingerpadError
            Unknown, missing or malformed parameters (the message lists the family's options),
            or any error of the generator.
        """
        name_of = label or (lambda p: p.option)
        kwargs: dict[str, Any] = {}
        for key, value in values.items():
            par = self.param(key)
            if par is None or par.kind == "grid":
                known = ", ".join(p.option for p in self.user_params()) or "none"
                shown = "--" + str(key).replace("_", "-")
                hint = " (give the grid once, as --grid)" if par is not None else ""
                raise FingerpadError(f"texture {self.name!r} has no parameter {shown}{hint} (its parameters: {known})")
            kwargs[key] = par.parse(value, name_of(par))
        if grid is not None:
            gp = self.grid_param
            if gp is None:
                raise FingerpadError(f"texture {self.name!r} takes no grid size")
            kwargs[gp.name] = grid
        if size is not None:
            if self.param("size") is None:
                raise FingerpadError(
                    f"--size applies to --surface files; texture {self.name!r} sets its own cell size from its parameters"
                )
            kwargs["size"] = size
        missing = [name_of(p) for p in self.params if p.required and p.name not in kwargs]
        if missing:
            raise FingerpadError(f"texture {self.name!r} needs {', '.join(missing)}")
        return self.generator(**kwargs)


_REGISTRY: dict[str, TextureFamily] = {}


def register(family: TextureFamily) -> TextureFamily:
    """Add a family to the registry (its name must be new)."""
    key = family.name.strip().lower()
    if key in _REGISTRY and _REGISTRY[key] is not family:
        raise ValueError(f"a texture family named {key!r} is already registered")
    _REGISTRY[key] = family
    return family


def registry() -> dict[str, TextureFamily]:
    """The registered families by name (filled when :mod:`fingerpad.textures` is imported)."""
    return dict(_REGISTRY)


def get_family(name: str) -> TextureFamily:
    """The family called ``name`` (case-insensitive); a FingerpadError lists the known ones."""
    key = str(name).strip().lower()
    if key not in _REGISTRY:
        raise FingerpadError(f"unknown texture {name!r} (choose from: {', '.join(sorted(_REGISTRY))})")
    return _REGISTRY[key]


# ------------------------------------------------------------------------------------------------
# Helpers
# ------------------------------------------------------------------------------------------------


def base_mask(texture: Texture, rel_tol: float = 1e-6) -> np.ndarray:
    """Boolean (nx, ny) mask of the pixels at the base level of the texture.

    With ``texture.base_level`` set (measured maps), the pixels at or below it. Otherwise a pixel
    belongs to the base when ``height <= min + rel_tol * peak_to_valley`` (all pixels for a flat
    texture): for bumps, pillars and ridges the flat base between features, for dimples the
    dimple bottoms.
    """
    h = texture.heights
    if texture.base_level is not None:
        return h <= texture.base_level
    lowest = float(h.min())
    return h <= lowest + float(rel_tol) * texture.peak_to_valley


_LENGTH_KEYS = {
    "radius", "height", "depth", "spacing", "width", "top_width", "semi_axis_x", "semi_axis_y",
    "spacing_x", "spacing_y", "diameter", "amplitude", "wavelength",
}
_HIDDEN_KEYS = {"grid", "ny", "size", "height_factor", "filled_points"}


def describe(texture: Texture) -> str:
    """One-line human description, e.g. ``caps (radius=50 um, ...): periodic cell 100 um x ...``."""
    parts = []
    for key, value in texture.params.items():
        if key in _HIDDEN_KEYS:
            continue
        if key in _LENGTH_KEYS and isinstance(value, (int, float)):
            parts.append(f"{key}={fmt_length(float(value))}")
        elif key == "orientation" and isinstance(value, (int, float)):
            parts.append(f"orientation={math.degrees(value):.4g} deg")
        elif key == "level":
            parts.append("levelled" if value else "not levelled")
        elif key == "path":
            parts.append(f"from {value}")
        else:
            parts.append(f"{key}={value}")
    if texture.params.get("filled_points"):
        parts.append(f"{texture.params['filled_points']} missing points filled")
    lx, ly = texture.size
    nx, ny = texture.shape
    kind = "periodic cell" if texture.periodic else "finite patch"
    head = f"{texture.name} ({', '.join(parts)})" if parts else texture.name
    return (
        f"{head}: {kind} {fmt_length(lx)} x {fmt_length(ly)}, {nx} x {ny} px, "
        f"peak-to-valley {fmt_length(texture.peak_to_valley)}"
    )
