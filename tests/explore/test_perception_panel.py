"""The explorer's perception section (issue 32): the numbers of ``against_flat`` on the design shown,
the library's messages for bad fields."""

from __future__ import annotations

import re

import numpy as np
import pytest

pytest.importorskip("panel")

from .test_inplace import _drain, _run_page  # noqa: E402


def test_the_section_shows_the_library_numbers(tmp_path):
    from fingerpad.explore.app import ExplorerApp, ServerState
    from fingerpad.explore.inputs import data_key
    from fingerpad.perception.compare import against_flat

    async def main() -> None:
        app = ExplorerApp(ServerState(upload_dir=str(tmp_path)))
        view = app.single
        {f.fid: f for f in view.form.all_fields()}["model.kind"].widget.value = "hertz"
        await _drain()
        body = view.perception.body.object
        assert view.pred is not None and "fp-perception-table" in body
        want = against_flat(view.pred, speeds=(0.02, 0.1), weber=0.11, amplitudes=False)
        # the forced-choice P of the loads shown, in the table's data-value attributes
        loads = [float(v) for v in re.findall(r'data-key="load" data-value="([^"]+)"', body)]
        shown = [float(v) for v in re.findall(r'data-key="p" data-value="([^"]+)"', body)]
        index = [list(want.loads).index(f) for f in loads]
        assert 2 <= len(index) <= 8 and index[0] == 0 and index[-1] == len(want.loads) - 1
        np.testing.assert_array_equal(shown, want.summary()["p_correct_median"][index])
        # f = v / lambda along x of the hexagonal caps (spacing 175 um) at 20 mm/s
        f = float(re.search(r'data-key="perception_f_0_1_20" data-value="([^"]+)"', body).group(1))
        assert f == pytest.approx(0.02 / 175e-6)
        view.perception.speed.value = "50mm/s"
        await _drain()
        assert 'data-key="perception_f_0_1_50"' in view.perception.body.object
        # with a population shown for this design: the fraction of its fingers
        view.population.choice.value = "adults"
        await _drain()
        pop = view.population.result
        assert pop is not None and view.population.result_key[0] == data_key(view.shown_data)
        # adults draws each finger's W: the field left empty takes the members' own
        want = against_flat(view.pred, pop, speeds=(0.05,), amplitudes=False)
        assert np.array_equal(want.weber, [m["weber_fraction"] for m in pop.members])
        body = view.perception.body.object
        fractions = [float(v) for v in re.findall(r'data-key="tell" data-value="([^"]+)"', body)]
        np.testing.assert_array_equal(fractions, want.summary()["fraction"][index])
        assert "1000 fingers of adults" in body
        # a W typed beside it: the population's rule, named by the field, and no stale verdicts
        view.perception.weber.value = "0.2"
        await _drain()
        message = view.perception.message.object
        assert "Weber fraction W: the population &#x27;adults&#x27; draws weber_fraction" in message, message
        assert view.perception.result is None and view.perception.body.object == ""
        view.perception.weber.value = "0"
        await _drain()
        assert "Weber fraction" in view.perception.message.object and "fp-error" in view.perception.message.object

    _run_page(main)


def test_the_exported_study_holds_the_weber_fraction_typed_in(tmp_path):
    """The study TOML export carries the W of the perception section ([perception] weber_fraction),
    so that the file reproduces the verdicts shown; an empty or refused field exports none."""
    import tomllib

    from fingerpad.explore.app import ExplorerApp, ServerState
    from fingerpad.explore.views.exports import study_toml
    from fingerpad.study.spec import study_from_dict

    async def main() -> None:
        app = ExplorerApp(ServerState(upload_dir=str(tmp_path)))
        view = app.single
        {f.fid: f for f in view.form.all_fields()}["model.kind"].widget.value = "hertz"
        await _drain()
        assert "perception" not in tomllib.loads(study_toml(view))
        view.perception.weber.value = "0.2"
        await _drain()
        data = tomllib.loads(study_toml(view))
        assert data["perception"] == {"weber_fraction": 0.2}
        assert study_from_dict(data).weber == 0.2
        assert float(re.search(r'data-key="perception_weber" data-value="([^"]+)"',
                               view.perception.body.object).group(1)) == 0.2  # what the section shows
        view.perception.weber.value = "-1"
        await _drain()
        assert "perception" not in tomllib.loads(study_toml(view))

    _run_page(main)
