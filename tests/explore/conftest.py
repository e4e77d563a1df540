"""Fixtures of the explorer's tests: a synthetic sweep store, the explorer served on 127.0.0.1,
a headless Chromium (Debian's /usr/bin/chromium) driven by Playwright, screenshots.

Browser tests skip cleanly when Panel/Bokeh, Playwright or Chromium are missing. Everything is
bounded in time: the server must announce its URL within 90 s, Playwright waits at most 60 s
for any element, and the server is stopped (SIGTERM, then SIGKILL) in the fixture's finaliser.
"""

from __future__ import annotations

import os
import queue
import re
import shutil
import signal
import subprocess
import sys
import threading
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from synthetic_sweep import synthetic_sweep  # noqa: E402

CHROMIUM = os.environ.get("FINGERPAD_CHROMIUM", "/usr/bin/chromium")
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def _browser_missing() -> str | None:
    import importlib.util

    for mod in ("panel", "bokeh", "playwright"):
        if importlib.util.find_spec(mod) is None:
            return f"{mod} is not installed (pip install 'fingerpad[explore]' playwright)"
    if not (os.path.isfile(CHROMIUM) and os.access(CHROMIUM, os.X_OK)):
        return f"no Chromium at {CHROMIUM} (apt-get install -y chromium)"
    return None


@pytest.fixture(scope="session")
def sweep_store(tmp_path_factory: pytest.TempPathFactory) -> Path:
    pytest.importorskip("zarr")
    return synthetic_sweep(tmp_path_factory.mktemp("sweep") / "results.zarr")


@pytest.fixture(scope="session")
def screenshot_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Where the browser tests save screenshots: $FINGERPAD_SCREENSHOTS or a temporary folder."""
    env = os.environ.get("FINGERPAD_SCREENSHOTS")
    folder = Path(env) if env else tmp_path_factory.mktemp("screenshots")
    folder.mkdir(parents=True, exist_ok=True)
    return folder


class Server:
    """``fingerpad explore --no-browser`` in a subprocess; ``url`` once it listens."""

    def __init__(self, args: list[str], tmpdir: Path | None = None) -> None:
        code = "import sys; from fingerpad.cli import main; sys.argv[0] = 'fingerpad'; main()"
        env = {**os.environ, "BOKEH_BROWSER": "none"}
        self.cache: Path | None = None
        if tmpdir is not None:  # the server's upload area is made in here (tests look into it)
            env["TMPDIR"] = str(tmpdir)
            # a unit-cell cache of its own: what the tests expect to compute is not already in
            # the user's cache from an earlier run (CI runs on a machine that has run the suite)
            self.cache = tmpdir / "cell-cache"
            env["FINGERPAD_CACHE"] = str(self.cache)
        self.tmpdir = tmpdir
        self.proc = subprocess.Popen([sys.executable, "-c", code, "explore", "--no-browser", *args],
                                     stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)
        self.lines: queue.Queue[str] = queue.Queue()
        self.output: list[str] = []
        threading.Thread(target=self._read, daemon=True).start()
        self.url = None
        try:
            while self.url is None:
                line = self.lines.get(timeout=90)
                match = re.search(r"serving on (http://127\.0\.0\.1:\d+/)", line)
                if match:
                    self.url = match.group(1)
        except queue.Empty:
            self.stop()
            raise RuntimeError("the explorer did not start within 90 s:\n" + "".join(self.output)) from None

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self.output.append(line)
            self.lines.put(line)

    def stop(self) -> None:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(timeout=15)


@pytest.fixture(scope="session")
def explorer(sweep_store: Path, tmp_path_factory: pytest.TempPathFactory) -> Server:
    """The explorer with the synthetic sweep, on a free port of 127.0.0.1 (its temporary files,
    the upload area among them, in a folder of the test session: ``explorer.tmpdir``)."""
    reason = _browser_missing()
    if reason:
        pytest.skip(reason)
    server = Server(["--sweep", str(sweep_store)], tmpdir=tmp_path_factory.mktemp("server-tmp"))
    yield server
    server.stop()


@pytest.fixture(scope="session")
def browser_context(explorer: Server, tmp_path_factory: pytest.TempPathFactory):
    from playwright.sync_api import expect, sync_playwright

    expect.set_options(timeout=30_000)  # a page update may take seconds on a 2-core machine
    pw = sync_playwright().start()
    profile = tmp_path_factory.mktemp("chromium-profile")
    context = pw.chromium.launch_persistent_context(
        str(profile), executable_path=CHROMIUM, headless=True, args=CHROMIUM_ARGS, accept_downloads=True,
        viewport={"width": 1500, "height": 1000}, timeout=60_000)
    context.set_default_timeout(60_000)
    yield context
    context.close()
    pw.stop()


@pytest.fixture(scope="session")
def page(browser_context, explorer: Server):
    """One page of the explorer for the session's browser tests (loading costs seconds); every
    request that leaves 127.0.0.1 is refused and recorded in ``page.external``."""
    pg = browser_context.new_page()
    pg.external = []

    def route(r):
        url = r.request.url
        if url.startswith(("http://127.0.0.1", "ws://127.0.0.1", "data:", "blob:")):
            r.continue_()
        else:
            pg.external.append(url)
            r.abort()

    pg.route("**/*", route)
    pg.goto(explorer.url)
    pg.wait_for_selector(".fp-results td")
    yield pg
    pg.close()
