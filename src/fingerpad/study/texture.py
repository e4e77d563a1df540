"""The texture of a study: a generator with its parameters, or a height-map file, built once."""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass, field
from typing import Any

from ..errors import FingerpadError
from ..textures import Texture
from ..textures.measured import DEFAULT_BASE_QUANTILE
from ..units import parse_size
from .values import text

__all__ = ["TEXTURE_KEYS", "TextureSpec"]

#: Keys of a study file's [texture] section (plus the generator's own parameters).
TEXTURE_KEYS = ("name", "surface", "size", "pixel_size", "height_unit", "periodic", "periodize", "fill_missing",
                "base_quantile", "grid")


@dataclass
class TextureSpec:
    """A texture to build: a generator with parameters, or a height-map file.

    Attributes
    ----------
    name
        Texture family (see ``fingerpad textures``), or ``None`` with ``surface``.
    params
        Family parameters: SI numbers or strings with units (``"50um"``), as on the command line;
        read through the family's declared kinds (a bare angle is in degrees).
    surface
        Height-map file (see :func:`fingerpad.textures.read_surface`).
    size
        ``(Lx, Ly)`` in m, or text ``"200um,150um"``: the map size of a ``surface``, or the ``size``
        parameter of a family that takes one (``flat``).
    height_unit
        Unit of the heights in a plain ``surface`` file (``"um"``, ...).
    periodic
        Take the ``surface`` map as one period of a periodic texture.
    periodize
        Mirror the ``surface`` map into a periodic cell (:func:`fingerpad.textures.periodize`).
    fill_missing
        Fill missing (NaN) points of the ``surface`` map.
    pixel_size
        ``(dx, dy)`` in m or text ``"2um"``/``"2um,3um"``: the pixel size of a ``surface``, instead
        of ``size``.
    base_quantile
        Share of the lowest pixels of a ``surface`` map taken as the bottom of its base (default
        0.01); the base level lies 4 noise sigmas above it (:func:`fingerpad.textures.measured.base_level_of`).
    labels
        How to name each parameter in error messages (``--radius`` or ``study.toml [texture] radius``).
    """

    name: str | None = None
    params: dict[str, Any] = field(default_factory=dict)
    surface: str | None = None
    size: Any = None
    height_unit: str | None = None
    periodic: bool | None = None
    periodize: bool = False
    fill_missing: bool = False
    pixel_size: Any = None
    base_quantile: float | None = None
    labels: dict[str, str] = field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self) -> None:
        if (self.name is None) == (self.surface is None):
            raise FingerpadError("a texture needs exactly one of a generator name or a surface file")
        if self.periodic and self.periodize:
            raise FingerpadError(f"{self._label('periodic')} and {self._label('periodize')} contradict each other: a map "
                                 "is either one period already (periodic) or mirrored into one (periodize)")

    @property
    def source(self) -> dict[str, Any]:
        if self.surface is not None:
            return {"source": "file", "file": os.path.abspath(self.surface)}
        return {"source": "generator", "file": None}

    def _label(self, key: str) -> str:
        return self.labels.get(key, "--" + key.replace("_", "-"))

    def _size(self) -> tuple[float, float] | None:
        if self.size is None:
            return None
        if isinstance(self.size, (tuple, list)) and all(isinstance(v, float) for v in self.size):
            return (float(self.size[0]), float(self.size[-1]))
        return parse_size(text(self.size), self._label("size"))

    def build(self, grid: int | None = None) -> Texture:
        """The :class:`~fingerpad.textures.Texture` (``grid``: points along x, generators only)."""
        from ..textures import get_family
        from ..textures.measured import read_surface_option

        size = self._size()
        if self.name is not None:
            for key, value in (("height_unit", self.height_unit), ("periodize", self.periodize),
                               ("fill_missing", self.fill_missing), ("pixel_size", self.pixel_size),
                               ("base_quantile", self.base_quantile)):
                if value:
                    raise FingerpadError(f"{self._label(key)} applies to surface files only")
            family = get_family(self.name)
            tex = family.build(self.params, grid=grid, size=size,
                               label=lambda p: self.labels.get(p.name, p.option))
            if self.periodic is False:
                tex = dataclasses.replace(tex, periodic=False)
            return tex
        if self.params:
            first = sorted(self.params)[0]
            raise FingerpadError(
                f"{self._label(first)}: unknown texture key(s) {', '.join(sorted(self.params))} for a surface file "
                f"(texture parameters belong to generated textures, --texture NAME)"
            )
        if grid is not None:
            raise FingerpadError("the grid applies to generated textures; a surface file keeps its own grid")
        pixel = None
        if self.pixel_size is not None:
            pixel = parse_size(text(self.pixel_size), self._label("pixel_size"))
        quantile = DEFAULT_BASE_QUANTILE if self.base_quantile is None else self.base_quantile
        if not 0.0 <= quantile < 1.0:
            raise FingerpadError(f"{self._label('base_quantile')}: must lie in [0, 1), got {quantile!r}")
        tex = read_surface_option(str(self.surface), size, self.height_unit, bool(self.periodic), self.fill_missing,
                                  pixel_size=pixel, base_quantile=quantile)
        if self.periodize:
            from ..textures import periodize

            tex = periodize(tex)
        return tex
