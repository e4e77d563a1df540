"""The worked example of docs/measurements.md runs as documented."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from fingerpad import measure as m

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "measurements"


@pytest.mark.skipif(not EXAMPLE.is_dir(), reason="examples/measurements not in this checkout")
def test_example_study_as_documented():
    truth = json.loads((EXAMPLE / "truth.json").read_text())
    recordings = m.load_study([EXAMPLE])
    assert len(recordings) == 12
    p03 = [r for r in recordings if r.participant == "P03"]
    assert p03 and all(r.session for r in recordings)  # decimal-comma gf files read like the rest
    result = m.analyse_study(recordings, m.AnalysisOptions(reference="flat", n_null=199),
                             textures=m.read_textures(EXAMPLE / "samples.csv"))
    parts = result.participants.set_index("participant")
    for pid, tr in truth["participants"].items():
        assert parts.loc[pid, "ref_k"] == pytest.approx(tr["k"], rel=0.1)
        lo, hi = parts.loc[pid, "skin_modulus_ci_low"], parts.loc[pid, "skin_modulus_ci_high"]
        assert lo < tr["skin_modulus"] < hi
        assert parts.loc[pid, "skin_modulus_model"] == "bem" and parts.loc[pid, "skin_modulus_other_model"] == "hertz"
    spread = result.spread_summary.set_index("sample")
    assert spread.loc["bumps", "cv_norm"] < spread.loc["bumps", "cv_raw"]
