"""The explorer's design map shows who tells each design from the flat reference (the colour
"telling it from flat") and the perception's lines (lambda = v / 250 Hz, 160 um felt smooth, the
fingerprint ridge band), as ``fingerpad design-map --tell-apart flat`` does."""

from __future__ import annotations

import numpy as np
import pytest


@pytest.fixture(scope="module")
def store(tmp_path_factory):
    pytest.importorskip("zarr")
    from synthetic_sweep import synthetic_sweep

    return synthetic_sweep(tmp_path_factory.mktemp("sweep") / "s.zarr")


def test_map_data_has_the_study_fingers_p_against_flat(store):
    from fingerpad.explore import sweepdata as sd
    from fingerpad.perception.discrimination import p_correct

    ds = sd.open_sweep(store)
    md = sd.map_data(ds, "spacing", "height", at=1.0)
    at = md.attrs["at"]
    mu = ds["mu"].sel(load=at).transpose("height", "spacing").values
    ref = ds["mu_ref"].sel(load=at).transpose("height", "spacing").values
    valid = md["valid"].values
    # the study's W (the default), none where the texture is not possible
    assert np.array_equal(md["tell_flat"].values[valid], p_correct(mu, ref, 0.11)[valid])
    assert np.isnan(md["tell_flat"].values[~valid]).all() and (~valid).any()


def test_map_view_colours_by_it_and_draws_the_perception_lines(store):
    pytest.importorskip("panel")
    from bokeh.models import BoxAnnotation, Span

    from fingerpad.explore import sweepdata as sd
    from fingerpad.explore.views.mapview import MapView

    ds = sd.open_sweep(store)
    view = MapView(None, ds, str(store))
    view.x.value, view.y.value = "spacing", "height"
    view.quantity.value = "tell_flat"
    fig = view.plot.object
    values = np.asarray(fig.renderers[0].data_source.data["value"], float)
    assert np.array_equal(np.sort(values[np.isfinite(values)]),
                          np.sort(view.md["tell_flat"].values[view.md["valid"].values]))
    lines = [a for a in fig.center if isinstance(a, Span)]
    vertical = sorted(s.location for s in lines if s.dimension == "height")
    # 160 um felt smooth and lambda = 50 mm/s / 250 Hz = 200 um on the spacing axis (150-200 um)
    assert vertical == pytest.approx([160.0, 200.0])
    # the interlocking height 33.5 um on the height axis (10-40 um)
    assert [s.location for s in lines if s.dimension == "width"] == pytest.approx([33.5])
    assert not [a for a in fig.center if isinstance(a, BoxAnnotation)]  # the ridge band (400-500 um) is off the map


def test_the_sweep_studys_w_is_the_maps(store):
    """A sweep study's [perception] weber_fraction is the W of both maps (the explorer's and
    ``design-map --tell-apart flat``), read by one function."""
    import json

    from fingerpad.design.designmap import map_data
    from fingerpad.explore import sweepdata as sd
    from fingerpad.perception.discrimination import p_correct
    from synthetic_sweep import BASE_STUDY

    ds = sd.open_sweep(store)
    ds.attrs["study"] = json.dumps({**BASE_STUDY, "perception": {"weber_fraction": 0.3}})
    md = sd.map_data(ds, "spacing", "height", at=1.0)
    at = md.attrs["at"]
    mu = ds["mu"].sel(load=at).transpose("height", "spacing").values
    ref = ds["mu_ref"].sel(load=at).transpose("height", "spacing").values
    valid = md["valid"].values
    assert np.array_equal(md["tell_flat"].values[valid], p_correct(mu, ref, 0.3)[valid])
    assert not np.array_equal(p_correct(mu, ref, 0.3)[valid], p_correct(mu, ref, 0.11)[valid])
    cmd = map_data(ds, "spacing", "height", at=at, tell_apart={"reference": "flat", "mu": None, "weber": None})
    got = cmd["tell_apart"].transpose("height", "spacing").values
    assert np.allclose(got[valid], p_correct(mu, ref, 0.3)[valid], rtol=0, atol=1e-12)


def test_the_map_download_draws_the_lines_the_page_draws(store, monkeypatch):
    """The PNG/SVG download of the map draws the markers of the map on the page (one list,
    :func:`marker_items`): the same lines at the same places, with their labels."""
    pytest.importorskip("panel")
    import re
    from html import unescape

    from bokeh.models import Span

    from fingerpad.explore import sweepdata as sd
    from fingerpad.explore.views.mapview import MapView

    ds = sd.open_sweep(store)
    view = MapView(None, ds, str(store))
    view.x.value, view.y.value = "spacing", "height"
    page = sorted((s.dimension == "height", round(s.location, 9)) for s in view.plot.object.center
                  if isinstance(s, Span))
    svg = view.image("svg").decode()
    # matplotlib writes a line's gid as the id of its group
    ids = sorted(unescape(i) for i in re.findall(r'<g id="(marker-[^"]+)"', svg))
    assert ids == sorted(["marker-felt smooth below 160 µm", "marker-250 Hz at 50 mm/s",
                          "marker-interlocking from 33.5 µm"]), ids
    assert view.image("png").startswith(b"\x89PNG")
    # at the places the page draws them
    from fingerpad.plotting import render

    drawn = []
    real = render.map_image
    monkeypatch.setattr(render, "map_image", lambda *a, **k: drawn.append(k["markers"]) or real(*a, **k))
    view.image("png")
    assert sorted((m["vertical"], round(m["value"], 9)) for m in drawn[0] if m["kind"] == "line") == page
    assert len(page) == 3
