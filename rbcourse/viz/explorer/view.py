"""Where the explorer's 3-D view looks from, and what holds the bodies: the camera (fixed, or following a body
that moves far), the floor and its grid (view_setup), the pivots and springs drawn with the bodies
(attachments)."""
from __future__ import annotations

import math

import numpy as np

from ...contact import Ground
from ...effects import Gravity, Spring
from ...pivot import Pivot

FOV = 40.0                                        # the camera's vertical field of view (degrees)
VIEW_DIRECTION = np.array([1.0, 0.7, 0.55])       # where the camera sits, seen from what it looks at


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
