use thiserror::Error;

/// Why a hydrological analysis or an erosion step could not run.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum HydrologyError {
    /// Every cell of the heightfield is no-data: there is no terrain to analyse.
    #[error("the heightfield holds no data ({cells} cells, all no-data)")]
    AllNoData {
        /// Number of cells.
        cells: usize,
    },
    /// A per-cell or per-node array does not match the grid or graph it goes with.
    #[error("{what}: {found} values given for {expected}")]
    LengthMismatch {
        /// Which array.
        what: &'static str,
        /// The length it needs.
        expected: usize,
        /// The length given.
        found: usize,
    },
    /// A parameter is out of its valid range.
    #[error("invalid {name} = {value}: {reason}")]
    InvalidParameter {
        /// The parameter.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What it must be.
        reason: &'static str,
    },
    /// A per-cell or per-node value is not finite where it must be.
    #[error("{what} at index {index} is {value}, not a finite number")]
    NonFinite {
        /// Which array.
        what: &'static str,
        /// Where.
        index: usize,
        /// The value.
        value: f64,
    },
    /// A graph's adjacency is malformed (offsets not monotone, a neighbour out of range).
    #[error("invalid graph: {reason}")]
    InvalidGraph {
        /// What is wrong.
        reason: String,
    },
}

/// Checks that a parameter is finite and satisfies `ok`.
pub(crate) fn check_param(
    name: &'static str,
    value: f64,
    ok: impl Fn(f64) -> bool,
    reason: &'static str,
) -> Result<(), HydrologyError> {
    if value.is_finite() && ok(value) { Ok(()) } else { Err(HydrologyError::InvalidParameter { name, value, reason }) }
}

impl HydrologyError {
    /// Where the offending value is, as a JSON path relative to the value the failing call was
    /// given (the parameter of a [`crate::StreamPower`] or [`crate::Thermal`]); empty when the error
    /// concerns the terrain or the call as a whole. The `relief` facade prefixes it with the
    /// value's own path in the scene.
    pub fn location(&self) -> String {
        match self {
            Self::InvalidParameter { name, .. } => (*name).to_owned(),
            Self::LengthMismatch { what, .. } => (*what).to_owned(),
            _ => String::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parameter_errors_are_located_at_the_parameter() {
        let bad = HydrologyError::InvalidParameter { name: "n", value: -1.0, reason: "must be finite and > 0" };
        assert_eq!(bad.location(), "n");
        let short = HydrologyError::LengthMismatch { what: "uplift", expected: 4, found: 3 };
        assert_eq!(short.location(), "uplift");
        assert_eq!(HydrologyError::AllNoData { cells: 4 }.location(), "");
    }
}
