"""Shared test set-up: a private unit-cell cache per test session (never ~/.cache), and a small
prediction to write and draw."""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True, scope="session")
def _private_cache(tmp_path_factory: pytest.TempPathFactory) -> None:
    mp = pytest.MonkeyPatch()
    mp.setenv("FINGERPAD_CACHE", str(tmp_path_factory.mktemp("fingerpad-cache")))
    yield
    mp.undo()


@pytest.fixture(scope="module")
def prediction(tmp_path_factory):
    """Caps on the default finger by BEM (32-point cell) and Hertz, 0.2-3 N (~0.3 s); one per
    test module, so that a module may change it."""
    from fingerpad.study import run as study_run
    from fingerpad.study import study_from_dict

    study = study_from_dict({
        "texture": {"name": "caps", "radius": "50um", "height": "10um", "spacing": "100um"},
        "material": {"modulus": "0.5GPa", "poisson": 0.4},
        "loads": {"range": "0.2N:3N:5"},
        "model": {"kind": "both", "grid": 32, "cache": str(tmp_path_factory.mktemp("cells"))},
    })
    return study_run.run_study(study)


@pytest.fixture
def slow_token():
    """``slow_token(delay, after)``: a cancellation token (:mod:`fingerpad.cancel`) whose checks,
    one per solver iteration, each wait ``delay`` s (a solve made slow on purpose, so that it can
    be cancelled in its middle); it counts them (``checks``), sets ``reached`` after ``after`` of
    them and records the count when cancelled (``at_cancel``)."""
    import threading

    from fingerpad.cancel import CancelToken

    class SlowToken(CancelToken):
        __slots__ = ("after", "at_cancel", "checks", "delay", "reached")

        def __init__(self, delay: float, after: int) -> None:
            super().__init__()
            self.delay, self.after, self.checks, self.at_cancel = delay, after, 0, None
            self.reached = threading.Event()

        def check(self) -> None:
            self.checks += 1
            if self.checks >= self.after:
                self.reached.set()
            if self.delay:
                threading.Event().wait(self.delay)
            super().check()

        def cancel(self) -> None:
            if self.at_cancel is None:
                self.at_cancel = self.checks
            super().cancel()

    return SlowToken


@pytest.fixture
def cancel_midway(slow_token):
    """``cancel_midway(work, delay, after)``: run ``work()`` in a thread, in a cancellation scope
    whose token is ``slow_token(delay, after)``, cancel it once ``after`` checks are reached, and
    return (what ``work`` returned or raised, the token)."""
    import threading

    from fingerpad.cancel import Cancelled, cancellable

    def run(work, delay: float, after: int):
        token = slow_token(delay, after)
        out = []

        def body() -> None:
            try:
                with cancellable(token):
                    out.append(work())
            except Cancelled as exc:
                out.append(exc)

        worker = threading.Thread(target=body)
        worker.start()
        assert token.reached.wait(60), "the work ended before it could be cancelled"
        token.cancel()
        worker.join(60)
        assert not worker.is_alive()
        return out[0], token

    return run
