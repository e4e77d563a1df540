"""Measurement figures: one per participant, one per sample, one QC figure per recording."""

from __future__ import annotations

import pytest

from fingerpad.errors import FingerpadError
from fingerpad.plotting.measure import figure_participant, figure_qc, figure_sample, png_bytes


def write(fig, path):
    path.write_bytes(png_bytes(fig, 60))
    return path


def test_participant_figure(tmp_path, measured, png_is_drawn):
    fig = figure_participant(measured, "P01")
    png_is_drawn(write(fig, tmp_path / "P01.png"))
    for ax in fig.axes:
        assert ax.get_xlabel() == "normal load F (N)"


def test_sample_figures(tmp_path, measured, png_is_drawn):
    fig = figure_sample(measured, "bumps")
    png_is_drawn(write(fig, tmp_path / "bumps.png"))
    assert [ax.get_title() for ax in fig.axes] == ["bumps: raw friction", "normalised by each participant's reference",
                                                   "spread between people"]
    ref = figure_sample(measured, "flat")
    assert [ax.get_title() for ax in ref.axes] == ["flat (reference): raw friction"]
    with pytest.raises(FingerpadError, match="no data on sample 'glass'"):
        figure_sample(measured, "glass")


def test_qc_figure(tmp_path, measured, png_is_drawn):
    source = measured.recordings[0].source
    fig = figure_qc(measured, source)
    png_is_drawn(write(fig, tmp_path / "qc.png"))
    assert "strokes" in fig._suptitle.get_text()


def test_png_bytes_is_a_png(measured):
    data = png_bytes(figure_sample(measured, "flat"), 40)
    assert data[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("dpi", [40, 100])
def test_png_bytes_has_the_pixels_and_metadata_of_savefig(measured, dpi):
    """png_bytes encodes the PNG itself (plotting/png.py): the image Pillow decodes is the one
    savefig writes, pixel for pixel, with the same mode, size, resolution and Software text;
    savefig afterwards still writes the same image (the figure is left as it was)."""
    import io

    from PIL import Image

    def decoded(data: bytes) -> tuple:
        with Image.open(io.BytesIO(data)) as im:
            im.load()
            return im.mode, im.size, im.tobytes(), dict(im.info)

    def saved(fig) -> bytes:
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=dpi)
        return buf.getvalue()

    source = measured.recordings[0].source
    for fig in (figure_qc(measured, source), figure_sample(measured, "flat")):
        before = saved(fig)
        ours = png_bytes(fig, dpi)
        assert decoded(ours) == decoded(before)
        assert saved(fig) == before
