"""The prediction job (``fingerpad predict``): study spec -> run -> outputs.

* :mod:`.spec` - the study: TOML study files and values, checked once (:func:`study_from_dict`);
* :mod:`.overrides` - command-line flags laid over a study file;
* :mod:`.run` - :func:`run_study` chains macro, meso, micro, coupling and friction;
* :mod:`.outputs` - ``predict.json``, ``predict.nc`` and the figures, all or none;
* :mod:`.solve` - the one-cell job of ``fingerpad solve``.
"""

from .spec import DEFAULT_STUDY, Study, load_study_file, read_study_file, study_from_dict
from .texture import TextureSpec

__all__ = ["DEFAULT_STUDY", "Study", "TextureSpec", "load_study_file", "read_study_file", "study_from_dict"]
