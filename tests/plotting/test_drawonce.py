"""Tick labels and 'best' legends worked out once per draw: the same PNG bytes as matplotlib's
own double work, and the work is in fact done once."""

import numpy as np

from fingerpad.plotting.drawonce import lay_out_ticks_once, place_legend_once
from fingerpad.plotting.measure import png_bytes


def _figure(once: bool):
    from matplotlib.figure import Figure

    rng = np.random.default_rng(3)
    fig = Figure(figsize=(6, 4))
    axes = fig.subplots(2, 1)
    legends = []
    for i, ax in enumerate(axes):
        if once:
            lay_out_ticks_once(ax.xaxis)
            lay_out_ticks_once(ax.yaxis)
        x = np.geomspace(0.05, 8.0, 200)
        ax.plot(x, 0.4 * x ** -0.3 * (1 + 0.05 * rng.standard_normal(x.size)), "o", ms=2, label="measured")
        ax.plot(x, 0.4 * x ** -0.3, label="fit")
        ax.set(xscale="log", yscale="log", ylabel=f"mu (panel {i})", xlabel="load (N)")
        legend = ax.legend(fontsize=7, loc="best")
        if once:
            place_legend_once(legend)
        legends.append(legend)
    return fig, legends


def test_the_same_png_bytes():
    for dpi in (40, 100):
        assert png_bytes(_figure(True)[0], dpi) == png_bytes(_figure(False)[0], dpi)


def test_each_legend_is_placed_once_per_draw():
    """_find_best_position, counted on the class before the figures are made (the helper keeps
    the bound method it wraps): twice per legend per draw without the helper, once with it."""
    calls = []
    from matplotlib.legend import Legend

    original = Legend._find_best_position

    def counting(self, *args, **kwargs):
        calls.append(1)
        return original(self, *args, **kwargs)

    Legend._find_best_position = counting
    try:
        calls.clear()
        fig, legends = _figure(False)
        png_bytes(fig, 60)
        twice = len(calls)
        calls.clear()
        fig, legends = _figure(True)
        png_bytes(fig, 60)
        once = len(calls)
    finally:
        Legend._find_best_position = original
    assert twice == 2 * len(legends)
    assert once == len(legends)
