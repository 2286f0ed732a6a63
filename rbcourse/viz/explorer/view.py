"""The explorer's 3-D view, drawn by meshcat's three.js scene (the viewer's script, as in every page of
rbcourse.viz.viewer): the scene's objects as meshcat commands, made of the viewer's own pieces (viewer/parts.py):
each body's shape and axes, the reference's ghost, the floor grid, a Ground's plane, a Pivot's point and its stem,
each Spring's coil; and the camera.  There is no animation in it: the page's own time cursor (js/scene.js) sets
the nodes' transforms from the chosen run's frames — the bodies, the ghost, and the links (a spring's coil, a
pivot's stem) stretched between their two ends — and follows a body that moves far."""
from __future__ import annotations

import math

import meshcat.geometry as g
import numpy as np

from ...contact import Ground
from ...effects import Spring
from ...pivot import Pivot
from ..viewer import assets
from ..viewer.commands import Builder, pack
from ..viewer.parts import (COLORS, FOV, add_body_shapes, add_camera, add_effects, add_grid, add_spring_shape,
                            body_radius)

GHOST_OPACITY = 0.22     # fainter than a drawing's (0.4): over an accurate run the body keeps its own colour
GHOST_SCALE = 1.02       # and a shell just around it: over an accurate run, no surface fights the body's


def view_setup(scene, ghost, *, show_ghost: bool) -> dict:
    """The view's data for the page: {"commands", "size"} (the meshcat commands, compressed: viewer.assets), "follow"
    (the camera follows body 0 of the chosen run: one body that moves more than 3 body sizes), "links" (what the
    page stretches between two ends at each time).  ghost: the reference's Track (its path frames the view)."""
    size = max(2 * float(b.half_extents().max()) for b in scene.bodies)
    radius = max(body_radius(b) for b in scene.bodies)
    path = ghost.x.astype(float).reshape(len(ghost.t), -1, 3)
    follow = scene.single and float(np.linalg.norm(path[:, 0] - path[0, 0], axis=-1).max()) > 3 * size
    anchors = [np.asarray(e.world_point, dtype=float) for e in scene.effects
               if isinstance(e, (Pivot, Spring)) and getattr(e, "other_body", None) is None]
    pts = np.concatenate([path.reshape(-1, 3)] + ([np.array(anchors)] if anchors else []))
    lo, hi = pts.min(0), pts.max(0)
    grounds = [e.height for e in scene.effects if isinstance(e, Ground)]
    floor = float(grounds[0]) if grounds else float(lo[2] - 1.3 * radius)
    half_fov = math.radians(FOV / 2)
    if follow:
        target, distance = path[0, 0], 2.2 * radius / math.sin(half_fov)
    else:
        low = lo.copy()
        low[2] = min(low[2], floor)
        target = (low + hi) / 2
        distance = max(1.15 * (float(np.linalg.norm(hi - low)) / 2 + radius), 2.2 * radius) / math.sin(half_fov)
    b = Builder(np.zeros(1))
    add_body_shapes(b, scene, axes=scene.n_bodies <= 3, ghost=show_ghost, ghost_opacity=GHOST_OPACITY,
                    ghost_scale=GHOST_SCALE)
    links = []
    for k, e in enumerate(scene.effects):
        if isinstance(e, Spring):
            node = f"/meshcat/springs/{k}"
            add_spring_shape(b, scene, k, e, node, size, e.world_point)
            links.append(_link(node, int(scene.bodies_of(e)[0]), e.body_point, e.world_point, scene.other_body_of(e),
                               getattr(e, "other_point", None)))
        elif isinstance(e, Pivot):
            for i in scene.bodies_of(e):
                node = f"/meshcat/stems/{k}_{int(i)}"
                b.raw_object(node + "/line", g.Line(g.PointsGeometry(np.array([[0, 0], [0, 1], [0, 0]], np.float32)),
                                                    g.LineBasicMaterial(color=COLORS["pivot"], linewidth=2)))
                links.append(_link(node, int(i), np.zeros(3), e.world_point, None, None))
    add_effects(b, scene, size, lo, hi)
    b.prop("/Grid", "visible", False)                              # ours instead: segments (parts.add_grid)
    b.prop("/Axes", "visible", False)                              # the bodies' own axes only
    add_grid(b, lo, hi, size, floor)
    add_camera(b, target, distance, None)
    text, n = assets.compressed_commands([pack(c) for c in b.commands(fps=30.0, loop=False)])
    return {"commands": text, "size": n, "follow": bool(follow), "links": links}


def _link(node: str, body: int, body_point, anchor, other: int | None, other_point) -> dict:
    """A node stretched from an anchor (a world point, or a point of the body `other`) to a point of body `body`."""
    return {"path": node.strip("/").split("/"), "body": body, "b": np.asarray(body_point, float).tolist(),
            "anchor": None if other is not None else np.asarray(anchor, float).tolist(),
            "other": other, "ob": None if other is None else np.asarray(other_point, float).tolist()}
