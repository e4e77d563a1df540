"""The sensitivity part of ``fingerpad predict --population ... --sensitivity``: its two flags read
and its table printed (the indices are computed by :mod:`fingerpad.population.sobol`, the rules
checked by :func:`fingerpad.population.rules.attach`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ..errors import FingerpadError
from .common import say, say_wrapped, stdout_console

__all__ = ["print_sensitivity", "sensitivity_asked"]


def sensitivity_asked(flag: bool, samples: str | None) -> bool | str | None:
    """What ``--sensitivity [--sensitivity-samples N]`` asks of
    :func:`fingerpad.population.rules.attach` (which checks it against the population):
    ``None`` (no indices), ``True`` (the default N) or the text of N."""
    if not flag:
        if samples is not None:
            raise FingerpadError("--sensitivity-samples needs --sensitivity")
        return None
    return True if samples is None else samples


def print_sensitivity(sens: Mapping[str, Any]) -> None:
    """The Sobol indices, first-order / total, per parameter (80 columns)."""
    from rich import box
    from rich.table import Table

    from ..plotting.sensitivity import shown_loads  # the loads the figure shows (no matplotlib import)

    console = stdout_console(80)
    plan = sens["plan"]
    loads = sens["loads"]
    picks = shown_loads(loads)
    table = Table(title=f"Sobol indices, first-order/total (N = {plan['base_samples']}, "
                        f"{plan['evaluations']} fingers)", box=box.SIMPLE_HEAD,
                  pad_edge=False)
    table.add_column("parameter", no_wrap=True)
    for j in picks:
        table.add_column(f"μ/μ_ref {loads[j]:.3g} N", justify="right", no_wrap=True)
    table.add_column("log F_crit", justify="right", no_wrap=True)

    marked = []

    def cell(entry: Mapping[str, Any], j: int | None) -> str:
        first, total = (entry[k] if j is None else entry[k][j] for k in ("first", "total"))
        if first is None or total is None:
            return "-"
        if first > total:  # an estimate, not the index: see the note below the table
            marked.append(1)
            return f"{first:.2f}/{total:.2f}*"
        return f"{first:.2f}/{total:.2f}"

    for name, entry in sens["mu_normalised"].items():
        table.add_row(name, *(cell(entry, j) for j in picks), cell(sens["log10_critical_load"][name], None))
    console.print(table)
    widths = [e["first_conf"][j] for e in sens["mu_normalised"].values() for j in picks
              if e["first_conf"][j] is not None]
    if widths:
        say(console, f"(95 % half-widths up to {max(widths):.2f}; all loads, intervals: JSON, sensitivity.csv)")
    if marked:
        say_wrapped(console, "* first-order above total: sampling error of two separate estimates "
                             "(S_T >= S holds for the indices themselves); see the note")
    for note in sens.get("notes", []):
        say_wrapped(console, f"note: {note}")
