/* The URL fragment #method=…&dt=…&t=…: read when the page opens and on hashchange (an unknown value falls back
   to the default, with a visible note; t: that time, paused), written (history.replaceState, method and dt) when a
   run is picked. */
function readFragment() {
  var h = (location.hash || "").replace(/^#/, ""), notes = [];
  var mi = D.default.method, di = D.default.dt;
  if (h) {
    var p = new URLSearchParams(h), names = D.methods.map(function (m) { return m.name; });
    p.forEach(function (v, k) { if (["method", "dt", "t"].indexOf(k) < 0) notes.push(rbSay("unknown_key", { key: k })); });
    if (p.has("method")) {
      var i = names.indexOf(p.get("method"));
      if (i >= 0) mi = i;
      else notes.push(rbSay("unknown_method", { method: p.get("method"), default: names[mi], all: names.join(", ") }));
    }
    if (p.has("dt")) {
      var v = Number(p.get("dt")), j = -1;
      D.dts.forEach(function (d, k) { if (j < 0 && isFinite(v) && Math.abs(d - v) <= 1e-9 * d) j = k; });
      if (j >= 0) di = j;
      else notes.push(rbSay("unknown_dt", { dt: p.get("dt"), default: D.dt_labels[di], all: D.dt_labels.join(", ") }));
    }
  }
  var t = h ? new URLSearchParams(h).get("t") : null;
  if (t !== null) {                              // #t=1.5: that time, paused (as a linked view's page)
    if (t !== "" && isFinite(Number(t)) && Number(t) >= 0 && Number(t) <= D.t_end) { pause(); seek(Number(t)); }
    else notes.push(rbSay("bad_link_t", { t: t, t_end: D.t_end }));
  }
  var note = $("rb-note");
  note.hidden = notes.length === 0;
  note.textContent = notes.length ? rbSay("link", { notes: notes.join(rbSay("semicolon")) }) : "";
  select(mi, di);
}
function writeFragment() {
  var h = "#method=" + D.methods[S.mi].name + "&dt=" + D.dt_labels[S.di];
  try { history.replaceState(null, "", h); } catch (e) { /* a sandboxed frame (srcdoc): no URL to update */ }
  $("rb-note").hidden = true;
}
window.addEventListener("hashchange", readFragment);
