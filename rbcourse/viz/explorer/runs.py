"""The grid of runs behind an explorer page: every method × every step, each timed, measured against the
reference at its own step times, and kept in a compact form (resampled curves and animation frames).

check_arguments(...) -> Settings      every argument checked, nothing computed
run_grid(settings) -> Grid            the runs: one untimed warm-up per method (warmup_scene), then each run timed
                                      (time.perf_counter around rb.simulate), measured (viz/quantities.py)
                                      against the reference (reference.py), and resampled

Resampling: each curve keeps at most `frames` points; each point is the largest value over the steps
since the previous point (no spike is lost).  The animation keeps the state nearest each of `frames`
instants (fewer with many bodies: MAX_BODY_FRAMES body-frames over all runs), R projected onto SO(3).
A run that diverged (rb.simulate(..., on_divergence="stop")) keeps its steps up to the blow-up: its
curves stop there; its animation stops at its last state that can be drawn (|x| < 1e6 m, |R| < 1e15).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ...support import checks
from ...body import RigidBody
from ...impulse import Impulse
from ...methods import METHODS, get_method
from ...rotation import project_so3, quat_from_matrix
from ...scene import Scene, as_scene
from ...simulate import simulate
from ...state import State
from .. import quantities
from .reference import reference_for
from .text import page_text

MAX_METHODS = 6                 # a page holds at most 6 methods × 6 steps
MAX_DTS = 6
MAX_STEPS = 10**6               # steps × bodies of one run (t_end / dt × bodies); the fine reference takes 8× more
MIN_FRAMES, MAX_FRAMES = 30, 1000
MAX_BODY_FRAMES = 120_000       # animation frames × bodies over all runs and the ghost (≈ 4.5 MB of float32 in base64)
DRAW_LIMITS = {"x": 1e6, "R": 1e15}    # beyond these (m; entries of R) a state is not drawn
CLIP = 1e30                     # curve values beyond this are stored as this (float32 holds up to 3.4e38)
WARMUP_STEPS = 10               # a method's untimed warm-up: this many of the grid's coarsest steps (warmup_scene)
DEFAULT_METHODS = ("euler", "splitting", "rk4", "exact_splitting")
DEFAULT_DT_FACTORS = (20.0, 10.0, 5.0, 2.5)    # the default steps: the scene's suggested dt times these
BARE_DEFAULTS = {"t_end": 5.0, "dts": (0.02, 0.01, 0.005, 0.0025)}   # for a scene given without an Example


@dataclass(frozen=True)
class Settings:
    """The checked arguments of an explorer (check_arguments)."""
    scene: Scene
    X0: State
    methods: tuple
    dts: tuple                  # as given (s)
    steps: tuple                # n = round(t_end / dt) for each; the run's step is t_end / n
    t_end: float
    drift_from: float
    frames: int                 # curve points (and animation frames with one body)
    track_frames: int           # animation frames per run (fewer with many bodies)
    default: tuple              # (method, dt)
    name: str
    description: str


def _is_example(obj) -> bool:
    """A named set-up of rbcourse.examples (an Example: scene, X0, t_end, dt, …), read by its fields."""
    return not isinstance(obj, (Scene, RigidBody)) and all(hasattr(obj, k) for k in ("scene", "X0", "t_end", "dt"))


def check_arguments(scene, X0=None, *, methods=None, dts=None, t_end=None, drift_from=None, frames=None,
                    default=None, name=None, description=None) -> Settings:
    """Every argument of explore(), checked, before anything is computed: a ValueError names the first bad one
    and what is allowed.  scene: a Scene, a RigidBody (a free body) or an Example (its X0, t_end, dt,
    drift_from, name and description are the defaults)."""
    example = scene if _is_example(scene) else None
    if example is not None:
        scene = example.scene
        X0 = example.X0 if X0 is None else X0
    scene = as_scene(scene)
    if not isinstance(X0, State):
        raise ValueError(f"X0 must be a State (the initial state of the scene's bodies), got {X0!r}")
    scene.batch(X0)                                                  # X0 holds the scene's bodies
    if methods is None:
        methods = DEFAULT_METHODS
    if isinstance(methods, str) or not isinstance(methods, (list, tuple)) or not methods:
        raise ValueError(f"methods must be a non-empty list of method names among {sorted(METHODS)}, got {methods!r}")
    methods = tuple(get_method(m).name for m in methods)
    if len(set(methods)) != len(methods):
        raise ValueError(f"methods must not repeat a method, got {list(methods)}")
    if len(methods) > MAX_METHODS:
        raise ValueError(f"methods must hold at most {MAX_METHODS} methods (one page: at most {MAX_METHODS} methods × "
                         f"{MAX_DTS} steps), got {len(methods)}")
    if t_end is None:
        t_end = example.t_end if example is not None else BARE_DEFAULTS["t_end"]
    t_end = checks.positive("t_end", t_end)
    scene.check_start(X0, t_end)          # as every run will: an Impulse in [0, t_end], no body below a Ground, …
    if dts is None:
        dts = (tuple(example.dt * f for f in DEFAULT_DT_FACTORS) if example is not None else BARE_DEFAULTS["dts"])
        if max(dts) > t_end:
            raise ValueError(f"t_end = {t_end:g} s is shorter than the default steps dts = {[float(d) for d in dts]} s: "
                             f"give a longer t_end, or dts (each <= t_end)")
    if isinstance(dts, str) or not isinstance(dts, (list, tuple, np.ndarray)) or len(dts) == 0:
        raise ValueError(f"dts must be a non-empty list of time steps (s, finite, > 0), got {dts!r}")
    dts = tuple(checks.positive(f"dts[{i}]", d) for i, d in enumerate(dts))
    if len(dts) > MAX_DTS:
        raise ValueError(f"dts must hold at most {MAX_DTS} steps (one page: at most {MAX_METHODS} methods × {MAX_DTS} "
                         f"steps), got {len(dts)}")
    for i, d in enumerate(dts):
        if d > t_end:
            raise ValueError(f"dts[{i}] must be <= t_end = {t_end:g} s, got {d:g} s")
    for i, d in enumerate(dts):                         # t_end / d may overflow to inf (t_end = 1e308, d = 1e-300)
        n = t_end / d
        if not (n <= MAX_STEPS and max(1, round(n)) * scene.n_bodies <= MAX_STEPS):
            count = f"{n:,.0f}" if n < 1e15 else f"{n:.3g}"          # (1e-300 s: not a 300-digit count)
            raise ValueError(f"dts[{i}] = {dts[i]:g} s gives {count} steps × {scene.n_bodies} bod"
                             f"{'y' if scene.n_bodies == 1 else 'ies'} over t_end = {t_end:g} s: steps × bodies must "
                             f"be at most MAX_STEPS = {MAX_STEPS:,} per run (choose a larger dt or a shorter t_end)")
    steps = tuple(max(1, round(t_end / d)) for d in dts)
    if len(set(steps)) != len(steps):
        i, j = next((i, j) for i in range(len(steps)) for j in range(i) if steps[i] == steps[j])
        raise ValueError(f"dts must be distinct steps: dts[{j}] = {dts[j]:g} s and dts[{i}] = {dts[i]:g} s both give "
                         f"{steps[i]} steps over t_end = {t_end:g} s")
    if drift_from is None:
        drift_from = float(getattr(example, "drift_from", 0.0)) if example is not None else 0.0
        drift_from = drift_from if drift_from < t_end else 0.0
    drift_from = checks.real("drift_from", drift_from, low=0.0, high=t_end, high_open=True)
    if frames is None:
        frames = int(round(min(600.0, max(200.0, 60 * t_end))))
    frames = checks.integer("frames", frames, low=MIN_FRAMES, high=MAX_FRAMES)
    runs = len(methods) * len(dts) + 1
    track_frames = min(frames, MAX_BODY_FRAMES // (runs * scene.n_bodies))
    if track_frames < MIN_FRAMES:
        most = MAX_BODY_FRAMES // (MIN_FRAMES * runs)
        raise ValueError(f"scene has {scene.n_bodies} bodies: too many for one page with {runs - 1} runs "
                         f"(frames × bodies × (runs + 1) must be at most MAX_BODY_FRAMES = {MAX_BODY_FRAMES:,} with at "
                         f"least {MIN_FRAMES} frames: at most {most} bodies for this grid; fewer methods or dts "
                         f"allow more)")
    if default is None:               # rk4 at the coarsest step if it is in the grid (a run that stays), else the first
        default = ("rk4" if "rk4" in methods else methods[0], dts[0])
    if not isinstance(default, (list, tuple)) or len(default) != 2:
        raise ValueError(f"default must be None or a pair (method, dt) of the grid, got {default!r}")
    d_method, d_dt = default
    if d_method not in methods:
        raise ValueError(f"default's method must be one of the methods {list(methods)}, got {d_method!r}")
    if not checks.is_real_scalar(d_dt) or not any(math.isclose(d_dt, d, rel_tol=1e-9) for d in dts):
        raise ValueError(f"default's dt must be one of the dts {list(dts)}, got {d_dt!r}")
    d_dt = next(d for d in dts if math.isclose(d_dt, d, rel_tol=1e-9))
    if name is None:
        name = (scene.name or (example.name if example is not None else "")
                or (scene.bodies[0].name if scene.single else "") or "scene")
    if not isinstance(name, str):
        raise ValueError(f"name must be a string or None, got {name!r}")
    if description is None:
        description = example.description if example is not None else ""
    if not isinstance(description, str):
        raise ValueError(f"description must be a string or None, got {description!r}")
    return Settings(scene, X0, methods, dts, steps, t_end, drift_from, frames, track_frames, (d_method, d_dt),
                    name, description)


@dataclass
class Track:
    """Animation frames: times t (F,), centres x (F, N, 3), orientations q (F, N, 4) (w, x, y, z; R projected)."""
    t: np.ndarray
    x: np.ndarray
    q: np.ndarray


@dataclass
class Run:
    """One run of the grid, kept compact."""
    method: str
    dt: float                   # as asked
    h: float                    # the step taken: t_end / steps
    steps: int
    seconds: float              # wall time of rb.simulate (after a warm-up run of the method)
    error: float                # rotation error against the reference at t_end (rad); inf if it diverged
    position_error: float       # ‖x − x_ref‖ at t_end (m, largest over the bodies); inf if it diverged
    diverged: bool
    reason: str                 # why it stopped ("" if it did not): rb.Trajectory.outcome
    t_last: float               # the last recorded time (t_end unless it diverged: then its last finite state)
    t_diverged: float           # when it blew up (the first bad state: rb.Trajectory.divergence.t); nan if it did not
    implementation: str
    curve_t: np.ndarray         # (F,) times of the curve points
    curves: dict                # key -> (F,) values (NaN before t₀ for drifts)
    track: Track
    drawn_note: str = ""        # why the animation stops before t_last ("" if it does not)


@dataclass
class Grid:
    """Everything an explorer page shows."""
    settings: Settings
    plan: quantities.Plan
    reference: object           # ExactReference or FineReference (label, detail, accuracy)
    runs: list
    ghost: Track
    seconds: float              # how long the whole grid took to compute (warm-ups and references included)
    warmup_note: str = ""
    notes: list = field(default_factory=list)

    def run(self, method: str, dt: float) -> Run:
        for r in self.runs:
            if r.method == method and math.isclose(r.dt, dt, rel_tol=1e-9):
                return r
        raise ValueError(f"no run ({method!r}, dt = {dt!r}) in this grid: methods {list(self.settings.methods)}, "
                         f"dts {list(self.settings.dts)}")


def nearest_indices(t: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """Indices of the recorded times t nearest to the targets within [t0, t[-1]], unique, ending with the last."""
    targets = targets[targets <= t[-1]]
    if len(t) == 1 or len(targets) == 0:
        return np.array([len(t) - 1])
    k = np.clip(np.searchsorted(t, targets), 1, len(t) - 1)
    k = np.where(targets - t[k - 1] <= t[k] - targets, k - 1, k)
    return np.unique(np.append(k, len(t) - 1))


def largest_since_previous(v: np.ndarray, k: np.ndarray) -> np.ndarray:
    """For increasing indices k: the largest of v over (k[j-1], k[j]] (NaN ignored; [0, k[0]] first)."""
    starts = np.r_[0, k[:-1] + 1]
    with np.errstate(invalid="ignore"):
        return np.fmax.reduceat(v[: k[-1] + 1], starts)


def drawable_rows(traj) -> int:
    """How many leading states of the run can be drawn (|x| < 1e6 m, |entries of R| < 1e15)."""
    m = len(traj.t)
    ok = np.ones(m, dtype=bool)
    with np.errstate(invalid="ignore"):
        for key, limit in DRAW_LIMITS.items():
            ok &= (np.abs(getattr(traj, key)).reshape(m, -1) < limit).all(axis=1)
    return m if ok.all() else max(int(np.argmin(ok)), 1)


def make_track(traj, targets: np.ndarray, rows: int | None = None) -> Track:
    """The states of traj nearest the target times (among its first `rows`), R projected onto SO(3)."""
    rows = len(traj.t) if rows is None else rows
    k = nearest_indices(traj.t[:rows], targets)
    x, R = traj.x[k], traj.R[k]
    if x.ndim == 2:
        x, R = x[:, None], R[:, None]
    q = quat_from_matrix(project_so3(R))
    return Track(traj.t[k].copy(), x.astype(np.float32), q.astype(np.float32))


def warmup_scene(scene: Scene, t_warm: float) -> Scene:
    """The scene a method's untimed warm-up runs over [0, t_warm] (WARMUP_STEPS coarse steps): numba compiles there
    what the timed runs call, and the user's scene is not changed.  It is the scene itself unless an Impulse falls
    after t_warm (a run refuses an Impulse outside [0, t_end]): then a copy of it where each such kick is replaced by
    one of J = 0 (ΔP = J = 0, ΔL = (r − c) × J = 0: nothing kicked) at the same body point and body, at t_warm / 2,
    so the warm-up still splits a step and kicks (the same compiled step and kick as the timed runs), and its
    t_end = t_warm is never named to the user."""
    late = {id(e) for e in scene.effects if isinstance(e, Impulse) and e.time > t_warm}
    if not late:
        return scene
    effects = [Impulse(e.body_point, (0.0, 0.0, 0.0), t_warm / 2, body=e.body) if id(e) in late else e
               for e in scene.effects]
    return Scene(scene.bodies, effects, name=scene.name)


def run_grid(settings: Settings, progress: bool = False) -> Grid:
    """Every run of the grid (module docstring).  progress: a progress bar over the runs."""
    from ...support.outputs import progress as bar_of
    s = settings
    start = time.perf_counter()
    n_max = max(s.steps)
    reference = reference_for(s.scene, s.X0, s.t_end, n_max)
    if not reference.exact:
        reference.prepare(s.steps)
    plan = quantities.plan(s.scene, s.drift_from, s.t_end, s.t_end / n_max)
    targets = np.linspace(0.0, s.t_end, s.frames)
    track_targets = np.linspace(0.0, s.t_end, s.track_frames)
    total = len(s.methods) * (len(s.dts) + 1) + (0 if reference.exact else len(s.dts) + 1)
    runs, ghost = {}, None
    with bar_of(total, "run", "explore", progress) as bar:
        h = s.t_end / min(s.steps)
        t_warm = min(s.t_end, WARMUP_STEPS * h)
        warm = warmup_scene(s.scene, t_warm)
        for method in s.methods:                      # numba compiles each method's step at its first run: not timed
            simulate(warm, s.X0, t_warm, h, method, on_divergence="stop")
            bar.update()
        for dt, n in sorted(zip(s.dts, s.steps), key=lambda p: p[1]):   # coarse to fine: one reference at a time
            h = s.t_end / n
            ref = reference.for_run(h, n)
            if not reference.exact:
                bar.update()
            for method in s.methods:
                t0 = time.perf_counter()
                traj = simulate(s.scene, s.X0, s.t_end, h, method, on_divergence="stop")
                seconds = time.perf_counter() - t0
                runs[method, dt] = _measure(s, plan, method, dt, n, seconds, traj, ref, targets, track_targets)
                bar.update()
            if n == n_max:
                if reference.exact:
                    ghost = make_track(reference.at(track_targets), track_targets)
                else:
                    ghost = make_track(ref, track_targets)
                    reference.measure_accuracy(ref)
                    bar.update()
    ordered = [runs[m, d] for m in s.methods for d in s.dts]
    return Grid(s, plan, reference, ordered, ghost, time.perf_counter() - start,
                warmup_note=page_text("warmup"))


def _measure(s: Settings, plan, method, dt, n, seconds, traj, ref, targets, track_targets) -> Run:
    """A run's curves, end errors and animation frames."""
    k = nearest_indices(traj.t, targets)
    vals = quantities.values(plan, traj, ref, keep=k)
    curves = {key: np.clip(largest_since_previous(v, k), 0.0, CLIP) for key, v in vals.items()}
    finished = not traj.diverged
    if finished:
        error = float(vals["rotation"][-1])
        dx = np.linalg.norm(traj.x[-1] - ref.x[len(traj.t) - 1], axis=-1)
        position_error = float(np.max(dx))
    else:
        error = position_error = math.inf
    rows = drawable_rows(traj)
    note = ""
    if rows < len(traj.t):
        note = page_text("drawn_note", t=traj.t[rows - 1])
    return Run(method=method, dt=dt, h=s.t_end / n, steps=n, seconds=seconds, error=error,
               position_error=position_error, diverged=traj.diverged, reason=traj.outcome if traj.diverged else "",
               t_last=float(traj.t[-1]), t_diverged=traj.divergence.t if traj.diverged else math.nan,
               implementation=traj.implementation, curve_t=traj.t[k].copy(),
               curves=curves, track=make_track(traj, track_targets, rows), drawn_note=note)
