"""Bad inputs as a new user gives them, tried against the contract (issue 30): not a benchmark of
speed, an audit of the front doors, run by hand (``make bench`` does not run it).

The contract, for every user mistake: one ``error: ...`` line on stderr, exit code 2, no
traceback, nothing written (no output, no hidden left-over), a message of reasonable length, and
the check before any long work (each case has a time limit). The Python API raises
:class:`fingerpad.errors.FingerpadError` (never another exception); the explorer's server-side
check (``fingerpad.explore.inputs.validate``) returns field messages (never raises).

Each case runs the real ``fingerpad`` command in a fresh folder holding a few prepared files
(a valid study, a valid sweep study, a simulated measurement, a small sweep store, bad files).
The table lists every case that broke the contract and how; the last line counts
``tried / held / broke``. The important cases are also tests (tests/cli/test_bad_inputs.py,
tests/test_locks.py, ...).

Usage: ``.venv/bin/python benchmarks/bad_inputs.py [--jobs 2] [-k WORD] [--json out/bench/bad_inputs.json]``
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BIG = "9" * 5000
CAPS = ["--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "100um", "--grid", "16"]
SOLVE = ["solve", *CAPS, "--pressure", "1kPa"]
PREDICT = ["predict", *CAPS, "--loads", "1N", "--json", "-"]
STUDY = """[texture]
name = "caps"
radius = "50um"
height = "10um"
spacing = "100um"
[model]
grid = 16
[loads]
range = "0.5N:2N:3"
"""
SWEEP = STUDY.replace("[loads]\nrange = \"0.5N:2N:3\"\n", "") + """[sweep]
loads = "0.5N:2N:3"
[sweep.axes]
spacing = "100um:150um:2"
"""
DESIGN = ["design", "study.toml", "--vary", "spacing=100um:300um", "--target", "mu_rel=0.5@1N", "--evaluations", "2"]
ANALYSE = ["analyse", "sim", "--reference", "flat", "--out", "res", "--no-figures", "--no-sensitivity", "--n-null",
           "19"]


@dataclass
class Case:
    door: str
    args: list[str] | None = None  # a command line (run as `fingerpad ARGS`)
    files: dict[str, str | bytes] = field(default_factory=dict)  # files made in the case's folder first
    call: Callable[[Path], object] | None = None  # a Python API call (must raise FingerpadError)
    explore: dict | None = None  # study data for explore.inputs.validate (must return errors)
    limit: float = 60.0
    expect: str = ""  # a piece the error line must hold
    fifo: str = ""  # a FIFO made under this name


def study(**sections: str) -> str:
    """The valid study with sections replaced or added (TOML text per section name)."""
    text = STUDY
    for name, body in sections.items():
        start = text.find(f"[{name}]")
        if start >= 0:
            end = text.find("\n[", start + 1)
            text = text[:start] + text[(end + 1) if end >= 0 else len(text):]
        text += f"[{name}]\n{body}\n"
    return text


def cases() -> list[Case]:
    c: list[Case] = []
    cli = lambda door, *args, **kw: c.append(Case(door, list(args), **kw))  # noqa: E731

    # ------------------------------------------------------------------ solve
    for p in ("-1kPa", "0", "nan", "inf", "1e400", "1kPa:", "1:2:3:4", "abc", "1kPa:2kPa:0", "1kPa:2kPa:-3",
              "1kPa:2kPa:1.5", "1N", "2kPa:1kPa:3", f"1kPa:2kPa:{BIG}", "1kPa:2kPa:1000000", ""):
        cli("solve --pressure", *CAPS[:-2], "--pressure", p)
    for args in (["--texture", "nosuch"], ["--texture", ""], ["--texture", "caps", "--height", "10um", "--spacing",
                                                               "100um"],
                 ["--texture", "caps", "--radius", "-50um", "--height", "10um", "--spacing", "100um"],
                 ["--texture", "caps", "--radius", "0", "--height", "10um", "--spacing", "100um"],
                 ["--texture", "caps", "--radius", "nan", "--height", "10um", "--spacing", "100um"],
                 ["--texture", "caps", "--radius", "50parsec", "--height", "10um", "--spacing", "100um"],
                 ["--texture", "caps", "--radius", "50um", "--height", "60um", "--spacing", "100um"],
                 ["--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "10um"],
                 ["--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "100um", "--lattice",
                  "triangle"],
                 ["--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "100um", "--radius",
                  "60um"],
                 ["--texture", "ridges", "--width", "40um", "--height", "10um", "--spacing", "30um"],
                 ["--texture", "flat"], ["--texture", "sinusoid", "--amplitude", "-1um", "--wavelength", "100um"]):
        cli("solve --texture", "solve", *args, "--pressure", "1kPa")
    for opt, val in (("--grid", "3"), ("--grid", "abc"), ("--grid", "1.5"), ("--grid", "-4"), ("--grid", BIG),
                     ("--grid", "100000"), ("--modulus", "-1"), ("--skin-poisson", "0.6"), ("--skin-poisson", "-1"),
                     ("--skin-modulus", "0"), ("--skin-modulus", "1kN"), ("--tol", "0"), ("--tol", "2"),
                     ("--tol", "nan"), ("--max-iter", "0"), ("--max-iter", BIG), ("--json", "/nonexistent/x.json"),
                     ("--json", "out.txt"), ("--save", "x.txt"), ("--plot", "x.gif"), ("--json", "adir"),
                     ("--json", ""), ("--device", "gpu"), ("--save", "/proc/x.nc")):
        cli(f"solve {opt}", *SOLVE[:-2] if opt == "--grid" else SOLVE, opt, val, files={"adir/keep": "x"})
    cli("solve --modulus and --skin-modulus", *SOLVE, "--modulus", "1MPa", "--skin-modulus", "0.3MPa")
    cli("solve --material-poisson alone", *SOLVE, "--material-poisson", "0.3")
    cli("solve --material-modulus inf --material-poisson", *SOLVE, "--material-modulus", "inf",
        "--material-poisson", "0.3")
    for files, args in (({}, ["--surface", "missing.npy", "--size", "1mm"]),
                        ({"d/x": "x"}, ["--surface", "d", "--size", "1mm"]),
                        ({"e.npy": b""}, ["--surface", "e.npy", "--size", "1mm"]),
                        ({"g.npy": b"\x93NUMPY garbage"}, ["--surface", "g.npy", "--size", "1mm"]),
                        ({"t.txt": "1 2\n3\n"}, ["--surface", "t.txt", "--size", "1mm", "--height-unit", "um"]),
                        ({"t.txt": "1 2\n3 nan\n"}, ["--surface", "t.txt", "--size", "1mm", "--height-unit", "um"]),
                        ({"t.txt": "1 2\n3 4\n"}, ["--surface", "t.txt", "--size", "0", "--height-unit", "um"]),
                        ({"t.txt": "1 2\n3 4\n"}, ["--surface", "t.txt", "--size", "1mm", "--height-unit",
                                                   "furlong"]),
                        ({"t.txt": "1 2\n3 4\n"}, ["--surface", "t.txt", "--height-unit", "um"]),
                        ({"t.txt": "1 2\n3 4\n"}, ["--surface", "t.txt", "--size", "1mm,1mm,1mm", "--height-unit",
                                                   "um"]),
                        ({"t.txt": "1 2\n3 4\n"}, ["--surface", "t.txt", "--size", "1mm", "--pixel-size", "1um",
                                                   "--height-unit", "um"]),
                        ({"t.txt": "\x1b[2J 1 2\n3 4\n"}, ["--surface", "t.txt", "--size", "1mm", "--height-unit",
                                                             "um"])):
        cli("solve --surface", "solve", *args, "--pressure", "1kPa", files=files)
    c.append(Case("solve --surface FIFO", ["solve", "--surface", "pipe.npy", "--size", "1mm", "--pressure", "1kPa"],
                  fifo="pipe.npy", limit=20))

    # ------------------------------------------------------------------ predict
    for loads in ("0N", "-1N", "nan", "1N:2N:0", "2N:1N:3", "1kg", "1kPa", "", f"1N:2N:{BIG}", "1N:2N:1000000"):
        cli("predict --loads", "predict", *CAPS, "--loads", loads, "--json", "-")
    for opt, val in (("--finger", "nosuch"), ("--finger-param", "foo=1"), ("--finger-param", "radius=-1mm"),
                     ("--finger-param", "radius"), ("--finger-param", "radius=abc"), ("--finger-param", "tau0=1N"),
                     ("--finger-param", "ridge_fraction=2"), ("--model", "fem"), ("--accuracy", "0"),
                     ("--accuracy", "1.5"), ("--direction", "abc"), ("--direction", "1e400"), ("--direction", "30"),
                     ("--skin-layer-thickness", "2"), ("--skin-layer-thickness", "-1um"), ("--skin-base", "wood"),
                     ("--skin-substrate-modulus", "40kPa"), ("--max-iter", "1000000"), ("--tol", "-1"),
                     ("--material-modulus", "-1GPa"), ("--material-modulus", "soft"), ("--quantiles", "0.5"),
                     ("--population", "nosuch"), ("--population", ""), ("--sensitivity-samples", "1"),
                     ("--csv", "x.json"), ("--device", "tpu")):
        # (--cache /proc/nope is no mistake of the contract's kind: an unusable cache is a warning
        # and the work goes on, docs/outputs.md)
        cli(f"predict {opt}", *PREDICT, opt, val)
    for out, files in (("", {}), (".", {}), ("/proc/x", {}), ("f.txt", {"f.txt": "mine"}),
                       ("mine", {"mine/notes.txt": "mine"}), ("study.toml", {"study.toml": STUDY})):
        cli("predict --out", "predict", *CAPS, "--loads", "1N", "--out", out, files=files)
    cli("predict --json and --csv the same", "predict", *CAPS, "--loads", "1N", "--json", "a.json", "--csv", "a.json")
    cli("predict --json inside --out", "predict", *CAPS, "--loads", "1N", "--out", "o", "--json", "o/x.json")
    cli("predict --log --linear", *PREDICT, "--log", "--linear")
    cli("predict --texture and --surface", *PREDICT, "--surface", "x.npy")
    cli("predict unknown option", *PREDICT, "--outt", "x")
    cli("predict texture option typo", "predict", *CAPS[:-2], "--heigth", "1um", "--json", "-")
    cli("predict grid twice", *PREDICT, "--grid", "32")
    cli("predict ridges --direction on caps", *PREDICT, "--direction", "0")

    # study files (predict's door; sweep's and design's read the same files)
    bad_studies = {
        "missing": None, "directory": None, "fifo": None,
        "binary": b"\x00\x01\x02[texture]", "utf16": "[texture]\nname='caps'\n".encode("utf-16"),
        "latin1": b"[texture]\nname = 'caps\xe9'\n", "syntax": "[texture\nname = 'caps'",
        "nested": "x = " + "[" * 2000 + "]" * 2000, "nested tables": "x = " + "{a = " * 2000 + "1" + "}" * 2000,
        "big int": f"[model]\ngrid = {BIG}\n", "unknown section": STUDY + "[texturee]\nname = 'caps'\n",
        "unknown key": study(texture='name = "caps"\nradius = "50um"\nheight = "10um"\nspacing = "100um"\ncolour = 1'),
        "texture not a table": "texture = 3\n", "no texture": "[loads]\nrange = '1N:2N:2'\n",
        "texture name nosuch": study(texture='name = "nosuch"'),
        "texture radius list": study(texture='name = "caps"\nradius = ["50um"]\nheight = "10um"\nspacing = "100um"'),
        "texture radius bool": study(texture='name = "caps"\nradius = true\nheight = "10um"\nspacing = "100um"'),
        "texture radius table": study(texture='name = "caps"\nradius = {a = 1}\nheight = "10um"\nspacing = "100um"'),
        "loads range reversed": study(loads='range = "4N:1N:3"'), "loads values strings": study(loads='values = ["a"]'),
        "loads values empty": study(loads="values = []"), "loads both": study(loads='range = "1N:2N:2"\nvalues = [1]'),
        "loads log string": study(loads='range = "1N:2N:2"\nlog = "maybe"'),
        "loads zones_at -1": study(loads='range = "1N:2N:2"\nzones_at = "-1N"'),
        "finger preset nosuch": study(finger='preset = "thumb"'), "finger radius -1": study(finger='radius = "-1mm"'),
        "finger gross nosuch": study(finger='gross = { model = "nosuch" }'),
        "finger gross bad param": study(finger='gross = { model = "hertz", colour = 1 }'),
        "finger ridges fraction 2": study(finger='ridges = { model = "constant_fraction", fraction = 2 }'),
        "material modulus -1": study(material='modulus = "-1GPa"'), "material poisson 0.7": study(
            material='modulus = "1GPa"\npoisson = 0.7'), "material poisson no modulus": study(material="poisson = 0.3"),
        "model kind fem": study(model='kind = "fem"'), "model grid 3": study(model="grid = 3"),
        "model grid string": study(model='grid = "abc"'), "model tol 2": study(model="tol = 2"),
        "model max_iter 0": study(model="max_iter = 0"), "model cache not folder": study(model="cache = 3"),
        "model accuracy nan": study(model="accuracy = nan"), "model direction list": study(model="direction = [1]"),
        "surface missing": study(texture='surface = "nope.npy"\nsize = "1mm"'),
        "surface escape": study(texture='surface = "\\u001b[2J.npy"\nsize = "1mm"'),
        "population nosuch": STUDY + "[population]\nsize = 4\nbogus = 1\n",
        "huge file": None,
    }
    for name, text in bad_studies.items():
        files: dict[str, str | bytes] = {}
        target, fifo = "s.toml", ""
        if name == "directory":
            files = {"s.toml/x": "x"}
        elif name == "fifo":
            fifo = "s.toml"
        elif name == "huge file":
            files = {"s.toml": "# " + "x" * (17 * 2**20) + "\n" + STUDY}
        elif text is not None:
            files = {"s.toml": text}
        c.append(Case(f"study file: {name}", ["predict", target, "--json", "-"], files=files, fifo=fifo, limit=30))

    # ------------------------------------------------------------------ sweep
    sweeps = {
        "no [sweep]": STUDY, "empty axes": SWEEP.replace('spacing = "100um:150um:2"', ""),
        "axis nosuch": SWEEP.replace("spacing =", "colour ="), "axis no count": SWEEP.replace(":2\"", "\""),
        "axis count 0": SWEEP.replace(":2\"", ":0\""), "axis bare number": SWEEP.replace('"100um:150um:2"', "[1, 2]"),
        "axis values strings": SWEEP.replace('"100um:150um:2"', '["a", "b"]'),
        "axis too many points": SWEEP.replace('"100um:150um:2"', '"100um:150um:2000000"'),
        "design nosuch": SWEEP.replace("[sweep]\n", "[sweep]\ndesign = \"random\"\n"),
        "lhs without points": SWEEP.replace("[sweep]\n", "[sweep]\ndesign = \"lhs\"\n").replace(":2\"", "\""),
        "lhs points -1": SWEEP.replace("[sweep]\n", "[sweep]\ndesign = \"lhs\"\npoints = -1\n").replace(":2\"", "\""),
        "points without tables": SWEEP.replace("[sweep]\n", "[sweep]\ndesign = \"points\"\n"),
        "loads bad": SWEEP.replace('loads = "0.5N:2N:3"', 'loads = "abc"'),
        "loads negative": SWEEP.replace('loads = "0.5N:2N:3"', 'loads = "-1N:2N:3"'),
        "chunk 0": SWEEP.replace("[sweep]\n", "[sweep]\nchunk = 0\n"),
        "chunk string": SWEEP.replace("[sweep]\n", "[sweep]\nchunk = \"x\"\n"),
        "unknown key": SWEEP.replace("[sweep]\n", "[sweep]\ncolour = 1\n"),
        "sweep not a table": STUDY + "sweep = 3\n",
    }
    for name, text in sweeps.items():
        c.append(Case(f"sweep file: {name}", ["sweep", "s.toml", "--out", "r.zarr"], files={"s.toml": text}))
    for opt, val, files in (("--workers", "abc", {}), ("--workers", "0", {}), ("--workers", "100000", {}),
                            ("--scheduler", "nowhere", {}), ("--scheduler", "tcp://127.0.0.1:99999", {}),
                            ("--quantiles", "2", {}), ("--population", "nosuch", {}),
                            ("--out", "f.txt", {"f.txt": "mine"}), ("--out", "mine", {"mine/a.txt": "x"}),
                            ("--out", "", {}), ("--device", "tpu", {})):
        cli(f"sweep {opt}", "sweep", "sweep.toml", "--out", "r.zarr", opt, val, files=files)
    cli("sweep --overwrite on a user folder", "sweep", "sweep.toml", "--out", "mine", "--overwrite",
        files={"mine/a.txt": "x"})
    cli("sweep --workers and --scheduler", "sweep", "sweep.toml", "--out", "r.zarr", "--workers", "1",
        "--scheduler", "tcp://127.0.0.1:8786")
    cli("sweep --repair without a store", "sweep", "sweep.toml", "--out", "none.zarr", "--repair")
    cli("sweep into another sweep's store", "sweep", "sweep.toml", "--out", "store.zarr",
        files={"sweep.toml": SWEEP.replace("100um:150um:2", "100um:160um:2")})

    # ------------------------------------------------------------------ design
    for args in (["--vary", "spacing"], ["--vary", "spacing=1:2:3"], ["--vary", "nosuch=1:2"],
                 ["--vary", "spacing=300um:100um"], ["--vary", "lattice=1:2"], ["--vary", "spacing=-1um:100um"],
                 ["--target", "mu_rel=0.5"], ["--target", "mu_rel"], ["--target", "colour=0.5@1N"],
                 ["--target", "mu_rel=-1@1N"], ["--target", "mu_rel=0.5@-1N"], ["--target", "mu_rel=abc@1N"],
                 ["--tolerance", "0"], ["--tolerance", "2"], ["--coverage", "2"], ["--coverage", "0.5"],
                 ["--quantile", "-1", "--population", "adults"], ["--coverage", "0.5", "--quantile", "0.5",
                                                                  "--population", "adults"],
                 ["--population", "adults"], ["--from-sweep", "missing.zarr"], ["--from-sweep", "study.toml"],
                 ["--min-feature", "-1um"], ["--max-aspect", "0"], ["--min-critical-load", "abc"],
                 ["--json", "x.txt"], ["--candidates", "0"], ["--evaluations", "0"], ["--evaluations", "100000"]):
        base = [a for a in DESIGN]
        for a in args:
            if a in ("--vary", "--target") and a in base:
                i = base.index(a)
                del base[i:i + 2]
        cli(f"design {args[0]}", *base, *args)

    # ------------------------------------------------------------------ design-map
    for args in (["missing.zarr", "--x", "spacing", "--y", "height"], ["study.toml", "--x", "spacing", "--y", "h"],
                 ["store.zarr", "--x", "nosuch", "--y", "spacing"], ["store.zarr", "--x", "spacing", "--y", "spacing"],
                 ["store.zarr", "--x", "spacing", "--y", "height", "--at", "-1N"],
                 ["store.zarr", "--x", "spacing", "--y", "height", "--at", "100N"],
                 ["store.zarr", "--x", "spacing", "--y", "height", "--select", "bad"],
                 ["store.zarr", "--x", "spacing", "--y", "height", "--quantity", "nosuch"],
                 ["store.zarr", "--x", "spacing", "--y", "height", "--out", "f.txt"],
                 ["store.zarr", "--x", "spacing", "--y", "height", "--population", "adults"]):
        cli(f"design-map {args[1:3]}", "design-map", *args, files={"f.txt": "mine"})

    # ------------------------------------------------------------------ analyse / simulate-measurement
    for opt, val in (("--level", "2"), ("--outlier-z", "-1"), ("--trim", "0.6"), ("--n-null", "5"), ("--bins", "0"),
                     ("--seed", "-1"), ("--min-strokes", "0"), ("--trend", "up"), ("--loads", "5N:1N"),
                     ("--spec", "missing.toml"), ("--reference", "nosuch"), ("--n-null", "1000000000"),
                     ("--out", "sim"), ("--out", ""), ("--pattern", "{nope")):
        cli(f"analyse {opt}", *ANALYSE, opt, val)
    for name, files, data in (("no data", {}, []), ("missing", {}, ["nope.csv"]),
                              ("empty folder", {"empty/.keep": ""}, ["empty"]),
                              ("garbage csv", {"P01_flat_1.csv": "a,b\nx,y\n"}, ["P01_flat_1.csv"]),
                              ("empty csv", {"P01_flat_1.csv": ""}, ["P01_flat_1.csv"]),
                              ("binary csv", {"P01_flat_1.csv": b"\x00\x01\xff"}, ["P01_flat_1.csv"]),
                              ("manifest to missing file", {"m/manifest.csv": "file,participant,sample\nx.csv,P1,flat\n"},
                               ["m"]),
                              ("unknown format", {"P01_flat_1.xyz": "1"}, ["P01_flat_1.xyz"]),
                              ("bad spec toml", {"spec.toml": "[columns\n"}, ["sim", "--spec", "spec.toml"])):
        cli(f"analyse data: {name}", "analyse", *data, "--reference", "flat", "--out", "res2", files=files)
    for opt, val in (("--participants", "0"), ("--participants", "abc"), ("--repetitions", "0"), ("--strokes", "1"),
                     ("--loads", "5N:1N"), ("--loads", "abc"), ("--reference", "bumps"), ("--radius", "-1um"),
                     ("--sampling-rate", "0"), ("--seed", "-1"), ("--participants", BIG)):
        cli(f"simulate-measurement {opt}", "simulate-measurement", "--out", "sim2", opt, val)
    cli("simulate-measurement --out a user folder", "simulate-measurement", "--out", "mine", files={"mine/a.txt": "x"})

    # ------------------------------------------------------------------ deflection, fingers, textures, explore
    deflect = ["deflection", "--texture", "ellipsoids", "--height", "50um", "--semi-axis-x", "30um", "--semi-axis-y",
               "30um", "--spacing-x", "200um", "--spacing-y", "200um", "--levels", "1"]
    for opt, val in (("--texture", "caps"), ("--levels", "0"), ("--levels", "100"), ("--mu-max", "10"),
                     ("--resolution", "1"), ("--height", "-1um"), ("--pressure", "abc"), ("--pressure", "5kPa:1kPa"),
                     ("--out", "f.txt"), ("--levels", BIG), ("--alpha", "nan"), ("--skin-poisson", "0.7")):
        cli(f"deflection {opt}", *deflect, opt, val, files={"f.txt": "mine"})
    cli("fingers extra argument", "fingers", "extra")
    cli("textures extra argument", "textures", "--nosuch")
    cli("no such command", "frobnicate")
    for opt, val in (("--sweep", "missing.zarr"), ("--sweep", "study.toml"), ("--port", "99999"), ("--port", "abc"),
                     ("--max-upload", "0"), ("--population", "nosuch"), ("--population", "")):
        cli(f"explore {opt}", "explore", "--no-browser", opt, val, limit=30)

    # ------------------------------------------------------------------ explorer's server-side check
    good = {"texture": {"name": "caps", "radius": "50um", "height": "10um", "spacing": "100um"}}
    for name, data in {
        "grid huge": {**good, "model": {"grid": BIG}}, "grid negative": {**good, "model": {"grid": "-4"}},
        "loads huge": {**good, "loads": {"range": "0.1N:4N:100000"}},
        "texture forged": {"texture": {"name": "../../etc/passwd"}},
        "radius nan": {"texture": {**good["texture"], "radius": "nan"}},
        "radius 5 MB": {"texture": {**good["texture"], "radius": "x" * 5_000_000}},
        "finger forged": {**good, "finger": {"preset": "/etc/shadow"}},
        "model kind forged": {**good, "model": {"kind": "rm -rf"}},
        "surface path": {"texture": {"surface": "/etc/passwd", "size": "1mm"}},
        "escape in value": {"texture": {**good["texture"], "radius": "\x1b[2J"}},
        "loads reversed": {**good, "loads": {"range": "4N:1N:3"}},
        "material poisson alone": {**good, "material": {"poisson": "0.3"}},
        "tol 0": {**good, "model": {"tol": "0"}}, "unknown section": {**good, "colour": {"a": "1"}},
        "max_iter huge": {**good, "model": {"max_iter": BIG}},
    }.items():
        c.append(Case(f"explore validate: {name}", explore=data))

    # ------------------------------------------------------------------ the Python API
    def api(name: str, fn: Callable[[Path], object]) -> None:
        c.append(Case(f"api: {name}", call=fn))

    import fingerpad as fp

    def caps(**kw):
        from fingerpad import textures

        args = dict(radius=50e-6, height=10e-6, spacing=100e-6, grid=16)
        args.update(kw)
        return textures.spherical_caps(**args)

    api("spherical_caps radius -1", lambda d: caps(radius=-1))
    api("spherical_caps radius 'abc'", lambda d: caps(radius="abc"))
    api("spherical_caps grid 1.5", lambda d: caps(grid=1.5))
    api("spherical_caps grid huge", lambda d: caps(grid=10**40))
    api("HalfSpaceSolver modulus -1", lambda d: fp.HalfSpaceSolver(caps(), -1.0))
    api("HalfSpaceSolver max_iter huge", lambda d: fp.HalfSpaceSolver(caps(), 1e6, max_iter=10**9))
    api("HalfSpaceSolver texture None", lambda d: fp.HalfSpaceSolver(None, 1e6))
    api("solve_pressure -1", lambda d: fp.HalfSpaceSolver(caps(), 1e6).solve_pressure(-1.0))
    api("solve_pressure nan", lambda d: fp.HalfSpaceSolver(caps(), 1e6).solve_pressure(float("nan")))
    api("solve_approach inf", lambda d: fp.HalfSpaceSolver(caps(), 1e6).solve_approach(float("inf")))
    api("get_finger nosuch", lambda d: fp.get_finger("nosuch"))
    api("finger with_overrides radius abc", lambda d: fp.get_finger("default").with_overrides(radius="abc"))
    api("finger with_overrides unknown", lambda d: fp.get_finger("default").with_overrides(colour=1))
    api("predict_curve loads -1", lambda d: fp.predict_curve([-1.0], fp.get_finger("default"),
                                                             fp.BEMUnitCell(caps(), 1e6)))
    api("BEMUnitCell modulus 0", lambda d: fp.BEMUnitCell(caps(), 0.0))
    api("BEMUnitCell prepare reversed", lambda d: fp.BEMUnitCell(caps(), 1e6, cache=False).prepare(1e5, 1e2))
    from fingerpad.study import study_from_dict

    api("study_from_dict texture 3", lambda d: study_from_dict({"texture": 3}))
    api("study_from_dict loads list of str", lambda d: study_from_dict(
        {"texture": {"name": "flat", "size": "1mm"}, "loads": {"values": ["a"]}}))
    api("study_from_dict loads a list", lambda d: study_from_dict({"texture": {"name": "flat", "size": "1mm"},
                                                                   "loads": [1]}))
    api("study_from_dict not a dict", lambda d: study_from_dict(["texture"]))
    api("load_population ''", lambda d: __import__("fingerpad.population.sources", fromlist=["x"]).load_population(""))
    api("design_textures targets []", lambda d: __import__("fingerpad.design.inverse_design", fromlist=["x"]).design_textures(
        {"texture": {"name": "caps", "radius": "50um", "height": "10um", "spacing": "100um"}},
        ["spacing=100um:300um"], []))
    api("sweep_from_dict no sweep", lambda d: __import__("fingerpad.design.spec", fromlist=["x"]).sweep_from_dict(
        {"texture": {"name": "caps", "radius": "50um", "height": "10um", "spacing": "100um"}}))
    api("run_sweep workers 10**6", lambda d: __import__("fingerpad.design.engine", fromlist=["x"]).run_sweep(
        __import__("fingerpad.design.spec", fromlist=["x"]).sweep_from_dict({**{k: v for k, v in __import__(
            "tomllib").loads(SWEEP).items()}}), d / "r.zarr", workers=10**6))
    api("parse_quantity None", lambda d: __import__("fingerpad.units", fromlist=["x"]).parse_quantity(None, "length"))
    api("open_sweep of a file", lambda d: (d / "x.txt").write_text("x") and __import__(
        "fingerpad.design.store", fromlist=["x"]).open_sweep(d / "x.txt"))
    api("read_study_file nested", lambda d: (d / "n.toml").write_text("x = " + "[" * 3000 + "]" * 3000) and __import__(
        "fingerpad.study.spec", fromlist=["x"]).read_study_file(d / "n.toml"))
    api("OutputFolder of the current folder", lambda d: __import__("fingerpad.io", fromlist=["x"]).OutputFolder("."))
    # ------------------------------------------------------------------ a second round (after the first fixes)
    for opt, val in (("--plot-at", "1kPa"), ("--critical", "2"), ("--critical", "abc"), ("--formulation", "nosuch"),
                     ("--base-quantile", "2"), ("--pixel-size", "1um"), ("--periodize", None), ("--csv", "-"),
                     ("--csv", "x.csv"), ("--json", "x.csv")):
        extra = [opt] if val is None else [opt, val]
        if opt == "--csv" and val == "x.csv":
            extra += ["--json", "x.csv"]
        cli(f"solve {opt} (2)", *SOLVE, *extra)
    cli("solve --plot-at -1kPa", *SOLVE, "--plot", "p.png", "--plot-at", "-1kPa")
    for opt, val in (("--zones-at", "-1N"), ("--zones-at", "abc"), ("--finger-param", "=1"),
                     ("--finger-param", "radius=1mm=2"), ("--finger-param", "skin=layered"),
                     ("--sensitivity", None), ("--quantiles", "0.5,abc"), ("--csv", "-"), ("--base-quantile", "0.5"),
                     ("--pixel-size", "1um"), ("--size", "1mm"), ("--height-unit", "um"), ("--skin-base", "rigid"),
                     ("--skin-substrate-poisson", "0.3"), ("--material-poisson", "0.7"), ("--skin-modulus", "nan"),
                     ("--finger", ""), ("--model", ""), ("--accuracy", "abc"), ("--tol", "1e-400")):
        cli(f"predict {opt} (2)", *PREDICT, *([opt] if val is None else [opt, val]))
    cli("predict ridges without width", "predict", "--texture", "ridges", "--height", "10um", "--spacing", "100um",
        "--json", "-")
    cli("predict ellipsoids orientation abc", "predict", "--texture", "ellipsoids", "--semi-axis-x", "30um",
        "--semi-axis-y", "30um", "--height", "10um", "--spacing-x", "100um", "--spacing-y", "100um", "--orientation",
        "abc", "--json", "-")
    cli("predict surface with texture options", "predict", "--surface", "t.txt", "--radius", "50um", "--size",
        "1mm", "--height-unit", "um", "--json", "-", files={"t.txt": "1 2\n3 4\n"})
    cli("predict --model hertz on ridges", "predict", "--texture", "ridges", "--width", "40um", "--height", "10um",
        "--spacing", "100um", "--model", "hertz", "--json", "-")
    for sel in ("height=abc", "height=99um", "nosuch=1", "height=8um", "spacing=100um"):
        cli(f"design-map --select {sel}", "design-map", "store.zarr", "--x", "spacing", "--y", "height", "--select",
            sel, *(["--select", "height=10um"] if sel == "height=8um" else []))
    for opt, val in (("--at", "abc"), ("--at", "0"), ("--quantity", "mu_perp_over_par"), ("--out", ""),
                     ("--out", "."), ("--x", "")):
        cli(f"design-map {opt} (2)", "design-map", "store.zarr", "--x", "spacing", "--y", "height", opt, val)
    for opt, val in (("--quantiles", "0.5,abc"), ("--quantiles", ""), ("--quantiles", "0.5,2"),
                     ("--population", "examples"), ("--workers", "1.5"), ("--scheduler", ""),
                     ("--scheduler", "tcp://[::1"), ("--out", "."), ("--out", "sweep.toml")):
        cli(f"sweep {opt} (2)", "sweep", "sweep.toml", "--out", "r.zarr", opt, val)
    pop = {"population size 0": "[population]\nsize = 0\n", "size -1": "[population]\nsize = -1\n",
           "size abc": "[population]\nsize = \"abc\"\n", "size 1e7": "[population]\nsize = 10000000\n",
           "unknown distribution": "[population]\nsize = 4\n[population.skin_modulus]\ndist = \"nosuch\"\n",
           "sd nan": "[population]\nsize = 4\n[population.skin_modulus]\ndist = \"normal\"\nmean = \"0.3MPa\"\n"
                     "sd = nan\n",
           "values with a unit": "[population]\nsize = 4\n[population.alpha]\nvalues = [0.1, \"5kPa\"]\n",
           "nested": "x = " + "[" * 2000 + "]" * 2000, "not a table": "population = 3\n", "empty file": ""}
    for name, text in pop.items():
        c.append(Case(f"population file: {name}", ["predict", *CAPS, "--loads", "1N", "--json", "-", "--population",
                                                   "p.toml"], files={"p.toml": text}))
    c.append(Case("population file: FIFO", ["predict", *CAPS, "--loads", "1N", "--json", "-", "--population", "p.toml"],
                  fifo="p.toml", limit=20))
    c.append(Case("population folder without participants", ["predict", *CAPS, "--loads", "1N", "--json", "-",
                                                              "--population", "d"], files={"d/x.txt": "x"}))
    for opt, val in (("--reference", ""), ("--samples", "missing.csv"), ("--samples", "sim/manifest.csv"),
                     ("--loads", "1N"), ("--level", "abc")):
        cli(f"analyse {opt} (2)", *ANALYSE, opt, val)
    cli("analyse a file the pattern does not match", "analyse", "sim/P01_flat_1.csv", "--pattern", "nothing",
        "--reference", "flat", "--out", "res3")
    # (not mistakes of the contract's kind, tried and left out: a 100 000-character --title is a
    # title; the same file given twice is read once; --pattern is unused where a manifest is read)
    for opt, val in (("--friction", "nosuch"), ("--time-limit", "-1"), ("--max-steps", "0"), ("--direction", "abc"),
                     ("--tau0", "-1kPa"), ("--material-poisson", "0.7"), ("--material-modulus", "-1MPa"),
                     ("--skin-modulus", "0")):
        cli(f"deflection {opt} (2)", *deflect, opt, val)
    for opt, val in (("--texture", "flat"), ("--participants", "1.5"), ("--strokes", BIG), ("--repetitions", "-1")):
        cli(f"simulate-measurement {opt} (2)", "simulate-measurement", "--out", "sim3", opt, val)
    for name, data in {
        "no texture": {"loads": {"range": "1N:2N:3"}}, "texture name empty": {"texture": {"name": ""}},
        "spacing escape": {"texture": {**good["texture"], "spacing": "1\u202e00um"}},
        "loads 5 MB": {**good, "loads": {"range": "x" * 5_000_000}},
        "finger radius -1": {**good, "finger": {"radius": "-1mm"}},
        "material modulus inf poisson": {**good, "material": {"modulus": "inf", "poisson": "0.3"}},
        "direction abc": {**good, "model": {"direction": "abc"}},
        "grid 1.5": {**good, "model": {"grid": "1.5"}},
    }.items():
        c.append(Case(f"explore validate (2): {name}", explore=data))
    from fingerpad.contact.layered import Layer

    api("Layer thickness -1", lambda d: Layer(-1.0, 1e6, 0.49, 4e4, 0.49))
    api("Layer poisson 0.7", lambda d: Layer(3e-4, 1e6, 0.7, 4e4, 0.49))
    api("ridges width 0", lambda d: __import__("fingerpad.textures", fromlist=["x"]).ridges(width=0, height=1e-5,
                                                                                          spacing=1e-4))
    api("periodize of a list", lambda d: __import__("fingerpad.textures", fromlist=["x"]).periodize([1, 2]))
    api("finger_param nosuch", lambda d: __import__("fingerpad.finger", fromlist=["x"]).finger_param("nosuch"))
    api("parse_range reversed", lambda d: __import__("fingerpad.units", fromlist=["x"]).parse_range("2N:1N:3", "force"))
    api("Study loads nan", lambda d: __import__("fingerpad.study", fromlist=["x"]).Study(
        texture=__import__("fingerpad.study", fromlist=["x"]).TextureSpec(name="flat", params={"size": "1mm"}),
        loads=[float("nan")]))
    api("predict_curve finger None", lambda d: fp.predict_curve([1.0], None, fp.BEMUnitCell(caps(), 1e6)))
    api("open_sweep of a folder", lambda d: (d / "f").mkdir() or __import__(
        "fingerpad.design.store", fromlist=["x"]).open_sweep(d / "f"))
    api("read_toml of a FIFO", lambda d: os.mkfifo(d / "p.toml") or __import__(
        "fingerpad.io", fromlist=["x"]).read_toml(d / "p.toml"))

    # ------------------------------------------------ round 3: the population's rules and sources
    # (after the house's population/ and its attach: a fixed value, an analyse folder tampered
    # with, the population's flags at every door, the library's calls)
    def panel(participants: str | bytes, summary: str = '{"study": {}}') -> dict[str, str | bytes]:
        manifest = json.dumps({"files": ["participants.csv", "summary.json"]})
        return {"a/.fingerpad-output.json": manifest, "a/participants.csv": participants, "a/summary.json": summary}

    ok_row = "participant,skin_modulus\nP01,300000\n"
    for name, files in {
        "E_s inf": panel("participant,skin_modulus\nP01,inf\n"),
        "E_s text": panel("participant,skin_modulus\nP01,soft\n"),
        "header only": panel("participant,skin_modulus\n"),
        "participants UTF-16": panel(ok_row.encode("utf-16")),
        "participants binary": panel(b"\x00\x01\x02" * 100),
        "tau0 text": panel("participant,skin_modulus,tau0\nP01,300000,x\n"),
        "tau0 negative": panel("participant,skin_modulus,tau0\nP01,300000,-5\n"),
        "tau0 for one only": panel("participant,skin_modulus,tau0\nP01,300000,5000\nP02,350000,\n"),
        "summary []": panel(ok_row, "[]"),
        "summary not JSON": panel(ok_row, "{"),
        "summary 2000 deep": panel(ok_row, "[" * 2000 + "]" * 2000),
        "manifest not JSON": {**panel(ok_row), "a/.fingerpad-output.json": "{"},
        "participants a folder": {**panel(ok_row), "a/participants.csv": None},
    }.items():
        files = {k: v for k, v in files.items() if v is not None}
        if name == "participants a folder":
            files["a/participants.csv/x"] = "x"
        cli(f"pop3 analyse folder: {name}", *PREDICT, "--population", "a", files=files)
    study_pop = STUDY + "[finger]\nskin_modulus = \"0.45MPa\"\n"
    cli("pop3 [finger] skin_modulus with adults", "predict", "s.toml", "--json", "-", "--population", "adults",
        files={"s.toml": study_pop})
    cli("pop3 [finger] tau0 with adults (sweep)", "sweep", "s.toml", "--out", "r.zarr", "--population", "adults",
        files={"s.toml": SWEEP + "[finger]\ntau0 = \"5kPa\"\n"})
    cli("pop3 [finger] skin_modulus with adults (design)", *DESIGN[:1], "s.toml", *DESIGN[2:], "--population",
        "adults", "--coverage", "0.5", files={"s.toml": study_pop})
    cli("pop3 --finger-param radius with adults", *PREDICT, "--finger-param", "radius=9mm", "--population", "adults")
    cli("pop3 --sensitivity-samples without --sensitivity", *PREDICT, "--population", "adults",
        "--sensitivity-samples", "8")
    cli("pop3 --quantiles without a population (sweep)", "sweep", "sweep.toml", "--out", "r.zarr", "--quantiles",
        "0.5")
    cli("pop3 --quantile without a population (design)", *DESIGN, "--quantile", "0.1")
    cli("pop3 --coverage 0 (design)", *DESIGN, "--population", "adults", "--coverage", "0")
    cli("pop3 --population with a direction", *PREDICT, "--population", "adults", "--direction", "0deg")
    cli("pop3 study [population] size 20001", "predict", "s.toml", "--json", "-",
        files={"s.toml": STUDY + "[population]\nsize = 20001\n"})
    cli("pop3 study [population] not a table", "predict", "s.toml", "--json", "-",
        files={"s.toml": "population = 3\n" + STUDY})
    cli("pop3 population file: [population] 5 MB name", *PREDICT, "--population", "p.toml",
        files={"p.toml": "[population]\nname = \"" + "x" * 5_000_000 + "\"\n"})
    cli("pop3 population file: correlation 2", *PREDICT, "--population", "p.toml",
        files={"p.toml": "[population]\nsize = 8\ncorrelations = [[\"radius\", \"modulus\", 2]]\n"
                         "radius = { values = [\"8mm\", \"9mm\"] }\nmodulus = { values = [\"30kPa\", \"40kPa\"] }\n"})
    cli("pop3 population file: a bare pressure", *PREDICT, "--population", "p.toml",
        files={"p.toml": "[population]\ntau0 = { distribution = \"uniform\", low = 1000, high = 5000 }\n"})
    cli("pop3 explore --population a FIFO", "explore", "--no-browser", "--population", "p.toml", fifo="p.toml",
        limit=20)
    cli("pop3 explore --population a bad table", "explore", "--no-browser", "--population", "p.toml",
        files={"p.toml": "[population]\ntau0 = { distribution = \"beta\" }\n"})
    from fingerpad.study.spec import DEFAULT_STUDY, study_from_dict

    def nominal(**finger: str):
        data = json.loads(json.dumps(DEFAULT_STUDY))
        data["model"], data["loads"] = {"kind": "hertz"}, {"range": "0.1N:4N:3"}
        data["finger"] = {"preset": "default", **finger}
        return study_from_dict(data)

    pop_api = __import__("fingerpad.population", fromlist=["x"])
    api("pop3 run_population E_s fixed, adults", lambda d: pop_api.run_population(nominal(skin_modulus="0.45MPa"),
                                                                                  "adults"))
    api("pop3 run_population of a list", lambda d: pop_api.run_population(nominal(), [1, 2]))
    api("pop3 run_population quantiles 2", lambda d: pop_api.run_population(nominal(), "adults", quantiles=[2]))
    api("pop3 run_population sensitivity 1e9", lambda d: pop_api.run_population(nominal(), "adults",
                                                                                 sensitivity=10**9))
    api("pop3 population_from_table size 1e7", lambda d: pop_api.population_from_table({"size": 10**7}))
    api("pop3 attach a direction axis", lambda d: pop_api.attach(nominal(), "adults", axes=["direction"]))
    api("pop3 design_textures E_s fixed, adults", lambda d: __import__(
        "fingerpad.design.inverse_design", fromlist=["x"]).design_textures(
        {**json.loads(json.dumps(DEFAULT_STUDY)), "finger": {"skin_modulus": "0.45MPa"}}, ["spacing=100um:200um"],
        ["mu_rel=0.5@1N"], population="adults", coverage=0.5))
    c.append(Case("pop3 explore validate: E_s typed, adults chosen (run_preset)", call=lambda d: __import__(
        "fingerpad.explore.views.population", fromlist=["x"]).run_preset(
        {**json.loads(json.dumps(DEFAULT_STUDY)), "finger": {"skin_modulus": "0.45MPa"}}, "adults")))
    return c


# ---------------------------------------------------------------------------------------------------------------


def prepare(base: Path) -> None:
    """The files every case finds: a valid study, a sweep study, a simulated measurement, a store."""
    (base / "study.toml").write_text(STUDY)
    (base / "sweep.toml").write_text(SWEEP)
    env = {**os.environ, "FINGERPAD_CACHE": str(base / "cache")}
    fp = [sys.executable, "-c", "import sys; from fingerpad.cli import main; sys.argv[0] = 'fingerpad'; main()"]
    subprocess.run([*fp, "simulate-measurement", "--out", str(base / "sim"), "--participants", "2"], env=env,
                   check=True, capture_output=True)
    store = SWEEP.replace('spacing = "100um:150um:2"', 'spacing = "100um:150um:2"\nheight = ["8um", "10um"]')
    (base / "store.toml").write_text(store)
    subprocess.run([*fp, "sweep", str(base / "store.toml"), "--out", str(base / "store.zarr"), "--workers", "1"],
                   env=env, check=True, capture_output=True)


def snapshot(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*")}


def run_case(case: Case, base: Path) -> tuple[bool, str, float]:
    """Run one case; (held, why it broke, seconds)."""
    folder = Path(tempfile.mkdtemp(prefix="bad-input-"))
    try:
        for name in ("study.toml", "sweep.toml", "sim", "store.zarr", "cache"):
            src = base / name
            (shutil.copytree if src.is_dir() else shutil.copy2)(src, folder / name)
        for name, content in case.files.items():
            path = folder / name
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(content if isinstance(content, bytes) else content.encode())
        if case.fifo:
            os.mkfifo(folder / case.fifo)
        before = snapshot(folder)
        t0 = time.perf_counter()
        if case.args is not None:
            env = {**os.environ, "FINGERPAD_CACHE": str(folder / "cache"), "COLUMNS": "100"}
            code = "import sys; from fingerpad.cli import main; sys.argv[0] = 'fingerpad'; main()"
            try:
                done = subprocess.run([sys.executable, "-c", code, *case.args], cwd=folder, env=env, text=True,
                                      capture_output=True, timeout=case.limit, errors="replace")
            except subprocess.TimeoutExpired:
                return False, f"no refusal within {case.limit:.0f} s (the work ran)", time.perf_counter() - t0
            seconds = time.perf_counter() - t0
            lines = [ln for ln in done.stderr.splitlines() if ln.strip() and not ln.startswith("warning:")
                     and not ln.startswith("note:")]
            why = []
            if done.returncode != 2:
                why.append(f"exit {done.returncode}")
            if "Traceback" in done.stderr or "Traceback" in done.stdout:
                why.append("traceback")
            if len(lines) != 1 or not lines[0].startswith("error: "):
                why.append(f"{len(lines)} lines on stderr: {(lines or [''])[-1][:160]!r}")
            elif len(lines[0]) > 1200:
                why.append(f"an error line of {len(lines[0])} characters")
            elif case.expect and case.expect not in lines[0]:
                why.append(f"message without {case.expect!r}: {lines[0][:160]}")
            if any(ord(ch) < 32 and ch not in "\n\t" for ch in done.stderr + done.stdout):
                why.append("control characters printed raw")
            after = snapshot(folder)
            made = sorted(p for p in after - before if not p.startswith("cache"))
            if made:
                why.append(f"left behind: {', '.join(made[:3])}")
            return not why, "; ".join(why), seconds
        if case.explore is not None:
            from fingerpad.explore.inputs import validate

            try:
                result = validate(case.explore)
            except Exception as exc:  # noqa: BLE001 - what the audit looks for
                return False, f"raised {type(exc).__name__}: {str(exc)[:120]}", time.perf_counter() - t0
            longest = max((len(e.message) for e in result.errors), default=0)
            why = [] if result.errors and result.study is None else ["accepted"]
            if longest > 1200:
                why.append(f"a message of {longest} characters")
            return not why, "; ".join(why), time.perf_counter() - t0
        from fingerpad.errors import FingerpadError

        try:
            case.call(folder)  # type: ignore[misc]
        except FingerpadError as exc:
            long = len(str(exc)) > 1200
            return not long, "a message of more than 1200 characters" if long else "", time.perf_counter() - t0
        except Exception as exc:  # noqa: BLE001 - what the audit looks for
            return False, f"raised {type(exc).__name__}: {str(exc)[:120]}", time.perf_counter() - t0
        return False, "accepted", time.perf_counter() - t0
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--jobs", type=int, default=2, help="cases run side by side")
    ap.add_argument("-k", default="", help="only the cases whose name holds this")
    ap.add_argument("--json", type=Path, default=None, help="write the results as JSON")
    args = ap.parse_args()
    chosen = [c for c in cases() if args.k in c.door]
    base = Path(tempfile.mkdtemp(prefix="bad-input-base-"))
    try:
        prepare(base)
        cli = [c for c in chosen if c.args is not None]
        inproc = [c for c in chosen if c.args is None]
        with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            results = list(pool.map(lambda c: (c, *run_case(c, base)), cli))
        results += [(c, *run_case(c, base)) for c in inproc]
    finally:
        shutil.rmtree(base, ignore_errors=True)
    broke = [(c, why, s) for c, held, why, s in results if not held]
    for c, why, s in broke:
        print(f"BROKE  {c.door:45.45s}  {' '.join(c.args or [])[:60]!s:60.60s}  {why}")
    held = len(results) - len(broke)
    print(f"tried {len(results)} / held {held} / broke {len(broke)}")
    if args.json is not None:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({
            "tried": len(results), "held": held, "broke": len(broke),
            "cases": [{"door": c.door, "args": c.args, "held": h, "why": w, "seconds": round(s, 2)}
                      for c, h, w, s in results]}, indent=1))


if __name__ == "__main__":
    main()
