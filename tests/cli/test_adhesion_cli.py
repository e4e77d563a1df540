"""Adhesion at the command line: ``solve``, ``predict`` and ``sweep`` with ``--work-of-adhesion``.

* w = 0 (or no flag) is the non-adhesive prediction to the bit, its outputs without a key more;
* solve prints per pressure the contact fraction, mean gap and converged flag, and the pull-off
  pressure; tensions beyond it lift the skin off (a result, exit 0);
* predict reports the pull-off force, the adhesive share of A_re per load and the threshold load;
* bad adhesion input is one ``error:`` line, exit 2, at every door.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from fingerpad.cli import app

runner = CliRunner()

CAPS = ["--texture", "caps", "--radius", "100um", "--height", "20um", "--spacing", "175um", "--lattice",
        "hexagonal", "--grid", "32"]
MATERIAL = ["--material-modulus", "0.5GPa", "--material-poisson", "0.4"]


def invoke(*args: str):
    return runner.invoke(app, [str(a) for a in args])


def one_error(result) -> str:
    assert result.exit_code == 2, (result.exit_code, result.output)
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr
    assert "Traceback" not in result.output
    return lines[0]


def test_solve_prints_the_loading_branch_and_the_pull_off() -> None:
    result = invoke("solve", *CAPS, *MATERIAL, "--work-of-adhesion", "0.05J/m2",
                    "--pressure", "-2kPa,0Pa,5kPa", "--json", "-")
    assert result.exit_code == 0, result.output
    payload = json.loads(result.stdout)
    rows = payload["results"]
    assert [r["mean_pressure"] for r in rows] == [-2000.0, 0.0, 5000.0]  # in the order given
    for row in rows:
        assert {"contact_fraction", "mean_gap", "converged", "law", "work_of_adhesion"} <= set(row)
    # adhesion holds a contact at zero load; -2 kPa is beyond the pull-off: the skin lifts off
    assert rows[1]["contact_fraction"] > 0 and rows[1]["converged"]
    assert rows[0]["contact_state"] == "detached" and rows[0]["contact_fraction"] == 0
    assert rows[0]["mean_gap"] is None
    assert -2000.0 < payload["pull_off_pressure"] < 0
    assert payload["adhesion"]["range_regularised"] is True
    assert payload["inputs"]["adhesion"] == {"work_of_adhesion": 0.05, "adhesion_range": 3e-10,
                                             "adhesion_law": "exponential"}


def test_solve_table_says_the_pull_off_and_the_lift_off() -> None:
    result = invoke("solve", *CAPS, *MATERIAL, "--work-of-adhesion", "50mJ/m2", "--adhesion-law", "maugis",
                    "--pressure", "-2kPa", "--pressure", "1kPa")
    assert result.exit_code == 0, result.output
    assert "pull-off pressure:" in result.stdout
    assert "lifts off" in result.stderr


@pytest.mark.parametrize(("args", "message"), [
    (["--pressure", "-1kPa"], "zero and tensions need --work-of-adhesion"),
    (["--pressure", "1kPa", "--adhesion-law", "sticky", "--work-of-adhesion", "0.1J/m2"],
     "--adhesion-law: must be one of exponential, maugis"),
    (["--pressure", "1kPa", "--adhesion-range", "1nm"], "--adhesion-range needs a positive --work-of-adhesion"),
    (["--pressure", "1kPa", "--work-of-adhesion", "5um"], "is a length, expected a surface energy"),
    (["--pressure", "1kPa", "--work-of-adhesion", "-0.1J/m2"], "--work-of-adhesion: must lie in"),
    (["--pressure", "1kPa", "--work-of-adhesion", "0.1J/m2", "--adhesion-range", "2"], "has no unit"),
    (["--pressure", "1kPa", "--work-of-adhesion", "0.1J/m2", "--critical", "1e-3"], "--critical is not available"),
])
def test_solve_refuses_bad_adhesion(args: list[str], message: str) -> None:
    assert message in one_error(invoke("solve", *CAPS, *MATERIAL, *args))


def test_predict_without_adhesion_is_unchanged(tmp_path) -> None:
    base = ["predict", *CAPS, *MATERIAL, "--loads", "0.2N:2N:4", "--model", "bem", "--cache", str(tmp_path),
            "--json", "-"]
    plain = json.loads(invoke(*base).stdout)
    zero = json.loads(invoke(*base, "--work-of-adhesion", "0J/m2").stdout)
    for doc in (plain, zero):
        doc.pop("timings")
        doc["cell"].pop("seconds")
        doc["cell"].pop("solves")
        doc["cell"].pop("cached")
        doc["cell"]["resolution"].pop("solves")
    assert zero == plain  # the same numbers to the bit, not a key more
    assert "adhesion" not in plain and "adhesive_share" not in plain["results"][0]


def test_solve_without_adhesion_is_unchanged() -> None:
    base = ["solve", *CAPS, *MATERIAL, "--pressure", "1kPa:30kPa:3", "--json", "-"]
    plain = json.loads(invoke(*base).stdout)
    zero = json.loads(invoke(*base, "--work-of-adhesion", "0J/m2").stdout)
    for doc in (plain, zero):
        doc.pop("timings", None)
        for row in doc["results"]:
            row.pop("seconds")
    assert zero == plain  # the same numbers to the bit, not a key more
    assert "pull_off_pressure" not in plain and "adhesion" not in plain["results"][0]


def test_predict_reports_pull_off_share_and_threshold(tmp_path) -> None:
    base = ["predict", *CAPS, *MATERIAL, "--loads", "0.05N:2N:4", "--model", "bem", "--cache", str(tmp_path)]
    plain = json.loads(invoke(*base, "--json", "-").stdout)
    result = invoke(*base, "--work-of-adhesion", "0.3J/m2", "--json", "-")
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    adh = doc["adhesion"]
    assert adh["pull_off_force"] > 0 and adh["pad_work_of_adhesion"] > 0
    assert adh["pull_off_force"] == pytest.approx(1.5 * 3.141592653589793 * adh["pad_work_of_adhesion"] * 9e-3)
    assert adh["threshold_load_bound"] in ("exact", "at least", "at most") and adh["threshold_load"] > 0
    for row, ref in zip(doc["results"], plain["results"], strict=True):
        # adhesion enlarges the real contact and raises the friction at a given load
        assert row["real_area"] > ref["real_area"] and row["mu"] > ref["mu"]
        # the same cell, prepared over the threshold search's loads too: more nodes, the same curve
        # to within its interpolation error
        assert row["real_area_without_adhesion"] == pytest.approx(ref["real_area"], rel=1e-4)
        assert 0 < row["adhesive_share"] < 1
    assert doc["inputs"]["finger"]["work_of_adhesion"] == 0.3
    assert doc["units"]["pull_off_force"] == "N"
    # every number carries its grid estimate, as without adhesion: the state pressures against
    # the half grid, the loads they give through the adhesive pad, the pull-off force from the
    # cell's work of separation. On grid 32 the jump goes into full contact (on 16 it does not):
    # full contact, which cannot precede the transition, is reported with the extrapolated
    # transition and its estimate (docs/model.md 6.6)
    full = doc["state_brackets"]["full"]
    assert full["grid"] == [32, 56] and full["coarse_grid"] == [16, 28]
    assert doc["cell"]["full_contact_pressure"] == doc["cell"]["transition_pressure"]
    assert full["pressure_error"] == doc["state_brackets"]["transition"]["pressure_error"]
    assert doc["full_contact_load_error"]["bem"] == full["load_error"] and full["load_error"] > 0
    assert doc["cell"]["resolution"]["full_contact_pressure_error"] == full["pressure_error"]
    assert 0 < adh["pull_off_force_error"] < 1 and doc["units"]["pull_off_force_error"].startswith("1 ")
    # at w 0.3 the caps' contacts pull the skin onto the base from ~3 ranges (docs/model.md 6.6):
    # the transition is reported extrapolated to a vanishing pixel, p_N + (p_N - p_{N/2}), the
    # critical load with it; the grid's own pressure beside it, the middle of its own bracket
    tr = doc["state_brackets"]["transition"]
    own = tr["own_pressure"]
    assert own == pytest.approx(math.sqrt(tr["pressure"][0] * tr["pressure"][1]), rel=1e-9)
    assert doc["cell"]["transition_pressure"] > own and tr["method"].startswith("the skin was pulled onto the base")
    assert tr["pressure_error"] == pytest.approx(abs(doc["cell"]["transition_pressure"] / tr["coarse_pressure"] - 1),
                                                 rel=1e-9)


def test_predict_where_adhesion_alone_reaches_the_transition(tmp_path) -> None:
    """On a coarse grid w 0.3 J/m^2 brings the skin onto the base at no load: the transition's
    bracket is [0, 0] and the critical load 0 (documented), not a division by zero (it was a
    ZeroDivisionError traceback in the bracket's relative width)."""
    args = ["predict", *CAPS[:-1], "8", *MATERIAL, "--loads", "0.5N", "--model", "bem", "--cache", str(tmp_path),
            "--work-of-adhesion", "0.3J/m2", "--json", "-"]
    result = invoke(*args)
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    tr = doc["state_brackets"]["transition"]
    assert tr["pressure"] == [0.0, 0.0] and tr["relative_width"] is None
    assert doc["critical_load"]["bem"] == 0.0


def test_predict_table_and_errors(tmp_path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)  # its refusals use the default --out, which make run's out/ must not meet
    base = ["predict", *CAPS, *MATERIAL, "--loads", "0.5N", "--model", "bem", "--cache", str(tmp_path)]
    result = invoke(*base, "--work-of-adhesion", "0.05J/m2", "--out", str(tmp_path / "out"))
    assert result.exit_code == 0, result.output
    assert "pull-off force" in result.stdout
    assert "--adhesion-law: must be one of" in one_error(invoke(*base, "--adhesion-law", "glue"))
    assert "directional friction (--direction) with a work of adhesion" in one_error(
        invoke(*base, "--work-of-adhesion", "0.05J/m2", "--direction", "0"))
    # a population with adhesion is read from one family in w / (E* Lx): a layered skin is refused
    assert "a population of adhesive fingers with a layered skin" in one_error(
        invoke(*base, "--finger", "layered", "--work-of-adhesion", "0.05J/m2", "--population", "adults"))


def test_predict_on_a_flat_surface_with_adhesion(tmp_path) -> None:
    """A flat cell holds any tension (its pull-off pressure -inf, null in the JSON): the terminal
    says so instead of a traceback, and the pad adheres with the ridge fraction times w."""
    base = ["predict", "--texture", "flat", "--size", "100um", *MATERIAL, "--loads", "0.1N", "--model", "bem",
            "--cache", str(tmp_path), "--work-of-adhesion", "0.05J/m2"]
    result = invoke(*base, "--out", str(tmp_path / "out"))
    assert result.exit_code == 0, result.output
    assert "cell pull-off none (a flat cell)" in " ".join(result.stdout.split())
    adh = json.loads((tmp_path / "out" / "predict.json").read_text())["adhesion"]
    assert adh["pull_off_pressure"] is None and adh["work_of_separation"] == 0.05
    assert adh["pad_work_of_adhesion"] == pytest.approx(0.5 * 0.05)  # the default finger's ridge fraction


def test_sweep_checks_the_adhesion_flags(tmp_path) -> None:
    study = tmp_path / "s.toml"
    study.write_text('[texture]\nname = "caps"\nradius = "100um"\nheight = "20um"\nspacing = "175um"\n'
                     '[model]\ngrid = 32\n[sweep]\nspacing = ["150um", "200um"]\n')
    assert "--work-of-adhesion" in one_error(invoke("sweep", str(study), "--work-of-adhesion", "0.1um",
                                                    "--out", str(tmp_path / "r.zarr")))


@pytest.mark.slow  # an adhesive cell inside a sweep worker: ~15 s on 2 cores
def test_sweep_axis_of_the_work_of_adhesion(tmp_path) -> None:
    pytest.importorskip("zarr")
    xr = pytest.importorskip("xarray")
    study = tmp_path / "s.toml"
    study.write_text('[texture]\nname = "caps"\nradius = "100um"\nheight = "20um"\nspacing = "175um"\n'
                     'lattice = "hexagonal"\n[material]\nmodulus = "0.5GPa"\npoisson = 0.4\n'
                     '[model]\nkind = "bem"\ngrid = 32\n[sweep]\nloads = "0.1N:1N:3"\n'
                     '[sweep.axes]\nwork_of_adhesion = ["0J/m2", "0.05J/m2"]\n')
    store = tmp_path / "r.zarr"
    result = invoke("sweep", str(study), "--out", str(store), "--workers", "1")
    assert result.exit_code == 0, result.output
    data = xr.open_zarr(store)
    assert list(data["work_of_adhesion"].values) == [0.0, 0.05]
    assert data["work_of_adhesion"].attrs["units"] == "J/m2"
    mu = data["mu"].values
    assert np.all(np.isfinite(mu)) and np.all(mu[1] > mu[0])  # adhesion raises friction at every load
    # the w = 0 point is the plain prediction of the same finger and cell
    plain = json.loads(invoke("predict", *CAPS, *MATERIAL, "--loads", "0.1N:1N:3", "--model", "bem",
                              "--cache", str(tmp_path / "c"), "--json", "-").stdout)
    assert mu[0].tolist() == pytest.approx([r["mu"] for r in plain["results"]], rel=1e-12)


def test_every_error_estimate_beyond_100_percent_reads_gt_100():
    """The terminal's per-cent estimates share one rule: two digits, or '>100' (a population's
    pull-off estimate printed '3.5e+03 %' while predict's own line said '>100 %')."""
    from fingerpad.cli.predict import _percent, _plus_minus
    from fingerpad.units import format_percent

    assert [_percent(e) for e in (0.0123, 0.5, 0.996, 1.0, 1.73, 35.0)] == ["1.2", "50", "100", "100", ">100", ">100"]
    assert [_percent(e) for e in (0.0123, 1.1)] == [format_percent(e) for e in (0.0123, 1.1)]
    assert _plus_minus(35.0) == " ± >100 %" and _plus_minus(0.059) == " ± 5.9 %" and _plus_minus(None) == ""
