/* rbcourse accuracy explorer: pick a method and a step, watch the body and its drift together.
   Everything is in this page: the runs are base64 float32 arrays in the JSON block #rb-data.
   The 3-D view is drawn by hand on a 2-D canvas (convex meshes, back faces culled, Lambert shading),
   as are the plots.  window.rbExplorer: select(method, dt), seek(t), play(), pause(), state(), frames. */
(function () {
  "use strict";
  var D = JSON.parse(document.getElementById("rb-data").textContent);
  var $ = function (id) { return document.getElementById(id); };
  var NB = D.bodies.length, NM = D.methods.length, ND = D.dts.length;
  var CURSOR = "#f0a000", GHOST = "23,190,207";
  var SUP = { "0": "⁰", "1": "¹", "2": "²", "3": "³", "4": "⁴", "5": "⁵", "6": "⁶", "7": "⁷", "8": "⁸", "9": "⁹", "-": "⁻" };

  function f32(s) {
    var b = atob(s), u = new Uint8Array(b.length);
    for (var i = 0; i < b.length; i++) u[i] = b.charCodeAt(i);
    return new Float32Array(u.buffer);
  }
  function track(t) { return { n: t.n, t: f32(t.t), x: f32(t.x), q: f32(t.q) }; }
  var KEYS = D.panels.map(function (p) { return p.key; });
  var runs = D.runs.map(function (r) {
    var c = {};
    KEYS.forEach(function (k) { c[k] = f32(r.curves[k]); });
    return Object.assign({}, r, { ct: f32(r.curve_t), cv: c, tr: track(r.track) });
  });
  var ghost = track(D.ghost);
  function runOf(mi, di) { return runs[mi * ND + di]; }

  // --- number formatting ----------------------------------------------------------------------
  function sup(n) { return String(n).split("").map(function (c) { return SUP[c] || c; }).join(""); }
  function pow10(e) { return e === 0 ? "1" : e === 1 ? "10" : "10" + sup(e); }
  function sci(v) {
    if (!isFinite(v)) return "∞";
    if (v === 0) return "0";
    var e = Math.floor(Math.log10(Math.abs(v))), m = v / Math.pow(10, e);
    if (Math.abs(m) >= 9.95) { m /= 10; e += 1; }
    if (e >= -2 && e <= 3) return String(Number(v.toPrecision(2)));
    return m.toFixed(1) + "×10" + sup(e);
  }
  function secs(s) { return s < 1 ? (s * 1e3).toPrecision(3) + " ms" : s.toPrecision(3) + " s"; }
  function niceStep(span, n) {
    var raw = span / n, k = Math.pow(10, Math.floor(Math.log10(raw))), m = raw / k;
    return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * k;
  }
  function fmtT(v, step) { var d = Math.max(0, -Math.floor(Math.log10(step) + 1e-9)); return v.toFixed(d); }

  // --- state ----------------------------------------------------------------------------------
  var S = { mi: D.default.method, di: D.default.dt, t: 0, playing: true, speed: 1, onscreen: true,
            hold: 0, ghost: D.show_ghost, scrubbing: false };
  var api = { frames: 0 };

  // --- controls -------------------------------------------------------------------------------
  var methodButtons = D.methods.map(function (m, i) {
    var b = document.createElement("button");
    b.type = "button";
    b.innerHTML = '<span class="rb-sw" style="background:' + m.color + '"></span>';
    b.appendChild(document.createTextNode(m.name));
    b.title = m.name + " (order " + m.order + "): " + m.summary;
    b.dataset.method = m.name;
    b.addEventListener("click", function () { pick(i, S.di); });
    $("rb-methods").appendChild(b);
    return b;
  });
  var dtButtons = D.dts.map(function (d, i) {
    var b = document.createElement("button");
    b.type = "button";
    b.textContent = D.dt_labels[i] + " s";
    b.dataset.dt = D.dt_labels[i];
    b.addEventListener("click", function () { pick(S.mi, i); });
    $("rb-dts").appendChild(b);
    return b;
  });
  $("rb-play").addEventListener("click", function () { S.playing ? pause() : play(); });
  $("rb-slider").addEventListener("input", function (e) {
    seek(Number(e.target.value) / 1000 * D.t_end);
  });
  $("rb-slider").addEventListener("pointerdown", function () { S.scrubbing = true; });
  window.addEventListener("pointerup", function () { S.scrubbing = false; });
  $("rb-speed").addEventListener("change", function (e) { S.speed = Number(e.target.value); });
  $("rb-ghost").checked = S.ghost;
  $("rb-ghost").addEventListener("change", function (e) { S.ghost = e.target.checked; dirty(); });

  function play() { S.playing = true; if (S.t >= D.t_end) { S.t = 0; } S.hold = 0; lastTs = null; controls(); schedule(); }
  function pause() { S.playing = false; controls(); dirty(); }
  function seek(t) {
    S.t = Math.min(Math.max(Number(t) || 0, 0), D.t_end); S.hold = 0; dirty();
  }
  function pick(mi, di) { select(mi, di); writeFragment(); }
  function select(mi, di) {
    S.mi = mi; S.di = di;
    methodButtons.forEach(function (b, i) { b.setAttribute("aria-pressed", String(i === mi)); });
    dtButtons.forEach(function (b, i) {
      b.setAttribute("aria-pressed", String(i === di));
      var r = runOf(mi, i);
      b.classList.toggle("rb-diverged", r.diverged);
      b.title = r.diverged ? r.method + ", dt = " + D.dt_labels[i] + " s: " + r.reason
                           : D.steps[i] + " steps; error at the end " + sci(r.error) + " rad";
    });
    var r = runOf(mi, di);
    document.body.dataset.method = r.method;
    document.body.dataset.dt = D.dt_labels[di];
    var st = $("rb-status");
    var what = "<b>" + r.method + "</b>, dt = " + D.dt_labels[di] + " s (" + r.steps + " steps of " +
               Number(r.h.toPrecision(6)) + " s), wall time " + secs(r.seconds) + ": ";
    if (r.diverged) {
      st.innerHTML = what + "<b>" + esc(r.reason) + "</b>: its curves stop at its last finite state, t = " +
        fmtNum(r.t_last) + " s (×), and the animation at t = " + fmtNum(r.drawn_until) + " s" +
        (r.drawn_note ? " (" + esc(r.drawn_note.replace(/^drawn up to t = [^:]*: /, "")) + ")" : "") + ".";
      st.className = "rb-bad";
    } else {
      st.innerHTML = what + "ran to t = " + fmtNum(r.t_last) + " s; rotation error at the end " + sci(r.error) +
        " rad, position error " + sci(r.position_error) + " m.";
      st.className = "";
    }
    plots.forEach(function (p) { p.stale = true; });
    wp.stale = true;
    dirty();
  }
  function fmtNum(v) { return String(Number(v.toPrecision(4))); }
  function esc(s) { return String(s).replace(/[&<>"]/g, function (c) { return { "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" }[c]; }); }
  function controls() {
    $("rb-play").textContent = S.playing ? "❚❚ pause" : "▶ play";
    $("rb-play").setAttribute("aria-pressed", String(!S.playing));
  }

  // --- the URL fragment: #method=rk4&dt=0.002 ----------------------------------------------------
  function readFragment() {
    var h = (location.hash || "").replace(/^#/, ""), notes = [];
    var mi = D.default.method, di = D.default.dt;
    if (h) {
      var p = new URLSearchParams(h), names = D.methods.map(function (m) { return m.name; });
      p.forEach(function (v, k) { if (k !== "method" && k !== "dt") notes.push("unknown key “" + k + "” ignored"); });
      if (p.has("method")) {
        var i = names.indexOf(p.get("method"));
        if (i >= 0) mi = i;
        else notes.push("unknown method “" + p.get("method") + "”: showing the default method " + names[mi] +
                        " (this page has " + names.join(", ") + ")");
      }
      if (p.has("dt")) {
        var v = Number(p.get("dt")), j = -1;
        D.dts.forEach(function (d, k) { if (j < 0 && isFinite(v) && Math.abs(d - v) <= 1e-9 * d) j = k; });
        if (j >= 0) di = j;
        else notes.push("no step dt = “" + p.get("dt") + "” here: showing the default dt = " + D.dt_labels[di] +
                        " s (this page has dt = " + D.dt_labels.join(", ") + " s)");
      }
    }
    var note = $("rb-note");
    note.hidden = notes.length === 0;
    note.textContent = notes.length ? "Link: " + notes.join("; ") + "." : "";
    select(mi, di);
  }
  function writeFragment() {
    var h = "#method=" + D.methods[S.mi].name + "&dt=" + D.dt_labels[S.di];
    try { history.replaceState(null, "", h); } catch (e) { /* a sandboxed frame (srcdoc): no URL to update */ }
    $("rb-note").hidden = true;
  }
  window.addEventListener("hashchange", readFragment);

  // --- small vector algebra ----------------------------------------------------------------------
  function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
  function add(a, b) { return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]; }
  function mul(a, s) { return [a[0] * s, a[1] * s, a[2] * s]; }
  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
  function unit(a) { var n = Math.sqrt(dot(a, a)) || 1; return [a[0] / n, a[1] / n, a[2] / n]; }
  function rot(R, v) { return [R[0] * v[0] + R[1] * v[1] + R[2] * v[2], R[3] * v[0] + R[4] * v[1] + R[5] * v[2],
                               R[6] * v[0] + R[7] * v[1] + R[8] * v[2]]; }
  function quatR(w, x, y, z) {
    var n = Math.sqrt(w * w + x * x + y * y + z * z) || 1; w /= n; x /= n; y /= n; z /= n;
    return [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
            2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
            2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)];
  }
  // the poses of every body at time t: x lerped, q nlerped between the two nearest frames (the last after the end)
  function poses(tr, t) {
    var T = tr.t, n = tr.n, i = 0, j = 0, a = 0;
    if (t >= T[n - 1]) { i = j = n - 1; }
    else if (t > T[0]) {
      var lo = 0, hi = n - 1;
      while (hi - lo > 1) { var m = (lo + hi) >> 1; if (T[m] <= t) lo = m; else hi = m; }
      i = lo; j = hi; a = (t - T[lo]) / (T[hi] - T[lo]);
    }
    var out = [];
    for (var b = 0; b < NB; b++) {
      var xi = (i * NB + b) * 3, xj = (j * NB + b) * 3, qi = (i * NB + b) * 4, qj = (j * NB + b) * 4;
      var X = tr.x, Q = tr.q, s = 1;
      if (Q[qi] * Q[qj] + Q[qi + 1] * Q[qj + 1] + Q[qi + 2] * Q[qj + 2] + Q[qi + 3] * Q[qj + 3] < 0) s = -1;
      out.push({
        x: [X[xi] + a * (X[xj] - X[xi]), X[xi + 1] + a * (X[xj + 1] - X[xi + 1]), X[xi + 2] + a * (X[xj + 2] - X[xi + 2])],
        R: quatR(Q[qi] + a * (s * Q[qj] - Q[qi]), Q[qi + 1] + a * (s * Q[qj + 1] - Q[qi + 1]),
                 Q[qi + 2] + a * (s * Q[qj + 2] - Q[qi + 2]), Q[qi + 3] + a * (s * Q[qj + 3] - Q[qi + 3]))
      });
    }
    return out;
  }

  // --- canvases ---------------------------------------------------------------------------------
  function fit(canvas) {
    var dpr = window.devicePixelRatio || 1, w = canvas.clientWidth, h = canvas.clientHeight;
    if (canvas.width !== Math.round(w * dpr) || canvas.height !== Math.round(h * dpr)) {
      canvas.width = Math.round(w * dpr); canvas.height = Math.round(h * dpr);
    }
    var g = canvas.getContext("2d");
    g.setTransform(dpr, 0, 0, dpr, 0, 0);
    return { g: g, w: w, h: h };
  }

  // --- the 3-D view -----------------------------------------------------------------------------
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

  // --- the plots --------------------------------------------------------------------------------
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

  // --- the work-precision panel -----------------------------------------------------------------
  var WM = { l: 58, r: 24, t: 24, b: 34 };
  var wp = { canvas: $("rb-wp"), stale: true, pts: [], hover: -1 };
  function wpX(s, w) { var L = D.wp.xlim; return WM.l + (Math.log10(Math.max(s, 1e-12)) - L[0]) / (L[1] - L[0]) * (w - WM.l - WM.r); }
  function wpY(e, h) {
    var L = D.wp.ylim, v = Math.min(Math.max(Math.log10(Math.max(e, 1e-30)), L[0]), L[1]);
    return h - WM.b - (v - L[0]) / (L[1] - L[0]) * (h - WM.t - WM.b);
  }
  function drawWP() {
    var c = fit(wp.canvas), g = c.g, w = c.w, h = c.h;
    g.fillStyle = "#fff"; g.fillRect(0, 0, w, h);
    var XL = D.wp.xlim, YL = D.wp.ylim;
    g.font = "10.5px sans-serif";
    var ey = Math.max(1, Math.ceil((YL[1] - YL[0]) / 6)), ex = Math.max(1, Math.ceil((XL[1] - XL[0]) / 6));
    for (var e = YL[0]; e <= YL[1]; e++) {
      var y = wpY(Math.pow(10, e), h);
      g.strokeStyle = "#eee"; g.beginPath(); g.moveTo(WM.l, y); g.lineTo(w - WM.r, y); g.stroke();
      if (e % ey === 0) { g.fillStyle = "#444"; g.textAlign = "right"; g.textBaseline = "middle"; g.fillText(pow10(e), WM.l - 4, y); }
    }
    for (var e2 = XL[0]; e2 <= XL[1]; e2++) {
      var x = wpX(Math.pow(10, e2), w);
      g.strokeStyle = "#eee"; g.beginPath(); g.moveTo(x, WM.t); g.lineTo(x, h - WM.b); g.stroke();
      if (e2 % ex === 0) { g.fillStyle = "#444"; g.textAlign = "center"; g.textBaseline = "top"; g.fillText(pow10(e2) + " s", x, h - WM.b + 3); }
    }
    g.strokeStyle = "#888"; g.strokeRect(WM.l + 0.5, WM.t + 0.5, w - WM.l - WM.r - 1, h - WM.t - WM.b - 1);
    g.fillStyle = "#444"; g.textAlign = "center"; g.textBaseline = "bottom";
    g.fillText("wall time of the run (s, numba compile excluded)", (WM.l + w - WM.r) / 2, h - 1);
    g.save(); g.translate(11, (WM.t + h - WM.b) / 2); g.rotate(-Math.PI / 2); g.textBaseline = "middle";
    g.fillText("rotation error at t_end (rad)", 0, 0); g.restore();
    g.fillStyle = "rgba(176,0,0,0.07)"; g.fillRect(WM.l, 2, w - WM.l - WM.r, WM.t - 4);
    g.fillStyle = "#b00"; g.textAlign = "right"; g.textBaseline = "middle"; g.fillText("diverged", WM.l - 4, WM.t / 2);
    var acc = D.reference.accuracy;
    if (acc !== null && acc > 0) {
      var ya = wpY(acc, h);
      g.setLineDash([5, 4]); g.strokeStyle = "#777"; g.beginPath(); g.moveTo(WM.l, ya); g.lineTo(w - WM.r, ya); g.stroke();
      g.setLineDash([]); g.fillStyle = "#666"; g.textAlign = "right"; g.textBaseline = "bottom";
      g.fillText("the reference's own accuracy", w - WM.r - 3, ya - 2);
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
      var txt = r.method + ", dt = " + D.dt_labels[hv.di] + " s: " + secs(r.seconds) + ", " +
                (r.error === null ? "diverged" : "error " + sci(r.error) + " rad");
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
    return '<span class="rb-sw" style="background:' + m.color + '"></span>' + esc(m.name) + " (order " + m.order + ")";
  }).join("") + '<span class="rb-sw" style="border:2px solid #111;border-radius:50%;background:none"></span>the chosen run';

  // --- the animation loop: requestAnimationFrame, paused when the page is hidden or the view off-screen ---
  var raf = 0, lastTs = null, needsDraw = true;
  function visible() { return !document.hidden && S.onscreen; }
  function dirty() { needsDraw = true; schedule(); }
  function schedule() {
    if (raf) return;
    if (visible() && (S.playing || needsDraw)) raf = requestAnimationFrame(tick);
    else lastTs = null;
  }
  function advance(dt) {
    if (S.t >= D.t_end) {                    // hold the end for a second, then loop
      S.hold += dt;
      if (S.hold > 1.0) { S.t = 0; S.hold = 0; }
      return;
    }
    S.t = Math.min(S.t + dt * S.speed, D.t_end);
  }
  var lastSel = "";
  function tick(ts) {
    raf = 0;
    if (S.playing && visible()) {
      if (lastTs !== null) advance(Math.min(ts - lastTs, 100) / 1000);
      lastTs = ts;
    } else lastTs = null;
    render();
    needsDraw = false;
    api.frames++;
    schedule();
  }
  function render() {
    var sel = S.mi + ":" + S.di;
    if (sel !== lastSel) { viewLegend(); lastSel = sel; }
    drawView();
    plots.forEach(function (p) { p.draw(); });
    if (wp.stale || wp.w !== wp.canvas.clientWidth) { drawWP(); wp.w = wp.canvas.clientWidth; }
    if (!S.scrubbing) $("rb-slider").value = String(Math.round(S.t / D.t_end * 1000));
    $("rb-t").textContent = "t = " + S.t.toFixed(2) + " s";
    document.body.dataset.t = S.t.toFixed(4);
  }
  document.addEventListener("visibilitychange", function () { lastTs = null; schedule(); });
  if ("IntersectionObserver" in window) {
    new IntersectionObserver(function (entries) {
      S.onscreen = entries.some(function (e) { return e.isIntersecting; });
      lastTs = null; schedule();
    }).observe($("rb-root"));
  }
  if ("ResizeObserver" in window) {
    new ResizeObserver(function () { plots.forEach(function (p) { p.stale = true; }); wp.stale = true; dirty(); })
      .observe($("rb-main"));
  } else window.addEventListener("resize", function () { wp.stale = true; dirty(); });

  api.select = function (method, dt) {
    var mi = D.methods.map(function (m) { return m.name; }).indexOf(method), di = -1;
    D.dts.forEach(function (d, k) { if (Math.abs(d - Number(dt)) <= 1e-9 * d) di = k; });
    if (mi < 0 || di < 0) throw new Error("no run (" + method + ", " + dt + ") in this page");
    pick(mi, di);
  };
  api.seek = seek; api.play = play; api.pause = pause;
  api.points = function () {                  // the work-precision points, in CSS pixels of the page
    var rect = wp.canvas.getBoundingClientRect();
    return wp.pts.map(function (p) {
      return { method: D.methods[p.mi].name, dt: D.dts[p.di], x: rect.left + p.x, y: rect.top + p.y };
    });
  };
  api.state = function () {
    return { method: D.methods[S.mi].name, dt: D.dts[S.di], t: S.t, playing: S.playing, onscreen: S.onscreen,
             hidden: document.hidden, note: $("rb-note").hidden ? "" : $("rb-note").textContent };
  };
  window.rbExplorer = api;
  controls();
  readFragment();
})();
