"""The explorer's response as a user sees it, in a real browser (``bench_explorer.py --browser``).

``fingerpad explore`` is served on 127.0.0.1 in a subprocess; Debian's headless Chromium
(``/usr/bin/chromium``, driven by Playwright, nothing downloaded) opens the page. Each change is
made and timed inside the page (``performance.now()``): the text input's value is set and its
``change`` event dispatched (what typing and Enter do), then the page waits until

* **numbers**: the summary's and the results table's DOM hold the new design's numbers (the
  critical load's ``data-value`` and the table differ from before, or equal those recorded at an
  earlier visit of that design), and
* **figures**: no Bokeh figure of the page has a paint pending. Every figure's view
  (``PlotView``) is instrumented through its prototype (views made later included):
  ``schedule_paint`` marks the figure dirty (BokehJS calls it when a patch changes a figure's
  data, ranges or glyphs; the paint itself waits for the next animation frame),
  ``_actual_paint`` (the canvas drawing) clears it. A figure that is not displayed never paints
  and is not waited for.

The time reported ("page") is from the change to the end of the later of the two, plus the next
animation frame (the browser composites the new DOM and canvases there). BokehJS's own
"document idle" signal fires once, at the first render, so it cannot serve here.

"settled" waits further: until neither a websocket frame nor a paint has happened for 0.6 s (the
contact maps of the unit cell come in a later patch, after their solve in a worker thread); the
time of the last of them is reported. The profile of each change: when the page sent the change
and when the first and last websocket frames of the reply arrived (server + network), the time
spent applying patches (``Document.apply_json_patch``: models, DOM of the HTML panes), drawing
the figures' canvases, and the layout/style/script time Chromium reports (``Performance.getMetrics``
over CDP); CPU seconds of the server process and of Chromium's process tree.
"""

from __future__ import annotations

import os
import queue
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

CHROMIUM = os.environ.get("FINGERPAD_CHROMIUM", "/usr/bin/chromium")
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync"]

# Before the page's own scripts: every websocket frame sent and received, with its time.
INIT_JS = """
(() => {
  const W = window.WebSocket;
  const net = window.fpNet = {recv: [], sent: []};
  window.WebSocket = class extends W {
    constructor(...a) {
      super(...a);
      // registered before Bokeh's onmessage: the arrival time, before the message is handled
      this.addEventListener('message', e => net.recv.push(performance.now()));
    }
    send(d) { net.sent.push(performance.now()); return super.send(d); }
  };
})();
"""

# Instruments the figures' views and the document; defines fpChange(cls, value, expect).
SETUP_JS = """
() => {
  const views = [...Bokeh.index.all_views()];
  const plot = views.find(v => typeof v._actual_paint === 'function');
  if (!plot) return 'no figure view';
  let proto = Object.getPrototypeOf(plot);
  while (!Object.prototype.hasOwnProperty.call(proto, '_actual_paint')) proto = Object.getPrototypeOf(proto);
  const st = window.fpState = {dirty: new Set(), paints: [], paint_s: 0, apply_s: 0, applies: []};
  const schedule = proto.schedule_paint, actual = proto._actual_paint;
  proto.schedule_paint = function (...a) {
    if (!this.is_paused) st.dirty.add(this);
    return schedule.apply(this, a);
  };
  proto._actual_paint = function (...a) {
    const t0 = performance.now();
    try { return actual.apply(this, a); } finally {
      const t1 = performance.now();
      st.dirty.delete(this); st.paints.push(t1); st.paint_s += (t1 - t0) / 1000;
    }
  };
  const doc = Bokeh.documents[0];
  const apply = doc.apply_json_patch.bind(doc);
  doc.apply_json_patch = (...a) => {
    const t0 = performance.now();
    try { return apply(...a); } finally {
      const t1 = performance.now(); st.applies.push(t1); st.apply_s += (t1 - t0) / 1000;
    }
  };
  window.fpView = cls => [...Bokeh.index.all_views()].find(v => (v.model.css_classes ?? []).includes(cls));
  window.fpNumbers = () => {
    const s = fpView('fp-summary').shadow_el, t = fpView('fp-results-pane').shadow_el;
    const keyed = {};
    for (const e of s.querySelectorAll('.fp-num')) keyed[e.dataset.key] = e.dataset.value;
    const rows = [...t.querySelectorAll('tbody tr')]
      .map(r => [...r.querySelectorAll('td')].map(c => c.dataset.value).join(','));
    return {keyed, table: rows.join(';'), status: fpView('fp-status').shadow_el.textContent};
  };
  const frame = () => new Promise(r => requestAnimationFrame(() => setTimeout(r, 0)));
  const sleep = ms => new Promise(r => setTimeout(r, ms));
  window.fpChange = async (cls, value, expect, quietMs, maxMs) => {
    const input = fpView(cls).shadow_el.querySelector('input');
    const before = fpNumbers();
    const net = window.fpNet, nr = net.recv.length, ns = net.sent.length;
    st.paints = []; st.applies = []; st.paint_s = 0; st.apply_s = 0;
    const same = (a, b) => a.table === b.table && JSON.stringify(a.keyed) === JSON.stringify(b.keyed);
    const shown = () => {
      const now = fpNumbers();
      if (expect) return same(now, expect);
      return now.table !== before.table && now.keyed.critical_load_hertz !== before.keyed.critical_load_hertz;
    };
    const visible = () => [...st.dirty].filter(v => v.is_displayed && !v.is_destroyed && !v.is_paused);
    await frame();
    const t0 = performance.now();
    input.value = value;
    input.dispatchEvent(new Event('change'));
    let tNumbers = null, tPage = null;
    // the DOM of the numbers, checked at once after every change of it (and every 5 ms)
    const mo = new MutationObserver(() => { if (tNumbers === null && shown()) tNumbers = performance.now(); });
    for (const c of ['fp-summary', 'fp-results-pane'])
      mo.observe(fpView(c).shadow_el, {subtree: true, childList: true, characterData: true, attributes: true});
    while (tPage === null && performance.now() - t0 < maxMs) {
      if (tNumbers === null && shown()) tNumbers = performance.now();
      if (tNumbers !== null && visible().length === 0) {
        await frame();
        if (visible().length === 0) tPage = performance.now();
      } else {
        await sleep(5);
      }
    }
    mo.disconnect();
    // settled: no frame received and no paint for quietMs
    let last = Math.max(tPage ?? t0, ...net.recv.slice(nr), ...st.paints);
    while (performance.now() - last < quietMs && performance.now() - t0 < maxMs) {
      await sleep(20);
      last = Math.max(last, ...net.recv.slice(nr), ...st.paints);
    }
    const recv = net.recv.slice(nr), sent = net.sent.slice(ns);
    const firstPatch = recv.filter(t => t <= (tNumbers ?? Infinity));
    return {
      ok: tPage !== null, t0, numbers_s: tNumbers === null ? null : (tNumbers - t0) / 1000,
      page_s: tPage === null ? null : (tPage - t0) / 1000, settled_s: (last - t0) / 1000,
      sent_s: sent.length ? (sent[0] - t0) / 1000 : null,
      first_frame_s: recv.length ? (recv[0] - t0) / 1000 : null,
      numbers_frame_s: firstPatch.length ? (firstPatch[firstPatch.length - 1] - t0) / 1000 : null,
      frames: recv.length, apply_s: st.apply_s, paint_s: st.paint_s, paints: st.paints.length,
      last_paint_s: st.paints.length ? (Math.max(...st.paints) - t0) / 1000 : null,
      after: fpNumbers(), recv_ms: recv.map(t => Math.round(t - t0)),
    };
  };
  return 'ok';
}
"""


def browser_missing() -> str | None:
    """Why the browser benchmark cannot run here (None: it can)."""
    import importlib.util

    for mod in ("panel", "bokeh", "playwright"):
        if importlib.util.find_spec(mod) is None:
            return f"{mod} is not installed"
    if not (os.path.isfile(CHROMIUM) and os.access(CHROMIUM, os.X_OK)):
        return f"no Chromium at {CHROMIUM} (apt-get install -y chromium)"
    return None


def _ticks(pid: int) -> int:
    """utime + stime of a process, clock ticks (0 once it is gone)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return 0
    return int(fields[11]) + int(fields[12])


def _tree(root: int) -> list[int]:
    """``root`` and its descendants (read from /proc)."""
    parent: dict[int, int] = {}
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                parent[int(d)] = int(Path(f"/proc/{d}/stat").read_text().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                pass
    out, todo = [], [root]
    while todo:
        p = todo.pop()
        out.append(p)
        todo += [c for c, pp in parent.items() if pp == p]
    return out


def _cpu_s(pids: list[int]) -> float:
    return sum(_ticks(p) for p in pids) / os.sysconf("SC_CLK_TCK")


class _Server:
    """``fingerpad explore --no-browser`` in a subprocess, its URL once it listens."""

    def __init__(self, env: dict[str, str]) -> None:
        code = "import sys; from fingerpad.cli import main; sys.argv[0] = 'fingerpad'; main()"
        if env.get("FINGERPAD_BENCH_PROFILE"):  # the server under cProfile (where its time goes)
            code = ("import cProfile, os, sys; from fingerpad.cli import main; sys.argv[0] = 'fingerpad'\n"
                    "prof = cProfile.Profile(); prof.enable()\ntry:\n    main()\nfinally:\n"
                    "    prof.disable(); prof.dump_stats(os.environ['FINGERPAD_BENCH_PROFILE'])")
        self.proc = subprocess.Popen([sys.executable, "-c", code, "explore", "--no-browser"],
                                     stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                     env={**os.environ, **env, "BOKEH_BROWSER": "none"})
        lines: queue.Queue[str] = queue.Queue()
        self.output: list[str] = []

        def read() -> None:
            assert self.proc.stdout is not None
            for line in self.proc.stdout:
                self.output.append(line)
                lines.put(line)

        threading.Thread(target=read, daemon=True).start()
        self.url = None
        while self.url is None:
            try:
                m = re.search(r"serving on (http://127\.0\.0\.1:\d+/)", lines.get(timeout=90))
            except queue.Empty:
                self.stop()
                raise RuntimeError("the explorer did not start within 90 s:\n" + "".join(self.output)) from None
            if m:
                self.url = m.group(1)

    def stop(self) -> None:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(timeout=15)


def _css(fid: str) -> str:
    return "fp-field-" + fid.replace(".", "-").replace("_", "-")


class _Page:
    def __init__(self, page: Any, cdp: Any, server: _Server, chromium: list[int]) -> None:
        self.page, self.cdp, self.server, self.chromium = page, cdp, server, chromium
        self.seen: dict[str, Any] = {}  # design -> the numbers the page showed for it

    def metrics(self) -> dict[str, float]:
        m = {x["name"]: x["value"] for x in self.cdp.send("Performance.getMetrics")["metrics"]}
        return {k: m.get(k, 0.0) for k in ("ScriptDuration", "LayoutDuration", "RecalcStyleDuration", "TaskDuration")}

    def change(self, value: str, key: str, max_s: float = 60.0, quiet_s: float = 0.6) -> dict[str, Any]:
        """Set the spacing to ``value`` and time the page until it shows the design ``key``."""
        m0, s0, c0 = self.metrics(), _cpu_s([self.server.proc.pid]), _cpu_s(self.chromium)
        r = self.page.evaluate("([c, v, e, q, m]) => fpChange(c, v, e, q, m)",
                               [_css("texture.spacing"), value, self.seen.get(key), quiet_s * 1000, max_s * 1000])
        m1, s1, c1 = self.metrics(), _cpu_s([self.server.proc.pid]), _cpu_s(self.chromium)
        if not r["ok"]:
            raise RuntimeError(f"the page did not show {key} within {max_s} s: {r}")
        self.seen.setdefault(key, r.pop("after"))
        r.pop("after", None)
        self.timeline = r.pop("recv_ms")
        r.update({"layout_s": m1["LayoutDuration"] - m0["LayoutDuration"],
                  "style_s": m1["RecalcStyleDuration"] - m0["RecalcStyleDuration"],
                  "script_s": m1["ScriptDuration"] - m0["ScriptDuration"],
                  "task_s": m1["TaskDuration"] - m0["TaskDuration"],
                  "server_cpu_s": s1 - s0, "chromium_cpu_s": c1 - c0})
        return r

    def select_kind(self, kind: str) -> None:
        self.page.locator(f".{_css('model.kind')} select").select_option(kind)
        self.page.wait_for_timeout(500)

    def run_bem(self, value: str) -> None:
        """Show ``value`` with model 'both' and run its BEM (from the disk cache when there)."""
        from playwright.sync_api import expect

        self.change(value, f"pending {value}")
        self.page.locator(".fp-run-bem button").click()
        expect(self.page.locator(".fp-job-done")).to_be_visible(timeout=600_000)
        expect(self.page.locator(".fp-current")).to_contain_text("bem", timeout=120_000)
        self.page.wait_for_timeout(1000)
        self.seen[f"bem {value}"] = self.page.evaluate("() => fpNumbers()")


def _summary(rows: list[dict[str, Any]]) -> dict[str, float]:
    out = {}
    for k in rows[0]:
        vals = [r[k] for r in rows if isinstance(r.get(k), (int, float)) and not isinstance(r.get(k), bool)]
        if vals:
            out[k] = statistics.median(vals)
    for k in ("page_s", "numbers_s", "settled_s"):
        out[k + "_max"] = max(r[k] for r in rows)
    return out


def run(cache: str, repeats: int) -> dict[str, Any]:
    """The three cases in one browser page; per case the medians (and maxima) of ``repeats`` changes."""
    from playwright.sync_api import sync_playwright

    tmp = tempfile.mkdtemp(prefix="fingerpad-bench-browser-", dir=cache)
    server = _Server({"FINGERPAD_CACHE": os.path.join(cache, "cells"), "TMPDIR": tmp,
                      "FINGERPAD_BENCH_PROFILE": os.environ.get("FINGERPAD_BENCH_PROFILE", "")})
    pw = sync_playwright().start()
    try:
        profile = os.path.join(tmp, "chromium-profile")
        context = pw.chromium.launch_persistent_context(
            profile, executable_path=CHROMIUM, headless=True, args=CHROMIUM_ARGS,
            viewport={"width": 1500, "height": 1000}, timeout=60_000)
        try:
            page = context.pages[0] if context.pages else context.new_page()
            page.set_default_timeout(120_000)
            page.route("**/*", lambda r: r.continue_() if r.request.url.startswith(
                ("http://127.0.0.1", "ws://127.0.0.1", "data:", "blob:")) else r.abort())
            page.add_init_script(INIT_JS)
            t0 = time.perf_counter()
            page.goto(server.url)
            page.wait_for_selector(".fp-results td", timeout=180_000)
            load_s = time.perf_counter() - t0
            page.wait_for_timeout(1500)
            assert page.evaluate(SETUP_JS) == "ok"
            cdp = context.new_cdp_session(page)
            cdp.send("Performance.enable")
            browser = [p for p in _tree(os.getpid()) if "chrom" in _cmd(p) and "--type=" not in _cmd(p)
                       and profile in _cmd(p)]
            chromium = _tree(browser[0]) if browser else []
            pg = _Page(page, cdp, server, chromium)
            pg.select_kind("hertz")
            pg.change("149um", "hertz 149um")  # the first change after the choice of model: untimed
            results: dict[str, Any] = {"page_load_s": load_s}
            new = [pg.change(f"{150 + k}um", f"hertz {150 + k}um") for k in range(repeats)]
            results["new Hertz design"] = _summary(new)
            for v in ("170um", "172um"):  # first visits, untimed
                pg.change(v, f"hertz {v}")
            back = [pg.change(v, f"hertz {v}") for v in ["170um", "172um"] * ((repeats + 1) // 2)]
            results["back to a computed Hertz design"] = _summary(back[:max(repeats, 2)])
            pg.select_kind("both")
            pg.run_bem("175um")
            pg.run_bem("180um")
            bem = [pg.change(v, f"bem {v}") for v in ["175um", "180um"] * ((repeats + 1) // 2)]
            results["back to a computed BEM design"] = _summary(bem[:max(repeats, 2)])
            results["raw"] = {"new Hertz design": new, "back to a computed Hertz design": back,
                              "back to a computed BEM design": bem}
            return results
        finally:
            context.close()
    finally:
        pw.stop()
        server.stop()
        shutil.rmtree(tmp, ignore_errors=True)


def _cmd(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
    except OSError:
        return ""
