"""Every figure of fingerpad (matplotlib's object API and the Agg canvas; no pyplot state).

Physics modules draw nothing: they return numbers, and these modules turn them into figures.

* :mod:`.solution` - pressure and contact maps of a solved cell, psi(p);
* :mod:`.specs` - figures as data (panels, axes with SI and shown units), CSV/JSON in SI; no toolkit;
* :mod:`.prediction_specs` - the one definition of predict's figures (matplotlib here, Bokeh in
  the explorer);
* :mod:`.render` - drawing specs with matplotlib (PNG/SVG), the design-map image;
* :mod:`.prediction` - areas, friction and contact zones against load (``fingerpad predict``);
* :mod:`.ridges` - the ridge-area models side by side (thesis Fig. 2.4 idea);
* :mod:`.measure` - friction-measurement figures per participant and sample.
"""
