"""A Drawing: the lowered meshcat commands of a still or an animation, and the page that shows them —
standalone (meshcat's viewer script and the commands inlined: works offline, loads nothing), or
inline in JupyterLab (an iframe holding the page, no server).  Drawing.show() sends it to the live
server (live.py)."""
from __future__ import annotations

import base64
import html as _html
import os
from pathlib import Path

import meshcat.geometry as g
import numpy as np
import umsgpack


_JS_PATH = Path(os.path.dirname(g.__file__)) / "viewer" / "dist" / "main.min.js"


class Drawing:
    """What a viewer shows: lowered meshcat commands (dicts), in the order they are applied.

    commands: set_object / set_transform / set_property, then at most one set_animation.
    duration: playback length in seconds (0 for a still); t0, speed: the simulated time
    shown at playback time τ is t0 + speed·τ.  arrow_scales: metres per unit of each
    kind of arrow ("omega": m per rad/s, "L": m per kg m²/s, "force": m per N).
    """

    def __init__(self, commands, *, duration=0.0, t0=0.0, speed=1.0, title="rbcourse", legend=(),
                 arrow_scales=None, frame_times=None):
        self.commands = list(commands)
        self.duration = float(duration)
        self.t0 = float(t0)
        self.speed = float(speed)
        self.title = str(title)
        self.legend = list(legend)
        self.arrow_scales = dict(arrow_scales or {})
        self.frame_times = None if frame_times is None else np.asarray(frame_times, dtype=float)

    def __repr__(self) -> str:
        kind = f"an animation of {self.duration:g} s" if self.duration else "a still"
        return f"<Drawing {self.title!r}: {kind}, {len(self.commands)} meshcat commands>"

    @property
    def animation(self) -> dict | None:
        """The set_animation command, or None for a still."""
        return next((c for c in self.commands if c["type"] == "set_animation"), None)

    def packed(self) -> list[bytes]:
        """Each command as the msgpack bytes meshcat's viewer decodes."""
        return [umsgpack.packb(c) for c in self.commands]

    def html(self, *, title: str | None = None) -> str:
        """A standalone page: meshcat's viewer script and the commands inlined.

        It works from a file, offline, and loads no external resource: the script is
        embedded, and the commands are base64 strings decoded synchronously in order
        (meshcat's own static_html goes through fetch() of data: URLs, unordered).
        """
        if title is not None and not isinstance(title, str):
            raise ValueError(f"title must be a string or None, got {title!r}")
        title = self.title if title is None else title
        blobs = ",\n".join(f'"{base64.b64encode(b).decode("ascii")}"' for b in self.packed())
        legend = "".join(f'<div><span class="sw" style="background:#{c:06x}"></span>{_html.escape(t)}</div>'
                         for c, t in self.legend)
        return _PAGE.format(title=_html.escape(title), script=_viewer_script(), commands=blobs, legend=legend,
                            t0=repr(self.t0), speed=repr(self.speed), animated="true" if self.duration else "false")

    def save(self, path) -> Path:
        """Write the standalone page (html()) to path; returns the path."""
        if not isinstance(path, (str, os.PathLike)):
            raise ValueError(f"path must be a file path, got {path!r}")
        path = Path(path)
        path.write_text(self.html(), encoding="utf-8")
        return path

    def _repr_html_(self) -> str:
        """JupyterLab / Jupyter: the recorded drawing inline (an iframe holding the page; no server)."""
        return iframe(srcdoc=self.html(), height=420)

    def show(self, server: "LiveServer | None" = None) -> "LiveView":
        """Send to the live viewer (this process's server unless one is given); returns a LiveView."""
        from .live import LiveServer, LiveView, live_server        # the page needs no server: only show() does
        if server is None:
            server = live_server()
        elif not isinstance(server, LiveServer):
            raise ValueError(f"server must be a LiveServer or None, got {server!r}")
        server.draw(self)
        return LiveView(server.url)


def iframe(*, height: int, src: str | None = None, srcdoc: str | None = None) -> str:
    """A resizable box holding an iframe on src (a URL) or srcdoc (a whole page)."""
    attr = f'src="{_html.escape(src)}"' if src is not None else f'srcdoc="{_html.escape(srcdoc)}"'
    return (f'<div style="height:{height}px;width:100%;overflow:hidden;resize:both">'
            f'<iframe {attr} style="width:100%;height:100%;border:none"></iframe></div>')


def _viewer_script() -> str:
    """meshcat's bundled viewer (three.js included), as shipped with the meshcat package."""
    return _JS_PATH.read_text(encoding="utf-8")

_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>{title}</title>
<style>
  body {{ margin: 0; }}
  #meshcat-pane {{ width: 100vw; height: 100vh; overflow: hidden; }}
  #rb-info {{ position: absolute; left: 8px; top: 8px; padding: 6px 9px; font: 13px/1.45 sans-serif;
             color: #fff; background: rgba(0, 0, 0, 0.45); border-radius: 4px; pointer-events: none; }}
  #rb-info .sw {{ display: inline-block; width: 10px; height: 10px; margin-right: 6px; border-radius: 2px; }}
</style>
</head>
<body>
<div id="meshcat-pane"></div>
<div id="rb-info"><div><b>{title}</b></div><div id="rb-time"></div>{legend}</div>
<script>
{script}
</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
(function (commands) {{
  for (const c of commands) {{
    viewer.handle_command_bytearray(Uint8Array.from(atob(c), ch => ch.charCodeAt(0)));
  }}
}})([
{commands}
]);
(function (t0, speed, animated) {{
  var el = document.getElementById("rb-time");
  function tick() {{
    var tau = viewer.animator.actions.reduce((acc, a) => Math.max(acc, a.time), 0);
    var t = t0 + speed * (animated ? tau : 0);
    el.textContent = "t = " + t.toFixed(2) + " s" + (speed != 1 ? "  (played at \\u00d7" + speed + ")" : "");
    requestAnimationFrame(tick);
  }}
  tick();
}})({t0}, {speed}, {animated});
</script>
</body>
</html>
"""
