"""Updates in place (issue 23): a figure given a new spec shows exactly what a fresh figure of
that spec shows, whatever series the new spec adds or drops; results remembered per design; the
population's bands (issue 22) from the library's quantiles, and only preset names accepted."""

from __future__ import annotations

import copy
import csv
import io
import json

import numpy as np
import pytest

pytest.importorskip("bokeh")

from fingerpad.errors import FingerpadError  # noqa: E402
from fingerpad.explore import builders  # noqa: E402
from fingerpad.explore.jobs import LRU, contact_at, run_data  # noqa: E402
from fingerpad.explore.render_bokeh import adds_models, bokeh_figure, figure_content, update_figure  # noqa: E402
from fingerpad.plotting.specs import spec_csv, spec_json  # noqa: E402
from fingerpad.study.spec import DEFAULT_STUDY  # noqa: E402


def _data(cache, kind="hertz", grid=None, **texture):
    data = copy.deepcopy(DEFAULT_STUDY)
    data["texture"].update(texture)
    data["model"] = {"kind": kind, "cache": str(cache)}
    if grid is not None:
        data["model"]["grid"] = grid
    data["loads"] = {"range": "0.1N:4N:12", "log": True}
    return data


@pytest.fixture(scope="module")
def preds(tmp_path_factory):
    """Predictions whose figures differ in their series: Hertz only, BEM and Hertz (a 32-point
    cell), a critical load inside and outside the loads (a reference line and a state band more
    or fewer), another zone load (other zone discs)."""
    cache = tmp_path_factory.mktemp("cells")
    hertz = run_data(_data(cache))
    both = run_data(_data(cache, "both", 32))
    sparse = run_data(_data(cache, spacing="400um"))  # transition at a small load
    dense = run_data(_data(cache, spacing="130um"))
    zoned = _data(cache)
    zoned["loads"]["zones_at"] = "0.2N"
    return [hertz, both, sparse, dense, run_data(zoned), hertz, both]


def _sequence(preds, make):
    return [make(p) for p in preds]


@pytest.mark.parametrize("key", ["areas", "friction", "friction-normalised", "zones", "zone-profile", "psi",
                                 "height-map"])
def test_an_update_in_place_shows_what_a_fresh_figure_shows(preds, key):
    if key == "psi":
        specs = _sequence(preds, lambda p: builders.psi_spec(p, 2e3))
    elif key == "height-map":
        specs = _sequence(preds, lambda p: builders.height_map_spec(p.texture))
    else:
        specs = _sequence(preds, lambda p: builders.prediction_panels(p)[key])
    drawn = bokeh_figure(specs[0])
    assert figure_content(drawn) == figure_content(bokeh_figure(specs[0]))
    in_place = 0
    for spec in specs[1:]:
        grew = adds_models(drawn, spec)
        if update_figure(drawn, spec):
            in_place += 1
        else:
            assert grew  # a new frame always needs new models
            drawn = bokeh_figure(spec)
        assert figure_content(drawn) == figure_content(bokeh_figure(spec)), spec.key
    assert in_place == len(specs) - 1  # none of these changes needs a new figure


def test_series_come_and_go_in_place(preds):
    """Hertz only -> BEM and Hertz -> Hertz only: the areas figure gains the BEM's curve and its
    critical load, then hides them (no data left in them, not in the legend)."""
    hertz, both = preds[0], preds[1]
    first, second = builders.prediction_panels(hertz)["areas"], builders.prediction_panels(both)["areas"]
    drawn = bokeh_figure(first)
    assert adds_models(drawn, second) and update_figure(drawn, second)
    legend = [lbl for lbl, _ in figure_content(drawn)["legend"]]
    assert "real A_re (bem)" in legend and "real A_re (hertz)" in legend
    assert not adds_models(drawn, first) and update_figure(drawn, first)
    content = figure_content(drawn)
    assert "real A_re (bem)" not in [lbl for lbl, _ in content["legend"]]
    hidden = [r for r in drawn.figure.renderers if not r.visible]
    assert hidden and all(len(v) == 0 for r in hidden for v in r.data_source.data.values())
    assert not adds_models(drawn, second)  # the BEM's series are there to be shown again


def test_contact_maps_update_in_place_and_are_remembered(preds):
    pred = preds[1]
    cache = LRU(4)
    a = contact_at(pred.texture, pred.reduced_modulus, 5e3, cache=cache)
    assert contact_at(pred.texture, pred.reduced_modulus, 5e3, cache=cache) is a  # no second solve
    b = contact_at(pred.texture, pred.reduced_modulus, 9e3, cache=cache)
    assert b is not a and b.contact_fraction > a.contact_fraction
    for first, second in zip(builders.contact_specs(a), builders.contact_specs(b), strict=True):
        drawn = bokeh_figure(first)
        assert update_figure(drawn, second)
        assert figure_content(drawn) == figure_content(bokeh_figure(second))


def test_lru_keeps_the_last_ones():
    lru = LRU(2)
    for k in range(3):
        lru.put_key(k, str(k))
    assert lru.get_key(0) is None and lru.get_key(1) == "1" and lru.get_key(2) == "2" and len(lru) == 2


# ---------------------------------------------------------------------------------------------
# populations


@pytest.fixture(scope="module")
def population(tmp_path_factory):
    from fingerpad.explore.views.population import run_preset

    data = _data(tmp_path_factory.mktemp("cells"))
    return data, run_preset(data, "adults")


def test_population_bands_are_the_reported_quantiles(population):
    data, result = population
    specs = {s.key: s for s in builders.population_specs(result)}
    table = result.quantiles()
    loads = np.asarray(result.nominal.study.loads)
    for key, quantity in (("population-area-ratio", "area_ratio"), ("population-normalised", "mu_normalised")):
        spec = specs[key]
        outer, inner = spec.fills
        assert outer.name == "5-95 % of fingers" and inner.name == "25-75 % of fingers"
        np.testing.assert_array_equal(outer.lower, table[quantity]["0.05"])
        np.testing.assert_array_equal(outer.upper, table[quantity]["0.95"])
        np.testing.assert_array_equal(inner.lower, table[quantity]["0.25"])
        median = next(ln for ln in spec.lines if ln.name == "median")
        np.testing.assert_array_equal(median.y, table[quantity]["0.5"])
        np.testing.assert_array_equal(median.x, loads)
        assert np.all(outer.lower <= median.y) and np.all(median.y <= outer.upper)
        # the data downloads carry the bands (SI, one column per edge)
        rows = list(csv.reader(io.StringIO(spec_csv(spec))))
        col = rows[0].index(f"5-95 % of fingers upper [{spec.y.si_label}]")
        assert [float(r[col]) for r in rows[1:]] == pytest.approx(list(table[quantity]["0.95"]), rel=1e-15)
        assert json.loads(spec_json(spec))["bands"][0]["lower"] == pytest.approx(list(outer.lower), rel=1e-15)
        drawn = bokeh_figure(spec)
        assert figure_content(drawn) == figure_content(bokeh_figure(spec))
    crit = specs["population-critical-load"]
    (share,) = crit.lines
    finite = np.sort(result.critical_load[np.isfinite(result.critical_load)])
    np.testing.assert_array_equal(share.x, finite)
    assert share.y[-1] == pytest.approx(finite.size / len(result.members))  # the share of every finger
    median = [v for v in crit.vlines if v.label.startswith("50 %")]
    assert median and median[0].x == pytest.approx(table["critical_load"]["0.5"])


def test_population_images_draw_the_bands(population):
    pytest.importorskip("matplotlib")
    from fingerpad.plotting.render import figure

    spec = builders.population_specs(population[1])[0]
    ax = figure(spec).axes[0]
    assert len(ax.collections) == len(spec.fills)  # one fill_between per band
    assert {t.get_text() for t in ax.get_legend().get_texts()} >= {"median", "5-95 % of fingers"}


def test_only_preset_names_are_read(tmp_path, population):
    """``load_population`` also reads files: the page's choice must never reach it unless it is
    a preset's name (a file that exists and holds a valid population is refused too)."""
    from fingerpad.explore.views.population import population_choices, run_preset

    data = population[0]
    table = tmp_path / "pop.toml"
    table.write_text('[population]\nsize = 4\nskin_modulus = { distribution = "uniform", low = "0.2MPa", '
                     'high = "0.5MPa" }\n')
    for forged in (str(table), "/etc/passwd", "../adults", "Adults ", ""):
        with pytest.raises(FingerpadError, match="population: choose one of none, .*adults"):
            run_preset(data, forged)
    assert population_choices()[0] == "none" and "adults" in population_choices()


def test_the_servers_own_populations_are_chosen_by_label_only(tmp_path, population):
    """`fingerpad explore --population FILE`: the file is read once when the server starts and
    offered under its label; the page still cannot name a path (not even that file's)."""
    from fingerpad.explore.server import server_populations
    from fingerpad.explore.views.population import population_choices, run_preset
    from fingerpad.population import load_population, run_population
    from fingerpad.study.spec import study_from_dict
    from fingerpad.explore.inputs import labels_for

    data = population[0]
    table = tmp_path / "panel.toml"
    table.write_text('[population]\nsize = 4\nskin_modulus = { distribution = "uniform", low = "0.2MPa", '
                     'high = "0.5MPa" }\n')
    adults = tmp_path / "other.toml"  # a population named like a preset gets a label of its own
    adults.write_text(table.read_text().replace("[population]\n", '[population]\nname = "adults"\n'))
    extra = server_populations([str(table), str(adults), "adults"])
    assert list(extra) == ["panel.toml", "adults (2)"]
    assert population_choices(extra) == ["none", "adults", "adults-adhesive", "panel.toml", "adults (2)"]
    got = run_preset(data, "panel.toml", extra)
    want = run_population(study_from_dict(data, labels_for(data)), load_population(str(table)))
    np.testing.assert_array_equal(got.values("mu_normalised"), want.values("mu_normalised"))
    for forged in (str(table), "/etc/passwd", "panel.toml ", "panel"):
        with pytest.raises(FingerpadError, match="population: choose one of none, adults, adults-adhesive, panel"):
            run_preset(data, forged, extra)
    with pytest.raises(FingerpadError, match="neither a preset"):
        server_populations([str(tmp_path / "missing.toml")])


def test_explore_with_an_unreadable_population_is_one_error_line(tmp_path):
    from typer.testing import CliRunner

    from fingerpad.cli import app

    res = CliRunner().invoke(app, ["explore", "--no-browser", "--population", str(tmp_path / "missing.toml")])
    assert res.exit_code == 2
    lines = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: --population:"), res.stderr


def _drain():
    import asyncio

    async def drain() -> None:
        # Panel schedules a coroutine as a task, or (off the main thread) as a loop callback that
        # becomes one: idle is no task left over a few turns of the loop
        me = asyncio.current_task()
        idle = 0
        while idle < 3:
            await asyncio.sleep(0.01)
            pending = [t for t in asyncio.all_tasks() if t is not me and not t.done()]
            if pending:
                await asyncio.wait(pending)
            idle = 0 if pending else idle + 1

    return drain()


def test_the_page_runs_its_background_work(tmp_path, population, monkeypatch):
    """In a page (no server): a population choice computes in the background and shows its bands
    (with the study shown), and a contact-map pressure typed in gives maps at that pressure."""
    pytest.importorskip("panel")

    from fingerpad.explore.app import ExplorerApp, ServerState
    from fingerpad.explore.views import population as popview

    calls = []

    def fake(data, name, extra=None):  # the fixture's result: the wiring is tested here, the numbers above
        calls.append((data, name))
        return population[1]

    monkeypatch.setattr(popview, "run_preset", fake)

    async def main() -> None:
        app = ExplorerApp(ServerState(upload_dir=str(tmp_path)))
        view = app.single
        {f.fid: f for f in view.form.all_fields()}["model.kind"].widget.value = "hertz"
        await _drain()
        view.population.choice.value = "adults"
        await _drain()
        assert calls == [(view.shown_data, "adults")]
        assert view.population.result is population[1]
        assert view.population.cards["population-normalised"].spec.fills
        assert 'data-key="population_critical_load_0.5"' in view.population.summary.object
        view.population.choice.value = "none"
        view.population.choice.value = "adults"  # remembered: no second run
        await _drain()
        assert len(calls) == 1 and view.population.result is population[1]
        view.pressure.widget.value = "5kPa"
        await _drain()
        assert view.cards["pressure-map"].spec.meta["mean_pressure_Pa"] == pytest.approx(5e3)
        marks = [v.x for v in view.cards["psi"].spec.vlines if v.label.startswith("contact map")]
        assert marks == [pytest.approx(5e3)]

    _run_page(main)


def _run_page(main, timeout: float = 300) -> None:
    """Run the coroutine function ``main`` (a page's test) in a thread of its own (a browser test
    of the session may hold the main thread's event loop), at most ``timeout`` s; its error is
    raised here."""
    import asyncio
    import threading

    errors: list[BaseException] = []

    def run() -> None:
        try:
            asyncio.run(main())
        except BaseException as exc:  # noqa: BLE001 -- reported below, in the test's thread
            errors.append(exc)

    worker = threading.Thread(target=run)
    worker.start()
    worker.join(timeout)
    assert not worker.is_alive(), f"the page's background work did not end within {timeout:g} s"
    if errors:
        raise errors[0]


def test_an_update_of_many_figures_walks_the_document_at_most_once(preds, monkeypatch):
    """``set_cards`` over a document's figures: one walk over its models where the update changes
    which models the figures refer to (series added, renderers and legends reordered), none where
    it changes data only; the document knows every model its figures refer to afterwards."""
    pytest.importorskip("panel")
    from bokeh.document import Document
    from bokeh.document.models import DocumentModelManager

    from fingerpad.explore.views.common import PlotCard, set_cards

    keys = ("areas", "friction", "friction-normalised", "zones", "zone-profile")
    cards = {k: PlotCard(k) for k in keys}
    doc = Document()
    for k, card in cards.items():
        card.set(builders.prediction_panels(preds[0])[k])
        doc.add_root(card.drawn.figure)
    walks = []
    real = DocumentModelManager.recompute
    monkeypatch.setattr(DocumentModelManager, "recompute", lambda self: (walks.append(1), real(self))[1])
    counts = []
    for pred in [*preds[1:], preds[-1]]:  # the last one again: the same models, data only
        walks.clear()
        set_cards((cards[k], builders.prediction_panels(pred)[k], None) for k in keys)
        counts.append(len(walks))
        known = {m.id for m in doc.models}
        real(doc.models)
        assert known == {m.id for m in doc.models}
        for k in keys:
            assert figure_content(cards[k].drawn) == figure_content(bokeh_figure(builders.prediction_panels(pred)[k]))
    assert max(counts) == 1 and counts[-1] == 0, counts
