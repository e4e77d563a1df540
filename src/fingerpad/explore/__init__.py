"""The texture design explorer: the model in a browser (``fingerpad explore``).

A local web app (Panel with Bokeh plots) on the library: the single-texture view (inputs with
units from the declared parameters, live Hertz curves, BEM unit cells as background jobs through
the cache), the comparison of pinned designs, the design map of a sweep store, and the methods
and references. Every plot downloads its data (CSV/JSON) and image (PNG/SVG); the inputs export
as a study TOML that ``fingerpad predict`` reproduces. See docs/explorer.md.

Modules without a browser dependency: :mod:`.inputs` (the form as a study, validation),
:mod:`.uploads` (the only files read for a client), :mod:`.jobs` (running predictions),
:mod:`.builders` (plots as data: predict's figures from :mod:`fingerpad.plotting.prediction_specs`,
the explorer's own on :mod:`fingerpad.plotting.specs`; images by :mod:`fingerpad.plotting.render`),
:mod:`.sweepdata` (reading sweep stores). Panel and Bokeh are
imported only when the server starts (:func:`.server.serve`), so that ``fingerpad --help`` stays
fast and the rest of the package works without them (``pip install 'fingerpad[explore]'``).
"""

from __future__ import annotations

__all__ = ["serve"]


def serve(**kwargs):  # noqa: ANN003, ANN201 -- see fingerpad.explore.server.serve
    """Start the explorer (see :func:`fingerpad.explore.server.serve`)."""
    from .server import serve as _serve

    return _serve(**kwargs)
