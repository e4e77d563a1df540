"""Text drawn by Agg from glyphs rasterised once: the same pixels, a third less time per figure.

matplotlib's Agg renderer lays out every string it draws (FreeType's shaping of the string
into glyphs and their offsets) and rasterises each glyph again at every draw: a QC figure
draws ~60 tick labels, titles and legend entries, most of them the same strings in every
recording's figure, and this was ~40 % of its time (issue 23). :func:`cache_glyphs` makes a
renderer keep both:

* the layout of a string, keyed by everything the layout reads (the font files, size, dpi,
  string, hinting; strings with OpenType features or a language set are left to matplotlib);
* each glyph's bitmap, keyed by the glyph, its size, the rotation and the position's fraction
  of a pixel (1/64 px, FreeType's unit): the same glyph at a whole number of pixels away is
  the same outline shifted by whole pixels, which FreeType rasterises to the same bitmap,
  shifted. So the cached bitmap is drawn where matplotlib would have drawn a new one, byte for
  byte (tests: every measurement figure's PNG is identical with and without the cache).

It relies on private methods of matplotlib's Agg renderer and fonts (``_prepare_font``,
``FT2Font._layout``, ``_set_transform``, ``_render_glyph``, from matplotlib 3.11 on); with an
older matplotlib, which draws text another way, the renderer is left as it is.
"""

from __future__ import annotations

import math
from typing import Any

__all__ = ["cache_glyphs"]

#: Entries kept at most (strings laid out; glyph bitmaps, each a few hundred bytes): reached,
#: a cache starts again empty.
MAX_LAYOUTS = 4096
MAX_GLYPHS = 65536

_LAYOUTS: dict[tuple[Any, ...], list[tuple[Any, int, float, float]]] = {}
_GLYPHS: dict[tuple[Any, ...], tuple[Any, int, int]] = {}
#: Glyphs drawn from the cache and rasterised (for the tests).
counts = {"hits": 0, "misses": 0}


def _supported(renderer: Any) -> bool:
    from matplotlib.backends import backend_agg

    return (hasattr(backend_agg, "RenderMode") and hasattr(renderer, "_prepare_font")
            and hasattr(renderer, "_draw_text_glyphs_and_boxes") and hasattr(renderer, "_renderer"))


def cache_glyphs(renderer: Any) -> None:
    """Make ``renderer`` (a ``RendererAgg``) draw plain text (not mathtext, not TeX) from the
    caches of this module: the same pixels as without them. Nothing happens where the
    renderer is not one this module knows (see the module doc) or has them already."""
    if "draw_text" in vars(renderer) or not _supported(renderer):
        return
    from matplotlib.backends.backend_agg import RenderMode, get_hinting_flag
    from matplotlib.font_manager import fontManager

    draw_text = renderer.draw_text

    def cached_draw_text(gc: Any, x: float, y: float, s: str, prop: Any, angle: float, ismath: Any = False,
                         mtext: Any = None) -> None:
        features = mtext.get_fontfeatures() if mtext is not None else None
        language = mtext.get_language() if mtext is not None else None
        if ismath or features is not None or language is not None:
            draw_text(gc, x, y, s, prop, angle, ismath=ismath, mtext=mtext)
            return
        flags = get_hinting_flag()
        size = prop.get_size_in_points()
        dpi = renderer.dpi
        key = (tuple(fontManager._find_fonts_by_props(prop)), size, dpi, s, flags)
        items = _LAYOUTS.get(key)
        if items is None:
            font = renderer._prepare_font(prop)
            items = [(item.ft_object, item.glyph_index, item.x, item.y)
                     for item in font._layout(s, flags=flags, features=None, language=None)]
            if len(_LAYOUTS) >= MAX_LAYOUTS:
                _LAYOUTS.clear()
            _LAYOUTS[key] = items
        _draw_glyphs(renderer, gc, x, y, angle, size, items, flags, RenderMode)

    renderer.draw_text = cached_draw_text


def _draw_glyphs(renderer: Any, gc: Any, x: float, y: float, angle: float, size: float,
                 items: list[tuple[Any, int, float, float]], flags: Any, render_mode: Any) -> None:
    """What ``RendererAgg._draw_text_glyphs_and_boxes`` does for the glyphs of plain text (no
    slant, no stretch, no boxes), with each bitmap rasterised once per fraction of a pixel."""
    import numpy as np

    cos = math.cos(math.radians(angle))
    sin = math.sin(math.radians(angle))
    # as matplotlib computes it (slant 0, extend 1): 16.16 fixed point
    matrix = (0x10000 * np.array([[cos, -sin], [sin, cos]]) @ [[1, 0], [0, 1]]).round().astype(int)
    rotation = tuple(matrix.ravel().tolist())
    antialiased = gc.get_antialiased()
    mode = render_mode.NORMAL if antialiased else render_mode.MONO
    height = renderer.height
    dpi = renderer.dpi
    for font, glyph, dx, dy in items:
        # the glyph's origin in FreeType's 26.6 fixed point (1/64 px), y upwards, as matplotlib
        # places it
        gx = round(0x40 * (x + dx * cos - dy * sin))
        gy = round(0x40 * (height - y + dx * sin + dy * cos))
        key = (font, size, dpi, glyph, rotation, gx & 63, gy & 63, antialiased, flags)
        cached = _GLYPHS.get(key)
        if cached is None:
            counts["misses"] += 1
            font.set_size(size, dpi)
            font._set_transform(matrix, [gx, gy])
            bitmap = font._render_glyph(glyph, flags, mode)
            buffer = np.array(bitmap.buffer, dtype=np.uint8)
            if not antialiased:
                buffer *= 0xff
            # the bitmap's corner relative to the whole pixel of the origin
            cached = (buffer, bitmap.left - (gx >> 6), bitmap.top - (gy >> 6))
            if len(_GLYPHS) >= MAX_GLYPHS:
                _GLYPHS.clear()
            _GLYPHS[key] = cached
        else:
            counts["hits"] += 1
        buffer, left, top = cached
        # draw_text_image's y is downwards and the bitmap's bottom side
        renderer._renderer.draw_text_image(buffer, left + (gx >> 6), int(height) - (top + (gy >> 6)) + buffer.shape[0],
                                           0, gc)
