"""A population of fingers: distributions of a person's parameters, their members predicted on
one unit cell, the bands over them and which parameter drives the spread.

* :mod:`.run` - a ``[population]`` table read, sampled and predicted (:func:`run_population`);
* :mod:`.presets` - the built-in populations (``adults``); :mod:`.correlations` - rank
  correlations by a Gaussian copula; :mod:`.measured` - the participants of an ``analyse`` folder;
* :mod:`.members` - many fingers on one texture at once; :mod:`.sobol` - Sobol indices;
* :mod:`.outputs` - the population's tables.
"""
