"""``fingerpad cite``: how to cite fingerpad, the thesis it implements and the methods a run used."""

from __future__ import annotations

import sys
from typing import Annotated

import typer

from .common import user_errors


def _wrapped(text: str, width: int, first: str = "", rest: str = "    ") -> str:
    import textwrap

    return textwrap.fill(text, width=width, initial_indent=first, subsequent_indent=rest,
                         break_long_words=False, break_on_hyphens=False)


def _output_keys(path: str) -> tuple[list[str], list[dict[str, str]]]:
    """The reference keys an output lists (``predict.json``, ``summary.json``, a solve's JSON, or
    the folder holding one), and the entries of keys this version does not know."""
    import json
    from pathlib import Path

    from ..errors import FingerpadError
    from ..references import REFERENCES

    p = Path(path)
    files = sorted(p.glob("*.json")) if p.is_dir() else [p]
    if not p.exists():
        raise FingerpadError(f"{path!r}: no such file or folder")
    found: list[dict[str, str]] = []
    for file in files:
        try:
            doc = json.loads(file.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
            if p.is_dir():
                continue
            raise FingerpadError(f"{path!r}: not a JSON output of fingerpad ({exc})") from None
        entries = doc.get("references") if isinstance(doc, dict) else None
        if isinstance(entries, list):
            found += [e for e in entries if isinstance(e, dict) and isinstance(e.get("key"), str)]
    if not found:
        raise FingerpadError(f"{path!r}: lists no references (an output of fingerpad 0.2.0 or later: "
                             "predict.json, summary.json, a solve's --json file, or their folder)")
    known = [e["key"] for e in found if e["key"] in REFERENCES]
    seen: set[str] = set()
    unknown = [e for e in found if e["key"] not in REFERENCES and not (e["key"] in seen or seen.add(e["key"]))]
    return known, unknown


def cite_command(
    output: Annotated[str | None, typer.Argument(
        metavar="[OUTPUT]", show_default=False,
        help="An output (predict.json, an analysis's summary.json, a solve's JSON, or the folder holding one): "
             "the references of the methods that run used.")] = None,
    bibtex: Annotated[bool, typer.Option("--bibtex", help="BibTeX entries instead of text.")] = False,
    every: Annotated[bool, typer.Option("--all", help="Every publication fingerpad's methods rest on, with "
                                                      "what each is used for.")] = False,
) -> None:
    """How to cite fingerpad and the thesis it implements; with OUTPUT, the methods a run used.

    Without arguments: the thesis whose model fingerpad implements (the
    preferred reference for the model) and the package. With OUTPUT: the
    publications of the methods that run used, as its files list them;
    with --all: every publication fingerpad's methods rest on.
    """
    import shutil

    from .. import references as refs

    with user_errors():
        if output is not None and every:
            from ..errors import FingerpadError

            raise FingerpadError("give OUTPUT or --all, not both")
        unknown: list[dict[str, str]] = []
        if output is not None:
            keys, unknown = _output_keys(output)
        elif every:
            keys = list(refs.REFERENCES)
        else:
            keys = [refs.THESIS, refs.PACKAGE]
    if bibtex:
        sys.stdout.write(refs.bibtex(keys))
        for entry in unknown:  # written by another version: its citation as a comment
            sys.stdout.write(f"% {entry['key']}: {entry.get('citation', '')}\n")
        return
    width = min(shutil.get_terminal_size((80, 24)).columns, 100)
    lines: list[str] = []
    if output is None and not every:
        lines.append(_wrapped("fingerpad implements the multiscale contact and friction model of this thesis; "
                              "please cite it for the model:", width, rest=""))
        lines += ["", _wrapped(refs.citation(refs.THESIS), width, "  ", "    "), ""]
        lines.append(_wrapped("and the package, for the implementation:", width, rest=""))
        lines += ["", _wrapped(refs.citation(refs.PACKAGE), width, "  ", "    "), ""]
        lines.append(_wrapped("Every output lists the publications of the methods its run used (predict.json and "
                              "the other JSON outputs: 'references'; NetCDF files and sweep stores: the "
                              "'references' attribute); 'fingerpad cite OUTPUT' prints them, '--all' lists "
                              "every one, '--bibtex' gives BibTeX. CITATION.cff in the repository says the same.",
                              width, rest=""))
    else:
        for ref in refs.ordered(keys):
            lines.append(_wrapped(refs.citation(ref), width, "- ", "  "))
            lines.append(_wrapped(f"used for: {ref.used_for}", width, "  ", "  "))
        for entry in unknown:  # written by another version: as the output has it
            lines.append(_wrapped(str(entry.get("citation", entry["key"])), width, "- ", "  "))
    sys.stdout.write("\n".join(lines) + "\n")


def register(app: typer.Typer) -> None:
    app.command("cite")(cite_command)
