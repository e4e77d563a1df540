"""Serving the explorer: a Panel (Bokeh) server on 127.0.0.1, every asset from installed packages.

The page's JavaScript and CSS (Bokeh, Panel and its bundled components) are served by the same
server from the installed packages (resources mode ``server``), never from a CDN: the explorer
works without a network.
"""

from __future__ import annotations

import os
import shutil
import signal
import sys
import tempfile
import webbrowser
from collections.abc import Callable, Sequence
from typing import Any

from ..errors import FingerpadError
from ..extras import require

__all__ = ["DEFAULT_HOST", "MAX_UPLOAD_MB", "serve"]

DEFAULT_HOST = "127.0.0.1"
#: Largest measured map that may be uploaded (MiB).
MAX_UPLOAD_MB = 20


def _check_installed() -> None:
    require("explore", modules=("panel", "bokeh"))


def serve(
    *,
    sweep: str | None = None,
    port: int = 0,
    host: str = DEFAULT_HOST,
    open_browser: bool = True,
    max_upload_mb: int = MAX_UPLOAD_MB,
    announce: Callable[[str], None] | None = None,
    populations: Sequence[str] = (),
) -> None:
    """Start the explorer and serve until interrupted (Ctrl+C).

    Parameters
    ----------
    sweep
        A sweep results store (Zarr folder) for the design-map view.
    port
        TCP port; 0 picks a free one.
    host
        Address to listen on (127.0.0.1: this machine only).
    open_browser
        Open the page in the default browser once serving.
    max_upload_mb
        Size limit of uploaded measured maps, MiB.
    announce
        Called with the page's URL once the server listens (default: print it).
    populations
        Populations the page may choose besides the presets: a preset name, a TOML file with a
        ``[population]`` table or a ``fingerpad analyse`` folder each
        (:func:`~fingerpad.population.sources.load_population`), read here, once; the page names
        them by label only.

    Raises
    ------
    FingerpadError
        Panel/Bokeh missing, an unreadable sweep store or population, a port in use, an absent
        device or FFT engine (:func:`~fingerpad.contact.greens.check_setup`).
    """
    _check_installed()
    from ..contact.greens import check_setup

    check_setup()  # an absent FINGERPAD_DEVICE or FFT engine: refused here, not at the first BEM run
    extra = server_populations(populations)  # a bad file is a user error before anything starts
    ds = None
    if sweep is not None:  # a bad store is a user error before anything starts
        from .sweepdata import open_sweep

        ds = open_sweep(sweep)
    os.environ.setdefault("BOKEH_RESOURCES", "server")  # assets from this server, never a CDN
    import panel as pn

    from .app import ExplorerApp, ServerState
    pn.config.inline = False
    upload_dir = tempfile.mkdtemp(prefix="fingerpad-explore-")
    state = ServerState(upload_dir=upload_dir, max_upload_bytes=int(max_upload_mb) * 2**20, sweep=ds,
                        sweep_path=None if sweep is None else os.path.abspath(sweep), extra_populations=extra)

    def page() -> Any:
        return ExplorerApp(state).page

    options: dict[str, Any] = {
        # an upload arrives in chunks of FileDropper.chunk_size (10 MB) as base64 over the websocket
        "websocket_max_message_size": 32 * 2**20,
    }
    if host != DEFAULT_HOST:
        options["websocket_origin"] = "*"
    try:
        server = pn.serve({"/": page}, port=port, address=host, show=False, start=False,
                          title="fingerpad explorer", **options)
    except OSError as exc:
        shutil.rmtree(upload_dir, ignore_errors=True)
        raise FingerpadError(f"cannot serve on {host}:{port}: {exc.strerror or exc}") from None
    shown_host = "127.0.0.1" if host in ("0.0.0.0", "") else host
    url = f"http://{shown_host}:{server.port}/"
    (announce or (lambda u: (sys.stdout.write(f"fingerpad explorer: serving on {u} (Ctrl+C stops it)\n"),
                             sys.stdout.flush())))(url)
    if open_browser:
        server.io_loop.add_callback(lambda: webbrowser.open(url))

    def stop(*_: Any) -> None:  # SIGTERM as SIGINT: stop the loop, then clean up below
        server.io_loop.asyncio_loop.call_soon_threadsafe(server.io_loop.stop)

    try:
        signal.signal(signal.SIGTERM, stop)
    except ValueError:  # not the main thread
        pass
    try:
        server.start()
        server.io_loop.start()
    except KeyboardInterrupt:
        pass
    finally:
        try:
            server.stop()
        except Exception:  # noqa: BLE001 -- already stopping
            pass
        shutil.rmtree(upload_dir, ignore_errors=True)


def server_populations(sources: Sequence[str]) -> dict[str, Any]:
    """The populations of ``fingerpad explore --population`` by the label the page shows: the
    population's name (a file's stem, a preset's name), made unique against the presets and each
    other by a suffix. Read once, here: the page can only choose among them by label."""
    from ..population.sources import load_population
    from ..population.presets import POPULATION_PRESETS

    out: dict[str, Any] = {}
    for source in sources:
        pop = load_population(source)
        if source in POPULATION_PRESETS:
            continue  # already a choice
        label, k = pop.name, 2
        while label in POPULATION_PRESETS or label in out or label == "none":
            label, k = f"{pop.name} ({k})", k + 1
        out[label] = pop
    return out
