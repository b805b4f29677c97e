//! Typed errors of the vector-terrain model and its rasterizer.

use thiserror::Error;

/// What went wrong while building, loading or rasterizing a [`crate::VectorTerrain`].
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum GaussianError {
    /// A primitive parameter is NaN or infinite.
    #[error("primitive {index}: {what} is not finite")]
    NotFinite {
        /// Index of the primitive in its list.
        index: usize,
        /// Which parameter.
        what: &'static str,
    },
    /// A primitive parameter is out of its range (σ ≤ 0, β ≤ 0, …).
    #[error("primitive {index}: {what} = {value} ({reason})")]
    InvalidPrimitive {
        /// Index of the primitive in its list.
        index: usize,
        /// Which parameter.
        what: &'static str,
        /// Its value.
        value: f64,
        /// The rule it breaks.
        reason: &'static str,
    },
    /// More primitives than the memory cap allows.
    #[error("{count} primitives exceed the limit of {limit}")]
    TooManyPrimitives {
        /// Primitives asked for.
        count: usize,
        /// The cap ([`crate::MAX_PRIMITIVES`] unless configured).
        limit: usize,
    },
    /// An option of the rasterizer is out of range.
    #[error("{name} = {value}: {reason}")]
    InvalidOption {
        /// The option.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The rule it breaks.
        reason: &'static str,
    },
    /// The output grid is too large.
    #[error("output grid of {nx} × {ny} samples exceeds the limit of {limit} samples")]
    GridTooLarge {
        /// Samples along x.
        nx: usize,
        /// Samples along y.
        ny: usize,
        /// The cap ([`crate::MAX_RASTER_CELLS`]).
        limit: usize,
    },
    /// The summed elevation left the f32 range of grids (amplitudes near ±3.4·10³⁸ adding up).
    #[error("rasterized elevation: {0}")]
    Raster(#[from] relief_heightfield::HeightfieldError),
    /// The DEM to vectorize has fewer than 2 × 2 samples or no valid sample.
    #[error("the DEM has {nx} × {ny} samples and no relief to fit: need at least 2 × 2 valid samples")]
    EmptyDem {
        /// Samples along x.
        nx: usize,
        /// Samples along y.
        ny: usize,
    },
    /// The DEM to vectorize has no-data samples.
    #[error("the DEM has {count} no-data samples: fill them first (e.g. Heightfield::fill_no_data)")]
    DemHasNoData {
        /// How many.
        count: usize,
    },
    /// A selection region or placement is unusable.
    #[error("invalid region: {reason}")]
    InvalidRegion {
        /// What is wrong.
        reason: &'static str,
    },
    /// A skeleton, its attachments or a skeleton edit is unusable.
    #[error("skeleton: {reason}")]
    InvalidSkeleton {
        /// What is wrong.
        reason: &'static str,
    },
    /// A crest tool names a node the skeleton does not have.
    #[error(
        "crest node {node} does not exist: the skeleton has {nodes} nodes (ids 0..{nodes}, as outputs.skeleton lists them)"
    )]
    NoSuchNode {
        /// The id asked for.
        node: usize,
        /// How many nodes the skeleton has.
        nodes: usize,
    },
    /// No landform of that name in an atlas.
    #[error("no landform named {name:?} in the atlas")]
    NoSuchLandform {
        /// The name asked for.
        name: String,
    },
}
