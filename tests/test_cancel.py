"""Cooperative cancellation (fingerpad.cancel) and the contact solver's check of it: a solve nobody
waits for stops within one iteration and returns or stores nothing; a solve in a scope that is
never cancelled gives the same bits as one outside any scope."""

from __future__ import annotations

import threading

import numpy as np
import pytest

from fingerpad.cancel import CancelToken, Cancelled, cancellable, check, current
from fingerpad.contact import HalfSpaceSolver
from fingerpad.textures import spherical_caps


class CountingToken(CancelToken):
    """A token that counts the checks (the solver's iterations) and, with ``delay``, makes each
    one slow: a solve made slow on purpose, long enough to be cancelled in its middle."""

    __slots__ = ("checks", "delay", "at_cancel", "reached", "_after")

    def __init__(self, delay: float = 0.0, cancel_after: int | None = None) -> None:
        super().__init__()
        self.checks, self.delay, self.at_cancel = 0, delay, None
        self.reached = threading.Event()
        self._after = cancel_after

    def check(self) -> None:
        self.checks += 1
        if self._after is not None and self.checks >= self._after:
            self.reached.set()
        if self.delay:
            threading.Event().wait(self.delay)
        super().check()

    def cancel(self) -> None:
        self.at_cancel = self.checks
        super().cancel()


def _cell(grid: int = 128):
    return spherical_caps(radius=100e-6, height=20e-6, spacing=175e-6, grid=grid)


def test_no_scope_no_check():
    assert current() is None
    check()  # outside a scope: nothing to stop


def test_scope_checks_its_token_and_nests():
    outer, inner = CancelToken(), CancelToken()
    with cancellable(outer):
        assert current() is outer
        with cancellable(inner):
            assert current() is inner
            outer.cancel()
            check()  # the innermost scope counts: inner is not cancelled
            inner.cancel()
            with pytest.raises(Cancelled):
                check()
        with pytest.raises(Cancelled):
            check()
    assert current() is None


def test_a_cancelled_token_runs_nothing():
    token = CancelToken()
    token.cancel()
    ran = []
    with pytest.raises(Cancelled):
        with cancellable(token):
            ran.append(1)
    assert ran == []


def test_cancelled_is_not_an_error_that_fallbacks_catch():
    assert not issubclass(Cancelled, Exception)  # `except Exception` in a fallback lets it through


def test_a_scope_never_cancelled_changes_no_bit():
    """The check is a read of a flag: the solve inside a scope is the solve outside it."""
    tex = _cell(64)
    plain = HalfSpaceSolver(tex, 1e6).solve_pressure(20e3)
    token = CountingToken()
    with cancellable(token):
        scoped = HalfSpaceSolver(tex, 1e6).solve_pressure(20e3)
    assert token.checks >= plain.iterations > 0  # checked once per iteration (nested levels too)
    assert np.array_equal(plain.pressure, scoped.pressure)
    assert np.array_equal(plain.gap, scoped.gap)
    assert plain.iterations == scoped.iterations


def test_a_superseded_solve_stops_within_one_iteration():
    """A solve made slow on purpose (each iteration waits), cancelled from another thread after a
    few iterations: it raises Cancelled at its next iteration, long before it would converge."""
    tex = _cell(128)
    full = HalfSpaceSolver(tex, 1e6, tol=1e-10).solve_pressure(20e3)
    token = CountingToken(delay=0.01, cancel_after=3)
    out: list[BaseException | object] = []

    def run() -> None:
        try:
            with cancellable(token):
                out.append(HalfSpaceSolver(tex, 1e6, tol=1e-10).solve_pressure(20e3))
        except Cancelled as exc:
            out.append(exc)

    worker = threading.Thread(target=run)
    worker.start()
    assert token.reached.wait(60)
    token.cancel()
    worker.join(60)
    assert not worker.is_alive()
    assert len(out) == 1 and isinstance(out[0], Cancelled)  # no result came back
    assert token.checks <= token.at_cancel + 1  # stopped at the first check after the cancel
    assert token.checks < full.iterations  # before the solve's end (nested levels included)
