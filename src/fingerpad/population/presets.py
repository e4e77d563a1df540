"""Built-in populations of fingers (``--population adults``), each range with its source.

Every entry is a ``[population]`` table as a study file writes it (quantities with units).
Sources are docs/model.md (the thesis and the literature it cites); docs/population.md lists
each range, its source and whether it is measured or assumed.
"""

from __future__ import annotations

from typing import Any

__all__ = ["POPULATION_PRESETS"]

POPULATION_PRESETS: dict[str, dict[str, Any]] = {
    "adults": {
        "size": 1000,
        "seed": 0,
        "method": "sobol",
        # measured: the thesis estimated the micro-scale skin modulus E_s at 0.2-0.5 MPa across
        # participants (docs/model.md, "Micro"); no shape is given, so uniform over the range.
        "skin_modulus": {"distribution": "uniform", "low": "0.2MPa", "high": "0.5MPa"},
        # literature range: skin Poisson ratio 0.48-0.5 (docs/model.md).
        "skin_poisson": {"distribution": "uniform", "low": 0.48, "high": 0.5},
        # literature range: equivalent pad radius 7-11 mm (docs/model.md, "Macro").
        "radius": {"distribution": "uniform", "low": "7mm", "high": "11mm"},
        # literature range: pad reduced modulus 10-100 kPa (docs/model.md, "Macro"); a factor of
        # ten, so log-uniform would also do; kept uniform (assumed shape).
        "modulus": {"distribution": "uniform", "low": "10kPa", "high": "100kPa"},
        # literature range: ridge contact 10-70 % of the gross area (docs/model.md, "Meso").
        "ridge_fraction": {"distribution": "uniform", "low": 0.1, "high": 0.7},
        # ASSUMED: docs/model.md gives no spread of tau0; +-50 % about the default 8.1 kPa, which is
        # calibrated to dry mu ~ 0.5 on a smooth flat (finger.py).
        "tau0": {"distribution": "uniform", "low": "4kPa", "high": "12kPa"},
        # ASSUMED: no value in docs/model.md; 0-0.2 about the assumed default 0.1.
        "alpha": {"distribution": "uniform", "low": 0.0, "high": 0.2},
        # ASSUMED: no value in docs/model.md; 0.05-0.2 about the assumed default 0.1 (friction
        # "mostly adhesive", so the hysteresis term stays small).
        "beta": {"distribution": "uniform", "low": 0.05, "high": 0.2},
        # no "correlations": docs/model.md (the thesis and its literature) gives no correlation
        # between any two of these parameters, so they are drawn independently.
    },
}
