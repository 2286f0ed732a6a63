/* window.rbExplorer, the page's API (select, seek, play, pause, points, state, frames), and the start:
   the controls, then the run the URL fragment names, drawn at once. */
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
render();                                  // placed and drawn now: meshcat's first frame shows the chosen run
