"""A read-only install (a shared JupyterHub environment) still caches the compiled engine — in the user's own
folder, ~/.cache/numba/engine_<hash> (numba's user-wide locator) — and keeps it in step with the sources there
(engine.jit: the stamp engine_sources.sha256 beside it).  Run for real: an unprivileged user, a copy of the
package it cannot write, a simulate twice (the second reads the cache: compiles nothing), then an engine source changed
(the stale cache dropped at the next import)."""
import os
import shutil
import stat
import subprocess
import sys
import sysconfig
import tempfile
from pathlib import Path

import pytest

from rbcourse.engine import jit

PACKAGE = Path(__file__).resolve().parents[1] / "rbcourse"
USER = "nobody"
RUN = """
import sys, numpy as np, rbcourse as rb
from numba.core import event
from rbcourse.engine import jit
assert rb.__file__.startswith(sys.argv[1]), rb.__file__
compiles = event.RecordingListener()
event.register("numba:compile", compiles)
b = rb.RigidBody.box(mass=1.0, size=(0.3, 0.2, 0.05))
X0 = rb.State.from_velocities(b, x=np.zeros(3), R=np.eye(3), v=np.zeros(3), omega=[0.01, 5, 0.01])
rb.simulate(b, X0, 0.05, 1e-3, "euler")
print(sum(ev.is_start for _, ev in compiles.buffer), jit.cache_folder())
"""
"""A first simulate as the user: how many functions numba compiled in it, and the engine's cache folder."""


def as_user(python, home, pkg, *args, timeout=240):
    """python *args as USER, HOME=home, the read-only copy first on the path, then this venv's packages."""
    path = os.pathsep.join([str(pkg), sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]])
    env = {"HOME": str(home), "PATH": "/usr/bin:/bin", "PYTHONPATH": path, "PYTHONDONTWRITEBYTECODE": "1"}
    return subprocess.run(["runuser", "-u", USER, "--", "env", "-i", *[f"{k}={v}" for k, v in env.items()],
                           python, *args], capture_output=True, text=True, timeout=timeout, cwd=home)


def interpreter(home, pkg):
    """A Python of this version that USER can run with this venv's packages (this one may live in root's
    folder: then the system's of the same version); None if there is none."""
    here = f"{sys.version_info.major}.{sys.version_info.minor}"
    for python in dict.fromkeys([os.path.realpath(sys.executable), shutil.which(f"python{here}") or "",
                                 f"/usr/bin/python{here}", f"/usr/local/bin/python{here}"]):
        if python and os.path.exists(python):
            probe = as_user(python, home, pkg, "-c", "import numba, numpy, scipy, tqdm", timeout=60)
            if probe.returncode == 0:
                return python
    return None


@pytest.fixture
def readonly(tmp_path_factory):
    """(python, home, the read-only copy's folder): skipped when no unprivileged user can be used."""
    if not jit.COMPILED:
        pytest.skip(f"the engine is not compiled here ({jit.WHY})")
    if os.geteuid() != 0 or not shutil.which("runuser"):
        pytest.skip("needs root (to run as another user: runuser) to test a read-only install for real")
    top = Path(tempfile.mkdtemp(prefix="rbcourse-readonly-"))     # not under pytest's tmp: USER must reach it
    try:
        top.chmod(0o755)
        home, pkg = top / "home", top / "site"
        home.mkdir()
        shutil.chown(home, USER)
        shutil.copytree(PACKAGE, pkg / "rbcourse", ignore=shutil.ignore_patterns("__pycache__", "*.nb?"))
        subprocess.run([sys.executable, "-m", "compileall", "-q", str(pkg)], check=True, capture_output=True)
        python = interpreter(home, pkg)
        if python is None:
            pytest.skip(f"no Python {sys.version_info.major}.{sys.version_info.minor} that user {USER} can run "
                        "with this environment's packages")
        for p in [pkg, *pkg.rglob("*")]:                          # as pip install --target, then chmod -R a-w
            p.chmod(stat.S_IMODE(p.stat().st_mode) & ~0o222)
        yield python, home, pkg
    finally:
        for p in [top, *top.rglob("*")]:
            if not p.is_symlink():
                p.chmod(stat.S_IMODE(p.stat().st_mode) | stat.S_IWUSR)
        shutil.rmtree(top, ignore_errors=True)


def test_a_read_only_install_caches_in_the_users_folder_and_drops_it_when_stale(readonly):
    python, home, pkg = readonly
    engine = pkg / "rbcourse" / "engine"
    runs = []
    for _ in range(2):
        run = as_user(python, home, pkg, "-c", RUN, str(pkg))
        assert run.returncode == 0, run.stderr[-3000:]
        compiled, folder = run.stdout.split()
        runs.append((int(compiled), Path(folder)))
    (cold, folder), (warm, again) = runs
    assert folder == again and folder.parent == home / ".cache" / "numba" and folder.name.startswith("engine_")
    assert not list((engine / "__pycache__").glob("*.nb?"))            # nothing beside the read-only sources
    cached = list(folder.glob("*.nbi"))
    assert cached and list(folder.glob("*.nbc")) and (folder / "engine_sources.sha256").exists()
    assert cold > 0 and warm == 0, (cold, warm)                      # the second run compiled nothing
    engine.chmod(0o755)                                               # the administrator updates the install
    algebra = engine / "algebra.py"
    algebra.chmod(0o644)
    algebra.write_text(algebra.read_text() + "\n# edited\n")
    algebra.chmod(0o444)
    engine.chmod(0o555)
    run = as_user(python, home, pkg, "-c", "import rbcourse.engine.jit")
    assert run.returncode == 0, run.stderr[-3000:]
    assert not list(folder.glob("*.nbi")) and not list(folder.glob("*.nbc"))     # the stale cache dropped
