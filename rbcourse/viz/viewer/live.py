"""The live viewer: one meshcat server per process, on 127.0.0.1 only, started on first use and
closed at exit (or by close_live_server); a LiveView is its address, shown in JupyterLab as an iframe
(reachable only from the kernel's machine).  The server serves our live page (live_page: meshcat's viewer,
paused out of sight, saying when its server is gone) and accepts a websocket from a sandboxed frame
(origin "null") only with its token."""
from __future__ import annotations

import atexit
import html as _html
import json
import os
import secrets
import shutil
import subprocess
import sys
import tempfile
import time

from meshcat.animation import Animation
from meshcat.commands import Delete, SetAnimation
from meshcat.path import Path as MeshcatPath

from ...support import checks
from ...support.language import current, say
from . import assets
from ..frame import INLINE_HEIGHT, iframe, trust_hint
from .commands import pack
from .recording import Recording


class LiveView:
    """The live viewer's address; in JupyterLab it shows as a sandboxed iframe on it (the kernel's machine).

    The saved output points at no dead port: the frame holds a small page that first tries the server's
    websocket (with this server's token) and only then opens the live page; if the server is gone
    (the kernel restarted, the notebook reopened later) it says so instead.  The live page itself says
    when its connection closes.  Untrusted, the output shows its text: what it is and what it needs.
    """

    def __init__(self, url: str, height: int = INLINE_HEIGHT, *, token: str | None = None):
        if not isinstance(url, str) or not url.startswith(("http://", "https://")):
            raise ValueError(f"url must be the live viewer's http(s) URL, got {url!r}")
        if token is not None and (not isinstance(token, str) or not token.replace("-", "").replace("_", "").isalnum()):
            raise ValueError(f"token must be None or the server's token (letters, digits, - and _), got {token!r}")
        self.url = url
        self.height = checks.integer("height", height, low=100, high=4000)
        self.token = token

    def __repr__(self) -> str:
        return f"<LiveView: open {self.url} in a browser>"

    @property
    def frame_url(self) -> str:
        """The page's URL with the server's token (a sandboxed frame has no origin of its own to show)."""
        if self.token is None:
            return self.url
        return self.url + ("&" if "?" in self.url else "?") + "token=" + self.token

    def _text(self) -> str:
        return say(f"live 3-D view at {self.url} (this kernel's meshcat server, 127.0.0.1 only): it shows in a trusted "
                   f"notebook while the kernel runs, in a browser on the kernel's machine ({trust_hint()}); a recorded "
                   "view needs neither: the drawing itself, not d.show()",
                   f"vue 3-D en direct à {self.url} (le serveur meshcat de ce noyau, 127.0.0.1 seulement) : elle "
                   f"s'affiche dans un notebook de confiance tant que le noyau tourne, dans un navigateur sur la machine "
                   f"du noyau ({trust_hint()}) ; une vue enregistrée n'a besoin ni de l'un ni de l'autre : le dessin "
                   "lui-même, pas d.show()")

    def _repr_html_(self) -> str:
        probe = (_PROBE.replace("{lang}", current()).replace("{connecting}", say(*CONNECTING))
                 .replace("{unreachable}", json.dumps(say(UNREACHABLE, UNREACHABLE_FR)))
                 .replace("{url}", json.dumps(self.frame_url).replace("</", "<\\/")))
        return iframe(srcdoc=probe, height=self.height, title=say(f"live 3-D view: meshcat server at {self.url}",
                                                                  f"vue 3-D en direct : serveur meshcat à {self.url}"),
                      fallback=_html.escape(self._text()))

    def _repr_mimebundle_(self, include=None, exclude=None) -> dict:
        return {"text/html": self._repr_html_(), "text/plain": self._text()}


GONE = "The live viewer's server has stopped (kernel restarted?): run the cell again."
UNREACHABLE = ("The live viewer's server cannot be reached: it has stopped (kernel restarted, notebook reopened?): "
               "run the cell again; or it runs on another machine (a remote kernel): show the drawing itself, "
               "recorded, instead of d.show().")
GONE_FR = "Le serveur de la vue en direct s'est arrêté (noyau redémarré ?) : exécutez la cellule à nouveau."
UNREACHABLE_FR = ("Le serveur de la vue en direct est injoignable : il s'est arrêté (noyau redémarré, notebook rouvert ?) :"
                  " exécutez la cellule à nouveau ; ou il tourne sur une autre machine (un noyau distant) : montrez le "
                  "dessin lui-même, enregistré, au lieu de d.show().")
CONNECTING = ("Connecting to the live viewer&hellip;", "Connexion à la vue en direct&hellip;")

# The saved output's page: try the websocket, then open the live page, or say the server is gone.
_PROBE = """<!DOCTYPE html>
<html lang="{lang}"><head><meta charset="utf-8"><title>live 3-D view</title>
<style>body { margin: 0; font: 15px/1.5 sans-serif; } #m { padding: 14px; }</style></head>
<body><div id="m">{connecting}</div>
<script>
(function (url) {
  var ws = new URL("../", url), token = new URL(url).searchParams.get("token"), done = false;
  ws.protocol = ws.protocol === "https:" ? "wss:" : "ws:";
  ws.search = token ? "?token=" + encodeURIComponent(token) : "";
  function gone() {
    if (done) return;
    done = true;
    var m = document.getElementById("m");
    m.textContent = {unreachable};
    m.style.cssText = "padding: 14px; color: #fff; background: #a01414; font-weight: bold";
  }
  try {
    var c = new WebSocket(ws.href);
    c.onopen = function () { done = true; c.close(); location.replace(url); };
    c.onerror = gone; c.onclose = gone;
  } catch (e) { gone(); }
})({url});
</script></body></html>
"""

# The live page the server serves (static/index.html): meshcat's viewer on the websocket, paused out of
# sight, and a note when the connection closes.  The websocket is found from the page's own URL
# (../ of .../static/), so the page works behind a proxy path too.
_LIVE_PAGE = """<!DOCTYPE html>
<html lang="{lang}">
<head>
<meta charset="utf-8">
<title>rbcourse: live viewer (MeshCat)</title>
<style>{css}</style>
</head>
<body>
<div id="meshcat-pane"></div>
<div id="rb-info" hidden></div>
<div id="rb-note" hidden></div>
{runtime}
<script src="main.min.js"></script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
(function () {{
  var ws = new URL("../", location.href), token = new URLSearchParams(location.search).get("token"), opened = false;
  ws.protocol = location.protocol === "https:" ? "wss:" : "ws:";
  ws.search = token ? "?token=" + encodeURIComponent(token) : "";
  ws.hash = "";
  window.rbLive = "connecting";
  var c = viewer.connection = new WebSocket(ws.href);
  c.binaryType = "arraybuffer";
  c.onopen = function () {{ opened = true; window.rbLive = "open"; }};
  c.onmessage = function (msg) {{ viewer.handle_command_message(msg); rbLiveInfo(viewer); }};
  c.onclose = function () {{
    window.rbLive = "closed";
    rbNote(opened ? {gone} : {unreachable});
  }};
}})();
</script>
</body>
</html>
"""


INFO_PATH = ("meshcat", "rb_info")


def info_command(drawing: Recording) -> dict:
    """The drawing's title and legend for the live page, as meshcat can carry them: an empty three.js Object3D at
    /meshcat/rb_info whose userData holds them (the live page reads it after each command and writes its box,
    as the standalone page shows them: rbLiveInfo)."""
    legend = [{"color": f"#{c:06x}", "text": t} for c, t in drawing.legend]
    obj = {"metadata": {"version": 4.5, "type": "Object"}, "geometries": [], "materials": [],
           "object": {"uuid": "rbcourse-info", "type": "Object3D", "name": "rb_info",
                      "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1],
                      "userData": {"title": drawing.title, "legend": legend}}}
    return {"type": "set_object", "path": "/" + "/".join(INFO_PATH), "object": obj}


def live_page() -> str:
    """The live page (served as the server's static/index.html)."""
    return _LIVE_PAGE.format(lang=current(), css=assets.CSS, runtime=assets.script_tag(assets.RUNTIME),
                             gone=json.dumps(say(GONE, GONE_FR)), unreachable=json.dumps(say(UNREACHABLE, UNREACHABLE_FR)))


# meshcat 0.3.2's zmqserver takes its host for the zmq socket and the URL, but its
# tornado file/websocket server calls app.listen(port) with no address: all interfaces.
# We start the same server with listen forced to 127.0.0.1, and make it quit when this
# process is gone (checked every second), so no server outlives its owner.  It serves our live page
# from our folder, and takes a websocket from another origin (a sandboxed frame's is "null") only
# with the token it was given (tornado's own check, same host only, otherwise).
_SERVER_SCRIPT = r"""
import faulthandler, os, sys
faulthandler.dump_traceback_later(float(sys.argv[4]), exit=False)   # a start that hangs says where, on stderr
import tornado.ioloop, tornado.web
_listen = tornado.web.Application.listen
def _loopback_listen(self, port, address=None, **kwargs):
    return _listen(self, port, "127.0.0.1", **kwargs)
tornado.web.Application.listen = _loopback_listen
import hmac
import tornado.websocket
import meshcat.servers.zmqserver as zmqserver
owner, static, token = int(sys.argv[1]), sys.argv[2], sys.argv[3]
zmqserver.VIEWER_ROOT = static          # our live page (index.html) and meshcat's main.min.js
_check_origin = tornado.websocket.WebSocketHandler.check_origin
def _token_or_same_origin(self, origin):
    given = self.get_query_argument("token", "")
    return hmac.compare_digest(given.encode(), token.encode()) or _check_origin(self, origin)
zmqserver.WebSocketHandler.check_origin = _token_or_same_origin
bridge = zmqserver.ZMQWebSocketBridge(host="127.0.0.1")
print("zmq_url=" + bridge.zmq_url, flush=True)
print("web_url=" + bridge.web_url, flush=True)
faulthandler.cancel_dump_traceback_later()
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
        static = os.path.join(self._dir.name, "static")
        os.mkdir(static)
        shutil.copyfile(assets.VIEWER_JS, os.path.join(static, "main.min.js"))
        with open(os.path.join(static, "index.html"), "w", encoding="utf-8") as f:
            f.write(live_page())
        self.token = secrets.token_urlsafe(18)
        self._static = static
        self.proc = None
        self.owner = os.getpid()
        self._socket = None
        try:
            self.zmq_url, self.url = self._start()
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
        return f"<LiveServer {state}, pid {getattr(self.proc, 'pid', '?')}, {self.url if hasattr(self, 'url') else '?'}>"

    @property
    def running(self) -> bool:
        return self.proc is not None and self.proc.poll() is None

    def _start(self):
        """Start the server subprocess; read the two URLs it prints.  A start that hangs (seen once in CI: no URL
        and no word in 60 s, where 0.6 s is usual) is stopped and tried once more; a start that fails is not."""
        window = self.timeout / 2
        hung = ""
        for attempt in (1, 2):
            self.proc = subprocess.Popen(
                [sys.executable, "-u", "-c", _SERVER_SCRIPT, str(os.getpid()), self._static, self.token,
                 repr(0.75 * window)],
                stdin=subprocess.DEVNULL, stdout=self._out, stderr=self._err, start_new_session=True)
            urls = self._read_urls(time.monotonic() + window)
            if urls is not None:
                return urls
            if self.proc.poll() is not None:
                raise RuntimeError(f"the meshcat server did not start (exit code {self.proc.poll()}): {self._stderr()}")
            self._stop_process()
            hung = self._stderr()
            for f in (self._out, self._err):
                f.seek(0)
                f.truncate()
        raise RuntimeError(f"the meshcat server did not start: twice it printed no address within {window:g} s "
                           f"(it was stopped); where it waited:\n{hung}")

    def _read_urls(self, deadline: float):
        while time.monotonic() < deadline:
            self._out.seek(0)
            lines = self._out.read().decode("utf-8", "replace").splitlines()
            urls = dict(line.split("=", 1) for line in lines if line.startswith(("zmq_url=", "web_url=")))
            if len(urls) == 2:
                return urls["zmq_url"], urls["web_url"]
            if self.proc.poll() is not None:
                return None
            time.sleep(0.05)
        return None

    def _stderr(self) -> str:
        self._err.seek(0)
        return self._err.read().decode("utf-8", "replace")[-2000:]

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
        reply = self._request([command["type"].encode(), command.get("path", "").encode(), pack(command)])
        if reply != b"ok":
            raise RuntimeError(f"the meshcat server refused {command['type']}: {reply!r}")

    def draw(self, drawing: Recording):
        """Replace what the viewer shows by a Drawing (page.py; any Recording) (the old drawing and animation are
        cleared)."""
        if not isinstance(drawing, Recording):
            raise ValueError(f"drawing must be a Drawing, got {drawing!r}")
        self.send(Delete(MeshcatPath(("meshcat",))).lower())
        self.send(info_command(drawing))
        for cmd in drawing.commands:
            self.send(cmd)
        if drawing.animation is None:
            self.send(SetAnimation(Animation(), play=False).lower())     # clear a previous animation

    def visualizer(self):
        """A meshcat.Visualizer on this server, for meshcat's own API (it prints the URL)."""
        import meshcat
        return meshcat.Visualizer(zmq_url=self.zmq_url)

    def _stop_process(self):
        if self.proc is not None and self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()

    def close(self):
        """Stop the server subprocess (meshcat 0.3.2's Visualizer.close() is broken) and our socket."""
        if self._socket is not None:
            self._socket.close(linger=0)
            self._context.term()
            self._socket = None
        self._stop_process()
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
