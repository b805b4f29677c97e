use glam::DVec2;
use rayon::prelude::*;

use crate::{Warp, WarpError};

/// Deepest subdivision of one segment (2¹⁶ pieces): a bound, not a target.
const MAX_DEPTH: u32 = 16;

/// Most points one warped polyline may have (2^24): a tolerance far below what the warp's bends
/// need would otherwise split every segment 2¹⁶ ways.
pub const MAX_POLYLINE_POINTS: usize = 1 << 24;

/// Warps points in place (in parallel).
pub fn warp_points(warp: &(impl Warp + ?Sized), points: &mut [DVec2]) {
    points.par_iter_mut().for_each(|p| *p = warp.forward(*p));
}

/// Warps a polyline with adaptive subdivision: a segment is split at its midpoint while the warped
/// midpoint lies farther than `tolerance` from the midpoint of its warped ends, so the output
/// follows the warped curve to within about `tolerance` however the warp bends it. (Appendix C of
/// the contours paper shows no fixed sampling step can prevent crossings; a tolerance below the
/// warped spacing of neighbouring contours does.)
///
/// # Errors
/// [`WarpError::InvalidTolerance`] unless `tolerance` is finite and positive;
/// [`WarpError::TooManyPoints`] when the output would exceed [`MAX_POLYLINE_POINTS`].
pub fn warp_polyline(
    warp: &(impl Warp + ?Sized),
    points: &[DVec2],
    closed: bool,
    tolerance: f64,
) -> Result<Vec<DVec2>, WarpError> {
    capped_polyline(warp, points, closed, tolerance, MAX_POLYLINE_POINTS)
}

/// [`warp_polyline`] with the point cap `max` (a parameter so tests can reach it cheaply).
fn capped_polyline(
    warp: &(impl Warp + ?Sized),
    points: &[DVec2],
    closed: bool,
    tolerance: f64,
    max: usize,
) -> Result<Vec<DVec2>, WarpError> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(WarpError::InvalidTolerance { tolerance });
    }
    let n = points.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let warped: Vec<DVec2> = points.iter().map(|&p| warp.forward(p)).collect();
    let mut out = Vec::with_capacity(n);
    let segments = if closed { n } else { n - 1 };
    for i in 0..segments {
        let j = (i + 1) % n;
        out.push(warped[i]);
        subdivide(warp, points[i], points[j], warped[i], warped[j], tolerance, (0, max), &mut out);
        if out.len() > max {
            return Err(WarpError::TooManyPoints { tolerance, max });
        }
    }
    if !closed {
        out.push(warped[n - 1]);
    }
    Ok(out)
}

/// Pushes the interior points of segment `a–b` (warped `wa–wb`), in order.
#[allow(clippy::too_many_arguments, reason = "recursion state: the segment, its image, and the bound")]
fn subdivide(
    warp: &(impl Warp + ?Sized),
    a: DVec2,
    b: DVec2,
    wa: DVec2,
    wb: DVec2,
    tol: f64,
    (depth, max): (u32, usize),
    out: &mut Vec<DVec2>,
) {
    if depth >= MAX_DEPTH || out.len() > max {
        return;
    }
    let m = 0.5 * (a + b);
    let wm = warp.forward(m);
    if wm.distance(0.5 * (wa + wb)) <= tol {
        return;
    }
    subdivide(warp, a, m, wa, wm, tol, (depth + 1, max), out);
    out.push(wm);
    subdivide(warp, m, b, wm, wb, tol, (depth + 1, max), out);
}

/// Warps many polylines `(points, closed)` in parallel with [`warp_polyline`].
///
/// # Errors
/// As [`warp_polyline`].
pub fn warp_polylines(
    warp: &(impl Warp + ?Sized),
    polylines: &[(Vec<DVec2>, bool)],
    tolerance: f64,
) -> Result<Vec<Vec<DVec2>>, WarpError> {
    polylines.par_iter().map(|(p, closed)| warp_polyline(warp, p, *closed, tolerance)).collect()
}

/// Warps a raster by backward mapping (beyond the paper: a DEM warped directly): sample `(i, j)`
/// of the output, at world position `position(i, j)`, takes `sample(warp.inverse(position))` —
/// e.g. the source's bilinear interpolation there. Parallel over rows; row-major output.
pub fn warp_raster(
    warp: &(impl Warp + ?Sized),
    nx: usize,
    ny: usize,
    position: impl Fn(usize, usize) -> DVec2 + Sync,
    sample: impl Fn(DVec2) -> f32 + Sync,
) -> Vec<f32> {
    let support = warp.support();
    let mut out = vec![0.0f32; nx * ny];
    out.par_chunks_mut(nx.max(1)).enumerate().for_each(|(j, row)| {
        for (i, v) in row.iter_mut().enumerate() {
            let p = position(i, j);
            let inside = support.is_none_or(|[lo, hi]| p.cmpge(lo).all() && p.cmple(hi).all());
            *v = sample(if inside { warp.inverse(p) } else { p });
        }
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{PathOptions, PathWarp};

    #[test]
    fn a_tolerance_too_fine_for_the_cap_is_an_error_not_an_allocation() {
        let warp = PathWarp::new(&[DVec2::ZERO, DVec2::new(100.0, 0.0)], &PathOptions::new(40.0, 1.0)).unwrap();
        let line: Vec<DVec2> = (0..=10).map(|i| DVec2::new(10.0 * f64::from(i), 5.0)).collect();
        let fine = capped_polyline(&warp, &line, false, 1e-6, usize::MAX).unwrap();
        assert!(fine.len() > 100, "{}", fine.len());
        match capped_polyline(&warp, &line, false, 1e-6, fine.len() / 2) {
            Err(WarpError::TooManyPoints { max, .. }) => assert_eq!(max, fine.len() / 2),
            other => panic!("{other:?}"),
        }
        // The public function's cap is far above what ordinary tolerances need.
        assert_eq!(warp_polyline(&warp, &line, false, 1e-6).unwrap(), fine);
    }
}
