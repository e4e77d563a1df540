"""The cell's grid chosen by a stated accuracy, and the error estimate it reports."""

from __future__ import annotations

import math

import numpy as np

from fingerpad.coupling import couple
from fingerpad.micro.companions import halve
from fingerpad.micro.resolution import choose_grid
from fingerpad.textures import spherical_caps

E = 0.395e6
LOADS = np.array([0.2, 1.0, 4.0])
RIDGE = 0.5 * np.pi * (3 * LOADS * 9e-3 / (4 * 40e3)) ** (2 / 3)  # the default finger's A_fr (m^2)


def make(nx: int):
    return spherical_caps(radius=100e-6, height=20e-6, spacing=175e-6, lattice="hexagonal", grid=nx)


def ratio(cell):
    return couple(LOADS, RIDGE, cell).area_ratio


def test_grid_doubles_until_the_estimate_meets_the_target_and_the_estimate_is_honest():
    choice = choose_grid(make, make(32), E, (1e2, 2e5), ratio, target=0.03, cell_options={"cache": False})
    grids = [g for g, _ in choice.history]
    assert grids == [32, 64] and choice.met  # estimates 4.7 % at 32, 2.3 % at 64
    assert choice.error <= 0.03 < choice.history[0][1]
    # the estimate bounds the error against a finer cell
    finer = choose_grid(make, make(2 * grids[-1]), E, (1e2, 2e5), ratio, target=None, cell_options={"cache": False})
    actual = np.max(np.abs(ratio(choice.cell) / ratio(finer.cell) - 1))
    assert actual <= choice.error


def test_a_given_grid_is_kept_and_only_reported():
    choice = choose_grid(make, make(32), E, (1e2, 2e5), ratio, target=None, cell_options={"cache": False})
    assert choice.cell.texture.shape[0] == 32 and len(choice.history) == 1
    assert choice.met is None and 0 < choice.error < 0.1
    assert choice.coarse is not None and choice.coarse.texture.shape[0] == 16


def test_measured_map_companion_is_block_averaged():
    tex = make(32)
    half = halve(tex)
    assert half.shape == (16, tex.shape[1] // 2)
    assert math.isclose(half.heights.mean(), tex.heights.mean(), rel_tol=1e-12)
    choice = choose_grid(None, tex, E, (1e2, 2e5), ratio, target=0.001, cell_options={"cache": False})
    assert choice.cell.texture is tex and len(choice.history) == 1  # a map's grid is never raised
