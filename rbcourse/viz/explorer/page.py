"""The explorer's page: one self-contained HTML file (explorer.css and explorer.js inlined, the runs as
base64 float32 arrays in a JSON block), and the Explorer object that holds a computed grid.

Nothing is fetched: no CDN, no font, no image; the 3-D view is drawn by hand on a 2-D canvas (the bodies'
faces projected with a fixed camera, back faces culled, Lambert shading; a floor grid and shadow; the
body axes), the plots and the work-precision panel too — no WebGL, so the page works on any browser and a
screenshot is the same on every machine.
"""
from __future__ import annotations

import base64
import html as _html
import json
import math
import os
from importlib import resources
from pathlib import Path

import numpy as np

from ...contact import Ground
from ...effects import Gravity, Spring
from ...pivot import Pivot
from .quantities import ROTATION_EVALS

METHOD_COLORS = ("#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#e377c2")
BODY_COLORS = ("#f28e2b", "#59a14f", "#b07aa1", "#9c755f", "#edc948", "#ff9da7")
GHOST_COLOR = "#17becf"
FOV = 40.0                                        # the camera's vertical field of view (degrees)
VIEW_DIRECTION = np.array([1.0, 0.7, 0.55])       # where the camera sits, seen from what it looks at
FRAME_HEIGHT = 940                                # the inline frame's height (px)
FLOOR = 1e-17                                     # the log plots' lowest value
CEILING = 1e3                                     # and their highest (a relative drift of 10³: the run has blown up)


def asset(name: str) -> str:
    """explorer.css or explorer.js, package data read with importlib.resources."""
    return resources.files(__package__).joinpath(name).read_text(encoding="utf-8")


def _b64(a) -> str:
    return base64.b64encode(np.ascontiguousarray(a, dtype="<f4").tobytes()).decode("ascii")


def _num(x):
    """A float for JSON, or None if it is not finite (JSON has no inf)."""
    x = float(x)
    return x if math.isfinite(x) else None


def dt_text(dt: float) -> str:
    """dt as the page and its links write it: the shortest text that reads back as the same float."""
    return repr(float(dt))


# --- the bodies' shapes, as convex meshes in body axes ------------------------------------------------

def mesh(body) -> dict:
    """A convex mesh of the body in body axes: vertices v (flat list), faces f (vertex indices, outward
    normals n), outline (draw the edges: a box).  A box of its size, a cylinder (24 sides, axis body z),
    a sphere; any other body: the ellipsoid of its inertia along its principal axes (body.half_extents())."""
    if body.shape == "box" and body.size:
        a, b, c = (float(s) / 2 for s in body.size)
        v = np.array([[sx * a, sy * b, sz * c] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
        faces = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
        return _finish(v, faces, True)
    if body.shape == "cylinder" and body.size:
        r, h = (float(s) for s in body.size)
        k = 24
        ang = 2 * np.pi * np.arange(k) / k
        ring = np.stack([r * np.cos(ang), r * np.sin(ang)], -1)
        h = max(h, 1e-3 * r)
        v = np.concatenate([np.c_[ring, np.full(k, -h / 2)], np.c_[ring, np.full(k, h / 2)]])
        faces = [[i, (i + 1) % k, k + (i + 1) % k, k + i] for i in range(k)]
        faces += [list(range(k)), list(range(k, 2 * k))]
        return _finish(v, faces, False)
    if body.shape == "sphere" and body.size:
        radii, axes = np.full(3, float(body.size[0])), np.eye(3)
    else:
        radii, axes = body.half_extents(), np.asarray(body.principal_axes, dtype=float)
        radii = np.maximum(radii, 1e-3 * radii.max())
    n_lat, n_lon = 8, 16
    lat = np.pi * (np.arange(1, n_lat) / n_lat - 0.5)
    lon = 2 * np.pi * np.arange(n_lon) / n_lon
    pts = [[0, 0, -1.0]] + [[np.cos(a) * np.cos(o), np.cos(a) * np.sin(o), np.sin(a)] for a in lat for o in lon] \
        + [[0, 0, 1.0]]
    v = (np.array(pts) * radii) @ axes.T
    faces = [[0, 1 + (j + 1) % n_lon, 1 + j] for j in range(n_lon)]
    for i in range(n_lat - 2):
        for j in range(n_lon):
            a, b = 1 + i * n_lon + j, 1 + i * n_lon + (j + 1) % n_lon
            faces.append([a, b, b + n_lon, a + n_lon])
    top, last = len(pts) - 1, 1 + (n_lat - 2) * n_lon
    faces += [[last + j, last + (j + 1) % n_lon, top] for j in range(n_lon)]
    return _finish(v, faces, False)


def _finish(v: np.ndarray, faces: list, outline: bool) -> dict:
    """Faces turned so that their normals point outwards (away from the centre), with those normals."""
    centre = v.mean(0)
    out, normals = [], []
    for f in faces:
        p = v[f]
        n = np.zeros(3)
        for i in range(len(f)):                     # Newell's normal: robust for any planar polygon
            a, b = p[i], p[(i + 1) % len(f)]
            n += np.cross(a, b)
        if np.dot(n, p.mean(0) - centre) < 0:
            f, n = f[::-1], -n
        out.append([int(i) for i in f])
        normals.append((n / np.linalg.norm(n)).round(6).tolist())
    return {"v": np.round(v, 7).ravel().tolist(), "f": out, "n": normals, "outline": outline}


# --- camera, floor and what holds the bodies ------------------------------------------------------

def _nice(value: float) -> float:
    """The number among 1, 2, 5 × 10^k nearest to value (in ratio)."""
    k = np.floor(np.log10(value))
    candidates = np.array([1.0, 2.0, 5.0, 10.0]) * 10.0 ** k
    return float(candidates[np.abs(np.log(candidates / value)).argmin()])


def view_setup(scene, ghost) -> dict:
    """Camera and floor, from the reference's path (ghost: a Track).

    One body moving far (more than 3 body sizes): the camera follows the chosen run's body (the reference is
    seen against it) and a floor under it; otherwise a fixed camera frames the whole motion of every body,
    the floor at a Ground's height, or under the lowest point of the motion."""
    radius = max(float(np.linalg.norm(b.half_extents())) for b in scene.bodies)
    size = max(2 * float(b.half_extents().max()) for b in scene.bodies)
    path = ghost.x.astype(float).reshape(len(ghost.t), -1, 3)
    anchors = [np.asarray(e.world_point, dtype=float) for e in scene.effects if isinstance(e, (Pivot, Spring))
               and getattr(e, "other_body", None) is None]
    reach = float(np.linalg.norm(path[:, 0] - path[0, 0], axis=-1).max())
    follow = scene.single and reach > 3 * size
    ground = next((e.height for e in scene.effects if isinstance(e, Ground)), None)
    half_fov = math.radians(FOV / 2)
    if follow:
        distance = 2.2 * radius / math.sin(half_fov)
        target = path[0, 0]
        extent = distance
    else:
        pts = np.concatenate([path.reshape(-1, 3)] + ([np.array(anchors)] if anchors else []))
        lo, hi = pts.min(0), pts.max(0)
        if ground is not None:
            lo[2] = min(lo[2], ground)
        target = (lo + hi) / 2
        sphere = float(np.linalg.norm(hi - lo)) / 2 + radius
        distance = max(1.4 * sphere, 2.2 * radius) / math.sin(half_fov)
        extent = max(sphere, 4 * size)
    if ground is not None:
        floor = {"z": float(ground), "follow": False}
    elif follow:
        floor = {"z": None, "follow": True, "offset": 1.6 * radius}
    else:
        floor = {"z": float(path[..., 2].min() - 1.3 * radius), "follow": False}
    step = _nice(max(1.6 * size, extent / 8))
    floor.update(step=step, lines=int(np.clip(np.ceil(1.6 * extent / step) + 2, 6, 24)))
    d = VIEW_DIRECTION / np.linalg.norm(VIEW_DIRECTION)
    return {"fov": FOV, "direction": d.round(6).tolist(), "distance": float(distance), "follow": bool(follow),
            "target": np.round(target, 9).tolist(), "floor": floor, "ground": ground is not None,
            "gravity": any(isinstance(e, Gravity) for e in scene.effects)}


def attachments(scene) -> list:
    """Pivots (a point, and the stem to the centre of mass) and springs (a zigzag to their anchor)."""
    out = []
    for e in scene.effects:
        if isinstance(e, Pivot):
            for i in scene.bodies_of(e):
                out.append({"kind": "pivot", "body": int(i), "b": e.body_point.tolist(), "p": e.world_point.tolist()})
        elif isinstance(e, Spring) and e.other_body is None:
            for i in scene.bodies_of(e):
                out.append({"kind": "spring", "body": int(i), "b": e.body_point.tolist(), "p": e.world_point.tolist()})
        elif isinstance(e, Spring):
            out.append({"kind": "spring2", "body": int(scene.bodies_of(e)[0]), "b": e.body_point.tolist(),
                        "other": scene.other_body_of(e), "ob": e.other_point.tolist()})
    return out


# --- the page's data ------------------------------------------------------------------------------

def _track(tr) -> dict:
    return {"n": int(len(tr.t)), "t": _b64(tr.t), "x": _b64(tr.x), "q": _b64(tr.q)}


def _decades(values, low=FLOOR, high=1e30, pad_low=0.3, pad_high=0.3):
    """[lo, hi] (log10, integers) holding the positive finite values (lo >= log10(low)); down to log10(low)
    if some value is exactly 0 (drawn on the bottom edge)."""
    v = np.concatenate([np.ravel(a) for a in values]) if values else np.array([])
    zero = bool(np.any(v == 0))
    v = v[np.isfinite(v) & (v > 0)]
    if v.size == 0:
        return [round(math.log10(low)), 0]
    lo = max(math.floor(math.log10(max(v.min(), low)) - pad_low), round(math.log10(low)))
    if zero:
        lo = round(math.log10(low))
    hi = min(math.ceil(math.log10(min(v.max(), high)) + pad_high), math.ceil(math.log10(high) - 1e-9))
    return [int(lo), int(max(hi, lo + 1))]


def _after_start(v: np.ndarray) -> np.ndarray:
    """A curve without its first defined point (0 by construction: a drift from itself, R(0) = R_ref(0))."""
    v = v.astype(float)
    first = np.flatnonzero(~np.isnan(v))
    if first.size:
        v[first[0]] = np.nan
    return v


def page_data(grid) -> dict:
    """Everything the page's script reads (one JSON object; arrays as base64 float32)."""
    s, plan, ref = grid.settings, grid.plan, grid.reference
    panels = []
    for q in plan.quantities:
        v = [_after_start(r.curves[q.key]) for r in grid.runs]
        rotation = q.key == "rotation"              # at most π; the others are cut at CEILING (off the chart above)
        panels.append({"key": q.key, "title": q.title, "unit": q.unit, "note": q.note, "mode": q.mode,
                       "ylim": _decades(v, high=math.pi if rotation else CEILING, pad_high=0.0 if rotation else 0.3)})
    errors = [r.error for r in grid.runs if math.isfinite(r.error)]
    if ref.accuracy is not None and math.isfinite(ref.accuracy):
        errors.append(ref.accuracy)
    seconds = [r.seconds for r in grid.runs]
    runs = []
    for r in grid.runs:
        runs.append({
            "method": r.method, "dt": r.dt, "dt_index": s.dts.index(r.dt), "h": r.h, "steps": r.steps,
            "seconds": r.seconds, "error": _num(r.error), "position_error": _num(r.position_error),
            "diverged": r.diverged, "reason": r.reason, "t_last": r.t_last, "t_diverged": _num(r.t_diverged),
            "implementation": r.implementation,
            "drawn_note": r.drawn_note, "drawn_until": float(r.track.t[-1]),
            "curve_t": _b64(r.curve_t), "curves": {k: _b64(v) for k, v in r.curves.items()}, "track": _track(r.track)})
    from ...integrators import METHODS
    methods = [{"name": m, "color": METHOD_COLORS[i % len(METHOD_COLORS)], "order": METHODS[m].order,
                "summary": METHODS[m].summary} for i, m in enumerate(s.methods)]
    bodies = [{"mesh": mesh(b), "color": BODY_COLORS[0] if s.scene.single else BODY_COLORS[i % len(BODY_COLORS)],
               "axis": 1.5 * float(b.half_extents().max())} for i, b in enumerate(s.scene.bodies)]
    return {
        "version": 1, "name": s.name, "description": s.description, "t_end": s.t_end, "t0": s.drift_from,
        "methods": methods, "dts": list(s.dts), "dt_labels": [dt_text(d) for d in s.dts], "steps": list(s.steps),
        "default": {"method": s.methods.index(s.default[0]), "dt": s.dts.index(s.default[1])},
        "panels": panels,
        "reference": {"exact": ref.exact, "label": ref.label, "detail": ref.detail,
                      "accuracy": None if ref.accuracy is None else _num(ref.accuracy)},
        "wp": {"xlim": _decades([np.array(seconds)], low=1e-9, pad_low=0.1, pad_high=0.1),
               "ylim": _decades([np.array(errors)], high=10.0, pad_high=0.0)},
        "bodies": bodies, "attachments": attachments(s.scene), "view": view_setup(s.scene, grid.ghost),
        "show_ghost": s.scene.n_bodies <= 3,
        "ghost": _track(grid.ghost), "runs": runs,
    }


# --- the page -------------------------------------------------------------------------------------

def _count(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"


def _fmt_seconds(x: float) -> str:
    return f"{x * 1e3:.3g} ms" if x < 1 else f"{x:.3g} s"


def _table(grid) -> str:
    rows = []
    for r in grid.runs:
        outcome = _html.escape(r.reason) if r.diverged else f"ran to t = {r.t_last:g} s"
        err = "—" if not math.isfinite(r.error) else f"{r.error:.2e}"
        pos = "—" if not math.isfinite(r.position_error) else f"{r.position_error:.2e}"
        rows.append(f"<tr><td>{r.method}</td><td>{dt_text(r.dt)}</td><td>{r.steps}</td><td>{_fmt_seconds(r.seconds)}"
                    f"</td><td>{err}</td><td>{pos}</td><td>{outcome}</td></tr>")
    return ("<table><thead><tr><th>method</th><th>dt (s)</th><th>steps</th><th>wall time</th>"
            "<th>rotation error at t_end (rad)</th><th>position error at t_end (m)</th><th>outcome</th></tr></thead>"
            "<tbody>" + "".join(rows) + "</tbody></table>")


def render(grid) -> str:
    """The whole page as one string."""
    return fill(page_fields(grid))


def fill(fields: dict) -> str:
    """The page template with its fields (page_fields), explorer.css and explorer.js filled in."""
    out = TEMPLATE
    for key, value in {**fields, "CSS": asset("explorer.css"), "JS": asset("explorer.js")}.items():
        out = out.replace("%%" + key + "%%", value)
    return out


def page_fields(grid) -> dict:
    """The page's text fields and its data (JSON), from a computed grid."""
    s, plan, ref = grid.settings, grid.plan, grid.reference
    data = json.dumps(page_data(grid), separators=(",", ":"), ensure_ascii=False, allow_nan=False)
    data = data.replace("</", "<\\/")
    esc = _html.escape
    notes = "".join(f"<li><b>{esc(q.title)}</b> ({esc(q.unit)}): {esc(q.note)}</li>" for q in plan.quantities)
    accuracy = ""
    if ref.accuracy is not None:
        accuracy = (" Errors below its own accuracy (the dashed line in the work-precision panel) are not "
                    "resolved by this reference.")
    n_runs = len(grid.runs)
    fields = {
        "TITLE": esc(f"{s.name}: accuracy explorer"),
        "NAME": esc(s.name),
        "DESCRIPTION": esc(s.description + ("." if s.description and not s.description.endswith(".") else "")),
        "SCENE": esc(s.scene.describe()),
        "GRID": esc(f"{_count(len(s.methods), 'method')} × {_count(len(s.dts), 'step')} ({_count(n_runs, 'run')}), "
                    f"t = 0 … {s.t_end:g} s"),
        "REFERENCE": esc(f"Reference (the ghost, and what the errors are measured against): {ref.detail}.") + accuracy,
        "TIMING": esc(f"Wall time: time.perf_counter() around each rb.simulate call when this page was made, "
                      f"{grid.warmup_note}; one measurement each, on the machine that made the page (the whole grid "
                      f"took {grid.seconds:.3g} s, warm-ups and reference included). Error at the end: the "
                      f"rotation angle between "
                      f"R(t_end) and the reference's (rad); a run that diverged has none and sits in the top band."),
        "NOTES": notes,
        "TABLE": _table(grid),
        "ROTATION_EVALS": f"{ROTATION_EVALS:,}",
        "DATA": data,
    }
    return fields


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
        from ...outputs import write_text
        if not isinstance(path, (str, os.PathLike)) or str(path) == "":
            raise ValueError(f"path must be a file path, got {path!r}")
        path = Path(path)
        if path.is_dir():
            raise ValueError(f"path must be a file path, but {path} is a folder")
        if not path.parent.is_dir():
            raise ValueError(f"path: the folder {path.parent} does not exist")
        return write_text(path, self.html())

    def title(self) -> str:
        s = self.settings
        grid = f"{_count(len(s.methods), 'method')} × {_count(len(s.dts), 'step')}"
        return f"rbcourse accuracy explorer: {s.name}, {grid}"

    def _repr_html_(self) -> str:
        """Inline in JupyterLab / Jupyter: an iframe holding the page (no server, no kernel needed to use it)."""
        from ..frame import iframe
        fallback = (f"<b>{_html.escape(self.title())}</b>: an interactive page (pick a method and a step, watch the "
                    "body and its drift together). It needs a <i>trusted</i> notebook: run this cell, or File ▸ Trust "
                    "Notebook. Or save it, <code>explorer.save(\"explorer.html\")</code>, and open the file in a browser.")
        return iframe(srcdoc=self.html(), height=FRAME_HEIGHT, title=self.title(), fallback=fallback)

    def _repr_mimebundle_(self, include=None, exclude=None):
        """text/html (the page in a frame, a text line under it for an untrusted notebook) and text/plain."""
        return {"text/html": self._repr_html_(), "text/plain": self.summary()}

    def summary(self) -> str:
        """The runs as text: method, dt, steps, wall time, end error, outcome."""
        lines = [f"{self.title()} (reference: {self.reference.label})"]
        for r in self.runs:
            err = f"{r.error:.2e} rad" if math.isfinite(r.error) else "—"
            end = r.reason if r.diverged else f"ran to t = {r.t_last:g} s"
            lines.append(f"  {r.method:>17} dt = {dt_text(r.dt):>8} s  {r.steps:>7} steps  "
                         f"{_fmt_seconds(r.seconds):>9}  error {err:>12}  {end}")
        return "\n".join(lines)

    def __repr__(self) -> str:
        return f"<Explorer: {self.title()}; .save(path) writes the page>"


TEMPLATE = """<!DOCTYPE html>
<html lang="en">
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
  <h1>%%NAME%% <span class="rb-sub">— accuracy explorer: what each method and step cost, and what they keep</span></h1>
  <p class="rb-desc">%%DESCRIPTION%% %%GRID%%.</p>
</header>
<div id="rb-controls">
  <div class="rb-group" role="group" aria-label="method (méthode d'intégration)"><span class="rb-label">method</span><span id="rb-methods"></span></div>
  <div class="rb-group" role="group" aria-label="time step dt (pas de temps)"><span class="rb-label">step dt</span><span id="rb-dts"></span></div>
  <div class="rb-group rb-time">
    <button type="button" id="rb-play" aria-label="play or pause the animation">pause</button>
    <input type="range" id="rb-slider" min="0" max="1000" step="1" value="0" aria-label="time t (s)">
    <output id="rb-t" for="rb-slider">t = 0.00 s</output>
    <select id="rb-speed" aria-label="playback speed"><option value="0.25">×0.25</option><option value="0.5">×0.5</option><option value="1" selected>×1 real time</option><option value="2">×2</option><option value="4">×4</option></select>
    <label class="rb-check" title="the reference motion, drawn semi-transparent"><input type="checkbox" id="rb-ghost"> ghost</label>
  </div>
</div>
<p id="rb-note" role="status" hidden></p>
<p id="rb-status" role="status"></p>
<div id="rb-main">
  <section id="rb-view-box" aria-label="the body in 3-D">
    <canvas id="rb-view" aria-label="3-D view of the chosen run, with the reference as a ghost"></canvas>
    <div id="rb-view-legend"></div>
    <div id="rb-view-warning" hidden></div>
  </section>
  <section id="rb-plots" aria-label="the chosen run's drift and error over time (click a plot to jump there)"></section>
  <section id="rb-wp-box" aria-label="work-precision: wall time against the error at the end">
    <h2>What accuracy costs: wall time vs error at t_end <span class="rb-sub">(click a point to pick that run)</span></h2>
    <canvas id="rb-wp"></canvas>
    <div id="rb-wp-legend"></div>
  </section>
  <section id="rb-notes">
    <h2>What is plotted, and why</h2>
    <ul>%%NOTES%%</ul>
    <p>%%REFERENCE%%</p>
    <p>%%TIMING%%</p>
    <p class="rb-small">Each plotted point is the largest value over the steps since the previous point, so no spike
    is lost in the resampling (the rotation error: over every step, or every k-th step in runs of more than
    %%ROTATION_EVALS%% body-steps); log scales. Link to one run with the page's address followed by
    <code>#method=…&amp;dt=…</code>.</p>
    <details><summary>The scene, and every run</summary><p class="rb-small">%%SCENE%%</p>%%TABLE%%</details>
  </section>
</div>
</div>
<script type="application/json" id="rb-data">%%DATA%%</script>
<script>
%%JS%%
</script>
</body>
</html>
"""
