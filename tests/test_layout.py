"""The package's structure: every module imports on its own, no import cycles (lazy imports
included), the layers of README "Layout", one version."""

from __future__ import annotations

import ast
import subprocess
import sys
import tomllib
from pathlib import Path

import fingerpad

SRC = Path(fingerpad.__file__).resolve().parent
ROOT = SRC.parents[1]


def _modules() -> list[str]:
    names = []
    for path in sorted(SRC.rglob("*.py")):
        rel = path.relative_to(SRC.parent).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        names.append(".".join(parts))
    return names


def _from_target(node: ast.ImportFrom, package: str) -> str:
    """The absolute module of ``from X import ...`` written in ``package`` (relative levels resolved)."""
    if not node.level:
        return node.module or ""
    base = package.split(".")
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


MODULES = set(_modules())


def test_every_module_imports_on_its_own():
    """Each module imported first, in a fresh fingerpad namespace: no hidden import-order needs."""
    # Two interpreters, each importing every other module, run side by side: the imports are
    # independent, and on CI's two cores this halves the test's ~20 s.
    names = sorted(MODULES)
    procs = [subprocess.Popen([sys.executable, "-c", _import_each_code(names[start::2])],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for start in (0, 1)]
    outputs = [proc.communicate(timeout=300) for proc in procs]
    failures = [out + err for proc, (out, err) in zip(procs, outputs) if proc.returncode != 0]
    assert not failures, "\n".join(failures)


def _import_each_code(names: list[str]) -> str:
    """A script that imports each of ``names`` first, the fingerpad namespace emptied before each."""
    return (
        "import importlib, sys\n"
        "failed = []\n"
        f"for name in {names!r}:\n"
        "    for key in [k for k in sys.modules if k == 'fingerpad' or k.startswith('fingerpad.')]:\n"
        "        del sys.modules[key]\n"
        "    try:\n"
        "        importlib.import_module(name)\n"
        "    except Exception as exc:\n"
        "        failed.append(f'{name}: {type(exc).__name__}: {exc}')\n"
        "print('\\n'.join(failed))\n"
        "sys.exit(1 if failed else 0)\n"
    )


def find_cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan): the import cycles."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    cycles: list[list[str]] = []

    def strongconnect(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                strongconnect(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                cycles.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            strongconnect(v)
    return cycles


def import_graph() -> dict[str, set[str]]:
    """``module -> modules of fingerpad it imports``: at module level and inside functions alike
    (a lazy import still ties the two modules in a loop), TYPE_CHECKING blocks aside."""
    return _package_imports()[0]


def test_no_import_cycles():
    """No loop of imports, lazy (function-level) imports included."""
    assert not find_cycles(import_graph()), f"import cycles: {find_cycles(import_graph())}"


def test_cycle_detector_finds_cycles():
    """The detector itself: a three-module loop is found, a chain is not."""
    assert find_cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert find_cycles({"a": {"b"}, "b": {"c"}, "c": set()}) == []
    graph = import_graph()
    assert "fingerpad.contact" in graph["fingerpad.micro.bem"]  # the parser sees imports
    # ... lazy ones too: run_population imports the Sobol indices inside the function
    assert "fingerpad.population.sobol" in graph["fingerpad.population.run"]


def test_one_version_source():
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert "version" not in pyproject["project"] and "version" in pyproject["project"]["dynamic"]
    assert pyproject["tool"]["setuptools"]["dynamic"]["version"]["attr"] == "fingerpad._version.__version__"
    from fingerpad._version import __version__

    assert fingerpad.__version__ == __version__


def test_public_names_resolve():
    for name in fingerpad.__all__:
        assert getattr(fingerpad, name) is not None


def test_cli_start_imports_no_numerics():
    """`fingerpad --help` must start fast: the command modules import no numerics at import time."""
    code = ("import sys, fingerpad.cli\n"
            "heavy = [m for m in ('numpy', 'scipy', 'matplotlib', 'xarray', 'pandas', 'numba', 'SurfaceTopography')"
            " if m in sys.modules]\n"
            "print(heavy)\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0 and proc.stdout.strip() == "[]", proc.stdout + proc.stderr


def test_docs_refer_inside_the_repository():
    for path in [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]:
        text = path.read_text(encoding="utf-8")
        assert "../shared" not in text and "MODEL.md" not in text, path


# ------------------------------------------------------------------------------------------------
# Layer rules (README "Layout"): which part of the package may import which
# ------------------------------------------------------------------------------------------------

#: The layers, lowest first. A part (a folder, or a module at the package's top) may import its
#: own modules and any part of a LOWER layer; parts of one layer do not import each other, except
#: in the foundation, whose small modules form a chain (the cycle test keeps it acyclic).
LAYERS: list[tuple[str, tuple[str, ...]]] = [
    ("foundation", ("errors", "_version", "cancel", "extras", "references", "units", "checks", "materials", "plausibility",
                    "person", "discover", "params", "encode", "locks", "io", "netcdf")),
    ("surfaces", ("textures",)),
    ("contact engine", ("contact",)),
    ("macro scale", ("macro",)),
    ("meso scale", ("meso",)),
    ("friction laws", ("friction",)),
    ("finger", ("finger",)),
    ("micro scale", ("micro",)),
    ("coupling", ("coupling",)),
    ("figures", ("plotting",)),
    ("jobs", ("study", "measure")),
    ("population", ("population",)),
    ("perception", ("perception",)),
    ("design", ("design",)),
    ("explorer", ("explore",)),
    ("command line", ("cli",)),
    ("python -m fingerpad", ("__main__",)),
]

#: Heavy toolkits and the one part each may be imported in (at any depth, lazily too).
TOOLKITS: dict[str, str] = {
    "typer": "cli", "rich": "cli", "click": "cli",
    "matplotlib": "plotting",
    "panel": "explore", "bokeh": "explore", "param": "explore",
    "dask": "design", "distributed": "design", "zarr": "design",
    "statsmodels": "measure", "SurfaceTopography": "textures",
}


def _part(module: str) -> str:
    """``fingerpad.micro.bem`` -> ``micro``; ``fingerpad.coupling`` -> ``coupling``."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def _all_imports(path: Path, module: str) -> tuple[set[str], set[str]]:
    """Every import of ``path`` outside TYPE_CHECKING blocks, lazy ones inside functions too:
    (fingerpad modules, top-level names of other packages, including ``lazy_loader.load(...)``)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    skipped: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            skipped.update(id(n) for n in ast.walk(node))
    ours: set[str] = set()
    others: set[str] = set()
    for node in ast.walk(tree):
        if id(node) in skipped:
            continue
        if isinstance(node, ast.Import):
            for alias in node.names:
                (ours if alias.name.startswith("fingerpad") else others).add(alias.name)
        elif isinstance(node, ast.ImportFrom):
            target = _from_target(node, package)
            if not target.startswith("fingerpad"):
                others.add(target)
                continue
            submodules = {f"{target}.{a.name}" for a in node.names} & MODULES
            # `from .. import io` imports the module fingerpad.io, not the package's face
            ours.update(submodules if submodules and node.module is None else {target, *submodules})
        elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "load"
              and isinstance(node.func.value, ast.Name) and node.func.value.id == "lazy_loader"
              and node.args and isinstance(node.args[0], ast.Constant)):
            others.add(str(node.args[0].value))
    return ours, {name.split(".")[0] for name in others if name}


def _layer_of() -> dict[str, int]:
    return {part: i for i, (_, parts) in enumerate(LAYERS) for part in parts}


def layer_violations(edges: dict[str, set[str]]) -> list[str]:
    """Imports ``module -> module`` that break :data:`LAYERS` (given module-level edges)."""
    level = _layer_of()
    bad = []
    for source, targets in sorted(edges.items()):
        a = _part(source)
        if a == "__init__":
            continue  # the package's face hands every public name on, lazily
        for target in sorted(targets):
            b = _part(target)
            if a == b or b == "__init__" and target == "fingerpad._version":
                continue
            if b == "__init__":
                bad.append(f"{source} -> {target} (import the module, not the package's face)")
            elif a not in level or b not in level:
                bad.append(f"{source} -> {target} (part {a if a not in level else b!r} has no layer: add it)")
            elif level[b] > level[a] or (level[b] == level[a] and LAYERS[level[a]][0] != "foundation"):
                bad.append(f"{source} -> {target} ({LAYERS[level[a]][0]} may not import {LAYERS[level[b]][0]})")
    return bad


def _package_imports() -> tuple[dict[str, set[str]], dict[str, set[str]]]:
    ours: dict[str, set[str]] = {}
    others: dict[str, set[str]] = {}
    for path in SRC.rglob("*.py"):
        rel = path.relative_to(SRC.parent).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        name = ".".join(parts)
        found, third = _all_imports(path, name)
        ours[name] = {m for m in found if m in MODULES and m != name}
        others[name] = third
    return ours, others


def test_every_part_has_a_layer():
    parts = {_part(m) for m in MODULES} - {"__init__"}
    assert parts <= set(_layer_of()), f"parts without a layer: {sorted(parts - set(_layer_of()))}"


def test_no_import_breaks_the_layers():
    """No arrow climbs back up: lazy imports inside functions count too."""
    ours, _ = _package_imports()
    assert not layer_violations(ours), "\n".join(layer_violations(ours))


def test_heavy_toolkits_stay_in_their_folder():
    _, others = _package_imports()
    bad = [f"{module} imports {lib} (only {TOOLKITS[lib]}/ may)"
           for module, libs in sorted(others.items()) for lib in sorted(libs)
           if lib in TOOLKITS and _part(module) != TOOLKITS[lib]]
    assert not bad, "\n".join(bad)


def test_layer_checker_finds_a_climb():
    """The checker itself: an arrow up, a sibling arrow and an arrow to the face are found; arrows
    down and inside a part are not."""
    edges = {
        "fingerpad.plotting.measure": {"fingerpad.measure.analysis", "fingerpad.io"},
        "fingerpad.study.run": {"fingerpad.measure.curves", "fingerpad.study.spec", "fingerpad.coupling"},
        "fingerpad.micro.bem": {"fingerpad"},
        "fingerpad.units": {"fingerpad.errors"},
    }
    found = layer_violations(edges)
    assert len(found) == 3, found
    assert any("plotting.measure -> fingerpad.measure.analysis" in f for f in found)
    assert any("study.run -> fingerpad.measure.curves" in f for f in found)
    assert any("package's face" in f for f in found)
    _, others = _package_imports()
    assert "panel" in others["fingerpad.explore.app"]  # lazy_loader.load("panel") is seen
