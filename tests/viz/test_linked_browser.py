"""The linked view in a real browser (draw_trajectory(..., plots=True)): meshcat's scene above, the drift plots
under it, one time cursor.  Opened at two times (#t=), the box and the plots' cursor both move; a click on a plot
moves the 3-D scene there; nothing is fetched; the page stays within 300 kB."""
import time

import numpy as np
import pytest

pytest.importorskip("meshcat", reason="the viewer needs meshcat (pip install meshcat)")
from tests.viz.chromium import CHROMIUM, SKIP_REASON  # noqa: E402
from tests.viz.test_browser import chromium  # noqa: E402,F401  (the fixture: one headless Chromium per module)

import rbcourse as rb  # noqa: E402
from rbcourse.rotation import quat_from_matrix, project_so3  # noqa: E402
from rbcourse.viz import viewer  # noqa: E402
from rbcourse.examples import get_scene  # noqa: E402

pytestmark = pytest.mark.skipif(CHROMIUM is None, reason=SKIP_REASON)

BODY_QUATERNION = ('(() => { const q = viewer.scene_tree.find(["meshcat", "bodies", "0"]).object.quaternion;'
                   ' return [q.w, q.x, q.y, q.z]; })()')
CURSORS = 'Array.from(document.querySelectorAll("#rb-panels canvas")).map(c => Number(c.dataset.cursorX))'


@pytest.fixture(scope="module")
def linked(tmp_path_factory):
    ex = get_scene("tennis_racket")
    euler = rb.simulate(ex.scene, ex.X0, 4.0, 0.002, "euler", on_divergence="stop")
    rk4 = rb.simulate(ex.scene, ex.X0, 4.0, 0.002, "rk4")
    exact = rb.exact_free_body(ex.scene.bodies[0], ex.X0, euler.t)
    d = viewer.draw_trajectory([euler, rk4], ghost=exact, ghost_label="exact motion", plots=True)
    return euler, d, d.save(tmp_path_factory.mktemp("linked") / "linked.html")


def _settle(chromium, seconds=0.6):
    time.sleep(seconds)                    # a few animation frames: the plots follow the animator
    return chromium.js(BODY_QUATERNION), chromium.js(CURSORS)


def _same_rotation(q, R) -> bool:
    p = quat_from_matrix(project_so3(R))
    return abs(abs(float(np.dot(q, p))) - 1) < 1e-4


def test_two_times_move_the_box_and_the_cursor_and_nothing_is_fetched(chromium, linked):
    euler, d, path = linked
    assert path.stat().st_size <= 300_000, f"the linked view is {path.stat().st_size} bytes"
    panels = [p["key"] for p in d.plots["panels"]]
    assert panels == ["energy", "momentum", "orthogonality", "rotation"]           # a free body keeps E and L
    chromium.open(path.as_uri() + "#t=1")
    q1, x1 = _settle(chromium)
    shot1 = chromium.screenshot(path.parent / "t1.png")
    chromium.open("about:blank")                  # a fresh load at the other time (a new fragment alone: no load)
    chromium.open(path.as_uri() + "#t=3")
    q3, x3 = _settle(chromium)
    shot3 = chromium.screenshot(path.parent / "t3.png")
    assert len(x1) == 4 and len(set(x1)) == 1 and len(set(x3)) == 1 and x3[0] > x1[0] + 50, (x1, x3)
    k1, k3 = (int(np.argmin(np.abs(euler.t - t))) for t in (1.0, 3.0))
    assert _same_rotation(q1, euler.R[k1]) and _same_rotation(q3, euler.R[k3])   # the box at those times
    assert not _same_rotation(q1, euler.R[k3])
    h = int(0.6 * shot1.shape[0])
    assert np.abs(shot1[:h] - shot3[:h]).mean() > 1.0, "the 3-D scene did not move"
    requests = chromium.requests()
    assert all(u == path.as_uri() or u.startswith(("data:", "about:")) for u in requests), requests
    assert chromium.page_errors() == []


def test_a_click_on_a_plot_moves_the_scene_there(chromium, linked):
    euler, _, path = linked
    chromium.open("about:blank")
    chromium.open(path.as_uri() + "#t=0.5")
    q0, x0 = _settle(chromium)
    box = chromium.js('(() => { const r = document.querySelector("#rb-panels canvas").getBoundingClientRect();'
                      ' return [r.left, r.top, r.width, r.height]; })()')
    left, top, width, height = box
    x = left + 62 + (width - 62 - 10) * 2.5 / 4.0                     # t = 2.5 s on the time axis (M.l, M.r)
    y = top + height / 2
    for kind in ("mousePressed", "mouseReleased"):
        chromium.send("Input.dispatchMouseEvent", {"type": kind, "x": x, "y": y, "button": "left", "clickCount": 1},
                      session=chromium.session)                          # a real click: pointer events follow
    q, xs = _settle(chromium)
    t = chromium.js("rbLinked.now()")
    assert abs(t - 2.5) < 4.0 / (width - 72) + 1e-3, t                  # within a pixel of the click
    assert not chromium.js("viewer.animator.playing")
    k = int(np.argmin(np.abs(euler.t - t)))
    assert _same_rotation(q, euler.R[k]) and _same_rotation(q0, euler.R[250]) and not _same_rotation(q, euler.R[250])
    assert abs(xs[0] - round(x - left)) <= 1 and xs[0] > x0[0]
