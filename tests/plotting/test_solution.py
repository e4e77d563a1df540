"""Figures of a solved cell: pressure and contact maps, psi(p); psi(p) of several curves."""

from __future__ import annotations

import pytest

from fingerpad.errors import FingerpadError
from fingerpad.plotting.solution import figure_solution, plot_load_curves, plot_solution


def test_solution_png(tmp_path, sinusoid_curve, png_is_drawn):
    path = plot_solution(sinusoid_curve, tmp_path / "cell.png", dpi=50)
    assert path == tmp_path / "cell.png"
    png_is_drawn(path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cell.png"]


def test_solution_titles_and_labels(sinusoid_curve):
    last = sinusoid_curve.results[-1]
    fig = figure_solution(sinusoid_curve)
    ax_p, ax_c, ax_psi = fig.axes[:3]  # then the two colour bars
    assert ax_p.get_title() == "pressure at p = 300 kPa"
    assert ax_c.get_title() == f"contact in red ({last.contact_state}, psi = {last.contact_fraction:.3g})"
    assert ax_p.get_xlabel() == "x (µm)" and ax_p.get_ylabel() == "y (µm)"
    assert ax_psi.get_xscale() == "log", "four pressures over three decades"
    assert ax_psi.get_xlabel() == "mean pressure p (Pa)"
    assert fig._suptitle.get_text() == "texture sinusoid: 100 x 50 µm cell, E* = 1 MPa"
    # the psi(p) panel plots the curve's own numbers
    line = ax_psi.get_lines()[0]
    assert sorted(line.get_ydata()) == sorted(sinusoid_curve.contact_fraction)


def test_solution_of_one_result_and_chosen_index(sinusoid_curve):
    fig = figure_solution(sinusoid_curve.results[0], title="one")
    assert fig._suptitle.get_text() == "one"
    assert fig.axes[0].get_title() == "pressure at p = 300 Pa"
    fig = figure_solution(sinusoid_curve, index=1)
    assert fig.axes[0].get_title() == "pressure at p = 3 kPa"
    with pytest.raises(FingerpadError, match="plot index 9 out of range for 4 results"):
        figure_solution(sinusoid_curve, index=9)


def test_solution_svg_and_pdf(tmp_path, sinusoid_curve):
    svg = plot_solution(sinusoid_curve.results[0], tmp_path / "cell.svg", fmt="svg")
    assert svg.read_text().lstrip().startswith("<?xml") and "<svg" in svg.read_text()[:2000]
    pdf = plot_solution(sinusoid_curve.results[0], tmp_path / "cell.pdf", fmt="pdf")
    assert pdf.read_bytes()[:5] == b"%PDF-"


def test_load_curves_png(tmp_path, sinusoid_curve, png_is_drawn):
    path = plot_load_curves([sinusoid_curve, sinusoid_curve], ["a", "b"], tmp_path / "curves.png")
    png_is_drawn(path)
    with pytest.raises(ValueError):
        plot_load_curves([sinusoid_curve], ["a", "b"], tmp_path / "bad.png")
    assert not (tmp_path / "bad.png").exists()


def test_narrow_pressure_range_keeps_a_linear_axis(sinusoid_curve):
    # two pressures a factor 10 apart at most: a linear axis in a readable unit
    fig = figure_solution(sinusoid_curve.results[:2])
    ax_psi = fig.axes[2]
    assert ax_psi.get_xscale() == "linear" and ax_psi.get_xlabel() == "mean pressure p (kPa)"


def test_unconverged_results_are_marked(sinusoid_curve):
    import dataclasses

    results = list(sinusoid_curve.results)
    results[1] = dataclasses.replace(results[1], converged=False)
    fig = figure_solution(results)
    labels = fig.axes[2].get_legend_handles_labels()[1]
    assert "not converged" in labels and "shown left" in labels
    clean = figure_solution(sinusoid_curve.results)
    assert "not converged" not in clean.axes[2].get_legend_handles_labels()[1]
