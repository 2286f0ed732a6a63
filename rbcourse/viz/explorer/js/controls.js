/* The page's state (S: the chosen run, the time, playing or not) and its controls: the method and step
   buttons, play/pause, the time slider, the speed, the ghost; select() shows a run and its status line. */
var S = { mi: D.default.method, di: D.default.dt, t: 0, playing: true, speed: 1, onscreen: true,
          hold: 0, ghost: D.show_ghost, scrubbing: false };
var api = { frames: 0 };

// --- controls -------------------------------------------------------------------------------
var methodButtons = D.methods.map(function (m, i) {
  var b = document.createElement("button");
  b.type = "button";
  b.innerHTML = '<span class="rb-sw" style="background:' + m.color + '"></span>';
  b.appendChild(document.createTextNode(m.name));
  b.title = rbSay("method_title", { name: m.name, order: m.order, summary: m.summary });
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
    b.title = r.diverged ? rbSay("run_diverged", { method: r.method, dt: D.dt_labels[i], reason: r.reason })
                         : rbSay("dt_title", { steps: D.steps[i], error: rbSci(r.error) });
  });
  var r = runOf(mi, di);
  document.body.dataset.method = r.method;
  document.body.dataset.dt = D.dt_labels[di];
  var st = $("rb-status");
  var what = rbSay("status", { method: r.method, dt: D.dt_labels[di], steps: r.steps, h: Number(r.h.toPrecision(6)),
                               seconds: secs(r.seconds) });
  if (r.diverged) {
    st.innerHTML = what + rbSay("status_diverged", { reason: esc(r.reason), t_last: fmtNum(r.t_last),
      drawn: fmtNum(r.drawn_until), why: r.drawn_note ? " (" + esc(r.drawn_note.replace(/^[^:]*:\s*/, "")) + ")" : "" });
    st.className = "rb-bad";
  } else {
    st.innerHTML = what + rbSay("status_ran", { t_last: fmtNum(r.t_last), error: rbSci(r.error),
                                                position: rbSci(r.position_error) });
    st.className = "";
  }
  wp.stale = true;
  dirty();
}
function controls() {
  $("rb-play").textContent = rbSay(S.playing ? "pause" : "play");
  $("rb-play").setAttribute("aria-pressed", String(!S.playing));
}
