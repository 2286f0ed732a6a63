/* Small vector algebra on [x, y, z] arrays and row-major 3×3 matrices, and the bodies' poses at a time t
   (positions lerped, quaternions nlerped between the two nearest frames of a track). */
function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
function add(a, b) { return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]; }
function mul(a, s) { return [a[0] * s, a[1] * s, a[2] * s]; }
function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
function unit(a) { var n = Math.sqrt(dot(a, a)) || 1; return [a[0] / n, a[1] / n, a[2] / n]; }
function rot(R, v) { return [R[0] * v[0] + R[1] * v[1] + R[2] * v[2], R[3] * v[0] + R[4] * v[1] + R[5] * v[2],
                             R[6] * v[0] + R[7] * v[1] + R[8] * v[2]]; }
function quatR(w, x, y, z) {
  var n = Math.sqrt(w * w + x * x + y * y + z * z) || 1; w /= n; x /= n; y /= n; z /= n;
  return [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
          2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
          2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)];
}
// the poses of every body at time t: x lerped, q nlerped between the two nearest frames (the last after the end)
function poses(tr, t) {
  var T = tr.t, n = tr.n, i = 0, j = 0, a = 0;
  if (t >= T[n - 1]) { i = j = n - 1; }
  else if (t > T[0]) {
    var lo = 0, hi = n - 1;
    while (hi - lo > 1) { var m = (lo + hi) >> 1; if (T[m] <= t) lo = m; else hi = m; }
    i = lo; j = hi; a = (t - T[lo]) / (T[hi] - T[lo]);
  }
  var out = [];
  for (var b = 0; b < NB; b++) {
    var xi = (i * NB + b) * 3, xj = (j * NB + b) * 3, qi = (i * NB + b) * 4, qj = (j * NB + b) * 4;
    var X = tr.x, Q = tr.q, s = 1;
    if (Q[qi] * Q[qj] + Q[qi + 1] * Q[qj + 1] + Q[qi + 2] * Q[qj + 2] + Q[qi + 3] * Q[qj + 3] < 0) s = -1;
    out.push({
      x: [X[xi] + a * (X[xj] - X[xi]), X[xi + 1] + a * (X[xj + 1] - X[xi + 1]), X[xi + 2] + a * (X[xj + 2] - X[xi + 2])],
      R: quatR(Q[qi] + a * (s * Q[qj] - Q[qi]), Q[qi + 1] + a * (s * Q[qj + 1] - Q[qi + 1]),
               Q[qi + 2] + a * (s * Q[qj + 2] - Q[qi + 2]), Q[qi + 3] + a * (s * Q[qj + 3] - Q[qi + 3]))
    });
  }
  return out;
}
