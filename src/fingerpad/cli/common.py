"""What every command shares: one-line user errors, warnings as one line, consoles, option help.

Kept free of heavy imports: the command line's start-up (``fingerpad --help``) imports only
Typer, this module and the command modules.
"""

from __future__ import annotations

import contextlib
import sys
import warnings
from collections.abc import Callable, Iterator
from typing import Any, NoReturn

import typer

from ..errors import FingerpadError, describe_exception, one_line, printable

EXIT_UNCONVERGED = 1
EXIT_USER_ERROR = 2
EXIT_INTERRUPTED = 130

_interrupt_reported = False


def reset_interrupt() -> None:
    """Forget an earlier interrupt report (a new command starts)."""
    global _interrupt_reported
    _interrupt_reported = False


def report_interrupt(kept: str | None = None) -> None:
    """Say once, on one stderr line, that the command was interrupted and what it left:
    ``kept`` (e.g. the points a sweep stored), else nothing (outputs are staged and moved into
    place only when complete)."""
    global _interrupt_reported
    if not _interrupt_reported:
        _interrupt_reported = True
        sys.stderr.write(f"interrupted: {kept or 'nothing written'}\n")
        sys.stderr.flush()

#: Typer settings of commands that take a texture's own ``--NAME VALUE`` options.
EXTRA_ARGS = {"allow_extra_args": True, "ignore_unknown_options": True}


@contextlib.contextmanager
def user_errors() -> Iterator[None]:
    """Turn user errors into ``error: <message>`` on one stderr line and exit code 2.

    The command's outputs, once checked, are its own until it ends (:func:`fingerpad.locks.claims`):
    a second run naming one of them is refused before its work, naming this one."""
    from ..locks import claims

    try:
        with claims():
            yield
    except (FingerpadError, OSError) as exc:
        sys.stderr.write(f"error: {one_line(describe_exception(exc))}\n")
        sys.stderr.flush()
        raise typer.Exit(EXIT_USER_ERROR) from None
    except ImportError as exc:
        missing_extra(exc)


def missing_extra(exc: ImportError) -> NoReturn:
    """An optional package imported deep inside a command and not installed: the same
    ``error:`` line naming the extra as the command's own check gives (:mod:`fingerpad.extras`),
    exit code 2. Any other failed import is a broken installation and is raised as it is."""
    from ..extras import from_import_error

    converted = from_import_error(exc)
    if converted is None:
        raise exc
    sys.stderr.write(f"error: {one_line(str(converted))}\n")
    sys.stderr.flush()
    raise typer.Exit(EXIT_USER_ERROR) from None


#: Help of the adhesion options (solve, predict, sweep): the finger's fields ``work_of_adhesion``,
#: ``adhesion_range`` and ``adhesion_law`` (fingerpad.finger.FINGER_PARAMS, whose checks they pass).
ADHESION_HELP = {
    "--work-of-adhesion": "Work of adhesion w of skin on the texture's material, e.g. 0.05J/m2 (default 0: no "
                          "adhesion; a dry finger's is at most ~0.3-0.4 J/m2, docs/model.md 6.6).",
    "--adhesion-range": "Range of the adhesive interaction, with a unit (default 0.3nm; a range below a pixel is "
                        "regularised to the grid: the JKR limit, docs/model.md 6.6).",
    "--adhesion-law": "Adhesive interaction law: exponential (default) or maugis (Maugis-Dugdale).",
}
#: The finger fields the adhesion options set.
ADHESION_FIELDS = {"--work-of-adhesion": "work_of_adhesion", "--adhesion-range": "adhesion_range",
                   "--adhesion-law": "adhesion_law"}

#: Help of ``--device`` (solve, predict, sweep).
DEVICE_HELP = ("Where the contact solves run: cpu (NumPy, the default), cupy or torch (a CUDA GPU, with that "
               "library installed). Default: $FINGERPAD_DEVICE, else cpu.")


@contextlib.contextmanager
def device_option(device: str | None) -> Iterator[None]:
    """``--device`` (or ``FINGERPAD_DEVICE``) checked at once and set as ``FINGERPAD_DEVICE`` for
    the command's duration, so that every solver it builds, and the workers of a local sweep
    cluster (which inherit the environment), run there. A device that is absent is a
    :class:`~fingerpad.errors.SetupError` (one ``error:`` line inside :func:`user_errors`)."""
    import os

    from ..contact.device import device_namespace, device_setting

    from ..contact.greens import check_setup

    name, _ = device_setting(device)
    device_namespace(device)  # the library and a GPU are there, or the command stops here
    before = os.environ.get("FINGERPAD_DEVICE")
    os.environ["FINGERPAD_DEVICE"] = name
    try:
        check_setup()  # and the FFT settings, before any work (the one check every door asks)
        yield
    finally:
        if before is None:
            os.environ.pop("FINGERPAD_DEVICE", None)
        else:
            os.environ["FINGERPAD_DEVICE"] = before


class _LazyConsole:
    """A Rich console on stderr that is made when first used.

    Most runs print nothing on stderr, and importing Rich's console and making one cost ~0.02 s
    of a command that may take 0.5 s (issue 23). Asking whether stderr is a terminal does not
    make it where Rich would answer no anyway (no tty, no FORCE_TERMINAL or TTY_INTERACTIVE).
    """

    def __init__(self) -> None:
        self._console: Any = None

    def _made(self) -> Any:
        if self._console is None:
            from rich.console import Console

            self._console = Console(file=sys.stderr, soft_wrap=True, highlight=False)
        return self._console

    @property
    def is_terminal(self) -> bool:
        import os

        if self._console is None and not (os.environ.get("FORCE_TERMINAL") or os.environ.get("TTY_INTERACTIVE")):
            isatty = getattr(sys.stderr, "isatty", None)
            if isatty is None or not isatty():
                return False
        return bool(self._made().is_terminal)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._made(), name)


def stderr_console() -> Any:
    """A Rich console on stderr (progress, notes, warnings), made on first use."""
    return _LazyConsole()


def rich_console(console: Any) -> Any:
    """The Rich console itself, for Rich objects that take one (a progress bar)."""
    return console._made() if isinstance(console, _LazyConsole) else console


def stdout_console(min_width: int = 0) -> Any:
    """A Rich console on stdout: the terminal's width; when piped, at least ``min_width`` columns
    wide unless ``COLUMNS`` says otherwise."""
    import os

    from rich.console import Console

    console = Console(file=sys.stdout, highlight=False)
    if not console.is_terminal and min_width and not os.environ.get("COLUMNS"):
        console = Console(file=sys.stdout, width=max(console.width, min_width), highlight=False)
    return console


def say(console: Any, text: str) -> None:
    """Print plain text (no markup; control characters of names read from files escaped,
    :func:`~fingerpad.errors.printable`) on ``console``."""
    console.print(printable(text), markup=False, highlight=False, soft_wrap=True)


def say_wrapped(console: Any, text: str, hang: int = 4) -> None:
    """Print plain text on ``console`` wrapped at its width, at word boundaries, continuation
    lines indented ``hang`` columns past the text's own indent (a listing stays readable on an
    80-column terminal instead of running on, or restarting at column 0)."""
    import textwrap

    lead = len(text) - len(text.lstrip(" "))
    lines = textwrap.wrap(text, width=max(int(console.width), 40), subsequent_indent=" " * (lead + hang),
                          break_long_words=False, break_on_hyphens=False) or [""]
    for line in lines:
        say(console, line)


@contextlib.contextmanager
def warnings_to(console: Any) -> Iterator[None]:
    """Show Python warnings as single ``warning: ...`` lines on ``console`` (stderr)."""
    seen: set[str] = set()

    def show(message, category, filename, lineno, file=None, line=None):  # noqa: ANN001
        text = f"warning: {one_line(str(message))}"
        if text not in seen:
            seen.add(text)
            say(console, text)

    with warnings.catch_warnings():
        warnings.simplefilter("always")
        warnings.filterwarnings("ignore", category=DeprecationWarning)
        warnings.filterwarnings("ignore", category=PendingDeprecationWarning)
        # SurfaceTopography's MPI layer announces its serial fallback on import: not for users.
        warnings.filterwarnings("ignore", message=".*mpi4py")
        warnings.showwarning = show
        yield


def flag_pair(on: bool, off: bool, on_name: str, off_name: str) -> bool | None:
    """The value of a pair of opposite flags: True, False, or None when neither is given.

    Both given is a contradiction, reported as a user error rather than letting the last win.
    """
    if on and off:
        raise FingerpadError(f"{on_name} and {off_name} contradict each other: give one of them")
    return True if on else False if off else None


def command_options(ctx: Any) -> list[str]:
    """Every option name of the command of ``ctx`` (``--out``, ``-o``, ...)."""
    names: list[str] = []
    for param in getattr(ctx.command, "params", []):
        names += [o for o in (*getattr(param, "opts", ()), *getattr(param, "secondary_opts", ())) if o.startswith("-")]
    return names


def check_texture_options(pairs: Any, texture: str | None, options: list[str]) -> None:
    """Options that are neither the command's nor the texture's: one clear error, with a guess.

    The texture's parameters arrive as unknown options, so a mistyped command option (``--outt``)
    would otherwise be reported as a texture parameter.
    """
    import difflib

    from ..textures import registry

    families = registry()
    family = families.get(str(texture).strip().lower()) if texture else None
    if family is None and texture is not None:
        return  # an unknown texture: its own error names the families
    scope = [family] if family is not None else list(families.values())
    params = {p.name for fam in scope for p in fam.user_params()}
    for key, _ in pairs:
        if key in params:
            continue
        flag = "--" + key.replace("_", "-")
        guess = difflib.get_close_matches(flag, options + ["--" + p.replace("_", "-") for p in sorted(params)], n=1)
        hint = f" (did you mean {guess[0]}?)" if guess else ""
        whose = f"nor a parameter of texture {family.name!r}" if family is not None else "nor a texture parameter"
        raise FingerpadError(f"unknown option {flag}: neither an option of this command {whose}{hint}")


def option(*decls: str, help_texts: dict[str, str], panel: str, metavar: str | None = None, **kw: Any) -> Any:
    """A Typer option whose help text is looked up by its first name in ``help_texts``."""
    return typer.Option(*decls, help=help_texts[decls[0].split("/")[0]], rich_help_panel=panel, metavar=metavar, **kw)


#: Seconds between the plain progress lines written where stderr is not a terminal (a log file,
#: a pipe, CI): a bar there cannot redraw itself and was left frozen in the log at its last
#: state; work shorter than this writes none.
PLAIN_PROGRESS_EVERY = 10.0


class PlainProgress:
    """Progress as plain lines (``LABEL: 45/202, DETAIL (12 s)``), at most one every
    :data:`PLAIN_PROGRESS_EVERY` seconds: what a bar becomes where stderr is not a terminal."""

    def __init__(self, console: Any, every: float | None = None) -> None:
        import time

        self.console = console
        self.every = PLAIN_PROGRESS_EVERY if every is None else every
        self.start = self.last = time.monotonic()

    def line(self, text: str) -> None:
        import time

        now = time.monotonic()
        if now - self.last >= self.every:
            self.last = now
            say(self.console, f"{text} ({now - self.start:.0f} s)")


class ProgressBar:
    """A Rich progress bar on stderr, started on the first call ``bar(i, n)`` or
    ``bar.detail(text)`` (none if neither is ever called); :meth:`stage` adds a row for a later
    stage of the work. Where stderr is not a terminal, plain lines instead (:class:`PlainProgress`)."""

    def __init__(self, console: Any, label: str, total: int = 1) -> None:
        self.console = console
        self.label = label
        self.total = total
        self.bar: Any = None
        self.task: Any = None
        self.plain = None if console.is_terminal else PlainProgress(console)
        self._count = ""
        self._detail = ""

    def _say(self) -> None:
        assert self.plain is not None
        self.plain.line(f"{self.label}: " + ", ".join(t for t in (self._count, self._detail) if t))

    def _progress(self) -> Any:
        if self.bar is None:
            from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

            # the count is a field, not MofNCompleteColumn: a stage's row has none (no "0/?")
            self.bar = Progress(TextColumn("{task.description}"), BarColumn(), TextColumn("{task.fields[count]}"),
                                TimeElapsedColumn(), TextColumn("{task.fields[detail]}"),
                                console=rich_console(self.console))
            self.bar.start()
        return self.bar

    def _start(self, n: int) -> None:
        self.task = self._progress().add_task(self.label, total=n, detail="", count=f"0/{n}")

    def __call__(self, i: int, n: int) -> None:
        if self.plain is not None:
            self._count = f"{min(i, n)}/{n}"
            self._say()
            return
        if self.task is None:
            self._start(n)
        self.bar.update(self.task, completed=min(i, n), total=n, count=f"{min(i, n)}/{n}")

    def detail(self, text: str) -> None:
        """Show ``text`` after the bar (e.g. the iteration of a long solve)."""
        if self.plain is not None:
            self._detail = text
            self._say()
            return
        if self.task is None:
            self._start(self.total)
        self.bar.update(self.task, detail=text)

    def stage(self, label: str) -> Callable[[str], None]:
        """A row under the bar for a later stage whose length is not known beforehand (a pulsing
        bar, its own elapsed time and the stage's last message), shown from its first message:
        ``show = bar.stage("deflection ramps"); show("shear ramp 3/6 done")``."""
        task: list[Any] = []

        def show(text: str) -> None:
            if self.plain is not None:
                self.plain.line(f"{label}: {text}")
                return
            if not task:
                task.append(self._progress().add_task(label, total=None, detail="", count=""))
            self.bar.update(task[0], detail=text)

        return show

    def finish(self) -> None:
        """The work ended before the announced total (a search that converged inside its
        budget): the bar closes full at the count done, not at e.g. 44/60 as if cut short."""
        if self.task is not None:
            done = next(t.completed for t in self.bar.tasks if t.id == self.task)
            self.bar.update(self.task, completed=done, total=done, count=f"{done:g}/{done:g}")

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()
            self.bar = self.task = None

    def __enter__(self) -> ProgressBar:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()
