/* The 3-D view: meshcat's three.js scene (meshcat's viewer script, inlined before this one; the scene's objects
   are meshcat commands made by view.py).  The page's time cursor moves it: the chosen run's bodies, the
   reference's ghost, the links (a spring's coil, a pivot's stem) stretched between their two ends, and, for one
   body that moves far, the whole drawing shifted under the camera (meshcat's camera looks at the origin).
   Poses between two frames of a track: positions lerped, quaternions nlerped.  Its legend, and the warning shown
   past the end of a run that diverged. */
var viewer = window.viewer = new MeshCat.Viewer($("meshcat-pane"));
rbCommands(viewer, D.view.commands, D.view.size);
viewer.gui.domElement.style.display = "none";         // the explorer's own controls instead of meshcat's
rbFitPane(viewer, $("meshcat-pane"));
var THREE = MeshCat.THREE;
function node(path) { return viewer.scene_tree.find(path).object; }
var bodyNodes = D.bodies.map(function (b, i) { return node(["meshcat", "bodies", String(i)]); });
var ghostNodes = D.show_ghost ? D.bodies.map(function (b, i) { return node(["meshcat", "ghost", String(i)]); }) : [];
var ghostGroup = D.show_ghost ? node(["meshcat", "ghost"]) : null;
var shifted = [node(["meshcat"]), node(["Axes"])];
var links = D.view.links.map(function (l) { return Object.assign({ obj: node(l.path) }, l); });
var Y_AXIS = new THREE.Vector3(0, 1, 0);

function place(nodes, tr, t) {
  // every body of track tr at time t (the last frame after its end)
  var T = tr.t, n = tr.n, i = 0, j = 0, a = 0;
  if (t >= T[n - 1]) { i = j = n - 1; }
  else if (t > T[0]) {
    var lo = 0, hi = n - 1;
    while (hi - lo > 1) { var m = (lo + hi) >> 1; if (T[m] <= t) lo = m; else hi = m; }
    i = lo; j = hi; a = (t - T[lo]) / (T[hi] - T[lo]);
  }
  nodes.forEach(function (obj, b) {
    var X = tr.x, Q = tr.q, xi = (i * NB + b) * 3, xj = (j * NB + b) * 3, qi = (i * NB + b) * 4, qj = (j * NB + b) * 4;
    var s = Q[qi] * Q[qj] + Q[qi + 1] * Q[qj + 1] + Q[qi + 2] * Q[qj + 2] + Q[qi + 3] * Q[qj + 3] < 0 ? -1 : 1;
    obj.position.set(X[xi] + a * (X[xj] - X[xi]), X[xi + 1] + a * (X[xj + 1] - X[xi + 1]),
                     X[xi + 2] + a * (X[xj + 2] - X[xi + 2]));
    var q = [0, 1, 2, 3].map(function (k) { return Q[qi + k] + a * (s * Q[qj + k] - Q[qi + k]); });
    obj.quaternion.set(q[1], q[2], q[3], q[0]).normalize();          // the track's (w, x, y, z); three.js's (x, y, z, w)
  });
}
function pointOf(obj, p) { return new THREE.Vector3(p[0], p[1], p[2]).applyQuaternion(obj.quaternion).add(obj.position); }
function stretch(l) {
  // a link's node: at its anchor, its +y turned to the body point and scaled to the distance
  var end = pointOf(bodyNodes[l.body], l.b);
  var from = l.anchor ? new THREE.Vector3(l.anchor[0], l.anchor[1], l.anchor[2]) : pointOf(bodyNodes[l.other], l.ob);
  var d = end.clone().sub(from), len = d.length();
  l.obj.position.copy(from);
  l.obj.quaternion.setFromUnitVectors(Y_AXIS, len > 0 ? d.divideScalar(len) : new THREE.Vector3(0, 0, -1));
  l.obj.scale.set(1, Math.max(len, 1e-9), 1);
}
function placeScene() {
  var run = runOf(S.mi, S.di);
  place(bodyNodes, run.tr, S.t);
  if (ghostGroup) { ghostGroup.visible = S.ghost; place(ghostNodes, ghost, S.t); }
  links.forEach(stretch);
  if (D.view.follow) {                      // the chosen run's body under the camera (frozen after its end)
    var p = bodyNodes[0].position;
    shifted.forEach(function (obj) { obj.position.set(-p.x, -p.y, -p.z); });
  }
  viewer.set_dirty();
  var warn = $("rb-view-warning");
  if (run.diverged && S.t > run.drawn_until) {
    warn.hidden = false;
    warn.textContent = rbSay(run.drawn_note ? "shown_last_drawable" : "shown_last_finite",
      { method: run.method, dt: D.dt_labels[S.di], reason: run.reason, t: fmtNum(run.drawn_until) });
  } else warn.hidden = true;
}
function viewLegend() {
  var run = runOf(S.mi, S.di), swatch = function (css) { return '<span class="rb-sw" style="' + css + '"></span>'; };
  $("rb-view-legend").innerHTML = swatch("background:" + D.bodies[0].color) + esc(run.method) + ", dt = " +
    D.dt_labels[S.di] + " s" + (D.show_ghost ? swatch("background:" + D.ghost_color + ";opacity:0.5") +
    esc(rbSay("ghost_reference", { label: D.reference.label })) : "") +
    (NB <= 3 ? swatch("background:linear-gradient(90deg,#f00 33%,#0f0 33% 66%,#00f 66%)") + rbSay("axes_xyz") : "") +
    '<span class="rb-sub">' + esc(rbSay("drag_hint")) + '</span>';
}
