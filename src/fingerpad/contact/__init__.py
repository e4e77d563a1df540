"""The FFT boundary-element engine shared by the meso and micro scales.

A load travels through it in three named hops:

1. :mod:`.solver` - :class:`HalfSpaceSolver` sets up the contact problem of a texture against the
   skin (an elastic half-space) at a given mean pressure or approach, chooses the primal or dual
   form and returns a :class:`ContactResult` (:mod:`.result`, with the contact state);
   :mod:`.formulations` sets up each primal or dual run and assembles its result;
2. :mod:`.ccg` - :func:`constrained_cg`, the Polonsky-Keer constrained conjugate gradient;
3. :mod:`.greens` - the elastic operators (Boussinesq compliance and stiffness) applied by FFT,
   periodic or zero-padded; :mod:`.kernels` fuses the element-wise work. :mod:`.layered` gives
   the skin a layer (an elastic layer on an elastic half-space or a rigid base): a factor on
   the half-space kernel, exact in Fourier space.
"""

from .layered import Layer
from .result import FULL_CONTACT_TOL, ContactResult, contact_state
from .solver import HalfSpaceSolver

__all__ = ["FULL_CONTACT_TOL", "ContactResult", "HalfSpaceSolver", "Layer", "contact_state"]
