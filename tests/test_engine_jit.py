"""The switch between compiled and interpreted, and the disk cache kept in step with the sources."""
import rbcourse as rb
from rbcourse.engine import jit


def test_the_implementation_is_named_with_its_reason():
    assert jit.IMPLEMENTATION in ("compiled", "interpreted")
    assert jit.describe().startswith(jit.IMPLEMENTATION + ": ")
    assert jit.COMPILED == (jit.IMPLEMENTATION == "compiled")


def test_a_stale_cache_is_dropped_when_any_engine_source_changes(tmp_path):
    """numba checks only a function's own file; the engine drops its whole cache when any source changes."""
    (tmp_path / "motion.py").write_text("k = 1\n")
    (tmp_path / "steps.py").write_text("from .motion import k\n")
    jit._drop_stale_cache(tmp_path)                       # first time: no stamp yet
    cache = jit.cache_folder(tmp_path)                    # tmp_path/__pycache__, or under NUMBA_CACHE_DIR if set
    compiled = [cache / "steps.step-1.py311.nbi", cache / "steps.step-1.py311.1.nbc"]
    for f in compiled:
        f.write_bytes(b"machine code")
    jit._drop_stale_cache(tmp_path)                       # nothing changed: kept
    assert all(f.exists() for f in compiled)
    (tmp_path / "motion.py").write_text("k = 2\n")        # a callee edited in another file
    jit._drop_stale_cache(tmp_path)
    assert not any(f.exists() for f in compiled)
    assert (cache / "engine_sources.sha256").exists()


def test_a_compiled_run_says_so():
    body = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
    X0 = rb.State.from_velocities(body, [0, 0, 0], [[1, 0, 0], [0, 1, 0], [0, 0, 1]], [0, 0, 0], [1.0, 2.0, 3.0])
    traj = rb.simulate(body, X0, 0.1, 0.01, "rk4")
    assert traj.implementation == jit.describe()
    assert "Implementation: " + jit.describe() in traj.describe()
    assert rb.simulate(body, X0, 0.1, 0.01, "rk4", fast=False).implementation.startswith("interpreted (fast=False)")


def test_ctrl_c_is_held_back_while_compiled_code_runs_and_raised_after():
    """A KeyboardInterrupt inside numba's compiler kills the process (a segmentation fault, seen in CI):
    the driver holds Ctrl-C back during its compiled calls and raises it between them."""
    import os
    import signal
    import pytest
    from rbcourse.forcing import deferred_interrupt
    reached = []
    with pytest.raises(KeyboardInterrupt):
        with deferred_interrupt() as held:
            os.kill(os.getpid(), signal.SIGINT)       # "inside a compiled call": not raised here
            reached.append("after the signal")
            held.check()                                # between two calls: raised now
            reached.append("not reached")
    assert reached == ["after the signal"]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler     # Python's handler is back
    with pytest.raises(KeyboardInterrupt):
        with deferred_interrupt():
            os.kill(os.getpid(), signal.SIGINT)
            reached.append("the block ends")            # raised at the end of the block
    assert reached[-1] == "the block ends"
