"""The machine code the package ships (rbcourse/engine/compiled/, engine/machine_code.py): built from the
engine's sources as they are, and used — a fresh process with an empty numba cache compiles nothing."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

from rbcourse.engine import jit

ROOT = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.skipif(not jit.COMPILED, reason=f"the engine is {jit.describe()}")

RUNS = """
import numpy as np, rbcourse as rb
from rbcourse import warmup
for name, scene, X in warmup.scenes():
    for method in rb.METHODS:
        try:
            rb.simulate(scene, X, 0.02, 1e-3, method, on_divergence="stop")
        except ValueError:
            pass                     # a method that refuses a scene: refused before anything compiles
print("ran")
"""


def test_the_shipped_machine_code_is_built_from_the_sources_as_they_are():
    """After any change to rbcourse/engine/, `python -m rbcourse compile --ship` builds it again."""
    from rbcourse.engine import machine_code as mc
    stamp = (mc.SHIPPED / mc.STAMP).read_text().strip() if (mc.SHIPPED / mc.STAMP).exists() else "none"
    assert stamp == mc.sources_digest(), ("rbcourse/engine/compiled/ was built from other engine sources: "
                                          "run `python -m rbcourse compile --ship` and commit the folder")
    assert list(mc.SHIPPED.glob("*.nbc")) and list(mc.SHIPPED.glob("*.nbi"))


def test_a_fresh_process_on_an_empty_cache_compiles_nothing(tmp_path):
    """Every method on every warm-up scene, in a process whose numba cache is empty: all loaded from the shipped
    machine code (this platform and CPython are the ones it was built on), no notice, nothing written."""
    from rbcourse.engine import machine_code as mc
    if not mc.shipped_is_current():
        pytest.fail("rbcourse/engine/compiled/ is stale: run `python -m rbcourse compile --ship`")
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    env.pop("NUMBA_CPU_NAME", None)
    done = subprocess.run([sys.executable, "-c", RUNS], env=env, cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert "compiling the engine" not in done.stderr, done.stderr
    compiled = sorted(p.name for p in tmp_path.rglob("*.nbc"))
    assert not compiled, f"compiled in the process, not loaded from the shipped code: {compiled[:10]}"


DIGEST = """
import hashlib, sys, numpy as np, rbcourse as rb
from rbcourse import rotation, warmup
if sys.argv[1] == "refreshed":                  # numba's own way: every registry installed before any load
    from numba.core.registry import cpu_target
    cpu_target.target_context.refresh()
h = hashlib.sha256()
for name, scene, X in warmup.scenes():
    for method in rb.METHODS:
        try:
            tr = rb.simulate(scene, X, 0.02, 1e-3, method, on_divergence="stop")
        except ValueError:
            continue
        for a in (tr.t, tr.x, tr.R, tr.P, tr.L, tr.kinetic_energy(), tr.potential_energy(),
                  rotation.quat_from_matrix(tr.R), rotation.orthonormalize(tr.R * 1.001)):
            h.update(np.ascontiguousarray(a).tobytes())
print(h.hexdigest(), "numba.np.arraymath" in sys.modules)
"""


def test_loading_without_numbas_refresh_runs_the_same_code(tmp_path):
    """EngineCache.load_overload skips numba's refresh of its target context (0.3-0.5 s of a fresh process): every
    method on every warm-up scene, and the row functions, give the same bits as in a process refreshed first, and
    the registries (numba.np.arraymath, which imports scipy.linalg) are never imported."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    env.pop("NUMBA_CPU_NAME", None)
    out = {}
    for way in ("loaded", "refreshed"):
        done = subprocess.run([sys.executable, "-c", DIGEST, way], env=env, cwd=ROOT, capture_output=True, text=True,
                              timeout=600)
        assert done.returncode == 0, done.stderr
        out[way] = done.stdout.split()
        if way == "loaded":
            compiled = sorted(p.name for p in tmp_path.rglob("*.nbc"))
            assert not compiled, f"compiled in the process, not loaded from the shipped code: {compiled[:10]}"
    assert out["loaded"][0] == out["refreshed"][0]
    assert out["loaded"][1:] == ["False"], out["loaded"]


def test_the_shipped_code_is_used_only_on_a_processor_that_runs_its_level(monkeypatch):
    """x86-64-v3 code (AVX2, FMA, BMI…) on a processor without one of its features would stop the process on an
    illegal instruction: there numba compiles for the processor instead."""
    from rbcourse.engine import machine_code as mc
    assert mc.host_runs_level(mc.LEVEL_FEATURES | {"avx512f"})
    for missing in ("avx2", "fma", "bmi2", "movbe"):
        assert not mc.host_runs_level(mc.LEVEL_FEATURES - {missing}), missing
    assert not mc.host_runs_level({"sse2", "sse4.2", "popcnt"})          # a generic x86-64 of 2008
    monkeypatch.setattr(mc, "host_runs_level", lambda features=None: False)
    mc.shipped_is_current.cache_clear()
    try:
        assert not mc.shipped_is_current()
    finally:
        mc.shipped_is_current.cache_clear()
