"""The ``fingerpad`` command line: one thin module per command.

Each module parses its options, calls the library once and prints:

``solve`` (:mod:`.solve`), ``textures`` (:mod:`.textures`), ``predict`` and ``run-default``
(:mod:`.predict`), ``fingers`` and ``finger-models`` (:mod:`.fingers`), ``analyse`` and
``simulate-measurement`` (:mod:`.measure`).

Every quantity accepts plain SI numbers or unit suffixes (``50um``, ``0.3MPa``, ``20kPa``).

Exit codes
----------
0
    Success.
1
    Every solve ran and all outputs were written, but at least one solve did not reach its
    tolerance (a warning names it; ``"converged": false`` in the JSON).
2
    A user error (bad option value, unknown unit, unreadable file, ...): one line
    ``error: <message>`` on stderr, nothing written.

Start-up is kept short: command modules import only Typer and light modules at import time;
the numerics load inside the commands.
"""

from __future__ import annotations

import sys
from typing import Annotated

import typer

from .._version import __version__
from . import fingers, measure, predict, solve, textures

app = typer.Typer(
    name="fingerpad",
    help="Finger-pad contact and tactile friction on micro-textured surfaces (SI units; unit suffixes such as "
         "50um, 0.3MPa accepted).",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_show_locals=False,
)

for _module in (solve, textures, predict, fingers, measure):
    _module.register(app)


def _version_callback(value: bool) -> None:
    if value:
        sys.stdout.write(f"fingerpad {__version__}\n")
        raise typer.Exit(0)


@app.callback()
def _root(
    version: Annotated[
        bool, typer.Option("--version", help="Show the version and exit.", is_eager=True, callback=_version_callback)
    ] = False,
) -> None:
    """Finger-pad contact on micro-textured surfaces (SI units; unit suffixes such as 50um, 0.3MPa)."""


def main() -> None:
    """Console-script entry point (``fingerpad``)."""
    app()


__all__ = ["app", "main"]
