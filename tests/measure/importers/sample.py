"""One small recording with known values, written by each importer test in its own format.

Twelve samples at 100 Hz: the values have at most four significant digits, so that every
format (text with a decimal point or comma, Excel cells, MATLAB and LabVIEW doubles) holds them
exactly and the readers' results can be compared to the SI values to round-off.
"""

from __future__ import annotations

import numpy as np

#: Force unit -> newtons per unit (docs/measurements.md; gf and kgf by standard gravity).
FORCE_UNITS = {"N": 1.0, "mN": 1e-3, "gf": 9.80665e-3, "kgf": 9.80665, "lbf": 4.4482216152605}

N_ROWS = 12
TIME = np.round(np.arange(N_ROWS) * 0.01, 2)  # s
NORMAL = np.array([1.25, 1.5, 1.75, 2.0, 2.25, 2.5, 2.5, 2.25, 2.0, 1.75, 1.5, 1.25])  # in the file's unit
FRICTION = np.array([0.5, 0.625, 0.75, 0.875, 1.0, 1.125, -1.125, -1.0, -0.875, -0.75, -0.625, -0.5])
POSITION_MM = np.array([0.0, 1.5, 3.0, 4.5, 6.0, 7.5, 7.5, 6.0, 4.5, 3.0, 1.5, 0.0])  # mm

HEADER = ["time [s]", "Fn [{unit}]", "Ft [{unit}]", "x [mm]"]


def header(unit: str) -> list[str]:
    return [h.format(unit=unit) for h in HEADER]


def columns() -> list[np.ndarray]:
    return [TIME, NORMAL, FRICTION, POSITION_MM]


def rows() -> list[tuple[float, float, float, float]]:
    return list(zip(*(c.tolist() for c in columns())))


def check_si(rec, unit: str) -> None:
    """The recording read from a sample file of force unit ``unit`` holds the SI values."""
    factor = FORCE_UNITS[unit]
    assert len(rec) == N_ROWS
    np.testing.assert_allclose(rec.time, TIME, rtol=0, atol=1e-15)
    np.testing.assert_allclose(rec.normal, NORMAL * factor, rtol=1e-14)
    np.testing.assert_allclose(rec.friction, FRICTION * factor, rtol=1e-14)
    np.testing.assert_allclose(rec.position, POSITION_MM * 1e-3, rtol=1e-14)
