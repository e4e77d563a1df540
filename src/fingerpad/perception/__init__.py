"""What a person feels: perception verdicts from the predicted friction and contact (issue 32).

Physics-free and drawing nothing, above the prediction and population jobs and below design:

* :mod:`.discrimination` - telling two surfaces apart by friction, a forced-choice model on
  ln(mu) with the person's Weber fraction W (:data:`~.discrimination.WEBER_FRACTION`);
* :mod:`.vibration` - f = v / lambda along the stroke for any lattice and direction, the receptor
  channel, the detection threshold and an amplitude estimate from the unit cell;
* :mod:`.roughness` - rough or smooth: the duplex theory's cue, the roughness peak at the
  transition, the 160 um marker;
* :mod:`.compare` - two surfaces on the same fingers (``fingerpad compare``,
  ``predict --perception``).

The models, their constants and their sources: docs/perception.md.
"""

import lazy_loader

__getattr__, __dir__, __all__ = lazy_loader.attach(
    __name__,
    submodules=["compare", "discrimination", "result", "roughness", "vibration"],
    submod_attrs={
        "compare": ["compare"],
        "result": ["Comparison"],
        "discrimination": ["WEBER_FRACTION", "p_correct"],
    },
)
