"""The README's directional example end to end (issue 31): the ramps reach the shear the
coupling needs (no gain held at any load), docs/deflection.md quotes the line the command
prints, and a finger modulus 1e-6 apart (pad-centre pressures 1e-6 apart) gives the same ratios.
Slow: two cold runs of the command (~1 min of CPU each on 2 cores)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from fingerpad.cli import app

ROOT = Path(__file__).resolve().parents[2]
README = ["predict", "--texture", "ellipsoids", "--semi-axis-x", "45um", "--semi-axis-y", "135um", "--height", "90um",
          "--spacing-x", "300um", "--spacing-y", "300um", "--material-modulus", "0.3MPa", "--material-poisson", "0.49",
          "--direction", "0"]

runner = CliRunner()


def _run(tmp_path: Path, name: str, *extra: str):
    out = tmp_path / name
    res = runner.invoke(app, [*README, *extra, "--cache", str(tmp_path / f"cache-{name}"), "--out", str(out)],
                        env={"COLUMNS": "200"})
    assert res.exit_code == 0, res.stderr
    return res.stdout, json.loads((out / "predict.json").read_text())


def _coupling_table(page: str) -> list[dict[str, str]]:
    """The rows of docs/deflection.md's "Through the coupling" table, by column name."""
    lines = page[page.index("**Through the coupling**"):].splitlines()
    start = next(i for i, ln in enumerate(lines) if ln.startswith("| F (N) |"))
    head = [c.strip() for c in lines[start].strip("|").split("|")]
    rows = []
    for ln in lines[start + 2:]:
        if not ln.startswith("|"):
            break
        rows.append(dict(zip(head, (c.strip() for c in ln.strip("|").split("|")), strict=True)))
    return rows


def test_the_coupling_table_is_read():
    """The slow test's reading of the docs' table (fast: no prediction)."""
    rows = _coupling_table((ROOT / "docs" / "deflection.md").read_text(encoding="utf-8"))
    assert [r["F (N)"] for r in rows] == ["0.1", "0.258", "0.663", "1.55", "4"]
    assert all(float(r["mu perp/par"]) == pytest.approx(float(r["mu perp"]) / float(r["mu par"]), abs=2e-3)
               for r in rows)


@pytest.mark.slow
def test_the_readme_directional_example(tmp_path):
    printed, doc = _run(tmp_path, "readme")
    line = next(ln for ln in printed.splitlines() if ln.startswith("directional friction:"))
    # the ramps reach the shear the coupling needs: no gain held at the pad centre at any load
    rows = doc["results"]
    assert not any(r["gain_held"] for r in rows)
    assert not any("gain is held" in n for n in doc["notes"])
    # docs/deflection.md quotes the printed line
    page = (ROOT / "docs" / "deflection.md").read_text(encoding="utf-8")
    assert line in " ".join(page.split()), f"docs/deflection.md does not quote: {line}"
    # ... and its table's friction columns are the command's numbers at those loads (predict.json)
    table = _coupling_table(page)
    assert len(table) == 5
    for row in table:
        (r,) = [r for r in rows if f"{r['load']:.3g}" == row["F (N)"]]
        assert row["mu perp"] == f"{r['mu_perpendicular']:.4f}", row["F (N)"]
        assert row["mu par"] == f"{r['mu_parallel']:.4f}", row["F (N)"]
        assert row["mu perp/par"] == f"{r['mu_perpendicular_over_parallel']:.3f}", row["F (N)"]
    ratios = [r["mu_perpendicular_over_parallel"] for r in rows]
    assert 1.1 < min(ratios) and max(ratios) < 1.3
    # a pad modulus 1e-6 apart moves every pad-centre pressure by ~1e-6: the same numbers
    _, near = _run(tmp_path, "near", "--finger-param", "modulus=40.00004kPa")
    close = [r["mu_perpendicular_over_parallel"] for r in near["results"]]
    assert close == pytest.approx(ratios, rel=1e-5)
