"""The documentation site (docs/, `make docs`): a strict Sphinx build without network, the API
reference covering the public API, and the tutorial notebook executed so that it cannot rot."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

import fingerpad

ROOT = Path(fingerpad.__file__).resolve().parents[2]
DOCS = ROOT / "docs"

# Run first in the build's interpreter: any attempt to reach another machine raises, so a build
# that needs the network (an intersphinx inventory, a theme's remote asset) fails the test.
NO_NETWORK = """
import socket
def _refuse(*args, **kwargs):
    raise OSError("the documentation build tried to reach the network")
socket.socket.connect = socket.socket.connect_ex = _refuse
socket.create_connection = socket.getaddrinfo = _refuse
"""

SPHINX = NO_NETWORK + "import sys\nfrom sphinx.cmd.build import main\nsys.exit(main(sys.argv[1:]))\n"


def _copy_docs(dest: Path) -> Path:
    """docs/ without what a local `make docs` generated in it, so the build starts clean."""
    return Path(shutil.copytree(DOCS, dest, ignore=shutil.ignore_patterns("generated", "_build", ".ipynb_checkpoints")))


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The site built as `make docs` does, with warnings as errors, the notebook not executed
    (test_tutorial_runs does that), in a process that cannot reach the network."""
    tmp = tmp_path_factory.mktemp("docs")
    source, out = _copy_docs(tmp / "source"), tmp / "html"
    env = {**os.environ, "FINGERPAD_DOCS_EXECUTE": "off"}
    start = time.perf_counter()
    proc = subprocess.run(
        [sys.executable, "-c", SPHINX, "-b", "html", "-W", "--keep-going", "-q", "-j", "1", str(source), str(out)],
        capture_output=True, text=True, timeout=600, env=env, cwd=tmp,
    )
    print(f"strict Sphinx build: {time.perf_counter() - start:.1f} s")
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-6000:]
    return out


def test_network_guard_refuses_a_connection():
    """The guard of the build itself: a download attempt in that interpreter fails."""
    code = NO_NETWORK + "import urllib.request\nurllib.request.urlopen('http://127.0.0.1:9/', timeout=1)\n"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert proc.returncode != 0 and "tried to reach the network" in proc.stderr


def test_references_must_exist(tmp_path: Path):
    """The strict build's reference check, on a one-page site with the site's configuration: a
    reference to an internal object that exists is accepted (text, or a link to the same object's
    entry), one to a name that exists nowhere fails the build and is the one warning."""
    source = tmp_path / "source"
    source.mkdir()
    shutil.copy(DOCS / "conf.py", source / "conf.py")
    (source / "index.rst").write_text(
        "Test\n====\n\n.. autofunction:: fingerpad.predict_curve\n\n"
        "Exist: :data:`fingerpad.micro.bem.STATE_SEARCH_CAP`, :mod:`fingerpad.measure.strokes`, "
        ":func:`fingerpad.coupling.predict_curve`.\n\nGone: :class:`fingerpad.unitcell.BEMUnitCell`.\n",
        encoding="utf-8")
    proc = subprocess.run(
        [sys.executable, "-c", SPHINX, "-b", "html", "-W", "--keep-going", "-q", str(source), str(tmp_path / "html")],
        capture_output=True, text=True, timeout=300, env={**os.environ, "FINGERPAD_DOCS_EXECUTE": "off"},
    )
    warnings = [line for line in proc.stderr.splitlines() if "WARNING" in line or "ERROR" in line]
    assert proc.returncode != 0 and len(warnings) == 1 and "fingerpad.unitcell.BEMUnitCell" in warnings[0], proc.stderr
    html = (tmp_path / "html" / "index.html").read_text(encoding="utf-8")
    assert 'href="#fingerpad.predict_curve"' in html  # coupling.predict_curve is fingerpad.predict_curve


def test_every_page_is_built(site: Path):
    """Every Markdown page of docs/ becomes a page of the site (unreachable pages are warnings,
    i.e. errors of the strict build, so every page is also in the landing page's tree)."""
    pages = sorted(p.relative_to(DOCS).with_suffix(".html") for p in DOCS.rglob("*.md"))
    assert len(pages) >= 10
    missing = [str(p) for p in pages if not (site / p).is_file()]
    assert not missing, missing
    assert (site / "tutorial.html").is_file() and (site / "api" / "index.html").is_file()
    index = (site / "index.html").read_text(encoding="utf-8")
    for page in pages:
        if page.name != "index.html":
            assert f'href="{page.as_posix()}' in index, f"{page} is not linked from the landing page"


def _documented_ids(site: Path) -> set[str]:
    ids: set[str] = set()
    for page in (site / "api" / "generated").glob("*.html"):
        ids.update(re.findall(r'<dt class="sig sig-object py" id="([^"]+)"', page.read_text(encoding="utf-8")))
    return ids


def test_api_reference_covers_the_public_api(site: Path):
    """Every name of fingerpad.__all__, fingerpad.textures, fingerpad.measure and fingerpad.contact
    has its entry, and the study, sweep and design functions users call are there."""
    import fingerpad.contact
    import fingerpad.measure
    import fingerpad.textures

    ids = _documented_ids(site)
    wanted = [f"fingerpad.{name}" for name in fingerpad.__all__ if not name.startswith("_")]
    for module in (fingerpad.textures, fingerpad.measure, fingerpad.contact):
        wanted += [f"{module.__name__}.{name}" for name in module.__all__ if f"fingerpad.{name}" not in wanted]
    wanted += [
        "fingerpad.design.engine.run_sweep", "fingerpad.design.spec.sweep_from_dict",
        "fingerpad.design.store.open_sweep", "fingerpad.design.designmap.map_data",
        "fingerpad.design.inverse.search", "fingerpad.design.inverse.rank_sweep",
        "fingerpad.study.spec.study_from_dict", "fingerpad.study.run.run_study",
    ]
    missing = [name for name in wanted if name not in ids]
    assert not missing, missing
    # numpydoc rendered the sections: predict_curve's parameters with their units.
    page = (site / "api" / "generated" / "fingerpad.html").read_text(encoding="utf-8")
    entry = page[page.index('id="fingerpad.predict_curve"'):]
    assert "Parameters" in entry[:4000] and "Normal loads, N" in entry[:4000]
    # The contents table's summaries do not stop at the "Eq." of an equation number.
    table = page[page.index('<table class="autosummary'):]
    table = re.sub(r"<[^>]+>", "", table[:table.index("</table>")])
    assert "by Hertz, Eq. 3.6." in table and "(Eqs. 3.1-3.3)" in table
    # A top-level name shown again on its subpackage's page links to its one indexed entry.
    contact = (site / "api" / "generated" / "fingerpad.contact.html").read_text(encoding="utf-8")
    assert 'href="fingerpad.html#fingerpad.HalfSpaceSolver"' in contact
    # A re-exported constant shows its own #: comment, not its type's docstring.
    entry = page[page.index('id="fingerpad.GENERATORS"'):]
    assert "CLI names of the texture generators" in entry[:2000]
    pages = "".join(p.read_text(encoding="utf-8") for p in (site / "api" / "generated").glob("*.html"))
    assert "int([x])" not in pages and "dict() -&gt; new empty dictionary" not in pages


def test_site_refers_to_nothing_outside_it(site: Path):
    """The pages load no script, style or image from elsewhere (links in the theme's footer aside).

    The one exception allowed is MathJax, which Sphinx adds to a page that shows an equation (the
    browser loads it to typeset; none of today's pages has one, they write equations as code)."""
    remote = set()
    for page in site.rglob("*.html"):
        found = re.findall(r'<(?:script|link|img)[^>]+(?:src|href)="(https?://[^"]+)"', page.read_text(encoding="utf-8"))
        remote.update(url for url in found if "mathjax" not in url.lower())
    assert not remote, sorted(remote)


def test_tutorial_is_stored_without_outputs():
    """Outputs stay out of git: the site and the test run the notebook."""
    notebook = json.loads((DOCS / "tutorial.ipynb").read_text(encoding="utf-8"))
    code = [cell for cell in notebook["cells"] if cell["cell_type"] == "code"]
    assert code and all(not cell["outputs"] and cell["execution_count"] is None for cell in code)


def test_tutorial_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    """The tutorial notebook runs from top to bottom (it checks its own numbers: the sweep's point
    equals the direct prediction), in a kernel whose working folder is a temporary one."""
    import nbformat
    from nbclient import NotebookClient

    notebook = nbformat.read(DOCS / "tutorial.ipynb", as_version=4)
    monkeypatch.setenv("FINGERPAD_CACHE", str(tmp_path / "cache"))  # the kernel inherits it
    start = time.perf_counter()
    NotebookClient(notebook, timeout=300, kernel_name="python3",
                   resources={"metadata": {"path": str(tmp_path)}}).execute()
    print(f"tutorial notebook: {time.perf_counter() - start:.1f} s")
    outputs = [out for cell in notebook.cells if cell.cell_type == "code" for out in cell.outputs]
    assert not [out for out in outputs if out.output_type == "error"]
    text = "".join(out.get("text", "") for out in outputs)
    assert "critical load" in text and "4 points computed" in text
    assert any("image/png" in out.get("data", {}) for out in outputs)  # the comparison figure
    assert not (tmp_path / "cache").exists()  # cache=False everywhere: the tutorial writes nothing


def test_make_run_has_a_folder_of_its_own():
    """Issue 30, item 21: the how-tos wrote into out/ (out/default, out/sim, ...), after which
    `make run`, writing out/ as a whole, refused it although the README says a rerun replaces it.
    `make run` now writes out/run, and nothing the docs or benchmarks run writes there."""
    run = re.search(r"^run:.*\n\t(.*)$", (ROOT / "Makefile").read_text(), re.M).group(1)
    folder = re.search(r"--out (\S+)", run).group(1)
    assert folder == "out/run"
    assert f"writes to `{folder}/`" in (ROOT / "README.md").read_text()
    texts = {p: p.read_text() for p in [ROOT / "README.md", *(ROOT / "docs").rglob("*.md"),
                                          *(ROOT / "benchmarks").glob("*.py")]}
    for path, text in texts.items():
        lines = [ln for ln in text.splitlines() if ln.lstrip().startswith(("fingerpad ", "--", "mkdir"))
                 or "--out" in ln or "--json" in ln]
        for line in lines:
            if "make run" in line or "run-default" in line and "--out" not in line:
                continue
            for target in re.findall(r"(?:--out|--json|--csv|--save|--plot|-o)[ =](\S+)|mkdir -p (\S+)", line):
                name = next(t for t in target if t).strip("`\"'")
                assert name.rstrip("/") != folder and not name.startswith(folder + "/"), (path, line)
