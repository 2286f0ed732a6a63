"""The public contract (../shared/DESIGN.md, last section): every fixed name imports from `rbcourse`
and does what the contract's example says.

Also a script: `.ci/wheel_check.sh` runs `python tests/test_public_contract.py` with a venv that holds
only the built wheel, from a folder outside the checkout, so the installed package is what is checked
(an editable install would hide a subpackage missing from the wheel).
"""
from __future__ import annotations

import importlib

import numpy as np

# every name the contract fixes, and the modules behind them (a subpackage missing from a wheel fails here)
NAMES = ["RigidBody", "State", "Scene", "simulate", "Trajectory", "Gravity", "PointForce", "Pivot", "Spring",
         "Ground", "SimulationDiverged", "METHODS", "exact_free_body", "walkthrough"]
METHOD_NAMES = ["euler", "euler_project", "quaternion_euler", "symplectic_euler", "implicit_gyro",
                "implicit_midpoint", "splitting", "rk4", "rkmk4", "adaptive", "exact_splitting"]
COMMANDS = ["demo", "bench", "stability", "throughput"]


def test_every_contract_name_imports():
    rb = importlib.import_module("rbcourse")
    missing = [n for n in NAMES if not hasattr(rb, n)]
    assert not missing, f"rbcourse lacks the contract's names {missing}"
    assert set(METHOD_NAMES) <= set(rb.METHODS), f"METHODS lacks {sorted(set(METHOD_NAMES) - set(rb.METHODS))}"
    for name in METHOD_NAMES:
        assert isinstance(rb.METHODS[name].order, int) and rb.METHODS[name].keeps is not None


def test_every_module_imports():
    import pkgutil

    rb = importlib.import_module("rbcourse")
    failed = []
    for info in pkgutil.walk_packages(rb.__path__, prefix="rbcourse."):
        if info.name.endswith("__main__"):
            continue
        try:
            importlib.import_module(info.name)
        except Exception as err:                       # noqa: BLE001 — report every module that fails
            failed.append(f"{info.name}: {type(err).__name__}: {err}")
    assert not failed, "modules that do not import:\n" + "\n".join(failed)


def test_the_contract_example_runs():
    import rbcourse as rb

    body = rb.RigidBody(mass=2.0, inertia=[1.0, 2.0, 3.0])
    body = rb.RigidBody.box(mass=1.0, size=(0.3, 0.2, 0.05))
    assert isinstance(body.mass, float) and body.I_body.shape == (3, 3) and body.I_body_inv.shape == (3, 3)
    X0 = rb.State(x=np.zeros(3), R=np.eye(3), P=np.zeros(3), L=np.zeros(3))
    X0 = rb.State.from_velocities(body, x=np.zeros(3), R=np.eye(3), v=np.zeros(3), omega=[0.01, 5.0, 0.01])
    scene = rb.Scene(body, effects=[rb.Gravity()])
    assert isinstance(scene.describe(), str)
    traj = rb.simulate(scene, X0, t_end=0.2, dt=1e-3, method="rk4")
    n = len(traj.t)
    assert traj.t.shape == (n,) and traj.x.shape == (n, 3) and traj.R.shape == (n, 3, 3)
    assert traj.P.shape == (n, 3) and traj.L.shape == (n, 3)
    assert traj.kinetic_energy().shape == (n,) and traj.angular_momentum().shape == (n, 3)
    free = rb.simulate(body, X0, t_end=0.2, dt=1e-3, method="rk4")     # a bare RigidBody: a free body
    exact = rb.exact_free_body(body, X0, free.t)
    assert np.abs(free.R - exact.R).max() < 1e-9
    recs = rb.walkthrough(body, rb.State.at_rest(), forces=[((0.15, 0.1, 0.025), (0, 0, 10.0))], dt=0.01,
                          iterations=2)
    assert len(recs) == 2 and "Itération 1" in str(recs[0])
    for name in ("PointForce", "Pivot", "Spring", "Ground"):
        assert callable(getattr(rb, name))
    assert issubclass(rb.SimulationDiverged, Exception)


def test_the_command_line_lists_its_commands():
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-m", "rbcourse", "--help"], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    missing = [c for c in COMMANDS if c not in out.stdout]
    assert not missing, f"python -m rbcourse --help does not list {missing}"


def test_import_loads_neither_scipy_special_nor_scipy_integrate():
    """rbcourse.exact (and scipy.special) load at the first exact use; the public names still work."""
    import subprocess
    import sys
    code = ("import sys, numpy as np, rbcourse as rb\n"
            "for m in ('scipy.special', 'scipy.integrate', 'rbcourse.exact.free_body', 'rbcourse.exact.flow'):\n"
            "    assert m not in sys.modules, m + ' imported by import rbcourse'\n"
            "assert 'exact_free_body' in dir(rb) and 'exact_free_body' in rb.__all__\n"
            "body = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))\n"
            "X0 = rb.State.from_velocities(body, np.zeros(3), np.eye(3), np.zeros(3), [0.3, 0.2, 1.0])\n"
            "traj = rb.simulate(body, X0, 0.1, 0.01, 'exact_splitting')\n"
            "assert 'scipy.special' not in sys.modules   # the engine has its own elliptic functions\n"
            "from rbcourse import exact_free_body\n"
            "from rbcourse.exact import FreeRotationFlow, free_rotation_flow, exact_free_body as same\n"
            "assert exact_free_body is rb.exact_free_body is same\n"
            "assert abs(exact_free_body(body, X0, traj.t).R - traj.R).max() < 1e-9\n"
            "assert 'scipy.special' in sys.modules        # the exact solution, the independent reference, uses scipy's\n"
            "try:\n"
            "    rb.exact.nothing\n"
            "except AttributeError:\n"
            "    pass\n"
            "else:\n"
            "    raise AssertionError('rb.exact.nothing')\n")
    subprocess.run([sys.executable, "-c", code], check=True)      # from the current folder: the wheel check runs it outside the checkout


if __name__ == "__main__":          # the wheel check: run every test here, without pytest
    import sys

    import rbcourse

    print(f"checking the installed package at {rbcourse.__file__}")
    failures = 0
    for name, fn in list(globals().items()):
        if name.startswith("test_") and callable(fn):
            try:
                fn()
                print(f"ok   {name}")
            except Exception as err:                   # noqa: BLE001
                failures += 1
                print(f"FAIL {name}: {type(err).__name__}: {err}")
    sys.exit(1 if failures else 0)
