"""Where a population comes from: a preset name, a TOML file with a ``[population]`` table, a
folder written by ``fingerpad analyse``, or a table."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..errors import FingerpadError
from .distributions import Population, population_from_table
from .presets import POPULATION_PRESETS

__all__ = ["load_population"]


def load_population(source: str | Mapping[str, Any]) -> Population:
    """A population from a preset name (:data:`POPULATION_PRESETS`), a TOML file with a
    ``[population]`` table (a study file will do), a folder written by ``fingerpad analyse``
    (:func:`~.measured.population_from_results`), or a table."""
    if isinstance(source, Mapping):
        return population_from_table(source)
    key = str(source).strip().lower()
    if key in POPULATION_PRESETS:
        return population_from_table(POPULATION_PRESETS[key], where=f"population {key!r}", name=key)
    path = Path(source)
    if path.is_dir():
        from .measured import population_from_results

        return population_from_results(path)
    if not path.is_file():
        raise FingerpadError(f"--population: {source!r} is neither a preset ({', '.join(POPULATION_PRESETS)}), "
                             "a file nor a folder written by fingerpad analyse")
    import tomllib

    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError, OSError) as exc:
        raise FingerpadError(f"--population {source}: cannot read it as TOML: {exc}") from None
    if "population" not in data:
        raise FingerpadError(f"--population {source}: no [population] table")
    return population_from_table(data["population"], where=f"{path.name} [population]", name=path.stem)

