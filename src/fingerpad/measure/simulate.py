"""Synthetic tribometer recordings with known parameters (for tests and how-tos)."""

from __future__ import annotations

import csv
import json
import math
import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from ..errors import FingerpadError
from ..io import OutputFolder
from .micro_models import Model, TextureGeometry, resolve_finger, texture_model
from .recordings import Recording


@dataclass(frozen=True)
class SimulationConfig:
    """A synthetic study (see :func:`simulate_study`); SI units.

    Attributes
    ----------
    participants
        Number of participants; each draws E_s, k, n uniformly from the ranges below.
    repetitions
        Files per participant and sample.
    strokes_per_file
        Reciprocating strokes in each file, each at its own load.
    load_range
        Loads (N) spread log-uniformly over the strokes of a file.
    stroke_length, speed, dwell
        Stroke travel (m), sliding speed (m/s) and pause at each reversal (s).
    sampling_rate
        Samples per second.
    reference
        Name of the flat reference sample.
    textures
        Textured samples: name -> :class:`TextureGeometry`.
    skin_modulus_range, k_range, n_range
        Ranges of the participants' E_s (Pa) and power law ``mu_ref = k F^(n-1)``.
    force_noise
        Relative noise of the friction force (stick-slip, sensor) per sample.
    stroke_noise, file_noise
        Log-normal spread of mu between strokes and between files (repetitions): skin
        moisture and finger posture change from stroke to stroke and session to session.
    drift
        Sensor offset drift over a file, N (normal and friction).
    outlier_rate
        Probability that a stroke's friction is raised 1.5-2x (e.g. a moisture burst).
    finger
        Finger preset of the micro-model (the same for everybody, so the normalisation holds).
    normal_range, friction_range
        Ranges of the force sensors, N (``None``: unlimited): the recorded normal force is capped
        at ``normal_range`` and the friction force at ``+-friction_range``, as a load cell driven
        past its range records (saturation, clipping).
    """

    participants: int = 4
    repetitions: int = 2
    strokes_per_file: int = 12
    load_range: tuple[float, float] = (0.1, 5.0)
    stroke_length: float = 0.03
    speed: float = 0.03
    dwell: float = 0.15
    sampling_rate: float = 200.0
    reference: str = "flat"
    textures: Mapping[str, TextureGeometry] = field(
        default_factory=lambda: {
            "bumps": TextureGeometry(radius=50e-6, height=18e-6, spacing=100e-6)
        }
    )
    skin_modulus_range: tuple[float, float] = (0.25e6, 0.4e6)
    k_range: tuple[float, float] = (0.35, 0.8)
    n_range: tuple[float, float] = (0.6, 0.8)
    force_noise: float = 0.03
    stroke_noise: float = 0.05
    file_noise: float = 0.03
    drift: float = 0.003
    outlier_rate: float = 0.02
    finger: str = "default"
    normal_range: float | None = None
    friction_range: float | None = None

    def __post_init__(self) -> None:
        for name in ("normal_range", "friction_range"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value > 0):
                raise FingerpadError(f"{name} must be a positive force (N) or None, got {value!r}")
        if self.participants < 1 or self.repetitions < 1 or self.strokes_per_file < 2:
            raise FingerpadError("need at least 1 participant, 1 repetition and 2 strokes per file")
        for name, value, cap in (("participants", self.participants, MAX_PARTICIPANTS),
                                 ("repetitions", self.repetitions, MAX_REPETITIONS),
                                 ("strokes per file", self.strokes_per_file, MAX_STROKES_PER_FILE)):
            if value > cap:
                raise FingerpadError(f"{name}: at most {cap} in a simulated study, got {value}")
        lo, hi = self.load_range
        if not 0 < lo < hi:
            raise FingerpadError(f"load range must satisfy 0 < low < high, got {self.load_range!r}")
        if self.reference in self.textures:
            raise FingerpadError(f"the reference {self.reference!r} cannot also be a textured sample")
        for name in ("stroke_length", "speed", "sampling_rate"):
            if not getattr(self, name) > 0:
                raise FingerpadError(f"{name} must be positive")
        if self.stroke_length / self.speed * self.sampling_rate < 40:
            raise FingerpadError("a stroke must span at least 40 samples (raise the sampling rate)")
        files = self.participants * self.repetitions * (1 + len(self.textures))
        per_file = self.strokes_per_file * (self.stroke_length / self.speed + 2 * self.dwell) * self.sampling_rate
        if files * per_file > MAX_SAMPLES:
            raise FingerpadError(
                f"the study would hold about {files * per_file:.3g} samples ({files} files of {per_file:.3g}); "
                f"at most {MAX_SAMPLES:.0e} are allowed: lower the sampling rate, strokes or participants")


#: Most samples a simulated study may hold (all files; checked before anything is allocated).
MAX_SAMPLES = 5e7
#: Most participants, files per participant and sample, and strokes per file of a simulated
#: study: each participant and each file is a row of the tables and a recording on disk, beyond
#: what the sample budget alone bounds (1 stroke-pair files of many participants).
MAX_PARTICIPANTS = 1000
MAX_REPETITIONS = 100
MAX_STROKES_PER_FILE = 10_000


def _smoothstep(u: np.ndarray) -> np.ndarray:
    u = np.clip(u, 0.0, 1.0)
    return u * u * (3.0 - 2.0 * u)


def _simulate_file(
    rng: np.random.Generator,
    cfg: SimulationConfig,
    mu_of_load: Callable[[np.ndarray], np.ndarray],
    first_sense: int,
) -> tuple[dict[str, np.ndarray], list[int]]:
    """Time series of one reciprocating recording (SI) and the (1-based) outlier strokes."""
    fs = cfg.sampling_rate
    m = cfg.strokes_per_file
    lo, hi = cfg.load_range
    # loads spread over the range, shuffled, so that drift and load are not confounded
    loads = np.exp(rng.permutation(np.linspace(math.log(lo), math.log(hi), m)) + rng.normal(0, 0.05, m))
    t_move = cfg.stroke_length / cfg.speed
    t_acc = 0.1 * t_move
    n_move, n_dwell = int(round(t_move * fs)), int(round(cfg.dwell * fs))
    pieces_v, pieces_target, pieces_phase, burst = [], [], [], []
    bursts = rng.random(m) < cfg.outlier_rate
    level = np.exp(cfg.file_noise * rng.standard_normal() + cfg.stroke_noise * rng.standard_normal(m))
    for j in range(m):
        sense = first_sense if j % 2 == 0 else -first_sense
        # dwell: at rest while the participant adjusts the load to the next target
        pieces_v.append(np.zeros(n_dwell))
        prev = loads[j - 1] if j else loads[0]
        u = np.arange(n_dwell) / max(n_dwell - 1, 1)
        pieces_target.append(prev + (loads[j] - prev) * _smoothstep(u))
        pieces_phase.append(np.full(n_dwell, -1.0))
        burst.append(np.ones(n_dwell))
        tt = np.arange(n_move) / fs
        ramp = _smoothstep(tt / t_acc) * _smoothstep((t_move - tt) / t_acc)
        pieces_v.append(sense * cfg.speed * ramp)
        pieces_target.append(np.full(n_move, loads[j]))
        pieces_phase.append(tt)
        burst.append(np.full(n_move, level[j] * (rng.uniform(1.5, 2.0) if bursts[j] else 1.0)))
    pieces_v.append(np.zeros(n_dwell))
    pieces_target.append(np.full(n_dwell, loads[-1]))
    pieces_phase.append(np.full(n_dwell, -1.0))
    burst.append(np.ones(n_dwell))
    v = np.concatenate(pieces_v)
    target = np.concatenate(pieces_target)
    phase = np.concatenate(pieces_phase)
    factor = np.concatenate(burst)
    n = v.size
    t = np.arange(n) / fs
    x = np.cumsum(v) / fs
    # participant's load control: slow wobble and tremor around the target
    wobble = 1.0 + 0.04 * np.sin(2 * math.pi * rng.uniform(0.5, 1.5) * t + rng.uniform(0, 2 * math.pi))
    fn_true = target * wobble * (1.0 + 0.01 * rng.standard_normal(n))
    mu = mu_of_load(np.clip(fn_true, lo / 10, None)) * factor
    # static-friction peak at the start of each stroke, friction vanishing at standstill
    peak = np.where(phase >= 0, 1.0 + 0.4 * np.exp(-np.clip(phase, 0, None) / (0.04 * t_move)), 1.0)
    ft_true = -np.tanh(v / (0.02 * cfg.speed)) * mu * fn_true * peak
    ft_true *= 1.0 + cfg.force_noise * rng.standard_normal(n)
    drift_n = cfg.drift * rng.uniform(-1, 1) * t / t[-1]
    drift_t = cfg.drift * rng.uniform(-1, 1) * t / t[-1]
    sensor = 0.002
    normal = fn_true + drift_n + sensor * rng.standard_normal(n)
    friction = ft_true + drift_t + sensor * rng.standard_normal(n)
    if cfg.normal_range is not None:  # a load cell at its range records its full-scale value
        normal = np.minimum(normal, cfg.normal_range)
    if cfg.friction_range is not None:
        friction = np.clip(friction, -cfg.friction_range, cfg.friction_range)
    return {
        "time": t,
        "normal": normal,
        "friction": friction,
        "position": x + 2e-6 * rng.standard_normal(n),
    }, [int(j) + 1 for j in np.flatnonzero(bursts)]


def simulate_recording(
    config: SimulationConfig = SimulationConfig(),
    *,
    k: float = 0.5,
    n: float = 0.7,
    seed: int = 0,
    source: str = "simulated.csv",
) -> Recording:
    """One synthetic recording in memory: the time series :func:`simulate_study` writes to a
    file (same noise, drift, static peaks, outliers and sensor ranges), on a sample with
    ``mu = k F^(n-1)``; for tests of stroke detection and clipping without files.

    Returns
    -------
    Recording
        Time (s), normal and friction force (N), position (m); ``participant`` ``P1``,
        ``sample`` ``config.reference``.
    """
    rng = np.random.default_rng(seed)
    data, _ = _simulate_file(rng, config, lambda f: k * f ** (n - 1.0), first_sense=1)
    return Recording(source=source, normal=data["normal"], friction=data["friction"], time=data["time"],
                     position=data["position"], participant="P1", sample=config.reference, repetition="1")


def _mean_log_uniform(lo: float, hi: float) -> float:
    """``E[ln X]`` for ``X`` uniform on ``[lo, hi]``."""
    if hi <= lo:
        return math.log(lo)
    return (hi * math.log(hi) - lo * math.log(lo)) / (hi - lo) - 1.0


def population_truth(config: SimulationConfig) -> dict[str, float]:
    """The population power law of a simulated study: ``k`` is the geometric mean of the
    participants' k (``exp E[ln k]``, what a fit in log space estimates) and ``n`` their mean
    exponent, for k and n drawn uniformly from ``config.k_range`` and ``config.n_range``; with
    the standard deviations of ``ln k`` and ``n`` between people."""
    (k_lo, k_hi), (n_lo, n_hi) = config.k_range, config.n_range
    m1 = _mean_log_uniform(k_lo, k_hi)
    if k_hi > k_lo:  # E[(ln X)^2] for X uniform: the antiderivative x (ln^2 x - 2 ln x + 2)
        def g(x: float) -> float:
            return x * (math.log(x) ** 2 - 2 * math.log(x) + 2)
        m2 = (g(k_hi) - g(k_lo)) / (k_hi - k_lo)
    else:
        m2 = m1 * m1
    return {"k": math.exp(m1), "n": 0.5 * (n_lo + n_hi), "sd_ln_k": math.sqrt(max(m2 - m1 * m1, 0.0)),
            "sd_n": (n_hi - n_lo) / math.sqrt(12.0)}


def simulate_stroke_table(config: SimulationConfig = SimulationConfig(), *, seed: int = 0
                          ) -> tuple[pd.DataFrame, dict[str, Any]]:
    """A study's stroke table on the reference sample drawn directly, without time series.

    Each participant draws k and n from ``config.k_range`` and ``config.n_range`` (as in
    :func:`simulate_study`); each of their ``repetitions`` recordings has a log-normal level
    (``file_noise``) and ``strokes_per_file`` strokes at loads spread log-uniformly over
    ``load_range`` with log-normal scatter (``stroke_noise``). Thousands of studies take
    seconds, which is what checking the coverage of population intervals needs.

    Returns
    -------
    strokes, truth
        The columns the study-level fits read (``participant``, ``sample``, ``direction``,
        ``file``, ``session``, ``sense``, ``load``, ``mu``, ``mu_norm`` = 1, ``outlier``,
        ``clipped``), and the truth: per participant k and n, and :func:`population_truth`.
    """
    rng = np.random.default_rng(seed)
    lo, hi = config.load_range
    m = config.strokes_per_file
    width = max(2, len(str(config.participants)))
    frames, people = [], {}
    for i in range(config.participants):
        pid = f"P{i + 1:0{width}d}"
        k = float(rng.uniform(*config.k_range))
        n_exp = float(rng.uniform(*config.n_range))
        people[pid] = {"k": k, "n": n_exp}
        for rep in range(1, config.repetitions + 1):
            loads = np.exp(rng.permutation(np.linspace(math.log(lo), math.log(hi), m)) + rng.normal(0, 0.05, m))
            level = config.file_noise * rng.standard_normal() + config.stroke_noise * rng.standard_normal(m)
            frames.append(pd.DataFrame({
                "file": f"{pid}_{config.reference}_{rep}.csv", "participant": pid, "sample": config.reference,
                "direction": "", "repetition": str(rep), "session": "", "stroke": np.arange(1, m + 1),
                "sense": np.where(np.arange(m) % 2 == 0, "+", "-"), "load": loads,
                "mu": k * loads ** (n_exp - 1.0) * np.exp(level), "mu_norm": 1.0, "outlier": False, "clipped": "",
            }))
    return pd.concat(frames, ignore_index=True), {"participants": people, "population": population_truth(config)}


def _write_csv(path: Path, header: Sequence[str], rows: Iterable[Sequence[Any]]) -> None:
    with path.open("w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        w.writerows(rows)


def simulate_study(
    out: str | os.PathLike[str],
    config: SimulationConfig = SimulationConfig(),
    *,
    seed: int = 0,
    model_factory: Callable[[TextureGeometry, Any], Model] | None = None,
) -> dict[str, Any]:
    """Write a synthetic tribometer study: recordings, ``manifest.csv``, ``samples.csv``, ``truth.json``.

    Each participant gets a skin modulus E_s and a reference power law ``mu_ref = k F^(n-1)``;
    on a texture ``mu = mu_ref(F) * model(F, E_s)`` with the same micro-model as the analysis
    (:func:`hertz_texture_model`). Recordings (``{participant}_{sample}_{repetition}.csv``:
    ``time [s]``, ``Fn [N]``, ``Ft [mN]``, ``x [mm]``) hold reciprocating strokes at loads over
    ``config.load_range`` with load wobble, friction noise, static-friction peaks at stroke
    starts, sensor drift and occasional outlier strokes. Files are written into a temporary
    folder and moved into ``out`` at the end.

    Parameters
    ----------
    out
        Output folder (created; existing files of the same names are replaced).
    config
        :class:`SimulationConfig`.
    seed
        Random seed; the same seed gives the same files.
    model_factory
        ``(geometry, finger) -> model``; default :func:`texture_model` (BEM unless the geometry says hertz).

    Returns
    -------
    dict
        The truth: per participant ``skin_modulus``, ``k``, ``n``; textures; files.
    """
    rng = np.random.default_rng(seed)
    finger = resolve_finger(config.finger)
    factory = model_factory or texture_model
    models = {name: factory(geom, finger) for name, geom in config.textures.items()}
    grid = np.geomspace(config.load_range[0] / 10, config.load_range[1] * 2, 64)
    width = max(2, len(str(config.participants)))
    truth: dict[str, Any] = {"seed": seed, "reference": config.reference, "finger": config.finger,
                             "participants": {}, "textures": {k: asdict(v) for k, v in config.textures.items()},
                             "outliers": []}
    manifest = []
    out_path = Path(out)
    with OutputFolder(out_path) as folder:  # refuses a folder of the user's files; errors name the user's path
        tmp = folder.build
        for i in range(config.participants):
            pid = f"P{i + 1:0{width}d}"
            es = float(rng.uniform(*config.skin_modulus_range))
            k = float(rng.uniform(*config.k_range))
            n_exp = float(rng.uniform(*config.n_range))
            truth["participants"][pid] = {"skin_modulus": es, "k": k, "n": n_exp}
            samples: dict[str, Callable[[np.ndarray], np.ndarray]] = {
                config.reference: (lambda f, k=k, n_exp=n_exp: k * f ** (n_exp - 1.0))
            }
            for name, model in models.items():
                curve = np.log(np.clip(np.asarray(model(grid, es), float), 1e-12, None))
                samples[name] = (lambda f, k=k, n_exp=n_exp, curve=curve:
                                 k * f ** (n_exp - 1.0) * np.exp(np.interp(np.log(f), np.log(grid), curve)))
            for sample, mu_of_load in samples.items():
                for rep in range(1, config.repetitions + 1):
                    data, bursts = _simulate_file(rng, config, mu_of_load, first_sense=1 if rep % 2 else -1)
                    name = f"{pid}_{sample}_{rep}.csv"
                    truth["outliers"] += [{"file": name, "stroke": b} for b in bursts]
                    _write_csv(tmp / name, ["time [s]", "Fn [N]", "Ft [mN]", "x [mm]"],
                               zip((f"{v:.4f}" for v in data["time"]), (f"{v:.5f}" for v in data["normal"]),
                                   (f"{v * 1e3:.3f}" for v in data["friction"]),
                                   (f"{v * 1e3:.4f}" for v in data["position"])))
                    manifest.append((name, pid, sample, rep))
        _write_csv(tmp / "manifest.csv", ["file", "participant", "sample", "repetition"], manifest)
        _write_csv(tmp / "samples.csv",
                   ["sample", "radius", "height", "spacing", "material_modulus", "micro_model", "full_contact_ratio"],
                   [(config.reference, "", "", "", "", "", "")]
                   + [(name, g.radius, g.height, g.spacing, g.material_modulus or "", g.micro_model,
                       g.full_contact_ratio or "")
                      for name, g in config.textures.items()])
        truth["files"] = [m[0] for m in manifest]
        truth["population"] = population_truth(config)
        truth["sensor_ranges"] = {"normal": config.normal_range, "friction": config.friction_range}
        (tmp / "truth.json").write_text(json.dumps(truth, indent=2), encoding="utf-8")
        folder.commit()
    return truth
