use glam::DVec2;

use crate::predicates::orient;
use crate::{NO_TRIANGLE, Tin, TinError};

/// Where a query point falls.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Location {
    /// In (or on the border of) `triangle`, with barycentric `weights` for its three corners
    /// (summing to 1; all ≥ 0 up to rounding).
    Inside {
        /// The containing triangle.
        triangle: u32,
        /// Barycentric coordinates of the point with respect to the triangle's corners.
        weights: [f64; 3],
    },
    /// Outside every triangle.
    Outside,
}

impl Tin {
    /// Locates `p` by a visibility walk from triangle 0. O(√N) on average; use a
    /// [`PointLocator`] for many queries.
    pub fn locate(&self, p: DVec2) -> Location {
        self.locate_from(p, 0)
    }

    /// Locates `p` by a visibility walk starting at triangle `hint` (clamped to a valid triangle):
    /// cheap when consecutive queries are close, such as along a scanline.
    pub fn locate_from(&self, p: DVec2, hint: u32) -> Location {
        if !p.is_finite() {
            return Location::Outside;
        }
        let tris = self.triangles();
        let nbrs = self.triangle_neighbors();
        let mut t = hint.min(tris.len() as u32 - 1);
        let mut came_from = NO_TRIANGLE;
        // A Delaunay walk always terminates; the cap (and rotating the first edge tested) guards
        // arbitrary triangulations from `from_parts`, which then fall back to a scan.
        for step in 0..tris.len() + 3 {
            let pts = self.triangle_points(t);
            let mut next = None;
            for j in 0..3 {
                let k = (j + step) % 3;
                let u = nbrs[t as usize][k];
                if u != NO_TRIANGLE && u == came_from {
                    continue;
                }
                if orient(pts[(k + 1) % 3], pts[(k + 2) % 3], p) < 0.0 {
                    next = Some(u);
                    break;
                }
            }
            match next {
                None => return Location::Inside { triangle: t, weights: barycentric(pts, p) },
                Some(NO_TRIANGLE) if self.is_convex() => return Location::Outside,
                Some(NO_TRIANGLE) => return self.locate_scan(p),
                Some(u) => {
                    came_from = t;
                    t = u;
                }
            }
        }
        self.locate_scan(p)
    }

    /// Tests every triangle: the fallback for non-convex meshes.
    fn locate_scan(&self, p: DVec2) -> Location {
        (0..self.num_triangles() as u32)
            .find_map(|t| {
                let pts = self.triangle_points(t);
                (0..3)
                    .all(|k| orient(pts[(k + 1) % 3], pts[(k + 2) % 3], p) >= 0.0)
                    .then(|| Location::Inside { triangle: t, weights: barycentric(pts, p) })
            })
            .unwrap_or(Location::Outside)
    }

    /// Piecewise-linear interpolation of per-node `values` at `p`; `None` outside the mesh.
    ///
    /// # Errors
    /// [`TinError::ValueCountMismatch`] if `values` does not have one entry per node.
    pub fn interpolate(&self, p: DVec2, values: &[f64]) -> Result<Option<f64>, TinError> {
        self.check_values(values)?;
        Ok(interpolate_at(self, self.locate(p), values))
    }

    pub(crate) fn check_values(&self, values: &[f64]) -> Result<(), TinError> {
        if values.len() == self.num_points() {
            Ok(())
        } else {
            Err(TinError::ValueCountMismatch { expected: self.num_points(), found: values.len() })
        }
    }
}

fn interpolate_at(tin: &Tin, loc: Location, values: &[f64]) -> Option<f64> {
    match loc {
        Location::Inside { triangle, weights } => {
            let tri = tin.triangles()[triangle as usize];
            Some((0..3).map(|k| weights[k] * values[tri[k] as usize]).sum())
        }
        Location::Outside => None,
    }
}

/// Barycentric coordinates of `p` in triangle `pts` (counter-clockwise, non-degenerate).
#[inline]
pub(crate) fn barycentric(pts: [DVec2; 3], p: DVec2) -> [f64; 3] {
    let [a, b, c] = pts;
    let area = (b - a).perp_dot(c - a);
    let wa = (c - b).perp_dot(p - b) / area;
    let wb = (a - c).perp_dot(p - c) / area;
    [wa, wb, 1.0 - wa - wb]
}

/// Fast repeated point location: a uniform grid over the mesh stores, per cell, a triangle near
/// the cell, and each query walks from there — O(1) expected per query on well-shaped meshes.
#[derive(Debug, Clone)]
pub struct PointLocator<'a> {
    tin: &'a Tin,
    origin: DVec2,
    inv_cell: DVec2,
    w: usize,
    h: usize,
    hints: Vec<u32>,
}

impl<'a> PointLocator<'a> {
    /// Builds the hint grid (about two triangles per cell).
    pub fn new(tin: &'a Tin) -> Self {
        let (lo, hi) =
            tin.points().iter().fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let size = (hi - lo).max(DVec2::splat(f64::MIN_POSITIVE));
        let cells = (tin.num_triangles() / 2).max(1) as f64;
        let side = (size.x * size.y / cells).sqrt().max(f64::MIN_POSITIVE);
        let w = ((size.x / side).ceil() as usize).clamp(1, 1 << 12);
        let h = ((size.y / side).ceil() as usize).clamp(1, 1 << 12);
        let inv_cell = DVec2::new(w as f64, h as f64) / size;
        let mut hints = vec![NO_TRIANGLE; w * h];
        let cell_of = |p: DVec2| {
            let g = ((p - lo) * inv_cell).floor();
            (g.y.clamp(0.0, (h - 1) as f64) as usize) * w + g.x.clamp(0.0, (w - 1) as f64) as usize
        };
        for t in 0..tin.num_triangles() as u32 {
            let [a, b, c] = tin.triangle_points(t);
            hints[cell_of((a + b + c) / 3.0)] = t;
        }
        // Cells no centroid fell in borrow the nearest earlier hint in scan order (or the first).
        let mut last = hints.iter().copied().find(|&t| t != NO_TRIANGLE).unwrap_or(0);
        for hint in &mut hints {
            if *hint == NO_TRIANGLE {
                *hint = last;
            } else {
                last = *hint;
            }
        }
        Self { tin, origin: lo, inv_cell, w, h, hints }
    }

    /// Locates `p`.
    pub fn locate(&self, p: DVec2) -> Location {
        if !p.is_finite() {
            return Location::Outside;
        }
        let g = ((p - self.origin) * self.inv_cell).floor();
        let k = (g.y.clamp(0.0, (self.h - 1) as f64) as usize) * self.w + g.x.clamp(0.0, (self.w - 1) as f64) as usize;
        self.tin.locate_from(p, self.hints[k])
    }

    /// Piecewise-linear interpolation of per-node `values` at `p`; `None` outside the mesh.
    ///
    /// # Errors
    /// [`TinError::ValueCountMismatch`] if `values` does not have one entry per node.
    pub fn interpolate(&self, p: DVec2, values: &[f64]) -> Result<Option<f64>, TinError> {
        self.tin.check_values(values)?;
        Ok(interpolate_at(self.tin, self.locate(p), values))
    }
}
