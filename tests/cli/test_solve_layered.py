"""``fingerpad solve`` with a layered skin (issue 24): the library's layered solve, and the
option combinations it refuses in one line."""

from __future__ import annotations

import json
import math
import warnings

import pytest
from typer.testing import CliRunner

import fingerpad as fp
from fingerpad.cli import app
from fingerpad.contact import Layer
from fingerpad.materials import reduced_modulus

BASE = ["solve", "--texture", "sinusoid", "--amplitude", "1um", "--wavelength", "100um", "--grid", "16",
        "--pressure", "10kPa", "--tol", "1e-10", "--json", "-"]
LAYER = ["--skin-layer-thickness", "20um", "--skin-layer-modulus", "1MPa", "--skin-substrate-modulus", "100kPa"]


def invoke(*args: str):
    return CliRunner().invoke(app, list(args))


def library(layer: Layer | None, modulus: float):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tex = fp.make_texture("sinusoid", amplitude=1e-6, wavelength=100e-6, grid=16)
    return fp.HalfSpaceSolver(tex, modulus, layer=layer, tol=1e-10).solve_pressure(1e4)


@pytest.mark.parametrize(("substrate", "e2"), [("100kPa", 1e5), ("rigid", math.inf)])
def test_layered_solve_equals_the_library(substrate: str, e2: float) -> None:
    res = invoke(*BASE, *LAYER[:4], "--skin-substrate-modulus", substrate, "--skin-poisson", "0.45")
    assert res.exit_code == 0, res.output
    doc = json.loads(res.stdout)
    layer = Layer(20e-6, 1e6, 0.45, e2, 0.45)
    ref = library(layer, reduced_modulus(1e6, 0.45))
    homog = library(None, reduced_modulus(1e6, 0.45))
    assert doc["inputs"]["materials"]["skin_layer_thickness"] == 20e-6
    got = doc["results"][0]
    assert got["contact_fraction"] == ref.contact_fraction
    assert got["max_pressure"] == pytest.approx(ref.max_pressure, rel=1e-9)
    assert abs(ref.max_pressure / homog.max_pressure - 1) > 0.05  # the layer changed the answer


def test_homogeneous_outputs_keep_their_keys() -> None:
    res = invoke(*BASE, "--skin-modulus", "1MPa")
    assert res.exit_code == 0, res.output
    assert not any(k.startswith("skin_layer") for k in json.loads(res.stdout)["inputs"]["materials"])


@pytest.mark.parametrize(("extra", "message"), [
    (LAYER[:4], "--skin-substrate-modulus missing"),
    ([*LAYER, "--modulus", "1MPa"], "either --modulus"),
    ([*LAYER, "--skin-modulus", "1MPa"], "either --skin-modulus"),
    ([*LAYER[:1], "-2um", *LAYER[2:]], "--skin-layer-thickness: must lie in (0 m, 10 mm]"),
    ([*LAYER[:1], "2", *LAYER[2:]], "has no unit"),
    ([*LAYER[:5], "soft"], "--skin-substrate-modulus"),
    ([*LAYER, "--skin-base", "rigid"], "would be ignored"),
    ([*LAYER[:4], "--skin-substrate-modulus", "rigid", "--skin-base", "elastic"], "contradicts"),
    ([*LAYER[:4], "--skin-base", "rigid", "--skin-substrate-poisson", "0.3"], "needs an elastic substrate"),
    ([*LAYER, "--skin-substrate-poisson", "0.7"], "--skin-substrate-poisson"),
    ([*LAYER, "--skin-base", "glued"], "--skin-base must be one of"),
    (["--skin-base", "rigid", "--skin-modulus", "1MPa"], "--skin-layer-thickness, --skin-layer-modulus missing"),
])
def test_layered_option_mistakes_are_one_line(extra: list[str], message: str) -> None:
    res = invoke(*BASE, *extra)
    assert res.exit_code == 2
    lines = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error:") and message in lines[0], res.stderr


@pytest.mark.parametrize(("extra", "layer"), [
    (["--skin-substrate-modulus", "100kPa", "--skin-substrate-poisson", "0.3"], Layer(20e-6, 1e6, 0.45, 1e5, 0.3)),
    (["--skin-base", "rigid"], Layer(20e-6, 1e6, 0.45, math.inf, 0.45)),
    (["--skin-base", "rigid-frictionless"], Layer(20e-6, 1e6, 0.45, math.inf, 0.45, "frictionless")),
])
def test_substrate_poisson_and_base_reach_the_solver(extra: list[str], layer: Layer) -> None:
    """--skin-substrate-poisson and --skin-base, as predict has them: each changes the answer as
    the library's Layer does, and the JSON names them."""
    res = invoke(*BASE, *LAYER[:4], *extra, "--skin-poisson", "0.45")
    assert res.exit_code == 0, res.output
    doc = json.loads(res.stdout)
    ref = library(layer, reduced_modulus(1e6, 0.45))
    got = doc["results"][0]
    assert got["contact_fraction"] == ref.contact_fraction
    assert got["max_pressure"] == pytest.approx(ref.max_pressure, rel=1e-9)
    materials = doc["inputs"]["materials"]
    assert materials["skin_substrate_poisson"] == layer.substrate_poisson
    assert materials["skin_base"] == ("elastic" if not layer.rigid_base else
                                      "rigid-frictionless" if layer.base == "frictionless" else "rigid")
    # against the default substrate (elastic, nu2 = nu1, bonded): each option moves the answer
    default = library(Layer(20e-6, 1e6, 0.45, 1e5, 0.45), reduced_modulus(1e6, 0.45))
    assert abs(ref.max_pressure / default.max_pressure - 1) > 1e-4
