"""Cooperative cancellation: work nobody waits for any more stops at its next check.

A caller that may lose interest in a computation (the explorer, when the design it was started
for is no longer shown) runs it inside :func:`cancellable` with a :class:`CancelToken`; the long
loops of the library call :func:`check` (the contact solver once per iteration of its conjugate
gradient, :meth:`fingerpad.contact.HalfSpaceSolver._callback`; a population once per block of
fingers), which raises :class:`Cancelled` once the token is cancelled. Outside a scope a check
costs one context-variable lookup and never raises: the command line and the Python API run
exactly as without it.

Cancelling changes no number: a computation either runs to its end, as it would have, or raises.
Whatever the interrupted code was about to store is not stored (the exception leaves it before
the store), so a cache holds complete results only.

The scope is a :class:`contextvars.ContextVar`: a thread starts without one, so a worker thread
opens its own scope (``with cancellable(token): ...``) around the work it runs.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar

__all__ = ["CancelToken", "Cancelled", "cancellable", "check", "current"]


class Cancelled(BaseException):
    """Raised by :func:`check` once the scope's token is cancelled.

    A :class:`BaseException`, as :class:`asyncio.CancelledError` is: code that catches
    ``Exception`` to report a failure (a fallback, a note) lets a cancellation through."""


class CancelToken:
    """A flag one thread sets (:meth:`cancel`) and the threads of the work read (thread-safe).

    ``cancelled_at``: :func:`time.monotonic` of the first :meth:`cancel` (``None`` before), so
    that the work can tell how long it took to stop."""

    __slots__ = ("_event", "cancelled_at")

    def __init__(self) -> None:
        self._event = threading.Event()
        self.cancelled_at: float | None = None

    def cancel(self) -> None:
        """Ask the work of this token to stop at its next check."""
        if self.cancelled_at is None:
            self.cancelled_at = time.monotonic()
        self._event.set()

    @property
    def cancelled(self) -> bool:
        return self._event.is_set()

    def check(self) -> None:
        """Raise :class:`Cancelled` if the token is cancelled."""
        if self._event.is_set():
            raise Cancelled


_SCOPE: ContextVar[CancelToken | None] = ContextVar("fingerpad_cancel_scope", default=None)


@contextmanager
def cancellable(token: CancelToken) -> Iterator[CancelToken]:
    """Run the body with ``token`` as the scope's token (nested scopes: the innermost counts)."""
    reset = _SCOPE.set(token)
    try:
        token.check()  # cancelled before it started: nothing runs
        yield token
    finally:
        _SCOPE.reset(reset)


def current() -> CancelToken | None:
    """The token of the enclosing scope (``None`` outside any)."""
    return _SCOPE.get()


def check() -> None:
    """Raise :class:`Cancelled` if the enclosing scope's token is cancelled (no-op outside one)."""
    token = _SCOPE.get()
    if token is not None and token.cancelled:
        raise Cancelled
