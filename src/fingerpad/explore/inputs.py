"""The inputs of the single-texture view as a study, validated exactly as the command line does.

The view's fields hold text as a user types it on the command line (``100um``, ``0.5GPa``,
``0.1N:4N:40``). :func:`study_data` turns them into the sections of a study file, the same
dictionary ``fingerpad predict`` builds from a TOML file and its flags; :func:`validate` hands
it to :func:`fingerpad.study.spec.study_from_dict` (the one place where studies are checked) and
routes each error message to the field it names; :func:`to_toml` writes it as a study file that
``fingerpad predict`` reproduces.

Nothing here imports Panel: the view (:mod:`.views.single`) only shows what this module returns.
"""

from __future__ import annotations

import json
import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from .._version import __version__
from ..errors import FingerpadError, one_line
from ..finger import FINGER_PARAMS

__all__ = [
    "FINGER_LABELS",
    "FieldError",
    "MAX_PAGE_LOADS",
    "StudyCheck",
    "data_key",
    "family_examples",
    "field_label",
    "study_data",
    "to_toml",
    "validate",
]

def family_examples(name: str) -> dict[str, str]:
    """Starting values of a texture family's fields: the ``example`` of each declared parameter
    (typical dimensions of docs/model.md, "Texture dimensions"; the default study's caps for caps)."""
    from ..textures import get_family

    return {p.name: str(p.example) for p in get_family(name).params if p.example is not None}


#: Labels (with symbol) of the finger fields, error messages name them: the declarations' own
#: (:data:`fingerpad.finger.FINGER_PARAMS`), so a new finger parameter is labelled where it is declared.
FINGER_LABELS = {p.name: p.label or p.name for p in FINGER_PARAMS}

#: Labels of the other fields: (section, key) -> label.
_LABELS = {
    ("texture", "name"): "texture",
    ("texture", "surface"): "measured map",
    ("texture", "size"): "map size",
    ("texture", "pixel_size"): "pixel size",
    ("texture", "height_unit"): "height unit",
    ("texture", "periodic"): "periodic",
    ("texture", "periodize"): "periodize",
    ("texture", "fill_missing"): "fill missing",
    ("texture", "base_quantile"): "base quantile",
    ("material", "modulus"): "material modulus E_m",
    ("material", "poisson"): "material Poisson ratio",
    ("finger", "preset"): "finger preset",
    ("loads", "range"): "loads",
    ("loads", "values"): "loads",
    ("loads", "log"): "log-spaced loads",
    ("loads", "zones_at"): "zone-map load",
    ("model", "kind"): "model",
    ("model", "grid"): "grid",
    ("model", "accuracy"): "accuracy",
    ("model", "tol"): "tolerance",
    ("model", "max_iter"): "iteration cap",
}


def field_label(section: str, key: str) -> str:
    """How error messages (and the view) name the field of ``[section] key``."""
    if section == "finger" and key in FINGER_LABELS:
        return FINGER_LABELS[key]
    if (section, key) in _LABELS:
        return _LABELS[(section, key)]
    return key  # a texture parameter: its own name, as in `fingerpad textures`


def study_data(values: Mapping[str, Any]) -> dict[str, dict[str, Any]]:
    """The study-file sections of the view's field values.

    ``values`` maps ``"section.key"`` to the text typed (empty text: not given, the library's
    default applies) or to a bool/choice. Only keys of the study format are produced, so nothing
    typed can become a path or an unknown key.
    """
    data: dict[str, dict[str, Any]] = {}
    for full, value in values.items():
        section, _, key = full.partition(".")
        if isinstance(value, str):
            value = value.strip()
            if value == "":
                continue
        if value is None:
            continue
        data.setdefault(section, {})[key] = value
    # a list typed (or filled in from a pinned design) as "0.5N, 1N, 2N" is read by the study's
    # own loads rule (study.values.parse_loads), as the CLI's --loads is
    mat = data.get("material", {})
    if isinstance(mat.get("modulus"), str) and mat["modulus"].lower() in ("rigid", "inf", "infinity"):
        mat.pop("poisson", None)  # a rigid counter-surface has no Poisson ratio (as --material-modulus rigid)
    return data


def labels_for(data: Mapping[str, Mapping[str, Any]]) -> dict[tuple[str, str], str]:
    """``(section, key) -> label`` for every value of ``data`` (passed to study_from_dict)."""
    return {(s, k): field_label(s, k) for s, body in data.items() for k in body}


def data_key(data: Mapping[str, Any]) -> str:
    """A canonical text of a study's sections (the key of remembered predictions)."""
    return json.dumps(data, sort_keys=True, default=str)


@dataclass(frozen=True)
class FieldError:
    """A message for one field (``field`` = ``"section.key"``) or for the whole form (``None``)."""

    field: str | None
    message: str
    warning: bool = False


@dataclass
class StudyCheck:
    """The outcome of :func:`validate`: the checked study, or the messages."""

    study: Any
    errors: list[FieldError]
    warnings: list[FieldError]

    @property
    def ok(self) -> bool:
        return self.study is not None and not self.errors


def _route(message: str, data: Mapping[str, Mapping[str, Any]]) -> str | None:
    """The field a message names (``"label: ..."``), the longest label first."""
    best: tuple[int, str] | None = None
    for section, body in data.items():
        for key in body:
            label = field_label(section, key)
            if message.startswith((label + ":", label + " ")):
                if best is None or len(label) > best[0]:
                    best = (len(label), f"{section}.{key}")
    return best[1] if best else None


def _texture_param_errors(data: Mapping[str, Mapping[str, Any]]) -> list[FieldError]:
    """Each texture parameter read through its declared kind (Param.parse, as the CLI does)."""
    from ..textures import registry

    tex = data.get("texture", {})
    family = registry().get(str(tex.get("name", "")).strip().lower())
    if family is None:
        return []
    out = []
    for key, value in tex.items():
        par = family.param(key)
        if par is None or par.kind == "grid":
            continue
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                par.parse(value, field_label("texture", key))
        except FingerpadError as exc:
            out.append(FieldError(f"texture.{key}", one_line(str(exc))))
            continue
        out += [FieldError(f"texture.{key}", one_line(str(w.message)), warning=True) for w in caught]
    return out


def _grid_error(data: Mapping[str, Mapping[str, Any]]) -> list[FieldError]:
    """The grid field read on its own, as ``study_from_dict`` reads it (bounds declared by the
    library: :data:`~fingerpad.textures.MIN_GRID`, :data:`~fingerpad.textures.MAX_GRID`)."""
    from ..study.values import integer
    from ..textures import MAX_GRID, MIN_GRID

    grid = data.get("model", {}).get("grid")
    if grid is None:
        return []
    try:
        integer(grid, field_label("model", "grid"), MIN_GRID, MAX_GRID)
    except FingerpadError as exc:
        return [FieldError("model.grid", one_line(str(exc)))]
    return []


def _too_many_loads(study: Any, data: Mapping[str, Mapping[str, Any]]) -> FieldError | None:
    """More loads than the page shows (counted as the library read them: ranges, lists, both)."""
    n = int(getattr(study.loads, "size", len(study.loads)))
    if n <= MAX_PAGE_LOADS:
        return None
    key = "range" if "range" in data.get("loads", {}) else "values"
    return FieldError(f"loads.{key}", f"loads: at most {MAX_PAGE_LOADS} loads in the explorer, got {n} "
                                      "(fingerpad predict takes more)")


#: Most loads of one curve in the page (each is a row of the table and a point of every plot).
MAX_PAGE_LOADS = 2000


def validate(data: Mapping[str, Mapping[str, Any]], *, check: bool = True, uploads: Any = None,
             upload: Any = None) -> StudyCheck:
    """Check a study with the library (``study_from_dict`` and, with ``check``, ``Study.check``,
    which builds the texture) and route every message to its field.

    Texture parameters are first read one by one (so that several bad fields are reported at
    once); then the whole study is read once, as ``fingerpad predict`` reads it.

    With ``uploads`` (an :class:`~.uploads.UploadArea`), a measured map is read only if it is a
    file of that area, and a study without a texture name must have one; ``upload`` (the
    session's :class:`~.uploads.StoredUpload`) puts the user's file name in place of the server's
    path in every message.
    """
    from ..study.spec import study_from_dict
    from .uploads import REFUSED, page_message

    tex = data.get("texture", {})
    if uploads is not None and "name" not in tex:
        try:
            uploads.check(tex.get("surface"))
        except FingerpadError:
            return StudyCheck(None, [FieldError("texture.surface", REFUSED)], [])
    words = (lambda m: m) if uploads is None else (lambda m: page_message(m, upload, uploads.root))
    param_msgs = _texture_param_errors(data) + _grid_error(data)
    if any(e.field == "model.grid" for e in param_msgs):
        # reported; the rest of the study is read without it, so that its other messages show too
        data = {**data, "model": {k: v for k, v in data.get("model", {}).items() if k != "grid"}}
    errors = [e for e in param_msgs if not e.warning]
    warns = [e for e in param_msgs if e.warning]
    study = None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        warnings.filterwarnings("ignore", category=DeprecationWarning)
        try:
            # the texture's parameters are read when it is built (check), so a bad one already
            # reported above does not hide the messages of the other sections
            study = study_from_dict(data, labels_for(data))
            many = _too_many_loads(study, data)
            if many is not None:
                errors.append(many)
            if check and not errors:
                study.check()
        except FingerpadError as exc:
            msg = words(one_line(str(exc)))
            errors.append(FieldError(_route(msg, data) or ("texture.surface" if "surface" in tex and (
                "surface" in msg or (upload is not None and upload.name in msg)) else None), msg))
            study = None
        except OSError as exc:  # an unreadable uploaded map
            errors.append(FieldError("texture.surface", one_line(f"cannot read the map: {exc.strerror or exc}")))
            study = None
    if errors:
        study = None
    seen = {w.message for w in warns}
    for w in caught:
        if issubclass(w.category, (DeprecationWarning, PendingDeprecationWarning)):
            continue
        msg = words(one_line(str(w.message)))
        if msg not in seen and "mpi4py" not in msg:
            seen.add(msg)
            warns.append(FieldError(_route(msg, data), msg, warning=True))
    return StudyCheck(study, errors, warns)


# ---------------------------------------------------------------------------------------------
# study files


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise FingerpadError(f"cannot write {value!r} in a study file")
        return repr(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, Mapping):
        return "{ " + ", ".join(f"{_toml_key(k)} = {_toml_value(v)}" for k, v in value.items()) + " }"
    return json.dumps(str(value), ensure_ascii=True)  # a TOML basic string: JSON escapes are TOML escapes


def _toml_key(key: str) -> str:
    return key if key.replace("_", "").replace("-", "").isalnum() else json.dumps(key)


#: Section order of exported study files (as in examples/study.toml).
_SECTIONS = ("texture", "material", "finger", "loads", "model")


def to_toml(data: Mapping[str, Mapping[str, Any]], comments: Mapping[str, str] | None = None,
            header: str | None = None) -> str:
    """A study file (TOML) of ``data``: ``fingerpad predict FILE`` reads back the same sections.

    ``comments`` adds a comment line above a section; ``header`` comment lines at the top.
    """
    lines = [f"# fingerpad study exported by the texture design explorer (fingerpad {__version__})",
             "# reproduce the explorer's numbers with:  fingerpad predict THIS_FILE.toml --json -"]
    if header:
        lines += [f"# {h}" for h in header.splitlines()]
    for section in [s for s in _SECTIONS if s in data] + [s for s in data if s not in _SECTIONS]:
        body = data[section]
        if section.startswith("_") or not isinstance(body, Mapping):
            continue
        lines.append("")
        if comments and section in comments:
            lines.append(f"# {comments[section]}")
        lines.append(f"[{section}]")
        for key, value in body.items():
            lines.append(f"{_toml_key(key)} = {_toml_value(value)}")
    return "\n".join(lines) + "\n"
