"""The roughness regime: the duplex boundary, the 160 um marker, the peak at the transition."""

from __future__ import annotations

import math

from fingerpad.perception.roughness import DUPLEX_PERIOD, SMOOTH_SPACING, regime


def test_regimes():
    assert regime(math.inf, "full")["scale"] == "flat"
    fine = regime(175e-6, "asperity")
    assert fine["scale"] == "fine" and not fine["felt_smooth"] and "vibration" in fine["cue"]
    assert regime(150e-6, "asperity")["felt_smooth"] and SMOOTH_SPACING == 160e-6
    coarse = regime(250e-6, "transition")
    assert coarse["scale"] == "coarse" and "peak" in coarse["roughness"] and DUPLEX_PERIOD == 200e-6
    assert "rising" in regime(250e-6, "asperity")["roughness"]
    assert "past" in regime(250e-6, "full")["roughness"]
