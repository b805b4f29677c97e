use glam::DVec2;
use thiserror::Error;

/// Why a warp could not be built or applied.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum WarpError {
    /// A stroke or curve has fewer than two distinct points (or zero length).
    #[error("stroke has {distinct} distinct point(s) and length {length}: a stroke needs two distinct points")]
    DegenerateStroke {
        /// Distinct points found.
        distinct: usize,
        /// Total length.
        length: f64,
    },
    /// A coordinate or parameter is NaN or infinite.
    #[error("{what} is not finite ({value})")]
    NonFinite {
        /// What the value is.
        what: &'static str,
        /// The value.
        value: f64,
    },
    /// The radius is not positive.
    #[error("radius {radius} must be > 0")]
    InvalidRadius {
        /// The radius given.
        radius: f64,
    },
    /// The strength is outside its valid range.
    #[error("strength μ = {mu} is outside {range}")]
    InvalidStrength {
        /// The strength given.
        mu: f64,
        /// The valid range, as text.
        range: &'static str,
    },
    /// A forced segment length exceeds the bijectivity bound (Appendix B).
    #[error("segment length ε = {epsilon} exceeds the bijectivity limit {limit} for radius {radius} and strength {mu}")]
    SegmentTooLong {
        /// The forced segment length.
        epsilon: f64,
        /// The largest valid one.
        limit: f64,
        /// The radius.
        radius: f64,
        /// The strength.
        mu: f64,
    },
    /// A displacement profile does not satisfy Appendix A's conditions.
    #[error("invalid displacement profile: {reason}")]
    InvalidProfile {
        /// What is wrong.
        reason: String,
    },
    /// A slope-modulation curve bends more sharply than its radius allows.
    #[error("curve bends with radius {curvature_radius} near ({}, {}), below the modulation radius {radius}: the warp would fold", at.x, at.y)]
    CurvatureTooHigh {
        /// Where.
        at: DVec2,
        /// The curve's radius of curvature there.
        curvature_radius: f64,
        /// The modulation radius.
        radius: f64,
    },
    /// Two distant parts of a slope-modulation curve come within twice the radius of each other.
    #[error("curve parts near ({}, {}) and ({}, {}) are {distance} apart, closer than twice the radius {radius}: the warp would fold", a.x, a.y, b.x, b.y)]
    CurveTooClose {
        /// A point on one part.
        a: DVec2,
        /// A point on the other.
        b: DVec2,
        /// Their distance.
        distance: f64,
        /// The modulation radius.
        radius: f64,
    },
    /// A stroke so long for its radius that it would need more discs than [`crate::MAX_DISCS`].
    #[error(
        "a stroke of length {length} at radius {radius} needs {discs:.0} discs, more than {max}: use a larger radius or a shorter stroke"
    )]
    TooManyDiscs {
        /// The stroke's length.
        length: f64,
        /// The disc radius.
        radius: f64,
        /// Discs it would need.
        discs: f64,
        /// The cap.
        max: usize,
    },
    /// Warping a polyline to within the tolerance would take more than
    /// [`crate::MAX_POLYLINE_POINTS`] points.
    #[error("warping a polyline to within {tolerance} would take more than {max} points: use a larger tolerance")]
    TooManyPoints {
        /// The tolerance asked for.
        tolerance: f64,
        /// The cap.
        max: usize,
    },
    /// A slope modulation was given both a centre point and a curve, or neither.
    #[error("give `point` or `curve` (exactly one)")]
    AmbiguousCentre,
    /// A subdivision tolerance is not finite and positive.
    #[error("tolerance {tolerance} must be finite and > 0")]
    InvalidTolerance {
        /// The tolerance given.
        tolerance: f64,
    },
}

pub(crate) fn finite(what: &'static str, value: f64) -> Result<f64, WarpError> {
    if value.is_finite() { Ok(value) } else { Err(WarpError::NonFinite { what, value }) }
}

pub(crate) fn finite_points(what: &'static str, points: &[DVec2]) -> Result<(), WarpError> {
    match points.iter().find(|p| !p.is_finite()) {
        Some(p) => Err(WarpError::NonFinite { what, value: if p.x.is_finite() { p.y } else { p.x } }),
        None => Ok(()),
    }
}

/// A disc or modulation radius: finite, above 0.
pub(crate) fn check_radius(radius: f64) -> Result<f64, WarpError> {
    let radius = finite("radius", radius)?;
    if radius <= 0.0 {
        return Err(WarpError::InvalidRadius { radius });
    }
    Ok(radius)
}

/// A path-warp strength: finite, in [0, 1].
pub(crate) fn check_path_strength(mu: f64) -> Result<f64, WarpError> {
    let mu = finite("strength", mu)?;
    if !(0.0..=1.0).contains(&mu) {
        return Err(WarpError::InvalidStrength { mu, range: "[0, 1]" });
    }
    Ok(mu)
}

impl WarpError {
    /// Where the offending value is, as a JSON path relative to the warp's JSON form (`radius`,
    /// `strength`, `stroke`, `exponent`, `segment`); empty when the error concerns the warp as a
    /// whole or a polyline it was applied to. The `relief` facade prefixes it with the warp's own
    /// path in the scene.
    pub fn location(&self) -> String {
        let field = match self {
            Self::InvalidRadius { .. } | Self::CurvatureTooHigh { .. } | Self::CurveTooClose { .. } => "radius",
            Self::InvalidStrength { .. } => "strength",
            Self::DegenerateStroke { .. } | Self::TooManyDiscs { .. } => "stroke",
            Self::InvalidProfile { .. } => "exponent",
            Self::SegmentTooLong { .. } => "segment",
            Self::NonFinite { what, .. } => match *what {
                "radius" | "strength" => what,
                "segment length" => "segment",
                _ => "",
            },
            _ => "",
        };
        field.to_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_error_is_located_at_the_field_of_the_warp_it_is_about() {
        let cases = [
            (WarpError::InvalidRadius { radius: -1.0 }, "radius"),
            (WarpError::CurvatureTooHigh { at: DVec2::ZERO, curvature_radius: 1.0, radius: 2.0 }, "radius"),
            (WarpError::CurveTooClose { a: DVec2::ZERO, b: DVec2::ONE, distance: 1.0, radius: 2.0 }, "radius"),
            (WarpError::InvalidStrength { mu: 4.0, range: "[0, 1]" }, "strength"),
            (WarpError::DegenerateStroke { distinct: 1, length: 0.0 }, "stroke"),
            (WarpError::TooManyDiscs { length: 1e9, radius: 1.0, discs: 1e9, max: 1 }, "stroke"),
            (WarpError::InvalidProfile { reason: String::new() }, "exponent"),
            (WarpError::SegmentTooLong { epsilon: 5.0, limit: 1.0, radius: 1.0, mu: 1.0 }, "segment"),
            (WarpError::NonFinite { what: "radius", value: f64::NAN }, "radius"),
            (WarpError::NonFinite { what: "strength", value: f64::NAN }, "strength"),
            (WarpError::NonFinite { what: "segment length", value: f64::NAN }, "segment"),
            (WarpError::NonFinite { what: "stroke point", value: f64::NAN }, ""),
            (WarpError::AmbiguousCentre, ""),
            (WarpError::TooManyPoints { tolerance: 1.0, max: 1 }, ""),
        ];
        for (e, path) in cases {
            assert_eq!(e.location(), path, "{e:?}");
        }
    }

    #[test]
    fn non_finite_points_are_named() {
        assert_eq!(finite_points("stroke point", &[DVec2::ZERO, DVec2::ONE]), Ok(()));
        let e = finite_points("stroke point", &[DVec2::ZERO, DVec2::new(1.0, f64::NAN)]).unwrap_err();
        assert!(matches!(e, WarpError::NonFinite { what: "stroke point", value } if value.is_nan()), "{e:?}");
        let e = finite_points("curve point", &[DVec2::new(f64::INFINITY, 2.0)]).unwrap_err();
        assert_eq!(e, WarpError::NonFinite { what: "curve point", value: f64::INFINITY });
        let stroke = [DVec2::ZERO, DVec2::new(f64::NAN, 0.0), DVec2::ONE];
        assert!(matches!(
            crate::PathWarp::new(&stroke, &crate::PathOptions::new(1.0, 1.0)),
            Err(WarpError::NonFinite { what: "stroke point", .. })
        ));
    }
}
