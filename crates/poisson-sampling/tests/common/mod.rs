//! Test helpers shared by the poisson-sampling suites: random polygons and spatial checks.
#![allow(dead_code)]

use std::collections::HashMap;

use glam::DVec2;
use proptest::prelude::*;
use relief_poisson_sampling::{Domain, Polygon};

/// A star-shaped simple ring around `center`: vertices at sorted angles, radii in [0.5, 1]·`radius`.
pub(crate) fn star(center: DVec2, radius: f64, radii: &[f64]) -> Vec<DVec2> {
    relief_fixtures::star_ring(center, radius, 0.5, 0.5, radii)
}

/// Strategy: a star polygon of radius 50 at the origin, optionally with up to two holes that fit.
pub(crate) fn polygon_with_holes() -> impl Strategy<Value = Polygon> {
    (
        // At least 8 vertices: a chord of the star then stays at ≥ 25·cos(π/8) ≈ 23.1 from the centre.
        proptest::collection::vec(0.0f64..1.0, 8..40),
        proptest::collection::vec(proptest::collection::vec(0.0f64..1.0, 3..12), 0..3),
    )
        .prop_map(|(outer, holes)| {
            // The exterior's edges stay at least 23.1 from the centre (see above); holes of radius
            // ≤ 10 centred at x = ±12.5 reach 22.5, so they stay inside it and apart from each other.
            let exterior = star(DVec2::ZERO, 50.0, &outer);
            let holes = holes
                .iter()
                .enumerate()
                .map(|(k, h)| star(DVec2::new(if k == 0 { -12.5 } else { 12.5 }, 0.0), 10.0, h))
                .collect();
            Polygon::new(exterior, holes).expect("generated polygon is valid")
        })
}

/// A hash grid over sample points for nearest-distance queries.
pub(crate) struct PointIndex {
    cell: f64,
    cells: HashMap<(i64, i64), Vec<DVec2>>,
}

impl PointIndex {
    pub(crate) fn new(points: &[DVec2], cell: f64) -> Self {
        let mut cells: HashMap<(i64, i64), Vec<DVec2>> = HashMap::new();
        for &p in points {
            cells.entry(Self::key(p, cell)).or_default().push(p);
        }
        Self { cell, cells }
    }

    fn key(p: DVec2, cell: f64) -> (i64, i64) {
        ((p.x / cell).floor() as i64, (p.y / cell).floor() as i64)
    }

    /// Whether some point lies within `dist` of `q` (`dist` at most 2 cells).
    pub(crate) fn any_within(&self, q: DVec2, dist: f64) -> bool {
        let (cx, cy) = Self::key(q, self.cell);
        (-2..=2).any(|dy| {
            (-2..=2)
                .any(|dx| self.cells.get(&(cx + dx, cy + dy)).is_some_and(|v| v.iter().any(|p| p.distance(q) <= dist)))
        })
    }
}

/// The smallest distance between two points of the set (sweep over x), with the offending pair.
pub(crate) fn closest_pair(points: &[DVec2], stop_at: f64) -> Option<(f64, DVec2, DVec2)> {
    let mut sorted = points.to_vec();
    sorted.sort_by(|a, b| a.x.total_cmp(&b.x));
    let mut best: Option<(f64, DVec2, DVec2)> = None;
    for i in 0..sorted.len() {
        for j in i + 1..sorted.len() {
            if sorted[j].x - sorted[i].x >= stop_at {
                break;
            }
            let d = sorted[i].distance(sorted[j]);
            if best.is_none_or(|(b, _, _)| d < b) {
                best = Some((d, sorted[i], sorted[j]));
            }
        }
    }
    best
}

/// Grid points of `domain`'s bounds at spacing `step` for which `keep` holds.
pub(crate) fn probe_points(domain: &impl Domain, step: f64, keep: impl Fn(DVec2) -> bool) -> Vec<DVec2> {
    let b = domain.bounds();
    let (nx, ny) = ((b.size().x / step) as usize, (b.size().y / step) as usize);
    (0..=ny)
        .flat_map(|j| (0..=nx).map(move |i| b.min + DVec2::new(i as f64, j as f64) * step))
        .filter(|&p| keep(p))
        .collect()
}
