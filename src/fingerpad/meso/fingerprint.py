"""Fingerprint ridge contact by the boundary element method (meso scale, thesis ch. 2.2.2).

The most detailed ridge model of the thesis: the finger pad's surface, a sphere of radius
``R_fp`` carrying the fingerprint ridges, pressed on a flat rigid plate and solved with the
non-periodic half-space solver (:mod:`fingerpad.contact`). For frictionless contact only the
sum of the two surfaces' heights matters, so the pad topography is handed to the solver as the
"texture" and the plate as the flat elastic body, with the skin's reduced modulus.

The ridge contact area A_fr is the contact area of the solution; the gross area A_g is the area
of the region enclosed by the outermost touching ridges, taken as the area of the disc whose
radius is the largest contact radius (the ridges cross the whole gross contact).

Synthetic fingerprints: ridges of raised-cosine profile (width ``w``, height ``h_r``) on a
pattern of wavelength ``lambda_r``, either ``"parallel"`` (straight ridges along y) or
``"whorl"`` (concentric rings about the pad centre). A measured replica (a height map of a
fingertip or of its cast, curvature included) can be used instead via :meth:`from_surface`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from ..contact import ContactResult, HalfSpaceSolver
from ..contact.layered import Layer
from ..checks import as_loads, scalar_out
from ..errors import FingerpadError
from ..params import Model, Param, check_fields
from ..textures import Texture

__all__ = ["FingerprintBEMRidges", "fingerprint_topography"]


def fingerprint_topography(
    *,
    pad_radius: float,
    wavelength: float,
    width: float,
    height: float,
    extent: float,
    grid: int,
    pattern: str = "whorl",
) -> Texture:
    """Height map (m) of a spherical pad carrying raised-cosine fingerprint ridges.

    Parameters
    ----------
    pad_radius
        Equivalent radius of the finger pad R_fp, m (docs/model.md: 7-11 mm).
    wavelength, width, height
        Ridge wavelength (0.4-0.5 mm), ridge base width (<= wavelength) and ridge height, m.
    extent
        Side of the square patch, m (must hold the gross contact).
    grid
        Points per side.
    pattern
        ``"whorl"`` (concentric rings) or ``"parallel"`` (straight ridges).
    """
    for name, v in (("pad radius", pad_radius), ("ridge wavelength", wavelength), ("ridge width", width),
                    ("extent", extent)):
        if not (math.isfinite(v) and v > 0):
            raise FingerpadError(f"{name} must be positive, got {v!r}")
    if not (math.isfinite(height) and height >= 0):
        raise FingerpadError(f"ridge height must be non-negative, got {height!r}")
    if width > wavelength:
        raise FingerpadError(f"ridge width {width:.3g} m exceeds the ridge wavelength {wavelength:.3g} m")
    if pattern not in ("whorl", "parallel"):
        raise FingerpadError(f"fingerprint pattern must be 'whorl' or 'parallel', got {pattern!r}")
    if wavelength / (extent / grid) < 6:
        raise FingerpadError(
            f"grid {grid} resolves the ridge wavelength with fewer than 6 points: use at least "
            f"{math.ceil(6 * extent / wavelength)}"
        )
    x = (np.arange(grid) + 0.5) * extent / grid - extent / 2
    X, Y = np.meshgrid(x, x, indexing="ij")
    r = np.hypot(X, Y)
    # paraboloid (Hertz's sphere), apex at 0: without ridges the solve is the macro Hertz model
    pad = -(r**2) / (2 * pad_radius)
    s = r if pattern == "whorl" else X
    # signed distance to the nearest ridge centreline (ridge centred on the apex)
    d = (s + wavelength / 2) % wavelength - wavelength / 2
    ridges = np.where(np.abs(d) < width / 2, 0.5 * height * (1 + np.cos(2 * np.pi * d / width)), 0.0)
    params = dict(pad_radius=pad_radius, wavelength=wavelength, width=width, height=height,
                  extent=extent, grid=grid, pattern=pattern)
    return Texture(pad + ridges, (extent, extent), periodic=False, name="fingerprint", params=params)


@dataclass(frozen=True, kw_only=True)
class FingerprintBEMRidges:
    """Ridge contact area from a BEM solve on a fingerprint topography (RidgeAreaModel).

    ``area(load, gross_area)`` ignores ``gross_area``: the gross and ridge areas both follow from
    the solve (:meth:`solve`). Solves are cached per load in memory; each load costs one
    non-periodic solve (seconds at the default resolution), so this is the slow, most detailed
    model (the thesis: 0.5-2 N).

    Attributes
    ----------
    pad_radius
        R_fp, m.
    modulus
        Reduced modulus of the skin at the ridge scale, Pa (thesis Fig. 2.4: 100 kPa).
    wavelength, width, height, pattern
        Synthetic ridges (see :func:`fingerprint_topography`).
    max_load
        Largest load to be asked for, N: sets the patch size (1.3 x its Hertz radius).
    points_per_wavelength
        Resolution of the ridges.
    topography
        A measured replica instead of the synthetic pattern (see :meth:`from_surface`).
    layer
        A layered skin (:class:`~fingerpad.contact.layered.Layer`): the solve uses the layered
        padded kernel and ``modulus`` is the layer's E1* (the plate is rigid). A layered
        :class:`~fingerpad.finger.Finger` sets it (:meth:`with_layer`): its ridges, 0.4-0.5 mm,
        are the size of the stratum corneum's thickness, so they feel layer and tissue both.

    From a study file: ``[finger] ridges = { model = "fingerprint_bem", height = "30um" }``; the
    pad radius is the finger's and ``max_load`` the study's largest load unless given.
    """

    #: The declared fields (units, bounds) a study file may give.
    #: The publications of this model (:mod:`fingerpad.references` keys; the contact solver on the fingerprint).
    REFERENCES: ClassVar[tuple[str, ...]] = ("polonsky1999",)
    PARAMS: ClassVar[tuple[Param, ...]] = (
        Param("pad_radius", "length", "pad radius R_fp (default: the finger's)", 9e-3, low=0, low_open=True,
              label="pad radius", plausible="pad radius"),
        Param("modulus", "pressure", "reduced modulus of the skin at the ridge scale (thesis Fig. 2.4: 100 kPa)",
              100e3, low=0, low_open=True, label="ridge modulus"),
        Param("wavelength", "length", "ridge wavelength lambda_r (docs/model.md: 0.4-0.5 mm)", 0.45e-3, low=0,
              low_open=True, label="ridge wavelength"),
        Param("width", "length", "ridge base width (<= wavelength)", 0.3e-3, low=0, low_open=True,
              label="ridge width"),
        Param("height", "length", "ridge height", 30e-6, low=0, label="ridge height"),
        Param("pattern", "choice", "whorl: concentric rings; parallel: straight ridges along y", "whorl",
              ("whorl", "parallel"), label="fingerprint pattern"),
        Param("max_load", "force", "largest load asked for, sets the patch (default: the study's largest load)",
              2.0, low=0, low_open=True, label="max_load"),
        Param("points_per_wavelength", "count", "grid points per ridge wavelength", 10, low=6,
              label="points per wavelength"),
        Param("tol", "ratio", "relative tolerance of the half-space solver", 1e-6, low=0, high=1, low_open=True,
              high_open=True, label="solver tolerance"),
    )

    pad_radius: float = 9e-3
    modulus: float = 100e3
    wavelength: float = 0.45e-3
    width: float = 0.3e-3
    height: float = 30e-6
    pattern: str = "whorl"
    max_load: float = 2.0
    points_per_wavelength: int = 10
    tol: float = 1e-6
    topography: Texture | None = field(default=None, repr=False)
    layer: Layer | None = None
    _cache: dict[float, ContactResult] = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self) -> None:
        check_fields(self, self.PARAMS)
        # whether the patch is the synthetic one (sized by the moduli), not a measured replica
        object.__setattr__(self, "_synthetic_patch", self.topography is None)
        if self.topography is None:
            object.__setattr__(self, "topography", self._synthetic())
        elif self.topography.periodic:
            raise FingerpadError("a fingerprint topography must be a finite (non-periodic) patch")
        object.__setattr__(self, "_solver", HalfSpaceSolver(self.topography, self.modulus, layer=self.layer,
                                                            tol=self.tol))

    def with_layer(self, layer: Layer) -> "FingerprintBEMRidges":
        """The model solved on the layered skin ``layer`` (modulus: the layer's E1*, a rigid plate);
        ``self`` when it is already."""
        if self.layer == layer:
            return self
        import dataclasses

        # a fresh solve cache: the copy's solutions are another body's
        topography = None if getattr(self, "_synthetic_patch", False) else self.topography  # re-sized
        return dataclasses.replace(self, layer=layer, modulus=layer.reduced_modulus, topography=topography, _cache={})

    @classmethod
    def from_surface(cls, texture: Texture, *, modulus: float = 100e3, invert: bool = False, **kw: Any) -> "FingerprintBEMRidges":
        """Use a measured fingertip replica (heights toward the plate; ``invert`` for a cast)."""
        h = -texture.heights if invert else texture.heights
        tex = Texture(h - h.max(), texture.size, periodic=False, name=texture.name, params=dict(texture.params))
        return cls(modulus=modulus, topography=tex, **kw)

    def _synthetic(self) -> Texture:
        # the patch holds the Hertz contact of the softest modulus the pad can show: on a layered
        # skin the substrate's at long wavelengths, if softer than the layer
        e = self.modulus if self.layer is None else min(self.modulus, self.layer.substrate_reduced_modulus)
        a = (3 * self.max_load * self.pad_radius / (4 * e)) ** (1 / 3)
        extent = min(2.6 * a, 1.9 * self.pad_radius)
        grid = int(math.ceil(extent / self.wavelength * self.points_per_wavelength / 2) * 2)
        return fingerprint_topography(
            pad_radius=self.pad_radius, wavelength=self.wavelength, width=self.width, height=self.height,
            extent=extent, grid=grid, pattern=self.pattern,
        )

    def solve(self, load: float) -> ContactResult:
        """The contact solution of the pad on a flat plate at normal load ``load`` (N)."""
        load = float(load)
        if not (math.isfinite(load) and load > 0):
            raise FingerpadError(f"load must be positive, got {load!r}")
        if load in self._cache:
            return self._cache[load]
        tex = self.topography
        below = [f for f in self._cache if f < load]
        initial = self._cache[max(below)] if below else None
        res = self._solver.solve_pressure(load / tex.area, initial=initial)  # type: ignore[attr-defined]
        contact = res.contact
        edge = contact[0, :].any() or contact[-1, :].any() or contact[:, 0].any() or contact[:, -1].any()
        if edge:
            raise FingerpadError(
                f"the gross contact at {load:g} N reaches the edge of the fingerprint patch: raise max_load"
            )
        self._cache[load] = res
        return res

    def gross_area(self, load: "np.ndarray | float") -> np.ndarray:
        """Gross area (m^2): the disc through the outermost contact points."""
        out = []
        for f in np.atleast_1d(np.asarray(load, dtype=float)).ravel():
            res = self.solve(f)
            x, y = self.topography.coordinates()  # type: ignore[union-attr]
            xc = x - self.topography.size[0] / 2 + self.topography.spacing[0] / 2  # type: ignore[union-attr]
            yc = y - self.topography.size[1] / 2 + self.topography.spacing[1] / 2  # type: ignore[union-attr]
            r = np.hypot(xc[:, None], yc[None, :])[res.contact]
            out.append(math.pi * float(r.max()) ** 2 if r.size else 0.0)
        return np.asarray(out)

    def area(self, load: "np.ndarray | float", gross_area: "np.ndarray | float | None" = None) -> "np.ndarray | float":
        """Ridge contact area A_fr (m^2) at each load (N)."""
        return scalar_out(self.area_checked(as_loads(load)))

    def area_checked(self, f: np.ndarray, gross_area: np.ndarray | None = None) -> np.ndarray:
        """The same on loads already checked (a float array >= 0); the gross area is not used."""
        return np.array([self.solve(v).real_contact_area for v in f.ravel()]).reshape(f.shape)


MODELS = (
    Model("fingerprint_bem", FingerprintBEMRidges, FingerprintBEMRidges.PARAMS,
          "BEM on a synthetic fingerprint (whorl or parallel raised-cosine ridges on the pad sphere); slow",
          inherits={"pad_radius": "finger.radius", "max_load": "loads.max"}),
)
