//! A C¹ curve through a polyline (centripetal Catmull–Rom, in cubic Hermite form) with exact
//! closest-point queries and a check of its reach: the closest-point map to a polyline jumps across
//! the bisector of every corner, so a modulation measured from it would tear or fold, whereas
//! within the reach of a C¹ curve of bounded curvature it is continuous.

use glam::DVec2;

use crate::WarpError;

/// One cubic Hermite segment `c(s) = h₀₀P₁ + h₁₀m₁ + h₀₁P₂ + h₁₁m₂`, s ∈ [0, 1].
#[derive(Debug, Clone, Copy)]
struct Segment {
    p1: DVec2,
    p2: DVec2,
    m1: DVec2,
    m2: DVec2,
}

impl Segment {
    fn at(&self, s: f64) -> DVec2 {
        let (s2, s3) = (s * s, s * s * s);
        (2.0 * s3 - 3.0 * s2 + 1.0) * self.p1
            + (s3 - 2.0 * s2 + s) * self.m1
            + (-2.0 * s3 + 3.0 * s2) * self.p2
            + (s3 - s2) * self.m2
    }

    fn d1(&self, s: f64) -> DVec2 {
        let s2 = s * s;
        (6.0 * s2 - 6.0 * s) * self.p1
            + (3.0 * s2 - 4.0 * s + 1.0) * self.m1
            + (-6.0 * s2 + 6.0 * s) * self.p2
            + (3.0 * s2 - 2.0 * s) * self.m2
    }

    fn d2(&self, s: f64) -> DVec2 {
        (12.0 * s - 6.0) * self.p1 + (6.0 * s - 4.0) * self.m1 + (-12.0 * s + 6.0) * self.p2 + (6.0 * s - 2.0) * self.m2
    }

    /// The point of the segment nearest to `p`: best of a coarse sampling, then Newton on
    /// `(c(s) − p)·c′(s) = 0`.
    fn closest(&self, p: DVec2) -> (f64, DVec2) {
        const COARSE: usize = 16;
        let mut best = (0.0, f64::INFINITY);
        for i in 0..=COARSE {
            let s = i as f64 / COARSE as f64;
            let d = self.at(s).distance_squared(p);
            if d < best.1 {
                best = (s, d);
            }
        }
        let mut s = best.0;
        for _ in 0..12 {
            let (c, d1, d2) = (self.at(s), self.d1(s), self.d2(s));
            let f = (c - p).dot(d1);
            let df = d1.length_squared() + (c - p).dot(d2);
            if df <= 0.0 {
                break;
            }
            let next = (s - f / df).clamp(0.0, 1.0);
            if (next - s).abs() < 1e-14 {
                s = next;
                break;
            }
            s = next;
        }
        let q = self.at(s);
        let d = q.distance_squared(p);
        if d <= best.1 { (d, q) } else { (best.1, self.at(best.0)) }
    }

    /// Radius of curvature at `s`.
    fn curvature_radius(&self, s: f64) -> f64 {
        let (d1, d2) = (self.d1(s), self.d2(s));
        let cross = d1.perp_dot(d2).abs();
        if cross == 0.0 { f64::INFINITY } else { d1.length().powi(3) / cross }
    }
}

/// The smooth curve through a stroke's points, with the segments' bounding boxes for queries.
#[derive(Debug, Clone)]
pub(crate) struct SmoothCurve {
    segments: Vec<Segment>,
    boxes: Vec<[DVec2; 2]>,
}

/// Samples per segment for bounding boxes, curvature and the self-distance check.
const SAMPLES: usize = 32;

impl SmoothCurve {
    /// The centripetal Catmull–Rom curve through `pts` (≥ 2 distinct consecutive points), with
    /// reflected phantom points at both ends.
    pub(crate) fn new(pts: &[DVec2]) -> Self {
        let n = pts.len();
        let get = |i: isize| -> DVec2 {
            if i < 0 {
                2.0 * pts[0] - pts[1]
            } else if i as usize >= n {
                2.0 * pts[n - 1] - pts[n - 2]
            } else {
                pts[i as usize]
            }
        };
        let segments: Vec<Segment> = (0..n - 1)
            .map(|i| {
                let i = i as isize;
                let (p0, p1, p2, p3) = (get(i - 1), get(i), get(i + 1), get(i + 2));
                let dt = |a: DVec2, b: DVec2| a.distance(b).sqrt().max(1e-12);
                let (t01, t12, t23) = (dt(p0, p1), dt(p1, p2), dt(p2, p3));
                // Centripetal tangents, scaled to the segment's parameter interval.
                let m1 = t12 * ((p1 - p0) / t01 - (p2 - p0) / (t01 + t12) + (p2 - p1) / t12);
                let m2 = t12 * ((p2 - p1) / t12 - (p3 - p1) / (t12 + t23) + (p3 - p2) / t23);
                Segment { p1, p2, m1, m2 }
            })
            .collect();
        let boxes = segments
            .iter()
            .map(|s| {
                let pts = (0..=SAMPLES).map(|k| s.at(k as f64 / SAMPLES as f64));
                let (lo, hi) = pts.fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), q| (lo.min(q), hi.max(q)));
                // A cubic strays a little beyond its samples: pad by a tenth of the box.
                let pad = 0.1 * (hi - lo).max_element();
                [lo - DVec2::splat(pad), hi + DVec2::splat(pad)]
            })
            .collect();
        Self { segments, boxes }
    }

    /// Bounding box of the curve.
    pub(crate) fn bounds(&self) -> [DVec2; 2] {
        self.boxes.iter().fold([DVec2::INFINITY, DVec2::NEG_INFINITY], |[lo, hi], [a, b]| [lo.min(*a), hi.max(*b)])
    }

    /// The point of the curve nearest to `p`, if one lies within `max` of it.
    pub(crate) fn closest_within(&self, p: DVec2, max: f64) -> Option<DVec2> {
        let mut best: Option<(f64, DVec2)> = None;
        for (seg, [lo, hi]) in self.segments.iter().zip(&self.boxes) {
            let gap = (p - p.clamp(*lo, *hi)).length();
            if gap > max || best.is_some_and(|(d, _)| gap * gap > d) {
                continue;
            }
            let (d, q) = seg.closest(p);
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, q));
            }
        }
        best.filter(|(d, _)| *d < max * max).map(|(_, q)| q)
    }

    /// Checks that the curve's reach exceeds `radius`: curvature radius above it everywhere, and
    /// parts farther apart along the curve than half a turn of that radius at least `2·radius`
    /// apart in the plane.
    pub(crate) fn check_reach(&self, radius: f64) -> Result<(), WarpError> {
        let mut samples = Vec::new();
        let mut arc = Vec::new();
        let mut s_acc = 0.0;
        for seg in &self.segments {
            for k in 0..SAMPLES {
                let s = k as f64 / SAMPLES as f64;
                let r = seg.curvature_radius(s);
                if r < radius {
                    return Err(WarpError::CurvatureTooHigh { at: seg.at(s), curvature_radius: r, radius });
                }
                let q = seg.at(s);
                if let Some(&last) = samples.last() {
                    s_acc += q.distance(last);
                }
                samples.push(q);
                arc.push(s_acc);
            }
        }
        let end = self.segments[self.segments.len() - 1].at(1.0);
        s_acc += end.distance(samples[samples.len() - 1]);
        samples.push(end);
        arc.push(s_acc);
        // Pairs of samples more than half a turn apart along the curve, via a grid of cell 2r.
        let cell = 2.0 * radius;
        let key = |q: DVec2| ((q.x / cell).floor() as i64, (q.y / cell).floor() as i64);
        let mut grid: std::collections::HashMap<(i64, i64), Vec<usize>> = std::collections::HashMap::new();
        for (i, &q) in samples.iter().enumerate() {
            grid.entry(key(q)).or_default().push(i);
        }
        let far = std::f64::consts::PI * radius;
        for (i, &q) in samples.iter().enumerate() {
            let (kx, ky) = key(q);
            for dy in -1..=1 {
                for dx in -1..=1 {
                    for &j in grid.get(&(kx + dx, ky + dy)).map_or(&[][..], Vec::as_slice) {
                        if j > i && arc[j] - arc[i] > far {
                            let d = q.distance(samples[j]);
                            if d < 2.0 * radius {
                                return Err(WarpError::CurveTooClose { a: q, b: samples[j], distance: d, radius });
                            }
                        }
                    }
                }
            }
        }
        Ok(())
    }
}
