"""Sphinx configuration of the fingerpad documentation site (``make docs`` -> build/docs).

The Markdown pages are read by myst-parser (myst-nb for the tutorial notebook), the API reference
is generated from the numpydoc docstrings by autosummary + numpydoc. The build needs no network:
no intersphinx, MathJax is only referenced by the pages (the browser loads it when a page shows
an equation), and the tutorial is executed by the test suite, not by the build unless asked
(``make docs`` executes it; tests/test_docs.py builds with execution off and runs it separately).
"""

from __future__ import annotations

import importlib
import inspect
import os
import pkgutil
import sys

import sphinx.ext.autosummary
from sphinx.pycode import ModuleAnalyzer, PycodeError
from sphinx.util.nodes import make_refnode

import fingerpad

project = "fingerpad"
author = "the fingerpad developers"
copyright = "the fingerpad developers, MIT licence"  # noqa: A001 (Sphinx's name)
release = fingerpad.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_nb",  # also registers myst-parser for the .md pages
]

root_doc = "index"
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
exclude_patterns = ["_build", "**.ipynb_checkpoints"]
templates_path = ["_templates"]

# --- Markdown (myst) -------------------------------------------------------------------------
# Heading anchors as GitHub makes them, so that the pages' links `model.md#2-symbols` work both on
# the forge and in the site.
myst_heading_anchors = 4
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]

# --- The tutorial notebook -------------------------------------------------------------------
# FINGERPAD_DOCS_EXECUTE=off builds the site from the notebook's stored outputs (none are kept in
# git) and is what the strict build of the test suite uses: the notebook itself is executed by
# tests/test_docs.py. `make docs` executes it ("force", never from a cache keyed on the notebook
# alone: outputs of an older fingerpad would survive) so that the site shows its outputs.
nb_execution_mode = os.environ.get("FINGERPAD_DOCS_EXECUTE", "force")
nb_execution_timeout = 300
nb_execution_in_temp = True  # the kernel's working folder: a temporary one, not docs/
nb_execution_raise_on_error = True  # a tutorial that fails is a broken build, not a page with a traceback
nb_merge_streams = True

# --- API reference ---------------------------------------------------------------------------
autosummary_generate = True
autosummary_ignore_module_all = False  # a module page lists its __all__: the public names only
autodoc_typehints = "none"  # the numpydoc sections give the types, with units
autodoc_member_order = "bysource"
numpydoc_show_class_members = False  # the class pages list attributes from the docstrings
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_validation_checks: set[str] = set()
# The tables' one-line summaries end at the first full stop, but the docstrings cite equations:
# "Critical load of the first transition by Hertz, Eq. 3.6." would stop at "Eq.". autosummary has
# no setting for it, only this list of abbreviations that do not end a sentence.
sphinx.ext.autosummary.WELL_KNOWN_ABBREVIATIONS = (
    *sphinx.ext.autosummary.WELL_KNOWN_ABBREVIATIONS, "Eq.", "Eqs.", "ch.", "Fig.", "Sec.",
)
# The template (docs/_templates/api-module.rst) indexes the top-level names on fingerpad's page only.
autosummary_context = {"top_level": [name for name in fingerpad.__all__ if not name.startswith("_")]}

# Warnings are errors in the test suite (-W --keep-going): every unresolved reference is one.
nitpicky = True
nitpick_ignore_regex = [
    # Third-party types named in signatures and docstrings; the build has no intersphinx (no
    # network), so these are left as text.
    (r"py:.*", r"(numpy|np|scipy|xarray|xr|pandas|pd|dask|zarr|matplotlib|typing|collections|pathlib)(\..*)?"),
]


def _resolve(dotted: str) -> object | None:
    """The fingerpad object named ``dotted`` (module, then attributes), or None if there is none."""
    parts = dotted.split(".")
    for split in range(len(parts), 0, -1):
        try:
            obj: object = importlib.import_module(".".join(parts[:split]))
        except ImportError:
            continue
        for attr in parts[split:]:
            try:
                obj = getattr(obj, attr)
            except AttributeError:
                # A dataclass field without a default, or an annotated attribute, is no class
                # attribute, but the class's Attributes section documents it.
                fields = {name for klass in getattr(obj, "__mro__", ())
                          for name in vars(klass).get("__annotations__", {})}
                if attr != parts[-1] or attr not in fields:
                    return None
        return obj
    return None


def _in_submodules(package: str, name: str) -> bool:
    """Whether the direct submodules of ``package`` have exactly one object called ``name``.

    A package's docstring lists its modules and their main names (``:mod:`.run` -
    :func:`run_study```): the name is then one of its submodules'.
    """
    pkg = _resolve(package)
    if not hasattr(pkg, "__path__"):
        return False
    found = {id(obj) for info in pkgutil.iter_modules(pkg.__path__)
             if (obj := _resolve(f"{package}.{info.name}.{name}")) is not None}
    return len(found) == 1  # one object, whichever modules import it


def _parents(dotted: str) -> list[str]:
    """``a.b.c`` -> ``["a.b.c", "a.b", "a"]``."""
    parts = dotted.split(".") if dotted else []
    return [".".join(parts[:i]) for i in range(len(parts), 0, -1)]


def _linkable(obj: object) -> bool:
    """Classes, functions and modules: objects whose identity names them (not ints or strings)."""
    return inspect.isclass(obj) or inspect.isfunction(obj) or inspect.ismodule(obj)


_DOCUMENTED: dict[int, tuple[str, str]] = {}


def _documented_objects(env) -> dict[int, tuple[str, str]]:  # noqa: ANN001
    """id(object) -> (page, anchor) of every class, function and module the reference documents.

    Built once, when the first reference is resolved: by then every page has been read."""
    if not _DOCUMENTED:
        for fullname, entry in env.get_domain("py").objects.items():
            obj = _resolve(fullname) if not entry.aliased else None
            if obj is not None and _linkable(obj):
                _DOCUMENTED.setdefault(id(obj), (entry.docname, entry.node_id))
        _DOCUMENTED.setdefault(0, ("", ""))  # built, even if empty
    return _DOCUMENTED


def _existing_object_as_text(app, env, node, contnode):  # noqa: ANN001, ANN202 (Sphinx's event signature)
    """A docstring reference to a fingerpad object under a name the reference does not show.

    The reference documents the public API, each name once, while docstrings also name
    internals (``:mod:`.strokes```, ``:data:`STATE_SEARCH_CAP```) and full paths
    (``fingerpad.micro.bem.BEMUnitCell``). Such a reference is looked up the way Python's domain
    would (as written, in the current class, in the current module and its parents, and in the
    docstring's own module); when the object exists it becomes a link to where the same class or
    function is documented under another name, else code text. A name that exists nowhere, e.g.
    one left behind by a move, stays a warning, i.e. an error of the strict build.
    """
    if node.get("refdomain") != "py":
        return None
    target = node["reftarget"].lstrip("~")
    relative = target.startswith(".")
    target = target.lstrip(".")
    module = node.get("py:module") or ""
    cls = node.get("py:class") or ""
    scopes = [f"{module}.{cls}"] if module and cls else []
    scopes += _parents(module)
    # The docstring's own module: a class shown on fingerpad's page is defined in a submodule,
    # whose names its docstrings use (the node's source is "...: docstring of NAME").
    documented = str(node.source or "").rpartition("docstring of ")[2].strip()
    for name in _parents(documented) if documented.startswith("fingerpad") else []:
        owner = getattr(_resolve(name), "__module__", None)
        if isinstance(owner, str):
            scopes += [name, *_parents(owner)]
            break
    candidates = [f"{scope}.{target}" for scope in scopes]
    if not relative:
        candidates.append(target)
    for candidate in candidates:
        obj = _resolve(candidate) if candidate.split(".")[0] == "fingerpad" else None
        if obj is not None:
            # The same class or function documented under another name (the top-level
            # fingerpad.BEMUnitCell for fingerpad.micro.bem.BEMUnitCell): a link to it.
            documented_as = _documented_objects(env).get(id(obj)) if _linkable(obj) else None
            if documented_as is not None:
                docname, node_id = documented_as
                return make_refnode(app.builder, node["refdoc"], docname, node_id, contnode)
            return contnode
    in_package_docstring = documented == module and node.get("reftype") != "mod"
    if "." not in target and in_package_docstring and _in_submodules(module, target):
        return contnode
    return None


def _data_docstring(app, what, name, obj, options, lines):  # noqa: ANN001, ANN202, ARG001
    """A constant's documentation: its ``#:`` comment wherever it is defined, and its value.

    autodoc looks for the comment only in the module the page documents, so a constant that a
    package re-exports (``fingerpad.GENERATORS``, ``fingerpad.textures.MAX_GRID``) would show
    its type's docstring (``int([x]) -> integer ...``) instead. The comment is looked up in every
    fingerpad module that holds the same object under the same name.
    """
    if what != "data":
        return
    attr = name.rpartition(".")[2]
    comment: list[str] = []
    for modname in sorted(m for m in sys.modules if m == "fingerpad" or m.startswith("fingerpad.")):
        if getattr(sys.modules[modname], attr, _MISSING) is not obj:
            continue
        try:
            comment = ModuleAnalyzer.for_module(modname).find_attr_docs().get(("", attr), [])
        except PycodeError:
            continue
        if comment:
            break
    type_doc = inspect.getdoc(type(obj)) or ""
    if comment or "\n".join(lines).strip() == type_doc.strip():
        lines[:] = [line.rstrip("\n") for line in comment]
    text = repr(obj)
    if isinstance(obj, (int, float, str, tuple, dict)) and len(text) <= 100 and "<" not in text:
        lines += ["", f"Value: ``{text}``"]


_MISSING = object()


def setup(app):  # noqa: ANN001, ANN201
    app.connect("missing-reference", _existing_object_as_text)
    # Before numpydoc (priority 500) reformats the docstring.
    app.connect("autodoc-process-docstring", _data_docstring, priority=100)


# --- HTML ------------------------------------------------------------------------------------
html_theme = "furo"
html_title = f"fingerpad {release}"
html_static_path: list[str] = []
html_show_sourcelink = False
html_copy_source = False
