"""A population measured on a panel of people: the participants of a ``fingerpad analyse`` folder
as the members (issue 22, "from measurements").

``--population RESULTS_DIR`` names a folder written by ``fingerpad analyse``: one member per
participant, with exactly the values the analysis fitted to that participant (no resampling).
The folder is recognised by its output manifest (:data:`fingerpad.io.MANIFEST`), which lists
the analysis' ``participants.csv`` and ``summary.json`` (docs/outputs.md).

What the analysis fits per participant, and so what a member takes from it:

* ``skin_modulus`` (E_s, Pa): the joint fit to the participant's textured samples
  (``participants.csv``). A participant whose E_s is not determined (its 95 % set is not one
  interval), lies at the search bound, or is missing (no textured sample fitted) is left out,
  with a note naming them.
* Any other column of ``participants.csv`` named as a population parameter (``tau0``,
  ``alpha``, ``beta``, ``radius``, ``modulus``, ``skin_poisson``, ``ridge_fraction``; SI) is taken
  too, per participant, where it holds a number. ``fingerpad analyse`` writes none of these
  today: it does not fit the friction parameters (the reference power law ``ref_k``, ``ref_n``
  is a curve, not a model parameter) nor measure area laws, so the members keep the study's
  finger's values for them; the note says so.

The study and measurement layers are siblings, so the files are read here by their names
(written by :mod:`fingerpad.measure.report`), not through :mod:`fingerpad.measure`.
"""

from __future__ import annotations

import csv
import itertools
import json
import math
from pathlib import Path
from typing import Any

from ..errors import FingerpadError
from ..io import MANIFEST
from .distributions import MAX_MEMBERS, POPULATION_PARAMS, Distribution, Population

__all__ = ["RESULTS_FILES", "population_from_results"]

#: The files of an ``analyse`` folder that make it a population source.
RESULTS_FILES = ("participants.csv", "summary.json")


def _manifest_files(folder: Path) -> set[str]:
    try:
        return {str(f) for f in json.loads((folder / MANIFEST).read_text(encoding="utf-8"))["files"]}
    except (OSError, ValueError, KeyError, TypeError):
        return set()


def _number(text: Any, where: str) -> float:
    """A cell of participants.csv: a number, NaN where empty (not fitted); text that is no
    number is refused, naming the participant and column (it was left out without a word)."""
    if text is None or not str(text).strip():
        return math.nan
    try:
        return float(text)
    except (TypeError, ValueError):
        raise FingerpadError(f"{where}: {str(text)[:40]!r} is not a number") from None


#: Columns ``fingerpad analyse`` writes into participants.csv besides E_s: its own, not parameters.
_ANALYSE_COLUMNS = ("participant", "n_strokes", "n_textures", "note")
_ANALYSE_PREFIXES = ("ref_", "skin_modulus_")


def _analyse_column(name: str) -> bool:
    return name in _ANALYSE_COLUMNS or name.startswith(_ANALYSE_PREFIXES)


def population_from_results(folder: str | Path) -> Population:
    """The participants of the ``fingerpad analyse`` output ``folder`` as a population (see the
    module docstring): one member per usable participant, its fitted values (SI) exactly.

    Raises
    ------
    FingerpadError
        The folder is not an ``analyse`` output (no manifest listing its participants table and
        summary), cannot be read, or has no participant with a determined E_s.
    """
    path = Path(folder)
    opt = f"--population {str(folder)!r}"
    listed = _manifest_files(path)
    missing = [f for f in RESULTS_FILES if f not in listed or not (path / f).is_file()]
    if missing:
        what = "its output manifest lists predict.json: a predict output" if "predict.json" in listed else \
            f"no {' or '.join(missing)} in its output manifest"
        raise FingerpadError(f"{opt}: not a folder written by fingerpad analyse ({what}); name an analyse "
                             "--out folder, a preset or a population file")
    try:
        with open(path / "participants.csv", newline="", encoding="utf-8-sig") as fh:
            reader = csv.DictReader(fh)
            rows = list(itertools.islice(reader, MAX_MEMBERS + 1))
            header = list(reader.fieldnames or [])
        summary = json.loads((path / "summary.json").read_text(encoding="utf-8"))
    except (OSError, ValueError, UnicodeDecodeError, csv.Error, RecursionError) as exc:
        raise FingerpadError(f"{opt}: cannot read the analysis ({exc})") from None
    study = summary.get("study", {}) if isinstance(summary, dict) else None
    if not isinstance(study, dict):
        raise FingerpadError(f"{opt}: summary.json is not what fingerpad analyse writes (a JSON object whose "
                             "\"study\" is an object); run fingerpad analyse again into that folder")
    if len(rows) > MAX_MEMBERS:
        raise FingerpadError(f"{opt}: participants.csv has more than {MAX_MEMBERS} rows; a population has at most "
                             f"{MAX_MEMBERS} members")
    columns = [c for c in POPULATION_PARAMS if c in header]
    unknown = [c for c in header if c not in POPULATION_PARAMS and not _analyse_column(c)]
    members, labels, left_out = [], [], []
    for row in rows:
        who = str(row.get("participant", "?"))
        e_s = _number(row.get("skin_modulus"), f"{opt} participant {who} skin_modulus")
        why = None
        if not (math.isfinite(e_s) and e_s > 0):
            why = "no fitted E_s"
        elif row.get("skin_modulus_determined", "True") != "True":
            why = "E_s not determined (its 95 % set is not one interval)"
        elif row.get("skin_modulus_at_bound", "False") == "True":
            why = "E_s at the search bound"
        if why is not None:
            left_out.append(f"{who} ({why})")
            continue
        member = {}
        for name in columns:
            value = _number(row[name], f"{opt} participant {who} {name}")
            if math.isfinite(value):
                member[name] = POPULATION_PARAMS[name].check(value, f"{opt} participant {who} {name}")
        members.append(member)
        labels.append(who)
    if not members:
        detail = "; ".join(left_out) if left_out else "participants.csv has no rows"
        raise FingerpadError(f"{opt}: no participant with a fitted E_s to use ({detail})")
    used = sorted({k for m in members for k in m}, key=list(POPULATION_PARAMS).index)
    if any(set(m) != set(used) for m in members):
        raise FingerpadError(f"{opt}: the participants do not all have the same fitted parameters "
                             f"({', '.join(used)}); a member would mix fitted and study values")
    fitted_with = study.get("finger", "default")
    notes = [f"population from {path.name}: {len(members)} participant{'s' if len(members) != 1 else ''} as members ({', '.join(used)} as fitted "
             f"by analyse with finger {fitted_with!r}); every other parameter is the study's finger's "
             "(participants.csv has no other: analyse fits no friction parameter nor area law)"]
    if left_out:
        notes.append(f"population from {path.name}: left out {', '.join(left_out)}")
    if unknown:
        notes.append(f"population from {path.name}: participants.csv column(s) {', '.join(unknown)} are neither "
                     f"population parameters ({', '.join(POPULATION_PARAMS)}) nor analyse's own: left out")
    dists = {n: Distribution(POPULATION_PARAMS[n], "values", {"values": tuple(m[n] for m in members)})
             for n in used}
    return Population(dists, size=len(members), seed=0, method="measured", name=path.name,
                      measured=tuple(members), labels=tuple(labels), notes=tuple(notes))
