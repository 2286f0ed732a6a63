"""Helper of tests/test_engine.py, run in a subprocess with NUMBA_DISABLE_JIT=1 (the engine interpreted).

    python tests/engine_interpreted_check.py runs OUT.npz    the interpreted runs of test_engine.INTERPRETED_CASES
    python tests/engine_interpreted_check.py calls OUT.json  force-code calls of a free-body and a gravity run

It imports its scenes from test_engine.py (one definition of each scene, shared with the compiled runs).
"""
import json
import os
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))

import rbcourse as rb  # noqa: E402
import rbcourse.engine  # noqa: E402
from rbcourse.engine import motion, quaternion, stages  # noqa: E402
import test_engine as te  # noqa: E402


def header() -> dict:
    return {"IMPLEMENTATION": rbcourse.engine.IMPLEMENTATION,
            "NUMBA_DISABLE_JIT": os.environ.get("NUMBA_DISABLE_JIT", "")}


def runs(out: str):
    arrays, info = {}, header()
    for name, method in te.INTERPRETED_CASES:
        scene, X0 = te.CASES[name]()
        traj = rb.simulate(scene, X0, te.INTERPRETED_STEPS * te.DT, te.DT, method)
        for k in ("t", "x", "R", "P", "L"):
            arrays[f"{name}|{method}|{k}"] = getattr(traj, k)
        info[f"{name}|{method}|implementation"] = traj.implementation
    np.savez(out, **arrays)
    Path(out).with_suffix(".json").write_text(json.dumps(info))


def calls(out: str):
    """Count calls of the force code (motion.effect_on, effect_on_body, resultants, body_resultants) by patching
    the module globals (their callers read those globals at call time when interpreted)."""
    counts = {"effect_on": 0, "effect_on_body": 0, "resultants": 0, "body_resultants": 0}

    def counting(name):
        original = getattr(motion, name)

        def wrapper(*args, **kwargs):
            counts[name] += 1
            return original(*args, **kwargs)
        for module in (motion, quaternion, stages):  # each module that calls it by its own global name
            if getattr(module, name, None) is original:
                setattr(module, name, wrapper)

    for name in counts:
        counting(name)
    result = header()
    X0 = rb.State.from_velocities(te.BOX, x=(0.0, 0.0, 1.0), R=np.eye(3), v=(0.1, 0.0, 0.2), omega=(0.3, 2.0, 0.5))
    for label, scene in (("free", rb.Scene(te.BOX)), ("gravity", rb.Scene(te.BOX, [rb.Gravity()])),
                         ("drag", rb.Scene(te.BOX, [rb.LinearDrag(0.3)]))):
        for k in counts:
            counts[k] = 0
        traj = rb.simulate(scene, X0, 20 * te.DT, te.DT, "rk4")
        result[label] = dict(counts)
        result[f"{label}|implementation"] = traj.implementation
    Path(out).write_text(json.dumps(result))


if __name__ == "__main__":
    {"runs": runs, "calls": calls}[sys.argv[1]](sys.argv[2])
