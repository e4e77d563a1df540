"""The ``fingerpad`` command line: one thin module per command.

Each module parses its options, calls the library once and prints:

``solve`` (:mod:`.solve`), ``textures`` (:mod:`.textures`), ``predict`` and ``run-default``
(:mod:`.predict`), ``fingers`` and ``finger-models`` (:mod:`.fingers`), ``analyse`` and
``simulate-measurement`` (:mod:`.measure`), ``cite`` (:mod:`.cite`).

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
130
    Interrupted (Ctrl-C, SIGTERM): one line ``interrupted: nothing written`` on stderr (a sweep
    says how many points its store kept).

Start-up is kept short: command modules import only Typer and light modules at import time;
the numerics load inside the commands.
"""

from __future__ import annotations

import re
import sys
from typing import Annotated, Any

import typer
from typer.core import TyperGroup

from .._version import __version__
from ..errors import FingerpadError, one_line
from . import cite, compare, deflection, design, explore, fingers, measure, predict, solve, sweep, textures
from . import common
from .common import EXIT_INTERRUPTED, EXIT_USER_ERROR, report_interrupt


#: What Rich reads as a markup tag (its own pattern): ``[columns]`` in a help text would vanish.
_RICH_TAG = re.compile(r"(\\*)(\[[a-z#/@][^[]*?])")


def escape_markup(text: str) -> str:
    """``text`` with every bracketed word kept when Rich renders the help (``[sweep]``, ``[units]``)."""
    return _RICH_TAG.sub(lambda m: m.group(1) * 2 + "\\" + m.group(2), text)


def _escape_help(command: Any) -> None:
    """Help texts are plain text: escape them once for Typer's Rich formatting."""
    for attr in ("help", "short_help", "epilog"):
        text = getattr(command, attr, None)
        if isinstance(text, str) and "[" in text:
            setattr(command, attr, escape_markup(text))
    for param in getattr(command, "params", []):
        text = getattr(param, "help", None)
        if isinstance(text, str) and "[" in text:
            param.help = escape_markup(text)
    for sub in getattr(command, "commands", {}).values():
        _escape_help(sub)


class _OneLineErrors(TyperGroup):
    """Typer's own usage errors (a missing value, an unknown option) as one ``error:`` line on
    stderr and exit code 2, like every other user mistake, instead of a framed panel.

    Help texts are shown as written: a bracketed word is not taken for Rich markup."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        _escape_help(self)

    def _given_twice(self, args: list[Any]) -> None:
        """An option that takes one value, given twice (``--grid 16 ... --grid 32``): Click keeps
        the last silently; here it is a usage error, as a contradiction is."""
        args = [str(a) for a in args]  # Python callers (tests, scripts) may pass paths or numbers
        command = self.commands.get(args[0]) if args else None
        if command is None:
            return
        seen: dict[Any, str] = {}
        for i, token in enumerate(args[1:], 1):
            if token == "--":
                break
            for param in getattr(command, "params", []):
                if getattr(param, "multiple", True) or getattr(param, "is_flag", True) or getattr(param, "count", False):
                    continue
                opts = [*getattr(param, "opts", ()), *getattr(param, "secondary_opts", ())]
                hit = next((o for o in opts if token == o or (o.startswith("--") and token.startswith(o + "="))), None)
                if hit is None:
                    continue
                value = token.split("=", 1)[1] if "=" in token else (args[i + 1] if i + 1 < len(args) else "")
                if param.name in seen:
                    raise FingerpadError(f"{hit} is given twice ({seen[param.name]} and {value}): give it once "
                                         f"(see 'fingerpad {command.name} --help')")
                seen[param.name] = value

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True, **extra):  # noqa: ANN001
        common.reset_interrupt()
        try:
            self._given_twice(list(sys.argv[1:] if args is None else args))
            rv = super().main(args=args, prog_name=prog_name, complete_var=complete_var, standalone_mode=False,
                              **extra)
            code = rv if isinstance(rv, int) else 0
            if code == EXIT_INTERRUPTED:  # Typer turns Ctrl-C (and SIGTERM, see main) into exit code 130
                report_interrupt()
        except typer.Abort:
            report_interrupt()
            code = EXIT_INTERRUPTED
        except FingerpadError as exc:  # a usage error found before Click parses (_given_twice)
            sys.stderr.write(f"error: {one_line(str(exc))}\n")
            code = EXIT_USER_ERROR
        except typer.TyperException as exc:
            if type(exc).__name__ == "NoArgsIsHelpError":  # `fingerpad` alone: the help, as usual
                exc.show()  # type: ignore[attr-defined]
                code = getattr(exc, "exit_code", EXIT_USER_ERROR)
            else:
                message = exc.format_message() if hasattr(exc, "format_message") else str(exc)
                ctx = getattr(exc, "ctx", None)
                where = f" (see '{ctx.command_path} --help')" if ctx is not None else ""
                sys.stderr.write(f"error: {one_line(message)}{where}\n")
                code = getattr(exc, "exit_code", EXIT_USER_ERROR)
        if standalone_mode:
            sys.exit(code)
        return code


#: The command modules, in the order ``fingerpad --help`` lists their commands.
_MODULES = (solve, textures, predict, compare, fingers, measure, sweep, design, deflection, explore, cite)


def _version_callback(value: bool) -> None:
    if value:
        sys.stdout.write(f"fingerpad {__version__}\n")
        raise typer.Exit(0)


def _root(
    version: Annotated[
        bool, typer.Option("--version", help="Show the version and exit.", is_eager=True, callback=_version_callback)
    ] = False,
) -> None:
    """Finger-pad contact on micro-textured surfaces (SI units; unit suffixes such as 50um, 0.3MPa)."""


def _make_app(modules: tuple[Any, ...]) -> typer.Typer:
    """The ``fingerpad`` group holding the commands of ``modules``."""
    made = typer.Typer(
        cls=_OneLineErrors,
        name="fingerpad",
        help="Finger-pad contact and tactile friction on micro-textured surfaces (SI units; unit suffixes such as "
             "50um, 0.3MPa accepted).",
        no_args_is_help=True,
        add_completion=False,
        pretty_exceptions_show_locals=False,
    )
    for module in modules:
        module.register(made)
    made.callback()(_root)
    return made


#: Every command (the Python API's entry point, and what ``fingerpad --help`` lists).
app = _make_app(_MODULES)

#: Command name -> the module that registers it. Registering is cheap; what costs is Typer turning
#: every registered function into a Click command (reading ~300 annotated parameters), which it
#: does on every start: ~0.05 s of a 0.7 s ``fingerpad solve`` (issue 23). ``main`` therefore
#: builds a group holding only the command asked for; it behaves as the full group for that
#: command (same name, path, options, errors and exit codes).
_COMMAND_MODULE: dict[str, Any] = {
    info.name: module for module in _MODULES for info in _make_app((module,)).registered_commands
}


def app_for(args: list[str]) -> typer.Typer:
    """The group to run for the command-line arguments ``args``: the named command's alone when
    ``args`` starts with a command name, else every command (``--help``, ``--version``, a typo,
    which gets Click's suggestions)."""
    module = _COMMAND_MODULE.get(args[0]) if args else None
    return app if module is None else _make_app((module,))


def _terminate(signum: int, frame: object) -> None:
    """SIGTERM (a killed job, a timeout) unwinds like Ctrl-C, so that staged outputs are removed."""
    raise KeyboardInterrupt


def main() -> None:
    """Console-script entry point (``fingerpad``)."""
    import gc
    import os
    import signal

    # NumPy's OpenBLAS starts a thread per core when NumPy is imported, and each busy-waits about
    # 2^28 cycles (~0.1 s) before it sleeps, on every start and after every threaded BLAS call:
    # 0.04-0.07 s of CPU per command and per worker process, taken from the solver's FFT threads
    # on a small machine (issue 23). 2^4 cycles makes them sleep at once; a later BLAS call wakes
    # them (microseconds). It changes no result. Set before NumPy loads (the commands import it
    # lazily); a value the user set wins.
    os.environ.setdefault("OPENBLAS_THREAD_TIMEOUT", "4")
    signal.signal(signal.SIGTERM, _terminate)
    try:
        app_for(sys.argv[1:])()
    finally:
        # The interpreter's shutdown runs the cyclic garbage collector over every object still
        # alive (NumPy, Typer, Rich, the solver's caches): 0.03-0.06 s of a 0.6 s `solve`
        # (issue 23). Frozen objects are left to the process's end. Nothing is lost: outputs
        # are written and closed by then, and atexit handlers and finalizers registered with
        # weakref.finalize (temporary folders, worker pools) still run.
        gc.freeze()


__all__ = ["app", "main"]
