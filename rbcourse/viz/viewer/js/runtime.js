// The 3-D pages' runtime (viewer/assets.py RUNTIME): pause out of sight, notes, the LZMA decoder, the words (rbSay).
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
