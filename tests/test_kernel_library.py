"""A kernel function's code is LLVM IR that its compiled callers link, never machine code of its own
(engine/jit.py: KernelLibrary): numba translated it to machine code at every level of calls, and optimised it again
at each.  Seen in fresh processes on an empty numba cache, then on that cache filled: only the loop a run calls from
Python is machine code; a kernel function's library has none, on disk too (bitcode); and the numbers are the same, bit for bit, whether the kernel functions were
compiled in the process or loaded from the disk."""
from pathlib import Path

import pytest

from helpers import probe_report
from rbcourse.engine import jit

pytestmark = pytest.mark.skipif(not jit.COMPILED or not getattr(jit, "KERNEL_LIBRARY", False),
                                reason=f"the engine is {jit.describe()}")

PROBE = """
import json, sys, numpy as np, rbcourse as rb
from rbcourse.engine import contact, grounds, jit, least_norm, motion, run, steps, symmetric
method = sys.argv[1]
body = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
scene = rb.Scene(body, [rb.Gravity(), rb.Ground(height=0.0, restitution=0.2, friction=0.5)])
X0 = rb.State.from_velocities(body, [0.0, 0.0, 0.2], np.eye(3), np.zeros(3), [0.3, 0.5, 0.1])
traj = rb.simulate(scene, X0, 0.3, 1e-3, method)
kernel = {f.py_func.__name__: f for f in (grounds.contacts, contact.resolve_body, contact.impulses,
                                           contact.solve_modes, least_norm.min_norm_solve, symmetric.symmetric_solve,
                                           motion.motion, run.first_bad)}
libraries = {name: [c.library for c in f.overloads.values()] for name, f in kernel.items()}
def translated(lib):   # LLVM made machine code of this library's module (numba's object-code hook kept it)
    return bool(getattr(lib, "_compiled", False) or getattr(lib, "_compiled_object", None))
loop = getattr(run, run.LOOPS[rb.METHODS[method].kernel.family].loop.py_func.__name__).from_python
print(json.dumps({
    "kinds": {name: sorted({type(lib).__name__ for lib in libs}) for name, libs in libraries.items()},
    "machine code": {name: any(translated(lib) for lib in libs) for name, libs in libraries.items()},
    "loaded": {name: f.stats.cache_hits.total() for name, f in kernel.items()},
    "loop": [type(c.library).__name__ for c in loop.overloads.values()],
    "loop's machine code": bool(loop.overloads) and all(translated(c.library) for c in loop.overloads.values()),
    "x": traj.x[-1].tolist(), "L": traj.L[-1].tolist()}))
"""


def probe(cache: Path, method: str) -> dict:
    return probe_report(PROBE, cache, method)


def test_kernel_functions_are_ir_for_their_callers_and_only_the_loop_is_machine_code(tmp_path):
    cold = probe(tmp_path, "euler")
    assert all(kinds == ["KernelLibrary"] for kinds in cold["kinds"].values()), cold["kinds"]
    assert not any(cold["machine code"].values()), cold["machine code"]
    assert cold["loop"] == ["JITCodeLibrary"] and cold["loop's machine code"]    # the loop Python calls
    assert not any(cold["loaded"].values())


def test_a_second_method_links_the_kernel_functions_kept_on_disk_and_computes_the_same_numbers(tmp_path):
    probe(tmp_path / "shared", "euler")                                # fills the cache: euler's loop, the contacts
    warm = probe(tmp_path / "shared", "rk4")                           # links the contact solve read from the disk
    alone = probe(tmp_path / "alone", "rk4")                           # compiles everything itself
    assert warm["loaded"]["contacts"] == 1              # its IR holds the solve's parts: none compiled or read again
    assert warm["kinds"]["contacts"] == ["KernelLibrary"] and warm["kinds"]["resolve_body"] == []
    assert not any(warm["machine code"].values())
    assert (warm["x"], warm["L"]) == (alone["x"], alone["L"])          # bit for bit
    again = probe(tmp_path / "shared", "rk4")                          # the loop itself, now from the disk
    assert (again["x"], again["L"]) == (alone["x"], alone["L"])
