"""The vibration a texture excites in the sliding finger: frequency, receptor channel, amplitude.

Sliding at speed ``v`` over a texture that repeats every ``lambda`` along the stroke excites the
skin at ``f = v / lambda`` and its harmonics (Delhaye et al. 2012; docs/perception.md, Eq. P.4).
A lattice has different periods in different directions: the period along a direction ``d`` is
read from the texture's own periodic cell, so every lattice, spacing and orientation is handled
alike. The cell's height map is a sum of plane waves ``c_k exp(i k.x)``; along the stroke a point
of skin sees each at the frequency ``v |k.d| / 2 pi``. Of the waves holding at least
:data:`SIGNIFICANT` of the largest amplitude:

* the *fundamental* is the lowest non-zero ``|k.d| / 2 pi`` (the texture's period along ``d``:
  ``s`` along a square lattice's axes, ``s`` along the rows of a hexagonal lattice and
  ``sqrt(3) s`` across them, the spacing across ridges; none along them), when every other
  frequency is a whole multiple of it (the texture is periodic along ``d``); along a direction
  where the texture does not repeat there is none, and the strongest wave stands for it (of
  equally strong ones, the wave crossed most nearly head-on: the highest frequency);
* the *strongest* harmonic is the multiple that carries the most of the waves' power
  (``sum |c_k|^2`` over the waves of that frequency); on a hexagonal lattice sliding across the
  rows it can be the second, the row spacing ``sqrt(3)/2 s``.

The receptor channel of a frequency follows Bolanowski et al. (J. Acoust. Soc. Am. 84:1680,
1988): below 10 Hz the slowly adapting channels, NP I (Meissner) 10-40 Hz, P (Pacinian)
40-800 Hz, most sensitive near 250-300 Hz (:data:`CHANNELS`). The detection threshold follows the
shape of Verrillo's (1963) curve for large contactors (:func:`threshold`). The amplitude is an
*estimate* (:func:`amplitude`): the peak-to-peak variation of the skin surface's displacement over
the unit cell at the mean pressure of the ridge contact, quasi-static, at the fundamental only.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["CHANNELS", "FINGERPRINT_PERIOD", "PACINIAN_BEST", "SIGNIFICANT", "THRESHOLD_MIN", "Periods",
           "amplitude", "channel", "fingerprint_period", "periods", "threshold"]

#: The publications this module rests on (:mod:`fingerpad.references`).
REFERENCES = ("delhaye2012", "bolanowski1988", "verrillo1963")

#: A plane wave of the height map counts when its amplitude is at least this fraction of the
#: largest one (``|c_k|``, the mean removed): 1 %.
SIGNIFICANT = 0.01

#: Receptor channels by vibration frequency (Hz): (lowest, highest, key, description). Bolanowski
#: et al. 1988; the issue's and docs/perception.md's table.
CHANNELS: tuple[tuple[float, float, str, str], ...] = (
    (0.0, 10.0, "slow", "slowly adapting, below 10 Hz (NP II/NP III)"),
    (10.0, 40.0, "NP I", "non-Pacinian I (Meissner), 10-40 Hz"),
    (40.0, 800.0, "P", "Pacinian, 40-800 Hz"),
    (800.0, math.inf, "above P", "above the Pacinian range (800 Hz)"),
)

#: The Pacinian channel's most sensitive frequencies, Hz (Verrillo 1963; Bolanowski et al. 1988).
PACINIAN_BEST = (250.0, 300.0)

#: Detection threshold at the most sensitive frequency, m peak-to-peak: about 0.1 um near 250 Hz
#: (the textbook value; Hollins et al. 2000 give 15 um p-p at ~41 dB sensation level, 0.13 um).
THRESHOLD_MIN = 0.1e-6
#: Verrillo (1963), contactors of 2.9 cm^2 and more: flat below 40 Hz, falling 12 dB per octave
#: (a factor 4 in displacement) to its minimum near 250 Hz.
_FLAT_BELOW, _BEST, _SLOPE = 40.0, 250.0, 2.0

#: The fingerprint's ridge period, m, when the finger's ridge model has none: 0.45 mm, the middle
#: of the 0.4-0.5 mm of docs/model.md ("Typical values").
FINGERPRINT_PERIOD = 0.45e-3


def channel(frequency: float) -> str:
    """The receptor channel (key of :data:`CHANNELS`) of a frequency, Hz; ``"none"`` for 0."""
    f = float(frequency)
    if not f > 0:
        return "none"
    for low, high, key, _ in CHANNELS:
        if low <= f < high:
            return key
    return CHANNELS[-1][2]


def threshold(frequency: Any) -> Any:
    """Detection threshold, m peak-to-peak, at ``frequency`` (Hz; arrays too).

    Verrillo's shape (1963, large contactors): flat below 40 Hz, falling 12 dB per octave to
    :data:`THRESHOLD_MIN` at 250 Hz. Above 250 Hz the curve is taken to rise again at 12 dB per
    octave (the U of the Pacinian channel; that slope is an assumption, docs/perception.md).
    """
    f = np.asarray(frequency, float)
    ratio = np.where(f <= _BEST, _BEST / np.maximum(f, _FLAT_BELOW), f / _BEST)
    return THRESHOLD_MIN * ratio**_SLOPE


def fingerprint_period(finger: Any) -> float:
    """The finger's ridge period, m: its ridge model's wavelength if it has one (the sinusoidal,
    circular and fingerprint models), else :data:`FINGERPRINT_PERIOD`."""
    wavelength = getattr(getattr(finger, "ridges", None), "wavelength", None)
    return float(wavelength) if isinstance(wavelength, (int, float)) and wavelength > 0 else FINGERPRINT_PERIOD


@dataclass(frozen=True)
class Periods:
    """What the texture repeats along one stroke direction (SI units).

    Attributes
    ----------
    direction_deg
        The stroke direction, degrees from the texture's x axis.
    fundamental
        The period along it, m (``inf``: the texture does not vary along it, e.g. along ridges;
        ``nan``: not periodic along it, the direction is not a lattice direction).
    strongest
        The wavelength, m, of the harmonic carrying the most power (the fundamental's when it is
        the strongest; for a direction that is not a lattice one, the strongest wave's).
    harmonic
        Which multiple of the fundamental is the strongest (1: the fundamental; 0: none).
    power_share
        The strongest harmonic's share of the power of the waves that vary along the stroke.
    """

    direction_deg: float
    fundamental: float
    strongest: float
    harmonic: int
    power_share: float


def periods(texture: Any, direction_deg: float) -> Periods:
    """The periods of a periodic texture along a stroke direction (see the module docstring).

    Parameters
    ----------
    texture
        A periodic :class:`~fingerpad.textures.Texture` (its height map and cell size).
    direction_deg
        Stroke direction, degrees from the texture's x axis.
    """
    h = np.asarray(texture.heights, float)
    lx, ly = (float(s) for s in texture.size)
    theta = math.radians(float(direction_deg))
    c = np.fft.fft2(h - h.mean())
    amp = np.abs(c)
    amp[0, 0] = 0.0
    top = float(amp.max())
    if top <= 0 or not np.isfinite(top):  # flat
        return Periods(float(direction_deg), math.inf, math.inf, 0, 0.0)
    m = np.fft.fftfreq(h.shape[0]) * h.shape[0]
    n = np.fft.fftfreq(h.shape[1]) * h.shape[1] if h.shape[1] > 1 else np.zeros(1)
    keep = amp >= SIGNIFICANT * top
    mm, nn = np.meshgrid(m, n, indexing="ij")
    q = np.abs(mm[keep] * math.cos(theta) / lx + nn[keep] * math.sin(theta) / ly)  # cycles per metre
    power = amp[keep] ** 2
    scale = 1.0 / min(lx, ly)
    moving = q > 1e-9 * scale  # waves whose crests the stroke crosses
    if not moving.any():
        return Periods(float(direction_deg), math.inf, math.inf, 0, 0.0)
    q, power = q[moving], power[moving]
    q1 = float(q.min())
    multiple = q / q1
    order = np.rint(multiple)
    total = float(power.sum())
    if np.all(np.abs(multiple - order) <= 1e-6 * np.maximum(order, 1.0)):
        sums = np.bincount(order.astype(int), weights=power)
        best = int(np.argmax(sums))
        return Periods(float(direction_deg), 1.0 / q1, 1.0 / (best * q1), best, float(sums[best] / total))
    # not a lattice direction: the texture does not repeat along it; the strongest wave stands
    levels, which = np.unique(np.round(q / scale, 9), return_inverse=True)
    sums = np.bincount(which.ravel(), weights=power)
    # equal waves (a lattice's first shell) tie: the one crossed most nearly head-on, the highest
    best = int(np.flatnonzero(sums >= (1 - 1e-9) * sums.max())[-1])
    return Periods(float(direction_deg), math.nan, 1.0 / (levels[best] * scale), 0, float(sums[best] / total))


def amplitude(texture: Any, modulus: float, pressures: Sequence[float], *, layer: Any = None,
              tol: float = 1e-8, max_iter: int = 5000) -> np.ndarray:
    """Estimated skin vibration amplitude, m peak-to-peak, at each mean cell pressure (Pa).

    The unit cell is solved at the pressure (:class:`~fingerpad.contact.solver.HalfSpaceSolver`,
    the skin's reduced modulus E1* and layer); the estimate is the peak-to-peak variation of the
    skin surface's displacement over the cell, ``max u - min u``: the vertical excursion a point
    of skin makes as the texture passes under it, quasi-static (no dynamics of the finger, no
    stick-slip), an upper bound for any one line of the stroke. A flat texture gives 0.
    """
    from ..contact.solver import HalfSpaceSolver

    if float(np.ptp(np.asarray(texture.heights, float))) == 0.0:
        return np.zeros(len(pressures))
    solver = HalfSpaceSolver(texture, modulus, layer=layer, tol=tol, max_iter=max_iter)
    out = []
    previous = None
    for p in sorted(range(len(pressures)), key=lambda i: pressures[i]):
        previous = solver.solve_pressure(float(pressures[p]), initial=previous)
        u = np.asarray(previous.displacement, float)
        out.append((p, float(u.max() - u.min())))
    return np.array([v for _, v in sorted(out)])
