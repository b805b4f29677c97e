// Feature-curve geometry for the studio's curve tools: the scene's curves are piecewise cubic
// Béziers (control polygon p₀, c₀, c₁, p₁, …), their constraints placed by normalised arc length
// `u`, as `relief-diffusion-multigrid` reads them.

/** A smooth cubic Bézier spline through `anchors` (Catmull-Rom tangents, ends clamped): its
 * control polygon, 3(n − 1) + 1 points, each passed through `round`. */
export function smoothThrough(anchors, round = (p) => p) {
  const n = anchors.length;
  if (n < 2) return [];
  const at = (k) => anchors[Math.max(0, Math.min(n - 1, k))];
  const control = [round(anchors[0])];
  for (let k = 0; k + 1 < n; k++) {
    const [p0, p1, p2, p3] = [at(k - 1), at(k), at(k + 1), at(k + 2)];
    control.push(round([p1[0] + (p2[0] - p0[0]) / 6, p1[1] + (p2[1] - p0[1]) / 6]));
    control.push(round([p2[0] - (p3[0] - p1[0]) / 6, p2[1] - (p3[1] - p1[1]) / 6]));
    control.push(round(p2));
  }
  return control;
}

/** Point at parameter `t` ∈ [0, 1] of the cubic piece `a b c d`. */
function cubic(a, b, c, d, t) {
  const s = 1 - t;
  const [wa, wb, wc, wd] = [s * s * s, 3 * s * s * t, 3 * s * t * t, t * t * t];
  return [wa * a[0] + wb * b[0] + wc * c[0] + wd * d[0], wa * a[1] + wb * b[1] + wc * c[1] + wd * d[1]];
}

/** The centre line of a control polygon (2 points, or 3k + 1), `perPiece` samples a piece. */
export function centreLine(points, perPiece = 32) {
  if (points.length === 2) return points.slice();
  const line = [points[0]];
  for (let k = 0; k + 3 < points.length; k += 3) {
    for (let s = 1; s <= perPiece; s++) line.push(cubic(points[k], points[k + 1], points[k + 2], points[k + 3], s / perPiece));
  }
  return line;
}

/** The sample of `line` nearest `p`: `{ u, distance, point }`, `u` its normalised arc length. */
export function nearestOnLine(line, p) {
  const lengths = [0];
  for (let k = 1; k < line.length; k++) {
    lengths.push(lengths[k - 1] + Math.hypot(line[k][0] - line[k - 1][0], line[k][1] - line[k - 1][1]));
  }
  const total = lengths[lengths.length - 1] || 1;
  let best = { u: 0, distance: Infinity, point: line[0] };
  for (let k = 0; k + 1 < line.length; k++) {
    const [a, b] = [line[k], line[k + 1]];
    const [ex, ey] = [b[0] - a[0], b[1] - a[1]];
    const len2 = ex * ex + ey * ey;
    const t = len2 > 0 ? Math.max(0, Math.min(1, ((p[0] - a[0]) * ex + (p[1] - a[1]) * ey) / len2)) : 0;
    const q = [a[0] + t * ex, a[1] + t * ey];
    const distance = Math.hypot(p[0] - q[0], p[1] - q[1]);
    if (distance < best.distance) best = { u: (lengths[k] + t * (lengths[k + 1] - lengths[k])) / total, distance, point: q };
  }
  return best;
}

/** The point at normalised arc length `u` along `line`. */
export function pointAt(line, u) {
  const lengths = [0];
  for (let k = 1; k < line.length; k++) {
    lengths.push(lengths[k - 1] + Math.hypot(line[k][0] - line[k - 1][0], line[k][1] - line[k - 1][1]));
  }
  const target = u * lengths[lengths.length - 1];
  for (let k = 1; k < line.length; k++) {
    if (lengths[k] >= target) {
      const t = lengths[k] > lengths[k - 1] ? (target - lengths[k - 1]) / (lengths[k] - lengths[k - 1]) : 0;
      return [line[k - 1][0] + t * (line[k][0] - line[k - 1][0]), line[k - 1][1] + t * (line[k][1] - line[k - 1][1])];
    }
  }
  return line[line.length - 1];
}

/** `points` with control point `k` moved by `by`; an anchor (every third point) takes its two
 * handles along, so the curve keeps its shape around it. A new array. */
export function moveControl(points, k, by, round = (p) => p) {
  const moved = points.map((p) => p.slice());
  const shift = (i) => {
    if (i >= 0 && i < moved.length) moved[i] = round([moved[i][0] + by[0], moved[i][1] + by[1]]);
  };
  shift(k);
  if (points.length > 2 && k % 3 === 0) {
    shift(k - 1);
    shift(k + 1);
  }
  return moved;
}

/** `constraints` with `added` in place of any within `tolerance` of its `u`, sorted by `u`. */
export function placeConstraint(constraints, added, tolerance = 0.02) {
  return constraints
    .filter((c) => Math.abs(c.u - added.u) > tolerance)
    .concat([added])
    .sort((a, b) => a.u - b.u);
}
