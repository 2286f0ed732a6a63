"""meshcat's script once per notebook (viewer/sharing.py): the first inline view of a kernel carries it beside its
frame, the later ones borrow it through the notebook's page; a saved page always holds its own; a view whose
lender is absent says what to do.  The browser part renders outputs as a notebook's page does (one HTML page, the
outputs one under the other, their scripts run) in headless Chromium."""
import html
import time

import numpy as np
import pytest

pytest.importorskip("meshcat", reason="the viewer needs meshcat (pip install meshcat)")

import rbcourse as rb  # noqa: E402
from rbcourse.support import language  # noqa: E402
from rbcourse.viz import explore, viewer  # noqa: E402
from rbcourse.viz.viewer import assets, sharing  # noqa: E402
from rbcourse.examples import pushed_box  # noqa: E402
from tests.viz.chromium import CHROMIUM, SKIP_REASON, Chromium  # noqa: E402

SCRIPT = assets.viewer_script()[0]          # meshcat's script as the pages carry it (compressed, base 85)


@pytest.fixture(scope="module")
def drawing():
    ex = pushed_box()
    traj = rb.simulate(ex.scene, ex.X0, t_end=3.0, dt=0.01, method="rk4")
    return viewer.draw_trajectory(traj, title="shared view under test", plots=True)


def test_the_first_inline_view_carries_the_script_and_the_second_does_not(drawing):
    first, second = drawing._repr_html_(), drawing._repr_html_()
    assert first.count(SCRIPT) == 1 and SCRIPT not in second
    assert "rbShared(" in html.unescape(second) and "rbcourseMeshcat" not in second.split("</iframe>")[1]
    assert len(first) - len(second) > 0.95 * len(SCRIPT)
    # an explorer shown after it borrows the script too
    ex = explore(pushed_box(), methods=["euler", "rk4"], dts=[0.01], t_end=1.0)
    assert SCRIPT not in ex._repr_html_()


def test_a_saved_page_always_holds_its_script(drawing, tmp_path):
    drawing._repr_html_()                               # the script sent: a page must not care
    for _ in range(2):
        page = drawing.save(tmp_path / "run.html").read_text(encoding="utf-8")
        assert page.count(SCRIPT) == 1 and "rbShared(" not in page.split("function rbShared")[1]


def test_a_restarted_kernel_or_a_rerun_carrying_cell_sends_it_again(drawing, monkeypatch):
    cells = iter(["cell-a", "cell-b", "cell-a"])
    monkeypatch.setattr(sharing, "_cell", lambda: next(cells))
    assert SCRIPT in drawing._repr_html_()              # cell a: the first view
    assert SCRIPT not in drawing._repr_html_()          # cell b borrows it
    assert SCRIPT in drawing._repr_html_()              # cell a again: its old output (and the script) replaced
    sharing.forget()                                    # a new kernel process
    monkeypatch.setattr(sharing, "_cell", lambda: None)
    assert SCRIPT in drawing._repr_html_()


def test_a_page_without_meshcat_is_refused():
    with pytest.raises(ValueError, match="page must be a viewer page"):
        sharing.inline("<html><body>no viewer</body></html>")


def test_the_missing_message_follows_the_language():
    try:
        language.choose("fr")
        assert "ré-exécutez" in sharing.missing_text()
    finally:
        language.choose("en")
    assert "run the first 3-D view's cell again" in sharing.missing_text()


def test_two_views_in_a_notebook_stay_small(drawing):
    """A notebook's two linked views of 3 s: the second a few tens of kB, both well under one view before (~290 kB
    each, the script in both)."""
    first, second = drawing._repr_mimebundle_(), drawing._repr_mimebundle_()
    sizes = [len(b["text/html"]) + len(b["text/plain"]) for b in (first, second)]
    assert sizes[1] < 60_000 and sum(sizes) < 340_000, sizes


# ---- in a browser: the outputs as a notebook's page renders them

pytestmark_browser = pytest.mark.skipif(CHROMIUM is None, reason=SKIP_REASON)


@pytest.fixture(scope="module")
def chromium():
    if CHROMIUM is None:
        pytest.skip(SKIP_REASON)
    browser = Chromium(CHROMIUM)
    yield browser
    browser.close()


def notebook(tmp_path, outputs) -> str:
    path = tmp_path / "notebook.html"
    body = "".join(f'<div class="output">{o}</div>' for o in outputs)
    path.write_text(f'<!DOCTYPE html><html><head><meta charset="utf-8"></head><body style="margin:0">{body}</body>'
                    f'</html>', encoding="utf-8")
    return path.as_uri()


def frames(chromium, n, timeout=20.0):
    deadline = time.monotonic() + timeout
    while len(chromium.frames) < n:
        assert time.monotonic() < deadline, f"{len(chromium.frames)} of {n} frames attached"
        chromium.pump(0.1)
    return list(chromium.frames)[:n]


def wait_for(check, timeout=30.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = check()
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError("timed out")


@pytestmark_browser
def test_the_second_view_boots_from_the_first(chromium, drawing, tmp_path):
    outputs = [drawing._repr_html_(), drawing._repr_html_()]
    assert SCRIPT not in outputs[1]
    chromium.open(notebook(tmp_path, outputs))
    for session in frames(chromium, 2):
        wait_for(lambda: chromium.frame_js("!!(window.viewer && viewer.animator.actions.length && "
                                           "document.querySelector('#meshcat-pane canvas'))", session))
        assert chromium.frame_js("!!document.getElementById('rb-plots').children.length", session)
        assert chromium.frame_js("!document.getElementById('rb-missing')", session)
    assert not chromium.page_errors()


@pytestmark_browser
def test_a_view_whose_lender_is_absent_says_what_to_do(chromium, drawing, tmp_path):
    drawing._repr_html_()                                   # the first view's output: cleared
    chromium.open(notebook(tmp_path, [drawing._repr_html_()]))
    session = frames(chromium, 1)[0]
    text = wait_for(lambda: chromium.frame_js("(document.getElementById('rb-missing') || {}).textContent", session))
    assert text == sharing.missing_text()
    assert chromium.frame_js("!window.viewer && !window.MeshCat", session)


def test_the_cell_is_read_from_jupyterlabs_request(monkeypatch):
    """JupyterLab sends the running cell's id in the execute request's metadata: _cell reads it there."""
    import types

    import IPython
    kernel = types.SimpleNamespace(get_parent=lambda: {"metadata": {"cellId": "c-42"}})
    monkeypatch.setattr(IPython, "get_ipython", lambda: types.SimpleNamespace(kernel=kernel))
    assert sharing._cell() == "c-42"
    monkeypatch.setattr(IPython, "get_ipython", lambda: None)
    assert sharing._cell() is None
