"""numba's disk cache of the engine (engine/cache.py): nothing compiled is in the repository, and code loaded from
the cache, without numba's refresh of its compiler, runs the very code a refreshed process runs."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

from rbcourse.engine import jit

ROOT = Path(__file__).resolve().parents[1]
compiled_only = pytest.mark.skipif(not jit.COMPILED, reason=f"the engine is {jit.describe()}")


def test_no_machine_code_is_in_the_repository():
    """Compiled code is build output: numba's *.nbi/*.nbc files are never tracked (.gitignore keeps them out)."""
    done = subprocess.run(["git", "ls-files", "*.nbi", "*.nbc", "rbcourse/engine/compiled"], cwd=ROOT,
                          capture_output=True, text=True)
    if done.returncode != 0:
        pytest.skip("not a git checkout")
    assert done.stdout.split() == []
    ignored = (ROOT / ".gitignore").read_text().split()
    assert "*.nbi" in ignored and "*.nbc" in ignored


DIGEST = """
import hashlib, sys, numpy as np, rbcourse as rb
from rbcourse import rotation
from rbcourse.workbook import warmup
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


@compiled_only
def test_loading_without_numbas_refresh_runs_the_same_code():
    """EngineCache.load_overload skips numba's refresh of its target context (0.3-0.5 s of a fresh process): every
    method on every warm-up scene, and the row functions, give the same bits as in a process refreshed first (which
    compiles what the cache lacks), nothing is compiled in the loading process, and the registries
    (numba.np.arraymath, which imports scipy.linalg) are never imported there."""
    env = dict(os.environ)
    cache = jit.cache_folder()
    out = {}
    for way in ("refreshed", "loaded"):
        before = {p.name: p.stat().st_mtime_ns for p in cache.glob("*.nbc")} if cache else {}
        done = subprocess.run([sys.executable, "-c", DIGEST, way], env=env, cwd=ROOT, capture_output=True, text=True,
                              timeout=1800)
        assert done.returncode == 0, done.stderr
        out[way] = done.stdout.split()
        if way == "loaded" and cache:
            after = {p.name: p.stat().st_mtime_ns for p in cache.glob("*.nbc")}
            assert after == before, f"compiled in the loading process: {sorted(set(after) - set(before))[:10]}"
    assert out["loaded"][0] == out["refreshed"][0]
    assert out["loaded"][1:] == ["False"], out["loaded"]
