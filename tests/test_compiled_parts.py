"""A run compiles only what its scene calls for (engine/run.py: one loop per method, given its step; the contact
solve and the forces pruned by type): in a fresh process on an empty numba cache, a free body's run compiles no
contact solve and no force code, a box under gravity compiles the forces and still no contact solve, and only a
scene with a Ground compiles the contact solve — seen from the kernel functions numba compiled in the process."""
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from rbcourse.engine import jit

ROOT = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.skipif(not jit.COMPILED, reason=f"the engine is {jit.describe()}")

PROBE = """
import json, sys, numpy as np, rbcourse as rb
from rbcourse.engine import contact, grounds, least_norm, motion, run, stages, symmetric
body = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
X0 = rb.State.from_velocities(body, [0, 0, 0.2], np.eye(3), np.zeros(3), [0.01, 5.0, 0.01])
scenes = {"free": body, "gravity": rb.Scene(body, [rb.Gravity()]),
          "ground": rb.Scene(body, [rb.Gravity(), rb.Ground()])}
watched = {"contact solve": [grounds.contacts, contact.resolve_body, contact.impulses, least_norm.min_norm_solve,
                             symmetric.symmetric_solve],
           "forces": [motion.resultants, motion.effect_on, motion.effect_on_body],
           "other methods' steps": [stages.rk_stages_lanes, run.run_explicit_quat, run.run_splitting]}
seen = {}
for name in sys.argv[1].split(","):
    rb.simulate(scenes[name], X0, 0.01, 1e-3, "euler")
    seen[name] = {part: sorted(f.py_func.__name__ for f in fs if f.overloads) for part, fs in watched.items()}
print(json.dumps(seen))
"""


def compiled(tmp_path, scenes: str) -> dict:
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    done = subprocess.run([sys.executable, "-c", PROBE, scenes], env=env, cwd=ROOT, capture_output=True, text=True,
                          timeout=900)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_a_free_body_compiles_no_contact_solve_and_no_forces_a_ground_does(tmp_path):
    seen = compiled(tmp_path, "free,gravity,ground")
    assert seen["free"] == {"contact solve": [], "forces": [], "other methods' steps": []}
    assert seen["gravity"]["contact solve"] == [] and seen["gravity"]["forces"] == ["effect_on", "effect_on_body",
                                                                                     "resultants"]
    assert seen["ground"]["contact solve"] == ["contacts", "impulses", "min_norm_solve", "resolve_body",
                                               "symmetric_solve"]
    assert seen["ground"]["other methods' steps"] == []
