"""Command-line flags laid over a study file, as raw values; :func:`~.spec.study_from_dict`
validates the result once.

Each flag writes its text into the section and key of the study file it stands for and records
its own name, so that an error names the flag the user typed (``--material-modulus``), not the
study-file key.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from ..errors import FingerpadError

__all__ = ["FLAGS", "apply_flags", "split_texture_options"]

#: Flag -> (section, key) of the study file.
FLAGS: dict[str, tuple[str, str]] = {
    "--texture": ("texture", "name"),
    "--surface": ("texture", "surface"),
    "--size": ("texture", "size"),
    "--pixel-size": ("texture", "pixel_size"),
    "--base-quantile": ("texture", "base_quantile"),
    "--height-unit": ("texture", "height_unit"),
    "--periodic": ("texture", "periodic"),
    "--periodize": ("texture", "periodize"),
    "--fill-missing": ("texture", "fill_missing"),
    "--material-modulus": ("material", "modulus"),
    "--material-poisson": ("material", "poisson"),
    "--finger": ("finger", "preset"),
    "--skin-modulus": ("finger", "skin_modulus"),
    "--skin-poisson": ("finger", "skin_poisson"),
    "--skin-layer-thickness": ("finger", "skin_layer_thickness"),
    "--skin-layer-modulus": ("finger", "skin_layer_modulus"),
    "--skin-substrate-modulus": ("finger", "skin_substrate_modulus"),
    "--skin-substrate-poisson": ("finger", "skin_substrate_poisson"),
    "--skin-base": ("finger", "skin_base"),
    "--work-of-adhesion": ("finger", "work_of_adhesion"),
    "--adhesion-range": ("finger", "adhesion_range"),
    "--adhesion-law": ("finger", "adhesion_law"),
    "--loads": ("loads", "range"),
    "--log": ("loads", "log"),
    "--zones-at": ("loads", "zones_at"),
    "--model": ("model", "kind"),
    "--grid": ("model", "grid"),
    "--accuracy": ("model", "accuracy"),
    "--direction": ("model", "direction"),
    "--tol": ("model", "tol"),
    "--max-iter": ("model", "max_iter"),
    "--cache": ("model", "cache"),
    "--weber-fraction": ("perception", "weber_fraction"),
}


def split_texture_options(args: Sequence[str]) -> list[tuple[str, str]]:
    """``["--radius", "50um", "--lattice=hex"]`` -> ``[("radius", "50um"), ("lattice", "hex")]``.

    A parameter given twice is refused (the last would win silently)."""
    pairs: list[tuple[str, str]] = []
    i = 0
    args = list(args)
    while i < len(args):
        token = args[i]
        if not token.startswith("--") or len(token) <= 2:
            raise FingerpadError(f"unexpected argument {token!r} (texture parameters are given as --NAME VALUE)")
        body = token[2:]
        if "=" in body:
            key, value = body.split("=", 1)
            i += 1
        else:
            key = body
            if i + 1 >= len(args) or (args[i + 1].startswith("--") and len(args[i + 1]) > 2):
                raise FingerpadError(f"option {token} needs a value")
            value = args[i + 1]
            i += 2
        name = key.replace("-", "_")
        earlier = next((v for k, v in pairs if k == name), None)
        if earlier is not None:
            raise FingerpadError(f"--{name.replace('_', '-')} is given twice ({earlier} and {value}): give it once")
        pairs.append((name, value))
    return pairs


def apply_flags(
    data: Mapping[str, Mapping[str, Any]],
    flags: Mapping[str, Any],
    *,
    texture_options: Sequence[tuple[str, str]] = (),
    finger_params: Sequence[str] = (),
) -> tuple[dict[str, dict[str, Any]], dict[tuple[str, str], str]]:
    """Lay command-line values over study-file sections.

    Parameters
    ----------
    data
        Sections of a study file (or an empty dict).
    flags
        Flag name (a key of :data:`FLAGS`) -> value as typed; ``None`` values are not given.
        ``--loads`` takes a list of ``START:STOP:COUNT`` ranges or single loads.
    texture_options
        The texture's own ``--NAME VALUE`` pairs (see :func:`split_texture_options`).
    finger_params
        ``NAME=VALUE`` items of ``--finger-param``.

    Returns
    -------
    data, labels
        The merged sections and, for each value a flag set, the flag's name.
    """
    # Here, not at the top: `fingerpad solve` imports this module for split_texture_options only,
    # and the study spec pulls in the finger, ridge and pad models (~40 ms of its start-up).
    from ..finger import FINGER_FIELDS, RIDGE_FRACTION  # noqa: PLC0415
    from .spec import SECTION_KEYS  # noqa: PLC0415

    out: dict[str, dict[str, Any]] = {k: dict(v) for k, v in data.items()}
    labels: dict[tuple[str, str], str] = {}
    unknown = sorted(set(flags) - set(FLAGS))
    if unknown:
        raise ValueError(f"not study flags: {', '.join(unknown)}")  # a programming error

    texture, surface = flags.get("--texture"), flags.get("--surface")
    if texture is not None and surface is not None:
        raise FingerpadError("give either --texture NAME or --surface FILE, not both")
    tex = out.get("texture", {})
    if texture is not None or surface is not None:
        tex = {}  # --texture/--surface replace the file's texture; the other options update it
    if texture_options and not (tex or texture is not None or surface is not None):
        raise FingerpadError(f"unexpected option --{texture_options[0][0].replace('_', '-')} "
                             "(texture parameters follow --texture NAME)")
    for key, value in texture_options:
        if key in SECTION_KEYS["texture"] and key != "grid":
            raise FingerpadError(f"--{key.replace('_', '-')} is not a texture parameter here; use the option itself")
        if key == "grid":
            raise FingerpadError("give the grid size once, as --grid")
        tex[key] = value
        labels[("texture", key)] = "--" + key.replace("_", "-")
    if tex or texture is not None or surface is not None:
        out["texture"] = tex

    # (--material-poisson without a modulus: study.values.material refuses it, naming the flag
    # and the modulus as a command line gives it)
    if flags.get("--material-poisson") is not None and flags.get("--material-modulus") is None and \
            out.get("material", {}).get("modulus") is None:
        labels[("material", "modulus")] = "--material-modulus"
    if isinstance(flags.get("--material-modulus"), str) and \
            flags["--material-modulus"].strip().lower() in ("rigid", "inf", "infinity"):
        out.setdefault("material", {}).pop("poisson", None)

    substrate = flags.get("--skin-substrate-modulus")
    if isinstance(substrate, str) and substrate.strip().lower() == "rigid":
        # `solve` spells a rigid base --skin-substrate-modulus rigid: the same words work here
        base = flags.get("--skin-base")
        if base is not None and str(base).strip().lower() == "elastic":
            raise FingerpadError("--skin-substrate-modulus rigid contradicts --skin-base elastic")
        flags = {**flags, "--skin-substrate-modulus": None, "--skin-base": base or "rigid"}

    for flag, value in flags.items():
        if value is None:
            continue
        section, key = FLAGS[flag]
        if flag == "--loads":
            if not value:
                continue
            out.setdefault("loads", {}).pop("values", None)
        out.setdefault(section, {})[key] = value
        labels[(section, key)] = flag
    if flags.get("--grid") is not None:
        out.get("texture", {}).pop("grid", None)

    for item in finger_params:
        if "=" not in item:
            raise FingerpadError(f"--finger-param: expected NAME=VALUE, got {item!r}")
        pname, value = (s.strip() for s in item.split("=", 1))
        pname = pname.replace("-", "_")
        if pname == RIDGE_FRACTION.name:
            # the constant-fraction ridge model with this A_fr/A_g, in place of the finger's ridge
            # model: a population member with a ridge fraction is reproduced by this one option
            out.setdefault("finger", {})["ridges"] = {"model": "constant_fraction", "fraction": value}
            labels[("finger", "ridges")] = f"--finger-param {pname}"
            continue
        if pname not in FINGER_FIELDS:
            raise FingerpadError(f"--finger-param: unknown finger parameter {pname!r} "
                                 f"(known: {', '.join([*FINGER_FIELDS, RIDGE_FRACTION.name])})")
        out.setdefault("finger", {})[pname] = value
        labels[("finger", pname)] = f"--finger-param {pname}"
    return out, labels
