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
    """data as LZMA ("alone" format, lc 3 lp 0 pb 2) in base 85 (ALPHABET, padded to whole 4-byte groups);
    and its length (the page decodes exactly that many bytes)."""
    dict_size = max(1 << 16, 1 << max(len(data) - 1, 1).bit_length())        # the whole input: nothing larger
    packed = lzma.compress(data, format=lzma.FORMAT_ALONE,
                           filters=[{"id": lzma.FILTER_LZMA1, "preset": 9 | lzma.PRESET_EXTREME, "dict_size": dict_size}])
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
    file), else compressed here (~0.25 s: LZMA at its strongest) and kept there for the next process; a cache
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

# The runtime: pause out of sight, notes, and the LZMA decoder.  Plain ES5-ish JavaScript, no dependency.
RUNTIME = r"""
var ALPHABET = "%ALPHABET%";
(function () {
  // rendering pauses while the page is out of sight (tab hidden, frame scrolled away or hidden)
  var raf = window.requestAnimationFrame.bind(window), held = [], inView = true;
  var rb = window.rbView = {callbacks: 0, paused: false};
  window.requestAnimationFrame = function (cb) {
    return raf(function (ts) {
      if (rb.paused) { held.push(cb); } else { rb.callbacks++; cb(ts); }
    });
  };
  function update() {
    var paused = document.hidden || !inView;
    if (paused === rb.paused) return;
    rb.paused = paused;
    if (paused) return;
    var v = window.viewer;
    if (v && v.animator) {
      if (v.animator.playing) v.animator.clock.getDelta();      // resume where it was, not later
      v.set_dirty();
    }
    var cbs = held; held = [];
    cbs.forEach(function (cb) { window.requestAnimationFrame(cb); });
  }
  document.addEventListener("visibilitychange", update);
  if (window.IntersectionObserver) {
    new IntersectionObserver(function (entries) {
      inView = entries[entries.length - 1].isIntersecting; update();
    }).observe(document.documentElement);
  }
  update();
})();

function rbLiveInfo(viewer) {
  // the live page's title and legend: userData of /meshcat/rb_info (live.info_command), shown as the standalone page
  var node = viewer.scene_tree.children["meshcat"], el = document.getElementById("rb-info");
  node = node && node.children["rb_info"];
  node = node && node.children["<object>"];                // meshcat keeps a set object as the child <object>
  var info = node && node.object && node.object.userData;
  if (!info || !info.title || el.rbShown === info) return;
  el.rbShown = info;
  el.textContent = "";
  var head = document.createElement("div"), b = document.createElement("b");
  b.textContent = info.title; head.appendChild(b); el.appendChild(head);
  (info.legend || []).forEach(function (item) {
    var row = document.createElement("div"), sw = document.createElement("span");
    sw.className = "sw"; sw.style.background = item.color;
    row.appendChild(sw); row.appendChild(document.createTextNode(item.text)); el.appendChild(row);
  });
  el.hidden = false;
}

function rbFitPane(viewer, pane) {
  // meshcat sizes its scene to the window's height: make it size to its pane (a linked view, the explorer)
  var paneSize = viewer.set_3d_pane_size.bind(viewer);
  viewer.set_3d_pane_size = function (w, h) {
    paneSize(w === undefined ? pane.clientWidth : w, h === undefined ? pane.clientHeight : h);
  };
  viewer.set_3d_pane_size();
}

var RB_WORDS = {};          // the page's words in its language (viz/words.py: the page gives them at its start)
function rbSay(key, values) {
  // the page's word `key`, its {placeholders} filled from values
  return String(RB_WORDS[key]).replace(/\{(\w+)\}/g, function (m, k) { return values && k in values ? String(values[k]) : m; });
}

function rbNote(text) {
  var el = document.getElementById("rb-note");
  el.textContent = text; el.hidden = !text;
}

function rbBase85(text) {
  // 5 characters of ALPHABET -> 4 bytes (big-endian), as Python's base64.b85decode
  var digits = new Uint8Array(128), n = text.length / 5, out = new Uint8Array(4 * n), i, j;
  for (i = 0; i < ALPHABET.length; i++) digits[ALPHABET.charCodeAt(i)] = i;
  for (i = 0, j = 0; i < n; i++) {
    var k = 5 * i, v = digits[text.charCodeAt(k)];
    v = v * 85 + digits[text.charCodeAt(k + 1)]; v = v * 85 + digits[text.charCodeAt(k + 2)];
    v = v * 85 + digits[text.charCodeAt(k + 3)]; v = v * 85 + digits[text.charCodeAt(k + 4)];
    out[j++] = v / 16777216; out[j++] = (v >>> 16) & 255; out[j++] = (v >>> 8) & 255; out[j++] = v & 255;
  }
  return out;
}

function rbLzma(text, size) {
  // LZMA ("alone" format: props, dictionary size, length, then the range-coded stream), in base 85 -> Uint8Array(size)
  var src = rbBase85(text), i;
  var d = src[0], lc = d % 9; d = (d / 9) | 0;
  var lp = d % 5, pb = (d / 5) | 0;
  var out = new Uint8Array(size), ip = 14, range = 0xFFFFFFFF, code = 0;
  for (i = 0; i < 4; i++) code = ((code << 8) | src[ip++]) >>> 0;
  function probs(k) { var p = new Uint16Array(k); p.fill(1024); return p; }
  function bit(p, k) {
    var v = p[k], bound = (range >>> 11) * v, b;
    if (code < bound) { range = bound; p[k] = v + ((2048 - v) >> 5); b = 0; }
    else { range -= bound; code -= bound; p[k] = v - (v >> 5); b = 1; }
    if (range < 0x1000000) { range = (range << 8) >>> 0; code = ((code << 8) | src[ip++]) >>> 0; }
    return b;
  }
  function direct(nb) {
    var r = 0;
    for (; nb > 0; nb--) {
      range = range >>> 1;
      var t = 0;
      if (code >= range) { code -= range; t = 1; }
      r = r * 2 + t;
      if (range < 0x1000000) { range = (range << 8) >>> 0; code = ((code << 8) | src[ip++]) >>> 0; }
    }
    return r;
  }
  function tree(p, base, nb) { var m = 1; for (var j = 0; j < nb; j++) m = (m << 1) | bit(p, base + m); return m - (1 << nb); }
  function rtree(p, base, nb) {
    var m = 1, s = 0;
    for (var j = 0; j < nb; j++) { var b = bit(p, base + m); m = (m << 1) | b; s |= b << j; }
    return s;
  }
  function len(p, ps) {
    if (!bit(p, 0)) return tree(p, 2 + ps * 8, 3);
    if (!bit(p, 1)) return 8 + tree(p, 130 + ps * 8, 3);
    return 16 + tree(p, 258, 8);
  }
  var isMatch = probs(192), isRep = probs(12), isRepG0 = probs(12), isRepG1 = probs(12), isRepG2 = probs(12);
  var isRep0Long = probs(192), lit = probs(0x300 << (lc + lp)), posSlot = probs(256), posDec = probs(115);
  var align = probs(16), matchLen = probs(514), repLen = probs(514);
  var state = 0, rep0 = 0, rep1 = 0, rep2 = 0, rep3 = 0, op = 0, pbMask = (1 << pb) - 1, lpMask = (1 << lp) - 1;
  while (op < size) {
    var ps = op & pbMask, k;
    if (!bit(isMatch, (state << 4) + ps)) {                         // a literal byte
      var base = 0x300 * (((op & lpMask) << lc) + ((op > 0 ? out[op - 1] : 0) >> (8 - lc))), s = 1;
      if (state >= 7) {
        var mb = out[op - rep0 - 1];
        do {
          var mbit = (mb >> 7) & 1; mb <<= 1;
          var b = bit(lit, base + ((1 + mbit) << 8) + s);
          s = (s << 1) | b;
          if (mbit !== b) break;
        } while (s < 0x100);
      }
      while (s < 0x100) s = (s << 1) | bit(lit, base + s);
      out[op++] = s - 0x100;
      state = state < 4 ? 0 : (state < 10 ? state - 3 : state - 6);
      continue;
    }
    if (bit(isRep, state)) {                                        // a repeated distance
      if (!bit(isRepG0, state)) {
        if (!bit(isRep0Long, (state << 4) + ps)) {
          state = state < 7 ? 9 : 11;
          if (rep0 >= op) throw new Error("corrupt LZMA data");
          out[op] = out[op - rep0 - 1]; op++;
          continue;
        }
      } else {
        var dist;
        if (!bit(isRepG1, state)) dist = rep1;
        else { if (!bit(isRepG2, state)) dist = rep2; else { dist = rep3; rep3 = rep2; } rep2 = rep1; }
        rep1 = rep0; rep0 = dist;
      }
      k = len(repLen, ps);
      state = state < 7 ? 8 : 11;
    } else {                                                        // a match: its length, then its distance
      rep3 = rep2; rep2 = rep1; rep1 = rep0;
      k = len(matchLen, ps);
      state = state < 7 ? 7 : 10;
      var slot = tree(posSlot, (k < 3 ? k : 3) << 6, 6);
      if (slot < 4) rep0 = slot;
      else {
        var nd = (slot >> 1) - 1, dd = (2 | (slot & 1)) * Math.pow(2, nd);
        if (slot < 14) dd += rtree(posDec, dd - slot, nd);
        else dd += direct(nd - 4) * 16 + rtree(align, 0, 4);
        rep0 = dd;
      }
    }
    if (rep0 >= op) throw new Error("corrupt LZMA data");
    for (k += 2, i = op - rep0 - 1; k > 0 && op < size; k--) out[op++] = out[i++];
  }
  return out;
}

function rbScript(text, size) {
  // run a compressed script now, in the page's global scope (as an inline <script> would)
  var s = document.createElement("script");
  s.text = new TextDecoder().decode(rbLzma(text, size));
  document.head.appendChild(s);
}

function rbTimeline(viewer, t0, speed, duration, words) {
  // the time line ("t = 1.23 s", simulated time), and the URL fragment: #t=1.5 shows that time, paused;
  // #controls=hidden hides meshcat's controls (for stills); a bad t says so and plays the animation
  RB_WORDS = words;
  var el = document.getElementById("rb-time"), t1 = t0 + speed * duration;
  function tick() {
    var tau = viewer.animator.actions.reduce(function (acc, a) { return Math.max(acc, a.time); }, 0);
    var t = t0 + speed * (duration ? tau : 0);
    el.textContent = "t = " + t.toFixed(2) + " s" + (speed != 1 ? rbSay("played_at", { speed: speed }) : "");
    requestAnimationFrame(tick);
  }
  function fragment() {
    var q = new URLSearchParams(location.hash.slice(1)), note = "";
    if (q.has("t")) {
      var t = Number(q.get("t"));
      if (q.get("t") === "" || !isFinite(t) || t < t0 - 1e-9 * (1 + Math.abs(t0)) || t > t1 + 1e-9 * (1 + Math.abs(t1))) {
        note = rbSay("bad_t", { t: q.get("t"), t0: t0, t1: t1 });
      } else if (duration) {
        viewer.animator.pause();
        var tau = Math.min(Math.max((t - t0) / speed, 0), duration);
        viewer.animator.seek(tau);
        viewer.animator.display_progress(tau);                       // meshcat's time slider too
      }
    }
    viewer.gui.domElement.style.display = q.get("controls") === "hidden" ? "none" : "";
    rbNote(note);
    if (q.has("sheet")) sheet(q);
  }
  function sheet(q) {
    // #sheet=N&w=W&h=H&cols=C: N frames evenly over the animation, each W x H px, drawn on a C-column
    // contact sheet over the page (for a GIF: the sheet is one screenshot, cut into frames)
    var n = Number(q.get("sheet")), w = Number(q.get("w")), h = Number(q.get("h")), cols = Number(q.get("cols"));
    var rows = Math.ceil(n / cols), c = document.createElement("canvas"), ctx = c.getContext("2d");
    c.width = cols * w; c.height = rows * h;
    c.style.cssText = "position: absolute; left: 0; top: 0; z-index: 10";
    viewer.animator.pause();
    viewer.set_3d_pane_size(w, h);
    ctx.font = "bold 14px sans-serif";
    for (var i = 0; i < n; i++) {
      var tau = n > 1 ? duration * i / (n - 1) : 0, x = (i % cols) * w, y = Math.floor(i / cols) * h;
      viewer.animator.seek(tau);
      viewer.render();
      ctx.drawImage(viewer.renderer.domElement, x, y, w, h);
      var label = "t = " + (t0 + speed * tau).toFixed(2) + " s";
      ctx.fillStyle = "rgba(0, 0, 0, 0.45)";
      ctx.fillRect(x + 6, y + 6, ctx.measureText(label).width + 14, 24);
      ctx.fillStyle = "#fff";
      ctx.fillText(label, x + 13, y + 23);
    }
    document.body.appendChild(c);
    window.rbSheet = n;
  }
  fragment();
  window.addEventListener("hashchange", fragment);
  tick();
}

function rbCommands(viewer, text, size) {
  // apply meshcat commands given as one compressed buffer of (uint32 little-endian length, msgpack bytes)
  var buf = rbLzma(text, size), dv = new DataView(buf.buffer), i = 0;
  while (i < buf.length) {
    var n = dv.getUint32(i, true);
    viewer.handle_command_bytearray(buf.slice(i + 4, i + 4 + n));
    i += 4 + n;
  }
}
"""


AFTER = "text/x-rbcourse-after"     # the type of a shared page's scripts held until meshcat's script has come
RUNTIME = (RUNTIME + "\n" + resources.files(__package__).joinpath("js/shared.js").read_text(encoding="utf-8")
           ).replace("%ALPHABET%", ALPHABET).replace("%AFTER%", AFTER)      # js/shared.js: rbShared (sharing.py)


def viewer_tag() -> str:
    """The tag running meshcat's script in a page (an inline view's page borrows it instead: sharing.py)."""
    text, size = viewer_script()
    return script_tag(f'rbScript("{text}", {size});')


def script_tag(js: str) -> str:
    """An inline <script> (a literal "</" inside it closed early: escaped)."""
    return "<script>\n" + js.replace("</", "<\\/") + "\n</script>"
