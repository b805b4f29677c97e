use thiserror::Error;

/// Why feature curves could not be turned into a terrain.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum DiffusionError {
    /// A curve's control polygon is not 2 points (a segment) or 3k + 1 points (k cubic pieces).
    #[error("curve {curve}: {count} control points; give 2 (a straight segment) or 3k + 1 (k cubic Bézier pieces)")]
    ControlPoints {
        /// Index of the curve.
        curve: usize,
        /// Points given.
        count: usize,
    },
    /// A curve has no constraint point at all.
    #[error("curve {curve} has no constraint point")]
    NoConstraints {
        /// Index of the curve.
        curve: usize,
    },
    /// A value is out of range (names the curve, the constraint and the field).
    #[error("curve {curve}, constraint {constraint}: {field} = {value} {reason}")]
    InvalidConstraint {
        /// Index of the curve.
        curve: usize,
        /// Index of the constraint within the curve.
        constraint: usize,
        /// Field name (`u`, `h`, `r`, `a`, `b`, `theta`, `phi`, `amplitude`, `roughness`).
        field: &'static str,
        /// The value.
        value: f64,
        /// What it must be.
        reason: &'static str,
    },
    /// A control point is not finite.
    #[error("curve {curve}: control point {index} is not finite")]
    NonFinitePoint {
        /// Index of the curve.
        curve: usize,
        /// Index of the point.
        index: usize,
    },
    /// No curve carries an elevation constraint, so the elevation is only known up to a constant.
    #[error("no curve carries an elevation constraint: give at least one (h, r) so the elevation is anchored")]
    NoElevation,
    /// A solver option is out of range.
    #[error("invalid {name} = {value}: {reason}")]
    InvalidOption {
        /// The option.
        name: &'static str,
        /// The value.
        value: f64,
        /// What it must be.
        reason: &'static str,
    },
    /// A curve so long for the grid's cell size that sampling it every half cell would take more
    /// than [`crate::MAX_STATIONS`] stations (a curve far outside the grid, or a typo in its units).
    #[error(
        "curve {curve} needs about {stations:.0} samples at half a cell apart, more than {max}: is it in the grid's units?"
    )]
    CurveTooLong {
        /// Index of the curve.
        curve: usize,
        /// Samples its control polygon would take.
        stations: f64,
        /// The cap.
        max: usize,
    },
    /// The raster is too small to diffuse on.
    #[error("grid {nx} x {ny} is too small: diffusion needs at least 2 x 2 samples")]
    GridTooSmall {
        /// Samples along x.
        nx: usize,
        /// Samples along y.
        ny: usize,
    },
}
