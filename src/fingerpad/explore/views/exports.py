"""The single-texture view's exports: the study file of the results shown, the results as
``predict.json`` and as ``predict --csv`` writes them (made in memory when a button is pressed;
every text in the page's words, never a server path of an upload)."""

from __future__ import annotations

import copy
import csv
import io
import json
from typing import Any

from ..inputs import to_toml

__all__ = ["results_csv", "results_json", "study_toml"]


def study_toml(view: Any) -> str:
    """The study of the results shown (the inputs, if not computed yet) as a study file."""
    data = view.shown_data if view.shown_data is not None else view.data
    if data is None:
        return "# nothing to export: the inputs are not valid\n"
    header = None
    data = copy.deepcopy(data)
    # the perception section's Weber fraction: a parameter of the person, [perception] in a study file
    data.pop("perception", None)
    perception = view.perception.study_section()
    if perception:
        data["perception"] = perception
    tex = data.get("texture", {})
    if "surface" in tex:
        data["texture"]["surface"] = view.upload.original_name or "map"
        header = (f"the measured map was uploaded as {view.upload.original_name!r}: "
                  "put that file beside this study file")
    return to_toml(data, header=header)


def _scrub(view: Any, value: Any) -> Any:
    """``value`` with every text in the page's words (no server path of an upload)."""
    if isinstance(value, str):
        return view._words(value)
    if isinstance(value, dict):
        return {k: _scrub(view, v) for k, v in value.items()}
    if isinstance(value, list):
        return [_scrub(view, v) for v in value]
    return value


def results_json(view: Any) -> str:
    """The content of ``predict.json`` of the results shown."""
    from ...study.outputs import prediction_json

    if view.pred is None:
        return "{}\n"
    return json.dumps(_scrub(view, prediction_json(view.pred)), indent=2) + "\n"


def results_csv(view: Any) -> str:
    """The table of ``predict --csv`` of the results shown."""
    from ...study.outputs import CSV_COLUMNS, prediction_rows

    if view.pred is None:
        return ""
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=[h for _, h in CSV_COLUMNS], lineterminator="\n")
    writer.writeheader()
    writer.writerows(prediction_rows(view.pred))
    return out.getvalue()
