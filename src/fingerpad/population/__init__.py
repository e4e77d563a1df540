"""A population of fingers: distributions of a person's parameters, their members predicted on
one unit cell, the bands over them and which parameter drives the spread.

* :mod:`.distributions` - a ``[population]`` table read, checked and sampled;
  :mod:`.correlations` - rank correlations by a Gaussian copula; :mod:`.presets` - the built-in
  populations (``adults``); :mod:`.measured` - the participants of an ``analyse`` folder;
  :mod:`.sources` - a population by preset name, file, folder or table;
* :mod:`.rules` - :func:`attach`: every rule of a population on a study (which values the user
  fixed, a sliding direction, quantile levels, sizes, the Sobol design), asked by the library,
  the command line and the explorer alike;
* :mod:`.members` - the members on one texture at once (the coupling's vectorised twin,
  :mod:`fingerpad.coupling.members`); :mod:`.adhesion` - adhesive members, each read from one
  family of adhesive cells;
* :mod:`.run` - :func:`run_population`: the nominal prediction, every member, the bands;
  :mod:`.sobol` - which parameter drives the spread (Sobol indices); :mod:`.outputs` - the
  population's files.

The public names below are imported on first use.
"""

import lazy_loader

__getattr__, __dir__, __all__ = lazy_loader.attach(
    __name__,
    submodules=["adhesion", "correlations", "distributions", "measured", "members", "outputs", "presets", "rules", "run", "sobol",
                "sources"],
    submod_attrs={
        "distributions": ["POPULATION_PARAMS", "Distribution", "Population", "population_from_table"],
        "presets": ["POPULATION_PRESETS"],
        "rules": ["DEFAULT_QUANTILES", "PopulationStudy", "attach"],
        "run": ["QUANTITIES", "PopulationResult", "run_population"],
        "sobol": ["SensitivityResult", "population_sensitivity"],
        "sources": ["load_population"],
    },
)
