/* The page's data: the JSON block #rb-data ({lzma, size}: the data's JSON compressed, page.py) decoded once
   (rbLzma, the viewer's runtime; the runs' base64 float32 arrays as Float32Arrays),
   the names every other file of the page's script uses (D, $, NB, NM, ND, runs, ghost, runOf). */
var PACKED = JSON.parse(document.getElementById("rb-data").textContent);
var BYTES = rbLzma(PACKED.lzma, PACKED.size);
var D = JSON.parse(new TextDecoder().decode(BYTES.subarray(0, PACKED.json)));
var FLOATS = (function (b) {                 // the arrays' buffer, its bytes regrouped by place (data.py: Arrays)
  var n = b.length / 4, u = new Uint8Array(b.length);
  for (var k = 0; k < 4; k++) for (var i = 0; i < n; i++) u[4 * i + k] = b[k * n + i];
  return new Float32Array(u.buffer);
})(BYTES.subarray(PACKED.json));
var $ = function (id) { return document.getElementById(id); };
RB_WORDS = D.words;                 // the page's words (viz/words.py), read by rbSay
var NB = D.bodies.length, NM = D.methods.length, ND = D.dts.length;

function f32(ref) { return FLOATS.subarray(ref.f32[0], ref.f32[0] + ref.f32[1]); }
function track(t) { return { n: t.n, t: f32(t.t), x: f32(t.x), q: f32(t.q) }; }
var KEYS = D.panels.map(function (p) { return p.key; });
var runs = D.runs.map(function (r) {
  var c = {};
  KEYS.forEach(function (k) { c[k] = f32(r.curves[k]); });
  return Object.assign({}, r, { ct: f32(r.curve_t), cv: c, tr: track(r.track) });
});
var ghost = track(D.ghost);
function runOf(mi, di) { return runs[mi * ND + di]; }
