"""The one table of named set-ups, as box2d-lite's demos[]: the demo, the notebooks, the benchmarks
and the hard cases all take their scenes from here.

Each function returns an Example: the scene (bodies and effects), its initial state X0, a suggested
t_end, dt and method, and a description.  SCENES are the demos (``python -m rbcourse demo NAME``
runs SCENES[NAME]()); EXAMPLES holds every named set-up: the demos, and the free bodies that the
benchmark problems A, B, C (bench/problems.py) and the hard cases (bench/hardcases.py) run — those
add only their own data (duration, step, reference, what goes wrong).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .body import RigidBody
from .support import checks
from .support.language import say
from .effects import Gravity, LinearDrag, AngularDrag, PointForce, Spring
from .pivot import Pivot
from .profiles import Pulse  # noqa: F401  (examples.Pulse: the pushed box's push, evaluated by the kernel)
from .scene import Scene
from .state import State


@dataclass(frozen=True)
class Example:
    """A ready-to-run scene."""
    name: str
    scene: Scene
    X0: State
    t_end: float
    dt: float
    method: str
    description: str
    drift_from: float = 0.0     # measure drift from here (after a push, say)
    omega_body: np.ndarray | None = None    # ω(0) in body axes, when the set-up is given by it (as MuJoCo's)


def racket_box(mass: float = 1.0) -> RigidBody:
    """The benchmarks' box: 1 kg, 0.3 × 0.2 × 0.05 m (y is the intermediate axis)."""
    return RigidBody.box(mass=mass, size=(0.3, 0.2, 0.05))


def top_disc() -> RigidBody:
    """Benchmark C's disc: cylinder r = 0.04 m, h = 0.01 m, m = 1 kg (symmetry axis: body z)."""
    return RigidBody.cylinder(mass=1.0, radius=0.04, height=0.01)


def rotation_about_x(angle: float) -> np.ndarray:
    """The rotation by `angle` (rad) about world x."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


# =====================================================================================
# The demos
# =====================================================================================

def pushed_box(mass: float = 1.0, size=(0.3, 0.2, 0.05), push=(0.0, 0.0, 10.0), t_push: float = 0.1) -> Example:
    """The slides' box (1 kg, 0.3 × 0.2 × 0.05 m), at rest, pushed at its corner (a/2, b/2, c/2) by
    F = (0, 0, 10) N (world axes) for 0.1 s, then tumbling freely (no gravity)."""
    t_push = checks.real("t_push", t_push, low=0.0)         # the push's duration (s), named as the caller gave it
    body = RigidBody.box(mass=mass, size=size)
    corner = np.array(size, dtype=float) / 2
    force = PointForce(body_point=corner, force=Pulse(push, 0.0, t_push), frame="world")
    scene = Scene(body, [force], name=say("pushed box", "boîte poussée"))
    return Example("pushed_box", scene, State.at_rest(), t_end=5.0, dt=1e-3, method="rk4",
                   description=say(f"a box pushed at a corner for {t_push:g} s, then tumbling freely",
                                   f"une boîte poussée à un coin pendant {t_push:g} s, puis qui culbute librement"),
                   drift_from=t_push)


def tennis_racket() -> Example:
    """Benchmark A: free box spun about its intermediate axis (Dzhanibekov flip), ω0 = (0.01, 5, 0.01) body."""
    return free_spin("tennis_racket", racket_box(), [0.01, 5.0, 0.01], t_end=20.0,
                     description=say("a free box spinning about its intermediate axis: it flips about every 5 s",
                                     "une boîte libre lancée autour de son axe intermédiaire : elle se retourne toutes les 5 s environ"))


def box_on_spring() -> Example:
    """A box hanging from a damped spring attached at one of its corners, under gravity: it bobs and swings."""
    body = racket_box()
    spring = Spring(body_point=(0.15, 0.1, 0.025), world_point=(0.0, 0.0, 1.0), stiffness=50.0, damping=0.1,
                    rest_length=0.3)
    scene = Scene(body, [Gravity(), spring], name=say("box on a spring", "boîte au ressort"))
    X0 = State.from_velocities(body, [0.1, 0.0, 0.5], np.eye(3), np.zeros(3), [0.0, 0.0, 2.0])
    return Example("box_on_spring", scene, X0, t_end=10.0, dt=1e-3, method="rk4",
                   description=say("a box hanging from a spring at one corner, bobbing and swinging under gravity",
                                   "une boîte suspendue par un coin à un ressort, qui oscille et se balance sous la gravité"))


def heavy_top(tilt_deg: float = 30.0, spin: float = 200.0) -> Example:
    """Benchmark C: a disc on a massless stem, pivot at the world origin, centre of mass 5 cm up the
    symmetry axis; tilted 30° about world x, spinning at 200 rad/s about its axis, under gravity."""
    body = top_disc()
    pivot = Pivot(body_point=(0.0, 0.0, -0.05), world_point=(0.0, 0.0, 0.0))
    R0 = rotation_about_x(np.radians(tilt_deg))
    omega_body = np.array([0.0, 0.0, spin])
    X0 = pivot.state(body, R0, R0 @ omega_body)
    scene = Scene(body, [Gravity(), pivot], name=say("heavy top", "toupie pesante"))
    return Example("heavy_top", scene, X0, t_end=5.0, dt=2.5e-4, method="rk4",
                   description=say("a fast heavy top: it spins, precesses slowly and nutates a little",
                                   "une toupie pesante rapide : elle tourne, précesse lentement et nute un peu"),
                   omega_body=omega_body)


def many_bodies(n: int = 200, seed: int = 0) -> Example:
    """A field of n boxes of random sizes and spins on a grid, slowed by a little drag: stepped as arrays."""
    rng = np.random.default_rng(seed)
    side = int(np.ceil(np.sqrt(n)))
    bodies, states = [], []
    for i in range(n):
        size = rng.uniform(0.05, 0.3, 3)
        body = RigidBody.box(mass=float(rng.uniform(0.5, 2.0)), size=size)
        x = np.array([i % side, i // side, 1.0]) * 0.5
        states.append(State.from_velocities(body, x, np.eye(3), np.zeros(3), rng.normal(0.0, 3.0, 3)))
        bodies.append(body)
    scene = Scene(bodies, [AngularDrag(1e-4), LinearDrag(1e-3)], name=say("field of boxes", "champ de boîtes"))
    return Example("many_bodies", scene, State.stack(states), t_end=5.0, dt=2e-3, method="rk4",
                   description=say(f"{n} tumbling boxes, stepped together as arrays", f"{n} boîtes qui culbutent, avancées ensemble en tableaux"))


def dropped_box(restitution: float = 0.4, friction: float = 0.5) -> Example:
    """A box dropped from 1 m, tilted and spinning, moving sideways: it bounces, slides, tips over
    and comes to rest on the floor (gravity + ground contact, nothing else)."""
    from .contact import Ground
    from .rotation import rotation_about
    body = racket_box()
    R0 = rotation_about([1.0, 0.5, 0.0], 0.6)
    X0 = State.from_velocities(body, [0.0, 0.0, 1.0], R0, [1.0, 0.0, 0.0], [2.0, -3.0, 5.0])
    scene = Scene(body, [Gravity(), Ground(height=0.0, restitution=restitution, friction=friction)], name=say("dropped box", "boîte lâchée"))
    return Example("dropped_box", scene, X0, t_end=3.0, dt=2e-3, method="rk4",
                   description=say("a box dropped on the floor: it bounces, slides, tips over and comes to rest",
                                   "une boîte lâchée sur le sol : elle rebondit, glisse, bascule et s'immobilise"))


# =====================================================================================
# Free bodies spinning: the benchmarks' and the hard cases' set-ups
# =====================================================================================

def free_spin(name: str, body: RigidBody, omega_body, *, description: str, t_end: float = 10.0,
              dt: float = 1e-3) -> Example:
    """A free body (no force, no torque) at the origin, R(0) = I, spinning at ω(0) = omega_body (body
    axes, equal to world axes at t = 0):  P = 0,  L = I_body ω(0).  Method rk4."""
    omega = np.asarray(omega_body, dtype=float)
    X0 = State.from_velocities(body, np.zeros(3), np.eye(3), np.zeros(3), omega)
    said = say(name.replace("_", " "), FREE_SPINS_FR.get(name, name.replace("_", " ")))
    return Example(name, Scene(body, name=said), X0, t_end=t_end, dt=dt, method="rk4",
                   description=description, omega_body=omega)


FREE_SPINS_FR = {"tennis_racket": "raquette de tennis", "fast_spin": "rotation rapide", "slender_rod": "tige fine",
                 "near_separatrix": "près de la séparatrice", "principal_axis_spin": "rotation sur l'axe intermédiaire",
                 "tumbling_box": "boîte qui culbute", "sphere": "sphère", "symmetric_body": "corps symétrique",
                 "light_box": "boîte légère", "heavy_box": "boîte lourde"}
"""The free spins' scene names in French (a French notebook builds its scenes after langue("fr"))."""


def fast_spin() -> Example:
    """Benchmark B: the racket box spun fast about its major axis, ω0 = (0.1, 0.1, 50) body."""
    return free_spin("fast_spin", racket_box(), [0.1, 0.1, 50.0],
                     description="a free box spinning fast about its major axis: about 80 turns in 10 s")


def thin_disk() -> Example:
    """A thin disk, I = (0.25, 0.25, 0.5) kg m², given L(0) = (0.3, −0.2, 20): ω(0) = (1.2, −0.8, 40) rad/s."""
    body = RigidBody(1.0, [0.25, 0.25, 0.5], name="thin disk")
    X0 = State(np.zeros(3), np.eye(3), np.zeros(3), [0.3, -0.2, 20.0])
    return Example("thin_disk", Scene(body, name="thin disk"), X0, t_end=10.0, dt=1e-3, method="rk4",
                   description="a thin disk spinning fast about its axis, wobbling a little")


def slender_rod() -> Example:
    """A slender rod, inertia ratio 1000:1:1000, spun about an oblique axis: ω0 = (1, 300, 2) body."""
    rod = RigidBody(1.0, [1.72e-4, 1.72e-7, 1.7185e-4], name="slender rod")
    return free_spin("slender_rod", rod, [1.0, 300.0, 2.0], dt=1e-4,
                     description="a slender rod spinning fast about its long axis, tumbling slowly")


def near_separatrix() -> Example:
    """The racket box spun about its intermediate axis, off it by 1e-6 rad/s: ω0 = (1e-6, 5, 1e-6) body."""
    return free_spin("near_separatrix", racket_box(), [1e-6, 5.0, 1e-6], t_end=20.0,
                     description="a free box spinning almost exactly about its intermediate axis")


def principal_axis_spin() -> Example:
    """The racket box spun exactly about its (unstable) intermediate axis: ω0 = (0, 5, 0) body."""
    return free_spin("principal_axis_spin", racket_box(), [0.0, 5.0, 0.0], t_end=20.0,
                     description="a free box spinning exactly about its intermediate axis")


def tumbling_box() -> Example:
    """The racket box tumbling about no particular axis: ω0 = (1, 2, 3) body."""
    return free_spin("tumbling_box", racket_box(), [1.0, 2.0, 3.0],
                     description="a free box tumbling about no particular axis")


def sphere() -> Example:
    """A solid ball, m = 1 kg, r = 0.1 m: every axis is principal; ω0 = (1, −2, 3) body."""
    return free_spin("sphere", RigidBody.sphere(1.0, 0.1), [1.0, -2.0, 3.0],
                     description="a ball spinning: its ω stays fixed")


def symmetric_body() -> Example:
    """A disc (cylinder r = 0.1 m, h = 0.02 m, m = 1 kg), two equal moments: ω0 = (1, 0, 30) body."""
    return free_spin("symmetric_body", RigidBody.cylinder(1.0, 0.1, 0.02), [1.0, 0.0, 30.0],
                     description="a free disc spinning about its axis: steady precession")


def light_box() -> Example:
    """The racket box at 1 mg, spun as the tennis racket: ω0 = (0.01, 5, 0.01) body."""
    return free_spin("light_box", racket_box(1e-6), [0.01, 5.0, 0.01],
                     description="a 1 mg box spinning about its intermediate axis: the racket's motion")


def heavy_box() -> Example:
    """The racket box at 1000 t, spun as the tennis racket: ω0 = (0.01, 5, 0.01) body."""
    return free_spin("heavy_box", racket_box(1e6), [0.01, 5.0, 0.01],
                     description="a 1000 t box spinning about its intermediate axis: the racket's motion")


# =====================================================================================
# The hard cases' set-ups with forces: an asymmetric top, springs, a box at rest
# =====================================================================================

def asymmetric_top() -> Example:
    """A heavy top whose body is a box (moments 1 : 2 : 3 about its centre of mass, no symmetry axis),
    pivot 5 cm below the centre of mass along body z, tilted 30° about world x, spinning at
    ω0 = (2, 1, 40) rad/s body, under gravity: chaotic (only the energy and L_z are kept)."""
    body = RigidBody(1.0, [1.0e-3, 2.0e-3, 3.0e-3], name="asymmetric top")
    pivot = Pivot(body_point=(0.0, 0.0, -0.05), world_point=(0.0, 0.0, 0.0))
    R0 = rotation_about_x(np.radians(30.0))
    omega_body = np.array([2.0, 1.0, 40.0])
    X0 = pivot.state(body, R0, R0 @ omega_body)
    scene = Scene(body, [Gravity(), pivot], name="asymmetric heavy top")
    return Example("asymmetric_top", scene, X0, t_end=5.0, dt=1e-3, method="rk4",
                   description="a heavy top with no symmetry axis: chaotic tumbling about the pivot",
                   omega_body=omega_body)


def stiff_spring(k_dt2_over_m: float = 3.9, dt: float = 1e-2) -> Example:
    """A 1 kg ball on a spring k from its centre to the world origin (rest length 0, no gravity, no
    damping), released from x0 = (0.1, 0, 0) with v0 = (0, 1, 0) and a slow spin: a 2-D harmonic
    oscillator, ω = √(k/m), with k Δt²/m = k_dt2_over_m (3.9 at Δt = 1e-2: k = 3.9e4 N/m, ω Δt = 1.97,
    just inside the leapfrog's limit ω Δt < 2)."""
    body = RigidBody.sphere(1.0, 0.05)
    k = k_dt2_over_m * body.mass / dt**2
    scene = Scene(body, [Spring(body_point=(0.0, 0.0, 0.0), world_point=(0.0, 0.0, 0.0), stiffness=k)],
                  name="stiff spring")
    X0 = State.from_velocities(body, [0.1, 0.0, 0.0], np.eye(3), [0.0, 1.0, 0.0], [0.0, 0.0, 1.0])
    return Example("stiff_spring", scene, X0, t_end=10.0, dt=dt, method="splitting",
                   description=f"a ball on a stiff spring: k Δt²/m = {k_dt2_over_m:g} at Δt = {dt:g} s")


def box_at_rest() -> Example:
    """The racket box lying flat on the ground (centre 2.5 cm up, R = I, at rest), under gravity:
    nothing should move (no creep, no energy gained)."""
    from .contact import Ground
    body = racket_box()
    X0 = State.from_velocities(body, [0.0, 0.0, 0.025], np.eye(3), np.zeros(3), np.zeros(3))
    scene = Scene(body, [Gravity(), Ground(height=0.0, restitution=0.0, friction=0.5)], name="box at rest")
    return Example("box_at_rest", scene, X0, t_end=100.0, dt=1e-3, method="rk4",
                   description="a box lying at rest on the floor")


def mass_ratio_pair(ratio: float = 1000.0) -> Example:
    """Two boxes joined by a spring (k = 100 N/m, rest length 0.5 m, from a corner of each), no gravity:
    a heavy one of `ratio` kg and a light one of 1 kg, the light one thrown sideways and spinning;
    total P, total L about the origin and the energy are kept."""
    heavy = RigidBody.box(mass=ratio, size=(0.3, 0.2, 0.05))
    light = RigidBody.box(mass=1.0, size=(0.3, 0.2, 0.05))
    spring = Spring(body_point=(0.15, 0.1, 0.025), stiffness=100.0, rest_length=0.5, body=0,
                    other_body=1, other_point=(-0.15, -0.1, -0.025))
    scene = Scene([heavy, light], [spring], name="mass ratio 1000")
    X0 = State.stack([State.from_velocities(heavy, [0.0, 0.0, 0.0], np.eye(3), [0.01, 0.0, 0.0], [0.0, 0.0, 0.1]),
                      State.from_velocities(light, [0.8, 0.3, 0.0], np.eye(3), [0.0, 1.0, 0.5], [1.0, 2.0, 3.0])])
    return Example("mass_ratio_pair", scene, X0, t_end=10.0, dt=1e-2, method="rk4",
                   description=f"a {ratio:g} kg box and a 1 kg box joined by a spring")


SCENES = {
    "pushed_box": pushed_box,
    "tennis_racket": tennis_racket,
    "box_on_spring": box_on_spring,
    "heavy_top": heavy_top,
    "many_bodies": many_bodies,
    "dropped_box": dropped_box,
}
"""The demos: ``python -m rbcourse demo NAME`` runs SCENES[NAME]()."""

EXAMPLES = {
    **SCENES,
    "fast_spin": fast_spin,
    "thin_disk": thin_disk,
    "slender_rod": slender_rod,
    "near_separatrix": near_separatrix,
    "principal_axis_spin": principal_axis_spin,
    "tumbling_box": tumbling_box,
    "sphere": sphere,
    "symmetric_body": symmetric_body,
    "light_box": light_box,
    "heavy_box": heavy_box,
    "asymmetric_top": asymmetric_top,
    "stiff_spring": stiff_spring,
    "box_at_rest": box_at_rest,
    "mass_ratio_pair": mass_ratio_pair,
}
"""Every named set-up: the demos, and those the benchmarks and the hard cases run."""


def get_scene(name: str) -> Example:
    """SCENES[name]() with a clear error for an unknown name."""
    if name not in SCENES:
        raise ValueError(f"scene must be one of {sorted(SCENES)}, got {name!r}")
    return SCENES[name]()
