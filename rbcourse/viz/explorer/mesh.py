"""The bodies' shapes for the explorer's 3-D view: convex meshes in body axes (a box, a cylinder, a sphere, or
the ellipsoid of a body's inertia), their faces turned outwards with their normals, as the page's data."""
from __future__ import annotations

import numpy as np


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
