import os

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")

from hypothesis import HealthCheck, settings  # noqa: E402

# derandomize: the same examples on every run, so a test that passes in CI passes again (a flaky test is a
# failing test); explore with other seeds by hand: pytest --hypothesis-profile=explore --hypothesis-seed=N
settings.register_profile("ci", max_examples=60, deadline=None, derandomize=True,
                          suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("explore", max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("ci")


def pytest_sessionfinish(session, exitstatus):
    """No meshcat server may outlive the test session (notebooks, demo and viewer tests alike)."""
    import sys
    viewer = sys.modules.get("rbcourse.viz.viewer")
    if viewer is None:
        return
    left = viewer.live_server_pids()
    if left:
        viewer.close_live_server()
        print(f"\nERROR: meshcat server process(es) {left} were left running by the tests")
        session.exitstatus = 1


# long runs (hard cases, notebooks) are shortened under test; `python -m rbcourse stability` runs them in full
os.environ.setdefault("RBCOURSE_QUICK", "1")


@pytest.fixture
def french():
    """The workbook in French for one test (rbcourse.workbook.langue("fr")), then the language it had."""
    from rbcourse.workbook import current, langue
    before = current()
    langue("fr")
    yield
    langue(before)
