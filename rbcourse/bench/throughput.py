"""What a scene's effects cost, and how many bodies per second the engine steps.

    python -m rbcourse throughput [--bodies 10000] [--quick] [--no-peers] [--out DIR]

Table 1: µs per step for one body and for N bodies, free and with each effect added
(gravity, spring, ground), beside the bare integrator (the library's RK4 step called in a
plain loop, no simulate around it): a free scene should cost ≤ 1.1× the bare integrator.
Table 2: ns per body-step for N free bodies, a 4th-order and a first-order method, and
MuJoCo (one model of 1000 free boxes, no contacts) in the same run when installed.
"""
from __future__ import annotations

import time

import numpy as np

from .. import checks
from ..body import RigidBody
from ..effects import Gravity, Spring
from ..integrators import METHODS
from ..scene import Scene
from ..simulate import simulate
from ..state import State

MAX_BODIES = 10**6      # the runs build N Python bodies and states (five times) before stepping them as arrays:
#                         beyond 10⁶ that setup alone takes many minutes and gigabytes, and 10⁴ already gives the
#                         cost per body-step


def boxes(n: int, seed: int = 0):
    """n random boxes with random spins, on a grid 1 m up: bodies and their stacked State."""
    rng = np.random.default_rng(seed)
    bodies = [RigidBody.box(float(rng.uniform(0.5, 2.0)), rng.uniform(0.05, 0.3, 3)) for _ in range(n)]
    states = [State.from_velocities(b, [i % 100, i // 100, 1.0], np.eye(3), rng.normal(0, 0.1, 3), rng.normal(0, 3, 3))
              for i, b in enumerate(bodies)]
    return bodies, (states[0] if n == 1 else State.stack(states))


def effect_sets():
    """The scenes of table 1: free, and each effect added."""
    sets = {"free": [], "+ gravity": [Gravity()],
            "+ gravity + spring": [Gravity(), Spring((0.02, 0, 0), (0, 0, 2), stiffness=20.0, damping=0.1)]}
    try:
        from ..contact import Ground
        sets["+ gravity + ground"] = [Gravity(), Ground(height=0.0, restitution=0.5, friction=0.5)]
    except ImportError:
        pass
    return sets


def seconds_per_step(scene, X0, method: str, steps: int, dt: float = 1e-3, fast: bool = True, repeats: int = 3) -> float:
    """Median wall time of one step: a run of 2k steps minus a run of k steps, over k (no start-up cost)."""
    def run(k):
        t0 = time.perf_counter()
        simulate(scene, X0, k * dt, dt, method, record_every=k, fast=fast)
        return time.perf_counter() - t0
    return float(np.median([(run(2 * steps) - run(steps)) / steps for _ in range(repeats)]))


def bare_rk4_seconds(scene, X0, steps: int, dt: float = 1e-3, repeats: int = 3) -> float:
    """The bare integrator: the library's own RK4 step (METHODS["rk4"]) called in a plain loop on the
    method's state, Y ← step(scene, t, Y, dt) — no simulate around it (no input checks, no recording,
    no divergence check, no float kernel).  Median wall time of one step."""
    method = METHODS["rk4"]
    Y0 = method.encode(scene, scene.to_engine(X0))
    prep = method.prepare(scene)            # what the method precomputes for a run (once, as simulate does)
    times = []
    for _ in range(repeats):
        Y = Y0
        t0 = time.perf_counter()
        for k in range(steps):
            Y = method(scene, k * dt, Y, dt, prep)
        times.append((time.perf_counter() - t0) / steps)
    return float(np.median(times))


def mujoco_ns_per_body_step(n: int, integrator: str, steps: int):
    """MuJoCo: one model of n free boxes, no contacts, no gravity; ns per body-step (None if not installed)."""
    try:
        import mujoco
    except ImportError:
        return None
    body = ('<body pos="{x} {y} 1"><freejoint/><geom type="box" size="0.1 0.05 0.02" contype="0" conaffinity="0" '
            'mass="1"/></body>')
    xml = (f'<mujoco><size memory="{max(64, n // 4)}M"/><option gravity="0 0 0" integrator="{integrator}" '
           f'timestep="0.001"/><worldbody>' + "".join(body.format(x=i % 100, y=i // 100) for i in range(n))
           + "</worldbody></mujoco>")
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    data.qvel[:] = np.random.default_rng(0).normal(0, 1, model.nv)
    mujoco.mj_step(model, data, nstep=2)
    t0 = time.perf_counter()
    mujoco.mj_step(model, data, nstep=steps)
    return (time.perf_counter() - t0) / steps / n * 1e9


def main(n: int = 10000, quick: bool = False, peers: bool = True) -> str:
    """Measure both tables; return them as markdown.  n: bodies of the many-body runs, 2 … MAX_BODIES."""
    n = checks.integer("n", n, low=2, high=MAX_BODIES)
    for name, flag in (("quick", quick), ("peers", peers)):
        if not isinstance(flag, bool):
            raise ValueError(f"{name} must be True or False, got {flag!r}")
    steps_one, steps_many = (200, 3) if quick else (2000, 20)
    out = ["# Throughput", "", "## What each effect costs (RK4, dt = 1 ms; µs per step)", "",
           f"| scene | 1 body, numpy | 1 body, float kernel | {n} bodies (µs per body-step) |", "|---|---|---|---|"]
    for name, effects in effect_sets().items():
        b1, X1 = boxes(1)
        s1 = Scene(b1[0], effects)
        bn, Xn = boxes(n)
        sn = Scene(bn, effects)
        numpy_one = seconds_per_step(s1, X1, "rk4", steps_one, fast=False) * 1e6
        from ..integrators import kernels
        kern = (f"{seconds_per_step(s1, X1, 'rk4', steps_one) * 1e6:.3g}" if kernels.available(METHODS["rk4"], s1)
                else "—")
        many = seconds_per_step(sn, Xn, "rk4", steps_many) * 1e6 / n
        out.append(f"| {name} | {numpy_one:.3g} | {kern} | {many:.3g} |")
    b1, X1 = boxes(1)
    bn, Xn = boxes(n)
    bare1 = bare_rk4_seconds(Scene(b1[0]), X1, steps_one)
    baren = bare_rk4_seconds(Scene(bn), Xn, steps_many)
    free1 = seconds_per_step(Scene(b1[0]), X1, "rk4", steps_one, fast=False)
    freen = seconds_per_step(Scene(bn), Xn, "rk4", steps_many)
    out += ["", "Free scene against the bare integrator (the RK4 step in a plain loop, no simulate): "
            f"1 body {free1 * 1e6:.3g} vs {bare1 * 1e6:.3g} µs = {free1 / bare1:.2f}×; "
            f"{n} bodies {freen * 1e3:.3g} vs {baren * 1e3:.3g} ms = {freen / baren:.2f}×.", "",
            "## Many free bodies (ns per body-step)", "", "| engine | method | order | N | ns per body-step |",
            "|---|---|---|---|---|"]
    for method in ("rk4", "quaternion_euler", "symplectic_euler", "euler"):
        ns = seconds_per_step(Scene(bn), Xn, method, steps_many) / n * 1e9
        out.append(f"| rbcourse | {method} | {METHODS[method].order} | {n} | {ns:.0f} |")
    if peers:
        for integrator, order in (("Euler", 1), ("RK4", 4)):
            ns = mujoco_ns_per_body_step(1000, integrator, steps_many * 5)
            if ns is not None:
                out.append(f"| MuJoCo | {integrator} | {order} | 1000 | {ns:.0f} |")
    return "\n".join(out) + "\n"
