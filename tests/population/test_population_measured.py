"""A population from measurements (issue 22): the participants of a `fingerpad analyse` folder of
simulated participants (known E_s) are the members, with exactly their fitted values."""

from __future__ import annotations

import csv
import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from fingerpad.errors import FingerpadError
from fingerpad.population import load_population

from .test_population_cli import _user_error, invoke

CAPS = ["--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "100um",
        "--lattice", "hexagonal", "--model", "hertz", "--loads", "0.1N:4N:5"]


@pytest.fixture(scope="module")
def panel(tmp_path_factory):
    """Three simulated participants (Hertz micro-model, known E_s) and their analysis (a few s)."""
    root = tmp_path_factory.mktemp("panel")
    sim, res = root / "sim", root / "res"
    out = invoke("simulate-measurement", "--out", sim, "--seed", 3, "--participants", 3, "--repetitions", 2,
                 "--strokes", 10, "--micro-model", "hertz")
    assert out.exit_code == 0, out.stderr
    out = invoke("analyse", sim, "--reference", "flat", "--out", res, "--no-figures", "--no-sensitivity")
    assert out.exit_code == 0, out.stderr
    truth = json.loads((sim / "truth.json").read_text())["participants"]
    with open(res / "participants.csv", newline="") as fh:
        fitted = {r["participant"]: r for r in csv.DictReader(fh)}
    return sim, res, truth, fitted


def test_participants_are_the_members(panel):
    """One member per participant, its fitted E_s exactly (no resampling), and the fitted values
    are those of the known participants: the simulated E_s lies inside each participant's 95 %
    set, the accuracy the analysis states (docs/measurements.md)."""
    _, res, truth, fitted = panel
    pop = load_population(res)
    assert pop.labels == ("P01", "P02", "P03") and pop.size == 3 and pop.method == "measured"
    members = pop.sample()
    assert members == pop.sample()  # the same members every time
    for who, member in zip(pop.labels, members, strict=True):
        assert set(member) == {"skin_modulus"}
        assert member["skin_modulus"] == float(fitted[who]["skin_modulus"])
        lo, hi = float(fitted[who]["skin_modulus_ci_low"]), float(fitted[who]["skin_modulus_ci_high"])
        assert lo < truth[who]["skin_modulus"] < hi
        assert member["skin_modulus"] == pytest.approx(truth[who]["skin_modulus"], rel=0.3)
    assert "analyse fits no friction parameter" in pop.notes[0]


def test_predict_with_an_analyse_folder(panel, tmp_path):
    """`predict --population RESULTS_DIR`: the JSON's members are the participants, a member
    reproduces by a plain predict, and the CSV tables hold the same numbers."""
    _, res, _, fitted = panel
    out = invoke("predict", *CAPS, "--population", res, "--out", tmp_path / "o")
    assert out.exit_code == 0, out.stderr
    assert "3 participants as members" in out.stderr
    doc = json.loads((tmp_path / "o" / "predict.json").read_text())["population"]
    assert doc["labels"] == ["P01", "P02", "P03"] and doc["method"] == "measured"
    assert [m["skin_modulus"] for m in doc["members"]] == [float(fitted[p]["skin_modulus"]) for p in doc["labels"]]
    plain = invoke("predict", *CAPS, f"--finger-param=skin_modulus={doc['members'][1]['skin_modulus']!r}",
                   "--json", "-")
    rows = json.loads(plain.stdout)["results"]
    np.testing.assert_array_equal(doc["member_results"][1]["mu"], [r["mu"] for r in rows])
    with open(tmp_path / "o" / "population_members.csv", newline="") as fh:
        table = list(csv.DictReader(fh))
    assert [r["participant"] for r in table] == doc["labels"]
    assert [float(r["skin_modulus_Pa"]) for r in table] == [m["skin_modulus"] for m in doc["members"]]


def test_fitted_columns_named_as_parameters_are_used(panel, tmp_path):
    """A participants table with a column named as a population parameter (a friction parameter
    fitted elsewhere) gives it to each member; one with none usable is refused."""
    _, res, _, _ = panel
    copy = tmp_path / "res"
    shutil.copytree(res, copy)
    with open(copy / "participants.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    for i, row in enumerate(rows):
        row["tau0"] = 6000.0 + 1000 * i
    _write(copy / "participants.csv", rows)
    members = load_population(copy).sample()
    assert [m["tau0"] for m in members] == [6000.0, 7000.0, 8000.0]
    for row in rows:
        row["skin_modulus_determined"] = "False"
    _write(copy / "participants.csv", rows)
    with pytest.raises(FingerpadError, match="no participant with a fitted E_s.*P01 .E_s not determined"):
        load_population(copy)


def _copy(panel, tmp_path: Path) -> tuple[Path, list[dict]]:
    """A copy of the panel's analyse folder and the rows of its participants.csv."""
    copy = tmp_path / "res"
    shutil.copytree(panel[1], copy)
    with open(copy / "participants.csv", newline="") as fh:
        return copy, list(csv.DictReader(fh))


def _write(path: Path, rows: list[dict]) -> None:
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def test_folders_that_are_not_an_analysis_are_refused(panel, tmp_path):
    sim, res, _, _ = panel
    assert "not a folder written by fingerpad analyse" in _user_error(
        invoke("predict", *CAPS, "--population", sim, "--out", tmp_path / "o"))
    pred = tmp_path / "pred"
    assert invoke("predict", *CAPS, "--out", pred).exit_code == 0
    assert "a predict output" in _user_error(invoke("predict", *CAPS, "--population", pred, "--out", tmp_path / "o"))
    (tmp_path / "empty").mkdir()
    assert "not a folder written by fingerpad analyse" in _user_error(
        invoke("predict", *CAPS, "--population", tmp_path / "empty", "--out", tmp_path / "o"))
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("summary", ["[]", '{"study": "x"}', '"text"', "{"])
def test_a_tampered_summary_is_one_error_line(panel, tmp_path, summary):
    """Issue 30, defect 8: `[]` or `{"study": "x"}` as summary.json gave an AttributeError traceback."""
    _, res, _, _ = panel
    copy = tmp_path / "res"
    shutil.copytree(res, copy)
    (copy / "summary.json").write_text(summary)
    line = _user_error(invoke("predict", *CAPS, "--population", copy, "--out", tmp_path / "o"))
    assert "summary.json" in line or "cannot read the analysis" in line
    assert not (tmp_path / "o").exists()


def test_unknown_and_unreadable_columns_are_named(panel, tmp_path):
    """Issue 30, defect 11: a column that is no population parameter (a misspelt `tau_0`) was left
    out without a word, and text in a parameter's column read as "not fitted"."""
    copy, rows = _copy(panel, tmp_path)
    for row in rows:
        row["tau_0"] = 6000.0
    _write(copy / "participants.csv", rows)
    pop = load_population(copy)
    assert any("column(s) tau_0 are neither population parameters" in n for n in pop.notes)
    assert not any("ref_k" in n or "n_strokes" in n for n in pop.notes[1:])  # analyse's own columns are not named
    rows[1]["tau0"] = "8 kPa?"
    for row in rows[:1] + rows[2:]:
        row["tau0"] = 8000.0
    _write(copy / "participants.csv", rows)
    with pytest.raises(FingerpadError, match="participant P02 tau0: '8 kPa\\?' is not a number"):
        load_population(copy)


def test_implausible_participants_are_warned_about(panel, tmp_path):
    """Issue 30, defect 10: E_s 1e30 Pa and 5 m pads from participants.csv passed without a word."""
    from fingerpad.plausibility import PlausibilityWarning
    from fingerpad.population import attach
    from fingerpad.study.spec import study_from_dict

    copy, rows = _copy(panel, tmp_path)
    for row in rows:
        row["radius"] = 5.0
    rows[0]["skin_modulus"] = 1e30
    _write(copy / "participants.csv", rows)
    study = study_from_dict({"texture": {"name": "caps", "radius": "50um", "height": "10um", "spacing": "100um"},
                             "model": {"kind": "hertz"}})
    with pytest.warns(PlausibilityWarning) as caught:
        attach(study, str(copy))
    text = " ".join(str(w.message) for w in caught)
    assert "radius: 3 of 3 values lie outside the plausible" in text and "pad radius" in text
    assert "skin_modulus: 1 of 3 values lie outside" in text
