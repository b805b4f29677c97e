use thiserror::Error;

/// Why heights, contours or a reconstruction could not be produced.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum ContoursError {
    /// A histogram has no bins or samples.
    #[error("histogram is empty: give at least one bin with positive weight or one sample")]
    EmptyHistogram,
    /// Histogram bin edges are not finite and strictly increasing, or counts do not match.
    #[error("invalid histogram: {reason}")]
    InvalidHistogram {
        /// What is wrong.
        reason: String,
    },
    /// A value given as a height or level is not finite.
    #[error("{what} {value} is not finite")]
    NonFinite {
        /// What the value is.
        what: &'static str,
        /// The value.
        value: f64,
    },
    /// The ranked nodes are inconsistent with the mesh.
    #[error("invalid ranking: {reason}")]
    InvalidRanking {
        /// What is wrong.
        reason: String,
    },
    /// Per-node heights have the wrong length.
    #[error("{found} heights given for {expected} nodes")]
    HeightCountMismatch {
        /// Nodes in the mesh.
        expected: usize,
        /// Heights given.
        found: usize,
    },
    /// Contour levels must be finite and strictly increasing.
    #[error("contour levels must be finite and strictly increasing (problem at index {index})")]
    InvalidLevels {
        /// First offending index.
        index: usize,
    },
    /// A smoothing parameter is out of range.
    #[error("smoothing {field} = {value} {reason}")]
    InvalidSmoothing {
        /// The parameter (`alpha` or `k`).
        field: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        reason: &'static str,
    },
    /// The requested contour interval or level count makes no sense for the data.
    #[error("invalid level request: {reason}")]
    InvalidLevelRequest {
        /// What is wrong.
        reason: String,
    },
    /// A contour set's structure is broken (reported by `check_invariants`).
    #[error("contour invariant violated: {0}")]
    Invariant(String),
}

impl ContoursError {
    /// Where the offending value is, as a JSON path relative to the value the failing call was
    /// given (the field of a [`crate::Smoothing`]); empty when the error concerns that value as a
    /// whole. The `relief` facade prefixes it with the value's own path in the scene.
    pub fn location(&self) -> String {
        match self {
            Self::InvalidSmoothing { field, .. } => (*field).to_owned(),
            _ => String::new(),
        }
    }
}
