"""What every page of the viewer carries besides its commands: meshcat's viewer script, compressed, and the
small script that unpacks it and keeps the view well-behaved.

meshcat's bundled viewer (three.js included, main.min.js) is 853 kB; LZMA brings it to ~180 kB, 225 kB in
base 85, so an inline view of a few seconds stays under 300 kB in a saved notebook (gzip, which the
browser's DecompressionStream reads, leaves 217 kB, 289 kB as base64: too much with the commands).  The
page decodes it with a 3 kB LZMA and base-85 decoder written here (LZMA after Igor Pavlov's public-domain
LzmaSpec), in the page itself and synchronously: nothing is fetched, nothing waits for a promise.

The runtime (RUNTIME, run before meshcat's script):
  * rendering pauses while the page is out of sight — its tab hidden (visibilitychange), or its frame
    scrolled out of the window or hidden (an IntersectionObserver on the page) — and resumes on return:
    requestAnimationFrame is wrapped so that a callback due while out of sight is held, and run when the
    page is seen again (meshcat's render loop, the time line, anything else);  rbView.callbacks counts
    the callbacks run, rbView.paused says whether the page is paused;
  * meshcat's controls panel scrolls inside the frame, so "Close Controls" and every folder stay reachable
    in a 420 px frame;
  * rbNote(text) shows a message over the view (the live view: its server is gone).
"""
from __future__ import annotations

import base64
import functools
import hashlib
import lzma
import os
from importlib import resources
from pathlib import Path

import meshcat.geometry as g

VIEWER_JS = Path(os.path.dirname(g.__file__)) / "viewer" / "dist" / "main.min.js"


# Base 85 (5 characters for 4 bytes, where base64 takes 5.33): Python's b85 alphabet (RFC 1924) with its
# four characters that a page's HTML attribute or script would have to escape (& < > `) replaced by
# four it does not use (, . : ]).  None of the 85 needs escaping in a srcdoc attribute, a JavaScript
# string or a notebook's JSON.
_B85 = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz!#$%&()*+-;<=>?@^_`{|}~"
ALPHABET = _B85.translate(str.maketrans("&<>`", ",.:]"))
_TO_SAFE, _FROM_SAFE = str.maketrans(_B85, ALPHABET), str.maketrans(ALPHABET, _B85)


def compress(data: bytes) -> tuple[str, int]:
    """data as LZMA ("alone" format, lc 3 lp 0 pb 2, preset 9: its "extreme" variant took twice as long for
    pages 0.3 % smaller) in base 85 (ALPHABET, padded to whole 4-byte groups); and its length (the page decodes
    exactly that many bytes)."""
    dict_size = max(1 << 16, 1 << max(len(data) - 1, 1).bit_length())        # the whole input: nothing larger
    packed = lzma.compress(data, format=lzma.FORMAT_ALONE,
                           filters=[{"id": lzma.FILTER_LZMA1, "preset": 9, "dict_size": dict_size}])
    packed += b"\0" * (-len(packed) % 4)
    return base64.b85encode(packed).decode("ascii").translate(_TO_SAFE), len(data)


def compressed_commands(packed: list) -> tuple[str, int]:
    """meshcat commands (each as msgpack bytes) as one compressed buffer of (uint32 little-endian length, bytes):
    what rbCommands (the runtime) applies to a viewer."""
    return compress(b"".join(len(b).to_bytes(4, "little") + b for b in packed))


def decompress(text: str) -> bytes:
    """The inverse of compress (Python's reading, for tests and tools)."""
    reader = lzma.LZMADecompressor(format=lzma.FORMAT_ALONE)
    out = reader.decompress(base64.b85decode(text.translate(_FROM_SAFE)))
    if not reader.eof or reader.unused_data.strip(b"\0"):            # one whole stream, then the padding only
        raise ValueError("text must be the output of compress(): a whole LZMA stream in base 85")
    return out


@functools.lru_cache(maxsize=4)
def _viewer(path: str, mtime_ns: int, size: int) -> tuple[str, int]:
    """The script compressed: read from the user's cache when it holds this very script (its SHA-256 names the
    file), else compressed here (~0.15 s: LZMA preset 9) and kept there for the next process; a cache
    that cannot be written is simply not used."""
    data = Path(path).read_bytes()
    cached = _cache_folder() / f"meshcat-{hashlib.sha256(data).hexdigest()[:32]}.b85"
    try:
        n, text = cached.read_text(encoding="ascii").split("\n", 1)      # its length, then the text
        if int(n) == len(data) and text:
            return text, len(data)
    except (OSError, ValueError, UnicodeDecodeError):
        pass
    text, n = compress(data)
    try:
        cached.parent.mkdir(parents=True, exist_ok=True)
        tmp = cached.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_text(f"{n}\n{text}", encoding="ascii")
        os.replace(tmp, cached)                     # whole or absent: another process may read it now
    except OSError:
        pass
    return text, n


def _cache_folder() -> Path:
    """$RBCOURSE_CACHE_DIR, else $XDG_CACHE_HOME/rbcourse, else ~/.cache/rbcourse."""
    if os.environ.get("RBCOURSE_CACHE_DIR"):
        return Path(os.environ["RBCOURSE_CACHE_DIR"])
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "rbcourse"


def viewer_script() -> tuple[str, int]:
    """meshcat's viewer script as shipped with the meshcat package, compressed (once per process and file version)."""
    st = VIEWER_JS.stat()
    return _viewer(str(VIEWER_JS), st.st_mtime_ns, st.st_size)


CSS = """
  body { margin: 0; }
  #meshcat-pane { width: 100vw; height: 100vh; overflow: hidden; }
  .dg.main > ul { max-height: calc(100vh - 21px); overflow-y: auto; overflow-x: hidden; }
  #rb-info { position: absolute; left: 8px; top: 8px; padding: 6px 9px; font: 13px/1.45 sans-serif; color: #fff;
             background: rgba(0, 0, 0, 0.45); border-radius: 4px; pointer-events: none; max-width: calc(100vw - 290px); }
  #rb-info[hidden] { display: none; }
  #rb-info .sw { display: inline-block; width: 10px; height: 10px; margin-right: 6px; border-radius: 2px; }
  #rb-note { position: absolute; left: 8px; right: 8px; bottom: 8px; padding: 10px 12px; font: bold 15px/1.4 sans-serif;
             color: #fff; background: rgba(160, 20, 20, 0.88); border-radius: 4px; }
  #rb-note[hidden] { display: none; }
"""

LINKED_CSS = """
  body { display: flex; flex-direction: column; height: 100vh; overflow: hidden; }
  #meshcat-pane { height: 60vh; flex: none; position: relative; }
  #rb-plots { flex: 1; min-height: 0; display: flex; flex-direction: column; font: 12px/1.4 sans-serif; color: #222;
              border-top: 1px solid #ccc; background: #fff; }
  #rb-bar { flex: none; display: flex; flex-wrap: wrap; align-items: center; gap: 4px 14px; padding: 4px 8px; }
  #rb-bar .sw { display: inline-block; width: 14px; height: 3px; margin: 0 5px 3px 0; vertical-align: middle; }
  #rb-bar .rb-aside { color: #666; }
  #rb-play { font: 12px sans-serif; padding: 2px 8px; min-width: 72px; }
  #rb-panels { flex: 1; min-height: 0; display: grid; gap: 0 6px; padding: 0 6px 4px; }
  #rb-panels figure { margin: 0; display: flex; flex-direction: column; min-width: 0; min-height: 0; }
  #rb-panels figcaption { flex: none; font-size: 11.5px; white-space: nowrap; overflow: hidden; text-overflow: ellipsis; }
  #rb-panels canvas { flex: 1; width: 100%; min-height: 0; cursor: crosshair; touch-action: none; }
"""
"""A linked view's layout: meshcat's scene on top, the bar (play/pause, the runs' colours) and the plots under it."""

TIMEPLOTS = resources.files(__package__).joinpath("js/timeplots.js").read_text(encoding="utf-8")
"""The linked view's plots (js/timeplots.js), inlined after RUNTIME."""

AFTER = "text/x-rbcourse-after"     # the type of a shared page's scripts held until meshcat's script has come
RUNTIME = "\n".join(resources.files(__package__).joinpath(f"js/{name}.js").read_text(encoding="utf-8")
                    for name in ("runtime", "shared")).replace("%ALPHABET%", ALPHABET).replace("%AFTER%", AFTER)
"""The pages' runtime, plain ES5-ish JavaScript with no dependency: js/runtime.js (pause out of sight, notes, the
LZMA decoder, the words: rbSay) and js/shared.js (rbShared: meshcat's script borrowed from a notebook's first view,
sharing.py)."""


def viewer_tag() -> str:
    """The tag running meshcat's script in a page (an inline view's page borrows it instead: sharing.py)."""
    text, size = viewer_script()
    return script_tag(f'rbScript("{text}", {size});')


def script_tag(js: str) -> str:
    """An inline <script> (a literal "</" inside it closed early: escaped)."""
    return "<script>\n" + js.replace("</", "<\\/") + "\n</script>"
