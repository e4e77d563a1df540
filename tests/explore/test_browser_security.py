"""What a client sends is not trusted: forged widget values, in Debian's Chromium (headless).

The measured-map field is disabled in the page, but a client can set its model's value to any
text. These tests do what a hostile page would: set the value from the page's JavaScript (the
Bokeh document's model) to files outside the server's upload area, and check that nothing of
them is read, shown or downloadable, and that the server answers the same whatever the path
names (a missing file, a secret one, a link out of the upload area, a climb out of it).
"""

from __future__ import annotations

import csv
import io
import os
from pathlib import Path

import pytest

pytest.importorskip("panel")
pytest.importorskip("playwright")

from test_browser import css, download, set_field  # noqa: E402

from fingerpad.explore.uploads import REFUSED  # noqa: E402

MEASURED = "measured map (upload)"
SECRET = 0.987654321  # a height no texture of the page has


def forge(page, css_class: str, value) -> bool:
    """Set the value of the model whose widget has ``css_class`` from the page's JavaScript, as
    a hostile page would (the widget may be disabled: the model does not care)."""
    return page.evaluate(
        """([cls, value]) => {
            for (const doc of Bokeh.documents) {
                for (const m of doc.all_models) {
                    if (m.css_classes && m.css_classes.includes(cls) && 'value' in m.properties) {
                        m.value = value;
                        return true;
                    }
                }
            }
            return false;
        }""", [css_class, value])


def secret_map(folder: Path) -> Path:
    """A readable height map (text, 8 x 8) with a value that shows if it is ever read."""
    path = folder / "heights.txt"
    rows = [" ".join(f"{SECRET + 1e-3 * (i + j):.9f}" for i in range(8)) for j in range(8)]
    path.write_text("\n".join(rows) + "\n")
    return path


def surface_message(page) -> str:
    return page.locator(f"{css('texture.surface')}-msg").locator(".fp-error, .fp-info, .fp-warning").inner_text().strip()


@pytest.fixture()
def measured(page):
    """The page with the measured-map family chosen, size and unit given (a read would work)."""
    from playwright.sync_api import expect

    page.locator(".bk-tab", has_text="Texture").click()
    page.locator(f"{css('model.kind')} select").select_option("both")  # Hertz has no measured maps
    page.locator(f"{css('texture.name')} select").select_option(MEASURED)
    expect(page.locator(f"{css('texture.surface')}-msg")).to_contain_text("upload a file")
    set_field(page, "texture.size", "200um")
    set_field(page, "texture.height_unit", "um")
    yield page
    page.locator(f"{css('texture.name')} select").select_option("caps")
    expect(page.locator(".fp-stale")).to_have_count(0)


def test_forged_map_paths_are_never_read(measured, explorer, tmp_path):
    from playwright.sync_api import expect

    page = measured
    secret = secret_map(tmp_path)
    area = next(Path(explorer.tmpdir).glob("fingerpad-explore-*"))  # the server's upload area
    inside = area / "upload-0123456789abcdef"
    inside.mkdir()
    (inside / "heights.txt").symlink_to(secret)  # a link in the area to a file outside
    (inside / "dir.txt").mkdir()
    attempts = [str(secret), "/etc/shadow", "/etc/passwd", str(tmp_path / "missing.txt"),
                str(inside / "heights.txt"), f"{inside}/../../../{secret.relative_to('/')}", str(inside / "dir.txt"),
                str(area), "heights.txt", "../heights.txt", "~/heights.txt", "file:///etc/passwd", "\x00", "  "]
    messages = []
    box = page.locator(f"{css('texture.surface')} input")
    for value in attempts:
        assert forge(page, "fp-field-texture-surface", value)
        expect(box).to_have_value("")  # the server put its own value back
        expect(page.locator(f"{css('texture.surface')}-msg")).to_be_visible()
        messages.append(surface_message(page))
        expect(page.locator(".fp-stale")).to_be_visible()  # nothing computed from it
    # one answer whatever the path: a client learns nothing of what exists outside the area
    assert set(messages) == {REFUSED}, list(zip(attempts, messages, strict=True))
    text = page.locator("body").inner_text()
    assert f"{SECRET:.6f}"[:8] not in text and str(explorer.tmpdir) not in text
    heights = download(page, "fp-dl-height-map-csv").decode()
    rows = list(csv.reader(io.StringIO(heights)))
    assert rows and not any(f"{SECRET:.6f}"[:8] in cell for row in rows for cell in row)


@pytest.mark.slow  # ~10 s of the 2-core CI's suite: run by make test-slow
def test_an_upload_is_read_named_as_the_user_named_it(measured, explorer, tmp_path):
    from playwright.sync_api import expect

    page = measured
    # record every text the message beside the field shows (Panel's panes live in shadow roots)
    page.evaluate("""() => {
        window.fpSeen = [];
        const find = (root) => {
            for (const el of root.querySelectorAll('*')) {
                if (el.classList.contains('fp-field-texture-surface-msg')) return el;
                if (el.shadowRoot) { const f = find(el.shadowRoot); if (f) return f; }
            }
            return null;
        };
        const text = (node) => {
            let t = '';
            const walk = (n) => { if (n.nodeName === 'STYLE') return;
                                  if (n.nodeType === 3) t += n.textContent;
                                  if (n.shadowRoot) walk(n.shadowRoot);
                                  for (const c of n.childNodes) walk(c); };
            walk(node);
            return t.trim();
        };
        let host = null;
        window.fpTimer = setInterval(() => {
            host = host && host.isConnected ? host : find(document);
            const t = host ? text(host) : '';
            if (t && window.fpSeen[window.fpSeen.length - 1] !== t) window.fpSeen.push(t);
        }, 20);
    }""")
    page.locator(".fp-upload input[type=file]").set_input_files(str(secret_map(tmp_path)))
    expect(page.locator(f"{css('texture.surface')}-msg")).to_contain_text("heights.txt: ")
    seen = page.evaluate("() => { clearInterval(window.fpTimer); return window.fpSeen; }")
    assert "reading heights.txt ..." in seen, seen  # said at once, before the map was read
    expect(page.locator(f"{css('texture.surface')} input")).to_have_value("heights.txt")
    expect(page.locator(".fp-stale")).to_have_count(0)
    text = page.locator("body").inner_text()
    assert str(explorer.tmpdir) not in text and "upload-" not in text
    toml = download(page, "fp-export-toml").decode()
    assert 'surface = "heights.txt"' in toml and str(explorer.tmpdir) not in toml
    # a forged value changes nothing: the map read is still the upload
    assert forge(page, "fp-field-texture-surface", "/etc/passwd")
    expect(page.locator(f"{css('texture.surface')} input")).to_have_value("heights.txt")
    expect(page.locator(".fp-stale")).to_have_count(0)
    assert os.path.isdir(next(Path(explorer.tmpdir).glob("fingerpad-explore-*")))


def test_forged_choices_and_indices_are_refused(page, explorer):
    """A choice outside a select's options, a map index outside the map: nothing changes."""
    from playwright.sync_api import expect

    page.locator(".bk-tab", has_text="Texture").click()
    assert forge(page, "fp-field-texture-name", "../../etc")
    assert forge(page, "fp-field-model-kind", "rm -rf")
    page.wait_for_timeout(1000)
    expect(page.locator(".fp-stale")).to_have_count(0)
    assert explorer.proc.poll() is None
    # a grid beyond the library's bound is refused before anything runs
    set_field(page, "model.grid", "100000")
    expect(page.locator(f"{css('model.grid')}-msg")).to_contain_text("at most 8192")
    set_field(page, "loads.range", "0.1N:4N:100000")
    expect(page.locator(f"{css('loads.range')}-msg")).to_contain_text("at most 2000 loads")
    set_field(page, "loads.range", "0.1N:4N:40")
    set_field(page, "model.grid", "")
    expect(page.locator(".fp-stale")).to_have_count(0)


def model_value(page, css_class: str):
    return page.evaluate(
        """(cls) => {
            for (const doc of Bokeh.documents) {
                for (const m of doc.all_models) {
                    if (m.css_classes && m.css_classes.includes(cls) && 'value' in m.properties) return m.value;
                }
            }
            return null;
        }""", css_class)


def test_a_forged_population_is_reset_to_none_and_logged_short(page, explorer):
    """Issue 30, item 17: Panel refused a choice outside the options before the package's check
    ran, so the selector was not set back to none as promised, and a 5 MB forged value was echoed
    whole into the server's output (with a traceback). Now the package checks it first."""
    from playwright.sync_api import expect

    start = len(explorer.output)
    assert forge(page, "fp-population", "x" * 5_000_000)
    expect(page.locator(".fp-population-msg")).to_contain_text("population: choose one of none, adults")
    page.wait_for_function("""() => {
        for (const doc of Bokeh.documents) for (const m of doc.all_models)
            if (m.css_classes && m.css_classes.includes('fp-population')) return m.value === 'none';
        return false; }""")
    assert forge(page, "fp-field-model-kind", "y" * 100_000)  # any select of the page
    page.wait_for_function("""() => {
        for (const doc of Bokeh.documents) for (const m of doc.all_models)
            if (m.css_classes && m.css_classes.includes('fp-field-model-kind')) return m.value.length < 10;
        return false; }""")
    page.wait_for_timeout(1000)
    said = "".join(explorer.output[start:])
    assert "Traceback" not in said and "not in list" not in said, said[:2000]
    assert max((len(line) for line in said.splitlines()), default=0) < 400
    assert said.count("refused a value from the page") == 2, said[:2000]
    assert "(5000000 characters)" in said and "(100000 characters)" in said
    assert explorer.proc.poll() is None
