"""A run compiles only what its scene calls for (engine/run.py: one loop per method, given its step; the contact
solve, the kicks and the forces pruned by type): in a fresh process on an empty numba cache, a free body's run
compiles no contact solve, no kick and no force code, a box under gravity compiles the forces and still no contact
solve and no kick, only a scene with a Ground compiles the contact solve, and only a scene with an Impulse the
kicks' walk — seen from the kernel functions numba compiled in the process, and from the functions named in the
LLVM IR of the run's loop."""
import re

import pytest

from helpers import probe_report
from rbcourse.engine import jit

pytestmark = pytest.mark.skipif(not jit.COMPILED, reason=f"the engine is {jit.describe()}")

PROBE = """
import json, sys, numpy as np, rbcourse as rb
from rbcourse.engine import contact, grounds, kicks, least_norm, motion, run, stages, symmetric
body = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
X0 = rb.State.from_velocities(body, [0, 0, 0.2], np.eye(3), np.zeros(3), [0.01, 5.0, 0.01])
scenes = {"free": body, "gravity": rb.Scene(body, [rb.Gravity()]),
          "ground": rb.Scene(body, [rb.Gravity(), rb.Ground()]),
          "impulse": rb.Scene(body, [rb.Impulse((0.1, 0, 0), (0, 0, 1.0), 0.0055)])}
watched = {"contact solve": [grounds.contacts, contact.resolve_body, contact.impulses, least_norm.min_norm_solve,
                             symmetric.symmetric_solve],
           "forces": [motion.resultants, motion.effect_on, motion.effect_on_body],
           "kicks": [run.split_step, kicks.first_kick, kicks.kick_state, kicks.in_order, motion.kick,
                     run.encode_matrix],
           "other methods' steps": [stages.rk_stages_lanes, run.run_explicit_quat, run.run_splitting]}
seen = {}
loops = run.run_euler.from_python.overloads          # the named loop, as the driver calls it
for name in sys.argv[1].split(","):
    before = set(loops)
    rb.simulate(scenes[name], X0, 0.01, 1e-3, "euler")
    seen[name] = {part: sorted(f.py_func.__name__ for f in fs if f.overloads) for part, fs in watched.items()}
    seen[name]["loop's IR"] = [loops[sig].library.get_llvm_str() for sig in set(loops) - before]
print(json.dumps(seen))
"""


def ir_functions(ir: str) -> set:
    """The engine's functions named in an LLVM IR text: 'module.function' of each mangled _ZN8rbcourse6engine…
    name (its length-prefixed parts)."""
    found = set()
    for m in re.finditer(r"_ZN8rbcourse6engine", ir):
        rest, parts = ir[m.end():], []
        for _ in range(2):
            size = re.match(r"\d+", rest)
            k = int(size.group())
            parts.append(rest[size.end():size.end() + k])
            rest = rest[size.end() + k:]
        found.add(".".join(parts))
    return found


def compiled(tmp_path, scenes: str) -> dict:
    return probe_report(PROBE, tmp_path, scenes)


def test_a_free_body_compiles_no_contact_solve_no_kick_and_no_forces_a_ground_and_an_impulse_do(tmp_path):
    seen = compiled(tmp_path, "free,gravity,ground,impulse")
    ir = {name: [ir_functions(text) for text in seen[name].pop("loop's IR")] for name in seen}
    assert seen["free"] == {"contact solve": [], "forces": [], "kicks": [], "other methods' steps": []}
    assert seen["gravity"]["contact solve"] == [] and seen["gravity"]["forces"] == ["effect_on", "effect_on_body",
                                                                                     "resultants"]
    assert seen["gravity"]["kicks"] == [] and seen["ground"]["kicks"] == []
    assert seen["ground"]["contact solve"] == ["contacts", "impulses", "min_norm_solve", "resolve_body",
                                               "symmetric_solve"]
    assert seen["ground"]["other methods' steps"] == []
    assert seen["impulse"]["kicks"] == ["encode_matrix", "first_kick", "in_order", "kick", "kick_state",
                                        "split_step"]
    # each run compiled its own loop, whose IR names the engine's functions it holds
    assert [len(ir[name]) for name in ir] == [1, 1, 1, 1]
    kick_parts = {"run.split_step", "kicks.first_kick", "kicks.kick_state", "kicks.in_order", "motion.kick",
                  "run.encode_matrix"}
    contact_parts = {"grounds.contacts", "contact.resolve_body"}
    for name in ("free", "gravity"):
        assert "run.loop" in ir[name][0] and not ir[name][0] & (kick_parts | contact_parts), name
    assert contact_parts <= ir["ground"][0] and not ir["ground"][0] & kick_parts
    assert kick_parts <= ir["impulse"][0] and not ir["impulse"][0] & contact_parts
