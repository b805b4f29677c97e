use glam::DVec2;

use crate::curve::SmoothCurve;
use crate::error::{check_radius, finite};
use crate::path::clean_stroke;
use crate::warp::solve_monotone;
use crate::{Warp, WarpError};

/// Slope modulation (§5.3): around a point or a curve Γ, `ω(p) = p − μ·δ(u)·(p − a)` with `a` the
/// point of Γ nearest to `p`, `u = |p − a| / r` and `δ(x) = x(1 − x)`, inside distance r of Γ.
/// Radially `ρ ↦ ρ(1 − μ(ρ/r)(1 − ρ/r))`, strictly increasing iff −1 < μ < 3: positive μ pulls the
/// contours near Γ together (steeper there, gentler farther out), negative μ spreads them.
///
/// A curve Γ is the C¹ centripetal Catmull–Rom curve through the given points, so the nearest-point
/// map is continuous; its reach is checked against r (curvature radius and clearance between
/// distant parts), and a curve that would fold the plane is rejected rather than warped.
///
/// In JSON (serde): `{ "point": [x, y], "radius": r, "strength": μ }` or `{ "curve": [[x, y], …],
/// "radius": r, "strength": μ }`; deserializing builds and so checks it, naming the offending
/// field. Two modulations are equal when they were built from equal parameters.
#[derive(Debug, Clone)]
pub struct SlopeModulation {
    pub(crate) center: Center,
    pub(crate) radius: f64,
    pub(crate) mu: f64,
}

#[derive(Debug, Clone)]
pub(crate) enum Center {
    Point(DVec2),
    /// The points as given, and the smooth curve through them.
    Curve(Vec<DVec2>, SmoothCurve),
}

fn check(radius: f64, mu: f64) -> Result<(f64, f64), WarpError> {
    Ok((check_radius(radius)?, check_strength(mu)?))
}

/// A modulation strength: finite, in (−1, 3).
pub(crate) fn check_strength(mu: f64) -> Result<f64, WarpError> {
    let mu = finite("strength", mu)?;
    if !(mu > -1.0 && mu < 3.0) {
        return Err(WarpError::InvalidStrength { mu, range: "(-1, 3)" });
    }
    Ok(mu)
}

impl SlopeModulation {
    /// Modulation around a point.
    ///
    /// # Errors
    /// [`WarpError::NonFinite`], [`WarpError::InvalidRadius`], [`WarpError::InvalidStrength`].
    pub fn point(center: DVec2, radius: f64, mu: f64) -> Result<Self, WarpError> {
        finite("centre x", center.x)?;
        finite("centre y", center.y)?;
        let (radius, mu) = check(radius, mu)?;
        Ok(Self { center: Center::Point(center), radius, mu })
    }

    /// Modulation around the smooth curve through `points` (≥ 2 distinct).
    ///
    /// # Errors
    /// As [`SlopeModulation::point`], plus [`WarpError::DegenerateStroke`],
    /// [`WarpError::CurvatureTooHigh`] and [`WarpError::CurveTooClose`] when the curve's reach is
    /// below the radius.
    pub fn curve(points: &[DVec2], radius: f64, mu: f64) -> Result<Self, WarpError> {
        let (pts, _) = clean_stroke(points)?;
        let (radius, mu) = check(radius, mu)?;
        let curve = SmoothCurve::new(&pts);
        curve.check_reach(radius)?;
        Ok(Self { center: Center::Curve(points.to_vec(), curve), radius, mu })
    }

    /// The point of Γ nearest to `p`, if within the radius.
    fn anchor(&self, p: DVec2) -> Option<DVec2> {
        match &self.center {
            Center::Point(c) => (c.distance_squared(p) < self.radius * self.radius).then_some(*c),
            Center::Curve(_, curve) => curve.closest_within(p, self.radius),
        }
    }
}

impl Warp for SlopeModulation {
    fn forward(&self, p: DVec2) -> DVec2 {
        let Some(a) = self.anchor(p) else { return p };
        let w = p - a;
        let u = w.length() / self.radius;
        if u <= 0.0 || u >= 1.0 {
            return p;
        }
        a + w * (1.0 - self.mu * u * (1.0 - u))
    }

    fn inverse(&self, q: DVec2) -> DVec2 {
        // The warp moves points along their own normal line, so q has the same anchor as its
        // preimage; only the radial profile needs inverting.
        let Some(a) = self.anchor(q) else { return q };
        let w = q - a;
        let t = w.length() / self.radius;
        if t <= 0.0 || t >= 1.0 {
            return q;
        }
        // g(u) = u(1 − μu(1 − u)) = u + μ·(−u²(1 − u)).
        let u = solve_monotone(t, self.mu, |x| -x * x * (1.0 - x), |x| -2.0 * x + 3.0 * x * x);
        a + w * (u / t)
    }

    fn support(&self) -> Option<[DVec2; 2]> {
        let [lo, hi] = match &self.center {
            Center::Point(c) => [*c, *c],
            Center::Curve(_, curve) => curve.bounds(),
        };
        Some([lo - DVec2::splat(self.radius), hi + DVec2::splat(self.radius)])
    }
}
