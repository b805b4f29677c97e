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
    /// No landform of that name in an atlas.
    #[error("no landform named {name:?} in the atlas")]
    NoSuchLandform {
        /// The name asked for.
        name: String,
    },
}
