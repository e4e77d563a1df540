"""What a person feels, in 80 columns: the comparison's table and lines, printed by ``compare``
and ``predict --perception``, and ``--perception``'s options (checked before any solve)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from .common import say_wrapped, stdout_console

__all__ = ["perception_options", "print_comparison", "roughness_text"]


def _mu_cell(band: Mapping[str, Any], i: int, many: bool) -> str:
    mid = float(band["0.5"][i])
    return f"{mid:.3f} [{float(band['0.05'][i]):.2f}-{float(band['0.95'][i]):.2f}]" if many else f"{mid:.3f}"


def _band_text(freqs: Sequence[float]) -> str:
    lo, hi = min(freqs), max(freqs)
    return f"{lo:.3g} Hz" if lo == hi else f"{lo:.3g}-{hi:.3g} Hz"


def print_comparison(doc: Mapping[str, Any]) -> None:
    """The comparison in 80 columns: per load the friction of both surfaces, the fraction of the
    fingers telling them apart and the median P; then per surface and direction the vibration
    band and channel, the amplitude estimate and the roughness regime."""
    from rich import box
    from rich.table import Table

    console = stdout_console(80)
    a, b = doc["a"]["label"], doc["b"]["label"]
    many = len(doc["members"]["p_correct"]) > 1
    pop = doc.get("population")
    w = doc["weber_fraction"]
    if w["drawn"]:  # each finger's own W: its median [5-95 %], as the friction's bands
        import numpy as np  # only here: the command line starts without NumPy

        ws = np.asarray(doc["members"]["weber_fraction"], float)
        wtext = f"W {np.median(ws):.2f} [{np.quantile(ws, 0.05):.2f}-{np.quantile(ws, 0.95):.2f}]"
    else:
        wtext = f"W = {w['value']:g}"
    who = f"{pop['size']} fingers of {pop['name']!r}" if pop else "the study's finger"
    table = Table(title=f"{a} against {b}: {who}, {wtext}", box=box.SIMPLE_HEAD, pad_edge=False)
    for col in ("load N", f"μ {a}", f"μ {b}", "tell apart", "median P"):
        table.add_column(col, justify="right", overflow="fold")
    fraction, median = doc["discrimination"]["fraction"], doc["discrimination"]["p_correct_median"]
    for i, (load, key) in enumerate(zip(doc["loads"], fraction, strict=True)):
        table.add_row(f"{float(load):.3g}", _mu_cell(doc["mu"][a], i, many), _mu_cell(doc["mu"][b], i, many),
                      f"{100 * fraction[key]:.3g} %", f"{median[key]:.3f}")
    console.print(table)
    say_wrapped(console, ("μ: median [5-95 %] over the fingers" + (", W too" if w["drawn"] else "") + "; "
                          if many else "")
                + "tell apart: the fraction of fingers choosing right in at least 75 % of forced choices by "
                  "friction alone (docs/perception.md)")
    speeds = doc["speeds"]
    span = f"{1e3 * min(speeds):g}-{1e3 * max(speeds):g} mm/s" if len(speeds) > 1 else f"{1e3 * speeds[0]:g} mm/s"
    groups: dict[tuple[str, float, int], list[dict[str, Any]]] = {}
    for e in doc["vibration"]:
        groups.setdefault((e["texture"], e["direction_deg"], e["harmonic"]), []).append(e)
    ridge = 1e6 * float(doc["ridge_period"])
    for (tex, direction, harmonic), rows in groups.items():
        lam = rows[0]["wavelength_m"]
        if lam is None or not math.isfinite(lam):
            say_wrapped(console, f"{tex} at {direction:g}°: no period along the stroke, no vibration")
            continue
        freqs = [r["frequency_hz"] for r in rows]
        channels = sorted({r["channel"] for r in rows}, key=lambda c: [r["channel"] for r in rows].index(c))
        which = "" if harmonic == 1 else f" (strongest: harmonic {harmonic})"
        side = "shorter" if lam * 1e6 < ridge else "longer"
        say_wrapped(console, f"{tex} at {direction:g}°{which}: λ {1e6 * lam:.4g} µm -> {_band_text(freqs)} at {span}, "
                             f"channel {'/'.join(channels)}; {side} than the ridge period {ridge:.3g} µm")
    loads = [f"{float(f):g}" for f in doc["loads"]]
    for label in (a, b):
        amp = doc["amplitude"].get(label)
        if amp is not None and any(float(v) > 0 for v in amp):
            say_wrapped(console, f"{label} amplitude estimate at {'/'.join(loads)} N: "
                                 f"{'/'.join(f'{1e6 * float(v):.3g}' for v in amp)} µm p-p (threshold 0.1 µm "
                                 "near 250 Hz, flat below 40 Hz)")
        say_wrapped(console, f"{label} roughness: {roughness_text(doc['roughness'][label], loads)}")


def roughness_text(regimes: Sequence[Mapping[str, Any]], loads: Sequence[str]) -> str:
    """The roughness regimes of one surface over the loads in one sentence: its scale and cue
    once, then where the roughness stands (coarse) or the centre's contact state (fine), the
    loads of each listed together."""
    first = regimes[0]
    if first.get("scale") in (None, "flat"):
        return str(first["verdict"])
    key = "roughness" if first["scale"] == "coarse" else "state"
    groups: dict[str, list[str]] = {}
    for f, r in zip(loads, regimes, strict=True):
        groups.setdefault(str(r[key]), []).append(f)
    where = "; ".join(f"{v} at {', '.join(fs)} N" for v, fs in groups.items())
    head = ("coarse, judged by skin intrusion; roughness " if key == "roughness" else
            "fine, judged by its vibration; pad centre in ")
    tail = "; spacing below 160 µm: felt smooth" if first.get("felt_smooth") else ""
    return head + where.replace(" at ", " contact at " if key == "state" else " at ") + tail


def perception_options(asked: bool, speed: str | None, weber: str | None, study: Any) -> dict[str, Any] | None:
    """``--perception``'s options, checked before any solve (``--speed`` and ``--weber-fraction``
    without it are refused; the Weber fraction itself is the study's, ``--weber-fraction`` a flag
    of the study, :attr:`fingerpad.study.spec.Study.weber_fraction`); the stroke directions are
    the study's sliding direction, else 0 and 90."""
    from ..errors import FingerpadError

    if not asked:
        for name, value in (("--speed", speed), ("--weber-fraction", weber)):
            if value is not None:
                raise FingerpadError(f"{name} needs --perception")
        return None
    from ..perception.compare import DEFAULT_DIRECTIONS, parse_speeds

    directions = DEFAULT_DIRECTIONS if study.direction is None else (float(study.direction),)
    return {"speeds": parse_speeds(speed), "directions": directions}
