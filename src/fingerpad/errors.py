"""Exceptions raised for user mistakes.

Every error a user can cause (bad parameter, unreadable file, unknown unit) is raised as a
:class:`FingerpadError`; the command line prints its message on one line and exits non-zero,
without a traceback. Anything else escaping is a bug in fingerpad.
"""

from __future__ import annotations


class FingerpadError(ValueError):
    """A user-facing error with a one-line message."""


class SetupError(FingerpadError):
    """A bad setting of the environment or the installation, not of the problem (an FFT engine
    or thread count, an optional package asked for but missing). Work that records the points
    it cannot compute as such (a sweep) stops on it instead of recording every point."""


class ConvergenceError(RuntimeError):
    """A solver did not reach its tolerance and the caller asked for strict behaviour."""


class ResolutionWarning(UserWarning):
    """A texture feature spans too few grid points to be resolved."""


#: Longest message :func:`one_line` prints whole: a longer one (a 5000-digit number or a 5 MB
#: forged value quoted back) keeps its start and its end around a note of what was left out.
MAX_LINE = 1000


def printable(text: str) -> str:
    """``text`` with every control or invisible formatting character shown escaped (``\\x1b``,
    ``\\u202e``): labels and names read from files are printed as text, never as terminal
    escapes that clear the screen, recolour it or reorder what follows. Newlines are kept."""
    text = str(text)
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() or c == "\n" else c.encode("unicode_escape").decode("ascii")
                   for c in text)


def excerpt(value: object, limit: int = 80) -> str:
    """``repr(value)``, printable (:func:`printable`) and at most about ``limit`` characters: a
    value a user or a page sent, quoted back in a message or a log line (a 5 MB forged value
    becomes its first characters and its length)."""
    text = printable(repr(value))
    if len(text) <= limit:
        return text
    size = len(value) if isinstance(value, (str, bytes)) else len(text)
    return f"{text[:limit]}... ({size} characters)"


def one_line(text: str) -> str:
    """``text`` on one line (for ``error: ...`` and ``warning: ...`` messages), control
    characters escaped (:func:`printable`), at most about :data:`MAX_LINE` characters."""
    line = " ".join(part.strip() for part in printable(text).splitlines() if part.strip()) or "unknown error"
    if len(line) > MAX_LINE:
        head, tail = MAX_LINE * 3 // 5, MAX_LINE // 5
        line = f"{line[:head]} [... {len(line) - head - tail} characters left out ...] {line[-tail:]}"
    return line


def describe_exception(exc: BaseException) -> str:
    """The message of ``exc``; for an :class:`OSError`, its reason and file name without the errno."""
    if isinstance(exc, OSError) and not isinstance(exc, FingerpadError):
        what = exc.strerror or str(exc)
        return f"{what}: {exc.filename}" if exc.filename else what
    return str(exc)
