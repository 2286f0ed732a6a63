/* Plots over time under meshcat's scene, with one time cursor shared with its animation (the linked view of
   draw_trajectory(..., plots=True); linked.py makes the data).  The cursor is the animation's time: meshcat's
   animator plays, the cursor follows; a click or a drag on a plot pauses it and seeks there (animator.seek),
   and the 3-D scene follows.  Log axes, with a row under the floor for the values that are exactly 0; a gap
   where a curve has no value (before t₀); a dotted line where a run diverged.  Plain canvas 2-D, no library. */
var RB_SUP = { "0": "⁰", "1": "¹", "2": "²", "3": "³", "4": "⁴", "5": "⁵", "6": "⁶", "7": "⁷", "8": "⁸", "9": "⁹", "-": "⁻" };
function rbPow10(e) {
  return e === 0 ? "1" : "10" + String(e).split("").map(function (c) { return RB_SUP[c] || c; }).join("");
}
function rbSci(v) {
  if (v === 0) return "exactly 0";
  if (v >= 1e300) return "∞ (overflow)";
  var e = Math.floor(Math.log10(v)), m = v / Math.pow(10, e);
  if (m >= 9.95) { m /= 10; e += 1; }
  return e >= -2 && e <= 3 ? String(Number(v.toPrecision(3))) : m.toFixed(2) + "×" + rbPow10(e);
}

function RbPlot(host, panel, data, span, seek) {
  var fig = document.createElement("figure"), cap = document.createElement("figcaption");
  cap.textContent = panel.title; cap.title = panel.note;
  this.canvas = document.createElement("canvas");
  this.canvas.dataset.key = panel.key;
  this.canvas.setAttribute("aria-label", panel.title + " over time: click or drag to move the time cursor");
  fig.appendChild(cap); fig.appendChild(this.canvas); host.appendChild(fig);
  this.panel = panel; this.data = data; this.span = span; this.M = { l: 62, r: 10, t: 16, b: 24 };
  var self = this, drag = false;
  function at(e) {
    var r = self.canvas.getBoundingClientRect();
    seek(self.T(e.clientX - r.left));
  }
  this.canvas.addEventListener("pointerdown", function (e) {
    drag = true; if (self.canvas.setPointerCapture) self.canvas.setPointerCapture(e.pointerId); at(e);
  });
  this.canvas.addEventListener("pointermove", function (e) { if (drag) at(e); });
  this.canvas.addEventListener("pointerup", function () { drag = false; });
}
RbPlot.prototype.X = function (t) {
  return this.M.l + (t - this.span[0]) / (this.span[1] - this.span[0] || 1) * (this.w - this.M.l - this.M.r);
};
RbPlot.prototype.T = function (x) {
  var f = (x - this.M.l) / (this.w - this.M.l - this.M.r);
  return this.span[0] + Math.min(Math.max(f, 0), 1) * (this.span[1] - this.span[0]);
};
RbPlot.prototype.Y = function (v) {            // log scale; 0 on its own row under the floor
  var lo = this.data.log[0], hi = this.data.log[1], bottom = this.h - this.M.b - 16;
  if (v === 0) return this.h - this.M.b - 6;
  var e = Math.min(Math.max(Math.log10(v), lo), hi);
  return bottom - (e - lo) / (hi - lo) * (bottom - this.M.t);
};
RbPlot.prototype.draw = function (t) {
  var c = this.canvas, dpr = window.devicePixelRatio || 1, M = this.M;
  this.w = c.clientWidth; this.h = c.clientHeight;
  if (c.width !== Math.round(this.w * dpr) || c.height !== Math.round(this.h * dpr)) {
    c.width = Math.round(this.w * dpr); c.height = Math.round(this.h * dpr);
  }
  var g = c.getContext("2d"), w = this.w, h = this.h, lo = this.data.log[0], hi = this.data.log[1];
  g.setTransform(dpr, 0, 0, dpr, 0, 0);
  g.fillStyle = "#fff"; g.fillRect(0, 0, w, h);
  g.fillStyle = "#f0f0f0"; g.fillRect(M.l, h - M.b - 12, w - M.l - M.r, 12);          // the exact zeros' row
  g.font = "10.5px sans-serif"; g.textAlign = "right"; g.textBaseline = "middle";
  for (var e = Math.ceil(lo); e <= hi; e++) {
    if ((e - Math.ceil(lo)) % 4) continue;
    var y = this.Y(Math.pow(10, e));
    g.strokeStyle = "#e6e6e6"; g.beginPath(); g.moveTo(M.l, y); g.lineTo(w - M.r, y); g.stroke();
    g.fillStyle = "#444"; g.fillText(rbPow10(e), M.l - 4, y);
  }
  g.fillText("exactly 0", M.l - 4, this.Y(0));
  var n = Math.max(2, Math.floor((w - M.l - M.r) / 70)), raw = (this.span[1] - this.span[0]) / n;
  var k = Math.pow(10, Math.floor(Math.log10(raw || 1))), m = raw / k;
  var step = (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * k, digits = Math.max(0, -Math.floor(Math.log10(step)));
  g.textAlign = "center"; g.textBaseline = "top";
  for (var s = Math.ceil(this.span[0] / step) * step; s <= this.span[1] + 1e-9 * step; s += step) {
    g.fillStyle = "#444"; g.fillText(s.toFixed(digits), this.X(s), h - M.b + 4);
  }
  g.textAlign = "left"; g.fillText("t (s)", 4, h - M.b + 4);
  if (this.data.t0 > this.span[0]) {                                  // before t₀: no drift
    g.fillStyle = "rgba(0,0,0,0.06)"; g.fillRect(M.l, M.t, this.X(this.data.t0) - M.l, h - M.t - M.b);
  }
  g.strokeStyle = "#999"; g.lineWidth = 1; g.strokeRect(M.l + 0.5, M.t + 0.5, w - M.l - M.r - 1, h - M.t - M.b - 1);
  var self = this, readout = [];
  this.panel.curves.forEach(function (cv) {
    var series = self.data.series[cv.s], pen = false, last = null;
    g.strokeStyle = series.color; g.lineWidth = 1.6; g.beginPath();
    for (var i = 0; i < cv.t.length; i++) {
      if (cv.v[i] === null) { pen = false; continue; }
      var x = self.X(cv.t[i]), y = self.Y(cv.v[i]);
      if (pen) g.lineTo(x, y); else g.moveTo(x, y);
      pen = true; last = i;
    }
    g.stroke();
    if (series.end !== null) {
      var xd = self.X(series.end);
      g.setLineDash([3, 3]); g.beginPath(); g.moveTo(xd, M.t); g.lineTo(xd, h - M.b); g.stroke(); g.setLineDash([]);
    }
    var j = self.index(cv.t, t);
    if (j !== null && cv.v[j] !== null && t <= cv.t[cv.t.length - 1] + 1e-9) {
      g.fillStyle = series.color; g.beginPath(); g.arc(self.X(t), self.Y(cv.v[j]), 3.5, 0, 2 * Math.PI); g.fill();
      readout.push(rbSci(cv.v[j]));
    }
  });
  var xc = this.X(t);                                                  // the time cursor
  g.strokeStyle = "#222"; g.lineWidth = 1.5; g.beginPath(); g.moveTo(xc, M.t); g.lineTo(xc, h - M.b); g.stroke();
  c.dataset.cursorX = String(Math.round(xc));
  g.font = "bold 11px sans-serif"; g.textAlign = "right"; g.textBaseline = "bottom"; g.fillStyle = "#333";
  g.fillText("t = " + t.toFixed(2) + " s" + (readout.length ? ": " + readout.join(", ") : ""), w - M.r, M.t - 2);
};
RbPlot.prototype.index = function (ts, t) {        // the last point at or before t (its stretch holds t)
  var lo = 0, hi = ts.length - 1;
  if (hi < 0) return null;
  while (lo < hi) { var mid = (lo + hi + 1) >> 1; if (ts[mid] <= t) lo = mid; else hi = mid - 1; }
  return ts[lo] > t && lo + 1 < ts.length ? lo + 1 : lo;
};

function rbPlots(viewer, data, t0, speed, duration) {
  // the plots of data (linked.py) under the scene; simulated time t = t0 + speed * (the animation's time)
  var host = document.getElementById("rb-plots"), bar = document.createElement("div"), grid = document.createElement("div");
  bar.id = "rb-bar"; grid.id = "rb-panels";
  host.appendChild(bar); host.appendChild(grid);
  var button = document.createElement("button");
  button.id = "rb-play"; bar.appendChild(button);
  data.series.forEach(function (s) {
    var item = document.createElement("span"), sw = document.createElement("span");
    sw.className = "sw"; sw.style.background = s.color;
    item.appendChild(sw); item.appendChild(document.createTextNode(s.label)); bar.appendChild(item);
  });
  data.notes.forEach(function (text) {
    var note = document.createElement("span"); note.className = "rb-aside"; note.textContent = text; bar.appendChild(note);
  });
  grid.style.gridTemplateColumns = "repeat(" + data.panels.length + ", minmax(0, 1fr))";
  var t1 = t0 + speed * duration, span = [t0, t1];
  function now() {
    var tau = viewer.animator.actions.reduce(function (acc, a) { return Math.max(acc, a.time); }, 0);
    return t0 + speed * (duration ? tau : 0);
  }
  function seek(t) {
    var tau = Math.min(Math.max((t - t0) / speed, 0), duration);
    viewer.animator.pause();
    viewer.animator.seek(tau);
    viewer.animator.display_progress(tau);
    viewer.set_dirty();
  }
  var plots = data.panels.map(function (p) { return new RbPlot(grid, p, data, span, seek); });
  var pane = document.getElementById("meshcat-pane"), paneSize = viewer.set_3d_pane_size.bind(viewer);
  viewer.set_3d_pane_size = function (w, h) {        // meshcat sizes its scene to the window's height: to its pane's
    paneSize(w === undefined ? pane.clientWidth : w, h === undefined ? pane.clientHeight : h);
  };
  viewer.set_3d_pane_size();
  button.addEventListener("click", function () {
    if (viewer.animator.playing) viewer.animator.pause(); else viewer.animator.play();
  });
  var shown = null;
  function frame() {
    var t = now(), key = t + " " + grid.clientWidth + " " + grid.clientHeight;
    button.textContent = viewer.animator.playing ? "❚❚ pause" : "▶ play";
    if (key !== shown) { shown = key; plots.forEach(function (p) { p.draw(t); }); }
    requestAnimationFrame(frame);
  }
  window.rbLinked = { seek: seek, now: now, plots: plots };
  frame();
}
