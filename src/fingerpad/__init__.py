"""fingerpad: multiscale finger-pad contact and tactile friction on textured surfaces.

The model of Sergachev (2021), "Surface engineering of tactile friction": finger-pad gross
contact (macro), fingerprint-ridge contact (meso), skin on the texture asperities by a boundary
element method (micro), coupled through the pad's pressure distribution into the real contact
area and the friction. SI units throughout (m, N, Pa). The equations are in ``docs/model.md``.

Layout (a load goes macro -> meso -> micro -> coupling -> friction):

* :mod:`fingerpad.textures` - unit cells of the counter-surface, one file per family; measured maps;
* :mod:`fingerpad.contact` - the FFT boundary-element engine (solver, Green's functions, CG);
* :mod:`fingerpad.macro`, :mod:`fingerpad.meso`, :mod:`fingerpad.micro` - the three scales;
* :mod:`fingerpad.finger`, :mod:`fingerpad.coupling`, :mod:`fingerpad.friction`;
* :mod:`fingerpad.study` - the prediction job (study files, run, outputs);
* :mod:`fingerpad.population` - a population of fingers on one texture (bands, Sobol indices);
* :mod:`fingerpad.measure` - friction measurements; :mod:`fingerpad.plotting` - every figure;
  :mod:`fingerpad.cli` - the command line.

The public names below are imported on first use, so ``import fingerpad`` (and the command
line's start-up) stays fast.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from ._version import __version__

#: Public name -> module that defines it.
_PUBLIC = {
    "BEMUnitCell": "micro.bem",
    "ContactResult": "contact.solver",
    "FINGER_PRESETS": "finger",
    "Finger": "finger",
    "FingerprintBEMRidges": "meso.fingerprint",
    "FingerpadError": "errors",
    "GENERATORS": "textures",
    "HalfSpaceSolver": "contact.solver",
    "HertzUnitCell": "micro.hertz",
    "Materials": "materials",
    "Texture": "textures",
    "couple": "coupling",
    "critical_load": "coupling",
    "critical_load_hertz": "micro.hertz",
    "critical_pressure": "micro.loadcurve",
    "fit_power_law": "friction",
    "full_contact_pressure": "micro.loadcurve",
    "get_finger": "finger",
    "load_curve": "micro.loadcurve",
    "make_texture": "textures",
    "periodize": "textures",
    "predict_curve": "coupling",
    "read_surface": "textures",
    "reduced_modulus": "materials",
    "ridge_models_figure": "plotting.ridges",
}

__all__ = [
    "BEMUnitCell",
    "ContactResult",
    "FINGER_PRESETS",
    "Finger",
    "FingerpadError",
    "FingerprintBEMRidges",
    "GENERATORS",
    "HalfSpaceSolver",
    "HertzUnitCell",
    "Materials",
    "Texture",
    "__version__",
    "couple",
    "critical_load",
    "critical_load_hertz",
    "critical_pressure",
    "fit_power_law",
    "full_contact_pressure",
    "get_finger",
    "load_curve",
    "make_texture",
    "periodize",
    "predict_curve",
    "read_surface",
    "reduced_modulus",
    "ridge_models_figure",
]


def __getattr__(name: str) -> Any:
    module = _PUBLIC.get(name)
    if module is None:
        raise AttributeError(f"module 'fingerpad' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{module}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *_PUBLIC])


if TYPE_CHECKING:  # static analysers see the eager imports
    from .contact import ContactResult, HalfSpaceSolver
    from .coupling import couple, critical_load, predict_curve
    from .errors import FingerpadError
    from .finger import FINGER_PRESETS, Finger, get_finger
    from .friction import fit_power_law
    from .materials import Materials, reduced_modulus
    from .meso.fingerprint import FingerprintBEMRidges
    from .micro.bem import BEMUnitCell
    from .micro.hertz import HertzUnitCell, critical_load_hertz
    from .micro.loadcurve import critical_pressure, full_contact_pressure, load_curve
    from .plotting.ridges import ridge_models_figure
    from .textures import GENERATORS, Texture, make_texture, periodize, read_surface
