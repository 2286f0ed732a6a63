/* How the page writes numbers and text (besides the plots' rbSci and rbPow10): durations, short numbers, HTML
   escapes. */
function secs(s) { return s < 1 ? (s * 1e3).toPrecision(3) + " ms" : s.toPrecision(3) + " s"; }
function fmtNum(v) { return String(Number(v.toPrecision(4))); }
function esc(s) { return String(s).replace(/[&<>"]/g, function (c) { return { "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" }[c]; }); }
