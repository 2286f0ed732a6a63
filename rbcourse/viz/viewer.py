"""The bodies in meshcat: a still, an animation of a Trajectory, a standalone page, a live viewer.

    from rbcourse import viewer
    d = viewer.draw_trajectory(traj)          # a Drawing: meshcat commands, nothing sent yet
    d                                         # in JupyterLab: the recorded animation, inline
    d.save("box.html")                        # a standalone page: works offline, loads nothing
    d.show()                                  # live: this process's meshcat server (127.0.0.1 only)
    viewer.close_live_server()                # stop it (also done at exit)

In JupyterLab, a Drawing as the last expression of a cell shows the recorded animation
inline (an iframe holding the page: no server, works with a remote kernel too); d.show()
returns a LiveView, shown as an iframe on the live server's URL, which the browser reaches
only when it runs on the kernel's machine (the server listens on 127.0.0.1 only).

What is drawn, all in world axes (z up, metres):
  * each body with its true shape: a box (size = full sides), a cylinder (axis = body z,
    size = (radius, height)), a sphere (size = (radius,)), any other body as the ellipsoid
    of its inertia (body.half_extents(), turned to the principal axes); its body axes
    (x red, y green, z blue);
  * arrows: ω and L from the centre of mass, each force of a PointForce from its point
    r = x + R b (tail at the point).  Each kind of arrow has its own scale: the largest
    value over the run is drawn ``arrow_length`` metres long (Drawing.arrow_scales gives
    the metres per unit);
  * optionally the trail of a body point, and a "ghost": a second trajectory (the exact
    motion, another integrator) drawn semi-transparent in another colour, over or beside;
  * a floor grid (at z = 0 or on the ground), the ground plane of a ``Ground`` effect
    (at its .height), the point of a ``Pivot``.
The camera follows the body of a one-body scene (the drawing is shifted under it), or
frames the whole motion.

R may have left SO(3) under the slides' Euler: every R is projected onto SO(3)
(rotation.project_so3) before it becomes a meshcat transform, since a transform
must be a rotation.  The arrows use the physics' own vectors (ω = I⁻¹(t) L with the
unprojected R, forces from the effects); body points use the projected R so that
they sit on the drawn body.

This module is imported on demand (the physics never imports it nor meshcat).
"""
from __future__ import annotations

import atexit
import base64
import html as _html
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import meshcat.geometry as g
import numpy as np
import umsgpack
from meshcat.animation import Animation, AnimationClip, AnimationTrack
from meshcat.commands import Delete, SetAnimation, SetObject, SetProperty, SetTransform
from meshcat.path import Path as MeshcatPath

from .. import Ground, Pivot, checks
from ..effects import PointForce
from ..rotation import matvec, project_so3, quat_from_matrix
from ..scene import as_scene
from ..state import State, angular_velocity, inverse_inertia
from ..trajectory import Trajectory

__all__ = ["Drawing", "draw_state", "draw_trajectory", "LiveServer", "LiveView", "live_server",
           "close_live_server", "live_server_pids", "COLORS"]

COLORS = {
    "body": 0xF28E2B, "ghost": 0x17BECF, "omega": 0xE040E0, "L": 0xFFD92F, "force": 0xE41A1C,
    "trail": 0xFFFFFF, "ground": 0x8A9A7B, "pivot": 0x333333, "grid": 0xB0B0B0,
}
_BODY_PALETTE = (0xF28E2B, 0x59A14F, 0xB07AA1, 0x9C755F, 0xEDC948, 0xFF9DA7)
_FOV = 75.0                                          # meshcat's default camera, vertical field of view (deg)
_VIEW_DIRECTION = np.array([1.0, 0.65, 0.45])       # where the camera sits, seen from its target
_TINY = 1e-9                                         # scale of an arrow of zero length (hidden)
_JS_PATH = Path(os.path.dirname(g.__file__)) / "viewer" / "dist" / "main.min.js"


# =====================================================================================
# Drawing: the commands, the page, the notebook view
# =====================================================================================

class Drawing:
    """What a viewer shows: lowered meshcat commands (dicts), in the order they are applied.

    commands: set_object / set_transform / set_property, then at most one set_animation.
    duration: playback length in seconds (0 for a still); t0, speed: the simulated time
    shown at playback time τ is t0 + speed·τ.  arrow_scales: metres per unit of each
    kind of arrow ("omega": m per rad/s, "L": m per kg m²/s, "force": m per N).
    """

    def __init__(self, commands, *, duration=0.0, t0=0.0, speed=1.0, title="rbcourse", legend=(),
                 arrow_scales=None, frame_times=None):
        self.commands = list(commands)
        self.duration = float(duration)
        self.t0 = float(t0)
        self.speed = float(speed)
        self.title = str(title)
        self.legend = list(legend)
        self.arrow_scales = dict(arrow_scales or {})
        self.frame_times = None if frame_times is None else np.asarray(frame_times, dtype=float)

    def __repr__(self) -> str:
        kind = f"an animation of {self.duration:g} s" if self.duration else "a still"
        return f"<Drawing {self.title!r}: {kind}, {len(self.commands)} meshcat commands>"

    @property
    def animation(self) -> dict | None:
        """The set_animation command, or None for a still."""
        return next((c for c in self.commands if c["type"] == "set_animation"), None)

    def packed(self) -> list[bytes]:
        """Each command as the msgpack bytes meshcat's viewer decodes."""
        return [umsgpack.packb(c) for c in self.commands]

    def html(self, *, title: str | None = None) -> str:
        """A standalone page: meshcat's viewer script and the commands inlined.

        It works from a file, offline, and loads no external resource: the script is
        embedded, and the commands are base64 strings decoded synchronously in order
        (meshcat's own static_html goes through fetch() of data: URLs, unordered).
        """
        if title is not None and not isinstance(title, str):
            raise ValueError(f"title must be a string or None, got {title!r}")
        title = self.title if title is None else title
        blobs = ",\n".join(f'"{base64.b64encode(b).decode("ascii")}"' for b in self.packed())
        legend = "".join(f'<div><span class="sw" style="background:#{c:06x}"></span>{_html.escape(t)}</div>'
                         for c, t in self.legend)
        return _PAGE.format(title=_html.escape(title), script=_viewer_script(), commands=blobs, legend=legend,
                            t0=repr(self.t0), speed=repr(self.speed), animated="true" if self.duration else "false")

    def save(self, path) -> Path:
        """Write the standalone page (html()) to path; returns the path."""
        if not isinstance(path, (str, os.PathLike)):
            raise ValueError(f"path must be a file path, got {path!r}")
        path = Path(path)
        path.write_text(self.html(), encoding="utf-8")
        return path

    def _repr_html_(self) -> str:
        """JupyterLab / Jupyter: the recorded drawing inline (an iframe holding the page; no server)."""
        return _iframe(srcdoc=self.html(), height=420)

    def show(self, server: "LiveServer | None" = None) -> "LiveView":
        """Send to the live viewer (this process's server unless one is given); returns a LiveView."""
        if server is None:
            server = live_server()
        elif not isinstance(server, LiveServer):
            raise ValueError(f"server must be a LiveServer or None, got {server!r}")
        server.draw(self)
        return LiveView(server.url)


class LiveView:
    """The live viewer's address; in JupyterLab it shows as an iframe on it (the kernel's machine)."""

    def __init__(self, url: str, height: int = 420):
        self.url = url
        self.height = height

    def __repr__(self) -> str:
        return f"<LiveView: open {self.url} in a browser>"

    def _repr_html_(self) -> str:
        return _iframe(src=self.url, height=self.height)


def _iframe(*, height: int, src: str | None = None, srcdoc: str | None = None) -> str:
    attr = f'src="{_html.escape(src)}"' if src is not None else f'srcdoc="{_html.escape(srcdoc)}"'
    return (f'<div style="height:{height}px;width:100%;overflow:hidden;resize:both">'
            f'<iframe {attr} style="width:100%;height:100%;border:none"></iframe></div>')


def _viewer_script() -> str:
    """meshcat's bundled viewer (three.js included), as shipped with the meshcat package."""
    return _JS_PATH.read_text(encoding="utf-8")


_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>{title}</title>
<style>
  body {{ margin: 0; }}
  #meshcat-pane {{ width: 100vw; height: 100vh; overflow: hidden; }}
  #rb-info {{ position: absolute; left: 8px; top: 8px; padding: 6px 9px; font: 13px/1.45 sans-serif;
             color: #fff; background: rgba(0, 0, 0, 0.45); border-radius: 4px; pointer-events: none; }}
  #rb-info .sw {{ display: inline-block; width: 10px; height: 10px; margin-right: 6px; border-radius: 2px; }}
</style>
</head>
<body>
<div id="meshcat-pane"></div>
<div id="rb-info"><div><b>{title}</b></div><div id="rb-time"></div>{legend}</div>
<script>
{script}
</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
(function (commands) {{
  for (const c of commands) {{
    viewer.handle_command_bytearray(Uint8Array.from(atob(c), ch => ch.charCodeAt(0)));
  }}
}})([
{commands}
]);
(function (t0, speed, animated) {{
  var el = document.getElementById("rb-time");
  function tick() {{
    var tau = viewer.animator.actions.reduce((acc, a) => Math.max(acc, a.time), 0);
    var t = t0 + speed * (animated ? tau : 0);
    el.textContent = "t = " + t.toFixed(2) + " s" + (speed != 1 ? "  (played at \\u00d7" + speed + ")" : "");
    requestAnimationFrame(tick);
  }}
  tick();
}})({t0}, {speed}, {animated});
</script>
</body>
</html>
"""


# =====================================================================================
# What to draw: frames of the bodies, arrows, and the builder of commands
# =====================================================================================

class _Frames:
    """States at the drawn instants, over N bodies: x (F, N, 3), R (F, N, 3, 3), ω, L (F, N, 3)."""

    def __init__(self, t, x, R, L, scene):
        self.t = np.asarray(t, dtype=float)
        self.x, self.R, self.L = x, R, L
        self.Rp = project_so3(R)
        self.omega = angular_velocity(inverse_inertia(R, scene.I_body_inv), L)
        self.scene = scene

    @classmethod
    def from_trajectory(cls, traj: Trajectory, index: np.ndarray) -> "_Frames":
        x, R, L = traj.x[index], traj.R[index], traj.L[index]
        if x.ndim == 2:                                  # one body: add the body axis
            x, R, L = x[:, None], R[:, None], L[:, None]
        return cls(traj.t[index], x, R, L, traj.scene)


DRAWABLE = {"x": 1e6, "R": 1e15, "L": 1e30}   # beyond these (m, entries of R, kg m²/s) a run is not drawn on (float32 in three.js)


def _drawable(traj: Trajectory) -> tuple[Trajectory, str]:
    """The part of a run that can be drawn, and a note if it was cut ('' if not).

    A run that blew up (the slides' Euler) keeps finite states up to 1e100, but a body 10⁸⁰ m away,
    or an R with entries of 10³⁰, cannot be framed or drawn (three.js computes NaN bounds): the
    drawing ends where the run stops being drawable, and says so.  A run that ended early
    (traj.diverged) says when it diverged."""
    m = len(traj.t)
    ok = np.ones(m, dtype=bool)
    for key, limit in DRAWABLE.items():
        ok &= (np.abs(getattr(traj, key)).reshape(m, -1) < limit).all(axis=1)
    k = m if ok.all() else int(np.argmin(ok))
    note = traj.outcome if traj.diverged else ""
    if k < m:
        note = note or f"not drawable after t = {traj.t[max(k - 1, 0)]:.4g} s"
        traj = traj.head(max(k, 1))
    return traj, note


def _check_trajectory(name: str, traj) -> Trajectory:
    if not isinstance(traj, Trajectory):
        raise ValueError(f"{name} must be a Trajectory (from rbcourse.simulate), got {traj!r}")
    n = traj.scene.n_bodies
    single = (len(traj.t),) + ((3,) if n == 1 else (n, 3))
    if len(traj.t) < 1 or traj.x.shape != single or traj.R.shape != single + (3,) or traj.L.shape != single:
        raise ValueError(f"{name} must hold states of its scene's {n} bod{'y' if n == 1 else 'ies'} "
                         f"(x of shape {single}), got x of shape {traj.x.shape}")
    for key in ("t", "x", "R", "L"):
        if not np.all(np.isfinite(getattr(traj, key))):
            raise ValueError(f"{name} must hold finite states only, but {name}.{key} has NaN or inf "
                             "(a diverged run: draw the steps before the blow-up)")
    if np.any(np.diff(traj.t) <= 0):
        raise ValueError(f"{name}.t must increase strictly")
    return traj


def _frame_indices(t: np.ndarray, speed: float, fps: float, max_frames: int) -> np.ndarray:
    """Indices of the recorded states nearest to the frames t0 + speed·j/fps (the last state always kept)."""
    span = t[-1] - t[0]
    n = int(np.floor(span / speed * fps + 1e-9)) + 1
    if n > max_frames:
        raise ValueError(f"fps must give at most max_frames = {max_frames} frames: {span:g} s played at "
                         f"×{speed:g} and {fps:g} fps is {n} frames (lower fps or raise speed or max_frames)")
    wanted = t[0] + speed * np.arange(n) / fps
    k = np.clip(np.searchsorted(t, wanted), 1, max(len(t) - 1, 1))
    if len(t) > 1:
        k = np.where(wanted - t[k - 1] <= t[k] - wanted, k - 1, k)
    else:
        k = np.zeros(n, dtype=int)
    return np.unique(np.append(k, len(t) - 1))


def _y_to(u: np.ndarray) -> np.ndarray:
    """Unit quaternions (x, y, z, w) turning +y onto the unit vectors u (F, 3), sign-continuous."""
    y = np.array([0.0, 1.0, 0.0])
    q = np.concatenate([np.cross(y, u), 1.0 + u @ y[:, None]], axis=-1)
    flip = q[:, 3] < 1e-9                                 # u = −y: half turn about x
    q[flip] = [1.0, 0.0, 0.0, 0.0]
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    return _continuous(q)


def _continuous(q: np.ndarray) -> np.ndarray:
    """Flip signs so that consecutive quaternions have a non-negative dot product (no long-way slerp)."""
    q = q.copy()
    for j in range(1, len(q)):
        if q[j] @ q[j - 1] < 0:
            q[j] = -q[j]
    return q


def _xyzw(R: np.ndarray) -> np.ndarray:
    """Quaternions (x, y, z, w) as three.js orders them, of rotations R (F, 3, 3)."""
    q = quat_from_matrix(R)
    return _continuous(np.concatenate([q[:, 1:], q[:, :1]], axis=-1))


def _matrix(position, quaternion=None, scale=None) -> np.ndarray:
    """4×4 transform from a position, a quaternion (x, y, z, w) and a scale."""
    T = np.eye(4)
    if quaternion is not None:
        x, y, z, w = quaternion
        T[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
    if scale is not None:
        T[:3, :3] = T[:3, :3] * np.asarray(scale)[None, :]
    T[:3, 3] = position
    return T


class _Builder:
    """Collects objects (static) and per-frame node values (position, quaternion, scale) by path."""

    def __init__(self, frame_times: np.ndarray):
        self.tau = frame_times                 # playback times of the frames (s)
        self.objects: list[dict] = []          # set_object / static set_transform / set_property
        self.tracks: dict[str, dict[str, np.ndarray]] = {}

    def object(self, path: str, geometry, material, transform=None):
        p = MeshcatPath(tuple(path.strip("/").split("/")))
        self.objects.append(SetObject(geometry, material, p).lower())
        if transform is not None:
            self.static(path, transform)

    def raw_object(self, path: str, obj):
        self.objects.append(SetObject(obj, path=MeshcatPath(tuple(path.strip("/").split("/")))).lower())

    def static(self, path: str, transform: np.ndarray):
        self.objects.append(SetTransform(transform, MeshcatPath(tuple(path.strip("/").split("/")))).lower())

    def prop(self, path: str, key: str, value):
        self.objects.append(SetProperty(key, value, MeshcatPath(tuple(path.strip("/").split("/")))).lower())

    def move(self, path: str, **values):
        """Per-frame values of a node: position (F, 3), quaternion (F, 4, x y z w), scale (F, 3)."""
        self.tracks.setdefault(path, {}).update({k: np.asarray(v, dtype=float) for k, v in values.items()})

    def commands(self, fps: float, loop: bool) -> list[dict]:
        """set_object..., the first frame as set_transform, then the animation (if more than one frame)."""
        cmds = list(self.objects)
        for path, vals in self.tracks.items():
            first = {k: v[0] for k, v in vals.items()}
            T = _matrix(first.get("position", np.zeros(3)), first.get("quaternion"), first.get("scale"))
            cmds.append(SetTransform(T, MeshcatPath(tuple(path.strip("/").split("/")))).lower())
        if len(self.tau) > 1:
            anim = Animation(default_framerate=fps)
            frames = [float(f) for f in self.tau * fps]
            jstype = {"position": "vector3", "quaternion": "quaternion", "scale": "vector3"}
            for path, vals in self.tracks.items():
                clip = AnimationClip(fps=fps)
                for key, v in vals.items():
                    clip.tracks[key] = AnimationTrack(key, jstype[key], list(frames), v.tolist())
                anim.clips[MeshcatPath(tuple(path.strip("/").split("/")))] = clip
            cmd = SetAnimation(anim, play=True, repetitions=1).lower()
            if loop:
                cmd["options"]["repetitions"] = float("inf")      # THREE.LoopRepeat, forever
            cmds.append(cmd)
        return cmds


def _body_shape(body):
    """The meshcat geometry of a body, and the transform from body axes to the geometry's own axes."""
    if body.shape == "box" and body.size:
        return g.Box([float(s) for s in body.size]), np.eye(4)
    if body.shape == "cylinder" and body.size:
        r, h = body.size
        turn = np.eye(4)
        turn[:3, :3] = [[1, 0, 0], [0, 0, -1], [0, 1, 0]]     # three.js cylinders lie along y: y → z
        return g.Cylinder(max(float(h), 1e-3 * r), radius=float(r)), turn
    if body.shape == "sphere" and body.size:
        return g.Sphere(float(body.size[0])), np.eye(4)
    radii = body.half_extents()
    radii = np.maximum(radii, 1e-3 * radii.max())
    turn = np.eye(4)
    turn[:3, :3] = body.principal_axes                         # the ellipsoid lies along the principal axes
    return g.Ellipsoid([float(r) for r in radii]), turn


def _body_radius(body) -> float:
    return float(np.linalg.norm(body.half_extents()))


def _material(color: int, opacity: float = 1.0):
    return g.MeshPhongMaterial(color=color, opacity=opacity, transparent=opacity < 1.0)


class _Arrow:
    """An arrow drawn from tail (F, 3) along vec (F, 3), physics units times scale (m per unit)."""

    def __init__(self, name, kind, tail, vec):
        self.name, self.kind, self.tail, self.vec = name, kind, tail, vec


def _arrow_scales(arrows, arrow_length: float, given: dict) -> dict:
    """Metres per unit for each kind: as given, else its largest value over the run becomes arrow_length long."""
    largest = {}
    for a in arrows:
        m = float(np.linalg.norm(a.vec, axis=-1).max(initial=0.0))
        largest[a.kind] = max(largest.get(a.kind, 0.0), m)
    return {k: given.get(k, arrow_length / m if m > 0 else 1.0) for k, m in largest.items()}


def _arrow_scales_arg(arrow_scales) -> dict:
    if arrow_scales is None:
        return {}
    if not isinstance(arrow_scales, dict) or not set(arrow_scales) <= {"omega", "L", "force"}:
        raise ValueError(f"arrow_scales must be None or a dict with keys among 'omega', 'L', 'force' "
                         f"(metres per unit), got {arrow_scales!r}")
    return {k: checks.positive(f"arrow_scales[{k!r}]", v) for k, v in arrow_scales.items()}


def _add_arrow(b: _Builder, path: str, tail, vec, scale: float, color: int, thickness: float):
    """Shaft + head, one node moved per frame: length |vec|·scale from tail, along vec."""
    r = thickness
    head_len, head_r = 6.0 * r, 2.4 * r
    norm = np.linalg.norm(vec, axis=-1)
    length = norm * scale
    u = np.where(norm[:, None] > 0, vec / np.where(norm > 0, norm, 1.0)[:, None], np.nan)
    # keep the last direction through zero-length frames (hidden anyway)
    u = _fill_directions(u)
    s = np.where(length > 0, np.minimum(1.0, length / head_len), _TINY)     # short arrows shrink whole
    local = np.where(length > 0, length / s, head_len)
    shaft = np.maximum(local - head_len, _TINY)
    ones, zeros = np.ones_like(s), np.zeros_like(s)
    b.move(path, position=tail, quaternion=_y_to(u), scale=np.stack([s, s, s], -1))
    b.move(path + "/shaft", scale=np.stack([ones, shaft, ones], -1))
    b.move(path + "/head", position=np.stack([zeros, local - head_len, zeros], -1))
    mat = _material(color)
    b.object(path + "/shaft/mesh", g.Cylinder(1.0, radius=r), mat, _matrix([0.0, 0.5, 0.0]))
    b.object(path + "/head/mesh", g.Cylinder(head_len, radiusTop=0.0, radiusBottom=head_r), mat,
             _matrix([0.0, head_len / 2, 0.0]))


def _fill_directions(u: np.ndarray) -> np.ndarray:
    u = u.copy()
    last = np.array([0.0, 0.0, 1.0])
    for j in range(len(u)):
        if np.isnan(u[j, 0]):
            u[j] = last
        else:
            last = u[j]
    return u


def _arrows(fr: _Frames, omega: bool, L: bool, forces: bool) -> list[_Arrow]:
    """ω and L from each centre of mass, and each PointForce's force from its point."""
    out = []
    n = fr.scene.n_bodies
    for i in range(n):
        if omega:
            out.append(_Arrow(f"omega_{i}", "omega", fr.x[:, i], fr.omega[:, i]))
        if L:
            out.append(_Arrow(f"L_{i}", "L", fr.x[:, i], fr.L[:, i]))
    if forces:
        for e_index, e in enumerate(fr.scene.effects):
            if not isinstance(e, PointForce):
                continue
            for j in fr.scene.bodies_of(e):
                f = np.array([e.force_at(float(t)) for t in fr.t], dtype=float)
                F = matvec(fr.R[:, j], f) if e.frame == "body" else f            # F = R f in body axes
                r = fr.x[:, j] + matvec(fr.Rp[:, j], e.body_point)               # r = x + R b
                out.append(_Arrow(f"force_{e_index}_{j}", "force", r, F))
    return out


def _nice(value: float) -> float:
    """The number among 1, 2, 5 × 10^k nearest to value (in ratio)."""
    k = np.floor(np.log10(value))
    candidates = np.array([1.0, 2.0, 5.0, 10.0]) * 10.0 ** k
    return float(candidates[np.abs(np.log(candidates / value)).argmin()])


def _grid(b: _Builder, lo: np.ndarray, hi: np.ndarray, size: float, height: float):
    """A square grid at z = height under the motion, of short segments.

    meshcat's own grid (/Grid, hidden here) is made of 20 m lines; software WebGL (SwiftShader,
    what Chromium uses without a GPU) drops a line that passes behind the camera, so from
    close up that grid vanishes.  Segments one cell long keep the grid visible.
    """
    half_xy = float(np.linalg.norm(hi[:2] - lo[:2])) / 2
    step = max(_nice(1.6 * size), _nice(max(half_xy, 1e-9) / 12))
    centre = np.round((lo[:2] + hi[:2]) / 2 / step) * step
    n = int(np.clip(np.ceil((half_xy + 3 * step) / step), 5, 20))
    ticks = np.arange(-n, n + 1) * step
    a, c = np.meshgrid(ticks, ticks[:-1], indexing="ij")          # a: the line, c: where its segment starts
    seg_x = np.stack([np.stack([a, c, 0 * a], -1), np.stack([a, c + step, 0 * a], -1)], -2).reshape(-1, 2, 3)
    seg_y = seg_x[..., [1, 0, 2]]
    pts = np.concatenate([seg_x, seg_y]).reshape(-1, 3) + [centre[0], centre[1], height]
    b.raw_object("/meshcat/grid", g.LineSegments(g.PointsGeometry(pts.T.astype(np.float32)),
                                                 g.LineBasicMaterial(color=COLORS["grid"])))


def _extra_effects(b: _Builder, scene, size: float, lo: np.ndarray, hi: np.ndarray) -> float:
    """A Ground effect's plane (at its height), a Pivot's point.  Returns the ground's height (0 without one)."""
    ground = 0.0
    for k, e in enumerate(scene.effects):
        if isinstance(e, Ground):
            ground = e.height
            width = float(2.0 * (np.linalg.norm(hi[:2] - lo[:2]) / 2 + max(2.0, 4 * size)))
            thick = 0.02 * size
            centre = (lo + hi) / 2
            b.object(f"/meshcat/ground_{k}", g.Box([width, width, thick]), _material(COLORS["ground"], 0.85),
                     _matrix([centre[0], centre[1], ground - thick / 2 - 1e-3 * size]))
        elif isinstance(e, Pivot):
            b.object(f"/meshcat/pivot_{k}", g.Sphere(0.06 * size), _material(COLORS["pivot"]),
                     _matrix(e.world_point))
    return ground


def _camera(b: _Builder, target, distance: float, follow_path: np.ndarray | None):
    """Look at target (or at the points follow_path (F, 3), frame by frame) from `distance`.

    meshcat's orbit controls always look at the world origin, whatever the camera group's
    transform, so the target is brought there instead: the drawing (/meshcat, our grid included)
    and meshcat's axes are shifted by −target (or by −x(t) of the followed body, per frame).
    """
    d = distance * _VIEW_DIRECTION / np.linalg.norm(_VIEW_DIRECTION)
    # the camera lives in meshcat's y-up "rotated" frame: world (x, y, z) is (x, z, −y) there
    b.prop("/Cameras/default/rotated/<object>", "position", [float(d[0]), float(d[2]), float(-d[1])])
    for path in ("/meshcat", "/Axes"):
        if follow_path is None:
            b.static(path, _matrix(-np.asarray(target)))
        else:
            b.move(path, position=-follow_path)


def _build(fr: _Frames, tau: np.ndarray, *, omega, L, forces, axes, grid, arrow_length, arrow_scales, trail_points,
           ghost: _Frames | None, ghost_offset, follow, camera_distance, title, legend_extra, fps, loop,
           t0, speed):
    """The commands for frames fr (and a ghost) at playback times tau."""
    scene = fr.scene
    b = _Builder(tau)
    size = max(2 * float(body.half_extents().max()) for body in scene.bodies)
    arrow_length = 1.2 * size if arrow_length is None else arrow_length
    for i, body in enumerate(scene.bodies):
        geom, turn = _body_shape(body)
        color = COLORS["body"] if scene.n_bodies == 1 else _BODY_PALETTE[i % len(_BODY_PALETTE)]
        b.object(f"/meshcat/bodies/{i}/shape", geom, _material(color), turn)
        b.move(f"/meshcat/bodies/{i}", position=fr.x[:, i], quaternion=_xyzw(fr.Rp[:, i]))
        if axes:
            b.raw_object(f"/meshcat/bodies/{i}/axes", g.triad(0.75 * 2 * float(body.half_extents().max())))
    if ghost is not None:
        for i, body in enumerate(ghost.scene.bodies):
            geom, turn = _body_shape(body)
            b.object(f"/meshcat/ghost/{i}/shape", geom, _material(COLORS["ghost"], 0.4), turn)
            shown = np.where(ghost.shown, 1.0, _TINY)[:, None] * np.ones(3)      # hidden after its end
            b.move(f"/meshcat/ghost/{i}", position=ghost.x[:, i] + ghost_offset, quaternion=_xyzw(ghost.Rp[:, i]),
                   scale=shown)
    arrows = _arrows(fr, omega, L, forces)
    scales = _arrow_scales(arrows, arrow_length, arrow_scales)
    for a in arrows:
        _add_arrow(b, f"/meshcat/arrows/{a.name}", a.tail, a.vec, scales[a.kind], COLORS[a.kind], 0.02 * size)
    if trail_points is not None:
        pts = np.asarray(trail_points, dtype=np.float32)
        b.raw_object("/meshcat/trail", g.Line(g.PointsGeometry(pts.T.copy()),
                                              g.LineBasicMaterial(color=COLORS["trail"])))
    # framing: what must be in view
    centres = fr.x.reshape(-1, 3)
    if ghost is not None:
        centres = np.concatenate([centres, (ghost.x + ghost_offset).reshape(-1, 3)])
    reach = max(_body_radius(body) for body in scene.bodies) + (0.6 * arrow_length if arrows else 0.0)
    lo, hi = centres.min(0), centres.max(0)
    if follow is None:
        target = (lo + hi) / 2
        radius = reach + np.linalg.norm(hi - lo) / 2
        follow_path = None
    else:                                   # the followed body, and its ghost when it is beside
        shift = ghost_offset / 2 if ghost is not None else np.zeros(3)
        follow_path = fr.x[:, follow] + shift
        target = follow_path[0]
        radius = reach + np.linalg.norm(shift)
    distance = radius / np.sin(np.radians(_FOV / 2)) if camera_distance is None else camera_distance
    _camera(b, target, distance, follow_path)
    ground = _extra_effects(b, scene, size, lo, hi)
    b.prop("/Grid", "visible", False)                              # ours instead (or none)
    if grid:
        _grid(b, lo, hi, size, ground)
    legend = [(COLORS["omega"], f"ω: {scales['omega']:.3g} m per rad/s")] if "omega" in scales else []
    if "L" in scales:
        legend.append((COLORS["L"], f"L: {scales['L']:.3g} m per kg m²/s"))
    if "force" in scales:
        legend.append((COLORS["force"], f"forces at their points: {scales['force']:.3g} m per N"))
    legend += legend_extra
    return Drawing(b.commands(fps, loop), duration=float(tau[-1]), t0=t0, speed=speed, title=title,
                   legend=legend, arrow_scales=scales, frame_times=fr.t)


# =====================================================================================
# Public: a still, an animation
# =====================================================================================

def _flag(name: str, value) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def _optional_positive(name: str, value):
    return None if value is None else checks.positive(name, value)


def _follow_arg(follow, n_bodies: int):
    if follow == "auto":
        return 0 if n_bodies == 1 else None
    if follow is None or follow is False:
        return None
    if isinstance(follow, (bool, np.bool_)) or not isinstance(follow, (int, np.integer)) or not 0 <= follow < n_bodies:
        raise ValueError(f"follow must be 'auto', None or a body index in [0, {n_bodies - 1}], got {follow!r}")
    return int(follow)


def _options(omega, L, forces, axes, grid, arrow_length, arrow_scales, camera_distance, title) -> dict:
    """The options draw_state and draw_trajectory share, checked."""
    if title is not None and not isinstance(title, str):
        raise ValueError(f"title must be a string or None, got {title!r}")
    return {"omega": _flag("omega", omega), "L": _flag("L", L), "forces": _flag("forces", forces),
            "axes": _flag("axes", axes), "grid": _flag("grid", grid),
            "arrow_length": _optional_positive("arrow_length", arrow_length),
            "arrow_scales": _arrow_scales_arg(arrow_scales),
            "camera_distance": _optional_positive("camera_distance", camera_distance)}


def draw_state(scene, X: State, *, t: float = 0.0, omega: bool = True, L: bool = True, forces: bool = True,
               axes: bool = True, grid: bool = True, arrow_length: float | None = None,
               arrow_scales: dict | None = None,
               follow="auto", camera_distance: float | None = None, title: str | None = None) -> Drawing:
    """A still: the scene's bodies at state X (forces evaluated at time t).

    scene: a Scene or a RigidBody; X: a State of its bodies.  See draw_trajectory for the rest.
    """
    scene = as_scene(scene)
    if not isinstance(X, State):
        raise ValueError(f"X must be a State, got {X!r}")
    if X.n_bodies != scene.n_bodies:
        raise ValueError(f"X must hold the scene's {scene.n_bodies} bodies, got {X.n_bodies}")
    t = checks.real("t", t)
    opts = _options(omega, L, forces, axes, grid, arrow_length, arrow_scales, camera_distance, title)
    follow = _follow_arg(follow, scene.n_bodies)
    n = scene.n_bodies
    fr = _Frames([t], X.x.reshape(1, n, 3), X.R.reshape(1, n, 3, 3), X.L.reshape(1, n, 3), scene)
    return _build(fr, np.zeros(1), **opts, trail_points=None, ghost=None, ghost_offset=np.zeros(3), follow=follow,
                  title=title or (scene.name or "rbcourse"), legend_extra=[], fps=30.0, loop=False, t0=t, speed=1.0)


def draw_trajectory(traj: Trajectory, *, speed: float = 1.0, fps: float = 30.0, omega: bool = True, L: bool = True,
                    forces: bool = True, axes: bool = True, grid: bool = True, arrow_length: float | None = None,
                    arrow_scales: dict | None = None, trail=None,
                    trail_body: int = 0, ghost: Trajectory | None = None, ghost_offset=(0.0, 0.0, 0.0),
                    ghost_label: str = "reference", follow="auto", camera_distance: float | None = None,
                    loop: bool = True, max_frames: int = 20000, title: str | None = None) -> Drawing:
    """A meshcat animation of a Trajectory, in real time (speed = 1) or speed times faster.

    The run is resampled to `fps` frames per second of playback (the recorded state nearest
    each frame; three.js interpolates between them), so a long run stays small.
    omega, L, forces, axes, grid: draw ω, L, the PointForce forces, the body axes, a floor grid
    (at z = 0, or at the height of a Ground effect, which is also drawn).
    arrow_length: metres of the longest arrow of each kind (default 1.2 × the largest body size);
    arrow_scales: fixed metres per unit instead, e.g. {"omega": 0.02} (m per rad/s), {"force": 0.05} (m per N).
    trail: a body point b (body axes) whose world path x + R b is drawn, of body trail_body.
    ghost: a reference trajectory (the exact motion, another method) drawn semi-transparent,
    shifted by ghost_offset (zero: over the bodies); ghost_label names it in the legend.
    follow: the camera follows a body's centre (an index), or frames the whole motion (None);
    "auto": follow the body of a one-body scene.  camera_distance overrides the framing.
    loop: play over and over (else once).  max_frames bounds the page's size.
    Every R is projected onto SO(3) before it is sent (Euler's R drifts off it).
    """
    traj, traj_note = _drawable(_check_trajectory("traj", traj))
    speed = checks.positive("speed", speed)
    fps = checks.real("fps", fps, low=1.0, high=240.0)
    max_frames = checks.integer("max_frames", max_frames, low=1)
    if not np.isfinite(float(traj.t[-1] - traj.t[0]) / speed * fps):     # speed = 1e-320: inf frames
        raise ValueError(f"speed must give at most max_frames = {max_frames} frames: {traj.t[-1] - traj.t[0]:g} s "
                         f"played at ×{speed:g} is more frames than a float can count (raise speed)")
    opts = _options(omega, L, forces, axes, grid, arrow_length, arrow_scales, camera_distance, title)
    loop = _flag("loop", loop)
    n = traj.scene.n_bodies
    follow = _follow_arg(follow, n)
    trail_body = checks.integer("trail_body", trail_body, low=0, high=n - 1)
    trail = None if trail is None else checks.vector3("trail", trail)
    ghost_offset = checks.vector3("ghost_offset", ghost_offset)
    if not isinstance(ghost_label, str):
        raise ValueError(f"ghost_label must be a string, got {ghost_label!r}")
    index = _frame_indices(traj.t, speed, fps, max_frames)
    fr = _Frames.from_trajectory(traj, index)
    tau = (fr.t - traj.t[0]) / speed
    ghost_fr, extra = None, []
    if ghost is not None:
        ghost, ghost_note = _drawable(_check_trajectory("ghost", ghost))
        if ghost_note and "diverged" not in ghost_label:
            ghost_label = f"{ghost_label} ({ghost_note})" if ghost_label else ghost_note
        if ghost.scene.n_bodies != n:
            raise ValueError(f"ghost must have the same number of bodies as traj ({n}), got {ghost.scene.n_bodies}")
        k = np.clip(np.searchsorted(ghost.t, fr.t), 0, len(ghost.t) - 1)
        prev = np.clip(k - 1, 0, None)
        k = np.where(np.abs(ghost.t[prev] - fr.t) <= np.abs(ghost.t[k] - fr.t), prev, k)
        ghost_fr = _Frames.from_trajectory(ghost, k)
        ghost_fr.shown = fr.t <= ghost.t[-1] + 0.5 * speed / fps
        extra.append((COLORS["ghost"], f"ghost: {ghost_label}"))
    trail_points = None
    if trail is not None:
        dense = np.unique(np.linspace(0, len(traj.t) - 1, min(len(traj.t), 4000)).round().astype(int))
        Rp = project_so3(traj.R[dense] if n == 1 else traj.R[dense, trail_body])
        xs = traj.x[dense] if n == 1 else traj.x[dense, trail_body]
        trail_points = xs + matvec(Rp, trail)
        extra.append((COLORS["trail"], f"trail of body point {np.round(trail, 4).tolist()}"))
    if title is None:
        name = traj.scene.name or "rbcourse"
        title = f"{name}: {traj.method or 'simulation'}" + (f", dt = {traj.dt:g} s" if traj.dt else "")
    if traj_note:
        title = f"{title} — {traj_note}"
    return _build(fr, tau, **opts, trail_points=trail_points, ghost=ghost_fr, ghost_offset=ghost_offset,
                  follow=follow, title=title, legend_extra=extra, fps=fps, loop=loop, t0=float(traj.t[0]), speed=speed)


# =====================================================================================
# The live viewer: one meshcat server per process, on 127.0.0.1 only
# =====================================================================================

# meshcat 0.3.2's zmqserver takes its host for the zmq socket and the URL, but its
# tornado file/websocket server calls app.listen(port) with no address: all interfaces.
# We start the same server with listen forced to 127.0.0.1, and make it quit when this
# process is gone (checked every second), so no server outlives its owner.
_SERVER_SCRIPT = r"""
import os, sys
import tornado.ioloop, tornado.web
_listen = tornado.web.Application.listen
def _loopback_listen(self, port, address=None, **kwargs):
    return _listen(self, port, "127.0.0.1", **kwargs)
tornado.web.Application.listen = _loopback_listen
import meshcat.servers.zmqserver as zmqserver
owner = int(sys.argv[1])
bridge = zmqserver.ZMQWebSocketBridge(host="127.0.0.1")
print("zmq_url=" + bridge.zmq_url, flush=True)
print("web_url=" + bridge.web_url, flush=True)
def _check_owner():
    if os.getppid() != owner:
        bridge.ioloop.stop()
tornado.ioloop.PeriodicCallback(_check_owner, 1000).start()
bridge.run()
"""


class LiveServer:
    """A meshcat server subprocess (tornado + zmq, 127.0.0.1 only) and our zmq socket to it.

    Use live_server() for the process's one server.  Nothing here waits for a browser:
    each command waits only for the server's "ok" (at most `timeout` seconds).
    """

    def __init__(self, *, timeout: float = 60.0):
        import zmq
        self.timeout = checks.positive("timeout", timeout)
        self._dir = tempfile.TemporaryDirectory(prefix="rbcourse-meshcat-")
        self._out = open(os.path.join(self._dir.name, "stdout.txt"), "w+b")
        self._err = open(os.path.join(self._dir.name, "stderr.txt"), "w+b")
        self.proc = subprocess.Popen([sys.executable, "-u", "-c", _SERVER_SCRIPT, str(os.getpid())],
                                     stdin=subprocess.DEVNULL, stdout=self._out, stderr=self._err,
                                     start_new_session=True)
        self.owner = os.getpid()
        self._socket = None
        try:
            self.zmq_url, self.url = self._read_urls()
            self._context = zmq.Context()
            self._socket = self._context.socket(zmq.REQ)
            ms = int(self.timeout * 1000)
            self._socket.setsockopt(zmq.RCVTIMEO, ms)
            self._socket.setsockopt(zmq.SNDTIMEO, ms)
            self._socket.setsockopt(zmq.LINGER, 0)
            self._socket.connect(self.zmq_url)
            self._request([b"url"])
        except BaseException:
            self.close()
            raise

    def __repr__(self) -> str:
        state = "running" if self.running else "stopped"
        return f"<LiveServer {state}, pid {self.proc.pid}, {self.url if hasattr(self, 'url') else '?'}>"

    @property
    def running(self) -> bool:
        return self.proc.poll() is None

    def _read_urls(self):
        deadline = time.monotonic() + self.timeout
        while time.monotonic() < deadline:
            self._out.seek(0)
            lines = self._out.read().decode("utf-8", "replace").splitlines()
            urls = dict(line.split("=", 1) for line in lines if line.startswith(("zmq_url=", "web_url=")))
            if len(urls) == 2:
                return urls["zmq_url"], urls["web_url"]
            if self.proc.poll() is not None:
                break
            time.sleep(0.05)
        self._err.seek(0)
        err = self._err.read().decode("utf-8", "replace")[-2000:]
        raise RuntimeError(f"the meshcat server did not start (exit code {self.proc.poll()}): {err}")

    def _request(self, frames: list[bytes]) -> bytes:
        import zmq
        if self._socket is None or not self.running:
            raise RuntimeError("the meshcat server is closed: use live_server() for a new one")
        try:
            self._socket.send_multipart(frames)
            return self._socket.recv()
        except zmq.Again:
            self.close()
            raise RuntimeError(f"the meshcat server did not answer within {self.timeout:g} s; it was closed") from None

    def send(self, command: dict):
        """Send one lowered meshcat command; waits only for the server's acknowledgement."""
        reply = self._request([command["type"].encode(), command.get("path", "").encode(), umsgpack.packb(command)])
        if reply != b"ok":
            raise RuntimeError(f"the meshcat server refused {command['type']}: {reply!r}")

    def draw(self, drawing: Drawing):
        """Replace what the viewer shows by a Drawing (the old drawing and animation are cleared)."""
        if not isinstance(drawing, Drawing):
            raise ValueError(f"drawing must be a Drawing, got {drawing!r}")
        self.send(Delete(MeshcatPath(("meshcat",))).lower())
        for cmd in drawing.commands:
            self.send(cmd)
        if drawing.animation is None:
            self.send(SetAnimation(Animation(), play=False).lower())     # clear a previous animation

    def visualizer(self):
        """A meshcat.Visualizer on this server, for meshcat's own API (it prints the URL)."""
        import meshcat
        return meshcat.Visualizer(zmq_url=self.zmq_url)

    def close(self):
        """Stop the server subprocess (meshcat 0.3.2's Visualizer.close() is broken) and our socket."""
        if self._socket is not None:
            self._socket.close(linger=0)
            self._context.term()
            self._socket = None
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        for f in (self._out, self._err):
            f.close()
        self._dir.cleanup()


_live = {"server": None, "atexit": False}      # this process's one server (not a switch: a registry)


def live_server(*, timeout: float = 60.0) -> LiveServer:
    """This process's meshcat server, started on first use and reused; stopped at exit."""
    server = _live["server"]
    if server is not None and server.owner == os.getpid() and server.running:
        return server
    if server is not None and server.owner == os.getpid():
        server.close()
    _live["server"] = LiveServer(timeout=timeout)
    if not _live["atexit"]:
        atexit.register(close_live_server)
        _live["atexit"] = True
    return _live["server"]


def close_live_server() -> bool:
    """Stop this process's server if there is one; True if one was stopped."""
    server = _live["server"]
    _live["server"] = None
    if server is None or server.owner != os.getpid():
        return False
    server.close()
    return True


def live_server_pids() -> list[int]:
    """Process ids of the meshcat servers this process has running (0 or 1 of them)."""
    server = _live["server"]
    if server is None or server.owner != os.getpid() or not server.running:
        return []
    return [server.proc.pid]
