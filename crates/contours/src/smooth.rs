use glam::DVec2;
use relief_tin::poisson_sampling::{orient, segment_distance_sq};
use serde::{Deserialize, Serialize};

use crate::geometry::{BoxIndex, segments_touch};
use crate::{ContourSet, ContoursError};

/// Parameters of contour smoothing (the contours paper, §5.1):
/// `qᵢ ← (1 − α)·qᵢ + α/(2k)·Σⱼ₌₁..ₖ (qᵢ₋ⱼ + qᵢ₊ⱼ)`, repeated `iterations` times.
/// In JSON every field is optional (defaults α = 0.5, k = 2, 4 passes).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct Smoothing {
    /// Strength α in (0, 1] (default 0.5).
    pub alpha: f64,
    /// Neighbourhood half-width k ≥ 1, vertices on each side (default 2).
    pub k: usize,
    /// Number of passes (default 4).
    pub iterations: u32,
    /// A brush: smooth only around this point, full strength at it and fading to none at
    /// `radius` (weight `(1 − (d/radius)²)²`). Give both or neither.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "schemars", schemars(with = "Option<[f64; 2]>"))]
    pub centre: Option<DVec2>,
    /// The brush radius, in world units.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
}

impl Smoothing {
    /// Checks the parameters: α in (0, 1], k ≥ 1.
    ///
    /// # Errors
    /// [`ContoursError::InvalidSmoothing`] naming the parameter.
    pub fn validate(&self) -> Result<(), ContoursError> {
        if !(self.alpha > 0.0 && self.alpha <= 1.0) {
            return Err(ContoursError::InvalidSmoothing {
                field: "alpha",
                value: self.alpha,
                reason: "must be in (0, 1]",
            });
        }
        if self.k == 0 {
            return Err(ContoursError::InvalidSmoothing { field: "k", value: 0.0, reason: "must be at least 1" });
        }
        match (self.centre, self.radius) {
            (Some(_), None) => {
                return Err(ContoursError::InvalidSmoothing {
                    field: "radius",
                    value: f64::NAN,
                    reason: "a brush needs a radius with its centre",
                });
            }
            (None, Some(r)) => {
                return Err(ContoursError::InvalidSmoothing {
                    field: "centre",
                    value: r,
                    reason: "a brush needs a centre with its radius",
                });
            }
            (Some(c), Some(r)) if !(c.is_finite() && r.is_finite() && r > 0.0) => {
                return Err(ContoursError::InvalidSmoothing {
                    field: "radius",
                    value: r,
                    reason: "must be finite and > 0, at a finite centre",
                });
            }
            (None, None) | (Some(_), Some(_)) => {}
        }
        Ok(())
    }
}

impl Default for Smoothing {
    fn default() -> Self {
        Self { alpha: 0.5, k: 2, iterations: 4, centre: None, radius: None }
    }
}

/// How many times a blocked move is halved before it is skipped.
const RETRIES: u32 = 3;

/// Minimum feature size kept by smoothing, as a fraction of the set's median segment length.
const CLEARANCE: f64 = 0.1;

impl ContourSet {
    /// Smooths every contour without ever making two contours (or two parts of one) touch or cross.
    ///
    /// The paper gives no such guarantee; here each vertex move sweeps the two triangles between
    /// the old and the new position, and the move is taken only if no other segment meets them
    /// (exact predicates) — a blocked move is halved up to three times, then skipped. Any crossing
    /// would have to pass through the swept area, so nesting is preserved exactly. A move must also
    /// keep a minimum feature size (a tenth of the median segment length) between the moved vertex
    /// and other segments, along its new segments, and between them and other vertices, so small
    /// loops stop shrinking before they degenerate. Endpoints of open contours stay fixed.
    ///
    /// # Errors
    /// [`ContoursError::InvalidSmoothing`] for α outside (0, 1] or k = 0.
    pub fn smoothed(&self, params: &Smoothing) -> Result<ContourSet, ContoursError> {
        params.validate()?;
        let mut pts: Vec<Vec<DVec2>> = self.contours().iter().map(|c| c.points.clone()).collect();
        let closed: Vec<bool> = self.contours().iter().map(|c| c.closed).collect();
        let mut lengths: Vec<f64> =
            self.contours().iter().flat_map(|c| c.segments().map(|[a, b]| a.distance(b))).collect();
        let clearance = if lengths.is_empty() {
            0.0
        } else {
            let mid = lengths.len() / 2;
            CLEARANCE * *lengths.select_nth_unstable_by(mid, f64::total_cmp).1
        };
        for _ in 0..params.iterations {
            pass(&mut pts, &closed, params, clearance);
        }
        self.with_geometry(pts)
    }
}

/// Where vertex `i` of a polyline wants to go (Jacobi: from the pass's starting positions).
fn target(p: &[DVec2], closed: bool, i: usize, params: &Smoothing) -> Option<DVec2> {
    let n = p.len();
    if !closed && (i == 0 || i + 1 == n) {
        return None;
    }
    // Open polylines use the neighbours that exist, symmetrically.
    let k = if closed { params.k.min((n - 1) / 2) } else { params.k.min(i).min(n - 1 - i) };
    if k == 0 {
        return None;
    }
    let alpha = params.alpha * params.weight(p[i]);
    if alpha == 0.0 {
        return None;
    }
    let sum: DVec2 = (1..=k).map(|j| p[(i + n - j) % n] + p[(i + j) % n]).sum();
    Some((1.0 - alpha) * p[i] + alpha / (2.0 * k as f64) * sum)
}

impl Smoothing {
    /// The brush's weight at `p`: 1 without a brush, else `(1 − (d/radius)²)²` inside it and 0
    /// beyond.
    pub fn weight(&self, p: DVec2) -> f64 {
        match (self.centre, self.radius) {
            (Some(c), Some(r)) => {
                let t = p.distance_squared(c) / (r * r);
                if t >= 1.0 { 0.0 } else { (1.0 - t) * (1.0 - t) }
            }
            _ => 1.0,
        }
    }
}

/// Smooths the heights of a TIN's nodes as [`ContourSet::smoothed`] smooths contour vertices:
/// `hᵢ ← (1 − α)·hᵢ + α·mean(h over the nodes within k edges)`, brush-weighted, `iterations`
/// times, each height then kept inside `bounds(i)` (its level's slice, so every input contour
/// stays where it is). For the TIN reconstruction, whose terrain is the nodes' surface.
///
/// # Errors
/// [`ContoursError::InvalidSmoothing`] for invalid parameters.
pub fn smooth_heights(
    tin: &relief_tin::Tin,
    heights: &mut [f64],
    params: &Smoothing,
    bounds: impl Fn(usize) -> (f64, f64) + Sync,
) -> Result<(), ContoursError> {
    use rayon::prelude::*;
    params.validate()?;
    let rings = ring_neighbours(tin, params.k);
    let weights: Vec<f64> = tin.points().par_iter().map(|&p| params.alpha * params.weight(p)).collect();
    for _ in 0..params.iterations {
        let next: Vec<f64> = (0..heights.len())
            .into_par_iter()
            .map(|i| {
                let (h, a) = (heights[i], weights[i]);
                if a == 0.0 || rings[i].is_empty() {
                    return h;
                }
                let mean = rings[i].iter().map(|&j| heights[j as usize]).sum::<f64>() / rings[i].len() as f64;
                let (lo, hi) = bounds(i);
                ((1.0 - a) * h + a * mean).clamp(lo, hi)
            })
            .collect();
        heights.copy_from_slice(&next);
    }
    Ok(())
}

/// The nodes within `k` edges of each node (itself excluded).
fn ring_neighbours(tin: &relief_tin::Tin, k: usize) -> Vec<Vec<u32>> {
    use rayon::prelude::*;
    (0..tin.num_points() as u32)
        .into_par_iter()
        .map(|v| {
            let mut seen = vec![v];
            let mut frontier = vec![v];
            for _ in 0..k {
                let mut next = Vec::new();
                for &u in &frontier {
                    for &w in tin.neighbors(u) {
                        if !seen.contains(&w) {
                            seen.push(w);
                            next.push(w);
                        }
                    }
                }
                frontier = next;
            }
            seen.remove(0);
            seen
        })
        .collect()
}

fn pass(pts: &mut [Vec<DVec2>], closed: &[bool], params: &Smoothing, clearance: f64) {
    let targets: Vec<Vec<Option<DVec2>>> =
        pts.iter().zip(closed).map(|(p, &c)| (0..p.len()).map(|i| target(p, c, i, params)).collect()).collect();
    // Each segment is indexed by the box of every position it can take during this pass (its
    // endpoints move, at most, straight to their targets), so queries need no global margin.
    let mut boxes = Vec::new();
    let mut owner = Vec::new();
    let mut total = 0.0;
    for (k, p) in pts.iter().enumerate() {
        let n = p.len();
        let count = if closed[k] { n } else { n - 1 };
        for i in 0..count {
            let j = (i + 1) % n;
            let corners = [p[i], p[j], targets[k][i].unwrap_or(p[i]), targets[k][j].unwrap_or(p[j])];
            let lo = corners.iter().fold(DVec2::INFINITY, |m, q| m.min(*q));
            let hi = corners.iter().fold(DVec2::NEG_INFINITY, |m, q| m.max(*q));
            total += p[i].distance(p[j]);
            boxes.push([lo, hi]);
            owner.push((k, i));
        }
    }
    let index = BoxIndex::new(&boxes, 2.0 * total / boxes.len().max(1) as f64);
    let ctx = Context { closed, index: &index, owner: &owner, clearance };
    for k in 0..pts.len() {
        for i in 0..pts[k].len() {
            let Some(goal) = targets[k][i] else { continue };
            let mut step = goal - pts[k][i];
            for _ in 0..=RETRIES {
                let to = pts[k][i] + step;
                if ctx.move_is_safe(pts, k, i, to) {
                    pts[k][i] = to;
                    break;
                }
                step *= 0.5;
            }
        }
    }
}

/// What every move check of a pass shares.
struct Context<'a> {
    closed: &'a [bool],
    index: &'a BoxIndex,
    owner: &'a [(usize, usize)],
    clearance: f64,
}

impl Context<'_> {
    /// Whether moving vertex `i` of contour `k` to `to` sweeps over no other segment and keeps the
    /// clearance.
    fn move_is_safe(&self, pts: &[Vec<DVec2>], k: usize, i: usize, to: DVec2) -> bool {
        let p = &pts[k];
        let n = p.len();
        let from = p[i];
        if to == from {
            return true;
        }
        let prev = (self.closed[k] || i > 0).then(|| (i + n - 1) % n);
        let next = (self.closed[k] || i + 1 < n).then(|| (i + 1) % n);
        let ends: Vec<usize> = [prev, next].iter().flatten().copied().collect();
        let c2 = self.clearance * self.clearance;
        if ends.iter().any(|&j| p[j].distance_squared(to) < c2) {
            return false;
        }
        // The swept triangles, each with the neighbour vertex it shares with the rest of the contour.
        let tris: Vec<([DVec2; 3], usize)> = ends.iter().map(|&j| ([p[j], from, to], j)).collect();
        if tris.iter().any(|([a, b, c], _)| orient(*a, *b, *c) == 0.0) {
            // Moving straight along a segment: rare, and skipping it is always safe.
            return false;
        }
        let lo = tris.iter().flat_map(|(t, _)| t.iter()).fold(DVec2::INFINITY, |m, q| m.min(*q))
            - DVec2::splat(self.clearance);
        let hi = tris.iter().flat_map(|(t, _)| t.iter()).fold(DVec2::NEG_INFINITY, |m, q| m.max(*q))
            + DVec2::splat(self.clearance);
        // The two segments at vertex i are the ones being replaced.
        let own = |ko: usize, s: usize| ko == k && (s == i || Some(s) == prev);
        let is_vertex = |ko: usize, q: DVec2| ko == k && (q == from || ends.iter().any(|&j| p[j] == q));
        !self.index.any_near(lo, hi, |s| {
            let (ko, so) = self.owner[s as usize];
            if own(ko, so) {
                return false;
            }
            let q = &pts[ko];
            let (r, t) = (q[so], q[(so + 1) % q.len()]);
            // Most candidates share a grid cell with the move but are nowhere near it.
            if r.max(t).cmplt(lo).any() || r.min(t).cmpgt(hi).any() {
                return false;
            }
            // Clearance: the new vertex from this segment, this segment's free ends from the new segments.
            if segment_distance_sq(to, r, t) < c2 {
                return true;
            }
            let too_close = |v: DVec2| !is_vertex(ko, v) && ends.iter().any(|&j| segment_distance_sq(v, p[j], to) < c2);
            if too_close(r) || too_close(t) {
                return true;
            }
            tris.iter().any(|(tri, shared)| {
                let sv = p[*shared];
                let at_shared = ko == k && (r == sv || t == sv);
                if at_shared {
                    enters_at_vertex(tri, sv, if r == sv { t } else { r })
                } else {
                    meets_triangle(tri, r, t)
                }
            })
        })
    }
}

/// Whether segment `r–t` meets the closed triangle `tri` (exact predicates).
fn meets_triangle(tri: &[DVec2; 3], r: DVec2, t: DVec2) -> bool {
    let [a, b, c] = *tri;
    let inside = |q: DVec2| {
        let (o1, o2, o3) = (orient(a, b, q), orient(b, c, q), orient(c, a, q));
        (o1 >= 0.0 && o2 >= 0.0 && o3 >= 0.0) || (o1 <= 0.0 && o2 <= 0.0 && o3 <= 0.0)
    };
    inside(r) || inside(t) || segments_touch(a, b, r, t) || segments_touch(b, c, r, t) || segments_touch(c, a, r, t)
}

/// For a segment leaving triangle vertex `v` towards `w`: whether it enters the triangle (points
/// into the triangle's corner at `v`, or runs along one of its sides). A segment from a corner of
/// a convex triangle that does not enter it there cannot meet it anywhere else.
fn enters_at_vertex(tri: &[DVec2; 3], v: DVec2, w: DVec2) -> bool {
    let others: Vec<DVec2> = tri.iter().copied().filter(|&q| q != v).collect();
    let [b, c] = [others[0], others[1]];
    let (ob, oc) = (orient(v, b, w), orient(v, w, c));
    let turn = orient(v, b, c);
    let along = |e: DVec2| orient(v, e, w) == 0.0 && (e - v).dot(w - v) > 0.0;
    along(b) || along(c) || (ob != 0.0 && oc != 0.0 && ob.signum() == turn.signum() && oc.signum() == turn.signum())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smoothing_parameters_are_checked_and_located() {
        assert_eq!(Smoothing::default().validate(), Ok(()));
        assert_eq!(Smoothing { alpha: 1.0, k: 1, iterations: 0, ..Smoothing::default() }.validate(), Ok(()));
        for alpha in [0.0, -0.5, 1.5, f64::NAN] {
            let e = Smoothing { alpha, ..Smoothing::default() }.validate().unwrap_err();
            assert!(matches!(e, ContoursError::InvalidSmoothing { field: "alpha", .. }), "{e:?}");
            assert_eq!(e.location(), "alpha");
        }
        let e = Smoothing { k: 0, ..Smoothing::default() }.validate().unwrap_err();
        assert_eq!(e.location(), "k");
        assert_eq!(ContoursError::EmptyHistogram.location(), "");
        // In JSON every field is optional, with the defaults.
        let read: Smoothing = serde_json::from_str(r#"{ "k": 3 }"#).unwrap();
        assert_eq!(read, Smoothing { k: 3, ..Smoothing::default() });
        assert!(serde_json::from_str::<Smoothing>(r#"{ "beta": 3 }"#).is_err());
    }
}
