/* Plots over time with a time cursor: the one plotting code of the linked view (draw_trajectory(..., plots=True),
   rbPlots below; linked.py makes its data) and of the accuracy explorer (its drift panels: the chosen run, and
   the chosen method's other steps in pale).  Log axes, with a row under the floor for the values that are exactly
   0; a gap where a curve has no value (null or NaN: before t₀, after a run's end); where a run diverged, a dotted
   red line, a cross on its last point and the word.  A click or a drag on a plot seeks there.  Also the axis
   helpers the explorer's work-precision panel shares (rbFit, rbPow10, rbSci, rbDecades).  Plain canvas 2-D. */
var RB_SUP = { "0": "⁰", "1": "¹", "2": "²", "3": "³", "4": "⁴", "5": "⁵", "6": "⁶", "7": "⁷", "8": "⁸", "9": "⁹", "-": "⁻" };
var RB_CURSOR = "#f0a000", RB_DIVERGED = "#b00";
function rbPow10(e) {
  return e === 0 ? "1" : e === 1 ? "10" : "10" + String(e).split("").map(function (c) { return RB_SUP[c] || c; }).join("");
}
function rbSci(v) {
  if (v === null || v === undefined) return "—";
  if (v === 0) return rbSay("exactly_0");
  if (!isFinite(v) || Math.abs(v) >= 1e300) return rbSay("overflow");
  var e = Math.floor(Math.log10(Math.abs(v))), m = v / Math.pow(10, e);
  if (Math.abs(m) >= 9.95) { m /= 10; e += 1; }
  return e >= -2 && e <= 3 ? String(Number(v.toPrecision(3))) : m.toFixed(2) + "×" + rbPow10(e);
}
function rbFit(canvas) {
  // a canvas sized to its CSS box at the device's pixel ratio, its context scaled to CSS pixels
  var dpr = window.devicePixelRatio || 1, w = canvas.clientWidth, h = canvas.clientHeight;
  if (canvas.width !== Math.round(w * dpr) || canvas.height !== Math.round(h * dpr)) {
    canvas.width = Math.round(w * dpr); canvas.height = Math.round(h * dpr);
  }
  var g = canvas.getContext("2d");
  g.setTransform(dpr, 0, 0, dpr, 0, 0);
  return { g: g, w: w, h: h };
}
function rbDecades(lo, hi, n) {
  // the labelled decades of a log axis [lo, hi] (log10): at most about n of them, multiples of one step
  var every = Math.max(1, Math.ceil((hi - lo) / n)), out = [];
  for (var e = Math.ceil(lo); e <= hi; e++) if (e % every === 0) out.push(e);
  return out;
}
function rbGap(v) { return v === null || v === undefined || v !== v; }

function RbPlot(host, panel, opts) {
  // panel: {key, title, note, unit}; opts: {span: [t_a, t_b], log: [lo, hi] (log10), t0: drifts' start or null,
  // seek: function (t)}
  var fig = document.createElement("figure"), cap = document.createElement("figcaption");
  cap.textContent = panel.title; cap.title = panel.note || "";
  this.canvas = document.createElement("canvas");
  this.canvas.dataset.key = panel.key;
  this.canvas.setAttribute("aria-label", rbSay("plot_aria", { title: panel.title }));
  fig.appendChild(cap); fig.appendChild(this.canvas); host.appendChild(fig);
  this.panel = panel; this.opts = opts; this.span = opts.span; this.M = { l: 62, r: 10, t: 16, b: 24 };
  var self = this, drag = false;
  function at(e) {
    var r = self.canvas.getBoundingClientRect();
    opts.seek(self.T(e.clientX - r.left));
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
  var lo = this.opts.log[0], hi = this.opts.log[1], bottom = this.h - this.M.b - 16;
  if (v === 0) return this.h - this.M.b - 6;
  var e = Math.min(Math.max(Math.log10(Math.abs(v)), lo), hi);
  return bottom - (e - lo) / (hi - lo) * (bottom - this.M.t);
};
RbPlot.prototype.axes = function (g) {
  var M = this.M, w = this.w, h = this.h, lo = this.opts.log[0], hi = this.opts.log[1];
  g.fillStyle = "#fff"; g.fillRect(0, 0, w, h);
  g.font = "10.5px sans-serif"; g.textAlign = "right"; g.textBaseline = "middle"; g.lineWidth = 1;
  M.l = Math.max(62, Math.ceil(g.measureText(rbSay("exactly_0")).width) + 8);   // the zero row's label fits, in any language
  g.fillStyle = "#f0f0f0"; g.fillRect(M.l, h - M.b - 12, w - M.l - M.r, 12);          // the exact zeros' row
  for (var e = Math.ceil(lo); e <= hi; e++) {
    var y = this.Y(Math.pow(10, e));
    g.strokeStyle = "#f3f3f3"; g.beginPath(); g.moveTo(M.l, y); g.lineTo(w - M.r, y); g.stroke();
  }
  var self = this;
  rbDecades(lo, hi, 5).forEach(function (e) {
    var y = self.Y(Math.pow(10, e));
    g.strokeStyle = "#e2e2e2"; g.beginPath(); g.moveTo(M.l, y); g.lineTo(w - M.r, y); g.stroke();
    g.fillStyle = "#444"; g.fillText(rbPow10(e), M.l - 4, y);
  });
  g.fillStyle = "#444"; g.fillText(rbSay("exactly_0"), M.l - 4, this.Y(0));
  var n = Math.max(2, Math.floor((w - M.l - M.r) / 70)), raw = (this.span[1] - this.span[0]) / n;
  var k = Math.pow(10, Math.floor(Math.log10(raw || 1))), m = raw / k;
  var step = (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * k, digits = Math.max(0, -Math.floor(Math.log10(step)));
  g.textAlign = "center"; g.textBaseline = "top";
  for (var s = Math.ceil(this.span[0] / step) * step; s <= this.span[1] + 1e-9 * step; s += step) {
    g.fillText(s.toFixed(digits), this.X(s), h - M.b + 4);
  }
  g.textAlign = "left"; g.fillText("t (s)", 4, h - M.b + 4);
  var t0 = this.opts.t0;
  if (t0 !== null && t0 > this.span[0]) {                             // before t₀: no drift
    g.fillStyle = "rgba(0,0,0,0.06)"; g.fillRect(M.l, M.t, this.X(Math.min(t0, this.span[1])) - M.l, h - M.t - M.b);
  }
  g.strokeStyle = "#999"; g.strokeRect(M.l + 0.5, M.t + 0.5, w - M.l - M.r - 1, h - M.t - M.b - 1);
};
RbPlot.prototype.curve = function (g, cv) {
  // one curve: pale (the other steps) or full; returns its last drawn point [x, y, t]
  var pen = false, last = null;
  g.globalAlpha = cv.pale ? 0.22 : 1; g.strokeStyle = cv.color; g.lineWidth = cv.pale ? 1 : 1.7; g.beginPath();
  for (var i = 0; i < cv.t.length; i++) {
    if (rbGap(cv.v[i])) { pen = false; continue; }
    var x = this.X(cv.t[i]), y = this.Y(cv.v[i]);
    if (pen) g.lineTo(x, y); else g.moveTo(x, y);
    pen = true; last = [x, y, cv.t[i]];
  }
  g.stroke(); g.globalAlpha = 1;
  return last;
};
RbPlot.prototype.diverged = function (g, cv, last) {
  var M = this.M, xd = this.X(cv.end), right = xd > this.w - 80;
  g.setLineDash([3, 3]); g.strokeStyle = RB_DIVERGED; g.lineWidth = 1.2;
  g.beginPath(); g.moveTo(xd, M.t); g.lineTo(xd, this.h - M.b); g.stroke(); g.setLineDash([]);
  if (last) {
    g.lineWidth = 2; g.beginPath();
    g.moveTo(last[0] - 5, last[1] - 5); g.lineTo(last[0] + 5, last[1] + 5);
    g.moveTo(last[0] + 5, last[1] - 5); g.lineTo(last[0] - 5, last[1] + 5); g.stroke();
  }
  g.fillStyle = RB_DIVERGED; g.font = "10.5px sans-serif"; g.textAlign = right ? "right" : "left";
  g.textBaseline = "bottom"; g.fillText(rbSay("diverged"), xd + (right ? -4 : 4), this.h - M.b - 18);
};
RbPlot.prototype.draw = function (t, curves) {
  // curves: [{t, v (null or NaN: no value), color, pale, end: the time it diverged or null}], drawn in order
  var fit = rbFit(this.canvas), g = fit.g, M = this.M, self = this, readout = [], valued = false;
  this.w = fit.w; this.h = fit.h;
  this.axes(g);
  curves.forEach(function (cv) {
    var last = self.curve(g, cv);
    if (cv.pale) return;
    if (cv.end !== null && cv.end !== undefined) self.diverged(g, cv, last);
    var j = self.index(cv.t, t), v = j === null ? null : cv.v[j];
    if (cv.end !== null && cv.end !== undefined && last && t > last[2]) readout.push(rbSay("diverged_at", { t: Number(cv.end.toPrecision(4)) }));
    else if (rbGap(v)) { if (self.opts.t0 !== null && t < self.opts.t0) readout.push(rbSay("before_t0", { t0: self.opts.t0 })); }
    else if (j !== null && t <= cv.t[cv.t.length - 1] + 1e-9) {
      g.fillStyle = cv.color; g.beginPath(); g.arc(self.X(t), self.Y(v), 3.5, 0, 2 * Math.PI); g.fill();
      readout.push(rbSci(v)); valued = valued || v !== 0;
    }
  });
  var xc = this.X(t);                                                  // the time cursor
  g.strokeStyle = RB_CURSOR; g.lineWidth = 2; g.beginPath(); g.moveTo(xc, M.t); g.lineTo(xc, this.h - M.b); g.stroke();
  this.canvas.dataset.cursorX = String(Math.round(xc));
  g.font = "bold 11px sans-serif"; g.textAlign = "right"; g.textBaseline = "bottom"; g.fillStyle = "#333";
  var unit = this.panel.unit === "rad" && valued ? " rad" : "";                   // once, after the values
  g.fillText("t = " + t.toFixed(2) + " s" + (readout.length ? rbSay("colon") + readout.join(", ") + unit : ""), this.w - M.r, M.t - 2);
};
RbPlot.prototype.index = function (ts, t) {        // the last point at or before t (its stretch holds t)
  var lo = 0, hi = ts.length - 1;
  if (hi < 0) return null;
  while (lo < hi) { var mid = (lo + hi + 1) >> 1; if (ts[mid] <= t) lo = mid; else hi = mid - 1; }
  return ts[lo] > t && lo + 1 < ts.length ? lo + 1 : lo;
};

function rbPlots(viewer, data, t0, speed, duration) {
  // the linked view: the plots of data (linked.py) under meshcat's scene, with one time cursor: the animation's
  // time.  meshcat's animator plays, the cursor follows; a click or a drag on a plot pauses it and seeks there
  // (animator.seek), and the 3-D scene follows.  Simulated time t = t0 + speed * (the animation's time).
  var host = document.getElementById("rb-plots"), bar = document.createElement("div"), grid = document.createElement("div");
  bar.id = "rb-bar"; grid.id = "rb-panels";
  host.appendChild(bar); host.appendChild(grid);
  var button = document.createElement("button");
  button.id = "rb-play"; button.title = rbSay("play_title"); bar.appendChild(button);
  data.series.forEach(function (s) {
    var item = document.createElement("span"), sw = document.createElement("span");
    sw.className = "sw"; sw.style.background = s.color;
    item.appendChild(sw); item.appendChild(document.createTextNode(s.label)); bar.appendChild(item);
  });
  data.notes.forEach(function (text) {
    var note = document.createElement("span"); note.className = "rb-aside"; note.textContent = text; bar.appendChild(note);
  });
  grid.style.gridTemplateColumns = "repeat(" + data.panels.length + ", minmax(0, 1fr))";
  var span = [t0, t0 + speed * duration];
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
  var plots = data.panels.map(function (p) {
    return new RbPlot(grid, p, { span: span, log: data.log, t0: data.t0, seek: seek });
  });
  var curves = data.panels.map(function (p) {
    return p.curves.map(function (cv) {
      var s = data.series[cv.s];
      return { t: cv.t, v: cv.v, color: s.color, pale: false, end: s.end };
    });
  });
  rbFitPane(viewer, document.getElementById("meshcat-pane"));
  button.addEventListener("click", function () {
    if (viewer.animator.playing) viewer.animator.pause(); else viewer.animator.play();
  });
  var shown = null;
  function frame() {
    var t = now(), key = t + " " + grid.clientWidth + " " + grid.clientHeight;
    button.textContent = rbSay(viewer.animator.playing ? "pause" : "play");
    if (key !== shown) { shown = key; plots.forEach(function (p, i) { p.draw(t, curves[i]); }); }
    requestAnimationFrame(frame);
  }
  window.rbLinked = { seek: seek, now: now, plots: plots };
  frame();
}
