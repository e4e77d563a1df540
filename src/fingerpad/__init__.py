"""fingerpad: multiscale finger-pad contact and tactile friction on textured surfaces.

The model of Sergachev (2021), "Surface engineering of tactile friction": finger-pad gross
contact (macro), fingerprint-ridge contact (meso), skin on the texture asperities by a boundary
element method (micro), coupled through the pad's pressure distribution into the real contact
area and the friction. SI units throughout (m, N, Pa).
"""

from .coupling import HertzUnitCell, couple, critical_load, critical_load_hertz, predict_curve
from .errors import FingerpadError
from .finger import FINGER_PRESETS, Finger, get_finger, ridge_models_figure
from .fingerprint import FingerprintBEMRidges
from .friction import fit_power_law
from .halfspace import ContactResult, HalfSpaceSolver
from .materials import Materials, reduced_modulus
from .textures import GENERATORS, Texture, make_texture, periodize, read_surface
from .unitcell import BEMUnitCell, critical_pressure, full_contact_pressure, load_curve

__version__ = "0.1.0"

__all__ = [
    "BEMUnitCell",
    "ContactResult",
    "FINGER_PRESETS",
    "Finger",
    "FingerprintBEMRidges",
    "FingerpadError",
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
