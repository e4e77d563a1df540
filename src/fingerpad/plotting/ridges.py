"""Figure of the ridge-area models side by side (the idea of the thesis Fig. 2.4)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from ..checks import ArrayLike
from ..io import atomic_write
from ..macro.hertz import HertzArea
from ..meso.compare import ridge_model_curves

__all__ = ["figure_ridge_models", "ridge_models_figure"]


def ridge_models_figure(
    path: str | os.PathLike[str],
    loads: ArrayLike | None = None,
    *,
    dpi: int = 120,
    **inputs: Any,
) -> Path:
    """Write :func:`~fingerpad.plotting.ridges.figure_ridge_models` to a PNG (atomically); returns the path."""
    fig = figure_ridge_models(loads, **inputs)
    return atomic_write(path, lambda tmp: fig.savefig(tmp, format="png", dpi=dpi))


def figure_ridge_models(
    loads: ArrayLike | None = None,
    *,
    skin_modulus: float = 100e3,
    radius: float = 9e-3,
    wavelength: float = 0.45e-3,
    amplitude: float = 30e-6,
    ridge_radius: float = 0.1e-3,
    bem_loads: ArrayLike | None = None,
    source: str = "the thesis' Fig. 2.4 inputs",
) -> Any:
    """Gross area and the ridge-area models against load (idea of thesis Fig. 2.4).

    Left: gross area (Hertz, Eq. 2.5) and the ridge areas in mm^2; right: the ridge fractions
    A_fr/A_g. All models share the inputs, named in the title with where they come from
    (``source``): by default the thesis' comparison, E_skin = 100 kPa, which is not the default
    finger's 40 kPa; ``fingerpad finger-models --finger NAME`` takes a preset's pad instead.

    Parameters
    ----------
    loads
        Loads, N (default 30 log-spaced from 0.1 to 4 N, the exploration range).
    bem_loads
        Loads at which to add the BEM fingerprint model (markers; seconds per load).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    if loads is None:
        loads = np.geomspace(0.1, 4.0, 30)
    curves = ridge_model_curves(
        loads, skin_modulus=skin_modulus, radius=radius, wavelength=wavelength,
        amplitude=amplitude, ridge_radius=ridge_radius, bem_loads=bem_loads,
    )
    f = curves.pop("load")
    bem_f, bem_a = curves.pop("BEM load", None), curves.pop("BEM", None)
    order = np.argsort(f)
    ag = curves["gross (Hertz)"]
    fig = Figure(figsize=(10, 4.2), layout="constrained")
    ax_area, ax_frac = fig.subplots(1, 2)
    for label, area in curves.items():
        style = "k-" if label.startswith("gross") else "-"
        ax_area.plot(f[order], area[order] * 1e6, style, label=label)
        if not label.startswith("gross"):
            ax_frac.plot(f[order], (area / ag)[order] * 100, "-", label=label)
    if bem_f is not None:
        hertz_bem = HertzArea(radius, skin_modulus).area(bem_f)
        ax_area.plot(bem_f, bem_a * 1e6, "ko", mfc="none", label="BEM fingerprint")
        ax_frac.plot(bem_f, bem_a / hertz_bem * 100, "ko", mfc="none", label="BEM fingerprint")
    ax_area.set_xlabel("normal load F (N)")
    ax_area.set_ylabel("contact area (mm²)")
    ax_area.set_title("gross and ridge contact area")
    ax_frac.set_xlabel("normal load F (N)")
    ax_frac.set_ylabel("ridge area / gross area (%)")
    ax_frac.set_ylim(0, 105)
    ax_frac.set_title("ridge fraction")
    for ax in (ax_area, ax_frac):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize="small")
    fig.suptitle(
        f"Ridge-area models, same inputs ({source}): E_skin = {skin_modulus / 1e3:.3g} kPa, "
        f"R_fp = {radius * 1e3:.3g} mm, λ_r = {wavelength * 1e3:.3g} mm, h_r = {amplitude * 1e6:.3g} µm, "
        f"R_r = {ridge_radius * 1e3:.3g} mm", fontsize="medium"
    )
    return fig

