"""Two surfaces on the same fingers: who tells them apart, what each vibrates at, rough or smooth.

:func:`compare` predicts surface A and surface B (another texture, a measured map, or the flat
reference ``"flat"``) for the same fingers, at the same loads: the study's finger, or every
member of a population (the same members for both surfaces, drawn once). Per load it gives each
surface's friction, each member's probability of telling them apart in a forced choice
(:mod:`.discrimination`, Eqs. P.1-P.3), the fraction of members who do (``P >= 0.75``) and the
median ``P``; per surface the vibration frequencies and receptor channels at the stroke speeds
and directions and an amplitude estimate (:mod:`.vibration`), and the roughness regime per load
(:mod:`.roughness`). The friction numbers are those of ``fingerpad predict`` (``--population``)
for each surface: nothing here solves anything but the amplitude's one cell per load.

B is taken under A's fingers and loads: its study file gives its texture, material and numerics;
a ``[finger]`` of its own that differs from A's is replaced by A's, with a note.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FingerpadError
from .discrimination import WEBER_FRACTION, p_correct, summarise
from .roughness import regime
from .vibration import (
    CHANNELS,
    Periods,
    amplitude,
    channel,
    fingerprint_period,
    periods,
    threshold,
)

__all__ = ["DEFAULT_DIRECTIONS", "DEFAULT_SPEEDS", "FLAT", "MAX_DIRECTIONS", "MAX_SPEEDS", "Comparison", "Surface",
           "against_flat", "assemble", "check_directions", "check_speeds", "compare", "parse_directions",
           "parse_speeds", "surface_verdicts", "weber_fractions"]

#: The name of the flat reference as surface B.
FLAT = "flat"
#: Stroke speeds of active touch, m/s: 20-100 mm/s (the band the issue reports; typical
#: exploration, Greenspon et al. 2019 measured 10-160 mm/s).
DEFAULT_SPEEDS = (0.02, 0.1)
#: Stroke directions, degrees from the texture's x axis: along x and along y.
DEFAULT_DIRECTIONS = (0.0, 90.0)
#: Caps on what a user may list.
MAX_SPEEDS, MAX_DIRECTIONS = 16, 16


def check_speeds(speeds: Sequence[float]) -> tuple[float, ...]:
    """Stroke speeds (m/s), checked: 1 to :data:`MAX_SPEEDS` positive finite values, sorted."""
    values = tuple(sorted(float(v) for v in speeds))
    if not values or len(values) > MAX_SPEEDS:
        raise FingerpadError(f"--speed: give 1 to {MAX_SPEEDS} stroke speeds, got {len(values)}")
    if not all(math.isfinite(v) and v > 0 for v in values):
        raise FingerpadError(f"--speed: stroke speeds must be positive, got {list(speeds)}")
    return values


def check_directions(directions: Sequence[float]) -> tuple[float, ...]:
    """Stroke directions (degrees), checked: 1 to :data:`MAX_DIRECTIONS` finite values, in order."""
    values = tuple(float(v) for v in directions)
    if not values or len(values) > MAX_DIRECTIONS:
        raise FingerpadError(f"--directions: give 1 to {MAX_DIRECTIONS} stroke directions, got {len(values)}")
    if not all(math.isfinite(v) for v in values):
        raise FingerpadError(f"--directions: directions must be finite angles, got {list(directions)}")
    return values


def parse_speeds(text: str | None) -> tuple[float, ...]:
    """Stroke speeds from text (``--speed``, the explorer's field): one speed, ``LOW:HIGH`` (the
    two ends of a band) or ``START:STOP:COUNT``, m/s with unit suffixes (``20mm/s:100mm/s``);
    ``None``: :data:`DEFAULT_SPEEDS`."""
    from ..units import parse_positive, parse_range

    if text is None:
        return DEFAULT_SPEEDS
    parts = str(text).split(":")
    if len(parts) == 2:
        values = [parse_positive(p, "speed", name="--speed") for p in parts]
    else:
        values = parse_range(text, "speed", name="--speed", max_count=MAX_SPEEDS)
    return check_speeds(values)


def parse_directions(text: str | None) -> tuple[float, ...]:
    """Stroke directions from text (``--directions 0,90``): angles in degrees, or with ``deg`` or
    ``rad``; ``None``: :data:`DEFAULT_DIRECTIONS`."""
    from ..params import parse_angle

    if text is None:
        return DEFAULT_DIRECTIONS
    items = str(text).split(",")
    if any(not t.strip() for t in items):
        raise FingerpadError(f"--directions: expected angles separated by commas, got {text!r}")
    return check_directions([math.degrees(parse_angle(t, "--directions")) for t in items])


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
                         "population": self.population["name"] if self.population else "none"})
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


def _label(study: Any, default: str) -> str:
    return Path(study.source).stem if getattr(study, "source", None) else default


def _under_fingers_of(b: Any, a: Any, notes: list[str]) -> Any:
    """B with A's finger and loads (its texture, material and numerics kept)."""
    if b.finger != a.finger:
        notes.append(f"B's finger ({getattr(b.finger, 'name', 'its own')}) replaced by A's: both surfaces are "
                     "compared on the same fingers")
    return dataclasses.replace(b, finger=a.finger, loads=np.asarray(a.loads, float), zones_at=None)


def _spacing(per: Sequence[Periods]) -> float:
    """The shortest finite period of a texture along the stroke directions (its spacing)."""
    finite = [p.fundamental for p in per if math.isfinite(p.fundamental)]
    return min(finite) if finite else math.inf


def surface_verdicts(pred: Any, directions: Sequence[float], notes: list[str], amplitudes: bool = True) -> tuple[
        list[Periods], np.ndarray | None, list[dict[str, Any]]]:
    """One surface's periods along ``directions``, its amplitude estimate per load (m p-p; the
    unit cell solved at the mean ridge pressure ``F / A_fr`` of the nominal finger; ``None``
    without ``amplitudes``) and its roughness regime per load; for a measured map, no periods and
    no amplitude (a note says so)."""
    states = pred.states()
    surface = Surface("", pred)
    if surface.flat:
        return [], np.zeros(len(states)), [regime(math.inf, s) for s in states]
    if not surface.lattice:
        notes.append(f"{describe_short(pred)}: a measured map has no lattice period: its vibration and "
                     "roughness regime are not estimated")
        return [], None, [{"verdict": "not estimated (measured map)", "state": s, "scale": None} for s in states]
    tex = pred.texture
    per = [periods(tex, d) for d in directions]
    # the spacing of the roughness verdicts: the shortest period along the cell's own axes
    axes = [periods(tex, d) for d in (0.0, 90.0)]
    spacing = _spacing(axes)
    if not amplitudes:
        return per, None, [regime(spacing, s) for s in states]
    study = pred.study
    loads = np.asarray(study.loads, float)
    pressures = loads / np.asarray(study.finger.ridge_area(loads), float)
    amp = amplitude(tex, pred.reduced_modulus, pressures, layer=study.finger.layer, tol=max(study.tol, 1e-7),
                    max_iter=study.max_iter)
    return per, amp, [regime(spacing, s) for s in states]


def describe_short(pred: Any) -> str:
    tex = pred.texture
    return str(tex.name or tex.family or "texture")


def weber_fractions(weber: Any, size: int) -> np.ndarray:
    """Every member's Weber fraction: ``weber`` (a number or text, checked against
    :data:`~.discrimination.WEBER_FRACTION`) or its default, for ``size`` members."""
    value = WEBER_FRACTION.default if weber is None else WEBER_FRACTION.check(
        WEBER_FRACTION.parse(weber, "--weber-fraction") if isinstance(weber, str) else float(weber),
        "--weber-fraction")
    return np.full(size, float(value))


def compare(a: Any, b: Any, *, population: Any = None, speeds: Sequence[float] = DEFAULT_SPEEDS,
            directions: Sequence[float] = DEFAULT_DIRECTIONS, weber: Any = None,
            notice: Callable[[str], None] | None = None) -> Comparison:
    """Compare surface ``a`` with ``b`` on the same fingers (see the module docstring).

    Parameters
    ----------
    a
        A :class:`~fingerpad.study.spec.Study`: the texture, material, finger and loads.
    b
        Another study (its texture, material and numerics; A's finger and loads), or
        ``"flat"``: the flat reference, ``A_re = A_fr`` (every finger's ``mu_ref``).
    population
        A :class:`~fingerpad.study.population.Population`, or ``None`` for the study's finger.
    speeds
        Stroke speeds, m/s (default 20 and 100 mm/s).
    directions
        Stroke directions, degrees from the texture's x axis (default 0 and 90).
    weber
        The Weber fraction W of every member (``None``: :data:`~.discrimination.WEBER_FRACTION`'s
        default, 0.11).
    notice
        Called with a short text before each prediction.

    Raises
    ------
    FingerpadError
        Bad speeds, directions or Weber fraction (checked before any prediction); what
        ``predict`` refuses for either study.
    """
    from ..study.run import run_study

    speeds = check_speeds(speeds)
    directions = check_directions(directions)
    notes: list[str] = []
    flat_b = isinstance(b, str)
    if flat_b and b.strip().lower() != FLAT:
        raise FingerpadError(f"surface B {b!r}: a study file or {FLAT!r} (the flat reference)")
    b_study = None if flat_b else _under_fingers_of(b, a, notes)
    label_a = _label(a, "A")
    label_b = FLAT if flat_b else _label(b, "B")
    if label_b == label_a:
        label_a, label_b = f"A:{label_a}", f"B:{label_b}"
    say = notice or (lambda text: None)
    members = population.sample() if population is not None else None
    w = weber_fractions(weber, 1 if members is None else len(members))  # checked before the predictions
    if population is not None:
        from ..study.population import run_population

        say(f"{label_a}: {len(members)} fingers of {population.name!r}")
        ra = run_population(a, population)
        notes.extend(ra.notes)
        pred_a, mu_a = ra.nominal, ra.values("mu")
        if flat_b:
            pred_b, mu_b = None, ra.values("mu_ref")
        else:
            say(f"{label_b}: the same {len(members)} fingers")
            rb = run_population(b_study, population)
            pred_b, mu_b = rb.nominal, rb.values("mu")
    else:
        say(f"{label_a}: the study's finger")
        pred_a = run_study(a)
        mu_a = np.asarray(pred_a.primary.mu, float)[None, :]
        if flat_b:
            pred_b, mu_b = None, np.asarray(pred_a.primary.mu_ref, float)[None, :]
        else:
            say(f"{label_b}: the study's finger")
            pred_b = run_study(b_study)
            mu_b = np.asarray(pred_b.primary.mu, float)[None, :]
    return assemble(Surface(label_a, pred_a), Surface(label_b, pred_b), mu_a, mu_b, w, members=members,
                    population=population, speeds=speeds, directions=directions, notes=notes, notice=say)


def against_flat(pred: Any, result: Any = None, *, speeds: Sequence[float] = DEFAULT_SPEEDS,
                 directions: Sequence[float] = DEFAULT_DIRECTIONS, weber: Any = None,
                 amplitudes: bool = True) -> Comparison:
    """The single-texture verdicts of ``predict --perception``: the prediction ``pred`` (and the
    population's ``result``, :class:`~fingerpad.study.population.PopulationResult`) against the
    flat reference, from the numbers already predicted (every finger's ``mu`` and ``mu_ref``);
    only the amplitude estimate solves the cell (once per load; ``amplitudes=False``: none, the
    explorer's quick view)."""
    speeds = check_speeds(speeds)
    directions = check_directions(directions)
    if result is not None:
        mu_a, mu_b, members, population = result.values("mu"), result.values("mu_ref"), result.members, \
            result.population
    else:
        curve = pred.primary
        mu_a, mu_b = np.asarray(curve.mu, float)[None, :], np.asarray(curve.mu_ref, float)[None, :]
        members, population = None, None
    w = weber_fractions(weber, mu_a.shape[0])
    return assemble(Surface(_label(pred.study, "texture"), pred), Surface(FLAT, None), mu_a, mu_b, w,
                    members=members, population=population, speeds=speeds, directions=directions, notes=[],
                    amplitudes=amplitudes)


def assemble(a: Surface, b: Surface, mu_a: np.ndarray, mu_b: np.ndarray, weber: np.ndarray, *,
             members: list[dict[str, float]] | None, population: Any, speeds: tuple[float, ...],
             directions: tuple[float, ...], notes: list[str],
             notice: Callable[[str], None] | None = None, amplitudes: bool = True) -> Comparison:
    """The :class:`Comparison` of two predicted surfaces: each member's P (Eqs. P.1-P.3) from its
    friction on both, and each surface's periods, amplitude and roughness regime."""
    say = notice or (lambda text: None)
    loads = np.asarray(a.prediction.study.loads, float)
    p = p_correct(mu_a, mu_b, np.asarray(weber, float)[:, None])
    per: dict[str, list[Periods]] = {}
    amp: dict[str, np.ndarray | None] = {}
    regimes: dict[str, list[dict[str, Any]]] = {}
    for surface in (a, b):
        if surface.prediction is None:
            per[surface.label], amp[surface.label] = [], np.zeros(loads.size)
            regimes[surface.label] = [regime(math.inf, "full") for _ in loads]
            continue
        say(f"{surface.label}: vibration amplitude")
        per[surface.label], amp[surface.label], regimes[surface.label] = surface_verdicts(
            surface.prediction, directions, notes, amplitudes)
    pop = None if population is None else {"name": population.name, "size": len(members or []),
                                           "seed": population.seed, "method": population.method}
    return Comparison(a=a, b=b, loads=loads, weber=np.asarray(weber, float), mu_a=mu_a, mu_b=mu_b, p=p,
                      members=members, population=pop, speeds=speeds, directions=directions, periods=per,
                      amplitude=amp, regimes=regimes, ridge_period=fingerprint_period(a.prediction.study.finger),
                      notes=notes)
