"""Every command of the README and docs/ runs as written (issue 20: "check every command of the
README and docs/ in a test that runs them").

Each document's shell blocks (fenced blocks holding a line that starts with ``fingerpad ``) are
run in order with bash in a fresh folder holding a copy of ``examples/``, as a reader following
the page would run them: earlier blocks make the files later ones read (``out/sim``, the maps of
the measured-map how-to). ``fingerpad`` there is a wrapper that runs the real command line with
small sizes added (a coarse grid, fewer simulated participants, a smaller sweep, fewer design
evaluations) and logs every call. Commands that need a server or a cluster (``explore``,
``--scheduler``) and synopsis lines (``fingerpad solve`` alone, ``[OPTIONS]``, ``DATA...``) run
with ``--help`` only. A block whose following text says it stops with an error must end with
exit code 2 and one ``error:`` line; every other call must succeed.

Files a page takes as the reader's own (``scan.x3p``, ``heights.npy``) are made here; the
sweep study that docs/sweeps.md shows and calls ``study.toml`` is the (smaller) example sweep.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
FENCE = re.compile(r"^```([A-Za-z]*)[^\n]*\n(.*?)^```", re.S | re.M)
#: Documents whose commands take more than ~10 s on a 2-core machine (a sweep, a design search,
#: BEM curves on measured maps, the deflection model).
SLOW = {"README.md", "sweeps.md", "read-a-measured-map.md", "predict-a-texture.md", "analyse-measurements.md",
        "formats.md", "measurements.md", "outputs.md", "design-for-a-population.md", "population.md",
        "getting-started.md", "perception.md",
        "feel-the-same-cheaper.md"}
#: What the text right after a block says when its command is meant to fail.
FAILS = re.compile(r"stops with `error:")

WRAPPER = r'''#!{python}
"""fingerpad for the docs test: small sizes, --help for servers and synopses, every call logged."""
import io, json, os, re, sys, time

args = sys.argv[1:]
placeholder = re.compile(r"^\[.*\]$|\.\.\.$|^[A-Z][A-Z_]*$")
help_only = (len(args) <= 1 or any(placeholder.search(a) for a in args) or args[0] == "explore"
             or any(a.startswith("--scheduler") for a in args))
def has(option):
    return any(a == option or a.startswith(option + "=") for a in args)
extra = []
if not help_only:
    command = args[0]
    if command in ("predict", "solve") and not has("--surface") and not has("--grid"):
        extra += ["--grid", "32"]
    if command == "simulate-measurement" and not has("--participants"):
        extra += ["--participants", "2"]
    if command == "analyse":
        extra += ["--n-null", "19", "--no-sensitivity"]
    if command == "sweep" and not has("--workers"):
        extra += ["--workers", "1"]
    if command == "design":
        # 6 evaluations whatever the page says (an option given twice is refused, so replace it)
        if "--evaluations" in args:
            args[args.index("--evaluations") + 1] = "6"
        args = [a if not a.startswith("--evaluations=") else "--evaluations=6" for a in args]
        if not has("--evaluations"):
            extra += ["--evaluations", "6"]
run = [args[0], "--help"] if help_only and args else args + extra


class Tee(io.TextIOBase):
    def __init__(self, real):
        self.real, self.seen = real, []
    def write(self, text):
        self.seen.append(text)
        return self.real.write(text)
    def flush(self):
        self.real.flush()
    def isatty(self):
        return False
    @property
    def encoding(self):
        return "utf-8"


def main():
    sys.stderr = tee = Tee(sys.stderr)
    code = 0
    start = time.monotonic()
    try:
        from fingerpad.cli import main
        sys.argv = ["fingerpad", *run]
        main()
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    finally:
        with open(os.environ["FINGERPAD_DOCS_LOG"], "a", encoding="utf-8") as fh:
            fh.write(json.dumps({{"args": args, "run": run, "code": code, "stderr": "".join(tee.seen),
                                 "seconds": round(time.monotonic() - start, 1)}}) + "\n")
    sys.exit(code)


if __name__ == "__main__":  # Dask's worker processes import this file again (spawn)
    main()
'''


def _has_command(code: str) -> bool:
    return any(line.strip().removeprefix("$ ").startswith("fingerpad ") for line in code.splitlines())


def shell_blocks(path: Path, every: bool = False) -> list[tuple[str, str]]:
    """(code, the text after it) of each shell block of ``path`` holding a fingerpad command;
    ``every``: also the ``bash`` blocks without one (they make the files later commands read)."""
    text = path.read_text(encoding="utf-8")
    out = []
    for m in FENCE.finditer(text):
        lang, code = m.group(1).lower(), m.group(2)
        if not (_has_command(code) and lang in ("", "bash", "sh", "shell", "console")
                or every and lang in ("bash", "sh", "shell")):
            continue
        out.append((code, text[m.end():m.end() + 250].split("```")[0]))
    return out


def commands(path: Path) -> list[str]:
    """The fingerpad command lines of ``path``'s shell blocks (continuations joined)."""
    found = []
    for code, _ in shell_blocks(path):
        lines = code.splitlines()
        i = 0
        while i < len(lines):
            line = lines[i].strip().removeprefix("$ ")
            if line.startswith("fingerpad "):
                while line.endswith("\\") and i + 1 < len(lines):
                    i += 1
                    line = line[:-1] + " " + lines[i].strip()
                found.append(line)
            i += 1
    return found


def _workspace(tmp_path: Path, doc: Path | None = None) -> tuple[Path, dict[str, str]]:
    """A folder like the repository root for a reader: examples/, the reader's own files, and
    ``fingerpad``/``python`` first on the PATH."""
    work = tmp_path / "work"
    shutil.copytree(ROOT / "examples", work / "examples")
    sweep = work / "examples" / "sweep.toml"
    text = sweep.read_text(encoding="utf-8")
    text = re.sub(r'(?m)^spacing = "100um:500um:9"', 'spacing = "150um:300um:2"', text)
    text = re.sub(r'(?m)^height = "5um:40um:6"', 'height = "10um:20um:2"', text)
    text = re.sub(r"(?m)^grid = 48", "grid = 16", text)
    sweep.write_text(text, encoding="utf-8")
    study = work / "examples" / "study.toml"  # one coarse grid instead of the accuracy's choice
    study.write_text(re.sub(r"(?m)^\[model\]$", "[model]\ngrid = 32", study.read_text(encoding="utf-8")),
                     encoding="utf-8")
    if doc is not None and doc.name == "sweeps.md":
        shutil.copy(sweep, work / "study.toml")  # the sweep study the page shows and calls study.toml
    # The reader's own height maps that README.md and docs/formats.md name.
    n = 64
    x = np.arange(n) / n
    bumps = 2.5 * (np.cos(2 * np.pi * 4 * x)[:, None] + 1) * (np.cos(2 * np.pi * 4 * x)[None, :] + 1) / 2
    np.save(work / "scan.npy", bumps)
    np.savetxt(work / "scan.txt", bumps.T, fmt="%.4f")
    xw = np.arange(80) / 80
    wide = 2.5 * (np.cos(2 * np.pi * 5 * xw)[:, None] + 1) * (np.cos(2 * np.pi * 4 * x)[None, :] + 1) / 2
    np.save(work / "heights.npy", wide)  # 500 um x 400 um at square pixels
    import SurfaceTopography as st

    st.Topography(bumps, (200.0, 200.0), unit="µm").to_x3p(str(work / "scan.x3p"))
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    wrapper = bin_dir / "fingerpad"
    wrapper.write_text(WRAPPER.format(python=sys.executable), encoding="utf-8")
    wrapper.chmod(0o755)
    python = bin_dir / "python"  # this environment's Python (a symlink would lose the virtualenv)
    python.write_text(f'#!/bin/sh\nexec "{sys.executable}" "$@"\n', encoding="utf-8")
    python.chmod(0o755)
    env = {**os.environ, "PATH": f"{bin_dir}{os.pathsep}{os.environ.get('PATH', '')}",
           "FINGERPAD_CACHE": str(tmp_path / "cache"), "FINGERPAD_DOCS_LOG": str(tmp_path / "calls.jsonl"),
           "COLUMNS": "120", "MPLBACKEND": "Agg"}
    return work, env


def _calls(tmp_path: Path) -> list[dict]:
    log = tmp_path / "calls.jsonl"
    if not log.exists():
        return []
    return [json.loads(line) for line in log.read_text(encoding="utf-8").splitlines()]


def _param(path: Path):
    marks = [pytest.mark.slow] if path.name in SLOW else []
    return pytest.param(path, marks=marks, id=str(path.relative_to(ROOT)))


@pytest.mark.parametrize("doc", [_param(p) for p in DOCS if shell_blocks(p)])
def test_every_command_of_the_page_runs(doc: Path, tmp_path: Path) -> None:
    work, env = _workspace(tmp_path, doc)
    for code, after in shell_blocks(doc, every=True):
        before = len(_calls(tmp_path))
        subprocess.run(["bash", "-c", code], cwd=work, env=env, timeout=1800, stdin=subprocess.DEVNULL,
                       capture_output=True)
        if not _has_command(code):
            continue
        calls = _calls(tmp_path)[before:]
        assert calls, f"{doc.name}: no fingerpad command of this block ran:\n{code}"
        fails = bool(FAILS.search(after))
        for call in calls:
            where = f"{doc.name}: fingerpad {' '.join(call['args'])}\n{call['stderr'][-2000:]}"
            if fails:
                lines = [line for line in call["stderr"].splitlines() if line.strip()]
                assert call["code"] == 2 and lines[-1].startswith("error: "), where
                assert sum(line.startswith("error: ") for line in lines) == 1, where
            else:
                assert call["code"] == 0, where


def test_the_docs_name_only_files_that_exist():
    """A command naming a repository file (examples/...) names one that is there."""
    for doc in DOCS:
        for line in commands(doc):
            for word in line.split():
                if word.startswith("examples/"):
                    assert (ROOT / word).exists(), f"{doc.name}: {line}"


def test_the_commands_are_found():
    """The parser sees the pages' commands (a change of fence style would silently skip them)."""
    found = {doc.name: commands(doc) for doc in DOCS}
    assert any(c.startswith("fingerpad predict examples/study.toml") for c in found["README.md"])
    assert any(c.startswith("fingerpad design-map") for c in found["sweeps.md"])
    assert sum(len(v) for v in found.values()) >= 50
