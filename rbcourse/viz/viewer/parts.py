"""The pieces of the meshcat scene: each body's true shape and its material, arrows (a shaft and a
head, one node moved per frame; each kind of arrow scaled so that its largest value is arrow_length
long), the floor grid, a Ground's plane and a Pivot's point, and the camera."""
from __future__ import annotations

import meshcat.geometry as g
import numpy as np

from ... import Ground, Pivot, Spring
from ...rotation import matvec
from .commands import Builder, quat_y_to, transform


COLORS = {
    "body": 0xF28E2B, "ghost": 0x17BECF, "omega": 0xE040E0, "L": 0xFFD92F, "force": 0xE41A1C,
    "trail": 0xFFFFFF, "ground": 0x8A9A7B, "pivot": 0x333333, "grid": 0xB0B0B0, "spring": 0x4E79A7,
}
BODY_PALETTE = (0xF28E2B, 0x59A14F, 0xB07AA1, 0x9C755F, 0xEDC948, 0xFF9DA7)
FOV = 75.0                                          # meshcat's default camera, vertical field of view (deg)
VIEW_DIRECTION = np.array([1.0, 0.65, 0.45])       # where the camera sits, seen from its target
HIDDEN = 1e-9                                       # scale of an arrow of zero length, of a ghost after its end


def body_shape(body):
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


def add_body_shapes(b: Builder, scene, *, axes: bool, ghost: bool, ghost_opacity: float = 0.4, ghost_scale: float = 1.0):
    """Each body's shape under the node /meshcat/bodies/i (its colour; its body axes if axes), and with ghost its
    ghost's under /meshcat/ghost/i (semi-transparent; ghost_scale > 1: a shell just around the body where they
    coincide, not a surface fighting the body's for the same pixels): the nodes are then moved (an animation, or the
    page's cursor)."""
    for i, body in enumerate(scene.bodies):
        geom, turn = body_shape(body)
        color = COLORS["body"] if scene.n_bodies == 1 else BODY_PALETTE[i % len(BODY_PALETTE)]
        b.object(f"/meshcat/bodies/{i}/shape", geom, material(color), turn)
        if axes:
            b.raw_object(f"/meshcat/bodies/{i}/axes", g.triad(0.75 * 2 * float(body.half_extents().max())))
        if ghost:
            b.object(f"/meshcat/ghost/{i}/shape", geom, material(COLORS["ghost"], ghost_opacity),
                     turn @ np.diag([ghost_scale, ghost_scale, ghost_scale, 1.0]))


def body_radius(body) -> float:
    """The radius of the sphere around the body's inertia box (|half extents|)."""
    return float(np.linalg.norm(body.half_extents()))


def material(color: int, opacity: float = 1.0):
    """A Phong material of that colour (transparent below opacity 1)."""
    return g.MeshPhongMaterial(color=color, opacity=opacity, transparent=opacity < 1.0)


BLOW_UP = 3.0             # in a run that blew up, an arrow over 3× its kind's median length is the blow-up's tail


def metres_per_unit(arrows, arrow_length: float, given: dict, blew_up: bool = False) -> dict:
    """Metres per unit for each kind: as given, else its largest value over the run becomes arrow_length long —
    in a run that blew up, the largest among the values at most BLOW_UP × the kind's median (nonzero) value:
    the blow-up's tail (the slides' Euler: ω 10⁶ times its start) does not shrink every sane arrow to nothing."""
    lengths = {}
    for a in arrows:
        lengths.setdefault(a.kind, []).append(np.linalg.norm(a.vec, axis=-1))
    out = {}
    for kind, ms in lengths.items():
        m = np.concatenate(ms)
        m = m[np.isfinite(m) & (m > 0)]
        sane = m[m <= BLOW_UP * np.median(m)] if m.size and blew_up else m
        out[kind] = given.get(kind, arrow_length / float(sane.max()) if sane.size else 1.0)
    return out


def capped(vec: np.ndarray, scale: float, cap: float) -> np.ndarray:
    """The vectors vec (F, 3) whose drawn length |vec|·scale is at most cap (m): longer ones cut to cap (a
    blow-up's tail, drawn as long as the frame allows, not off it)."""
    norm = np.linalg.norm(vec, axis=-1, keepdims=True) * scale
    return np.where(norm > cap, vec * (cap / np.where(norm > 0, norm, 1.0)), vec)


def spring_ends(scene, fr, e) -> tuple[np.ndarray, np.ndarray]:
    """A Spring's two ends over the frames (F, 3) each: the body point r = x + R b and the anchor (its world point,
    or the other body's point), body points with the projected R (on the drawn body)."""
    i = int(scene.bodies_of(e)[0])
    r = fr.x[:, i] + matvec(fr.Rp[:, i], e.body_point)
    j = scene.other_body_of(e)
    anchor = np.broadcast_to(e.world_point, r.shape) if j is None else fr.x[:, j] + matvec(fr.Rp[:, j], e.other_point)
    return r, np.array(anchor, dtype=float)


COIL_TURNS = 12


def add_springs(b: Builder, scene, fr, size: float):
    """Each Spring as a coil between its two ends, following the motion: a unit helix along y (COIL_TURNS turns,
    radius 0.08 × the body size) moved per frame to the anchor, turned to the body point and stretched to the
    distance between them."""
    for k, e in enumerate(scene.effects):
        if not isinstance(e, Spring):
            continue
        r, anchor = spring_ends(scene, fr, e)
        d = r - anchor
        length = np.linalg.norm(d, axis=-1)
        u = np.where(length[:, None] > 0, d / np.where(length > 0, length, 1.0)[:, None], [0.0, 0.0, -1.0])
        path = f"/meshcat/springs/{k}"
        b.move(path, position=anchor, quaternion=quat_y_to(u),
               scale=np.stack([np.ones_like(length), np.maximum(length, HIDDEN), np.ones_like(length)], -1))
        add_spring_shape(b, scene, k, e, path, size, anchor[0])


def add_spring_shape(b: Builder, scene, k: int, e, path: str, size: float, anchor):
    """A Spring's coil under the node path (a unit helix along y, COIL_TURNS turns, radius 0.08 × the body size:
    the node is moved to the anchor, turned to the body point and stretched to the distance), and its fixed anchor
    (a world point) as a pivot's point."""
    s = np.linspace(0.0, 1.0, 24 * COIL_TURNS + 1)
    radius = 0.08 * size
    coil = np.stack([radius * np.cos(2 * np.pi * COIL_TURNS * s), s, radius * np.sin(2 * np.pi * COIL_TURNS * s)])
    coil[0, [0, -1]] = coil[2, [0, -1]] = 0.0             # the ends on the axis: at the two points
    b.raw_object(path + "/coil", g.Line(g.PointsGeometry(coil.astype(np.float32)),
                                        g.LineBasicMaterial(color=COLORS["spring"], linewidth=2)))
    if scene.other_body_of(e) is None:
        b.object(f"/meshcat/spring_anchor_{k}", g.Sphere(0.04 * size), material(COLORS["pivot"]), transform(anchor))


def add_arrow(b: Builder, path: str, tail, vec, scale: float, color: int, thickness: float):
    """Shaft + head, one node moved per frame: length |vec|·scale from tail, along vec."""
    r = thickness
    head_len, head_r = 6.0 * r, 2.4 * r
    norm = np.linalg.norm(vec, axis=-1)
    length = norm * scale
    u = np.where(norm[:, None] > 0, vec / np.where(norm > 0, norm, 1.0)[:, None], np.nan)
    # keep the last direction through zero-length frames (hidden anyway)
    u = _fill_directions(u)
    s = np.where(length > 0, np.minimum(1.0, length / head_len), HIDDEN)     # short arrows shrink whole
    local = np.where(length > 0, length / s, head_len)
    shaft = np.maximum(local - head_len, HIDDEN)
    ones, zeros = np.ones_like(s), np.zeros_like(s)
    b.move(path, position=tail, quaternion=quat_y_to(u), scale=np.stack([s, s, s], -1))
    b.move(path + "/shaft", scale=np.stack([ones, shaft, ones], -1))
    b.move(path + "/head", position=np.stack([zeros, local - head_len, zeros], -1))
    mat = material(color)
    b.object(path + "/shaft/mesh", g.Cylinder(1.0, radius=r), mat, transform([0.0, 0.5, 0.0]))
    b.object(path + "/head/mesh", g.Cylinder(head_len, radiusTop=0.0, radiusBottom=head_r), mat,
             transform([0.0, head_len / 2, 0.0]))


def _fill_directions(u: np.ndarray) -> np.ndarray:
    """Each NaN direction (a zero-length arrow) replaced by the last real one (z at first)."""
    u = u.copy()
    last = np.array([0.0, 0.0, 1.0])
    for j in range(len(u)):
        if np.isnan(u[j, 0]):
            u[j] = last
        else:
            last = u[j]
    return u


def _nice(value: float) -> float:
    """The number among 1, 2, 5 × 10^k nearest to value (in ratio)."""
    k = np.floor(np.log10(value))
    candidates = np.array([1.0, 2.0, 5.0, 10.0]) * 10.0 ** k
    return float(candidates[np.abs(np.log(candidates / value)).argmin()])


def add_grid(b: Builder, lo: np.ndarray, hi: np.ndarray, size: float, height: float):
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


def add_effects(b: Builder, scene, size: float, lo: np.ndarray, hi: np.ndarray) -> float:
    """A Ground effect's plane (at its height), a Pivot's point.  Returns the ground's height (0 without one)."""
    ground = 0.0
    for k, e in enumerate(scene.effects):
        if isinstance(e, Ground):
            ground = e.height
            width = float(2.0 * (np.linalg.norm(hi[:2] - lo[:2]) / 2 + max(2.0, 4 * size)))
            thick = 0.02 * size
            centre = (lo + hi) / 2
            b.object(f"/meshcat/ground_{k}", g.Box([width, width, thick]), material(COLORS["ground"], 0.85),
                     transform([centre[0], centre[1], ground - thick / 2 - 1e-3 * size]))
        elif isinstance(e, Pivot):
            b.object(f"/meshcat/pivot_{k}", g.Sphere(0.06 * size), material(COLORS["pivot"]),
                     transform(e.world_point))
    return ground


def add_camera(b: Builder, target, distance: float, follow_path: np.ndarray | None):
    """Look at target (or at the points follow_path (F, 3), frame by frame) from `distance`.

    meshcat's orbit controls always look at the world origin, whatever the camera group's
    transform, so the target is brought there instead: the drawing (/meshcat, our grid included)
    and meshcat's axes are shifted by −target (or by −x(t) of the followed body, per frame).
    """
    d = distance * VIEW_DIRECTION / np.linalg.norm(VIEW_DIRECTION)
    # the camera lives in meshcat's y-up "rotated" frame: world (x, y, z) is (x, z, −y) there
    b.prop("/Cameras/default/rotated/<object>", "position", [float(d[0]), float(d[2]), float(-d[1])])
    for path in ("/meshcat", "/Axes"):
        if follow_path is None:
            b.static(path, transform(-np.asarray(target)))
        else:
            b.move(path, position=-follow_path)
