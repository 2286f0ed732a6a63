"""The explorer's page: one self-contained HTML file (explorer.css and the scripts inlined, the runs as base64
(data.py: a JSON object, its float32 arrays in one buffer after it, both compressed in a JSON block: {"lzma": text,
"size": bytes, "json": the object's bytes}, viewer/assets.compress), its text fields and its template.

Its scripts, in order: the viewer's runtime (viewer/assets.py: the LZMA decoder, rbCommands, pause out of sight)
and its plotting code (viewer/js/timeplots.js: the drift panels, the axis helpers), meshcat's viewer script
(three.js, compressed as in every viewer page), then the explorer's own: the files of js/ (SCRIPTS), inlined one
after the other in one function scope (they share its variables: data.js decodes the data, api.js, the last,
starts the page).  The 3-D view is meshcat's scene (view.py makes its objects; js/scene.js moves them from the
page's time cursor).  Nothing is fetched: no CDN, no font, no image.
"""
from __future__ import annotations

import html as _html
import json
import math
import re
from importlib import resources

from .data import Arrays, page_data
from ..quantities import ROTATION_EVALS
from ...support.language import current, say
from .text import count, dt_text, fmt_seconds, page_text

SCRIPTS = ("data.js", "format.js", "controls.js", "fragment.js", "scene.js", "panels.js", "work_precision.js",
           "loop.js", "api.js")
"""The explorer's own script, file by file (in js/), in the order they are inlined: each file's top-level
statements run in this order (the functions are hoisted: any file may call any other's)."""


def asset(name: str) -> str:
    """explorer.css or js/NAME.js, package data read with importlib.resources."""
    return resources.files(__package__).joinpath(name).read_text(encoding="utf-8")


def script() -> str:
    """The explorer's own script: the files of SCRIPTS, in order, in one function scope, in strict mode."""
    return '(function () {\n"use strict";\n' + "\n".join(asset("js/" + name) for name in SCRIPTS) + "})();\n"


def libraries() -> str:
    """The script tags run before the explorer's own: the viewer's runtime and plotting code, meshcat's viewer."""
    from ..viewer import assets                     # meshcat: loaded when a page is made, not with the package
    return "\n".join([assets.script_tag(assets.RUNTIME + "\n" + assets.TIMEPLOTS), assets.viewer_tag()])


def _table(grid) -> str:
    rows = []
    for r in grid.runs:
        outcome = _html.escape(r.reason) if r.diverged else page_text("ran_to", t=r.t_last)
        err = "—" if not math.isfinite(r.error) else f"{r.error:.2e}"
        pos = "—" if not math.isfinite(r.position_error) else f"{r.position_error:.2e}"
        rows.append(f"<tr><td>{r.method}</td><td>{dt_text(r.dt)}</td><td>{r.steps}</td><td>{fmt_seconds(r.seconds)}"
                    f"</td><td>{err}</td><td>{pos}</td><td>{outcome}</td></tr>")
    return ("<table><thead><tr>" + page_text("th") + "</tr></thead>"
            "<tbody>" + "".join(rows) + "</tbody></table>")


def render(grid) -> str:
    """The whole page as one string."""
    return fill(page_fields(grid))


def fill(fields: dict) -> str:
    """The page template with its fields (page_fields), explorer.css and the scripts filled in (one pass: a field's
    text is never read as a placeholder)."""
    from ..viewer.assets import script_tag
    values = {**fields, "CSS": asset("explorer.css"), "LIBRARIES": libraries(), "JS": script_tag(script())}
    return re.sub(r"%%([A-Z_]+)%%", lambda m: values[m.group(1)], TEMPLATE)


def page_fields(grid) -> dict:
    """The page's text fields and its data (JSON), from a computed grid."""
    s, plan, ref = grid.settings, grid.plan, grid.reference
    from ..viewer.assets import compress
    arrays = Arrays()
    body = json.dumps(page_data(grid, arrays), separators=(",", ":"), ensure_ascii=False, allow_nan=False).encode()
    text, size = compress(body + arrays.packed())   # LZMA in base 85: 02's explorer 650 kB of base64 -> ~220 kB
    data = json.dumps({"lzma": text, "size": size, "json": len(body)})
    esc = _html.escape
    colon = say(": ", " : ")
    notes = "".join(f"<li><b>{esc(q.title)}</b> ({esc(q.unit)}){colon}{esc(q.note)}</li>" for q in plan.quantities)
    accuracy = ""
    if ref.accuracy is not None:
        accuracy = page_text("beyond_accuracy")
    n_runs = len(grid.runs)
    fields = {
        "LANG": current(),
        "TITLE": esc(page_text("title", name=s.name)),
        "NAME": esc(s.name),
        "DESCRIPTION": esc(s.description + ("." if s.description and not s.description.endswith(".") else "")),
        "SCENE": esc(s.scene.describe()),
        "GRID": esc(f"{count(len(s.methods), 'method')} × {count(len(s.dts), 'step')} ({count(n_runs, 'run')}), "
                    f"t = 0 … {s.t_end:g} s"),
        "REFERENCE": esc(page_text("reference", detail=ref.detail)) + accuracy,
        "TIMING": esc(page_text("timing", warmup=grid.warmup_note, seconds=grid.seconds)),
        "NOTES": notes,
        "TABLE": _table(grid),
        "RESAMPLING": _words(page_text("resampling", evals=f"{ROTATION_EVALS:,}")),
        "DATA": data,
    }
    fields.update({f"W_{key.upper()}": _words(page_text(key)) for key in _TEMPLATE_WORDS})
    return fields


def _words(text: str) -> str:
    """A text for the template, in an element or a double-quoted attribute (& < > " escaped; ' kept)."""
    return _html.escape(text, quote=False).replace('"', "&quot;")


_TEMPLATE_WORDS = ("subtitle", "method", "method_aria", "step", "step_aria", "play_aria", "time_aria", "speed_aria",
                   "real_time", "ghost_title", "ghost", "view_aria", "pane_aria", "plots_aria", "wp_aria", "wp_head",
                   "wp_click", "notes_head", "scene_head")
"""The words of PAGE the template holds as they are (each as the field W_KEY)."""


TEMPLATE = """<!DOCTYPE html>
<html lang="%%LANG%%">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>%%TITLE%%</title>
<style>
%%CSS%%
</style>
</head>
<body>
<div id="rb-root">
<header>
  <h1>%%NAME%% <span class="rb-sub">%%W_SUBTITLE%%</span></h1>
  <p class="rb-desc">%%DESCRIPTION%% %%GRID%%.</p>
</header>
<div id="rb-controls">
  <div class="rb-group" role="group" aria-label="%%W_METHOD_ARIA%%"><span class="rb-label">%%W_METHOD%%</span><span id="rb-methods"></span></div>
  <div class="rb-group" role="group" aria-label="%%W_STEP_ARIA%%"><span class="rb-label">%%W_STEP%%</span><span id="rb-dts"></span></div>
  <div class="rb-group rb-time">
    <button type="button" id="rb-play" aria-label="%%W_PLAY_ARIA%%">pause</button>
    <input type="range" id="rb-slider" min="0" max="1000" step="1" value="0" aria-label="%%W_TIME_ARIA%%">
    <output id="rb-t" for="rb-slider">t = 0.00 s</output>
    <select id="rb-speed" aria-label="%%W_SPEED_ARIA%%"><option value="0.25">×0.25</option><option value="0.5">×0.5</option><option value="1" selected>×1 %%W_REAL_TIME%%</option><option value="2">×2</option><option value="4">×4</option></select>
    <label class="rb-check" title="%%W_GHOST_TITLE%%"><input type="checkbox" id="rb-ghost"> %%W_GHOST%%</label>
  </div>
</div>
<p id="rb-note" role="status" hidden></p>
<p id="rb-status" role="status"></p>
<div id="rb-main">
  <section id="rb-view-box" aria-label="%%W_VIEW_ARIA%%">
    <div id="meshcat-pane" aria-label="%%W_PANE_ARIA%%"></div>
    <div id="rb-view-legend"></div>
    <div id="rb-view-warning" hidden></div>
  </section>
  <section id="rb-plots" aria-label="%%W_PLOTS_ARIA%%"></section>
  <section id="rb-wp-box" aria-label="%%W_WP_ARIA%%">
    <h2>%%W_WP_HEAD%% <span class="rb-sub">%%W_WP_CLICK%%</span></h2>
    <canvas id="rb-wp"></canvas>
    <div id="rb-wp-legend"></div>
  </section>
  <section id="rb-notes">
    <h2>%%W_NOTES_HEAD%%</h2>
    <ul>%%NOTES%%</ul>
    <p>%%REFERENCE%%</p>
    <p>%%TIMING%%</p>
    <p class="rb-small">%%RESAMPLING%%<code>#method=…&amp;dt=…</code>.</p>
    <details><summary>%%W_SCENE_HEAD%%</summary><p class="rb-small">%%SCENE%%</p>%%TABLE%%</details>
  </section>
</div>
</div>
<script type="application/json" id="rb-data">%%DATA%%</script>
%%LIBRARIES%%
%%JS%%
</body>
</html>
"""
