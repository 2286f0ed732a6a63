"""The Explorer: a computed grid of runs and its page — the page as a string or a file, inline in a notebook
(an iframe), the runs and a run's link, the runs as text."""
from __future__ import annotations

import html as _html
import math
from pathlib import Path

from ...support import checks
from .page import render
from .text import count, dt_text, fmt_seconds, page_text

FRAME_HEIGHT = 940                                # the inline frame's height (px)


class Explorer:
    """A computed grid of runs and its page (see rbcourse.viz.explorer).

    .html(): the page (one string); .save(path): write it; shown inline in a notebook (an iframe holding the
    page: sandbox="allow-scripts", a title).  .runs: the runs (method, dt, steps, seconds, error, …);
    .run(method, dt); .fragment(method, dt): the link fragment that opens that run."""

    def __init__(self, grid):
        self.grid = grid
        self._html = None

    @property
    def runs(self) -> list:
        return self.grid.runs

    @property
    def settings(self):
        return self.grid.settings

    @property
    def reference(self):
        return self.grid.reference

    @property
    def plan(self):
        return self.grid.plan

    def run(self, method: str, dt: float):
        return self.grid.run(method, dt)

    def fragment(self, method: str | None = None, dt: float | None = None) -> str:
        """'#method=rk4&dt=0.005' (either key left out if None): the URL fragment that selects that run."""
        parts = []
        if method is not None:
            if method not in self.settings.methods:
                raise ValueError(f"method must be one of {list(self.settings.methods)}, got {method!r}")
            parts.append(f"method={method}")
        if dt is not None:
            number = isinstance(dt, (int, float)) and not isinstance(dt, bool)
            match = [d for d in self.settings.dts if number and math.isclose(d, dt, rel_tol=1e-9)]
            if not match:
                raise ValueError(f"dt must be one of {list(self.settings.dts)}, got {dt!r}")
            parts.append(f"dt={dt_text(match[0])}")
        return "#" + "&".join(parts) if parts else ""

    def html(self) -> str:
        """The standalone page: works from a file, offline; fetches nothing."""
        if self._html is None:
            self._html = render(self.grid)
        return self._html

    def save(self, path) -> Path:
        """Write the page to path (written whole or not at all); returns the path."""
        from ...support.outputs import write_text
        return write_text(checks.file_path("path", path), self.html())

    def title(self) -> str:
        s = self.settings
        grid = f"{count(len(s.methods), 'method')} × {count(len(s.dts), 'step')}"
        return page_text("explorer_title", name=s.name, grid=grid)

    def _repr_html_(self) -> str:
        """Inline in JupyterLab / Jupyter: an iframe holding the page (no server, no kernel needed to use it)."""
        from ..frame import iframe, trust_hint
        from ..viewer.sharing import inline         # meshcat's script: carried by the kernel's first view only
        fallback = page_text("fallback", title=_html.escape(self.title()), trust=_html.escape(trust_hint()))
        page, beside = inline(self.html())
        return iframe(srcdoc=page, height=FRAME_HEIGHT, title=self.title(), fallback=fallback) + beside

    def _repr_mimebundle_(self, include=None, exclude=None):
        """text/html (the page in a frame, a text line under it for an untrusted notebook) and text/plain."""
        return {"text/html": self._repr_html_(), "text/plain": self.summary()}

    def summary(self) -> str:
        """The runs as text: method, dt, steps, wall time, end error, outcome."""
        lines = [page_text("summary_head", title=self.title(), label=self.reference.label)]
        for r in self.runs:
            err = f"{r.error:.2e} rad" if math.isfinite(r.error) else "—"
            end = r.reason if r.diverged else page_text("ran_to", t=r.t_last)
            lines.append(f"  {r.method:>17} dt = {dt_text(r.dt):>8} s  " + page_text(
                "summary_row", steps=r.steps, seconds=fmt_seconds(r.seconds), err=err, end=end))
        return "\n".join(lines)

    def __repr__(self) -> str:
        return page_text("repr", title=self.title())
