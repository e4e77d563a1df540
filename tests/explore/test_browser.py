"""The explorer in a real browser (Debian's Chromium, headless, driven by Playwright).

One page serves the whole module (loading it costs seconds); each test sets the fields it relies
on. The numbers the page shows carry their full-precision value in ``data-value`` and are
compared with ``fingerpad predict --json -`` run on the study TOML the page exports.
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
from pathlib import Path

import pytest

pytest.importorskip("panel")
pytest.importorskip("playwright")

from typer.testing import CliRunner  # noqa: E402

from fingerpad.cli import app  # noqa: E402

runner = CliRunner()


def css(fid: str) -> str:
    return ".fp-field-" + fid.replace(".", "-").replace("_", "-")


def set_field(page, fid: str, value: str) -> None:
    box = page.locator(f"{css(fid)} input")
    box.fill(value)
    box.press("Enter")


def num(page, key: str) -> float:
    return float(page.locator(f'.fp-num[data-key="{key}"]').first.get_attribute("data-value"))


def table(page) -> list[dict[str, str]]:
    """The results table's rows, once it is the design of the summary: in a sequence of changes
    the page dims the table of the design before until the hand pauses (docs/explorer.md)."""
    from playwright.sync_api import expect

    expect(page.locator(".fp-results-pane").first).to_have_css("opacity", "1")
    return page.locator(".fp-results").evaluate(
        "t => [...t.querySelectorAll('tbody tr')].map(r => Object.fromEntries("
        "[...r.querySelectorAll('td')].map(c => [c.dataset.key, c.dataset.value])))")


def download(page, css_class: str) -> bytes:
    with page.expect_download(timeout=60_000) as info:
        page.locator(f".{css_class} button").click()
    return Path(info.value.path()).read_bytes()


def predict_toml(toml: bytes, tmp_path: Path, cache: Path | None = None) -> dict:
    """``fingerpad predict`` of a downloaded study, with the explorer's cell cache (``cache``)."""
    study = tmp_path / "study.toml"
    study.write_bytes(toml)
    env = {"FINGERPAD_CACHE": str(cache)} if cache is not None else None
    res = runner.invoke(app, ["predict", str(study), "--json", "-"], env=env)
    assert res.exit_code == 0, res.output
    return json.loads(res.stdout)


def wait_changed(page, key: str, old: float) -> float:
    from playwright.sync_api import expect

    expect(page.locator(f'.fp-num[data-key="{key}"]').first).not_to_have_attribute("data-value", repr(old),
                                                                                  timeout=60_000)
    return num(page, key)


def record_job_status(page) -> None:
    """Record in the page every text the BEM job's status takes (BokehJS applies each change the
    server sends, in order). A state shown for milliseconds cannot be caught by polling the page:
    on a loaded machine the browser applies the server's changes seconds late, and a short run's
    progress messages then arrive together, just before the message that it is done."""
    found = page.evaluate("""() => {
        window.fpJobStatus = [];
        let n = 0;
        for (const doc of Bokeh.documents) {
            for (const m of doc.all_models) {
                if ((m.css_classes ?? []).includes("fp-job-status") && !m.fpRecorded) {
                    m.fpRecorded = true;
                    m.property("text").change.connect(() => window.fpJobStatus.push(m.text));
                }
                n += (m.css_classes ?? []).includes("fp-job-status") ? 1 : 0;
            }
        }
        return n;
    }""")
    assert found == 1


def job_status_texts(page) -> list[str]:
    return page.evaluate("() => window.fpJobStatus")


def same(a: float | None, b: str | float | None) -> bool:
    if a is None or b in (None, ""):
        return a is None and b in (None, "")
    return math.isclose(float(a), float(b), rel_tol=1e-12, abs_tol=0.0)


def check_table_matches(rows: list[dict[str, str]], payload: dict) -> None:
    assert len(rows) == len(payload["results"])
    for row, ref in zip(rows, payload["results"], strict=True):
        for key in ("load", "gross_area", "ridge_area", "real_area", "area_ratio", "mu", "mu_ref", "mu_normalised"):
            assert same(ref[key], row[key]), (key, ref[key], row[key])
        assert row["contact_state"] == ref["contact_state"]


def test_page_loads_served_locally(page, screenshot_dir):
    assert page.locator(".bk-tab").all_inner_texts()[:2] == ["Texture", "Compare"]
    assert len(table(page)) == 40  # the default 0.1N:4N:40
    assert num(page, "critical_load_hertz") > 0
    page.screenshot(path=str(screenshot_dir / "texture-view.png"), full_page=True)
    assert page.external == [], f"requests left 127.0.0.1: {page.external}"


def test_parameter_change_updates_curves_and_matches_predict(page, tmp_path):
    page.locator(f"{css('model.kind')} select").select_option("hertz")
    set_field(page, "texture.spacing", "175um")
    before = num(page, "critical_load_hertz")
    set_field(page, "texture.spacing", "220um")
    after = wait_changed(page, "critical_load_hertz", before)
    assert after < before  # sparser caps carry more load each: the transition comes earlier (Eq. 3.6)
    rows = table(page)
    payload = predict_toml(download(page, "fp-export-toml"), tmp_path)
    assert payload["inputs"]["texture"]["params"]["spacing"] == pytest.approx(220e-6, rel=1e-15)
    assert same(payload["critical_load"]["hertz"], after)
    check_table_matches(rows, payload)
    set_field(page, "texture.spacing", "175um")
    wait_changed(page, "critical_load_hertz", after)


def test_invalid_value_shows_message_beside_the_field(page):
    from playwright.sync_api import expect

    set_field(page, "texture.radius", "100 furlongs")
    msg = page.locator(f"{css('texture.radius')}-msg")
    expect(msg).to_contain_text("unknown unit 'furlongs'")
    expect(page.locator(".fp-stale")).to_be_visible()
    set_field(page, "loads.range", "4N:0.1N:10")
    expect(page.locator(f"{css('loads.range')}-msg")).to_contain_text("STOP")
    set_field(page, "loads.range", "0.1N:4N:40")
    set_field(page, "texture.radius", "100um")
    expect(msg).to_be_hidden()
    expect(page.locator(".fp-stale")).to_have_count(0)


def test_plot_download_gives_the_numbers_shown(page, tmp_path):
    page.locator(f"{css('model.kind')} select").select_option("hertz")
    rows = table(page)
    data = download(page, "fp-dl-areas-csv").decode()
    table_csv = list(csv.reader(io.StringIO(data)))
    header, body = table_csv[0], table_csv[1:]
    col = header.index("real A_re (hertz) [contact area (m²)]")  # SI, as the page says (the plot shows mm²)
    assert header[0] == "normal load F (N)" and len(body) == len(rows)
    for line, row in zip(body, rows, strict=True):
        assert same(float(line[0]), row["load"])
        assert same(float(line[col]), row["real_area"])
    png = download(page, "fp-dl-friction-png")
    assert png.startswith(b"\x89PNG")
    svg = download(page, "fp-dl-psi-svg")
    assert b"<svg" in svg[:2000]
    js = json.loads(download(page, "fp-dl-friction-normalised-json"))
    assert js["series"][0]["y"] == pytest.approx([float(r["mu_normalised"]) for r in rows], rel=1e-12)
    full = json.loads(download(page, "fp-export-json"))
    check_table_matches(rows, full)


def test_bem_run_shows_progress_finishes_and_reproduces(page, explorer, tmp_path, screenshot_dir):
    from playwright.sync_api import expect

    page.locator(f"{css('model.kind')} select").select_option("both")
    set_field(page, "texture.spacing", "177um")  # a cell no other test computes: not in the cache
    set_field(page, "model.grid", "128")  # a given grid: the fine cell reports progress for seconds
    expect(page.locator(".fp-pending")).to_be_visible()
    record_job_status(page)
    page.locator(".fp-run-bem button").click()
    expect(page.locator(".fp-job-done")).to_be_visible(timeout=180_000)
    shown = job_status_texts(page)  # every text the status took, in order: the progress was shown
    assert any(re.search(r"[1-9]\d* / \d+ solves", t) for t in shown), shown
    expect(page.locator(".fp-current")).to_contain_text("bem")
    crit = num(page, "critical_load_bem")
    rows = table(page)
    page.screenshot(path=str(screenshot_dir / "texture-view-bem.png"), full_page=True)
    payload = predict_toml(download(page, "fp-export-toml"), tmp_path, explorer.cache)
    assert payload["model"] == "bem" and payload["cell"]["cached"]  # the explorer filled the cache
    assert same(payload["critical_load"]["bem"], crit)
    check_table_matches(rows, payload)
    # revisiting is instant: away and back shows the BEM without a run
    set_field(page, "model.grid", "32")
    expect(page.locator(".fp-pending")).to_be_visible()
    set_field(page, "model.grid", "128")
    expect(page.locator(".fp-current")).to_contain_text("bem")
    set_field(page, "model.grid", "")
    set_field(page, "texture.spacing", "175um")


@pytest.mark.slow
def test_cancel_stops_a_bem_run(page):
    from playwright.sync_api import expect

    page.locator(f"{css('model.kind')} select").select_option("both")
    set_field(page, "texture.spacing", "190um")  # a cell not in the cache
    set_field(page, "model.grid", "256")  # a fine cell of many seconds: cancelled long before its end
    expect(page.locator(".fp-pending")).to_be_visible()
    page.locator(".fp-run-bem button").click()
    expect(page.locator(".fp-job-running").first).to_contain_text(re.compile(r"[1-9]\d* / \d+ solves"),
                                                                   timeout=60_000)
    page.locator(".fp-cancel-bem button").click()
    expect(page.locator(".fp-job-cancelled")).to_be_visible(timeout=60_000)
    expect(page.locator(".fp-pending")).to_be_visible()  # still the Hertz curves, the BEM not shown
    set_field(page, "model.grid", "")
    set_field(page, "texture.spacing", "175um")


@pytest.mark.slow
def test_pin_and_compare(page, screenshot_dir):
    from playwright.sync_api import expect

    page.locator(f"{css('model.kind')} select").select_option("hertz")
    expect(page.locator(".fp-current")).to_contain_text("hertz")
    page.locator(".fp-pin button").click()
    expect(page.locator(".fp-pinned")).to_contain_text("pinned 1 of 4")
    before = num(page, "critical_load_hertz")
    set_field(page, "texture.height", "30um")
    wait_changed(page, "critical_load_hertz", before)
    page.locator(".fp-pin button").click()
    expect(page.locator(".fp-pinned")).to_contain_text("pinned 2 of 4")
    page.locator(".bk-tab", has_text="Compare").click()
    expect(page.locator(".fp-pin-remove-1")).to_be_visible()
    figure = page.locator(".fp-plot-compare-friction")
    expect(figure).to_be_visible()
    page.screenshot(path=str(screenshot_dir / "compare-view.png"), full_page=True)
    page.locator(".bk-tab", has_text="Texture").click()
    set_field(page, "texture.height", "20um")


def test_methods_and_references(page, screenshot_dir):
    from playwright.sync_api import expect

    page.locator(".bk-tab", has_text="Methods and references").click()
    expect(page.locator(".fp-methods td", has_text="3.11").first).to_be_visible()  # equation numbers
    expect(page.locator(".fp-methods li", has_text="Sergachev").first).to_be_visible()  # the thesis
    expect(page.locator(".fp-methods li", has_text="Polonsky").first).to_be_visible()  # the solver's paper
    page.screenshot(path=str(screenshot_dir / "methods-view.png"), full_page=True)
    page.locator(".bk-tab", has_text="Texture").click()


def test_map_click_opens_the_clicked_texture(page, screenshot_dir):
    from playwright.sync_api import expect

    page.locator(".bk-tab", has_text="Design map").click()
    expect(page.locator(".fp-plot-design-map")).to_be_visible()
    page.wait_for_timeout(500)
    page.screenshot(path=str(screenshot_dir / "design-map-view.png"), full_page=True)
    where = page.evaluate("""() => {
        for (const v of Bokeh.index.all_views()) {
            if (v.model && v.model.name === 'design-map' && v.frame) {
                const r = v.el.getBoundingClientRect();
                return [r.left + v.frame.x_scale.compute(200), r.top + v.frame.y_scale.compute(30)];
            }
        }
        return null;
    }""")
    assert where is not None
    page.mouse.click(*where)
    expect(page.locator(".bk-tab.bk-active")).to_have_text("Texture")  # the view switched
    expect(page.locator(f"{css('texture.spacing')} input")).to_have_value("200um")
    expect(page.locator(f"{css('texture.height')} input")).to_have_value("30um")
    expect(page.locator(".fp-current")).to_be_visible()  # the base study's model (hertz) is shown
    # the opened design is the sweep's: its inputs validate and run as the study TOML
    assert num(page, "critical_load_hertz") > 0
    page.screenshot(path=str(screenshot_dir / "texture-view-from-map.png"), full_page=False)


def test_population_bands_and_critical_loads(page, explorer, tmp_path, screenshot_dir):
    """The preset population on the design shown: the page's numbers and band data are
    ``run_population`` of the exported study; a forged choice (a file on the server) reads nothing."""
    import tomllib

    from playwright.sync_api import expect

    from fingerpad.population import load_population, run_population
    from fingerpad.study.spec import study_from_dict

    page.locator(".bk-tab", has_text="Texture").click()
    page.locator(f"{css('model.kind')} select").select_option("hertz")
    expect(page.locator(".fp-current")).to_contain_text("hertz")
    page.locator(".fp-population select").select_option("adults")
    expect(page.locator(".fp-population-done")).to_be_visible(timeout=180_000)
    expect(page.locator(".fp-plot-population-normalised")).to_be_visible()
    page.screenshot(path=str(screenshot_dir / "texture-view-population.png"), full_page=True)
    study = study_from_dict(tomllib.loads(download(page, "fp-export-toml").decode()))
    result = run_population(study, load_population("adults"))
    table = result.quantiles()
    assert num(page, "population_members") == len(result.members) == load_population("adults").size
    for level in ("0.05", "0.5", "0.95"):
        assert same(table["critical_load"][level], num(page, f"population_critical_load_{level}"))
    bands = json.loads(download(page, "fp-dl-population-normalised-json"))["bands"]
    assert bands[0]["name"] == "5-95 % of fingers"
    assert bands[0]["lower"] == pytest.approx(list(table["mu_normalised"]["0.05"]), rel=1e-12)
    assert bands[0]["upper"] == pytest.approx(list(table["mu_normalised"]["0.95"]), rel=1e-12)
    # a file on the server holding a valid population, forged as the choice: nothing is read
    secret = tmp_path / "population.toml"
    secret.write_text('[population]\nsize = 3\nskin_modulus = { values = ["0.25MPa"] }\n')
    page.locator(".fp-population select").select_option("none")
    expect(page.locator(".fp-population-section")).to_be_hidden()
    for forged in (str(secret), "/etc/passwd"):
        assert page.evaluate("""([value]) => {
            for (const doc of Bokeh.documents)
                for (const m of doc.all_models)
                    if ((m.css_classes ?? []).includes("fp-population") && 'value' in m.properties) {
                        m.value = value;
                        return true;
                    }
            return false;
        }""", [forged])
    page.wait_for_timeout(1000)
    expect(page.locator(".fp-population-section")).to_be_hidden()
    assert explorer.proc.poll() is None
    page.locator(".fp-population select").select_option("none")
