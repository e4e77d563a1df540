"""The explorer at a designer's pace, in a real browser (issue 37; ``bench_explorer.py``).

A designer does not pause between changes: they open the page and change something at once, go
back and forth between two candidates as soon as the numbers appear, type values in a burst,
drag a slider. Each case runs on the served explorer (``fingerpad explore``, the default page:
caps, model ``both``, the BEM not run, so the Hertz numbers are shown) in Debian's headless
Chromium, timed in the page (``performance.now()``) from the change (the spacing field's new text
and its ``change`` event, what typing and Enter do; or the slider's drag) to the moment the
page's numbers are those of the design entered: the critical load and the zone map's
``A_re / A_fr`` (their full-precision ``data-value``) equal what ``fingerpad.explore.jobs.run_data``
gives for that study in this process, i.e. what ``fingerpad predict`` prints for it.

Cases (the rows of issue 37's goal table):

* **first change**: a fresh server and browser, the page opened, ``--first-wait`` seconds
  (default 10), then 175 -> 240 um; ``--first-runs`` runs (default 3);
* **back and forth**: 240 <-> 300 um, both shown before (numbers and maps), each change entered
  as soon as the numbers of the last one show; median and maximum of 12;
* **computed after new**: a design shown before entered as soon as a new one's numbers show
  (175 after 260, 240 after 280, ...): 6 pairs;
* **burst**: five changes 0.3 s apart (designs never shown), then a sixth: its numbers' time, and
  whether they are the sixth design's; 3 bursts. The server's CPU seconds of work for designs no
  longer shown (``$FINGERPAD_EXPLORE_WORKLOG``: each piece of background work, its thread's CPU
  time and whether its design was still shown when it ended) per burst;
* **slider**: the spacing slider dragged over 20 values in 3 s (the mouse, 150 ms a value):
  the numbers updates the page shows during the drag per second, and after the release the time
  until it shows the numbers of where the slider stopped;
* **BEM on every change**: with the box ticked and a 256-point cell (a run of many seconds), a change
  while the run is under way: the new design's Hertz numbers, and when the run of the design
  before ended after the change (the work log's record of it).

With ``server_path`` the server runs another source tree (``PYTHONPATH``), e.g. the code before
issue 37 (which has no slider: that row then reads "no slider").
"""

from __future__ import annotations

import json
import os
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _explorer_browser import CHROMIUM, CHROMIUM_ARGS, INIT_JS, _cmd, _cpu_s, _Server, _tree  # noqa: E402

SPACING = "fp-field-texture-spacing"

# helpers in the page: the numbers shown, a change and the wait for given numbers
HANDS_JS = """
() => {
  window.fpView = cls => [...Bokeh.index.all_views()].find(v => (v.model.css_classes ?? []).includes(cls));
  window.fpKeyed = () => {
    const out = {};
    for (const e of fpView('fp-summary').shadow_el.querySelectorAll('.fp-num')) out[e.dataset.key] = e.dataset.value;
    return out;
  };
  // every change of the numbers shown, with its time (the summary's DOM, watched)
  window.fpLog = [];
  let last = JSON.stringify(fpKeyed());
  new MutationObserver(() => {
    const now = JSON.stringify(fpKeyed());
    if (now !== last) { last = now; fpLog.push([performance.now(), fpKeyed()]); }
  }).observe(fpView('fp-summary').shadow_el, {subtree: true, childList: true, characterData: true, attributes: true});
  window.fpIs = (want) => { const k = fpKeyed(); return Object.keys(want).every(key => k[key] === want[key]); };
  window.fpInput = (cls) => fpView(cls).shadow_el.querySelector('input');
  window.fpEnter = (cls, value) => {
    const input = fpInput(cls);
    input.value = value;
    input.dispatchEvent(new Event('change'));
    return performance.now();
  };
  const sleep = ms => new Promise(r => setTimeout(r, ms));
  // the time from t0 to the numbers taking the values ``want``: the observer's record of the
  // change (read every 10 ms: the page's DOM is not queried while it works), 0 if they had them
  const matches = (k, want) => Object.keys(want).every(key => k[key] === want[key]);
  window.fpWait = async (want, t0, maxMs, from) => {
    if (fpIs(want)) return 0;
    while (performance.now() - t0 <= maxMs) {
      const hit = fpLog.slice(from).reverse().find(([t, k]) => matches(k, want));
      if (hit && matches(fpLog[fpLog.length - 1][1], want)) return Math.max(0, hit[0] - t0) / 1000;
      await sleep(10);
    }
    return null;
  };
  window.fpChangeTo = async (cls, value, want, maxMs) => {
    const from = fpLog.length;
    return fpWait(want, fpEnter(cls, value), maxMs, from);
  };
  window.fpBurst = async (cls, values, gapMs, want, maxMs) => {
    for (const v of values.slice(0, -1)) { fpEnter(cls, v); await sleep(gapMs); }
    const from = fpLog.length;
    const t0 = fpEnter(cls, values[values.length - 1]);
    const s = await fpWait(want, t0, maxMs, from);
    return {numbers_s: s, shown: fpKeyed()};
  };
  window.fpQuiet = async (ms, maxMs) => {
    const t0 = performance.now();
    let n = fpNet.recv.length, since = performance.now();
    while (performance.now() - since < ms && performance.now() - t0 < maxMs) {
      await sleep(20);
      if (fpNet.recv.length !== n) { n = fpNet.recv.length; since = performance.now(); }
    }
  };
  return 'ok';
}
"""


class Expect:
    """The numbers the page must show for a spacing: ``run_data`` of the page's study."""

    def __init__(self) -> None:
        self.base: dict[str, Any] | None = None
        self._memo: dict[str, dict[str, str]] = {}

    def set_base(self, toml_text: str) -> None:
        import tomllib

        self.base = tomllib.loads(toml_text)

    def __call__(self, spacing: str, grid: int | None = None) -> dict[str, str]:
        if (spacing, grid) not in self._memo:
            import copy

            from fingerpad.explore.jobs import run_data
            from fingerpad.study.outputs import prediction_json

            data = copy.deepcopy(self.base)
            data["texture"]["spacing"] = spacing
            data.setdefault("model", {})["kind"] = "hertz"  # what a page with the BEM pending shows
            if grid is not None:
                data["model"]["grid"] = grid
            payload = prediction_json(run_data(data))
            self._memo[spacing, grid] = {"critical_load_hertz": repr(float(payload["critical_load"]["hertz"])),
                                         "zones_area_ratio": repr(float(payload["zones"]["area_ratio"]))}
        return self._memo[spacing, grid]


class _Browser:
    """A served explorer and a fresh headless Chromium on its page."""

    def __init__(self, pw: Any, cache: str, env: dict[str, str]) -> None:
        self.tmp = tempfile.mkdtemp(prefix="fingerpad-bench-hands-", dir=cache)
        self.worklog = os.path.join(self.tmp, "worklog.jsonl")
        self.server = _Server({"FINGERPAD_CACHE": os.path.join(cache, "cells"), "TMPDIR": self.tmp,
                               "FINGERPAD_EXPLORE_WORKLOG": self.worklog, **env})
        self.context = pw.chromium.launch_persistent_context(
            os.path.join(self.tmp, "chromium-profile"), executable_path=CHROMIUM, headless=True,
            args=CHROMIUM_ARGS, viewport={"width": 1500, "height": 1000}, timeout=60_000, accept_downloads=True)
        self.page = self.context.pages[0] if self.context.pages else self.context.new_page()
        self.page.set_default_timeout(120_000)
        self.page.route("**/*", lambda r: r.continue_() if r.request.url.startswith(
            ("http://127.0.0.1", "ws://127.0.0.1", "data:", "blob:")) else r.abort())
        self.page.add_init_script(INIT_JS)
        profile = os.path.join(self.tmp, "chromium-profile")
        main = [p for p in _tree(os.getpid()) if "chrom" in _cmd(p) and "--type=" not in _cmd(p) and profile in _cmd(p)]
        self.chromium = main[0] if main else None

    def cpu(self) -> tuple[float, float]:
        """CPU seconds so far of the server and of Chromium's processes."""
        return _cpu_s([self.server.proc.pid]), _cpu_s(_tree(self.chromium)) if self.chromium else float("nan")

    def open(self) -> float:
        t0 = time.perf_counter()
        self.page.goto(self.server.url)
        self.page.wait_for_selector(".fp-results td", timeout=180_000)
        return time.perf_counter() - t0

    def setup(self) -> None:
        assert self.page.evaluate(HANDS_JS) == "ok"

    def study_toml(self) -> str:
        with self.page.expect_download(timeout=60_000) as info:
            self.page.locator(".fp-export-toml button").click()
        return Path(info.value.path()).read_text()

    def change(self, value: str, want: dict[str, str], max_s: float = 60.0) -> float:
        s = self.page.evaluate("([c, v, w, m]) => fpChangeTo(c, v, w, m)", [SPACING, value, want, max_s * 1000])
        if s is None:
            raise RuntimeError(f"the page did not show the numbers of {value} within {max_s} s: {self.keyed()}")
        return float(s)

    def keyed(self) -> dict[str, str]:
        return self.page.evaluate("() => fpKeyed()")

    def quiet(self, seconds: float = 1.0, max_s: float = 60.0) -> None:
        self.page.evaluate("([q, m]) => fpQuiet(q, m)", [seconds * 1000, max_s * 1000])

    def records(self, since: float) -> list[dict[str, Any]]:
        """The work log's records since ``since`` (time.time())."""
        if not os.path.exists(self.worklog):
            return []
        return [r for r in map(json.loads, Path(self.worklog).read_text().splitlines()) if r["t"] >= since]

    def superseded_cpu(self, since: float) -> tuple[float | None, float | None]:
        """CPU seconds of background work ended since ``since`` (time.time()): for designs no
        longer shown, and in all (``None``: the server keeps no work log, code before issue 37)."""
        waste = total = 0.0
        if not os.path.exists(self.worklog):
            return None, None
        for line in Path(self.worklog).read_text().splitlines():
            rec = json.loads(line)
            if rec["t"] >= since:
                total += rec["cpu_s"]
                waste += rec["cpu_s"] if rec["superseded"] else 0.0
        return waste, total

    def close(self) -> None:
        try:
            self.context.close()
        finally:
            self.server.stop()
            shutil.rmtree(self.tmp, ignore_errors=True)


def _first_change(pw: Any, cache: str, env: dict[str, str], expect: Expect, runs: int, wait_s: float) -> list[float]:
    out = []
    for _ in range(runs):
        b = _Browser(pw, cache, env)
        try:
            b.open()
            b.page.wait_for_timeout(int(1000 * wait_s))
            b.setup()
            out.append(b.change("240um", expect("240um")))
        finally:
            b.close()
    return out


def _slider(b: _Browser, expect: Expect, values: int = 20, seconds: float = 3.0) -> dict[str, Any] | None:
    """Drag the spacing slider over ``values`` values in ``seconds``: numbers updates per second
    during the drag, and the time from the release to the numbers of where it stopped."""
    slider = b.page.locator(f".{SPACING}-slider input")
    if slider.count() == 0:
        return None
    box = slider.bounding_box()
    lo, hi = float(slider.get_attribute("min")), float(slider.get_attribute("max"))
    step = float(slider.get_attribute("step"))
    thumb = 8.0  # Chromium's range thumb: half its width at each end of the track

    def x_of(v: float) -> float:
        return box["x"] + thumb + (v - lo) / (hi - lo) * (box["width"] - 2 * thumb)

    y = box["y"] + box["height"] / 2
    start = float(slider.input_value())
    targets = [start + (k + 1) * step for k in range(values)]
    b.page.mouse.move(x_of(start), y)
    n0 = b.page.evaluate("() => fpLog.length")
    t_down = b.page.evaluate("() => performance.now()")
    b.page.mouse.down()
    t_wall = time.perf_counter()
    for k, v in enumerate(targets):
        b.page.mouse.move(x_of(v), y)
        pause = t_wall + (k + 1) * seconds / values - time.perf_counter()
        if pause > 0:
            b.page.wait_for_timeout(int(1000 * pause))
    t_up = b.page.evaluate("() => performance.now()")
    b.page.mouse.up()
    b.quiet(1.0)
    final = b.page.locator(f".{SPACING} input").input_value()
    want = expect(final)
    if not b.page.evaluate("(w) => fpIs(w)", want):
        raise RuntimeError(f"after the drag the page shows {b.keyed()}, not the numbers of {final}")
    log = b.page.evaluate("(n) => fpLog.slice(n)", n0)
    during = [t for t, _ in log if t_down <= t <= t_up]
    last = max((t for t, k in log if all(k.get(key) == v for key, v in want.items())), default=t_up)
    return {"updates_per_s": len(during) / ((t_up - t_down) / 1000), "updates": len(during),
            "drag_s": (t_up - t_down) / 1000, "after_release_s": max(0.0, (last - t_up) / 1000),
            "final": final, "values": values}


def _bem_on_every_change(b: _Browser, expect: Expect) -> dict[str, Any] | None:
    """A change during a BEM run of the design before (BEM on every change): the new Hertz
    numbers' time, and how long after the change that run ended."""
    from playwright.sync_api import expect as expect_

    if not os.path.exists(b.worklog):
        return None  # a server without a work log: when the run ended cannot be told
    b.page.evaluate("() => fpEnter('fp-field-model-grid', '256')")
    b.change("203um", expect("203um", 256))
    b.page.locator(".fp-auto-bem input").check()
    expect_(b.page.locator(".fp-job-running").first).to_be_visible(timeout=60_000)
    b.page.wait_for_timeout(1000)
    if not b.page.locator(".fp-job-running").count():
        raise RuntimeError("the BEM run ended before the change that was to cancel it")
    since = time.time()
    numbers = b.change("207um", expect("207um", 256))
    ended = stopped = None
    for _ in range(600):
        done = [r for r in b.records(since) if r["kind"] == "bem" and r["superseded"]]
        if done:
            ended, stopped = done[0]["t"] - since, done[0].get("stopped_s")
            break
        b.page.wait_for_timeout(100)
    b.page.locator(".fp-auto-bem input").uncheck()
    cancel = b.page.locator(".fp-cancel-bem button")
    if cancel.is_enabled():
        cancel.click()
    b.page.evaluate("() => fpEnter('fp-field-model-grid', '')")
    b.quiet(1.0)
    return {"numbers_s": numbers, "run_ended_s": ended, "stopped_s": stopped}


def run(cache: str, *, first_runs: int = 3, first_wait: float = 10.0, server_path: str | None = None) -> dict[str, Any]:
    """Every case; per case the times (s) and what they are of."""
    from playwright.sync_api import sync_playwright

    env = {"PYTHONPATH": server_path} if server_path else {}
    expect = Expect()
    pw = sync_playwright().start()
    results: dict[str, Any] = {}
    try:
        b = _Browser(pw, cache, env)
        try:
            b.open()
            expect.set_base(b.study_toml())
            b.setup()
            results["first change"] = _first_change(pw, cache, env, expect, first_runs, first_wait)
            for v in ("240um", "300um", "175um"):  # shown once, maps too
                b.change(v, expect(v))
                b.quiet(1.0)
            cpu0 = b.cpu()
            back = [b.change(v, expect(v)) for v in ["240um", "300um"] * 6]
            b.quiet(1.0)
            cpu1 = b.cpu()
            results["back and forth"] = back
            results["back and forth CPU per change, server / Chromium"] = [(y - x) / len(back) for x, y in zip(cpu0, cpu1)]
            b.quiet(1.0)
            pairs = [("260um", "175um"), ("280um", "240um"), ("265um", "300um"), ("285um", "175um"),
                     ("270um", "240um"), ("290um", "300um")]
            after_new = []
            for new, old in pairs:
                b.change(new, expect(new))
                after_new.append(b.change(old, expect(old)))
            results["computed after new"] = after_new
            b.quiet(1.0)
            bursts, waste, total, stale = [], [], [], 0
            for k in range(3):
                values = [f"{310 + 10 * k + j}um" for j in range(6)]
                want = expect(values[-1])
                since = time.time()
                r = b.page.evaluate("([c, v, g, w, m]) => fpBurst(c, v, g, w, m)", [SPACING, values, 300, want, 60_000])
                if r["numbers_s"] is None:
                    stale += 1
                bursts.append(r["numbers_s"])
                b.quiet(1.5)  # the last design's background work ends (shown), any other's is counted
                w, t = b.superseded_cpu(since)
                waste.append(w)
                total.append(t)
            results["burst"] = bursts
            results["burst stale"] = stale
            results["burst superseded CPU"] = waste
            results["burst background CPU"] = total
            b.change("200um", expect("200um"))
            b.quiet(1.0)
            results["slider"] = _slider(b, expect)
            results["bem on every change"] = _bem_on_every_change(b, expect)
        finally:
            b.close()
    finally:
        pw.stop()
    return results


def rows(r: dict[str, Any]) -> list[tuple[str, str, str, str, bool | None]]:
    """The goal table: (case, today in issue 37, measured, goal, met)."""
    def span(xs: list[float]) -> str:
        return f"{min(xs):.2f}-{max(xs):.2f} s ({len(xs)} runs)"

    first, back, after, burst = r["first change"], r["back and forth"], r["computed after new"], r["burst"]
    server, chromium = r["back and forth CPU per change, server / Chromium"]
    ok_burst = [x for x in burst if x is not None]
    out = [
        ("first change after the page opened (175 -> 240 um)", "2.6-4.8 s", span(first), "<= 0.5 s",
         max(first) <= 0.5),
        ("back and forth 240 <-> 300 um, no pause: median / max", "0.54 / 0.95 s",
         f"{statistics.median(back):.2f} / {max(back):.2f} s (CPU per change: server {server:.3f} s, Chromium "
         f"{chromium:.2f} s)", "<= 0.3 / 0.5 s",
         statistics.median(back) <= 0.3 and max(back) <= 0.5),
        ("a computed design right after a new one (not a goal row)", "1.2-2.1 s",
         f"{min(after):.2f}-{max(after):.2f} s (median {statistics.median(after):.2f}, {len(after)} pairs)",
         "-", None),
        ("burst of 6 changes 0.3 s apart: the last one's numbers", "0.27-0.38 s, right numbers",
         (span(ok_burst) if ok_burst else "-") + (f", {r['burst stale']} stale" if r["burst stale"] else
                                                  ", the last design's numbers every time"),
         "<= 0.5 s, never stale", bool(ok_burst) and max(ok_burst) <= 0.5 and not r["burst stale"]),
    ]
    s = r["slider"]
    if s is None:
        out.append(("slider drag over 20 values in 3 s", "no slider", "no slider", ">= 3 updates/s, <= 0.5 s", None))
    else:
        out.append(("slider drag over 20 values in 3 s", "no slider",
                    f"{s['updates_per_s']:.1f} updates/s ({s['updates']} in {s['drag_s']:.1f} s), last value's "
                    f"numbers {s['after_release_s']:.2f} s after release",
                    ">= 3 updates/s, <= 0.5 s", s["updates_per_s"] >= 3 and s["after_release_s"] <= 0.5))
    w = r["burst superseded CPU"]
    if None in w:
        out.append(("server CPU on designs no longer shown, per burst of 6", "not measured", "not measured (no work "
                    "log in this server)", "<= 0.1 s", None))
    else:
        out.append(("server CPU on designs no longer shown, per burst of 6", "not measured",
                    f"{max(w):.3f} s (bursts: {', '.join(f'{x:.3f}' for x in w)}; background work in all "
                    f"{', '.join(f'{x:.2f}' for x in r['burst background CPU'])} s)", "<= 0.1 s", max(w) <= 0.1))
    bem = r.get("bem on every change")
    if bem is not None:
        ended = "did not end" if bem["run_ended_s"] is None else (
            f"{bem['run_ended_s']:.2f} s after the change" + ("" if bem.get("stopped_s") is None else
                                                              f", {1000 * bem['stopped_s']:.0f} ms after its cancel"))
        out.append(("BEM on every change (grid 256): a change during the run", "not measured",
                    f"Hertz numbers {bem['numbers_s']:.2f} s; the run before ended {ended}",
                    "numbers at once, the run cancelled", bem["run_ended_s"] is not None))
    return out


def _key(r: dict[str, Any]) -> dict[str, float | None]:
    """One number per row of :func:`rows` (by its case), for the ratio of two runs: the median
    time of the row's changes (s), or for the slider its updates per second."""
    med = lambda xs: statistics.median(xs) if xs else None  # noqa: E731
    out: dict[str, float | None] = {}
    for case, *_ in rows(r):
        if case.startswith("first change"):
            out[case] = med(r["first change"])
        elif case.startswith("back and forth"):
            out[case] = med(r["back and forth"])
        elif case.startswith("a computed design"):
            out[case] = med(r["computed after new"])
        elif case.startswith("burst"):
            out[case] = med([x for x in r["burst"] if x is not None])
        elif case.startswith("slider") and r["slider"] is not None:
            out[case] = r["slider"]["updates_per_s"]
    return out


def rows_against(before: dict[str, Any], now: dict[str, Any]) -> list[tuple[str, str, str, str, str, str, bool | None]]:
    """The goal table with the code before measured in the same run: (case, issue 37's numbers,
    before (this run), now, ratio, goal, met). The ratio is before / now of the medians (times),
    now / before for the slider's updates per second; ``-`` where the code before has no such
    case."""
    then = {case: measured for case, _, measured, _, _ in rows(before)}
    k0, k1 = _key(before), _key(now)
    out = []
    for case, today, measured, goal, met in rows(now):
        a, b = k0.get(case), k1.get(case)
        if a is None or b is None or a <= 0 or b <= 0:
            ratio = "-"
        else:
            ratio = f"{(b / a if case.startswith('slider') else a / b):.1f}x"
        out.append((case, today, then.get(case, "-"), measured, ratio, goal, met))
    return out
