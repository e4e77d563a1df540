"""The outputs of a population prediction (``predict --population``, issue 22): ``predict``'s
files of the nominal finger, with the population's ``population`` entry in ``predict.json``, its
``member`` dimension in ``predict.nc``, ``population.png``, ``sensitivity.png`` and
``sensitivity.csv`` with Sobol indices, and two tables, the bands per load and one row per member:

* ``population_bands.csv``: one row per load, ``load_N`` and, for each per-load quantity and
  quantile ``q``, ``<quantity>_q<q>`` (the quantity's ``--csv`` header: ``area_ratio_Are_over_Afr``,
  ``mu``, ``mu_ref``, ``mu_over_mu_ref``), then ``p_asperity``, ``p_transition``, ``p_full`` (the
  fraction of members whose pad centre is in each state).
* ``population_members.csv``: one row per member, ``member`` (its index in ``members``),
  ``participant`` (a measured population only), its parameters in SI with the unit in the header
  (``skin_modulus_Pa``, ``radius_m``, ``alpha``; the name before the unit is the
  ``--finger-param`` name), ``critical_load_N``, ``full_contact_load_N`` and, at the lowest and
  the highest load, ``area_ratio_Are_over_Afr_at_<F>N``, ``mu_at_<F>N``, ``mu_over_mu_ref_at_<F>N``.

docs/outputs.md lists the columns with their units.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..study.outputs import CSV_COLUMNS, write_outputs
from .run import QUANTITIES, PopulationResult

__all__ = ["POPULATION_CSV", "band_table", "member_table", "population_files", "write_population_outputs"]

#: The population's tables in the output folder.
POPULATION_CSV = ("population_bands.csv", "population_members.csv")

_HEADER = dict(CSV_COLUMNS)


def _unit_suffix(unit: str) -> str:
    return f"_{unit}" if unit and unit != "1" else ""


def band_table(result: PopulationResult) -> tuple[list[str], list[list[Any]]]:
    """Header and rows of ``population_bands.csv`` (see the module docstring)."""
    levels = result.quantile_levels
    q = np.asarray(levels)
    loads = np.asarray(result.nominal.study.loads, float)
    header = ["load_N"]
    columns: list[np.ndarray] = [loads]
    for name in QUANTITIES:
        table = np.quantile(result.values(name), q, axis=0)  # as quantiles() computes them
        for i, level in enumerate(levels):
            header.append(f"{_HEADER[name]}_q{level:g}")
            columns.append(table[i])
    for state, share in result.state_probability().items():
        header.append(f"p_{state}")
        columns.append(share)
    return header, [[float(c[i]) for c in columns] for i in range(loads.size)]


def member_table(result: PopulationResult) -> tuple[list[str], list[list[Any]]]:
    """Header and rows of ``population_members.csv`` (see the module docstring)."""
    pop = result.population
    names = list(pop.distributions)
    loads = np.asarray(result.nominal.study.loads, float)
    ends = sorted({0, loads.size - 1})
    header = ["member", *(["participant"] if pop.labels else [])]
    header += [n + _unit_suffix(pop.distributions[n].param.unit) for n in names]
    header += ["critical_load_N", "full_contact_load_N"]
    header += [f"{_HEADER[q]}_at_{loads[j]:g}N" for j in ends for q in ("area_ratio", "mu", "mu_normalised")]
    rows = []
    for i, member in enumerate(result.members):
        curve = result.curves[i]
        row: list[Any] = [i, *([pop.labels[i]] if pop.labels else [])]
        row += [member.get(n, math.nan) for n in names]
        row += [float(result.critical_load[i]), float(result.full_contact_load[i])]
        row += [float(np.asarray(getattr(curve, q))[j]) for j in ends for q in ("area_ratio", "mu", "mu_normalised")]
        rows.append(row)
    return header, rows


def population_files(sensitivity: bool = False) -> tuple[str, ...]:
    """The files a population adds to ``predict``'s output folder (with ``sensitivity``: those of
    its Sobol indices too); known before anything is solved, so the folder is checked first."""
    return ("population.png", *(("sensitivity.png", "sensitivity.csv") if sensitivity else ()), *POPULATION_CSV)


def _csv_text(header: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    import csv
    import io

    buf = io.StringIO()
    writer = csv.writer(buf)
    writer.writerow(header)
    writer.writerows(rows)
    return buf.getvalue()


def write_population_outputs(result: PopulationResult, out_dir: str | os.PathLike[str] | None, *,
                             json_path: str | None = None, csv_path: str | None = None,
                             extra: dict[str, Any] | None = None, dpi: int = 110,
                             sections: Mapping[str, Any] | None = None) -> list[Path]:
    """Write the outputs of a population prediction, all of them or none (see the module docstring;
    :func:`fingerpad.study.outputs.write_outputs` writes them, ``result.nominal``'s files with the
    population's added). ``json_path``/``csv_path``: as there; ``extra``: more files for the
    folder; ``sections``: more top-level entries of the JSON (e.g. ``predict --perception``'s).
    Returns the files written."""
    from ..encode import to_jsonable

    files: dict[str, Any] = dict(extra or {})
    if out_dir is not None:
        from ..plotting.population import figure_population

        files["population.png"] = figure_population(result)
        if result.sensitivity is not None:
            from ..plotting.sensitivity import figure_sensitivity

            files["sensitivity.png"] = figure_sensitivity(result.sensitivity)
            files["sensitivity.csv"] = result.sensitivity.csv_text()
        for name, table in zip(POPULATION_CSV, (band_table, member_table), strict=True):
            files[name] = _csv_text(*table(result))
    return write_outputs(result.nominal, out_dir, json_path=json_path, csv_path=csv_path, extra=files, dpi=dpi,
                         sections={"population": to_jsonable(result.as_dict()), **(sections or {})}, dataset=result.add_to_dataset,
                         cited=result)
