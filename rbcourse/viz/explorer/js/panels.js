/* The drift panels, one a panel of D.panels, drawn by the plotting code the linked view uses (RbPlot, in
   viewer/js/timeplots.js): the chosen run in full, the chosen method's other steps in pale, where a run diverged,
   the time cursor and the value under it; a click or a drag on a panel seeks there. */
var plots = D.panels.map(function (p) {
  return new RbPlot($("rb-plots"), p, { span: [0, D.t_end], log: p.ylim, t0: p.mode === "drift" ? D.t0 : null,
                                        seek: seek });
});
function curveOf(r, key, pale) {
  return { t: r.ct, v: r.cv[key], color: D.methods[S.mi].color, pale: pale,
           end: r.diverged && r.t_diverged !== null ? r.t_diverged : null };
}
function drawPlots() {
  var r = runOf(S.mi, S.di);
  plots.forEach(function (plot) {
    var key = plot.panel.key, curves = [];
    for (var di = 0; di < ND; di++) if (di !== S.di) curves.push(curveOf(runOf(S.mi, di), key, true));
    curves.push(curveOf(r, key, false));
    plot.draw(S.t, curves);
    var c = plot.canvas, v = r.cv[key];
    c.dataset.run = r.method + " " + D.dt_labels[S.di];
    c.dataset.points = String(r.ct.length);
    c.dataset.last = String(v[v.length - 1]);
  });
}
