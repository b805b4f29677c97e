//! Typed errors of the orometric analysis.

use thiserror::Error;

/// What went wrong while analysing a DEM.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum OrometryError {
    /// Every sample is no-data (or below the sea level): there is no land to analyse.
    #[error("the DEM has no valid sample above the sea level ({cells} cells)")]
    NoLand {
        /// Samples in the grid.
        cells: usize,
    },
    /// The grid has more samples than the analysis indexes (2³² − 1).
    #[error("the DEM has {cells} samples, more than the {limit} the analysis indexes")]
    TooLarge {
        /// Samples in the grid.
        cells: usize,
        /// The cap.
        limit: usize,
    },
    /// An option is out of range.
    #[error("{name} = {value}: {reason}")]
    InvalidOption {
        /// The option.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The rule it breaks.
        reason: &'static str,
    },
}
