"""The meshcat commands of a drawing: static objects (set_object, set_transform, set_property) and
per-frame node values (position, quaternion, scale) collected by path (Builder), lowered to
commands with one three.js animation.  Transforms are 4×4 matrices [R s, p; 0, 1]; quaternions are
(x, y, z, w) as three.js orders them, made sign-continuous so that slerp takes the short way.
pack: a command as the msgpack bytes meshcat's viewer decodes."""
from __future__ import annotations

import numpy as np
import umsgpack
from meshcat.animation import Animation, AnimationClip, AnimationTrack
from meshcat.commands import SetAnimation, SetObject, SetProperty, SetTransform
from meshcat.path import Path as MeshcatPath

from ...rotation import matrix_from_quat, quat_from_matrix


def pack(command: dict) -> bytes:
    """A lowered command as msgpack.  An animation's key times and values go as float32: three.js keeps
    them in Float32Arrays (KeyframeTrack), so nothing shown changes, and the page is half the size;
    every other number (static transforms, sizes) stays float64, as three.js keeps them."""
    single = command.get("type") == "set_animation"
    return umsgpack.packb(command, force_float_precision="single" if single else "double")


def quat_y_to(u: np.ndarray) -> np.ndarray:
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


def xyzw(R: np.ndarray) -> np.ndarray:
    """Quaternions (x, y, z, w) as three.js orders them, of rotations R (F, 3, 3)."""
    q = quat_from_matrix(R)
    return _continuous(np.concatenate([q[:, 1:], q[:, :1]], axis=-1))


def transform(position, quaternion=None, scale=None) -> np.ndarray:
    """4×4 transform from a position, a quaternion (x, y, z, w) and a scale."""
    T = np.eye(4)
    if quaternion is not None:
        x, y, z, w = quaternion
        T[:3, :3] = matrix_from_quat(np.array([w, x, y, z], dtype=float))
    if scale is not None:
        T[:3, :3] = T[:3, :3] * np.asarray(scale)[None, :]
    T[:3, 3] = position
    return T


class Builder:
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
            T = transform(first.get("position", np.zeros(3)), first.get("quaternion"), first.get("scale"))
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
