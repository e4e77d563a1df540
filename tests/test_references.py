"""How fingerpad is cited: the registry of publications, what each method declares, the
``references`` of the outputs, ``fingerpad cite`` and CITATION.cff."""

from __future__ import annotations

import json
import re
import warnings
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from typer.testing import CliRunner

from fingerpad import references as refs
from fingerpad.cli import app

ROOT = Path(__file__).resolve().parents[1]
THESIS_DOI = "10.3990/1.9789036551786"  # as printed in the thesis' colophon


def invoke(*args):
    return CliRunner().invoke(app, [str(a) for a in args])


def _declarations() -> dict[str, tuple[str, ...]]:
    """Every declaration of publications in the package: model classes, modules, the solver."""
    from fingerpad import friction
    from fingerpad.contact.solver import solver_references
    from fingerpad.macro import GROSS_MODELS
    from fingerpad.measure import analysis
    from fingerpad.meso import RIDGE_MODELS
    from fingerpad.micro.bem import BEMUnitCell
    from fingerpad.micro.deflection import gain
    from fingerpad.micro.hertz import HertzUnitCell
    from fingerpad.perception import discrimination, roughness, vibration
    from fingerpad.population import correlations as population_correlations
    from fingerpad.population.sobol import SensitivityResult

    from fingerpad.macro.jkr import JKRArea
    from fingerpad.micro.adhesive_cell import AdhesiveUnitCell
    from fingerpad.study.citations import solve_references
    from fingerpad.textures import spherical_caps

    found = {f"model {m.name}": tuple(m.factory.REFERENCES) for m in [*GROSS_MODELS.values(), *RIDGE_MODELS.values()]}
    cell = spherical_caps(radius=50e-6, height=10e-6, spacing=200e-6, grid=16)
    found["adhesive cell"] = AdhesiveUnitCell(cell, 4e5, work_of_adhesion=0.05, law="maugis", cache=False).REFERENCES
    found["JKR pad"] = JKRArea.REFERENCES
    found["adhesive solve"] = solve_references(cell, None, {"adhesion_law": "maugis"})
    found.update({name: tuple(obj.REFERENCES) for name, obj in (
        ("friction", friction), ("BEMUnitCell", BEMUnitCell), ("HertzUnitCell", HertzUnitCell),
        ("deflection", gain), ("correlations", population_correlations), ("sensitivity", SensitivityResult),
        ("analysis", analysis), ("discrimination", discrimination), ("vibration", vibration),
        ("roughness", roughness))})
    for periodic in (True, False):
        for layered in (True, False):
            found[f"solver {periodic} {layered}"] = solver_references(periodic, layered)
    return found


def test_every_declared_key_is_in_the_registry():
    """A method citing a key the registry lacks is caught here (ordered() raises on it)."""
    for where, keys in _declarations().items():
        assert [r.key for r in refs.ordered(keys)] == [k for k in refs.REFERENCES if k in keys], where
    with pytest.raises(KeyError, match="no-such-paper"):
        refs.ordered(["no-such-paper"])


def test_every_registry_entry_is_cited_by_a_method():
    """No dead entries: each publication is declared by some method (the thesis and the package
    by every run, the layered derivation by the solver, Westergaard by the sinusoidal ridges)."""
    declared = {k for keys in _declarations().values() for k in keys} | {refs.THESIS, refs.PACKAGE}
    unused = set(refs.REFERENCES) - declared
    assert not unused, unused


def test_registry_entries_are_complete():
    for key, ref in refs.REFERENCES.items():
        assert ref.key == key and ref.authors and ref.title and 1800 < ref.year < 2100 and ref.used_for, key
        if ref.doi:
            assert re.fullmatch(r"10\.\d{4,}/\S+", ref.doi), (key, ref.doi)
    assert refs.REFERENCES[refs.THESIS].doi == THESIS_DOI
    assert list(refs.REFERENCES)[:2] == [refs.THESIS, refs.PACKAGE]


def test_citation_and_bibtex_of_the_thesis():
    text = refs.citation(refs.THESIS)
    assert text == ("Sergachev, D. A. (2021). Surface engineering of tactile friction. PhD thesis, University of "
                    f"Twente, Enschede. doi:{THESIS_DOI}")
    bib = refs.bibtex([refs.THESIS, refs.PACKAGE])
    assert bib.count("@") == 2 and "@phdthesis{sergachev2021," in bib and "@misc{fingerpad," in bib
    assert f"doi = {{{THESIS_DOI}}}" in bib
    assert "author = {{The fingerpad developers}}" in bib  # a body, not a person's name
    assert bib.count("{") == bib.count("}")


def test_keys_of_puts_thesis_and_package_first_and_dedupes():
    from fingerpad.micro.hertz import HertzUnitCell
    from fingerpad.perception import discrimination, roughness, vibration

    assert refs.keys_of(HertzUnitCell, "johnson1985", None, ("polonsky1999",)) == (
        "sergachev2021", "fingerpad", "johnson1985", "polonsky1999")


def test_models_cite_what_they_rest_on():
    from fingerpad import Finger
    from fingerpad.coupling import model_references
    from fingerpad.macro.dzidek import DzidekArea
    from fingerpad.meso.sinusoidal import SinusoidalRidges
    from fingerpad.micro.bem import BEMUnitCell

    plain = Finger()
    assert model_references(plain) == ("sergachev2021", "fingerpad", "johnson1985", "greenwood1958")
    finger = Finger(gross=DzidekArea(radius=plain.radius, modulus=plain.modulus, stiffening=5.0),
                    ridges=SinusoidalRidges(wavelength=450e-6, amplitude=50e-6, modulus=0.3e6))
    keys = model_references(finger, BEMUnitCell)
    assert {"dzidek2017", "westergaard1939", "polonsky1999"} <= set(keys)
    assert "johnson1985" in keys  # Dzidek's area is Hertz with a stiffened modulus
    layered = plain.with_overrides(skin="layered", skin_layer_thickness="300um", skin_layer_modulus="0.4MPa",
                                   skin_substrate_modulus="40kPa")
    assert "fingerpad-layered" in model_references(layered) and "fingerpad-layered" not in model_references(plain)


def test_solver_cites_love_only_on_a_map_and_the_layer_only_with_one():
    from fingerpad.study.citations import solve_references

    assert "love1929" not in solve_references(SimpleNamespace(periodic=True))
    assert "love1929" in solve_references(SimpleNamespace(periodic=False))
    assert "fingerpad-layered" in solve_references(SimpleNamespace(periodic=True), layer=object())


def test_prediction_outputs_list_the_references(prediction, tmp_path):
    """predict.json's ``references`` and predict.nc's CF ``references`` attribute: the model of
    the prediction fixture (default finger: Hertz pad, constant ridge fraction; BEM and Hertz
    cells), each once, the same in both files."""
    from fingerpad import netcdf
    from fingerpad.study.outputs import write_outputs

    write_outputs(prediction, tmp_path / "out", dpi=30)
    doc = json.loads((tmp_path / "out" / "predict.json").read_text())
    keys = [e["key"] for e in doc["references"]]
    assert keys == ["sergachev2021", "fingerpad", "johnson1985", "greenwood1958", "polonsky1999"]
    assert all(set(e) == {"key", "citation", "doi", "used_for"} for e in doc["references"])
    ds = netcdf.load_dataset(tmp_path / "out" / "predict.nc")
    assert ds.attrs["references"].splitlines() == [e["citation"] for e in doc["references"]]


def test_population_adds_its_methods(prediction):
    """A population result names its own methods (study/ imports nothing of population/): its
    correlated sampling and its Sobol indices, when it used them."""
    from fingerpad.population.distributions import Population
    from fingerpad.population.run import PopulationResult
    from fingerpad.population.sobol import SensitivityResult
    from fingerpad.study.citations import prediction_references

    def result(correlations: tuple, sensitivity: object) -> PopulationResult:
        pop = Population({}, size=1, correlations=correlations)
        return PopulationResult(prediction, pop, [], [], np.zeros(0), np.zeros(0), [], (0.5,),
                                sensitivity=sensitivity)

    bare = result((), None)
    assert bare.references() == () and prediction_references(prediction, bare) == prediction_references(prediction)
    full = result((("radius", "modulus", 0.3),), SensitivityResult)
    added = set(prediction_references(prediction, full)) - set(prediction_references(prediction))
    assert added == {"kruskal1958", "sobol2001", "saltelli2010", "jansen1999"}


def test_cite_prints_the_thesis_and_the_package():
    res = invoke("cite")
    assert res.exit_code == 0, res.output
    assert THESIS_DOI in res.stdout and "version" in res.stdout and "MIT" in res.stdout
    assert max(len(line) for line in res.stdout.splitlines()) <= 80
    bib = invoke("cite", "--bibtex")
    assert bib.exit_code == 0 and bib.stdout == refs.bibtex([refs.THESIS, refs.PACKAGE])
    every = invoke("cite", "--all")
    assert every.exit_code == 0
    assert every.stdout.count("used for:") == len(refs.REFERENCES)


def test_cite_an_output_prints_its_references(prediction, tmp_path):
    from fingerpad.study.outputs import prediction_json

    (tmp_path / "predict.json").write_text(json.dumps(prediction_json(prediction)))
    res = invoke("cite", tmp_path / "predict.json")
    assert res.exit_code == 0, res.output
    assert "Polonsky" in res.stdout and "Greenwood" in res.stdout and "Dzidek" not in res.stdout
    assert invoke("cite", tmp_path).stdout == res.stdout  # the folder holding it
    bib = invoke("cite", tmp_path / "predict.json", "--bibtex").stdout
    assert "@article{polonsky1999," in bib and "@article{dzidek2017," not in bib


def test_cite_refuses_a_file_without_references(tmp_path):
    (tmp_path / "x.json").write_text("{}")
    res = invoke("cite", tmp_path / "x.json")
    assert res.exit_code == 2 and res.stderr.startswith("error: ") and len(res.stderr.splitlines()) == 1
    assert invoke("cite", tmp_path / "x.json", "--all").exit_code == 2


def test_citation_cff_matches_the_package():
    text = (ROOT / "CITATION.cff").read_text(encoding="utf-8")
    from fingerpad import __version__

    assert re.search(rf"^version: {re.escape(__version__)}$", text, re.M)
    assert f"doi: {THESIS_DOI}" in text and "license: MIT" in text
    assert "preferred-citation:" in text and "Surface engineering of tactile friction" in text


def test_licence_is_mit():
    text = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert text.startswith("MIT License") and "Permission is hereby granted, free of charge" in text
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import tomllib

        project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert project["license"] == "MIT" and project["license-files"] == ["LICENSE"]
