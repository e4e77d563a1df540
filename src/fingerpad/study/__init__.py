"""The prediction job (``fingerpad predict``): study spec -> run -> outputs.

* :mod:`.spec` - the study: TOML study files and values, checked once (:func:`study_from_dict`);
* :mod:`.overrides` - command-line flags laid over a study file;
* :mod:`.run` - :func:`run_study` chains macro, meso, micro, coupling and friction;
* :mod:`.outputs` - ``predict.json``, ``predict.nc`` and the figures, all or none;
* :mod:`.cell_job` - the one-cell job of ``fingerpad solve``.
"""

import lazy_loader

# Lazily: `fingerpad solve` needs only .cell_job and .overrides, and .spec pulls in the finger,
# ridge and pad models (measured ~40 ms of the command's start-up, benchmarks/bench_startup.py).
__getattr__, __dir__, __all__ = lazy_loader.attach(
    __name__,
    submodules=["outputs", "overrides", "run", "cell_job", "spec", "texture", "values"],
    submod_attrs={
        "spec": ["DEFAULT_STUDY", "Study", "load_study_file", "read_study_file", "study_from_dict"],
        "texture": ["TextureSpec"],
    },
)
