/* The animation loop: requestAnimationFrame while playing or when something changed, stopped while the
   page is hidden or scrolled out of view; render() places meshcat's scene, draws the plots and the panel. */
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
  placeScene();
  drawPlots();
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
  new ResizeObserver(function () { viewer.set_3d_pane_size(); wp.stale = true; dirty(); }).observe($("rb-main"));
} else window.addEventListener("resize", function () { viewer.set_3d_pane_size(); wp.stale = true; dirty(); });
