"""A Drawing: a Recording (recording.py: the lowered meshcat commands of a still or an animation) and the page
that shows it — standalone (meshcat's viewer script and the commands inlined, compressed: works offline, loads
nothing), inline in JupyterLab (a sandboxed iframe holding the page, no server, with a text fallback for an
untrusted notebook), or as a PNG still or a GIF clip (save_png, save_gif, by headless Chromium: still.py).
Drawing.show() sends it to the live server (live.py)."""
from __future__ import annotations

import html as _html
import json
from pathlib import Path

import numpy as np

from ...support import checks
from ...support.language import say
from ..words import script_words
from . import assets
from ..frame import INLINE_HEIGHT, iframe, trust_hint
from .recording import Recording

LINKED_HEIGHT = 760          # px: a linked view's inline frame (the scene, and the plots under it)


class Drawing(Recording):
    """A Recording (recording.py: the lowered meshcat commands, duration, t0, speed, legend, arrow_scales)
    with its pages: html(), save(path), inline in a notebook, save_png, save_gif; show() sends it to the
    live viewer."""

    def html(self, *, title: str | None = None) -> str:
        """A standalone page: meshcat's viewer script and the commands inlined, compressed (assets.py).

        It works from a file, offline, and loads no external resource.  Its URL fragment
        ``#t=1.5`` shows the simulated time 1.5 s, paused; ``#controls=hidden`` hides meshcat's
        controls (both at once: ``#t=1.5&controls=hidden``).
        """
        if title is not None and not isinstance(title, str):
            raise ValueError(f"title must be a string or None, got {title!r}")
        title = self.title if title is None else title
        commands_text, commands_size = assets.compressed_commands(self.packed())
        legend = "".join(f'<div><span class="sw" style="background:#{c:06x}"></span>{_html.escape(t)}</div>'
                         for c, t in self.legend)
        boot = (f'var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));\n'
                f'rbCommands(viewer, "{commands_text}", {commands_size});\n'
                f'rbTimeline(viewer, {self.t0!r}, {self.speed!r}, {self.duration!r}, '
                f'{json.dumps(script_words(self.language), ensure_ascii=False)});')
        runtime, css, pane = assets.RUNTIME, assets.CSS, ""
        if self.plots is not None:                  # the linked view: the plots under the scene, one cursor
            data_text, data_size = assets.compress(json.dumps(self.plots, separators=(",", ":")).encode())
            runtime += "\n" + assets.TIMEPLOTS
            css += assets.LINKED_CSS
            pane = '<div id="rb-plots"></div>'
            boot += (f'\nrbPlots(viewer, JSON.parse(new TextDecoder().decode(rbLzma("{data_text}", {data_size}))), '
                     f'{self.t0!r}, {self.speed!r}, {self.duration!r});')
        return _PAGE.format(lang=self.language, title=_html.escape(title), css=css, legend=legend, plots=pane,
                            runtime=assets.script_tag(runtime),
                            viewer=assets.viewer_tag(),
                            boot=assets.script_tag(boot))

    def save(self, path) -> Path:
        """Write the standalone page (html()) to path; returns the path."""
        path = checks.file_path("path", path)
        path.write_text(self.html(), encoding="utf-8")
        return path

    def _fallback(self) -> str:
        return self.describe() + say(
            f". It shows in a trusted notebook (an untrusted notebook hides its scripts and frames): {trust_hint()}; "
            "or write it as a page with Drawing.save(path), which opens in any browser.",
            f". Elle s'affiche dans un notebook de confiance (un notebook non fiable cache ses scripts et ses cadres) : "
            f"{trust_hint()} ; ou écrivez-la comme une page avec Drawing.save(path), qui s'ouvre dans tout navigateur.")

    def _repr_html_(self) -> str:
        """JupyterLab / Jupyter: the recorded drawing inline (an iframe holding the page; no server), meshcat's
        script carried by the first view of the kernel only (sharing.py)."""
        from .sharing import inline
        page, beside = inline(self.html())
        return iframe(srcdoc=page, height=INLINE_HEIGHT if self.plots is None else LINKED_HEIGHT,
                      title=self.describe(),
                      fallback=_html.escape(self._fallback())) + beside

    def _repr_mimebundle_(self, include=None, exclude=None) -> dict:
        """The inline view (text/html, whose text says what it needs when its frame is stripped) and a text line."""
        return {"text/html": self._repr_html_(), "text/plain": self._fallback()}

    def save_png(self, path, t: float | None = None, *, size=(960, 640), chromium=None) -> Path:
        """A still of the drawing at simulated time t (default t0) as a PNG of size (width, height) pixels.

        Rendered by headless Chromium from the standalone page at ``#t=...`` (controls hidden),
        for slides; returns the path.  t must lie in time_range.  Needs Chromium (Debian/Ubuntu:
        apt-get install chromium): chromium is its executable, found on PATH by default.
        """
        from .still import render_png
        path = checks.file_path("path", path)
        lo, hi = self.time_range
        t = lo if t is None else t
        if (not checks.is_real_scalar(t) or not np.isfinite(float(t))
                or not lo - 1e-9 * (1 + abs(lo)) <= float(t) <= hi + 1e-9 * (1 + abs(hi))):
            raise ValueError(f"t must be a finite simulated time in [{lo:g}, {hi:g}] s (the drawing's range), got {t!r}")
        t = min(max(float(t), lo), hi)
        size = _size("size", size, high=4096)
        return render_png(self.html(), Path(path), fragment=f"t={t!r}&controls=hidden", size=size, chromium=chromium)

    def save_gif(self, path, *, frames: int = 30, size=(480, 320), chromium=None) -> Path:
        """The animation as a GIF of `frames` frames (evenly over it, played in real time, looping) of size
        (width, height) pixels, each with its time t written in a corner; returns the path.

        Drawn by headless Chromium in one go (a contact sheet of the frames, cut by Pillow).  Needs
        Chromium, as save_png.  A still has no animation: use save_png.
        """
        from .still import sheet_frames
        path = checks.file_path("path", path)
        if not self.duration:
            raise ValueError("a still has no animation to save as a GIF: use save_png(path)")
        frames = checks.integer("frames", frames, low=2, high=200)
        size = _size("size", size, high=1024)
        cols = int(np.ceil(np.sqrt(frames)))
        if cols * size[0] > 8192 or int(np.ceil(frames / cols)) * size[1] > 8192:
            raise ValueError(f"frames and size must fit 8192 x 8192 pixels in all ({frames} frames of {size}): "
                             "fewer frames or smaller ones")
        images = sheet_frames(self.html(), frames=frames, size=size, chromium=chromium)
        step_ms = max(20, int(round(1000 * self.duration / (frames - 1))))     # real time (GIF: 10 ms units, >= 20)
        images[0].save(Path(path), save_all=True, append_images=images[1:], duration=step_ms, loop=0,
                       optimize=True)
        return Path(path)

    def show(self, server: "LiveServer | None" = None) -> "LiveView":
        """Send to the live viewer (this process's server unless one is given); returns a LiveView."""
        from .live import LiveServer, LiveView, live_server        # the page needs no server: only show() does
        if server is None:
            server = live_server()
        elif not isinstance(server, LiveServer):
            raise ValueError(f"server must be a LiveServer or None, got {server!r}")
        server.draw(self)
        return LiveView(server.url, token=server.token)


def _size(name: str, size, *, high: int) -> tuple[int, int]:
    """(width, height) in pixels, each an integer in [16, high]."""
    if (not isinstance(size, (tuple, list)) or len(size) != 2
            or not all(isinstance(v, (int, np.integer)) and not isinstance(v, bool) for v in size)
            or not all(16 <= v <= high for v in size)):
        raise ValueError(f"{name} must be (width, height) in pixels, each an integer in [16, {high}], got {size!r}")
    return int(size[0]), int(size[1])


_PAGE = """<!DOCTYPE html>
<html lang="{lang}">
<head>
<meta charset="utf-8">
<title>{title}</title>
<style>{css}</style>
</head>
<body>
<div id="meshcat-pane"></div>
<div id="rb-info"><div><b>{title}</b></div><div id="rb-time"></div>{legend}</div>
<div id="rb-note" hidden></div>
{plots}
{runtime}
{viewer}
{boot}
</body>
</html>
"""
