"""Inputs of the figures, each the smallest real one: a solved 16 x 8 cell, a Hertz+BEM prediction
on a 32-point cell, a simulated two-person measurement study, a synthetic sweep store.

``png_is_drawn`` is the shared check that a written PNG is an image with something on it.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import fingerpad as fp


def png_is_drawn(path: Path, min_colours: int = 3) -> np.ndarray:
    """Open the PNG as matplotlib reads it and check it is not blank; return the pixels."""
    from matplotlib.image import imread

    assert path.is_file() and path.stat().st_size > 0, path
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    img = imread(path)
    assert img.ndim == 3 and img.shape[0] > 100 and img.shape[1] > 100, img.shape
    rgb = img[..., :3].reshape(-1, 3)
    assert float(rgb.var()) > 1e-3, "the image is (nearly) one colour"
    colours = np.unique((rgb * 255).round().astype(np.uint8), axis=0)
    assert len(colours) >= min_colours, f"only {len(colours)} colours"
    # not only white: some ink on at least 0.5 % of the pixels
    assert float(np.mean(rgb.min(axis=1) < 0.9)) > 0.005
    return img


@pytest.fixture(name="png_is_drawn", scope="session")
def _png_is_drawn():
    return png_is_drawn


@pytest.fixture(scope="session")
def sinusoid_curve():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fp.errors.ResolutionWarning)
        tex = fp.make_texture("sinusoid", amplitude=5e-6, wavelength=100e-6, grid=16)
    return fp.load_curve(fp.HalfSpaceSolver(tex, 1e6), [300.0, 3e3, 3e4, 3e5])


@pytest.fixture(scope="session")
def measured(tmp_path_factory):
    """A simulated study of two people on flat and bumps, analysed (about a second)."""
    from fingerpad import measure as m

    out = tmp_path_factory.mktemp("measured") / "study"
    m.simulate_study(out, m.SimulationConfig(participants=2, repetitions=1, strokes_per_file=6), seed=3)
    return m.analyse_study(m.load_study([out]), m.AnalysisOptions(reference="flat", n_null=19),
                           textures=m.read_textures(out / "samples.csv"))
