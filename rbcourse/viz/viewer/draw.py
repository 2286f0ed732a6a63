"""A still of a State (draw_state) and an animation of a Trajectory (draw_trajectory): the options
checked, the frames chosen (the recorded state nearest each frame at `fps`), the ghost matched to
them, the trail, and the scene built from the pieces (bodies, ghost, arrows, trail, framing, camera,
grid, legend) into a Drawing.

R may have left SO(3) under the slides' Euler: every R is projected onto SO(3)
(rotation.project_so3) before it becomes a meshcat transform, since a transform must be a rotation.
The arrows use the physics' own vectors (ω = I⁻¹(t) L with the unprojected R, forces from the
effects); body points use the projected R so that they sit on the drawn body."""
from __future__ import annotations

import meshcat.geometry as g
import numpy as np

from ...support import checks
from ...support.language import say
from ...rotation import matvec, project_so3
from ...effects import Spring
from ...scene import as_scene
from ...state import State
from ...trajectory import Trajectory
from .commands import Builder, xyzw
from .frames import Frames, checked_trajectory, drawable, frame_arrows, frame_indices
from .linked import panels
from .page import Drawing
from .parts import (COLORS, FOV, HIDDEN, add_arrow, add_body_shapes, add_camera, add_effects, add_grid, add_springs,
                    body_radius, capped, metres_per_unit, spring_ends)


def _build(fr: Frames, tau: np.ndarray, *, omega, L, forces, axes, grid, arrow_length, arrow_scales, trail_points,
           ghost: Frames | None, ghost_offset, follow, camera_distance, title, legend_extra, fps, loop,
           t0, speed, blew_up: bool = False):
    """The commands for frames fr (and a ghost) at playback times tau (blew_up: the run diverged or was cut, its
    arrows scaled without their tail: parts.metres_per_unit)."""
    scene = fr.scene
    b = Builder(tau)
    size = max(2 * float(body.half_extents().max()) for body in scene.bodies)
    arrow_length = 1.2 * size if arrow_length is None else arrow_length
    add_body_shapes(b, scene, axes=axes, ghost=ghost is not None)
    for i in range(scene.n_bodies):
        b.move(f"/meshcat/bodies/{i}", position=fr.x[:, i], quaternion=xyzw(fr.Rp[:, i]))
    if ghost is not None:
        for i in range(scene.n_bodies):
            shown = np.where(ghost.shown, 1.0, HIDDEN)[:, None] * np.ones(3)      # hidden after its end
            b.move(f"/meshcat/ghost/{i}", position=ghost.x[:, i] + ghost_offset, quaternion=xyzw(ghost.Rp[:, i]),
                   scale=shown)
    arrows = frame_arrows(fr, omega, L, forces)
    scales = metres_per_unit(arrows, arrow_length, arrow_scales, blew_up)
    cap, cut = ARROW_CAP * arrow_length, set()
    tips = []                                    # where each arrow ends, frame by frame (F, 3): to be in view
    for a in arrows:
        vec = a.vec if a.kind in arrow_scales else capped(a.vec, scales[a.kind], cap)
        if vec is not a.vec and not np.array_equal(vec, a.vec):
            cut.add(a.kind)
        add_arrow(b, f"/meshcat/arrows/{a.name}", a.tail, vec, scales[a.kind], COLORS[a.kind], 0.02 * size)
        tips.append((int(a.name.rsplit("_", 1)[1]), a.tail + vec * scales[a.kind]))      # (its body, tip)
    add_springs(b, scene, fr, size)
    tips += [(int(scene.bodies_of(e)[0]), end) for e in scene.effects if isinstance(e, Spring)
             for end in spring_ends(scene, fr, e)]
    if trail_points is not None:
        pts = np.asarray(trail_points, dtype=np.float32)
        b.raw_object("/meshcat/trail", g.Line(g.PointsGeometry(pts.T.copy()),
                                              g.LineBasicMaterial(color=COLORS["trail"])))
    # framing: what must be in view — every body (its centre and radius), every arrow's tip, every spring's ends
    centres = fr.x if follow is None else fr.x[:, [follow]]
    if ghost is not None and follow is None:          # followed: the ghost counts by its offset (shift), not where
        centres = np.concatenate([centres, ghost.x + ghost_offset], axis=1)      # a blown-up ghost has gone
    body_r = max(body_radius(body) for body in scene.bodies)
    tips = [tip for i, tip in tips if follow is None or i == follow]
    points = np.stack(tips, axis=1) if tips else np.zeros((len(fr.t), 0, 3))        # (F, k, 3)
    everywhere = fr.x.reshape(-1, 3) if ghost is None else np.concatenate([fr.x, ghost.x + ghost_offset]).reshape(-1, 3)
    lo, hi = everywhere.min(0), everywhere.max(0)                                   # the grid's, the ground's extent
    if follow is None:
        everything = np.concatenate([centres.reshape(-1, 3), points.reshape(-1, 3)])
        target = (everything.min(0) + everything.max(0)) / 2
        follow_path = None
        from_target = centres - target, points - target
    else:                                   # the followed body, and its ghost when it is beside
        shift = ghost_offset / 2 if ghost is not None else np.zeros(3)
        follow_path = fr.x[:, follow] + shift
        target = follow_path[0]
        from_target = centres - follow_path[:, None], points - follow_path[:, None]
    radius = max(float(np.linalg.norm(from_target[0], axis=-1).max()) + body_r,
                 float(np.linalg.norm(from_target[1], axis=-1).max(initial=0.0)))
    if follow is not None:
        radius += float(np.linalg.norm(shift))
    distance = MARGIN * radius / np.sin(np.radians(FOV / 2)) if camera_distance is None else camera_distance
    add_camera(b, target, distance, follow_path)
    ground = add_effects(b, scene, size, lo, hi)
    b.prop("/Grid", "visible", False)                              # ours instead (or none)
    if grid:
        add_grid(b, lo, hi, size, ground)
    per = say("m per", "m par")
    colon = say(": ", " : ")
    legend = [(COLORS["omega"], f"ω{colon}{scales['omega']:.3g} {per} rad/s")] if "omega" in scales else []
    if "L" in scales:
        legend.append((COLORS["L"], f"L{colon}{scales['L']:.3g} {per} kg m²/s"))
    if "force" in scales:
        legend.append((COLORS["force"], say("forces at their points", "forces à leurs points d'application")
                       + f"{colon}{scales['force']:.3g} {per} N"))
    legend = [(c, words + (say(f" (a blow-up's longer arrows cut at {cap:.2g} m)",
                               f" (les flèches plus longues d'une divergence coupées à {cap:.2g} m)") if kind in cut else ""))
              for (c, words), kind in zip(legend, [k for k in ("omega", "L", "force") if k in scales])]
    legend += [(COLORS["spring"], say("spring", "ressort") + (f" (k = {e.stiffness:g} N/m)" if e.stiffness else ""))
               for e in scene.effects if isinstance(e, Spring)]
    legend += legend_extra
    return Drawing(b.commands(fps, loop), duration=float(tau[-1]), t0=t0, speed=speed, title=title,
                   legend=legend, arrow_scales=scales, frame_times=fr.t)


MARGIN = 1.15               # the camera 15% farther than where what must be in view would touch the frame
ARROW_CAP = 3.0              # an arrow is drawn at most 3 × arrow_length long (a blow-up's tail, cut)
TRAIL_PER_FRAME = 4          # trail points per animation frame (at most 4000 in all)


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


def _arrow_scales_arg(arrow_scales) -> dict:
    if arrow_scales is None:
        return {}
    if not isinstance(arrow_scales, dict) or not set(arrow_scales) <= {"omega", "L", "force"}:
        raise ValueError(f"arrow_scales must be None or a dict with keys among 'omega', 'L', 'force' "
                         f"(metres per unit), got {arrow_scales!r}")
    return {k: checks.positive(f"arrow_scales[{k!r}]", v) for k, v in arrow_scales.items()}


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
    fr = Frames([t], X.x.reshape(1, n, 3), X.R.reshape(1, n, 3, 3), X.L.reshape(1, n, 3), scene)
    return _build(fr, np.zeros(1), **opts, trail_points=None, ghost=None, ghost_offset=np.zeros(3), follow=follow,
                  title=title or (scene.name or "rbcourse"), legend_extra=[], fps=30.0, loop=False, t0=t, speed=1.0)


def _one_scene(runs):
    """Refuse runs of several scenes (ValueError naming traj[i]): the page draws the first and plots every run by
    what the first one's scene conserves."""
    first = runs[0].scene
    for i, r in enumerate(runs[1:], 1):
        if r.scene.same_physics(first):
            continue
        n, m = first.n_bodies, r.scene.n_bodies
        what = (f"a scene of {m} bod{'y' if m == 1 else 'ies'}, traj[0] of {n}" if m != n else
                "a scene of other bodies or effects than traj[0]'s (Scene.same_physics)")
        raise ValueError(f"traj must be a list of runs of one scene (the first is drawn, every one is plotted by what "
                         f"the first one's scene conserves), but traj[{i}] is a run of {what}: draw each scene in its own draw_trajectory")


def draw_trajectory(traj: Trajectory, *, speed: float = 1.0, fps: float = 30.0, omega: bool = True, L: bool = True,
                    forces: bool = True, axes: bool = True, grid: bool = True, arrow_length: float | None = None,
                    arrow_scales: dict | None = None, trail=None,
                    trail_body: int = 0, ghost: Trajectory | None = None, ghost_offset=(0.0, 0.0, 0.0),
                    ghost_label: str | None = None, follow="auto", camera_distance: float | None = None,
                    loop: bool = True, max_frames: int = 20000, title: str | None = None, plots: bool = False,
                    labels=None, drift_from: float = 0.0, ghost_is_reference: bool = True) -> Drawing:
    """A meshcat animation of a Trajectory, in real time (speed = 1) or speed times faster.

    plots=True: the linked view — under the scene, the drift over time of what the scene conserves (energy, L or
    L_z about a pivot, from drift_from on), ‖RᵀR − I‖, and the rotation error against the ghost (when there is
    one and ghost_is_reference), with one time cursor shared with the animation: play/pause, click or drag a plot
    to seek, the scene follows; #t=1.5 opens at that time.  traj may then be a list of runs of one scene (the
    first is drawn, every one is plotted; labels: their names, default their methods): runs of another scene (other
    bodies or effects: Scene.same_physics) are refused, each is drawn in a draw_trajectory of its own.

    The run is resampled to `fps` frames per second of playback (the recorded state nearest
    each frame; three.js interpolates between them), so a long run stays small.
    omega, L, forces, axes, grid: draw ω, L, the PointForce forces, the body axes, a floor grid
    (at z = 0, or at the height of a Ground effect, which is also drawn).
    arrow_length: metres of the longest arrow of each kind (default 1.2 × the largest body size);
    arrow_scales: fixed metres per unit instead, e.g. {"omega": 0.02} (m per rad/s), {"force": 0.05} (m per N).
    trail: a body point b (body axes) whose world path x + R b is drawn, of body trail_body (at the
    recorded states, 4 a frame at most, 4000 in all).
    ghost: a reference trajectory (the exact motion, another method) drawn semi-transparent,
    shifted by ghost_offset (zero: over the bodies); ghost_label names it in the legend.
    follow: the camera follows a body's centre (an index), or frames the whole motion (None);
    "auto": follow the body of a one-body scene.  camera_distance overrides the framing.
    loop: play over and over (else once).  max_frames bounds the page's size.
    Every R is projected onto SO(3) before it is sent (Euler's R drifts off it).
    """
    plots = _flag("plots", plots)
    runs = list(traj) if isinstance(traj, (list, tuple)) and plots else [traj]
    if not runs:
        raise ValueError("traj must be a Trajectory or, with plots=True, a non-empty list of them")
    runs = [checked_trajectory("traj" if len(runs) == 1 else f"traj[{i}]", r) for i, r in enumerate(runs)]
    _one_scene(runs)
    if labels is None:
        labels = [r.method or say(f"run {i}", f"simulation {i}") for i, r in enumerate(runs)]
    elif not isinstance(labels, (list, tuple)) or len(labels) != len(runs) or not all(isinstance(x, str) for x in labels):
        raise ValueError(f"labels must be a list of {len(runs)} strings (one per run), got {labels!r}")
    drift_from = checks.real("drift_from", drift_from, low=float(runs[0].t[0]), high=float(runs[0].t[-1]))
    ghost_is_reference = _flag("ghost_is_reference", ghost_is_reference)
    traj, traj_note = drawable(runs[0])
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
    if ghost_label is None:
        ghost_label = say("reference", "référence")
    if not isinstance(ghost_label, str):
        raise ValueError(f"ghost_label must be a string, got {ghost_label!r}")
    index = frame_indices(traj.t, speed, fps, max_frames)
    fr = Frames.from_trajectory(traj, index)
    tau = (fr.t - traj.t[0]) / speed
    ghost_fr, extra = None, []
    if ghost is not None:
        ghost, ghost_note = drawable(checked_trajectory("ghost", ghost))
        if ghost_note and not any(word in ghost_label for word in ("diverged", "divergé")):
            ghost_label = f"{ghost_label} ({ghost_note})" if ghost_label else ghost_note
        if ghost.scene.n_bodies != n:
            raise ValueError(f"ghost must have the same number of bodies as traj ({n}), got {ghost.scene.n_bodies}")
        k = np.clip(np.searchsorted(ghost.t, fr.t), 0, len(ghost.t) - 1)
        prev = np.clip(k - 1, 0, None)
        k = np.where(np.abs(ghost.t[prev] - fr.t) <= np.abs(ghost.t[k] - fr.t), prev, k)
        ghost_fr = Frames.from_trajectory(ghost, k)
        ghost_fr.shown = fr.t <= ghost.t[-1] + 0.5 * speed / fps
        extra.append((COLORS["ghost"], say("ghost: ", "fantôme : ") + ghost_label))
    trail_points = None
    if trail is not None:
        # 4 points a frame (three.js moves the body in straight lines between frames: finer than that)
        dense = np.unique(np.linspace(0, len(traj.t) - 1, min(len(traj.t), TRAIL_PER_FRAME * len(fr.t), 4000))
                          .round().astype(int))
        Rp = project_so3(traj.R[dense] if n == 1 else traj.R[dense, trail_body])
        xs = traj.x[dense] if n == 1 else traj.x[dense, trail_body]
        trail_points = xs + matvec(Rp, trail)
        point = np.round(trail, 4).tolist()
        extra.append((COLORS["trail"], say(f"trail of body point {point}", f"trace du point {point} du corps")))
    if title is None:
        name = traj.scene.name or "rbcourse"
        title = f"{name}{say(': ', ' : ')}{traj.method or 'simulation'}" + (f", dt = {traj.dt:g} s" if traj.dt else "")
    if traj_note:
        title = f"{title} — {traj_note}"
    drawing = _build(fr, tau, **opts, trail_points=trail_points, ghost=ghost_fr, ghost_offset=ghost_offset,
                     follow=follow, title=title, legend_extra=extra, fps=fps, loop=loop, t0=float(traj.t[0]),
                     speed=speed, blew_up=bool(traj_note))
    if plots:
        reference = ghost if ghost is not None and ghost_is_reference else None
        drawing.plots = panels(runs, list(labels), reference, ghost_label or None, drift_from)
    return drawing
