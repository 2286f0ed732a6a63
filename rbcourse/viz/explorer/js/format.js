/* How the page writes numbers and text: powers of ten with superscripts, 2-digit scientific notation,
   durations, time-axis steps and labels, HTML escapes. */
var SUP = { "0": "⁰", "1": "¹", "2": "²", "3": "³", "4": "⁴", "5": "⁵", "6": "⁶", "7": "⁷", "8": "⁸", "9": "⁹", "-": "⁻" };
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
function fmtNum(v) { return String(Number(v.toPrecision(4))); }
function esc(s) { return String(s).replace(/[&<>"]/g, function (c) { return { "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" }[c]; }); }
