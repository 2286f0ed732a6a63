"""rbcourse.viz.viewer: what is drawn matches the physics, the page is standalone, the live server is
one per process, on 127.0.0.1 only, and is gone after the tests."""
import os
import re
import signal
import subprocess
import sys
import time
import urllib.request
from html.parser import HTMLParser

import numpy as np
import pytest

pytest.importorskip("meshcat", reason="the viewer needs meshcat (pip install meshcat)")

import umsgpack  # noqa: E402  (comes with meshcat)

import rbcourse as rb  # noqa: E402
from rbcourse.viz import viewer  # noqa: E402
from rbcourse.viz.viewer import assets  # noqa: E402
from rbcourse.__main__ import main  # noqa: E402
from rbcourse.rotation import project_so3, quat_from_matrix  # noqa: E402
from rbcourse.examples import pushed_box  # noqa: E402


def meshcat_server_pids() -> set:
    """Every meshcat server process on the machine (ours run `-c ... meshcat.servers.zmqserver ...`)."""
    out = subprocess.run(["pgrep", "-f", "meshcat.servers.zmqserver"], capture_output=True, text=True)
    return {int(p) for p in out.stdout.split()}


@pytest.fixture(scope="session", autouse=True)
def no_meshcat_server_left_behind():
    """After the whole session: no server in our registry, and no meshcat server started since."""
    before = meshcat_server_pids()
    yield
    assert viewer.live_server_pids() == [], "a test left this process's meshcat server running"
    deadline = time.monotonic() + 5          # an orphaned server quits within ~1 s of its owner
    while (meshcat_server_pids() - before) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert meshcat_server_pids() - before == set(), "a meshcat server started by the tests is still running"


# --- helpers -------------------------------------------------------------------------

def page_commands(page: str) -> list:
    """The meshcat commands embedded in an exported page, decoded (by Python's LZMA and base 85, not the page's decoder)."""
    found = re.findall(r'rbCommands\(viewer, "([^"]+)", (\d+)\)', page)
    assert len(found) == 1, "the page holds no command list"
    buf = assets.decompress(found[0][0])
    assert len(buf) == int(found[0][1])
    out, i = [], 0
    while i < len(buf):
        n = int.from_bytes(buf[i:i + 4], "little")
        out.append(umsgpack.unpackb(buf[i + 4:i + 4 + n]))
        i += 4 + n
    return out


def clips(commands) -> dict:
    """path -> {property: (key times in frames, values)} of the page's animation."""
    anim = [c for c in commands if c["type"] == "set_animation"]
    assert len(anim) == 1
    out = {}
    for a in anim[0]["animations"]:
        out[a["path"]] = {t["name"][1:]: (np.array([k["time"] for k in t["keys"]]),
                                          np.array([k["value"] for k in t["keys"]], dtype=float))
                          for t in a["clip"]["tracks"]}
        out[a["path"]]["fps"] = a["clip"]["fps"]
    return out


def rotate(q_xyzw: np.ndarray, v) -> np.ndarray:
    """Rotate v by unit quaternions (x, y, z, w) (F, 4)."""
    u, w = q_xyzw[:, :3], q_xyzw[:, 3:]
    v = np.broadcast_to(np.asarray(v, dtype=float), u.shape)
    t = 2 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


def objects(commands) -> dict:
    return {c["path"]: c["object"] for c in commands if c["type"] == "set_object"}


def arrow_tips(commands, path: str):
    """(keyframe times, tail, tip) of an arrow as drawn: group (position, quaternion, scale) and head offset."""
    c = clips(commands)
    times, tail = c[path]["position"]
    _, q = c[path]["quaternion"]
    _, s = c[path]["scale"]
    _, head = c[path + "/head"]["position"]
    head_len = objects(commands)[path + "/head/mesh"]["geometries"][0]["height"]
    along = np.zeros_like(head)
    along[:, 1] = head[:, 1] + head_len
    return times, tail, tail + s * rotate(q, along)


def f32(a) -> np.ndarray:
    """a rounded to float32, as the page's animation holds it (three.js keeps key times and values in Float32Arrays)."""
    return np.asarray(a, dtype=float).astype(np.float32).astype(float)


def traj_index(traj, key_times, fps, speed=1.0):
    """The recorded states the keyframes show (keyframe time in frames, float32 -> simulated time)."""
    t = traj.t[0] + speed * np.asarray(key_times) / fps
    k = np.abs(traj.t[None, :] - t[:, None]).argmin(1)
    np.testing.assert_array_equal(f32((traj.t[k] - traj.t[0]) / speed * fps), key_times)   # exactly those states
    return k


@pytest.fixture(scope="module")
def pushed():
    ex = pushed_box()
    return rb.simulate(ex.scene, ex.X0, t_end=1.0, dt=0.005, method="rk4")


# --- the animation -------------------------------------------------------------------

@pytest.mark.parametrize("speed, fps", [(1.0, 30.0), (2.0, 24.0), (0.5, 10.0)])
def test_page_holds_the_animation_for_the_whole_run(pushed, speed, fps):
    d = viewer.draw_trajectory(pushed, speed=speed, fps=fps)
    assert d.duration == pytest.approx(1.0 / speed)
    c = clips(page_commands(d.html()))
    body = c["/meshcat/bodies/0"]
    times, _ = body["position"]
    assert body["fps"] == fps
    assert times[0] == 0 and times[-1] / fps == pytest.approx(1.0 / speed)        # the whole run, in playback s
    assert len(times) == pytest.approx(fps / speed + 1, abs=1)                    # resampled: fps frames a second
    assert np.all(np.diff(times) > 0)
    for path, tracks in c.items():                                                # every clip spans it
        assert tracks["position" if "position" in tracks else "scale"][0][-1] / fps == pytest.approx(1.0 / speed)


def test_long_runs_stay_small():
    body = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
    t = np.linspace(0.0, 60.0, 60_001)                               # a minute at dt = 1 ms: spin about z
    c, s = np.cos(2.0 * t), np.sin(2.0 * t)
    R = np.zeros((len(t), 3, 3))
    R[:, 0, 0], R[:, 0, 1], R[:, 1, 0], R[:, 1, 1], R[:, 2, 2] = c, -s, s, c, 1.0
    L = np.broadcast_to(body.I_body @ [0, 0, 2.0], (len(t), 3))
    traj = rb.Trajectory(t, np.zeros((len(t), 3)), R, np.zeros((len(t), 3)), L, rb.Scene(body), "exact", 1e-3)
    c = clips(page_commands(viewer.draw_trajectory(traj, fps=20).html()))
    assert len(c["/meshcat/bodies/0"]["position"][0]) == 60 * 20 + 1
    with pytest.raises(ValueError, match="fps"):
        viewer.draw_trajectory(traj, fps=240, max_frames=1000)


def test_bodies_are_where_the_physics_says_with_R_projected_onto_SO3():
    body = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
    X0 = rb.State.from_velocities(body, np.zeros(3), np.eye(3), [0.2, 0, 0], [0.5, 6.0, 0.5])
    traj = rb.simulate(body, X0, t_end=1.0, dt=0.02, method="euler")           # the slides' Euler: R drifts
    assert traj.orthogonality_error()[-1] > 1e-2
    c = clips(page_commands(viewer.draw_trajectory(traj).html()))
    times, x = c["/meshcat/bodies/0"]["position"]
    _, q = c["/meshcat/bodies/0"]["quaternion"]
    k = traj_index(traj, times, c["/meshcat/bodies/0"]["fps"])
    np.testing.assert_array_equal(x, f32(traj.x[k]))                           # float32 of the physics' x
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=3e-7)      # a rotation was sent
    ref = quat_from_matrix(project_so3(traj.R[k]))
    dots = np.abs(np.sum(q[:, [3, 0, 1, 2]] * ref, axis=1))
    np.testing.assert_allclose(dots, 1.0, atol=3e-7)                           # the same rotation (±q)
    # the camera follows the body: the drawing is shifted by −x(t)
    np.testing.assert_array_equal(c["/meshcat"]["position"][1], f32(-traj.x[k]))


def test_arrows_point_where_the_physics_says(pushed):
    d = viewer.draw_trajectory(pushed)
    cmds = page_commands(d.html())
    fps = clips(cmds)["/meshcat/bodies/0"]["fps"]
    omega, L = pushed.angular_velocity(), pushed.L
    for name, vec in (("omega_0", omega), ("L_0", L)):
        times, tail, tip = arrow_tips(cmds, f"/meshcat/arrows/{name}")
        k = traj_index(pushed, times, fps)
        np.testing.assert_array_equal(tail, f32(pushed.x[k]))                         # from the centre of mass
        np.testing.assert_allclose(tip - tail, d.arrow_scales[name[:-2]] * vec[k], rtol=0, atol=1e-6)
        assert np.linalg.norm(tip - tail, axis=1).max() == pytest.approx(1.2 * 0.3)   # the longest: arrow_length
    # the push: F = (0, 0, 10) N at the corner r = x + R b while 0 <= t < 0.1 s, nothing after
    times, tail, tip = arrow_tips(cmds, "/meshcat/arrows/force_0_0")
    k = traj_index(pushed, times, fps)
    corner = np.array([0.15, 0.10, 0.025])
    np.testing.assert_array_equal(tail, f32(pushed.x[k] + project_so3(pushed.R[k]) @ corner))
    on = pushed.t[k] < 0.1
    assert on.sum() >= 3 and (~on).sum() > 20
    expected = np.broadcast_to(d.arrow_scales["force"] * np.array([0, 0, 10.0]), (on.sum(), 3))
    np.testing.assert_allclose((tip - tail)[on], expected, rtol=0, atol=1e-6)
    assert np.all(np.linalg.norm(tip - tail, axis=1)[~on] < 1e-6)
    assert d.arrow_scales["force"] == pytest.approx(0.36 / 10)


def test_body_frame_force_turns_with_the_body():
    body = rb.RigidBody.box(2.0, (0.4, 0.2, 0.1))
    push = rb.PointForce(body_point=(0.2, 0, 0), force=(0, 1.0, 0), frame="body")
    scene = rb.Scene(body, [push])
    traj = rb.simulate(scene, rb.State.at_rest(), t_end=1.5, dt=0.01, method="rk4")
    d = viewer.draw_trajectory(traj, arrow_scales={"force": 0.1})
    cmds = page_commands(d.html())
    times, tail, tip = arrow_tips(cmds, "/meshcat/arrows/force_0_0")
    k = traj_index(traj, times, 30.0)
    expected = np.einsum("kij,j->ki", traj.R[k], [0, 1.0, 0])                          # F = R f
    np.testing.assert_allclose(tip - tail, 0.1 * expected, rtol=0, atol=1e-6)
    assert d.arrow_scales["force"] == 0.1


def test_shapes_have_their_true_sizes_and_the_ground_is_drawn():
    box = rb.RigidBody.box(1.0, (0.3, 0.2, 0.05))
    cyl = rb.RigidBody.cylinder(1.0, radius=0.1, height=0.4)
    ball = rb.RigidBody.sphere(1.0, radius=0.15)
    Q = rb.rotation.rotation_about([1, 2, 3], 0.7)
    lump = rb.RigidBody(1.0, Q @ np.diag([0.01, 0.02, 0.025]) @ Q.T)
    scene = rb.Scene([box, cyl, ball, lump], [rb.Ground(height=-0.5)])
    R = np.stack([np.eye(3)] * 4)
    X = rb.State(x=np.arange(12.0).reshape(4, 3), R=R, P=np.zeros((4, 3)), L=np.zeros((4, 3)))
    d = viewer.draw_state(scene, X)
    assert d.animation is None and d.duration == 0
    cmds = page_commands(d.html())
    obj = objects(cmds)
    geom = {p: o["geometries"][0] for p, o in obj.items()}
    g = geom["/meshcat/bodies/0/shape"]
    assert (g["type"], g["width"], g["height"], g["depth"]) == ("BoxGeometry", 0.3, 0.2, 0.05)
    g = geom["/meshcat/bodies/1/shape"]
    assert (g["type"], g["radiusTop"], g["radiusBottom"], g["height"]) == ("CylinderGeometry", 0.1, 0.1, 0.4)
    g = geom["/meshcat/bodies/2/shape"]
    assert (g["type"], g["radius"]) == ("SphereGeometry", 0.15)
    assert geom["/meshcat/bodies/3/shape"]["type"] == "SphereGeometry"                   # the inertia ellipsoid
    radii = np.diag(np.array(obj["/meshcat/bodies/3/shape"]["object"]["matrix"]).reshape(4, 4))[:3]
    np.testing.assert_allclose(np.sort(radii), np.sort(lump.half_extents()))
    transforms = {c["path"]: np.array(c["matrix"]).reshape(4, 4).T for c in cmds if c["type"] == "set_transform"}
    np.testing.assert_allclose(transforms["/meshcat/bodies/1/shape"][:3, :3] @ [0, 1, 0], [0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(transforms["/meshcat/bodies/3/shape"][:3, :3], lump.principal_axes, atol=1e-12)
    for i in range(4):                                                                  # each body at its x
        np.testing.assert_allclose(transforms[f"/meshcat/bodies/{i}"][:3, 3], X.x[i])
    ground = [p for p in geom if "ground" in p]
    assert len(ground) == 1
    top = transforms[ground[0]][2, 3] + geom[ground[0]]["depth"] / 2
    assert top == pytest.approx(-0.5, abs=1e-3)
    grid = obj["/meshcat/grid"]                                                         # the floor grid, on it
    assert grid["object"]["type"] == "LineSegments"
    points = np.frombuffer(grid["geometries"][0]["data"]["attributes"]["position"]["array"].data, np.float32)
    np.testing.assert_allclose(points.reshape(-1, 3)[:, 2], -0.5, atol=1e-6)
    hidden = [c for c in cmds if c["type"] == "set_property" and c["path"] == "/Grid"]
    assert hidden and hidden[0]["property"] == "visible" and hidden[0]["value"] is False   # meshcat's own grid


def test_ghost_trail_and_axes(pushed):
    ex = pushed_box()
    euler = rb.simulate(ex.scene, ex.X0, t_end=0.6, dt=0.005, method="euler")      # shorter than the run
    d = viewer.draw_trajectory(pushed, ghost=euler, ghost_offset=(0, 0.5, 0), ghost_label="euler",
                               trail=(0.15, 0.1, 0.025))
    cmds = page_commands(d.html())
    obj = objects(cmds)
    ghost_material = obj["/meshcat/ghost/0/shape"]["materials"][0]
    assert ghost_material["transparent"] and ghost_material["opacity"] < 1
    assert ghost_material["color"] != obj["/meshcat/bodies/0/shape"]["materials"][0]["color"]
    c = clips(cmds)
    times, x = c["/meshcat/ghost/0"]["position"]
    _, scale = c["/meshcat/ghost/0"]["scale"]
    k = traj_index(euler, times[times / 30 <= 0.6], 30.0)
    np.testing.assert_array_equal(x[: len(k)], f32(euler.x[k] + [0, 0.5, 0]))       # beside the body
    assert np.all(scale[times / 30 <= 0.6] == 1) and np.all(scale[times / 30 > 0.62] < 1e-5)   # gone after its end
    trail = obj["/meshcat/trail"]
    assert trail["object"]["type"] == "Line"
    points = np.frombuffer(trail["geometries"][0]["data"]["attributes"]["position"]["array"].data,
                           np.float32).reshape(-1, 3)
    frames = len(c["/meshcat/bodies/0"]["position"][0])
    assert frames < len(points) <= 4 * frames < len(pushed.t)                # 4 points a frame, not every state
    path = pushed.x + project_so3(pushed.R) @ np.array([0.15, 0.1, 0.025])   # r = x + R b at every state
    nearest = np.abs(points[:, None, :] - path[None, :, :]).max(-1).min(1)
    assert nearest.max() < 1e-6                                              # each point on the corner's path
    assert np.allclose(points[[0, -1]], path[[0, -1]], atol=1e-6)            # from its start to its end
    assert "/meshcat/bodies/0/axes" in obj and obj["/meshcat/bodies/0/axes"]["object"]["type"] == "LineSegments"
    assert any("euler" in text for _, text in d.legend)


def test_the_page_is_standalone(pushed, tmp_path):
    path = viewer.draw_trajectory(pushed, title="a <b>box</b>").save(tmp_path / "box.html")
    page = path.read_text(encoding="utf-8")
    assert "MeshCat.Viewer" in page and "&lt;b&gt;box" in page

    class Links(HTMLParser):
        found = []

        def handle_starttag(self, tag, attrs):
            for name, value in attrs:
                if name in ("src", "href", "srcset", "data", "poster", "action") and value:
                    self.found.append((tag, name, value))
            if tag in ("link", "iframe", "img", "base"):
                self.found.append((tag, "tag", ""))

    parser = Links()
    parser.feed(page)
    assert parser.found == [], f"the page refers to resources: {parser.found}"
    assert not re.search(r"""url\(\s*['"]?\s*(https?:)?//""", page, re.I)
    assert not re.search(r"@import", page)
    assert not re.search(r"""(fetch|XMLHttpRequest|importScripts)\s*\(\s*['"`]\s*(https?:)?//""", page)


def test_notebook_views(pushed):
    d = viewer.draw_trajectory(pushed)
    html = d._repr_html_()
    frame, beside = html.split("</iframe></div>")
    assert frame.startswith("<div") and 'srcdoc="' in frame and "<script>" not in frame    # escaped page
    assert beside.startswith("<script>") and "rbcourseMeshcat" in beside                   # the first view: meshcat
    assert d._repr_html_().endswith("</iframe></div>")                                     # a later one: nothing
    assert "http://127.0.0.1:7000/static/" in viewer.LiveView("http://127.0.0.1:7000/static/")._repr_html_()


def test_physics_does_not_import_the_viewer():
    code = ("import sys, rbcourse as rb; from rbcourse.examples import pushed_box; ex = pushed_box(); "
            "rb.simulate(ex.scene, ex.X0, 0.05, 0.01); "
            "assert 'meshcat' not in sys.modules and 'rbcourse.viz.viewer' not in sys.modules, sorted(sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr


@pytest.mark.parametrize("kwargs, name", [
    (dict(speed=0), "speed"), (dict(speed=-1), "speed"), (dict(fps=0), "fps"), (dict(fps=1e4), "fps"),
    (dict(omega="yes"), "omega"), (dict(loop=1), "loop"), (dict(arrow_length=-0.1), "arrow_length"),
    (dict(arrow_scales={"torque": 1.0}), "arrow_scales"), (dict(arrow_scales={"omega": 0}), "arrow_scales"),
    (dict(trail=(1, 2)), "trail"), (dict(trail_body=1), "trail_body"), (dict(ghost="exact"), "ghost"),
    (dict(ghost_offset=(0, 1)), "ghost_offset"), (dict(follow=3), "follow"), (dict(follow=True), "follow"),
    (dict(camera_distance=0), "camera_distance"), (dict(max_frames=0), "max_frames"), (dict(title=3), "title"),
])
def test_bad_inputs_name_the_parameter(pushed, kwargs, name):
    with pytest.raises(ValueError, match=name):
        viewer.draw_trajectory(pushed, **kwargs)


def test_bad_inputs_of_the_rest(pushed):
    with pytest.raises(ValueError, match="traj"):
        viewer.draw_trajectory("not a trajectory")
    with pytest.raises(ValueError, match="x must contain only finite numbers"):      # refused where it is built
        rb.Trajectory(pushed.t, pushed.x * np.nan, pushed.R, pushed.P, pushed.L, pushed.scene)
    bad = rb.Trajectory.unchecked(pushed.t, pushed.x * np.nan, pushed.R, pushed.P, pushed.L, pushed.scene)
    with pytest.raises(ValueError, match="traj"):                   # and by the viewer, if built unchecked
        viewer.draw_trajectory(bad)
    two = rb.Scene([rb.RigidBody.sphere(1, 0.1), rb.RigidBody.sphere(1, 0.1)])
    X2 = rb.State.stack([rb.State.at_rest(), rb.State.at_rest(x=(1, 0, 0))])
    ghost = rb.simulate(two, X2, 0.1, 0.05)
    with pytest.raises(ValueError, match="ghost"):
        viewer.draw_trajectory(pushed, ghost=ghost)
    with pytest.raises(ValueError, match="X"):
        viewer.draw_state(two, rb.State.at_rest())
    with pytest.raises(ValueError, match="scene"):
        viewer.draw_state("box", rb.State.at_rest())
    with pytest.raises(ValueError, match="t"):
        viewer.draw_state(two, X2, t=float("nan"))
    d = viewer.draw_state(two, X2)
    with pytest.raises(ValueError, match="path"):
        d.save(None)
    with pytest.raises(ValueError, match="server"):
        d.show(server="http://127.0.0.1:7000")


# --- the live server -------------------------------------------------------------------

def listening_addresses(port: int) -> list:
    """Local addresses (hex, as /proc/net/tcp* shows them) listening on a TCP port."""
    found = []
    for name in ("/proc/net/tcp", "/proc/net/tcp6"):
        try:
            lines = open(name).read().splitlines()[1:]
        except FileNotFoundError:
            continue
        for line in lines:
            fields = line.split()
            address, hexport = fields[1].split(":")
            if fields[3] == "0A" and int(hexport, 16) == port:
                found.append(address)
    return found


def test_live_server_is_one_per_process_loopback_only_and_closes(pushed):
    assert viewer.live_server_pids() == []
    try:
        view = viewer.draw_trajectory(pushed).show()                 # no browser: must not wait for one
        server = viewer.live_server()
        assert viewer.live_server() is server and viewer.live_server_pids() == [server.proc.pid]
        assert view.url == server.url and view.url.startswith("http://127.0.0.1:")
        with urllib.request.urlopen(server.url, timeout=10) as page:
            assert page.status == 200 and b"MeshCat" in page.read()
        port = int(re.search(r":(\d+)/", server.url).group(1))
        zmq_port = int(server.zmq_url.rsplit(":", 1)[1])
        if os.path.exists("/proc/net/tcp"):
            assert listening_addresses(port) == ["0100007F"]         # 127.0.0.1, not 0.0.0.0 nor ::
            assert listening_addresses(zmq_port) == ["0100007F"]
        viewer.draw_state(pushed.scene, pushed.final).show()          # a still replaces the animation
        scene_page = server.visualizer().static_html()                # meshcat's own API on our server
        assert "MeshCat.Viewer" in scene_page
        pid = server.proc.pid
    finally:
        assert viewer.close_live_server() in (True, False)
    assert viewer.live_server_pids() == [] and not server.running
    assert pid not in meshcat_server_pids()
    with pytest.raises(RuntimeError, match="closed"):
        server.send({"type": "delete", "path": "/meshcat"})
    assert viewer.close_live_server() is False


def test_demo_writes_the_page_and_open_serves_it_without_blocking(tmp_path, capsys):
    seen = []

    def wait(url):                                       # instead of waiting for Ctrl-C
        with urllib.request.urlopen(url, timeout=10) as page:
            seen.append((url, page.status, viewer.live_server_pids()))

    assert main(["demo", "--t-end", "0.3", "--dt", "0.01", "--out", str(tmp_path), "--open"], wait=wait) == 0
    printed = capsys.readouterr().out
    page = tmp_path / "pushed_box.html"
    assert f"wrote {page}" in printed and page.stat().st_size > 100_000
    (url, status, pids), = seen
    assert status == 200 and len(pids) == 1 and f"live at {url}" in printed
    assert viewer.live_server_pids() == [] and pids[0] not in meshcat_server_pids()
    c = clips(page_commands(page.read_text(encoding="utf-8")))
    assert "/meshcat/ghost/0" in c and c["/meshcat/bodies/0"]["position"][0][-1] / 30 == pytest.approx(0.3)


def test_demo_open_from_the_command_line_stops_on_ctrl_c(tmp_path):
    proc = subprocess.Popen([sys.executable, "-m", "rbcourse", "demo", "--t-end", "0.2", "--dt", "0.01",
                             "--out", str(tmp_path), "--open"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            stdin=subprocess.DEVNULL, text=True)
    try:
        url = None
        deadline = time.monotonic() + 90
        while url is None and time.monotonic() < deadline:
            line = proc.stdout.readline()
            assert line, proc.stderr.read()
            if line.startswith("live at "):
                url = line.split()[-1]
        with urllib.request.urlopen(url, timeout=10) as page:
            assert page.status == 200
        servers = subprocess.run(["pgrep", "-P", str(proc.pid), "-f", "meshcat.servers.zmqserver"],
                                 capture_output=True, text=True).stdout.split()
        assert len(servers) == 1
        proc.send_signal(signal.SIGINT)
        assert proc.wait(timeout=20) == 0
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    deadline = time.monotonic() + 5
    while int(servers[0]) in meshcat_server_pids() and time.monotonic() < deadline:
        time.sleep(0.1)
    assert int(servers[0]) not in meshcat_server_pids()
