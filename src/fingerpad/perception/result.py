"""The result of comparing two surfaces (:class:`Comparison`, :class:`Surface`): the members'
friction and forced-choice probabilities, the vibration entries, amplitudes and roughness
regimes, and their JSON, NetCDF and CSV forms (docs/perception.md, "Commands and outputs").
Made by :func:`fingerpad.perception.compare.compare` and
:func:`~fingerpad.perception.compare.against_flat`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..references import metadata, netcdf_attribute
from .discrimination import summarise
from .vibration import CHANNELS, Periods, channel, threshold

__all__ = ["Comparison", "Surface"]


@dataclass
class Surface:
    """One side of a comparison.

    Attributes
    ----------
    label
        Its name in the outputs (the study file's stem, ``flat``, or ``A``/``B``).
    prediction
        The nominal finger's :class:`~fingerpad.study.run.Prediction` on it (``None`` for the flat
        reference, whose friction is every finger's ``mu_ref``).
    """

    label: str
    prediction: Any = None

    @property
    def flat(self) -> bool:
        return self.prediction is None or getattr(self.prediction.texture, "family", None) == "flat"

    @property
    def lattice(self) -> bool:
        """Whether it is a generated periodic texture (a lattice: its periods are known exactly)."""
        tex = None if self.prediction is None else self.prediction.texture
        return tex is not None and tex.periodic and tex.family not in (None, "flat")

    def description(self) -> str:
        if self.prediction is None:
            return "the flat reference (A_re = A_fr)"
        from ..textures import describe

        return describe(self.prediction.texture)


@dataclass
class Comparison:
    """The result of :func:`compare` (SI units; arrays are members x loads).

    Attributes
    ----------
    a, b
        The two surfaces.
    loads
        Normal loads, N.
    weber
        Each member's Weber fraction W.
    mu_a, mu_b
        Each member's friction coefficient on A and on B, per load.
    p
        Each member's probability of a correct forced choice between A and B, per load.
    members
        Each member's parameters (SI), or ``None``: one member, the study's finger.
    population
        The population's name, size, seed and method, or ``None``.
    speeds, directions
        Stroke speeds (m/s) and directions (degrees).
    periods
        Per surface label, its :class:`~.vibration.Periods` per direction.
    amplitude
        Per surface label, the estimated vibration amplitude per load (m peak-to-peak).
    regimes
        Per surface label, the roughness regime per load (:func:`~.roughness.regime`).
    ridge_period
        The fingerprint's ridge period, m.
    notes
        Remarks.
    references
        The publications of the methods used (:mod:`fingerpad.references` keys): the perception
        models' and both predictions'.
    """

    a: Surface
    b: Surface
    loads: np.ndarray
    weber: np.ndarray
    mu_a: np.ndarray
    mu_b: np.ndarray
    p: np.ndarray
    members: list[dict[str, float]] | None
    population: dict[str, Any] | None
    speeds: tuple[float, ...]
    directions: tuple[float, ...]
    periods: dict[str, list[Periods]]
    amplitude: dict[str, np.ndarray | None]
    regimes: dict[str, list[dict[str, Any]]]
    ridge_period: float
    notes: list[str] = field(default_factory=list)
    references: tuple[str, ...] = ()

    def summary(self) -> dict[str, np.ndarray]:
        """Per load: ``fraction`` of the members telling A from B and ``p_correct_median``."""
        return dict(summarise(self.p))

    def vibration(self) -> list[dict[str, Any]]:
        """One entry per surface, stroke direction, harmonic (the fundamental, and the strongest when
        it is another) and speed: ``texture``, ``direction_deg``, ``harmonic``, ``wavelength_m``,
        ``speed_m_s``, ``frequency_hz`` (``f = v / lambda``, Eq. P.4), ``channel``,
        ``threshold_m`` (detection threshold at f, peak-to-peak), ``sensation_level_db`` (per
        load: 20 log10 of the amplitude estimate over the threshold), ``below_ridge_period``
        (lambda shorter than the fingerprint's ridge period) and ``power_share``."""
        out: list[dict[str, Any]] = []
        for surface in (self.a, self.b):
            amp = self.amplitude.get(surface.label)
            for per in self.periods.get(surface.label, []):
                rows = [(1, per.fundamental, None)] if not math.isnan(per.fundamental) else []
                if per.harmonic != 1 or math.isnan(per.fundamental):
                    rows.append((per.harmonic, per.strongest, per.power_share))
                else:
                    rows = [(1, per.fundamental, per.power_share)]
                for harmonic, wavelength, share in rows:
                    for v in self.speeds:
                        f = v / wavelength if math.isfinite(wavelength) else 0.0
                        thr = float(threshold(f)) if f > 0 else math.nan
                        level = None
                        if amp is not None and f > 0:
                            with np.errstate(divide="ignore"):
                                level = (20 * np.log10(np.asarray(amp, float) / thr)).tolist()
                        out.append({
                            "texture": surface.label, "direction_deg": per.direction_deg, "harmonic": harmonic,
                            "wavelength_m": wavelength, "speed_m_s": v, "frequency_hz": f, "channel": channel(f),
                            "threshold_m": thr, "sensation_level_db": level,
                            "below_ridge_period": bool(wavelength < self.ridge_period),
                            "power_share": share,
                        })
        return out

    def as_dict(self) -> dict[str, Any]:
        """The ``perception`` entry of ``compare.json`` (and of ``predict.json`` with
        ``--perception``); SI units, listed under ``units``."""
        s = self.summary()
        keys = [f"{f:g}" for f in self.loads]
        return {
            "a": {"label": self.a.label, "description": self.a.description()},
            "b": {"label": self.b.label, "description": self.b.description()},
            "loads": self.loads,
            "weber_fraction": self._weber_summary(),
            "population": self.population,
            "discrimination": {
                "threshold": 0.75,
                "fraction": dict(zip(keys, s["fraction"].tolist(), strict=True)),
                "p_correct_median": dict(zip(keys, s["p_correct_median"].tolist(), strict=True)),
            },
            "members": {"mu_a": self.mu_a, "mu_b": self.mu_b, "p_correct": self.p, "weber_fraction": self.weber,
                        "parameters": self.members},
            "mu": {self.a.label: _band(self.mu_a), self.b.label: _band(self.mu_b)},
            "vibration": self.vibration(),
            "amplitude": {k: (None if v is None else np.asarray(v)) for k, v in self.amplitude.items()},
            "roughness": self.regimes,
            "speeds": list(self.speeds),
            "directions": list(self.directions),
            "ridge_period": self.ridge_period,
            "channels": [{"channel": key, "low_hz": lo, "high_hz": hi, "meaning": text}
                         for lo, hi, key, text in CHANNELS],
            "notes": self.notes,
            "references": metadata(self.references),
            "units": {"loads": "N", "mu": "1", "p_correct": "1 (probability of a correct forced choice)",
                      "fraction": "1 (fraction of the members with p_correct >= 0.75)", "weber_fraction": "1",
                      "wavelength_m": "m", "speed_m_s": "m/s", "frequency_hz": "Hz",
                      "threshold_m": "m peak-to-peak", "amplitude": "m peak-to-peak (estimate)",
                      "sensation_level_db": "dB re the detection threshold (estimate)", "ridge_period": "m",
                      "spacing_m": "m"},
        }

    def _weber_summary(self) -> dict[str, Any]:
        w = np.asarray(self.weber, float)
        if w.size and np.all(w == w[0]):
            return {"value": float(w[0]), "drawn": False}
        return {"value": None, "drawn": True, "median": float(np.median(w)), "min": float(w.min()),
                "max": float(w.max())}

    def dataset(self) -> Any:
        """The comparison as an :class:`xarray.Dataset` (``compare.nc``): the member arrays along
        ``member`` and ``load``, the fraction and median per load, the vibration entries along
        ``entry``, the amplitudes and regimes per surface and load."""
        import xarray as xr

        s = self.summary()
        vib = self.vibration()
        data: dict[str, Any] = {
            "mu_a": xr.Variable(("member", "load"), self.mu_a, {"units": "1", "long_name": f"mu on {self.a.label}"}),
            "mu_b": xr.Variable(("member", "load"), self.mu_b, {"units": "1", "long_name": f"mu on {self.b.label}"}),
            "p_correct": xr.Variable(("member", "load"), self.p, {"units": "1", "long_name": "probability of a "
                                                                    "correct forced choice (Eqs. P.1-P.3)"}),
            "weber_fraction": xr.Variable(("member",), self.weber, {"units": "1"}),
            "fraction": xr.Variable(("load",), s["fraction"], {"units": "1", "long_name": "fraction of the "
                                                              "members with p_correct >= 0.75"}),
            "p_correct_median": xr.Variable(("load",), s["p_correct_median"], {"units": "1"}),
        }
        for key in ("direction_deg", "harmonic", "wavelength_m", "speed_m_s", "frequency_hz", "threshold_m"):
            unit = {"direction_deg": "deg", "harmonic": "1", "wavelength_m": "m", "speed_m_s": "m/s",
                    "frequency_hz": "Hz", "threshold_m": "m"}[key]
            data[f"vibration_{key}"] = xr.Variable(("entry",), np.array([e[key] for e in vib], float),
                                                   {"units": unit})
        for key in ("texture", "channel"):
            data[f"vibration_{key}"] = xr.Variable(("entry",), np.array([e[key] for e in vib], dtype=str))
        for i, surface in enumerate((self.a, self.b)):
            side = "ab"[i]
            amp = self.amplitude.get(surface.label)
            if amp is not None:
                data[f"amplitude_{side}"] = xr.Variable(("load",), np.asarray(amp, float),
                                                        {"units": "m", "long_name": "estimated peak-to-peak skin "
                                                         f"vibration on {surface.label}"})
            data[f"roughness_{side}"] = xr.Variable(("load",), np.array([r["verdict"] for r in
                                                                         self.regimes[surface.label]], dtype=str))
        ds = xr.Dataset(data, coords={"load": ("load", np.asarray(self.loads, float), {"units": "N"}),
                                      "member": np.arange(self.p.shape[0]), "entry": np.arange(len(vib))})
        ds.attrs.update({"title": "fingerpad compare", "surface_a": self.a.label, "surface_b": self.b.label,
                         "description_a": self.a.description(), "description_b": self.b.description(),
                         "ridge_period_m": self.ridge_period, "threshold": 0.75,
                         "population": self.population["name"] if self.population else "none",
                         "references": netcdf_attribute(self.references)})
        return ds

    def table_rows(self) -> list[dict[str, Any]]:
        """One row per load (the CSV and the terminal table): the median mu of each surface, the
        fraction telling them apart, the median P and each surface's roughness verdict."""
        s = self.summary()
        rows = []
        for i, load in enumerate(self.loads):
            rows.append({"load_N": float(load), f"mu_{self.a.label}": float(np.median(self.mu_a[:, i])),
                         f"mu_{self.b.label}": float(np.median(self.mu_b[:, i])),
                         "fraction_telling_apart": float(s["fraction"][i]),
                         "p_correct_median": float(s["p_correct_median"][i]),
                         f"roughness_{self.a.label}": self.regimes[self.a.label][i]["verdict"],
                         f"roughness_{self.b.label}": self.regimes[self.b.label][i]["verdict"]})
        return rows

    def csv_text(self) -> str:
        """``compare.csv``: :meth:`table_rows` (SI units in the column names)."""
        return _csv(self.table_rows())

    def vibration_csv_text(self) -> str:
        """``compare_vibration.csv``: :meth:`vibration` without the per-load sensation levels."""
        rows = [{k: v for k, v in e.items() if k != "sensation_level_db"} for e in self.vibration()]
        return _csv(rows)


def _csv(rows: list[dict[str, Any]]) -> str:
    import csv
    import io

    buffer = io.StringIO()
    if rows:
        writer = csv.DictWriter(buffer, fieldnames=list(rows[0]), lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    return buffer.getvalue()


def _band(values: np.ndarray) -> dict[str, Any]:
    """Per load: the median and the 5 and 95 % quantiles over the members."""
    q = np.quantile(np.asarray(values, float), [0.05, 0.5, 0.95], axis=0)
    return {"0.05": q[0], "0.5": q[1], "0.95": q[2]}
