"""fingerpad: multiscale finger-pad contact and tactile friction on textured surfaces."""

from .errors import FingerpadError
from .materials import Materials, reduced_modulus
from .textures import Texture

__version__ = "0.1.0"

__all__ = ["FingerpadError", "Materials", "Texture", "reduced_modulus", "__version__"]
