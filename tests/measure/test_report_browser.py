"""The HTML report in a real browser: headless Chromium (Debian package) lays it out.

A copy of report.html gets a script that, once the page and its images have loaded, measures
the layout and writes it into the page; ``--dump-dom`` prints the page with the result. Skipped
when ``/usr/bin/chromium`` is absent (``apt-get install -y chromium``).
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from fingerpad.measure.report import write_report

CHROMIUM = Path("/usr/bin/chromium")

PROBE = """
<script>
window.addEventListener('load', function () {
  var doc = document.documentElement;
  var out = {viewport: window.innerWidth, page_width: doc.scrollWidth, tables: [], images: [], headers: []};
  document.querySelectorAll('table').forEach(function (t) {
    var box = t.parentElement.getBoundingClientRect();
    out.tables.push({box_right: box.right, box_width: box.width, scrolls: t.parentElement.scrollWidth > t.parentElement.clientWidth,
                     overflow: getComputedStyle(t.parentElement).overflowX});
  });
  document.querySelectorAll('img').forEach(function (i) {
    out.images.push({loaded: i.complete && i.naturalWidth > 0, right: i.getBoundingClientRect().right});
  });
  document.querySelectorAll('th').forEach(function (h) { out.headers.push(h.textContent); });
  var pre = document.createElement('pre');
  pre.id = 'layout-probe';
  pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
});
</script>
"""


def _layout(html_file: Path, width: int, tmp: Path) -> dict:
    probe = tmp / f"probe_{width}.html"
    text = html_file.read_text(encoding="utf-8").replace("</body>", PROBE + "</body>")
    probe.write_text(text, encoding="utf-8")
    cmd = [str(CHROMIUM), "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
           "--disable-component-update", "--disable-sync", "--no-first-run", f"--user-data-dir={tmp / 'profile'}",
           f"--window-size={width},1000", "--virtual-time-budget=10000", "--dump-dom", probe.as_uri()]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=90)
    match = re.search(r'<pre id="layout-probe">(.*?)</pre>', done.stdout, re.S)
    assert match, f"no layout probe in the page (chromium rc {done.returncode}): {done.stderr[-500:]}"
    return json.loads(match.group(1).replace("&amp;", "&").replace("&lt;", "<").replace("&gt;", ">"))


@pytest.mark.skipif(not CHROMIUM.exists() or shutil.which(str(CHROMIUM)) is None,
                    reason="headless Chromium not installed (apt-get install -y chromium)")
def test_report_layout_in_chromium(study_small, tmp_path):
    out = tmp_path / "res"
    write_report(study_small, out, qc=True, qc_recordings=True)
    for width in (1280, 800):
        layout = _layout(out / "report.html", width, tmp_path)
        # the page never scrolls sideways: wide tables scroll inside their own box
        assert layout["page_width"] <= layout["viewport"] + 1, layout
        assert layout["tables"], "no tables rendered"
        for t in layout["tables"]:
            assert t["box_right"] <= layout["viewport"] + 1 and t["overflow"] == "auto", t
        assert layout["images"] and all(i["loaded"] for i in layout["images"]), "an embedded figure did not load"
        assert all(i["right"] <= layout["viewport"] + 1 for i in layout["images"])
    headers = " | ".join(layout["headers"])
    for wanted in ("E s (MPa)", "k [CI]", "n [CI]", "sense ratio", "breakpoint p", "closed form, Eq. 3.6",
                   "other model"):
        assert wanted in headers.replace("Es", "E s"), (wanted, headers)
    page = (out / "report.html").read_text(encoding="utf-8")
    assert "nan" not in re.sub(r"<[^>]+>", " ", page.split("<h2>Figures</h2>")[0]).lower().split()
    qc = re.findall(r"href='(figures/qc/[^']+)'", page)
    assert qc and all((out / link).is_file() for link in qc)
