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
    /// A multigrid hierarchy breaks one of its invariants (found by
    /// [`crate::DiffusionProblem::check_invariants`]): a bug, never the user's input.
    #[error("multigrid level {level}{}: {reason}", sample.map_or_else(String::new, |(i, j)| format!(", sample ({i}, {j})")))]
    BrokenHierarchy {
        /// The level (0: the finest).
        level: usize,
        /// The sample `(i, j)` of that level, when the invariant is about one.
        sample: Option<(usize, usize)>,
        /// What is broken.
        reason: String,
    },
    /// The caller's progress callback stopped the generation or solve.
    #[error("cancelled")]
    Cancelled,
    /// The raster is too small to diffuse on.
    #[error("grid {nx} x {ny} is too small: diffusion needs at least 2 x 2 samples")]
    GridTooSmall {
        /// Samples along x.
        nx: usize,
        /// Samples along y.
        ny: usize,
    },
}

impl DiffusionError {
    /// Where the offending value is, as a JSON path relative to the inputs of [`crate::generate`]
    /// laid out as a scene's `diffusion` generator lays them out: `curves[2].points`,
    /// `curves[0].constraints[1].slope.theta`, `tolerance`…; empty when the error concerns the
    /// grid or the call as a whole. The `relief` facade prefixes it with the generator's path.
    pub fn location(&self) -> String {
        match self {
            Self::ControlPoints { curve, .. } => format!("curves[{curve}].points"),
            Self::NonFinitePoint { curve, index } => format!("curves[{curve}].points[{index}]"),
            Self::NoConstraints { curve } => format!("curves[{curve}].constraints"),
            Self::InvalidConstraint { curve, constraint, field, .. } => {
                let group = match *field {
                    "h" | "r" => "elevation.",
                    "a" | "b" | "theta" | "phi" => "slope.",
                    "amplitude" | "roughness" => "noise.",
                    _ => "",
                };
                format!("curves[{curve}].constraints[{constraint}].{group}{field}")
            }
            Self::CurveTooLong { curve, .. } => format!("curves[{curve}]"),
            Self::NoElevation => "curves".to_owned(),
            Self::InvalidOption { name, .. } => (*name).to_owned(),
            _ => String::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_error_is_located_as_a_diffusion_generator_lays_out_its_inputs() {
        let constraint =
            |field| DiffusionError::InvalidConstraint { curve: 3, constraint: 1, field, value: 0.0, reason: "" };
        let cases = [
            (DiffusionError::ControlPoints { curve: 2, count: 3 }, "curves[2].points"),
            (DiffusionError::NonFinitePoint { curve: 2, index: 4 }, "curves[2].points[4]"),
            (DiffusionError::NoConstraints { curve: 5 }, "curves[5].constraints"),
            (constraint("u"), "curves[3].constraints[1].u"),
            (constraint("h"), "curves[3].constraints[1].elevation.h"),
            (constraint("r"), "curves[3].constraints[1].elevation.r"),
            (constraint("a"), "curves[3].constraints[1].slope.a"),
            (constraint("b"), "curves[3].constraints[1].slope.b"),
            (constraint("theta"), "curves[3].constraints[1].slope.theta"),
            (constraint("phi"), "curves[3].constraints[1].slope.phi"),
            (constraint("amplitude"), "curves[3].constraints[1].noise.amplitude"),
            (constraint("roughness"), "curves[3].constraints[1].noise.roughness"),
            (DiffusionError::CurveTooLong { curve: 6, stations: 1e9, max: 1 }, "curves[6]"),
            (DiffusionError::NoElevation, "curves"),
            (DiffusionError::InvalidOption { name: "tolerance", value: 2.0, reason: "" }, "tolerance"),
            (DiffusionError::GridTooSmall { nx: 1, ny: 1 }, ""),
            (DiffusionError::Cancelled, ""),
        ];
        for (e, path) in cases {
            assert_eq!(e.location(), path, "{e:?}");
        }
    }
}
