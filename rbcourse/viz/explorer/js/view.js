/* The 3-D view, drawn by hand on a 2-D canvas: a fixed (or following) camera, the floor grid and shadows,
   the pivots and springs, the bodies as convex meshes (back faces culled, Lambert shading), the reference as
   a ghost, the body axes; and its legend. */
var V = D.view, viewCanvas = $("rb-view");
var meshes = D.bodies.map(function (b) {
  var v = [], m = b.mesh;
  for (var i = 0; i < m.v.length; i += 3) v.push([m.v[i], m.v[i + 1], m.v[i + 2]]);
  return { v: v, f: m.f, n: m.n, outline: m.outline, color: hexRgb(b.color), axis: b.axis };
});
function hexRgb(h) { return [parseInt(h.slice(1, 3), 16), parseInt(h.slice(3, 5), 16), parseInt(h.slice(5, 7), 16)]; }

function makeCamera(target, w, h) {
  var dir = V.direction, eye = add(target, mul(dir, V.distance));
  var f = unit(sub(target, eye)), r = unit(cross(f, [0, 0, 1])), u = cross(r, f);
  var focal = (h / 2) / Math.tan(V.fov * Math.PI / 360);
  var light = unit(add(add(mul(r, -0.35), mul(u, 0.8)), mul(f, -0.5)));
  return {
    eye: eye, f: f, r: r, u: u, light: light, near: 1e-3 * V.distance,
    p: function (P) {
      var d = sub(P, eye), z = dot(d, f);
      return [w / 2 + focal * dot(d, r) / z, h / 2 - focal * dot(d, u) / z, z];
    }
  };
}
function segment(g, cam, a, b) {                     // a 3-D segment, clipped to the near plane
  var za = dot(sub(a, cam.eye), cam.f), zb = dot(sub(b, cam.eye), cam.f);
  if (za < cam.near && zb < cam.near) return;
  if (za < cam.near) a = add(a, mul(sub(b, a), (cam.near - za) / (zb - za)));
  if (zb < cam.near) b = add(b, mul(sub(a, b), (cam.near - zb) / (za - zb)));
  var pa = cam.p(a), pb = cam.p(b);
  g.moveTo(pa[0], pa[1]); g.lineTo(pb[0], pb[1]);
}
function worldVerts(mesh, pose) { return mesh.v.map(function (v) { return add(pose.x, rot(pose.R, v)); }); }

function drawBody(g, cam, mesh, pose, style) {
  var W = worldVerts(mesh, pose), P = W.map(cam.p);
  var order = mesh.f.map(function (f, k) {
    var c = [0, 0, 0];
    f.forEach(function (i) { c = add(c, W[i]); });
    c = mul(c, 1 / f.length);
    var n = rot(pose.R, mesh.n[k]);
    return { k: k, n: n, front: dot(n, sub(cam.eye, c)) > 0, z: dot(sub(c, cam.eye), cam.f) };
  });
  if (style === "ghost") order.sort(function (a, b) { return b.z - a.z; });
  order.forEach(function (o) {
    if (!o.front && style !== "ghost") return;
    var f = mesh.f[o.k];
    if (f.some(function (i) { return P[i][2] < cam.near; })) return;
    g.beginPath();
    f.forEach(function (i, j) { if (j) g.lineTo(P[i][0], P[i][1]); else g.moveTo(P[i][0], P[i][1]); });
    g.closePath();
    if (style === "ghost") {
      g.fillStyle = "rgba(" + GHOST + "," + (o.front ? 0.15 : 0.06) + ")";
      g.fill();
      if (mesh.outline) { g.strokeStyle = "rgba(" + GHOST + ",0.95)"; g.lineWidth = 1.3; g.stroke(); }
    } else {
      var lit = 0.42 + 0.58 * Math.max(0, dot(o.n, cam.light)), c = mesh.color;
      var col = "rgb(" + Math.round(c[0] * lit) + "," + Math.round(c[1] * lit) + "," + Math.round(c[2] * lit) + ")";
      g.fillStyle = col; g.fill();
      g.strokeStyle = mesh.outline ? "rgba(40,25,10,0.55)" : col; g.lineWidth = mesh.outline ? 1 : 0.6; g.stroke();
    }
  });
}
function drawShadow(g, cam, mesh, pose, z) {
  var pts = worldVerts(mesh, pose).map(function (w) { return [w[0], w[1]]; });
  pts.sort(function (a, b) { return a[0] - b[0] || a[1] - b[1]; });
  var crossz = function (o, a, b) { return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]); };
  var lower = [], upper = [];
  pts.forEach(function (p) { while (lower.length >= 2 && crossz(lower[lower.length - 2], lower[lower.length - 1], p) <= 0) lower.pop(); lower.push(p); });
  pts.slice().reverse().forEach(function (p) { while (upper.length >= 2 && crossz(upper[upper.length - 2], upper[upper.length - 1], p) <= 0) upper.pop(); upper.push(p); });
  var hull = lower.slice(0, -1).concat(upper.slice(0, -1));
  if (hull.length < 3) return;
  var P = hull.map(function (p) { return cam.p([p[0], p[1], z]); });
  if (P.some(function (p) { return p[2] < cam.near; })) return;
  g.beginPath();
  P.forEach(function (p, j) { if (j) g.lineTo(p[0], p[1]); else g.moveTo(p[0], p[1]); });
  g.closePath(); g.fillStyle = "rgba(0,0,0,0.13)"; g.fill();
}
function drawView() {
  var c = fit(viewCanvas), g = c.g, w = c.w, h = c.h;
  var run = runOf(S.mi, S.di), rp = poses(run.tr, S.t), gp = poses(ghost, S.t);
  var target = V.follow ? rp[0].x : V.target;       // following: the chosen run's body (frozen after its end)
  var cam = makeCamera(target, w, h);
  var bg = g.createLinearGradient(0, 0, 0, h);
  bg.addColorStop(0, "#fbfcfd"); bg.addColorStop(1, "#e3e8ee");
  g.fillStyle = bg; g.fillRect(0, 0, w, h);
  var fz = V.floor.follow ? target[2] - V.floor.offset : V.floor.z, st = V.floor.step, nl = V.floor.lines;
  var cx = Math.round(target[0] / st) * st, cy = Math.round(target[1] / st) * st;
  if (V.ground) {                           // the ground's plane, under the grid's extent
    var ext = nl * st, corners = [[-1, -1], [1, -1], [1, 1], [-1, 1]].map(function (c) {
      return [cx + c[0] * ext, cy + c[1] * ext, fz]; });
    var pc = corners.map(cam.p);
    if (pc.every(function (p) { return p[2] > cam.near; })) {
      g.fillStyle = "rgba(138,154,123,0.22)"; g.beginPath();
      pc.forEach(function (p, j) { if (j) g.lineTo(p[0], p[1]); else g.moveTo(p[0], p[1]); });
      g.closePath(); g.fill();
    }
  }
  g.lineWidth = 1;
  for (var k = -nl; k <= nl; k++) {
    var far = Math.abs(k) / nl;
    g.strokeStyle = "rgba(90,100,115," + (0.45 * (1 - far * far)).toFixed(3) + ")";
    g.beginPath();
    for (var s = -nl; s < nl; s++) {
      segment(g, cam, [cx + k * st, cy + s * st, fz], [cx + k * st, cy + (s + 1) * st, fz]);
      segment(g, cam, [cx + s * st, cy + k * st, fz], [cx + (s + 1) * st, cy + k * st, fz]);
    }
    g.stroke();
  }
  meshes.forEach(function (m, b) { drawShadow(g, cam, m, rp[b], fz); });
  D.attachments.forEach(function (a) {
    var pose = rp[a.body];
    if (a.kind === "pivot") {
      g.strokeStyle = "#444"; g.lineWidth = 2; g.beginPath(); segment(g, cam, a.p, pose.x); g.stroke();
      var q = cam.p(a.p); g.fillStyle = "#222"; g.beginPath(); g.arc(q[0], q[1], 4, 0, 2 * Math.PI); g.fill();
    } else {
      var from = add(pose.x, rot(pose.R, a.b)), to = a.kind === "spring" ? a.p
                 : add(rp[a.other].x, rot(rp[a.other].R, a.ob));
      var axis = sub(to, from), side = unit(cross(axis, cam.f)), amp = 0.04 * Math.sqrt(dot(axis, axis)) + 1e-9;
      g.strokeStyle = "#555"; g.lineWidth = 1.4; g.beginPath();
      var prev = from;
      for (var i = 1; i <= 24; i++) {
        var s2 = i / 24, wig = (i === 24 || i < 2 || i > 22) ? 0 : (i % 2 ? 1 : -1) * amp;
        var pt = add(add(from, mul(axis, s2)), mul(side, wig));
        segment(g, cam, prev, pt); prev = pt;
      }
      g.stroke();
      if (a.kind === "spring") { var qa = cam.p(a.p); g.fillStyle = "#333"; g.fillRect(qa[0] - 3, qa[1] - 3, 6, 6); }
    }
  });
  var order = rp.map(function (p, b) { return { b: b, z: dot(sub(p.x, cam.eye), cam.f) }; })
    .sort(function (a, b) { return b.z - a.z; });
  order.forEach(function (o) { drawBody(g, cam, meshes[o.b], rp[o.b], "body"); });
  if (S.ghost) order.forEach(function (o) { drawBody(g, cam, meshes[o.b], gp[o.b], "ghost"); });
  if (NB <= 3) {
    var cols = ["#d62728", "#2ca02c", "#1f77b4"], names = ["x", "y", "z"];
    rp.forEach(function (p, b) {
      for (var i = 0; i < 3; i++) {
        var e = [0, 0, 0]; e[i] = meshes[b].axis;
        var tip = add(p.x, rot(p.R, e));
        g.strokeStyle = cols[i]; g.lineWidth = 2.2; g.beginPath(); segment(g, cam, p.x, tip); g.stroke();
        var q = cam.p(tip);
        if (q[2] > cam.near) { g.fillStyle = cols[i]; g.font = "bold 11px sans-serif"; g.fillText(names[i], q[0] + 3, q[1] - 3); }
      }
    });
  }
  g.fillStyle = "#222"; g.font = "13px sans-serif";
  g.fillText("t = " + S.t.toFixed(2) + " s", 10, 18);
  var warn = $("rb-view-warning");
  if (run.diverged && S.t > run.drawn_until) {
    warn.hidden = false;
    warn.textContent = run.method + ", dt = " + D.dt_labels[S.di] + " s: " + run.reason + "; shown at its last " +
      (run.drawn_note ? "drawable" : "finite") + " state, t = " + fmtNum(run.drawn_until) + " s";
  } else warn.hidden = true;
}
function viewLegend() {
  var run = runOf(S.mi, S.di), body = D.bodies[0].color;
  $("rb-view-legend").innerHTML = '<span class="rb-sw" style="background:' + body + '"></span>' + run.method +
    ", dt = " + D.dt_labels[S.di] + " s" + '<span class="rb-sw" style="background:rgba(' + GHOST + ',0.45);border:1px solid rgb(' +
    GHOST + ')"></span>ghost: reference (' + esc(D.reference.label) + ")" +
    (NB <= 3 ? '<span class="rb-sw" style="background:linear-gradient(90deg,#d62728 33%,#2ca02c 33% 66%,#1f77b4 66%)"></span>axes x y z' : "");
}
