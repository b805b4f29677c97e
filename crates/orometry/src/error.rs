//! Typed errors of the orometric analysis.

use relief_heightfield::HeightfieldError;
use relief_hydrology::HydrologyError;
use relief_tin::TinError;
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
    /// A descriptor's histogram or domain facts are malformed.
    #[error("descriptor feature {feature}: {reason}")]
    InvalidDescriptor {
        /// The feature (or `domain`).
        feature: &'static str,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// A control map does not cover the synthesis domain.
    #[error(
        "control map {name} covers [{found:?}] but the domain is [{expected:?}] (x0, y0, x1, y1); resample it to the domain"
    )]
    ControlMapExtent {
        /// `peak_density` or `elevation`.
        name: &'static str,
        /// The domain.
        expected: [f64; 4],
        /// The map's extent.
        found: [f64; 4],
    },
    /// A control map holds a value it may not.
    #[error("control map {name}: {reason}")]
    InvalidControlMap {
        /// `peak_density` or `elevation`.
        name: &'static str,
        /// What is wrong.
        reason: &'static str,
    },
    /// A divide tree refers to a peak or saddle that does not exist, or breaks a rule.
    #[error("divide tree: {0}")]
    InvalidTree(String),
    /// A `.dvt` divide-tree file is malformed, or its format cannot hold a grid.
    #[error("divide tree file (.dvt): {0}")]
    Dvt(String),
    /// A pinned peak cannot be honoured.
    #[error("pinned peak {index}: {reason}")]
    InvalidPinnedPeak {
        /// Index in the pinned list.
        index: usize,
        /// Why.
        reason: &'static str,
    },
    /// The meshing distance is too small for the domain: the label raster and refined ridges
    /// would exceed [`crate::MAX_MESH_SAMPLES`].
    #[error(
        "lambda_m = {lambda} m needs about {samples:.0} mesh and routing samples over this domain, more than {limit}: raise lambda_m"
    )]
    MeshTooFine {
        /// The meshing distance λ.
        lambda: f64,
        /// Samples the domain would take at λ (the label raster at λ/2 and the refined ridges).
        samples: f64,
        /// The cap, [`crate::MAX_MESH_SAMPLES`].
        limit: u64,
    },
    /// More peaks were asked for than the synthesis places.
    #[error("{peaks} peaks asked for; the synthesis places at most {limit}")]
    TooManyPeaks {
        /// Asked for.
        peaks: usize,
        /// The cap.
        limit: usize,
    },
    /// The grid could not be built.
    #[error(transparent)]
    Grid(#[from] HeightfieldError),
    /// The triangulation failed.
    #[error(transparent)]
    Tin(#[from] TinError),
    /// Erosion or filling failed.
    #[error(transparent)]
    Hydrology(#[from] HydrologyError),
}
