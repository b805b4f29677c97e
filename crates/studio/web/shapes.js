// Re-editing what was drawn: the points of the feature-curve presets (ridges, riverbeds, cliffs,
// hill crests, cracks, a mountain's peak and ends) and the corners of the contour regions. Pure
// functions of the scene: the page picks, then edits a copy through them.

/** Every movable point of the scene's presets: `{ preset, key, k, q }`, where `key` is the
 * field (`points`, `peak` or `ends`), `k` the index in it (0 for `peak`) and `q` the point. */
export function presetPoints(presets) {
  const found = [];
  (presets || []).forEach((preset, p) => {
    const v = Object.values(preset)[0];
    (v.points || []).forEach((q, k) => found.push({ preset: p, key: "points", k, q }));
    if (v.peak) found.push({ preset: p, key: "peak", k: 0, q: v.peak });
    (v.ends || []).forEach((q, k) => found.push({ preset: p, key: "ends", k, q }));
  });
  return found;
}

/** Moves the preset point `at` (one of [`presetPoints`]) of `presets` to `to`, in place. */
export function movePresetPoint(presets, at, to) {
  const v = Object.values(presets[at.preset])[0];
  if (at.key === "peak") v.peak = to;
  else v[at.key][at.k] = to;
}

/** The polylines a preset is drawn as: its course, or its peak joined to each end. */
export function presetLines(preset) {
  const v = Object.values(preset)[0];
  const lines = v.points ? [v.points] : [];
  return lines.concat((v.ends || []).map((end) => [v.peak, end]));
}

/** Distance from `p` to the polyline `line`. */
export function distanceToLine(line, p) {
  let best = Infinity;
  for (let k = 0; k + 1 < line.length; k++) {
    const [a, b] = [line[k], line[k + 1]];
    const [ex, ey] = [b[0] - a[0], b[1] - a[1]];
    const len2 = ex * ex + ey * ey;
    const t = len2 > 0 ? Math.max(0, Math.min(1, ((p[0] - a[0]) * ex + (p[1] - a[1]) * ey) / len2)) : 0;
    best = Math.min(best, Math.hypot(p[0] - a[0] - t * ex, p[1] - a[1] - t * ey));
  }
  return line.length === 1 ? Math.hypot(p[0] - line[0][0], p[1] - line[0][1]) : best;
}

/** Whether `p` lies inside the closed ring `ring` (even-odd rule). */
export function insideRing(ring, p) {
  let inside = false;
  for (let k = 0, j = ring.length - 1; k < ring.length; j = k++) {
    const [a, b] = [ring[k], ring[j]];
    if (a[1] > p[1] !== b[1] > p[1] && p[0] < ((b[0] - a[0]) * (p[1] - a[1])) / (b[1] - a[1]) + a[0]) inside = !inside;
  }
  return inside;
}

/** Absolute area of the ring `ring`. */
function area(ring) {
  let twice = 0;
  for (let k = 0, j = ring.length - 1; k < ring.length; j = k++) twice += ring[j][0] * ring[k][1] - ring[k][0] * ring[j][1];
  return Math.abs(twice) / 2;
}

/** The index of the innermost (smallest) region whose outline holds `p`, or -1. */
export function regionAt(regions, p) {
  let best = -1;
  (regions || []).forEach((region, k) => {
    const ring = region.polygon.exterior;
    if (insideRing(ring, p) && (best < 0 || area(ring) < area(regions[best].polygon.exterior))) best = k;
  });
  return best;
}

/** Every region corner: `{ region, k, q }`. */
export function regionCorners(regions) {
  return (regions || []).flatMap((region, r) => region.polygon.exterior.map((q, k) => ({ region: r, k, q })));
}
