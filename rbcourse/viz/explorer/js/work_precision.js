/* The work-precision panel: wall time against the rotation error at t_end (log-log; the axis helpers of
   viewer/js/timeplots.js), one line a method,
   the runs that diverged in the top band, the reference's own accuracy dashed; hover a point to read it,
   click it to pick that run. */
var WM = { l: 58, r: 24, t: 24, b: 34 };
var wp = { canvas: $("rb-wp"), stale: true, pts: [], hover: -1 };
function wpX(s, w) { var L = D.wp.xlim; return WM.l + (Math.log10(Math.max(s, 1e-12)) - L[0]) / (L[1] - L[0]) * (w - WM.l - WM.r); }
function wpY(e, h) {
  var L = D.wp.ylim, v = Math.min(Math.max(Math.log10(Math.max(e, 1e-30)), L[0]), L[1]);
  return h - WM.b - (v - L[0]) / (L[1] - L[0]) * (h - WM.t - WM.b);
}
function drawWP() {
  var c = rbFit(wp.canvas), g = c.g, w = c.w, h = c.h;
  g.fillStyle = "#fff"; g.fillRect(0, 0, w, h);
  var XL = D.wp.xlim, YL = D.wp.ylim;
  g.font = "10.5px sans-serif";
  var ylab = rbDecades(YL[0], YL[1], 6), xlab = rbDecades(XL[0], XL[1], 6);
  for (var e = YL[0]; e <= YL[1]; e++) {
    var y = wpY(Math.pow(10, e), h);
    g.strokeStyle = "#eee"; g.beginPath(); g.moveTo(WM.l, y); g.lineTo(w - WM.r, y); g.stroke();
    if (ylab.indexOf(e) >= 0) { g.fillStyle = "#444"; g.textAlign = "right"; g.textBaseline = "middle"; g.fillText(rbPow10(e), WM.l - 4, y); }
  }
  for (var e2 = XL[0]; e2 <= XL[1]; e2++) {
    var x = wpX(Math.pow(10, e2), w);
    g.strokeStyle = "#eee"; g.beginPath(); g.moveTo(x, WM.t); g.lineTo(x, h - WM.b); g.stroke();
    if (xlab.indexOf(e2) >= 0) { g.fillStyle = "#444"; g.textAlign = "center"; g.textBaseline = "top"; g.fillText(rbPow10(e2) + " s", x, h - WM.b + 3); }
  }
  g.strokeStyle = "#888"; g.strokeRect(WM.l + 0.5, WM.t + 0.5, w - WM.l - WM.r - 1, h - WM.t - WM.b - 1);
  g.fillStyle = "#444"; g.textAlign = "center"; g.textBaseline = "bottom";
  g.fillText(rbSay("wp_x"), (WM.l + w - WM.r) / 2, h - 1);
  g.save(); g.translate(11, (WM.t + h - WM.b) / 2); g.rotate(-Math.PI / 2); g.textBaseline = "middle";
  g.fillText(rbSay("wp_y"), 0, 0); g.restore();
  g.fillStyle = "rgba(176,0,0,0.07)"; g.fillRect(WM.l, 2, w - WM.l - WM.r, WM.t - 4);
  g.fillStyle = "#b00"; g.textAlign = "right"; g.textBaseline = "middle"; g.fillText(rbSay("diverged"), WM.l - 4, WM.t / 2);
  var acc = D.reference.accuracy;
  if (acc !== null && acc > 0) {
    var ya = wpY(acc, h);
    g.setLineDash([5, 4]); g.strokeStyle = "#777"; g.beginPath(); g.moveTo(WM.l, ya); g.lineTo(w - WM.r, ya); g.stroke();
    g.setLineDash([]); g.fillStyle = "#666"; g.textAlign = "right"; g.textBaseline = "bottom";
    g.fillText(rbSay("reference_accuracy"), w - WM.r - 3, ya - 2);
  }
  wp.pts = [];
  D.methods.forEach(function (m, mi) {
    g.strokeStyle = m.color; g.fillStyle = m.color; g.lineWidth = 1.5; g.beginPath();
    var pen = false;
    var idx = D.dts.map(function (d, i) { return i; }).sort(function (a, b) { return runOf(mi, a).seconds - runOf(mi, b).seconds; });
    idx.forEach(function (di) {
      var r = runOf(mi, di);
      if (r.error === null) { pen = false; return; }
      var x = wpX(r.seconds, w), y = wpY(Math.max(r.error, 1e-30), h);
      if (pen) g.lineTo(x, y); else g.moveTo(x, y);
      pen = true;
    });
    g.stroke();
    D.dts.forEach(function (d, di) {
      var r = runOf(mi, di), x = wpX(r.seconds, w), y;
      if (r.error === null) {
        y = WM.t / 2;
        g.strokeStyle = m.color; g.lineWidth = 2; g.beginPath();
        g.moveTo(x - 4, y - 4); g.lineTo(x + 4, y + 4); g.moveTo(x + 4, y - 4); g.lineTo(x - 4, y + 4); g.stroke();
      } else {
        y = wpY(Math.max(r.error, 1e-30), h);
        g.beginPath(); g.arc(x, y, 3.5, 0, 2 * Math.PI); g.fill();
      }
      wp.pts.push({ x: x, y: y, mi: mi, di: di });
    });
  });
  var me = wp.pts.filter(function (p) { return p.mi === S.mi && p.di === S.di; })[0];
  if (me) { g.strokeStyle = "#111"; g.lineWidth = 2; g.beginPath(); g.arc(me.x, me.y, 8, 0, 2 * Math.PI); g.stroke(); }
  wp.canvas.dataset.selected = D.methods[S.mi].name + " " + D.dt_labels[S.di];
  var hv = wp.pts[wp.hover];
  if (hv) {
    var r = runOf(hv.mi, hv.di);
    var txt = rbSay(r.error === null ? "wp_point_diverged" : "wp_point",
                    { method: r.method, dt: D.dt_labels[hv.di], seconds: secs(r.seconds), error: rbSci(r.error) });
    g.font = "11px sans-serif"; var tw = g.measureText(txt).width;
    var tx = Math.min(Math.max(hv.x + 8, WM.l), w - WM.r - tw - 6), ty = Math.max(hv.y - 22, WM.t + 2);
    g.fillStyle = "rgba(255,255,255,0.92)"; g.fillRect(tx - 3, ty, tw + 6, 16);
    g.strokeStyle = "#aaa"; g.lineWidth = 1; g.strokeRect(tx - 3, ty, tw + 6, 16);
    g.fillStyle = "#222"; g.textAlign = "left"; g.textBaseline = "top"; g.fillText(txt, tx, ty + 2);
  }
  wp.stale = false;
}
function nearestPoint(e) {
  var rect = wp.canvas.getBoundingClientRect(), x = e.clientX - rect.left, y = e.clientY - rect.top, best = -1, bd = 14 * 14;
  wp.pts.forEach(function (p, i) { var d = (p.x - x) * (p.x - x) + (p.y - y) * (p.y - y); if (d < bd) { bd = d; best = i; } });
  return best;
}
wp.canvas.addEventListener("click", function (e) { var i = nearestPoint(e); if (i >= 0) pick(wp.pts[i].mi, wp.pts[i].di); });
wp.canvas.addEventListener("pointermove", function (e) { var i = nearestPoint(e); if (i !== wp.hover) { wp.hover = i; wp.stale = true; dirty(); } });
wp.canvas.addEventListener("pointerleave", function () { if (wp.hover >= 0) { wp.hover = -1; wp.stale = true; dirty(); } });
$("rb-wp-legend").innerHTML = D.methods.map(function (m) {
  return '<span class="rb-sw" style="background:' + m.color + '"></span>' + esc(rbSay("order", { name: m.name, order: m.order }));
}).join("") + '<span class="rb-sw" style="border:2px solid #111;border-radius:50%;background:none"></span>' +
  esc(rbSay("chosen_run"));
