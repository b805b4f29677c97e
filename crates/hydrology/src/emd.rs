//! The earth mover's distance between two distributions on a line, the one implementation both
//! histogram distances in the workspace share: [`CountHistogram::wasserstein`] here, and
//! `relief_orometry::FractionHistogram::emd` (Argudo et al. 2019, §4.2), which is this integral
//! over bin indices instead of values, normalized by the bin count, and for circular histograms
//! taken after subtracting the median of the difference (Rabin et al. 2008's circular EMD).
//!
//! In one dimension the earth mover's (1-Wasserstein) distance is `∫|F₁(x) − F₂(x)| dx` over the
//! two cumulative distribution functions. For histograms both CDFs are known exactly between a
//! few breakpoints (the bin edges of either), so the integral is a sum over the intervals between
//! consecutive breakpoints of a closed form that depends on how the CDFs run in between
//! ([`CdfShape`]). The caller supplies the difference `D = F₁ − F₂` at the breakpoints, computed
//! as suits its histograms, so each caller keeps its exact rounding.
//!
//! [`CountHistogram::wasserstein`]: crate::CountHistogram::wasserstein

/// How the two CDFs, and so their difference `D`, run between consecutive breakpoints.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CdfShape {
    /// Linearly: the CDF of a histogram whose samples spread evenly within each bin. `D` is
    /// linear on each interval, so `|D|` integrates to a trapezoid, or to two triangles where
    /// `D` changes sign inside the interval.
    Linear,
    /// As steps: the CDF of point masses at the breakpoints (a histogram whose mass sits at each
    /// bin's lower edge). `D` keeps its value at an interval's left breakpoint up to the next, so
    /// `|D|` integrates to a rectangle; the value given at the last breakpoint is not used.
    Step,
}

/// The earth mover's distance `∫|D(x)| dx` over `[x₀, xₙ]`, with `D = F₁ − F₂` the difference of
/// two CDFs given as `(xᵢ, D(xᵢ))` at increasing breakpoints and running between them as `shape`
/// says. The interval terms are summed in order, from left to right. Fewer than two breakpoints
/// span nothing: the distance is zero.
///
/// ```
/// use relief_hydrology::{CdfShape, earth_movers_distance};
///
/// // All mass at 0 against all at 1: F₁ − F₂ is 1 on [0, 1) and 0 from 1 on.
/// let d = [(0.0, 1.0), (1.0, 0.0)];
/// assert_eq!(earth_movers_distance(d, CdfShape::Step), 1.0);
/// // The same mass spread evenly over [0, 1] and [1, 2]: the CDFs differ linearly.
/// let d = [(0.0, 0.0), (1.0, 1.0), (2.0, 0.0)];
/// assert_eq!(earth_movers_distance(d, CdfShape::Linear), 1.0);
/// ```
pub fn earth_movers_distance(cdf_difference: impl IntoIterator<Item = (f64, f64)>, shape: CdfShape) -> f64 {
    let mut left: Option<(f64, f64)> = None;
    cdf_difference.into_iter().filter_map(|right| left.replace(right).map(|left| interval(left, right, shape))).sum()
}

/// `∫|D|` over one interval between breakpoints `(x₀, a)` and `(x₁, b)`.
fn interval((x0, a): (f64, f64), (x1, b): (f64, f64), shape: CdfShape) -> f64 {
    let dx = x1 - x0;
    match shape {
        CdfShape::Step => a.abs() * dx,
        // With a sign change at the root t = a / (a − b) of the interval, the two triangles have
        // areas ½·a²/|a − b|·dx and ½·b²/|a − b|·dx.
        CdfShape::Linear if a * b >= 0.0 => 0.5 * (a.abs() + b.abs()) * dx,
        CdfShape::Linear => 0.5 * (a * a + b * b) / (a - b).abs() * dx,
    }
}
