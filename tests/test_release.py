"""The release path: ``python -m build`` makes an sdist and a wheel; the wheel holds the package,
its data and the licence, nothing else; installed (not editable) into a fresh environment with
the core dependencies alone, it predicts the built-in default, cites, and every command that
needs an extra stops with the one line naming it.

The fresh environment is installed without the network: a wheelhouse is packed from this
environment's own installed distributions (the core's dependency closure, read from the built
wheel's metadata), and pip installs from it with ``--no-index``. About 30-60 s on the 2-core
machine, most of it the build, the unpacking and the prediction's first solves.
"""

from __future__ import annotations

import base64
import email
import hashlib
import importlib.metadata as md
import os
import re
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src" / "fingerpad"

build = pytest.importorskip("build", reason="the release test needs `build` (the test extra)")
packaging_requirements = pytest.importorskip("packaging.requirements")


def _setuptools_is_new_enough() -> bool:
    try:
        return int(md.version("setuptools").split(".")[0]) >= 77
    except md.PackageNotFoundError:
        return False


pytestmark = pytest.mark.skipif(not _setuptools_is_new_enough(),
                                reason="building without isolation needs setuptools >= 77 (the test extra)")

#: Packages the core must not pull in (each belongs to an extra).
NOT_IN_CORE = ("numba", "llvmlite", "statsmodels", "dask", "distributed", "zarr", "surfacetopography", "panel",
               "bokeh", "ducc0", "openpyxl", "xlrd", "nptdms")


def run(cmd: list[str], **kw) -> subprocess.CompletedProcess:
    return subprocess.run(cmd, capture_output=True, text=True, timeout=600, **kw)


@pytest.fixture(scope="module")
def dist(tmp_path_factory) -> Path:
    """An sdist and a wheel built from the sdist, as ``python -m build`` (``make dist``) makes them."""
    out = tmp_path_factory.mktemp("dist")
    proc = run([sys.executable, "-m", "build", "--no-isolation", "--outdir", str(out), str(ROOT)])
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return out


def _wheel(dist: Path) -> Path:
    (wheel,) = dist.glob("fingerpad-*.whl")
    return wheel


def _core_requirements(wheel: Path) -> list[str]:
    with zipfile.ZipFile(wheel) as zf:
        meta = next(n for n in zf.namelist() if n.endswith(".dist-info/METADATA"))
        msg = email.message_from_bytes(zf.read(meta))
    return [r for r in msg.get_all("Requires-Dist") or [] if "extra ==" not in r]


def _closure(requirements: list[str]) -> dict[str, md.Distribution]:
    """The installed distributions the requirements need, recursively (markers evaluated here,
    extras only where a requirement names them)."""
    from packaging.requirements import Requirement
    from packaging.utils import canonicalize_name

    found: dict[str, md.Distribution] = {}
    todo = [(Requirement(r), "") for r in requirements]
    while todo:
        req, extra = todo.pop()
        if req.marker is not None and not req.marker.evaluate({"extra": extra}):
            continue
        name = canonicalize_name(req.name)
        if name in found:
            continue
        dist = md.distribution(req.name)
        found[name] = dist
        for sub in dist.requires or []:
            todo.append((Requirement(sub), ""))
            todo += [(Requirement(sub), e) for e in req.extras]
    return found


def _repack(dist: md.Distribution, house: Path) -> None:
    """A wheel of an installed distribution: its files as RECORD lists them (scripts outside
    site-packages left out: pip makes them again from entry_points.txt), a fresh RECORD."""
    info = Path(str(dist._path))  # type: ignore[attr-defined]  # the .dist-info folder
    site = info.parent
    tags = [line.split(":", 1)[1].strip().split("-") for line in (info / "WHEEL").read_text().splitlines()
            if line.startswith("Tag:")] or [["py3", "none", "any"]]
    tag = "-".join(".".join(sorted({t[i] for t in tags})) for i in range(3))  # py2.py3-none-any
    name = re.sub(r"[-_.]+", "_", dist.metadata["Name"])
    target = house / f"{name}-{dist.version}-{tag}.whl"
    record_name = f"{info.name}/RECORD"
    lines = []
    with zipfile.ZipFile(target, "w", zipfile.ZIP_STORED) as zf:
        for item in dist.files or []:
            rel = str(item)
            if rel.startswith("..") or rel == record_name or "__pycache__" in rel:
                continue
            path = site / rel
            if not path.is_file():
                continue
            data = path.read_bytes()
            zf.writestr(rel, data)
            digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
            lines.append(f"{rel},sha256={digest},{len(data)}")
        lines.append(f"{record_name},,")
        zf.writestr(record_name, "\n".join(lines) + "\n")


@pytest.fixture(scope="module")
def core_env(dist, tmp_path_factory) -> Path:
    """A fresh environment holding the wheel and the core's dependencies only (no network)."""
    base = tmp_path_factory.mktemp("core")
    house = base / "wheelhouse"
    house.mkdir()
    closure = _closure(_core_requirements(_wheel(dist)))
    for d in closure.values():
        _repack(d, house)
    env = base / "venv"
    proc = run([sys.executable, "-m", "venv", "--without-pip", str(env)])
    assert proc.returncode == 0, proc.stderr
    python = env / "bin" / "python"
    proc = run([sys.executable, "-m", "pip", "--python", str(python), "install", "--quiet", "--no-index",
                "--no-compile", "--disable-pip-version-check", "--find-links", str(house), str(_wheel(dist))])
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return env


def _env(tmp: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "VIRTUAL_ENV"))}
    env.update(FINGERPAD_CACHE=os.environ.get("FINGERPAD_CACHE", str(tmp / "cache")), COLUMNS="80")
    return env


def test_wheel_holds_the_package_its_data_and_the_licence_only(dist):
    with zipfile.ZipFile(_wheel(dist)) as zf:
        names = set(zf.namelist())
        licence = next(n for n in names if n.endswith("licenses/LICENSE"))
        assert zf.read(licence).decode() == (ROOT / "LICENSE").read_text()
        meta = email.message_from_bytes(zf.read(next(n for n in names if n.endswith("METADATA"))))
    info = {n for n in names if ".dist-info/" in n}
    assert {n.split("/", 1)[1] for n in info} == {"METADATA", "WHEEL", "RECORD", "entry_points.txt",
                                                  "top_level.txt", "licenses/LICENSE"}
    package = names - info
    expected = {f"fingerpad/{p.relative_to(SRC).as_posix()}" for p in SRC.rglob("*.py")} | {"fingerpad/py.typed"}
    assert package == expected, (sorted(package - expected)[:10], sorted(expected - package)[:10])
    from fingerpad import __version__

    assert meta["Version"] == __version__ and meta["License-Expression"] == "MIT"
    core = {re.split(r"[<>=!~; \[]", r, maxsplit=1)[0].lower() for r in _core_requirements(_wheel(dist))}
    assert not core & set(NOT_IN_CORE), core & set(NOT_IN_CORE)
    declared = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    assert len(core) == len(declared)


def test_sdist_holds_the_sources_and_the_user_texts(dist):
    import tarfile

    (sdist,) = dist.glob("fingerpad-*.tar.gz")
    with tarfile.open(sdist) as tf:
        names = {n.split("/", 1)[1] for n in tf.getnames() if "/" in n}
    assert {"LICENSE", "README.md", "CHANGELOG.md", "CITATION.cff", "pyproject.toml",
            "src/fingerpad/__init__.py", "src/fingerpad/py.typed"} <= names
    assert not any(n.startswith(("tests/", "benchmarks/", "docs/")) for n in names)


@pytest.mark.slow  # 16 s of the 2-core suite; the core environment is still built and used by the two below
def test_core_install_predicts_and_cites(core_env, tmp_path):
    env = _env(tmp_path)
    exe = str(core_env / "bin" / "fingerpad")
    installed = run([str(core_env / "bin" / "python"), "-c",
                     "import importlib.metadata as m; print(' '.join(d.metadata['Name'].lower() "
                     "for d in m.distributions()))"], env=env)
    names = set(installed.stdout.split())
    assert "fingerpad" in names and not names & set(NOT_IN_CORE), names & set(NOT_IN_CORE)
    # not the editable source tree: the installed copy
    where = run([str(core_env / "bin" / "python"), "-c", "import fingerpad; print(fingerpad.__file__)"], env=env)
    assert str(core_env) in where.stdout, where.stdout
    from fingerpad import __version__

    for cmd in ([exe, "--version"], [str(core_env / "bin" / "python"), "-m", "fingerpad", "--version"]):
        proc = run(cmd, env=env)
        assert proc.returncode == 0 and proc.stdout.strip() == f"fingerpad {__version__}", proc.stderr
    out = tmp_path / "out"
    proc = run([exe, "run-default", "--out", str(out)], env=env, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert {"predict.json", "predict.nc", "areas.png", "friction.png", "zones.png", "ridge_models.png"} <= {
        p.name for p in out.iterdir()}
    cite = run([exe, "cite"], env=env)
    assert cite.returncode == 0 and "10.3990/1.9789036551786" in cite.stdout
    cited = run([exe, "cite", str(out / "predict.json"), "--bibtex"], env=env)
    assert cited.returncode == 0 and "@article{polonsky1999," in cited.stdout


@pytest.mark.parametrize(("args", "extra"), [
    (["sweep", str(ROOT / "examples" / "sweep.toml"), "--out", "{tmp}/s.zarr"], "sweep"),
    (["design-map", "{tmp}/s.zarr", "--x", "spacing", "--y", "height", "--at", "1N"], "sweep"),
    (["analyse", "{tmp}", "--reference", "flat", "--out", "{tmp}/res"], "measure"),
    (["explore", "--no-browser"], "explore"),
    (["solve", "--surface", "{tmp}/scan.x3p", "--pressure", "20kPa"], "maps"),
])
def test_a_command_needing_an_extra_names_it(core_env, tmp_path, args, extra):
    (tmp_path / "scan.x3p").write_bytes(b"not read: the extra is checked first")
    before = sorted(p.name for p in tmp_path.iterdir())
    proc = run([str(core_env / "bin" / "fingerpad"), *[a.format(tmp=tmp_path) for a in args]], env=_env(tmp_path))
    assert proc.returncode == 2, (proc.stdout, proc.stderr)
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), proc.stderr
    assert f"the '{extra}' extra is not installed" in lines[0] and f"pip install 'fingerpad[{extra}]'" in lines[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # nothing written


def test_the_python_api_raises_the_same_message(core_env, tmp_path):
    """The library's own check, an ImportError and a FingerpadError at once, says what the
    command says."""
    code = ("from fingerpad.errors import FingerpadError\n"
            "from fingerpad.design.store import open_sweep\n"
            "try:\n    open_sweep('nowhere.zarr')\n"
            "except ImportError as exc:\n    assert isinstance(exc, FingerpadError); print(exc)\n")
    proc = run([str(core_env / "bin" / "python"), "-c", code], env=_env(tmp_path))
    assert proc.returncode == 0, proc.stderr
    cli = run([str(core_env / "bin" / "fingerpad"), "design-map", "nowhere.zarr", "--x", "a", "--y", "b"],
              env=_env(tmp_path), cwd=tmp_path)
    assert cli.stderr.strip() == f"error: {proc.stdout.strip()}"
