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
        return population_from_table(POPULATION_PRESETS[key], where=f"population {key!r}", name=key,
                                     require_units=True)
    if not str(source).strip():
        raise FingerpadError(f"--population: empty; name a preset ({', '.join(POPULATION_PRESETS)}), a file or a "
                             "folder written by fingerpad analyse")
    path = Path(source)
    if path.is_dir():
        from .measured import population_from_results

        return population_from_results(path)
    if not path.is_file():
        raise FingerpadError(f"--population: {str(source)!r} is neither a preset ({', '.join(POPULATION_PRESETS)}), "
                             "a file nor a folder written by fingerpad analyse")
    import tomllib

    try:
        # utf-8-sig: a byte-order mark (Windows editors write one) is skipped, as in study files
        data = tomllib.loads(path.read_bytes().decode("utf-8-sig"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError, OSError, RecursionError) as exc:
        why = "too deeply nested" if isinstance(exc, RecursionError) else str(exc)
        raise FingerpadError(f"--population {str(source)!r}: cannot read it as UTF-8 TOML text: {why}") from None
    if not isinstance(data.get("population"), Mapping):
        raise FingerpadError(f"--population {str(source)!r}: no [population] table")
    # named by the file's name: a file's stem alone ("population") read as a word
    return population_from_table(data["population"], where=f"{path.name} [population]", name=path.name,
                                 require_units=True)
