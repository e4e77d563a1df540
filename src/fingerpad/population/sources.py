"""Where a population comes from: a preset name, a TOML file with a ``[population]`` table, a
folder written by ``fingerpad analyse``, or a table."""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..errors import FingerpadError
from ..io import read_toml
from .distributions import Population, population_from_table
from .presets import POPULATION_PRESETS

__all__ = ["load_population"]


def load_population(source: str | Mapping[str, Any]) -> Population:
    """A population from a preset name (:data:`POPULATION_PRESETS`), a TOML file with a
    ``[population]`` table (a study file will do), a folder written by ``fingerpad analyse``
    (:func:`~.measured.population_from_results`), or a table."""
    if isinstance(source, Mapping):
        return population_from_table(source)
    if not isinstance(source, (str, os.PathLike)):  # a Python caller's slip: said, not a TypeError
        raise FingerpadError(f"population: expected a preset name ({', '.join(POPULATION_PRESETS)}), a file or "
                             f"folder, a table or a Population; got {type(source).__name__}")
    key = str(source).strip().lower()
    if key in POPULATION_PRESETS:
        return population_from_table(POPULATION_PRESETS[key], where=f"population {key!r}", name=key,
                                     require_units=True)
    if not str(source).strip():
        raise FingerpadError(f"--population: empty; name a preset ({', '.join(POPULATION_PRESETS)}), a file or a "
                             "folder written by fingerpad analyse")
    path = Path(source)
    if path.is_dir():
        from .measured import population_from_results

        return population_from_results(path)
    if not os.path.lexists(path):
        raise FingerpadError(f"--population: {str(source)!r} is neither a preset ({', '.join(POPULATION_PRESETS)}), "
                             "a file nor a folder written by fingerpad analyse")
    # the one reader of the TOML a user gives (a FIFO, a device, a huge or binary file, UTF-16,
    # deep nesting: each one line; a UTF-8 byte-order mark skipped), as for study files
    data = read_toml(path, "--population file")
    if not isinstance(data.get("population"), Mapping):
        raise FingerpadError(f"--population {str(source)!r}: no [population] table")
    # named by the file's name: a file's stem alone ("population") read as a word
    return population_from_table(data["population"], where=f"{path.name} [population]", name=path.name,
                                 require_units=True)
