"""The how-tos quote what their commands print (issue 31: the analyse how-to said E_s 0.305 and
0.418 MPa and p = 0.84 where the command printed 0.306, 0.417 and 0.86).

Each how-to's shell blocks are run as written -- the real command line, full sizes, in a fresh
folder holding a copy of ``examples/`` and an empty unit-cell cache -- and everything they print
(stdout and stderr) is collected. Then every quote of printed text on the page must be found in
it, whitespace aside (a terminal wraps lines at its width):

* every line of a ``text`` block (what a command prints, shown below it);
* every inline code span that reads as printed text: it holds a digit, a word and a space and
  is not a command, an option, a file or a Python expression (:func:`quotes`). A ``...`` in a
  quote stands for text left out: the pieces around it must appear, in order.

"Printed" includes the text files the commands wrote under ``out/`` (CSV, JSON, text): a quote
may name a value of a table.

A span that is not printed by the page's commands (a value read from a file, a later run's
line) is listed in ``NOT_PRINTED`` with the reason. Slow: the pages' commands take 1-3 minutes
each on a 2-core machine.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
HOWTOS = sorted((ROOT / "docs" / "howto").glob("*.md"))
FENCE = re.compile(r"^[ \t]*```([A-Za-z]*)[^\n]*\n(.*?)^[ \t]*```", re.S | re.M)  # also in a list item
SPAN = re.compile(r"(?<!`)`([^`\n]+(?:\n[^`\n]+)*)`(?!`)")
#: First words of a span that is a command, an option or code, not printed text.
NOT_TEXT = re.compile(r"^(fingerpad|python|make|source|ls|head|mkdir|cd|pip|--|\[|\{|[a-z_]+\(|[a-z_.]+ *=)")

#: Spans of a page that its commands do not print, with the reason (page name -> {span: why}).
NOT_PRINTED: dict[str, dict[str, str]] = {
    "predict-a-texture.md": {
        "0 solves (cached)": "what the next run prints",
    },
    "feel-the-same-cheaper.md": {
        "1 - coverage": "an expression of the option's value, not printed text",
    },
}


def quotes(text: str) -> list[str]:
    """The quotes of printed text on a page: the lines of its ``text`` blocks and the inline code
    spans that read as printed text (see the module docstring)."""
    out = []
    for m in FENCE.finditer(text):
        if m.group(1).lower() == "text":
            out += [line.strip() for line in m.group(2).splitlines() if line.strip()]
    prose = FENCE.sub("", text)
    for m in SPAN.finditer(prose):
        span = " ".join(m.group(1).split())
        if not (re.search(r"\d", span) and re.search(r"[^\W\d_]{3}", span) and " " in span) or NOT_TEXT.search(span):
            continue
        if re.fullmatch(r"[\w./-]+ [\w./-]+", span) and "/" in span:  # a path and a word
            continue
        out.append(span)
    return out


def shell_blocks(text: str) -> list[str]:
    return [m.group(2) for m in FENCE.finditer(text) if m.group(1).lower() in ("bash", "sh", "shell")]


def found(quote: str, printed: str) -> bool:
    """Whether ``quote`` (its ``...`` leaving text out) is in ``printed``, whitespace aside."""
    flat = " ".join(printed.split())
    start = 0
    for piece in (p.strip() for p in quote.split("...")):
        if not piece:
            continue
        i = flat.find(" ".join(piece.split()), start)
        if i < 0:
            return False
        start = i + len(piece)
    return True


@pytest.mark.slow
@pytest.mark.parametrize("page", HOWTOS, ids=[p.name for p in HOWTOS])
def test_the_howto_quotes_what_its_commands_print(page: Path, tmp_path: Path) -> None:
    text = page.read_text(encoding="utf-8")
    blocks = shell_blocks(text)
    if not any("fingerpad " in b for b in blocks):
        pytest.skip("no command on the page")
    work = tmp_path / "work"
    shutil.copytree(ROOT / "examples", work / "examples")
    bin_dir = Path(sys.executable).parent
    env = {**os.environ, "PATH": f"{bin_dir}{os.pathsep}{os.environ.get('PATH', '')}",
           "FINGERPAD_CACHE": str(tmp_path / "cache"), "COLUMNS": "100", "MPLBACKEND": "Agg"}
    env.pop("FINGERPAD_DEFLECTION_WORKERS", None)
    printed = []
    for code in blocks:
        if code.lstrip().startswith(("make ", "source ")):
            continue  # the install steps: done
        run = subprocess.run(["bash", "-c", code], cwd=work, env=env, timeout=1800, stdin=subprocess.DEVNULL,
                             capture_output=True, text=True)
        printed += [run.stdout, run.stderr]
    # and the text files they wrote (a quote may name a value of a table or report)
    for path in sorted((work / "out").rglob("*")) if (work / "out").is_dir() else []:
        if path.suffix in (".csv", ".json", ".txt") and path.stat().st_size < 2_000_000:
            printed.append(path.read_text(encoding="utf-8", errors="replace"))
    printed_text = "\n".join(printed)
    skip = NOT_PRINTED.get(page.name, {})
    missing = [q for q in quotes(text) if q not in skip and not found(q, printed_text)]
    (tmp_path / "printed.txt").write_text(printed_text, encoding="utf-8")
    assert not missing, f"{page.name} quotes text its commands do not print:\n" + "\n".join(
        f"  {q}\n    nearest printed: {nearest(q, printed_text)}" for q in missing)


def nearest(quote: str, printed: str) -> str:
    """The printed line most like ``quote`` (to say what to quote instead)."""
    import difflib

    lines = [" ".join(line.split()) for line in printed.splitlines() if line.strip()]
    best = difflib.get_close_matches(" ".join(quote.split()), lines, n=1, cutoff=0.0)
    return best[0] if best else "(nothing)"


def test_quotes_are_found_with_their_gaps_and_wrapping() -> None:
    printed = "P01 bumps: no transition detected in 0.135-3.35 N\n    (p = 0.86)\n"
    assert found("P01 bumps: no transition detected in 0.135-3.35 N (p = 0.86)", printed)
    assert not found("P01 bumps: no transition detected in 0.135-3.35 N (p = 0.84)", printed)
    assert found("P01 bumps: ... (p = 0.86)", printed)
    assert not found("(p = 0.86) ... P01", printed)  # the pieces in order
    page = "It prints `P01: E_s = 0.346 MPa`, reads `out/sim/truth.json`, runs `fingerpad solve --grid 32`.\n" \
           "```text\nunit cell 128x224 px\n```\n"
    assert quotes(page) == ["unit cell 128x224 px", "P01: E_s = 0.346 MPa"]
