"""Built-in populations of fingers (``--population adults``), each range with its source.

Every entry is a ``[population]`` table as a study file writes it (quantities with units).
Sources are docs/model.md (the thesis and the literature it cites); docs/population.md lists
each range, its source and whether it is measured or assumed.
"""

from __future__ import annotations

from typing import Any

from ..person import WEBER_SPREAD

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
        # literature range: pad reduced modulus 10-100 kPa (docs/model.md, "Macro"), a factor of
        # ten: log-normal about the default finger's 40 kPa ("the typical value"), 5-95 % at
        # 18-91 kPa (issue 31: uniform over 10-100 kPa put the median member at 55 kPa, a stiffer,
        # smaller pad than the finger the population varies). Assumed shape.
        "modulus": {"distribution": "lognormal", "median": "40kPa", "sigma": 0.5},
        # literature range: ridge contact 10-70 % of the gross area (docs/model.md, "Meso") -- a
        # range over the loads of the studies, not between people at one load; per person at a
        # given load: 30-70 %, about the 50 % of the default finger (Duvefelt). ASSUMED: held
        # over load for each person (docs/population.md, "The adults preset"). Issue 31: over
        # 10-70 % the median member had 40 %.
        "ridge_fraction": {"distribution": "uniform", "low": 0.3, "high": 0.7},
        # ASSUMED: docs/model.md gives no spread of tau0; log-normal about the default 8.1 kPa
        # (calibrated to dry mu ~ 0.5 on a smooth flat, finger.py), 5-95 % at 5-13 kPa, the
        # +-50 % assumed before, now centred (uniform 4-12 kPa had its median at 8 kPa).
        "tau0": {"distribution": "lognormal", "median": "8.1kPa", "sigma": 0.3},
        # ASSUMED: no value in docs/model.md; 0-0.2 about the assumed default 0.1.
        "alpha": {"distribution": "uniform", "low": 0.0, "high": 0.2},
        # ASSUMED: no value in docs/model.md; 0.05-0.15 about the assumed default 0.1 (friction
        # "mostly adhesive", so the hysteresis term stays small; 0.05-0.2 had its median at 0.125).
        "beta": {"distribution": "uniform", "low": 0.05, "high": 0.15},
        # not sampled: work_of_adhesion (every member keeps the finger's w, 0 by default); the
        # "adults-adhesive" preset below draws it.
        # ASSUMED shape around published values: the Weber fraction of friction, lognormal with
        # its median at 0.11 (Gueorguiev et al. 2017) and 0.2 (Fehlberg et al. 2022) at the 95th
        # percentile; no study reports W person by person (fingerpad.person.WEBER_SPREAD). Drawn
        # from a sequence of its own: the fingers above are those of the table without it.
        "weber_fraction": dict(WEBER_SPREAD),
        # no "correlations": docs/model.md (the thesis and its literature) gives no correlation
        # between any two of these parameters, so they are drawn independently.
    },
}
POPULATION_PRESETS["adults-adhesive"] = {
    **POPULATION_PRESETS["adults"],
    # The adults above with a work of adhesion (docs/model.md 7.6, docs/population.md "Adhesion").
    # A dry finger's effective w is at most ~0.24-0.40 J/m^2, an UPPER BOUND from a whole finger's
    # 15 mN pull-off on smooth epoxy (Spinner, Wiechert, Gorb 2016, with R_fp 8-10 mm: DMT 0.24-0.30,
    # JKR 0.32-0.40); none measurable on clean glass (Tiwari, Wang, Persson 2020); no w of finger skin
    # on glass or polymers found person by person. ASSUMED: uniform from 0.01 J/m^2 (little adhesion,
    # every member adheres: the adhesive and the plain model are two models) up to 0.3 J/m^2 (inside
    # both bounds), so its bands are an upper estimate of what adhesion does to a population.
    "work_of_adhesion": {"distribution": "uniform", "low": "0.01J/m2", "high": "0.3J/m2"},
}
