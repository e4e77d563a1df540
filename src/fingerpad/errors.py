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


def one_line(text: str) -> str:
    """``text`` on one line (for ``error: ...`` and ``warning: ...`` messages)."""
    return " ".join(part.strip() for part in str(text).splitlines() if part.strip()) or "unknown error"


def describe_exception(exc: BaseException) -> str:
    """The message of ``exc``; for an :class:`OSError`, its reason and file name without the errno."""
    if isinstance(exc, OSError) and not isinstance(exc, FingerpadError):
        what = exc.strerror or str(exc)
        return f"{what}: {exc.filename}" if exc.filename else what
    return str(exc)
