"""Rough or smooth: which cue judges a texture's roughness, per load (duplex theory).

* Periods above about 0.2 mm (:data:`DUPLEX_PERIOD`) are judged *spatially*, by the skin's
  intrusion between the elements (slowly adapting type I afferents); periods below it by the
  vibration they excite, weighted by the Pacinian channel (Hollins and Bensmaia 2007; Bensmaia and
  Hollins 2005).
* For shallow textures the felt roughness rises with the skin's intrusion and peaks where the
  skin first touches the texture's floor (Drewing 2016, 2018): the package's *transition*
  state at the pad centre (:func:`fingerpad.study.run.centre_state`). Below it (asperity contact)
  roughness is still rising, past full contact the skin follows the texture.
* Spacings below 160 um were felt smooth (Massimiani et al., thesis ch. 1.3 and 2.1):
  :data:`SMOOTH_SPACING`, the design map's marker.

The texture's spacing here is its shortest period along its cell's axes (the nearest-neighbour
distance of a square or hexagonal lattice, the period across ridges), from
:func:`fingerpad.perception.vibration.periods`. These are verdicts from published thresholds,
not a roughness model: docs/perception.md says what is not modelled.
"""

from __future__ import annotations

import math
from typing import Any

__all__ = ["DUPLEX_PERIOD", "SMOOTH_SPACING", "STATE_ROUGHNESS", "regime"]

#: The publications this module rests on (:mod:`fingerpad.references`).
REFERENCES = ("hollins2007", "drewing2016", "drewing2018")

#: The duplex theory's boundary between spatially and vibrotactilely coded textures, m (~0.2 mm).
DUPLEX_PERIOD = 200e-6
#: Spacings below this were felt smooth (Massimiani et al.), m.
SMOOTH_SPACING = 160e-6

#: The felt roughness against the contact state at the pad centre (Drewing 2016, 2018).
STATE_ROUGHNESS = {
    "asperity": "rising (skin on the tops)",
    "transition": "near its peak (skin reaches the floor)",
    "full": "past its peak (skin follows the texture)",
}


def regime(spacing: float, state: str) -> dict[str, Any]:
    """The roughness regime of a texture of ``spacing`` (m; ``inf`` for a flat) whose pad centre
    is in contact ``state`` (``asperity``, ``transition`` or ``full``).

    Returns
    -------
    dict
        ``scale`` (``coarse``, ``fine`` or ``flat``), ``cue`` (what judges it), ``roughness``
        (where it stands against the roughness peak), ``felt_smooth`` (spacing below 160 um),
        ``spacing_m``, ``state`` and a one-line ``verdict``.
    """
    if not math.isfinite(spacing):
        return {"scale": "flat", "cue": "none (no texture)", "roughness": "none", "felt_smooth": True,
                "spacing_m": None, "state": state, "verdict": "smooth (flat)"}
    coarse = spacing > DUPLEX_PERIOD
    smooth = spacing < SMOOTH_SPACING
    cue = "spatial (skin intrusion, SA I)" if coarse else "vibration (Pacinian-weighted)"
    rough = STATE_ROUGHNESS.get(state, state)
    if smooth:
        verdict = "felt smooth (spacing below 160 um)"
    elif coarse:
        verdict = f"coarse: roughness {rough}"
    else:
        verdict = f"fine: judged by its vibration ({state} contact)"
    return {"scale": "coarse" if coarse else "fine", "cue": cue, "roughness": rough, "felt_smooth": smooth,
            "spacing_m": float(spacing), "state": state, "verdict": verdict}
