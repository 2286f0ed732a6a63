"""The exported page in a real browser: headless Chromium draws the box, plays the animation,
and fetches nothing from the network.  Also the live viewer, through its websocket.

Chromium is driven over the DevTools protocol on a pipe (--remote-debugging-pipe: no port,
no extra package).  WebGL in headless Chromium without a GPU: --disable-gpu together with
--enable-unsafe-swiftshader (software WebGL, SwiftShader); --use-gl=swiftshader gives a blank page.
"""
import base64
import fcntl
import io
import json
import os
import select
import shutil
import subprocess
import tempfile
import time

import numpy as np
import pytest

pytest.importorskip("meshcat", reason="the viewer needs meshcat (pip install meshcat)")
from PIL import Image  # noqa: E402  (comes with meshcat)

import rbcourse as rb  # noqa: E402
from rbcourse.viz import viewer  # noqa: E402
from rbcourse.workbook.examples import pushed_box  # noqa: E402

CHROMIUM = shutil.which("chromium") or ("/usr/bin/chromium" if os.path.exists("/usr/bin/chromium") else None)
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="chromium is not installed (apt-get install chromium): "
                                                         "the browser tests need a real browser")
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync", "--disable-quic",
         "--hide-scrollbars", "--mute-audio"]
SIZE = (960, 640)


class Chromium:
    """Headless Chromium and one tab, driven over the DevTools protocol on a pipe (fds 3 and 4)."""

    def __init__(self, exe: str, size=SIZE, timeout: float = 30.0):
        self.timeout = timeout
        self.size = size
        self.profile = tempfile.mkdtemp(prefix="rbcourse-chromium-")
        to_chrome, self._w = os.pipe()
        self._r, from_chrome = os.pipe()
        hi_in = fcntl.fcntl(to_chrome, fcntl.F_DUPFD, 10)      # out of the way of fds 3 and 4
        hi_out = fcntl.fcntl(from_chrome, fcntl.F_DUPFD, 10)
        os.close(to_chrome)
        os.close(from_chrome)

        def child_fds():
            os.dup2(hi_in, 3)
            os.dup2(hi_out, 4)

        self.log = open(os.path.join(self.profile, "chromium.log"), "wb")
        self.proc = subprocess.Popen(
            [exe, *FLAGS, f"--user-data-dir={self.profile}", f"--window-size={size[0]},{size[1]}",
             "--remote-debugging-pipe", "about:blank"],
            stdin=subprocess.DEVNULL, stdout=self.log, stderr=self.log, preexec_fn=child_fds, pass_fds=(3, 4),
            start_new_session=True)
        os.close(hi_in)
        os.close(hi_out)
        self._buf, self._id, self.events = b"", 0, []
        target = self.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        self.session = self.send("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        for domain in ("Page", "Network", "Runtime"):
            self.send(f"{domain}.enable", session=self.session)
        self.send("Emulation.setDeviceMetricsOverride", {"width": size[0], "height": size[1],
                                                         "deviceScaleFactor": 1, "mobile": False},
                  session=self.session)

    def _message(self, deadline: float) -> dict:
        while b"\0" not in self._buf:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError("chromium did not answer in time")
            if select.select([self._r], [], [], left)[0]:
                chunk = os.read(self._r, 1 << 20)
                if not chunk:
                    raise RuntimeError("chromium closed its pipe")
                self._buf += chunk
        raw, self._buf = self._buf.split(b"\0", 1)
        return json.loads(raw)

    def send(self, method: str, params=None, session=None):
        """One DevTools command; events that arrive meanwhile are kept in .events."""
        self._id += 1
        msg = {"id": self._id, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        os.write(self._w, json.dumps(msg).encode() + b"\0")
        deadline = time.monotonic() + self.timeout
        while True:
            reply = self._message(deadline)
            if reply.get("id") == self._id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply["result"]
            self.events.append(reply)

    def wait_event(self, method: str):
        deadline = time.monotonic() + self.timeout
        while not any(e.get("method") == method for e in self.events):
            self.events.append(self._message(deadline))

    def open(self, url: str):
        """Load url in the tab and wait for its load event."""
        self.events.clear()
        self.send("Page.navigate", {"url": url}, session=self.session)
        self.wait_event("Page.loadEventFired")

    def js(self, expression: str):
        """Evaluate in the page (promises awaited); the value, or an error with the page's exception."""
        out = self.send("Runtime.evaluate", {"expression": expression, "returnByValue": True, "awaitPromise": True},
                        session=self.session)
        if "exceptionDetails" in out:
            raise RuntimeError(f"{expression}: {out['exceptionDetails']}")
        return out["result"].get("value")

    def screenshot(self, path) -> np.ndarray:
        """After two animation frames (so the last change is rendered): a PNG to path, as an RGB array."""
        self.js("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
        png = base64.b64decode(self.send("Page.captureScreenshot", {"format": "png"}, session=self.session)["data"])
        with open(path, "wb") as f:
            f.write(png)
        return np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)

    def requests(self) -> list:
        return [e["params"]["request"]["url"] for e in self.events if e.get("method") == "Network.requestWillBeSent"]

    def page_errors(self) -> list:
        return [e["params"] for e in self.events if e.get("method") == "Runtime.exceptionThrown"]

    def close(self):
        try:
            self.send("Browser.close")
        except (RuntimeError, TimeoutError, OSError):
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        os.close(self._w)
        os.close(self._r)
        self.log.close()
        shutil.rmtree(self.profile, ignore_errors=True)


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
        box = chromium.js(BOX_SCREEN)
        assert orange(patch(img, box, 12)).mean() > 0.3
        assert all(u.startswith(("http://127.0.0.1:", "ws://127.0.0.1:", "data:")) for u in chromium.requests())
    finally:
        viewer.close_live_server()
