//! Exact geometric predicates (Shewchuk's adaptive arithmetic via the `robust` crate).

use glam::DVec2;

#[inline]
fn coord(p: DVec2) -> robust::Coord<f64> {
    robust::Coord { x: p.x, y: p.y }
}

/// > 0 when `a → b → c` turns counter-clockwise, < 0 clockwise, exactly 0 when collinear.
#[inline]
pub(crate) fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    robust::orient2d(coord(a), coord(b), coord(c))
}

/// > 0 when `d` lies strictly inside the circumcircle of counter-clockwise `a, b, c`.
#[inline]
pub(crate) fn incircle(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> f64 {
    robust::incircle(coord(a), coord(b), coord(c), coord(d))
}
