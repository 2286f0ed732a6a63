"""Headless Chromium for the browser tests, driven over the DevTools protocol on a pipe
(--remote-debugging-pipe: no port, no extra package).

WebGL in headless Chromium without a GPU: --disable-gpu together with --enable-unsafe-swiftshader
(software WebGL, SwiftShader); --use-gl=swiftshader gives a blank page.

Frames: a sandboxed iframe (sandbox="allow-scripts", an opaque origin) runs in a process of its own,
a target of its own.  Chromium is told to attach to every such target on start (paused until its
Network and Runtime domains are enabled, so none of its requests is missed); frame_js evaluates in one.
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
from PIL import Image  # comes with meshcat

CHROMIUM = shutil.which("chromium") or ("/usr/bin/chromium" if os.path.exists("/usr/bin/chromium") else None)
SKIP_REASON = "chromium is not installed (apt-get install chromium): the browser tests need a real browser"
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
        self.frames: dict[str, str] = {}            # session id -> url of each attached iframe target, in order
        target = self.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        self.session = self.send("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        self._attach_frames(self.session)
        for domain in ("Page", "Network", "Runtime"):
            self.send(f"{domain}.enable", session=self.session)
        self.send("Emulation.setDeviceMetricsOverride", {"width": size[0], "height": size[1],
                                                         "deviceScaleFactor": 1, "mobile": False},
                  session=self.session)

    def _attach_frames(self, session: str):
        self.send("Target.setAutoAttach", {"autoAttach": True, "waitForDebuggerOnStart": True, "flatten": True},
                  session=session)

    def _post(self, method: str, params=None, session=None) -> int:
        """Send a command without waiting for its reply (the reply lands in .events)."""
        self._id += 1
        msg = {"id": self._id, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        os.write(self._w, json.dumps(msg).encode() + b"\0")
        return self._id

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
        msg = json.loads(raw)
        method = msg.get("method")
        if method == "Target.attachedToTarget":             # an iframe's target: record it, enable, let it run
            child = msg["params"]["sessionId"]
            self.frames[child] = msg["params"]["targetInfo"]["url"]
            for domain in ("Network", "Runtime", "Page"):
                self._post(f"{domain}.enable", session=child)
            self._post("Target.setAutoAttach", {"autoAttach": True, "waitForDebuggerOnStart": True, "flatten": True},
                       session=child)
            self._post("Runtime.runIfWaitingForDebugger", session=child)
        elif method == "Target.detachedFromTarget":
            self.frames.pop(msg["params"].get("sessionId"), None)
        return msg

    def send(self, method: str, params=None, session=None):
        """One DevTools command; events that arrive meanwhile are kept in .events."""
        sent = self._post(method, params, session)
        deadline = time.monotonic() + self.timeout
        while True:
            reply = self._message(deadline)
            if reply.get("id") == sent:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply["result"]
            self.events.append(reply)

    def wait_event(self, method: str):
        deadline = time.monotonic() + self.timeout
        while not any(e.get("method") == method for e in self.events):
            self.events.append(self._message(deadline))

    def pump(self, seconds: float):
        """Take the events that arrive within `seconds` (attaching frames on the way)."""
        deadline = time.monotonic() + seconds
        try:
            while True:
                self.events.append(self._message(deadline))
        except TimeoutError:
            pass

    def open(self, url: str):
        """Load url in the tab and wait for its load event."""
        self.events.clear()
        self.frames.clear()
        self.send("Page.navigate", {"url": url}, session=self.session)
        self.wait_event("Page.loadEventFired")

    def js(self, expression: str, session=None):
        """Evaluate in the page (promises awaited); the value, or an error with the page's exception."""
        out = self.send("Runtime.evaluate", {"expression": expression, "returnByValue": True, "awaitPromise": True},
                        session=session or self.session)
        if "exceptionDetails" in out:
            raise RuntimeError(f"{expression}: {out['exceptionDetails']}")
        return out["result"].get("value")

    def frame_session(self, timeout: float | None = None) -> str:
        """The session of the last attached iframe target (waiting for one to attach)."""
        deadline = time.monotonic() + (self.timeout if timeout is None else timeout)
        while not self.frames:
            self.events.append(self._message(deadline))
        return list(self.frames)[-1]

    def frame_js(self, expression: str, session=None, tries: int = 3):
        """Evaluate in an iframe's own page (the last attached one unless a session is given).  An iframe that
        navigates while it is asked (its page replaced as it loads) is asked again once the events so far are
        taken: in the same target if it is still attached, else in the last attached one."""
        for attempt in range(tries):
            target = session if session in self.frames else self.frame_session()
            try:
                return self.js(expression, session=target)
            except RuntimeError as error:
                if "navigated or closed" not in str(error) or attempt == tries - 1:
                    raise
                self.pump(0.2)

    def screenshot(self, path) -> np.ndarray:
        """After two animation frames (so the last change is rendered): a PNG to path, as an RGB array."""
        self.js("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
        png = base64.b64decode(self.send("Page.captureScreenshot", {"format": "png"}, session=self.session)["data"])
        with open(path, "wb") as f:
            f.write(png)
        return np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)

    def requests(self) -> list:
        """URLs requested by the page and its frames."""
        return [e["params"]["request"]["url"] for e in self.events if e.get("method") == "Network.requestWillBeSent"]

    def page_errors(self) -> list:
        """Uncaught exceptions in the page and its frames."""
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
        try:
            os.killpg(self.proc.pid, 9)              # any helper process left in its session
        except (ProcessLookupError, PermissionError):
            pass
        os.close(self._w)
        os.close(self._r)
        self.log.close()
        shutil.rmtree(self.profile, ignore_errors=True)
