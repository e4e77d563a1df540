"""``fingerpad explore``: the texture design explorer, a local web app (docs/explorer.md).

Panel and Bokeh are imported when the command runs, never at import: ``fingerpad --help`` stays fast.
"""

from __future__ import annotations

from typing import Annotated

import typer

from .common import say, stderr_console, user_errors


def explore(
    sweep: Annotated[str | None, typer.Option("--sweep", metavar="RESULTS.zarr",
                                              help="A sweep results store (fingerpad sweep): adds the design-map "
                                                   "view.")] = None,
    port: Annotated[int, typer.Option("--port", metavar="N", min=0, max=65535,
                                      help="TCP port (default: a free one).")] = 0,
    host: Annotated[str, typer.Option("--host", metavar="ADDRESS",
                                      help="Address to listen on (default 127.0.0.1, this machine only; any other "
                                           "exposes the explorer to the network, with a warning).")] = "127.0.0.1",
    no_browser: Annotated[bool, typer.Option("--no-browser", help="Do not open the page in a browser.")] = False,
    max_upload: Annotated[int, typer.Option("--max-upload", metavar="MIB", min=1, max=1024,
                                            help="Size limit of uploaded measured maps, MiB (default 20).")] = 20,
    population: Annotated[list[str] | None, typer.Option(
        "--population", metavar="NAME|FILE|DIR",
        help="A population of fingers the page may choose besides the presets: a TOML file with a [population] "
             "table or a folder written by fingerpad analyse (docs/population.md); read once here, the page "
             "names it by its label; repeatable.")] = None,
) -> None:
    """Explore texture designs in a browser: inputs with units, live curves, BEM in the background.

    Serves on http://127.0.0.1:PORT/ (printed) until Ctrl+C; every asset comes from the installed
    packages (no network needed). Needs the optional dependencies: pip install 'fingerpad[explore]'.
    """
    with user_errors():
        if host != "127.0.0.1":
            say(stderr_console(), f"warning: --host {host}: the explorer is reachable from other machines and "
                                  "anyone who reaches it can run computations here and upload files (no login)")
        from ..explore.server import serve

        serve(sweep=sweep, port=port, host=host, open_browser=not no_browser, max_upload_mb=max_upload,
              populations=population or ())


def register(app: typer.Typer) -> None:
    app.command("explore")(explore)
