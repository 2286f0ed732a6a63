"""Each test starts as a fresh kernel would: no inline view has sent meshcat's script yet (viewer/sharing.py),
so a test's first inline view carries it, whatever ran before."""
import pytest


@pytest.fixture(autouse=True)
def fresh_kernel():
    try:
        from rbcourse.viz.viewer import sharing
    except ImportError:                 # no meshcat: the tests that need it skip themselves
        yield
        return
    sharing.forget()
    yield
    sharing.forget()
