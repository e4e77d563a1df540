"""Cooperative cancellation (fingerpad.cancel) and the contact solver's check of it: a solve nobody
waits for stops within one iteration and returns or stores nothing; a solve in a scope that is
never cancelled gives the same bits as one outside any scope."""

from __future__ import annotations

import numpy as np
import pytest

from fingerpad.cancel import CancelToken, Cancelled, cancellable, check, current
from fingerpad.contact import HalfSpaceSolver
from fingerpad.textures import spherical_caps


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


def test_a_scope_never_cancelled_changes_no_bit(slow_token):
    """The check is a read of a flag: the solve inside a scope is the solve outside it."""
    tex = _cell(64)
    plain = HalfSpaceSolver(tex, 1e6).solve_pressure(20e3)
    token = slow_token(0.0, 10**9)
    with cancellable(token):
        scoped = HalfSpaceSolver(tex, 1e6).solve_pressure(20e3)
    assert token.checks >= plain.iterations > 0  # checked once per iteration (nested levels too)
    assert np.array_equal(plain.pressure, scoped.pressure)
    assert np.array_equal(plain.gap, scoped.gap)
    assert plain.iterations == scoped.iterations


def test_a_superseded_solve_stops_within_one_iteration(cancel_midway):
    """A solve made slow on purpose (each iteration waits), cancelled from another thread after a
    few iterations: it raises Cancelled at its next iteration, long before it would converge."""
    tex = _cell(128)
    full = HalfSpaceSolver(tex, 1e6, tol=1e-10).solve_pressure(20e3)
    out, token = cancel_midway(lambda: HalfSpaceSolver(tex, 1e6, tol=1e-10).solve_pressure(20e3), 0.01, 3)
    assert isinstance(out, Cancelled)  # no result came back
    assert token.checks <= token.at_cancel + 1  # stopped at the first check after the cancel
    assert token.checks < full.iterations  # before the solve's end (nested levels included)
