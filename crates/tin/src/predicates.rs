//! Exact geometric predicates (Shewchuk's adaptive arithmetic via the `robust` crate).

use glam::DVec2;
pub(crate) use relief_poisson_sampling::orient;

/// > 0 when `d` lies strictly inside the circumcircle of counter-clockwise `a, b, c`.
#[inline]
pub(crate) fn incircle(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> f64 {
    let k = |p: DVec2| robust::Coord { x: p.x, y: p.y };
    robust::incircle(k(a), k(b), k(c), k(d))
}
