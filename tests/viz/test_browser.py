"""The exported page in a real browser: headless Chromium draws the box, plays the animation,
and fetches nothing from the network.  Also the live viewer, through its websocket.

Chromium is driven over the DevTools protocol on a pipe (tests/viz/chromium.py; Chromium, CHROMIUM,
FLAGS and SIZE are importable from here too).
"""
import time

import numpy as np
import pytest

pytest.importorskip("meshcat", reason="the viewer needs meshcat (pip install meshcat)")
from tests.viz.chromium import CHROMIUM, FLAGS, SIZE, SKIP_REASON, Chromium  # noqa: E402,F401

import rbcourse as rb  # noqa: E402
from rbcourse.viz import viewer  # noqa: E402
from rbcourse.examples import pushed_box  # noqa: E402

pytestmark = pytest.mark.skipif(CHROMIUM is None, reason=SKIP_REASON)


@pytest.fixture(scope="module")
def chromium():
    browser = Chromium(CHROMIUM)
    yield browser
    browser.close()


@pytest.fixture(scope="module")
def shots(tmp_path_factory):
    """Where the screenshots go (kept by pytest under its basetemp, for a look)."""
    return tmp_path_factory.mktemp("screenshots")


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    ex = pushed_box()
    traj = rb.simulate(ex.scene, ex.X0, t_end=3.0, dt=0.01, method="rk4")
    return viewer.draw_trajectory(traj, trail=(0.15, 0.10, 0.025)).save(tmp_path_factory.mktemp("page") / "box.html")


BOX_SCREEN = """(() => {
  viewer.scene.updateMatrixWorld(true);
  const v = new MeshCat.THREE.Vector3();
  viewer.scene_tree.find(["meshcat", "bodies", "0"]).object.getWorldPosition(v);
  v.project(viewer.camera);
  const c = viewer.renderer.domElement;
  return [(v.x + 1) / 2 * c.clientWidth, (1 - v.y) / 2 * c.clientHeight];
})()"""


def seek(chromium, t: float):
    chromium.js(f"viewer.animator.pause(); viewer.animator.seek({t}); true")


def patch(img, centre, half: int) -> np.ndarray:
    x, y = (int(round(c)) for c in centre)
    return img[max(y - half, 0): y + half + 1, max(x - half, 0): x + half + 1]


def orange(pixels) -> np.ndarray:
    """The box's colour (#F28E2B, lit or shaded): red well above blue, green in between."""
    r, g, b = pixels[..., 0], pixels[..., 1], pixels[..., 2]
    return (r > 110) & (r - b > 70) & (g > b) & (r > g)


def test_the_page_draws_the_box_and_animates_offline(chromium, page, shots):
    start = time.monotonic()
    chromium.open(page.as_uri())
    assert chromium.js("!!viewer.renderer.getContext()"), "no WebGL context"
    # it plays by itself, in real time
    tau1 = chromium.js("viewer.animator.actions.reduce((m, a) => Math.max(m, a.time), 0)")
    first = chromium.screenshot(shots / "playing_1.png")
    time.sleep(1.0)
    tau2 = chromium.js("viewer.animator.actions.reduce((m, a) => Math.max(m, a.time), 0)")
    second = chromium.screenshot(shots / "playing_2.png")
    assert chromium.js("viewer.animator.playing") and 0.5 < tau2 - tau1 < 3.0
    assert np.abs(first - second).mean() > 1.0, "the animation does not move"
    # the box at t = 1 s, and the same view with the drawing hidden (an empty scene)
    seek(chromium, 1.0)
    at_1 = chromium.screenshot(shots / "t_1.png")
    box = chromium.js(BOX_SCREEN)
    assert 0 < box[0] < SIZE[0] and 0 < box[1] < SIZE[1], f"the box is off screen at {box}"
    chromium.js('viewer.scene_tree.find(["meshcat"]).object.visible = false; viewer.set_dirty(); true')
    empty = chromium.screenshot(shots / "empty.png")
    chromium.js('viewer.scene_tree.find(["meshcat"]).object.visible = true; viewer.set_dirty(); true')
    here, there = patch(at_1, box, 12), patch(empty, box, 12)
    assert np.abs(here - there).mean() > 40, "nothing is drawn where the box is"
    assert orange(here).mean() > 0.3 and orange(there).mean() == 0
    assert orange(at_1).sum() > 2000, "the box is too small to see"
    # later the box has turned: the view around it differs
    seek(chromium, 2.0)
    at_2 = chromium.screenshot(shots / "t_2.png")
    assert np.abs(patch(at_1, box, 60) - patch(at_2, box, 60)).mean() > 10
    # offline: nothing but the file itself and inline data: URLs, and no error in the page
    requests = chromium.requests()
    assert requests[0] == page.as_uri()
    assert all(u.startswith("data:") for u in requests[1:]), requests
    assert chromium.page_errors() == []
    assert time.monotonic() - start < 60


def test_the_live_viewer_shows_the_box_through_its_websocket(chromium, shots):
    ex = pushed_box()
    traj = rb.simulate(ex.scene, ex.X0, t_end=1.0, dt=0.01, method="rk4")
    try:
        view = viewer.draw_trajectory(traj).show()
        chromium.open(view.url)
        deadline = time.monotonic() + 20           # the server replays the scene when the websocket opens
        while not chromium.js("viewer.animator.actions.length > 0") and time.monotonic() < deadline:
            time.sleep(0.1)
        seek(chromium, 0.5)
        img = chromium.screenshot(shots / "live.png")
        info = chromium.js('document.getElementById("rb-info").hidden ? "" : document.getElementById("rb-info").innerText')
        assert "pushed box: rk4, dt = 0.01 s" in info and "ω:" in info and "m per rad/s" in info, info
        box = chromium.js(BOX_SCREEN)
        assert orange(patch(img, box, 12)).mean() > 0.3
        assert all(u.startswith(("http://127.0.0.1:", "ws://127.0.0.1:", "data:")) for u in chromium.requests())
    finally:
        viewer.close_live_server()
