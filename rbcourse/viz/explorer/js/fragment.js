/* The URL fragment #method=…&dt=…: read when the page opens and on hashchange (an unknown value falls back
   to the default, with a visible note), written (history.replaceState) when a run is picked. */
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
