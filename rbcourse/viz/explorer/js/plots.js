/* The plots over time, one a panel of D.panels (log scale): every step of the chosen method in pale,
   the chosen run in full, where it diverged, and the time cursor with the value under it; click or drag
   a plot to seek there. */
var M = { l: 50, r: 10, t: 17, b: 26 };
function Plot(panel) {
  var fig = document.createElement("figure");
  var cap = document.createElement("figcaption");
  cap.textContent = panel.title;
  cap.title = panel.note;
  var canvas = document.createElement("canvas");
  canvas.dataset.key = panel.key;
  canvas.setAttribute("aria-label", panel.title + " over time; click to jump the animation there");
  fig.appendChild(cap); fig.appendChild(canvas);
  $("rb-plots").appendChild(fig);
  this.panel = panel; this.canvas = canvas; this.cache = document.createElement("canvas"); this.stale = true;
  var self = this;
  function at(e) {
    var rect = canvas.getBoundingClientRect(), x = e.clientX - rect.left;
    seek((x - M.l) / (rect.width - M.l - M.r) * D.t_end);
  }
  canvas.addEventListener("pointerdown", function (e) { canvas.setPointerCapture(e.pointerId); self.drag = true; at(e); });
  canvas.addEventListener("pointermove", function (e) { if (self.drag) at(e); });
  canvas.addEventListener("pointerup", function () { self.drag = false; });
}
Plot.prototype.X = function (t) { return M.l + t / D.t_end * (this.w - M.l - M.r); };
Plot.prototype.Y = function (v) {
  var lo = this.panel.ylim[0], hi = this.panel.ylim[1];
  var e = v > 0 ? Math.log10(v) : lo;
  e = Math.min(Math.max(e, lo), hi);
  return this.h - M.b - (e - lo) / (hi - lo) * (this.h - M.t - M.b);
};
Plot.prototype.drawStatic = function () {
  var c = this.canvas, dpr = window.devicePixelRatio || 1;
  this.w = c.clientWidth; this.h = c.clientHeight;
  this.cache.width = Math.round(this.w * dpr); this.cache.height = Math.round(this.h * dpr);
  var g = this.cache.getContext("2d"), w = this.w, h = this.h, p = this.panel, self = this;
  g.setTransform(dpr, 0, 0, dpr, 0, 0);
  g.fillStyle = "#fff"; g.fillRect(0, 0, w, h);
  var lo = p.ylim[0], hi = p.ylim[1], every = Math.max(1, Math.ceil((hi - lo) / 5));
  g.font = "10.5px sans-serif"; g.textBaseline = "middle"; g.textAlign = "right";
  for (var e = Math.ceil(lo); e <= hi; e++) {
    var y = this.Y(Math.pow(10, e));
    g.strokeStyle = e % every === 0 ? "#e4e4e4" : "#f3f3f3"; g.lineWidth = 1;
    g.beginPath(); g.moveTo(M.l, y); g.lineTo(w - M.r, y); g.stroke();
    if (e % every === 0) { g.fillStyle = "#444"; g.fillText(pow10(e), M.l - 4, y); }
  }
  var step = niceStep(D.t_end, Math.max(2, Math.floor((w - M.l - M.r) / 60)));
  g.textAlign = "center"; g.textBaseline = "top";
  for (var t = 0; t <= D.t_end + 1e-9 * D.t_end; t += step) {
    var x = this.X(t);
    g.strokeStyle = "#f0f0f0"; g.beginPath(); g.moveTo(x, M.t); g.lineTo(x, h - M.b); g.stroke();
    g.fillStyle = "#444"; g.fillText(fmtT(t, step), x, h - M.b + 3);
  }
  g.textAlign = "right"; g.fillText("t (s)", w - M.r, h - 12);
  if (p.mode === "drift" && D.t0 > 0) {
    g.fillStyle = "rgba(0,0,0,0.06)"; g.fillRect(M.l, M.t, this.X(D.t0) - M.l, h - M.t - M.b);
  }
  g.strokeStyle = "#888"; g.lineWidth = 1; g.strokeRect(M.l + 0.5, M.t + 0.5, w - M.l - M.r - 1, h - M.t - M.b - 1);
  var color = D.methods[S.mi].color;
  for (var di = 0; di < ND; di++) if (di !== S.di) this.curve(g, runOf(S.mi, di), color, 0.22, 1);
  var r = runOf(S.mi, S.di), last = this.curve(g, r, color, 1, 2);
  if (r.diverged) {
    var xd = this.X(r.t_diverged);
    g.setLineDash([3, 3]); g.strokeStyle = "#b00"; g.beginPath(); g.moveTo(xd, M.t); g.lineTo(xd, h - M.b); g.stroke();
    g.setLineDash([]);
    if (last) { this.cross(g, last[0], last[1]); }
    g.fillStyle = "#b00"; g.textAlign = xd > w - 80 ? "right" : "left"; g.textBaseline = "bottom";
    g.fillText("diverged", xd + (xd > w - 80 ? -4 : 4), h - M.b - 3);
  }
  c.dataset.run = r.method + " " + D.dt_labels[S.di];
  c.dataset.points = String(r.ct.length);
  var v = r.cv[p.key];
  c.dataset.last = String(v[v.length - 1]);
  this.stale = false;
};
Plot.prototype.curve = function (g, r, color, alpha, width) {
  var t = r.ct, v = r.cv[this.panel.key], pen = false, last = null;
  g.globalAlpha = alpha; g.strokeStyle = color; g.lineWidth = width; g.beginPath();
  for (var i = 0; i < t.length; i++) {
    if (isNaN(v[i])) { pen = false; continue; }
    var x = this.X(t[i]), y = this.Y(v[i]);
    if (pen) g.lineTo(x, y); else g.moveTo(x, y);
    pen = true; last = [x, y];
  }
  g.stroke(); g.globalAlpha = 1;
  return last;
};
Plot.prototype.cross = function (g, x, y) {
  g.strokeStyle = "#b00"; g.lineWidth = 2; g.beginPath();
  g.moveTo(x - 5, y - 5); g.lineTo(x + 5, y + 5); g.moveTo(x + 5, y - 5); g.lineTo(x - 5, y + 5); g.stroke();
};
Plot.prototype.draw = function () {
  var c = fit(this.canvas);
  if (this.stale || this.w !== c.w || this.h !== c.h) this.drawStatic();
  var g = c.g;
  g.drawImage(this.cache, 0, 0, this.w, this.h);
  var x = this.X(S.t), r = runOf(S.mi, S.di);
  g.strokeStyle = CURSOR; g.lineWidth = 2; g.beginPath(); g.moveTo(x, M.t); g.lineTo(x, this.h - M.b); g.stroke();
  this.canvas.dataset.cursorX = String(Math.round(x));
  var txt;
  if (r.diverged && S.t > r.t_last) txt = "diverged at t = " + fmtNum(r.t_diverged) + " s";
  else {
    var t = r.ct, lo = 0, hi = t.length - 1;
    while (hi - lo > 1) { var m = (lo + hi) >> 1; if (t[m] < S.t) lo = m; else hi = m; }
    var k = t[lo] >= S.t ? lo : hi, v = r.cv[this.panel.key][k];
    if (isNaN(v)) txt = this.panel.mode === "drift" ? "not plotted before t₀ = " + D.t0 + " s" : "";
    else {
      txt = "at t = " + S.t.toFixed(2) + " s: " + sci(v) + (this.panel.unit === "rad" ? " rad" : "");
      g.fillStyle = CURSOR; g.beginPath(); g.arc(x, this.Y(v), 3.5, 0, 2 * Math.PI); g.fill();
    }
  }
  if (txt) {                                 // the value under the cursor, above the plot's top right corner
    g.font = "bold 11px sans-serif"; g.textBaseline = "bottom"; g.textAlign = "right";
    g.fillStyle = "#333"; g.fillText(txt, this.w - M.r, M.t - 3);
  }
};
var plots = D.panels.map(function (p) { return new Plot(p); });
