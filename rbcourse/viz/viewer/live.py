"""The live viewer: one meshcat server per process, on 127.0.0.1 only, started on first use and
closed at exit (or by close_live_server); a LiveView is its address, shown in JupyterLab as an iframe
(reachable only from the kernel's machine)."""
from __future__ import annotations

import atexit
import os
import subprocess
import sys
import tempfile
import time

import umsgpack
from meshcat.animation import Animation
from meshcat.commands import Delete, SetAnimation
from meshcat.path import Path as MeshcatPath

from ... import checks
from .page import Drawing, iframe


class LiveView:
    """The live viewer's address; in JupyterLab it shows as an iframe on it (the kernel's machine)."""

    def __init__(self, url: str, height: int = 420):
        self.url = url
        self.height = height

    def __repr__(self) -> str:
        return f"<LiveView: open {self.url} in a browser>"

    def _repr_html_(self) -> str:
        return iframe(src=self.url, height=self.height)


# meshcat 0.3.2's zmqserver takes its host for the zmq socket and the URL, but its
# tornado file/websocket server calls app.listen(port) with no address: all interfaces.
# We start the same server with listen forced to 127.0.0.1, and make it quit when this
# process is gone (checked every second), so no server outlives its owner.
_SERVER_SCRIPT = r"""
import os, sys
import tornado.ioloop, tornado.web
_listen = tornado.web.Application.listen
def _loopback_listen(self, port, address=None, **kwargs):
    return _listen(self, port, "127.0.0.1", **kwargs)
tornado.web.Application.listen = _loopback_listen
import meshcat.servers.zmqserver as zmqserver
owner = int(sys.argv[1])
bridge = zmqserver.ZMQWebSocketBridge(host="127.0.0.1")
print("zmq_url=" + bridge.zmq_url, flush=True)
print("web_url=" + bridge.web_url, flush=True)
def _check_owner():
    if os.getppid() != owner:
        bridge.ioloop.stop()
tornado.ioloop.PeriodicCallback(_check_owner, 1000).start()
bridge.run()
"""


class LiveServer:
    """A meshcat server subprocess (tornado + zmq, 127.0.0.1 only) and our zmq socket to it.

    Use live_server() for the process's one server.  Nothing here waits for a browser:
    each command waits only for the server's "ok" (at most `timeout` seconds).
    """

    def __init__(self, *, timeout: float = 60.0):
        import zmq
        self.timeout = checks.positive("timeout", timeout)
        self._dir = tempfile.TemporaryDirectory(prefix="rbcourse-meshcat-")
        self._out = open(os.path.join(self._dir.name, "stdout.txt"), "w+b")
        self._err = open(os.path.join(self._dir.name, "stderr.txt"), "w+b")
        self.proc = subprocess.Popen([sys.executable, "-u", "-c", _SERVER_SCRIPT, str(os.getpid())],
                                     stdin=subprocess.DEVNULL, stdout=self._out, stderr=self._err,
                                     start_new_session=True)
        self.owner = os.getpid()
        self._socket = None
        try:
            self.zmq_url, self.url = self._read_urls()
            self._context = zmq.Context()
            self._socket = self._context.socket(zmq.REQ)
            ms = int(self.timeout * 1000)
            self._socket.setsockopt(zmq.RCVTIMEO, ms)
            self._socket.setsockopt(zmq.SNDTIMEO, ms)
            self._socket.setsockopt(zmq.LINGER, 0)
            self._socket.connect(self.zmq_url)
            self._request([b"url"])
        except BaseException:
            self.close()
            raise

    def __repr__(self) -> str:
        state = "running" if self.running else "stopped"
        return f"<LiveServer {state}, pid {self.proc.pid}, {self.url if hasattr(self, 'url') else '?'}>"

    @property
    def running(self) -> bool:
        return self.proc.poll() is None

    def _read_urls(self):
        deadline = time.monotonic() + self.timeout
        while time.monotonic() < deadline:
            self._out.seek(0)
            lines = self._out.read().decode("utf-8", "replace").splitlines()
            urls = dict(line.split("=", 1) for line in lines if line.startswith(("zmq_url=", "web_url=")))
            if len(urls) == 2:
                return urls["zmq_url"], urls["web_url"]
            if self.proc.poll() is not None:
                break
            time.sleep(0.05)
        self._err.seek(0)
        err = self._err.read().decode("utf-8", "replace")[-2000:]
        raise RuntimeError(f"the meshcat server did not start (exit code {self.proc.poll()}): {err}")

    def _request(self, frames: list[bytes]) -> bytes:
        import zmq
        if self._socket is None or not self.running:
            raise RuntimeError("the meshcat server is closed: use live_server() for a new one")
        try:
            self._socket.send_multipart(frames)
            return self._socket.recv()
        except zmq.Again:
            self.close()
            raise RuntimeError(f"the meshcat server did not answer within {self.timeout:g} s; it was closed") from None

    def send(self, command: dict):
        """Send one lowered meshcat command; waits only for the server's acknowledgement."""
        reply = self._request([command["type"].encode(), command.get("path", "").encode(), umsgpack.packb(command)])
        if reply != b"ok":
            raise RuntimeError(f"the meshcat server refused {command['type']}: {reply!r}")

    def draw(self, drawing: Drawing):
        """Replace what the viewer shows by a Drawing (the old drawing and animation are cleared)."""
        if not isinstance(drawing, Drawing):
            raise ValueError(f"drawing must be a Drawing, got {drawing!r}")
        self.send(Delete(MeshcatPath(("meshcat",))).lower())
        for cmd in drawing.commands:
            self.send(cmd)
        if drawing.animation is None:
            self.send(SetAnimation(Animation(), play=False).lower())     # clear a previous animation

    def visualizer(self):
        """A meshcat.Visualizer on this server, for meshcat's own API (it prints the URL)."""
        import meshcat
        return meshcat.Visualizer(zmq_url=self.zmq_url)

    def close(self):
        """Stop the server subprocess (meshcat 0.3.2's Visualizer.close() is broken) and our socket."""
        if self._socket is not None:
            self._socket.close(linger=0)
            self._context.term()
            self._socket = None
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        for f in (self._out, self._err):
            f.close()
        self._dir.cleanup()


_live = {"server": None, "atexit": False}      # this process's one server (not a switch: a registry)


def live_server(*, timeout: float = 60.0) -> LiveServer:
    """This process's meshcat server, started on first use and reused; stopped at exit."""
    server = _live["server"]
    if server is not None and server.owner == os.getpid() and server.running:
        return server
    if server is not None and server.owner == os.getpid():
        server.close()
    _live["server"] = LiveServer(timeout=timeout)
    if not _live["atexit"]:
        atexit.register(close_live_server)
        _live["atexit"] = True
    return _live["server"]


def close_live_server() -> bool:
    """Stop this process's server if there is one; True if one was stopped."""
    server = _live["server"]
    _live["server"] = None
    if server is None or server.owner != os.getpid():
        return False
    server.close()
    return True


def live_server_pids() -> list[int]:
    """Process ids of the meshcat servers this process has running (0 or 1 of them)."""
    server = _live["server"]
    if server is None or server.owner != os.getpid() or not server.running:
        return []
    return [server.proc.pid]
