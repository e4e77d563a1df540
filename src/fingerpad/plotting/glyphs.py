"""Text laid out and rasterised once per string and glyph: the same pixels, less time per figure.

matplotlib lays out every string it draws and rasterises each glyph again at every draw: a
QC figure draws ~60 tick labels, titles and legend entries, most of them the same strings in
every recording's figure, and this was ~40 % of its time (issue 23). Three caches keep what
does not change from one draw to the next:

* a text's layout (:func:`laid_out_once`, around a draw: the box of each line relative to the
  text's anchor), keyed by everything ``Text._get_layout`` reads: the string, the resolved font
  files and properties, size, dpi, hinting, line spacing, alignment and rotation; texts with
  mathtext, TeX or wrapping are left to matplotlib;
* a string's glyphs and their offsets (FreeType's shaping), keyed by font files, size, dpi,
  string and hinting (:func:`cache_glyphs`; strings with OpenType features or a language set
  are left to matplotlib);
* each glyph's bitmap, keyed by the glyph, its size, the rotation and the position's fraction
  of a pixel (1/64 px, FreeType's unit): the same glyph a whole number of pixels away is the
  same outline shifted by whole pixels, which FreeType rasterises to the same bitmap, shifted.

So a figure is drawn with the same pixels, byte for byte (tests: every measurement figure's PNG
is identical with and without the caches). It relies on private methods of matplotlib's text
and Agg renderer (``Text._get_layout``, ``_prepare_font``, ``FT2Font._layout``,
``_set_transform``, ``_render_glyph``, from matplotlib 3.11 on); with an older matplotlib,
which draws text another way, nothing is cached.
"""

from __future__ import annotations

import contextlib
import math
import os
from collections.abc import Iterator
from typing import Any

__all__ = ["cache_glyphs", "laid_out_once"]

#: Entries kept at most (strings laid out; glyph bitmaps, each a few hundred bytes): reached,
#: a cache starts again empty.
MAX_LAYOUTS = 4096
MAX_GLYPHS = 65536

_LAYOUTS: dict[tuple[Any, ...], list[tuple[Any, int, float, float]]] = {}
_GLYPHS: dict[tuple[Any, ...], tuple[Any, int, int]] = {}
_TEXTS: dict[tuple[Any, ...], tuple[Any, list[Any], Any]] = {}
#: Glyphs drawn from the cache and rasterised, texts laid out from it and anew (for the tests).
counts = {"hits": 0, "misses": 0, "layouts": 0, "new_layouts": 0}


def _forget_fonts() -> None:
    """Empty the caches that hold FreeType fonts (a layout's glyphs name their font, a bitmap's
    key too), in a process just forked. A font reads its file through a descriptor whose offset
    the fork shares with the parent and the other children: two processes drawing from one
    inherited font read each other's bytes (``RuntimeError: failed to load glyph`` in
    ``fingerpad analyse``'s QC pool, now and then). matplotlib empties its own font cache at
    a fork for the same reason; the text layouts hold no fonts and stay."""
    _LAYOUTS.clear()
    _GLYPHS.clear()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_fonts)


def _keep(cache: dict[Any, Any], key: Any, value: Any, cap: int) -> None:
    """Store ``value`` under ``key``; a cache holding ``cap`` entries starts again empty."""
    if len(cache) >= cap:
        cache.clear()
    cache[key] = value


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
            _keep(_LAYOUTS, key, items, MAX_LAYOUTS)
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
            _keep(_GLYPHS, key, cached, MAX_GLYPHS)
        else:
            counts["hits"] += 1
        buffer, left, top = cached
        # draw_text_image's y is downwards and the bitmap's bottom side
        renderer._renderer.draw_text_image(buffer, left + (gx >> 6), int(height) - (top + (gy >> 6)) + buffer.shape[0],
                                           0, gc)


def _text_key(text: Any, renderer: Any) -> tuple[Any, ...] | None:
    """What ``Text._get_layout`` reads (matplotlib 3.11), or ``None`` for a text it cannot be
    cached for (wrapped, TeX, mathtext)."""
    from matplotlib import cbook, rcParams
    from matplotlib.font_manager import fontManager

    string = text.get_text()
    if text.get_wrap() or text.get_usetex() or (text.get_parse_math() and cbook.is_math_text(string)):
        return None
    fp = text.get_fontproperties()
    return (type(renderer), renderer.dpi, text.get_figure(root=True).dpi, string,
            tuple(fontManager._find_fonts_by_props(fp)), tuple(fp.get_family()), fp.get_style(), fp.get_variant(),
            fp.get_weight(), fp.get_stretch(), fp.get_size_in_points(), fp.get_file(), fp.get_math_fontfamily(),
            rcParams["text.hinting"], rcParams["text.hinting_factor"], text._linespacing,
            text._get_multialignment(), text.get_rotation(), text._horizontalalignment,
            text._verticalalignment, text.get_rotation_mode())


@contextlib.contextmanager
def laid_out_once() -> Iterator[None]:
    """While in the block, every plain text is laid out from this module's cache (the box of
    each line relative to its anchor, in pixels): the same layout as matplotlib's own, worked out
    once per string, font, size, alignment and rotation. Not for several threads at once."""
    from matplotlib.text import Text

    layout = Text.__dict__.get("_get_layout")
    if layout is None or getattr(layout, "_fingerpad", False):  # an older matplotlib, or inside the block
        yield
        return

    def cached_layout(self: Any, renderer: Any) -> Any:
        key = _text_key(self, renderer)
        if key is None:
            return layout(self, renderer)
        found = _TEXTS.get(key)
        if found is None:
            counts["new_layouts"] += 1
            box, lines, corner = layout(self, renderer)
            found = (box.frozen(), list(lines), corner)
            _keep(_TEXTS, key, found, MAX_LAYOUTS)
        else:
            counts["layouts"] += 1
        box, lines, corner = found
        from matplotlib.transforms import Bbox

        return Bbox(box.get_points().copy()), list(lines), corner

    cached_layout._fingerpad = True  # type: ignore[attr-defined]
    Text._get_layout = cached_layout
    try:
        yield
    finally:
        Text._get_layout = layout
