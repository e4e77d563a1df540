"""Figures of a prediction: areas, friction and contact zones against load (matplotlib, Agg).

What each figure shows is defined once, in :mod:`.prediction_specs` (the explorer draws the same
specifications with Bokeh); this module draws them (:func:`.render.figure`).
"""

from __future__ import annotations

from typing import Any

from .prediction_specs import areas_figure, friction_figure, zones_figure
from .render import figure
from .specs import STATE_FILL

#: The result these figures read (:class:`~fingerpad.study.run.Prediction`), named for the
#: signatures only: plotting imports nothing of the layers above it, not even for type checking.
Prediction = Any

__all__ = ["STATE_FILL", "figure_areas", "figure_friction", "figure_zones"]


def figure_areas(pred: Prediction) -> Any:
    """Gross, ridge and real contact areas against load (``areas.png``)."""
    return figure(areas_figure(pred))


def figure_friction(pred: Prediction) -> Any:
    """Friction, normalised friction (and the directional ratio) against load (``friction.png``)."""
    return figure(friction_figure(pred))


def figure_zones(pred: Prediction) -> Any:
    """The ridge-contact disc's zones and the pressure and psi along a radius (``zones.png``)."""
    return figure(zones_figure(pred))
