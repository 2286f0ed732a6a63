"""A notebook's inline matplotlib figures as 256-colour PNGs (issue 28: a full-length "Run All" of 02 saved 480 kB
of figures; a palette of 256 colours keeps every line and label as drawn — the figures are flat colours on white —
at ~40 % of the size).

register() makes it the PNG of every matplotlib Figure the running IPython shows (the inline backend's figures
and a Figure as a cell's value); outside IPython it does nothing.  rbcourse.viz.plots calls it when imported.
"""
from __future__ import annotations

import io
import sys

COLOURS = 256


def quantised(png: bytes, colours: int = COLOURS) -> bytes:
    """A PNG (bytes) as a PNG of at most `colours` colours (median cut, no dithering), optimised; an image with
    transparency is returned as it was (the palette would drop its alpha)."""
    from PIL import Image
    if not isinstance(png, (bytes, bytearray)):
        raise ValueError(f"png must be the bytes of a PNG image, got {type(png).__name__}")
    if not (isinstance(colours, int) and 2 <= colours <= 256):
        raise ValueError(f"colours must be an integer in [2, 256], got {colours!r}")
    image = Image.open(io.BytesIO(png))
    if image.mode in ("RGBA", "LA") and image.getchannel("A").getextrema()[0] < 255:
        return bytes(png)
    out = io.BytesIO()
    image.convert("RGB").quantize(colors=colours, method=Image.Quantize.MEDIANCUT,
                                  dither=Image.Dither.NONE).save(out, "PNG", optimize=True)
    return out.getvalue() if out.tell() < len(png) else bytes(png)


def figure_png(fig) -> bytes:
    """The figure as the inline backend draws it (its bounding box tight), quantised (None for an empty figure, as
    the inline backend: nothing shown)."""
    from IPython.core.pylabtools import print_figure
    png = print_figure(fig, "png", bbox_inches="tight")
    return None if png is None else quantised(png)


def register() -> bool:
    """Show the running IPython's matplotlib Figures as quantised PNGs; False (nothing done) outside IPython (a
    process that has not imported IPython is not running in it: IPython is not imported to ask, 0.06 s)."""
    if "IPython" not in sys.modules:
        return False
    from IPython import get_ipython
    shell = get_ipython()
    if shell is None:
        return False
    import matplotlib.pyplot  # noqa: F401  (the inline backend sets its own formatter on import: ours after it)
    from matplotlib.figure import Figure
    shell.display_formatter.formatters["image/png"].for_type(Figure, figure_png)
    return True
