"""The explorer on meshcat (issue 28, part 2), in headless Chromium: a 4 × 4 explorer page holds meshcat's viewer
(three.js, the box a mesh in its scene, drawn by WebGL) and no other 3-D renderer (every other canvas is a 2-D
plot); picking a method or a step moves the box in meshcat's scene to that run's pose, a seek moves it along the
run, the ghost is the reference's pose and its checkbox hides it; nothing is fetched; the page stays within 1 MB."""
import numpy as np
import pytest

pytest.importorskip("meshcat", reason="the explorer's 3-D view needs meshcat (pip install meshcat)")
from tests.viz.test_browser import BOX_SCREEN, orange, patch  # noqa: E402
from tests.viz.test_explorer_browser import CHROMIUM, chromium, load, rect, state, still  # noqa: E402,F401

from rbcourse.viz import explore  # noqa: E402
from rbcourse.examples import pushed_box  # noqa: E402

pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="chromium is not installed (apt-get install chromium): "
                                                         "the browser tests need a real browser")
METHODS, DTS = ["euler", "splitting", "rk4", "exact_splitting"], [0.02, 0.01, 0.005, 0.0025]
POSE = ('(() => { const o = viewer.scene_tree.find(["meshcat", %s, "0"]).object;'
        ' return [o.position.x, o.position.y, o.position.z, o.quaternion.w, o.quaternion.x, o.quaternion.y,'
        ' o.quaternion.z, o.visible]; })()')
CANVASES = """Array.from(document.querySelectorAll("canvas")).map(c =>
  c === viewer.renderer.domElement ? (c.closest("#meshcat-pane") ? "meshcat" : "meshcat elsewhere")
  : c.closest("#rb-plots, #rb-wp-box") && c.getContext("2d") !== null ? "plot" : "other: " + c.outerHTML.slice(0, 80))"""
BOX_MESH = """(() => {
  const o = viewer.scene_tree.find(["meshcat", "bodies", "0", "shape", "<object>"]).object;
  let root = o; while (root.parent) root = root.parent;
  return [o.type, o.geometry.type, o.geometry.parameters.width, o.geometry.parameters.height,
          o.geometry.parameters.depth, root === viewer.scene];
})()"""


@pytest.fixture(scope="module")
def grid(tmp_path_factory):
    """A 4 × 4 explorer of the pushed box (one body that moves far: the camera follows it), saved."""
    ex = explore(pushed_box(), methods=METHODS, dts=DTS, t_end=3.0)
    return ex, ex.save(tmp_path_factory.mktemp("explorer_meshcat") / "pushed_box_4x4.html")


def at(chromium, t: float):
    """Paused at time t, once the page has drawn it (its next animation frame)."""
    still(chromium, t)
    chromium.js("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")


def pose(chromium, which="bodies"):
    return chromium.js(POSE % f'"{which}"')


def frame_pose(track, k):
    """A track's frame k: position (3,) and quaternion (w, x, y, z) of body 0."""
    return np.asarray(track.x[k]).reshape(-1, 3)[0], np.asarray(track.q[k]).reshape(-1, 4)[0]


def same_pose(p, x, q) -> bool:
    return (np.allclose(p[:3], x, atol=1e-5 * (1 + np.abs(x).max()))
            and abs(abs(float(np.dot(p[3:7], q / np.linalg.norm(q)))) - 1) < 1e-5)


def test_a_4x4_explorer_is_meshcat_and_no_other_3d_renderer_and_stays_within_1_MB(chromium, grid):
    ex, path = grid
    size = path.stat().st_size
    assert len(ex.runs) == 16 and size <= 1_000_000, f"a 4 × 4 explorer is {size} bytes"      # measured: 0.47 MB
    load(chromium, path.as_uri() + "#method=rk4&dt=0.005")
    assert chromium.js("window.MeshCat && viewer.renderer.getContext().constructor.name").startswith("WebGL")
    kinds = chromium.js(CANVASES)
    assert kinds.count("meshcat") == 1 and set(kinds) == {"meshcat", "plot"}, kinds
    assert kinds.count("plot") == len(ex.plan.quantities) + 1                  # the drift panels, work-precision
    assert chromium.js("document.getElementById('rb-view') === null")         # the old painter's canvas is gone
    body = ex.settings.scene.bodies[0]
    kind, geometry, *sides, in_scene = chromium.js(BOX_MESH)
    assert (kind, geometry, in_scene) == ("Mesh", "BoxGeometry", True) and sides == pytest.approx(list(body.size))
    # meshcat draws it: where the box is, the pane shows its orange; hide meshcat's drawing and it is gone
    chromium.js("document.getElementById('rb-ghost').click(); true")           # the run alone (no ghost over it)
    at(chromium, 1.0)
    left, top, *_ = rect(chromium, "#meshcat-pane canvas")
    x, y = chromium.js(BOX_SCREEN)
    box = (left + x, top + y)
    shot = chromium.screenshot(path.parent / "meshcat_box.png")
    chromium.js('viewer.scene_tree.find(["meshcat"]).object.visible = false; viewer.set_dirty(); true')
    empty = chromium.screenshot(path.parent / "meshcat_empty.png")
    chromium.js('viewer.scene_tree.find(["meshcat"]).object.visible = true; viewer.set_dirty(); true')
    assert orange(patch(shot, box, 8)).mean() > 0.3 and orange(patch(empty, box, 8)).mean() == 0
    requests = chromium.requests()
    assert requests[0].startswith(path.as_uri()) and all(u.startswith("data:") for u in requests[1:]), requests
    assert chromium.page_errors() == []


def test_picking_a_method_or_a_step_moves_the_box_to_that_runs_pose(chromium, grid):
    ex, path = grid
    load(chromium, path.as_uri() + "#method=rk4&dt=0.02")
    runs = [ex.run("rk4", 0.02), ex.run("splitting", 0.02), ex.run("splitting", 0.0025)]
    assert not any(r.diverged for r in runs)
    t = next(float(t) for t in runs[0].track.t if t > 1.0 and all(np.isclose(r.track.t, t, rtol=0, atol=1e-9).any()
                                                                   for r in runs))
    frames = [int(np.argmin(np.abs(r.track.t - t))) for r in runs]       # a frame of each run, at that same time
    at(chromium, t)
    poses = [pose(chromium)]
    for method, dt in (("splitting", 0.02), ("splitting", 0.0025)):
        chromium.js(f"rbExplorer.select('{method}', {dt}); new Promise(r => requestAnimationFrame(r))")
        assert (state(chromium)["method"], state(chromium)["dt"], state(chromium)["t"]) == (method, dt, t)
        poses.append(pose(chromium))
    for p, r, k in zip(poses, runs, frames):
        assert same_pose(p, *frame_pose(r.track, k)), (r.method, r.dt, p)
    assert not np.allclose(poses[0][3:7], poses[1][3:7], atol=1e-4)           # another method: another pose
    assert not np.allclose(poses[1][3:7], poses[2][3:7], atol=1e-4)           # another step: another pose
    # a click on a method button does the same as select()
    x, y, w, h = rect(chromium, 'button[data-method="rk4"]')
    from tests.viz.test_explorer_browser import click
    click(chromium, x + w / 2, y + h / 2)
    chromium.js("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    rk4 = ex.run("rk4", 0.0025).track
    assert state(chromium)["method"] == "rk4"
    assert same_pose(pose(chromium), *frame_pose(rk4, int(np.argmin(np.abs(rk4.t - t)))))


def test_a_seek_moves_the_box_along_the_run_and_the_ghost_is_the_reference(chromium, grid):
    ex, path = grid
    load(chromium, path.as_uri() + "#method=exact_splitting&dt=0.01")
    run = ex.run("exact_splitting", 0.01)
    seen = []
    for k in (30, 150):
        at(chromium, float(run.track.t[k]))
        seen.append(pose(chromium))
        assert same_pose(seen[-1], *frame_pose(run.track, k))
        at(chromium, float(ex.grid.ghost.t[k]))                       # the ghost: the reference at its own frames
        ghost = pose(chromium, "ghost")
        assert ghost[7] is True and same_pose(ghost, *frame_pose(ex.grid.ghost, k))
    assert np.linalg.norm(np.subtract(seen[1][:3], seen[0][:3])) > 0.05          # it moved (metres)
    # the camera follows the box: the drawing is shifted by its position
    at(chromium, float(run.track.t[150]))
    shift = chromium.js('(() => { const p = viewer.scene_tree.find(["meshcat"]).object.position; return [p.x, p.y, p.z]; })()')
    assert np.allclose(shift, -np.array(seen[1][:3]), atol=1e-9)
    chromium.js("document.getElementById('rb-ghost').click(); new Promise(r => requestAnimationFrame(r))")
    assert chromium.js('viewer.scene_tree.find(["meshcat", "ghost"]).object.visible') is False


def test_a_link_with_a_time_opens_that_run_there_paused(chromium, grid):
    ex, path = grid
    track = ex.run("rk4", 0.005).track
    t = float(track.t[120])
    load(chromium, path.as_uri() + f"#method=rk4&dt=0.005&t={t!r}")
    chromium.js("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    s = state(chromium)
    assert (s["method"], s["dt"], s["t"], s["playing"], s["note"]) == ("rk4", 0.005, t, False, "")
    assert same_pose(pose(chromium), *frame_pose(track, 120))
    load(chromium, path.as_uri() + "#method=rk4&dt=0.005&t=99")          # not a time of the page: said, and it plays
    s = state(chromium)
    assert s["playing"] and "t = “99”" in s["note"] and "[0, 3" in s["note"]
