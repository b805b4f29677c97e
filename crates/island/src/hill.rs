//! Elliptic paraboloids (§3.3): the hills a user places and the small perturbations of the
//! filters (§3.4).

use glam::DVec2;
use serde::{Deserialize, Serialize};

use crate::IslandError;

/// An elliptic paraboloid `z = h·(1 − x²/a² − y²/b²)` inside its ellipse and 0 outside, in the
/// frame rotated by `rotation` about `center`. A negative height makes a valley, lake or crater.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct Hill {
    /// Centre `[x, y]` in world units.
    pub center: [f64; 2],
    /// Semi-axes `[a, b]`, `a ≥ b > 0` (the paper's convention; rotate by 90° for the other way).
    pub radii: [f64; 2],
    /// Rotation of the `a` axis from +x, degrees counter-clockwise (default 0).
    #[serde(default)]
    pub rotation: f64,
    /// Height at the centre, world units; negative for a hollow.
    pub height: f64,
}

impl Hill {
    /// A round hill.
    pub fn round(center: DVec2, radius: f64, height: f64) -> Self {
        Self { center: center.to_array(), radii: [radius, radius], rotation: 0.0, height }
    }

    /// Checks the parameters.
    ///
    /// # Errors
    /// [`IslandError::NotFinite`] or [`IslandError::InvalidHill`].
    pub fn validate(&self) -> Result<(), IslandError> {
        let values = [self.center[0], self.center[1], self.radii[0], self.radii[1], self.rotation, self.height];
        if values.iter().any(|v| !v.is_finite()) {
            return Err(IslandError::NotFinite { what: "a hill parameter" });
        }
        if self.height.abs() > crate::MAX_HEIGHT {
            return Err(IslandError::InvalidHill { reason: "a height beyond ±1e7 (MAX_HEIGHT)" });
        }
        if self.radii[0] <= 0.0 || self.radii[1] <= 0.0 {
            return Err(IslandError::InvalidHill { reason: "radii must be positive" });
        }
        if self.radii[0] < self.radii[1] {
            return Err(IslandError::InvalidHill { reason: "radii [a, b] need a ≥ b (rotate by 90° instead)" });
        }
        Ok(())
    }

    /// The paraboloid's height at `p` (0 outside its ellipse).
    pub fn at(&self, p: DVec2) -> f64 {
        Shape::new(self).at(p)
    }

    /// Axis-aligned bounds of the ellipse: `(min, max)`.
    pub fn bounds(&self) -> (DVec2, DVec2) {
        let (s, c) = self.rotation.to_radians().sin_cos();
        let [a, b] = self.radii;
        let half = DVec2::new((a * c).hypot(b * s), (a * s).hypot(b * c));
        let center = DVec2::from(self.center);
        (center - half, center + half)
    }
}

/// A hill prepared for evaluation at many points: rotation and radii folded into two axis
/// vectors, bounds computed once.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Shape {
    center: DVec2,
    /// Rotated unit axes divided by their radius: `x = d·u`, `y = d·v` in radius units.
    u: DVec2,
    v: DVec2,
    height: f64,
    pub(crate) lo: DVec2,
    pub(crate) hi: DVec2,
}

impl Shape {
    pub(crate) fn new(h: &Hill) -> Self {
        let (s, c) = h.rotation.to_radians().sin_cos();
        let (lo, hi) = h.bounds();
        Self {
            center: DVec2::from(h.center),
            u: DVec2::new(c, s) / h.radii[0],
            v: DVec2::new(-s, c) / h.radii[1],
            height: h.height,
            lo,
            hi,
        }
    }

    #[inline]
    pub(crate) fn at(&self, p: DVec2) -> f64 {
        let d = p - self.center;
        let (x, y) = (d.dot(self.u), d.dot(self.v));
        let q = x * x + y * y;
        if q < 1.0 { self.height * (1.0 - q) } else { 0.0 }
    }

    /// Adds the paraboloid's heights at the points `(x0 + (skip + k)·dx, y)` to `out[k]` (0
    /// beyond the ellipse). Linear along the row in the shape's frame, so each point costs a few
    /// multiply-adds and no branch. The walk always starts at `x0` (the span's first sample) and
    /// `skip` only says where `out` begins, so a window that clips the span gets the same bits as
    /// a whole row.
    #[inline]
    pub(crate) fn add_row(&self, x0: f64, dx: f64, y: f64, skip: usize, out: &mut [f64]) {
        let d = DVec2::new(x0, y) - self.center;
        let (x, y) = (d.dot(self.u), d.dot(self.v));
        let (sx, sy) = (dx * self.u.x, dx * self.v.x);
        for (k, o) in out.iter_mut().enumerate() {
            let t = (skip + k) as f64;
            let (a, b) = (x + t * sx, y + t * sy);
            let q = a * a + b * b;
            *o += if q < 1.0 { self.height * (1.0 - q) } else { 0.0 };
        }
    }

    /// Where the line at height `y` crosses the ellipse: the `x` range `(x0, x1)`, or `None` when
    /// it misses. Outside the range [`Self::at`] is 0 (up to rounding at the very rim, which is
    /// why callers widen it by a sample).
    #[inline]
    pub(crate) fn span(&self, y: f64) -> Option<(f64, f64)> {
        if y < self.lo.y || y > self.hi.y {
            return None;
        }
        // q(x) = (d·u)² + (d·v)² = A·x'² + 2B·x' + C with x' = x − centre.x; q < 1 between the roots.
        let dy = y - self.center.y;
        let a = self.u.x * self.u.x + self.v.x * self.v.x;
        let b = dy * (self.u.x * self.u.y + self.v.x * self.v.y);
        let c = dy * dy * (self.u.y * self.u.y + self.v.y * self.v.y) - 1.0;
        let disc = b * b - a * c;
        if disc < 0.0 {
            return None;
        }
        let r = disc.sqrt();
        Some((self.center.x + (-b - r) / a, self.center.x + (-b + r) / a))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The point at `(x, y)` in the hill's own frame (its `a` axis rotated by `rotation`).
    fn local(h: &Hill, x: f64, y: f64) -> DVec2 {
        let (s, c) = h.rotation.to_radians().sin_cos();
        DVec2::from(h.center) + DVec2::new(c * x - s * y, s * x + c * y)
    }

    #[test]
    fn a_hill_is_the_elliptic_paraboloid_in_its_rotated_frame() {
        let h = Hill { center: [300.0, -50.0], radii: [100.0, 50.0], rotation: 30.0, height: 40.0 };
        // z = h·(1 − x²/a² − y²/b²): 40·(1 − 0.36 − 0.16) = 19.2 at (60, 20).
        for (x, y, z) in
            [(0.0, 0.0, 40.0), (60.0, 20.0, 19.2), (-60.0, -20.0, 19.2), (0.0, 25.0, 30.0), (80.0, 0.0, 14.4)]
        {
            let got = h.at(local(&h, x, y));
            assert!((got - z).abs() < 1e-9, "({x}, {y}): {got}, want {z}");
        }
        // The rotation matters: the same offsets unrotated fall elsewhere on the surface.
        let unrotated = DVec2::from(h.center) + DVec2::new(60.0, 20.0);
        assert!((h.at(unrotated) - 19.2).abs() > 1.0);
        // Zero on and beyond the ellipse, along either axis.
        for (x, y) in [(100.0, 0.0), (0.0, 50.0), (0.0, 51.0), (101.0, 0.0), (75.0, 40.0)] {
            assert_eq!(h.at(local(&h, x, y)), 0.0, "({x}, {y})");
        }
        // A negative height is the same cup upside down (a lake, a crater).
        let hollow = Hill { height: -40.0, ..h };
        assert!((hollow.at(local(&h, 60.0, 20.0)) + 19.2).abs() < 1e-9);
    }

    #[test]
    fn rows_and_bounds_agree_with_single_points() {
        let h = Hill { center: [10.0, 20.0], radii: [80.0, 30.0], rotation: 65.0, height: 12.0 };
        let shape = Shape::new(&h);
        let (lo, hi) = h.bounds();
        // The bounds touch the ellipse: its extreme points along x and y.
        let extreme = (0..3600)
            .map(|k| {
                local(
                    &h,
                    80.0 * (f64::from(k) * 0.1f64).to_radians().cos(),
                    30.0 * (f64::from(k) * 0.1f64).to_radians().sin(),
                )
            })
            .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(a, b), p| (a.min(p), b.max(p)));
        assert!((extreme.0 - lo).abs().max_element() < 1e-3 && (extreme.1 - hi).abs().max_element() < 1e-3);
        let mut row = vec![0.0; 40];
        shape.add_row(-60.0, 3.0, 25.0, 0, &mut row);
        for (k, v) in row.iter().enumerate() {
            let p = DVec2::new(-60.0 + 3.0 * k as f64, 25.0);
            assert!((v - h.at(p)).abs() < 1e-9, "sample {k}");
        }
    }
}
