"""The explorer at a designer's pace, in Debian's Chromium (issue 37): arrow keys and sliders on the
number fields, a burst of changes, a change that cancels a BEM run under way.

No timing is asserted (``benchmarks/bench_explorer.py`` measures): the tests check what the page
shows. Every number compared is the full-precision ``data-value`` of the page against
``fingerpad predict --json -`` on the study the page exports.
"""

from __future__ import annotations

import re

import pytest

pytest.importorskip("panel")
pytest.importorskip("playwright")

from test_browser import (  # noqa: E402
    check_table_matches,
    css,
    download,
    job_status_texts,
    num,
    predict_toml,
    record_job_status,
    set_field,
    table,
)


def box(page, fid: str):
    return page.locator(f"{css(fid)} input")


def message(page, fid: str):
    return page.locator(f"{css(fid)}-msg")


def form_error(page) -> str:
    """The message of an invalid design (once the page says the plots keep the last valid one)."""
    from playwright.sync_api import expect

    expect(page.locator(".fp-stale")).to_be_visible()
    message = page.locator(".fp-form-error .fp-error").first
    expect(message).to_be_visible()
    return message.inner_text()


def shows_predict(page, tmp_path, spacing: str) -> None:
    """The page's numbers are those of ``fingerpad predict`` on the exported study, whose spacing
    is ``spacing`` (the last value entered, not one passed over)."""
    from playwright.sync_api import expect

    payload = predict_toml(download(page, "fp-export-toml"), tmp_path)
    assert payload["inputs"]["texture"]["params"]["spacing"] == pytest.approx(float(spacing[:-2]) * 1e-6, rel=1e-15)
    crit = page.locator('.fp-num[data-key="critical_load_hertz"]').first
    expect(crit).to_have_attribute("data-value", repr(float(payload["critical_load"]["hertz"])), timeout=60_000)
    page.wait_for_timeout(1500)  # nothing later replaces them with a design passed over
    assert num(page, "critical_load_hertz") == payload["critical_load"]["hertz"]
    check_table_matches(table(page), payload)


@pytest.fixture
def hertz(page):
    from playwright.sync_api import expect

    page.locator(".bk-tab", has_text="Texture").click()
    page.locator(f"{css('model.kind')} select").select_option("hertz")
    set_field(page, "texture.spacing", "175um")
    expect(page.locator(".fp-current")).to_contain_text("hertz")
    yield page
    set_field(page, "texture.spacing", "175um")
    set_field(page, "finger.beta", "")
    set_field(page, "finger.radius", "")
    set_field(page, "material.poisson", "0.4")


@pytest.mark.slow  # ~10 s of the 2-core CI's suite: run by make test-slow
def test_arrow_keys_step_with_the_unit_and_stop_at_the_limits(hertz, tmp_path):
    from playwright.sync_api import expect

    page = hertz
    expect(page.locator(f"{css('texture.spacing')} .fp-scan-hint")).to_have_text("↑↓ 10 µm (Shift ×10)")
    spacing = box(page, "texture.spacing")
    before = num(page, "critical_load_hertz")
    spacing.press("ArrowUp")
    expect(spacing).to_have_value("185um")
    expect(page.locator('.fp-num[data-key="critical_load_hertz"]').first).not_to_have_attribute(
        "data-value", repr(before), timeout=60_000)
    shows_predict(page, tmp_path, "185um")
    spacing.press("Shift+ArrowDown")  # 85 um: caps of 120 um overlap; the field's own message
    expect(spacing).to_have_value("85um")
    stepped = form_error(page)
    assert "caps overlap" in stepped
    set_field(page, "texture.spacing", "175um")
    expect(page.locator(".fp-stale")).to_have_count(0)
    set_field(page, "texture.spacing", "85um")  # typed: the same message
    expect(page.locator(".fp-form-error .fp-error")).to_have_text(stepped)
    # what the field refuses is not stepped: the text stays, with the field's message
    spacing.fill("abc")
    spacing.press("ArrowUp")
    expect(message(page, "texture.spacing")).to_contain_text("cannot read 'abc'")
    expect(spacing).to_have_value("abc")
    set_field(page, "texture.spacing", "175um")
    # a closed bound: beta lies in [0, 1]
    beta = box(page, "finger.beta")
    set_field(page, "finger.beta", "0.95")
    beta.press("Shift+ArrowUp")
    expect(beta).to_have_value("1")
    beta.press("ArrowUp")
    page.wait_for_timeout(500)
    expect(beta).to_have_value("1")
    expect(message(page, "finger.beta")).to_be_hidden()
    # an open bound: the material's Poisson ratio lies in (-1, 0.5]
    poisson = box(page, "material.poisson")
    set_field(page, "material.poisson", "-0.99")
    poisson.press("ArrowDown")
    page.wait_for_timeout(500)
    expect(poisson).to_have_value("-0.99")
    poisson.press("Shift+ArrowUp")
    expect(poisson).to_have_value("-0.89")
    # an empty finger field steps from the preset's value (9 mm)
    radius = box(page, "finger.radius")
    radius.press("ArrowUp")
    expect(radius).to_have_value("9.1mm")


@pytest.mark.slow  # ~10 s of the 2-core CI's suite: run by make test-slow
def test_slider_sets_the_field_and_stays_in_its_range(hertz, tmp_path):
    from playwright.sync_api import expect

    page = hertz
    slider = page.locator(f"{css('texture.spacing')}-slider input")
    assert (slider.get_attribute("min"), slider.get_attribute("max"), slider.get_attribute("step")) == ("50", "700", "10")
    expect(page.locator(f"{css('texture.spacing')}-slider")).to_contain_text("50 µm")
    set_field(page, "texture.spacing", "200um")
    expect(slider).to_have_value("200")  # the slider follows the field
    slider.focus()
    for _ in range(3):
        slider.press("ArrowRight")
    expect(box(page, "texture.spacing")).to_have_value("230um")
    shows_predict(page, tmp_path, "230um")
    # dragged past its end: it stops at the end of its range
    where = slider.bounding_box()
    page.mouse.move(where["x"] + where["width"] * 0.9, where["y"] + where["height"] / 2)
    page.mouse.down()
    page.mouse.move(where["x"] + where["width"] + 200, where["y"] + where["height"] / 2, steps=8)
    page.mouse.up()
    expect(box(page, "texture.spacing")).to_have_value("700um")
    shows_predict(page, tmp_path, "700um")
    # the same rules as the field: at 50 um the caps overlap, the message is the typed value's
    slider.focus()
    slider.press("Home")
    expect(box(page, "texture.spacing")).to_have_value("50um")
    slid = form_error(page)
    assert "caps overlap" in slid
    set_field(page, "texture.spacing", "175um")
    expect(page.locator(".fp-stale")).to_have_count(0)
    set_field(page, "texture.spacing", "50um")
    expect(page.locator(".fp-form-error .fp-error")).to_have_text(slid)


def test_a_burst_of_changes_shows_the_last_design(hertz, tmp_path):
    """Six values entered 50 ms apart (faster than the page computes them): the page ends on the
    last one's numbers, those of `fingerpad predict`, and stays there."""
    page = hertz
    values = [f"{v}um" for v in (181, 192, 203, 214, 225, 236)]
    page.evaluate("""async ([cls, values]) => {
        const view = [...Bokeh.index.all_views()].find(v => (v.model.css_classes ?? []).includes(cls));
        const input = view.shadow_el.querySelector('input');
        for (const v of values) {
            input.value = v;
            input.dispatchEvent(new Event('change'));
            await new Promise(r => setTimeout(r, 50));
        }
    }""", ["fp-field-texture-spacing", values])
    shows_predict(page, tmp_path, values[-1])


def test_a_change_cancels_the_bem_run_of_the_design_before(page):
    """With the BEM on every change, a change during a run cancels it (the Hertz numbers of the
    new design at once) and the new design's run starts."""
    from playwright.sync_api import expect

    page.locator(".bk-tab", has_text="Texture").click()
    page.locator(f"{css('model.kind')} select").select_option("both")
    set_field(page, "model.grid", "256")  # a fine cell of many seconds, not in the cache
    set_field(page, "texture.spacing", "183um")
    expect(page.locator(".fp-pending")).to_be_visible()
    record_job_status(page)
    page.locator(".fp-auto-bem input").check()
    expect(page.locator(".fp-job-running").first).to_be_visible(timeout=60_000)
    before = num(page, "critical_load_hertz")
    set_field(page, "texture.spacing", "187um")
    expect(page.locator('.fp-num[data-key="critical_load_hertz"]').first).not_to_have_attribute(
        "data-value", repr(before), timeout=60_000)
    expect(page.locator(".fp-pending")).to_be_visible()  # the new design's Hertz numbers, the BEM pending
    expect(page.locator(".fp-job-cancelled, .fp-job-running").first).to_be_visible(timeout=60_000)
    page.wait_for_function("() => window.fpJobStatus.some(t => t.includes('fp-job-cancelled'))", timeout=60_000)
    # the new design's run starts once it has been shown a moment (background work waits 0.4 s)
    page.wait_for_function(
        "() => { const s = window.fpJobStatus; const i = s.findIndex(t => t.includes('fp-job-cancelled'));"
        " return s.slice(i).some(t => t.includes('starting') || t.includes('fp-job-running')); }",
        timeout=60_000)
    shown = job_status_texts(page)
    cancelled = next(i for i, t in enumerate(shown) if "fp-job-cancelled" in t)
    assert any("starting" in t for t in shown[cancelled:]) or re.search("fp-job-running", shown[-1]), shown
    page.locator(".fp-auto-bem input").uncheck()
    cancel = page.locator(".fp-cancel-bem button")
    if cancel.is_enabled():
        cancel.click()
    expect(page.locator(".fp-job-running")).to_have_count(0, timeout=60_000)
    assert not any("fp-job-failed" in t for t in job_status_texts(page)), job_status_texts(page)
    set_field(page, "model.grid", "")
    set_field(page, "texture.spacing", "175um")


@pytest.mark.slow  # ~10 s of the 2-core CI's suite: run by make test-slow
def test_the_upload_script_comes_with_the_first_upload(browser_context, explorer):
    """FilePond (the drop zone's library) runs an animation loop from the moment its script is in
    the page: a fresh page has none of it until *measured map (upload)* is chosen, then the drop
    zone is there, its script from 127.0.0.1."""
    from playwright.sync_api import expect

    page = browser_context.new_page()
    requested = []
    page.on("request", lambda r: requested.append(r.url))
    try:
        page.goto(explorer.url)
        page.wait_for_selector(".fp-results td")
        assert page.evaluate("() => typeof window.FilePond") == "undefined"
        assert not any("filepond" in u for u in requested)
        page.locator(f"{css('model.kind')} select").select_option("both")
        page.locator(f"{css('texture.name')} select").select_option("measured map (upload)")
        expect(page.locator(".fp-upload input[type=file]")).to_have_count(1, timeout=60_000)
        assert page.evaluate("() => typeof window.FilePond") == "object"
        assert all(u.startswith(("http://127.0.0.1", "ws://127.0.0.1", "data:", "blob:")) for u in requested)
    finally:
        page.close()
