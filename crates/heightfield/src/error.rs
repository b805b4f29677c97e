use thiserror::Error;

/// Why a grid or heightfield could not be built or combined.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum HeightfieldError {
    /// A dimension is zero.
    #[error("grid dimensions {nx}x{ny} are empty: both must be at least 1")]
    EmptyGrid {
        /// Samples along x.
        nx: usize,
        /// Samples along y.
        ny: usize,
    },
    /// `nx * ny` does not fit the address space (or the 2^32 − 1 samples a grid may hold).
    #[error("grid dimensions {nx}x{ny} exceed the maximum of {max} samples")]
    TooManySamples {
        /// Samples along x.
        nx: usize,
        /// Samples along y.
        ny: usize,
        /// The largest sample count a grid may hold.
        max: u64,
    },
    /// The spacing between samples is not a finite positive number, is subnormal, or is too small
    /// for the origin's magnitude to tell neighbouring samples apart.
    #[error(
        "cell size ({x}, {y}) must be finite and > 0 along both axes, at least f64's smallest normal number, and \
         large enough that neighbouring samples' coordinates differ"
    )]
    InvalidCellSize {
        /// Spacing along x.
        x: f64,
        /// Spacing along y.
        y: f64,
    },
    /// The grid origin (or the far corner it implies) is not finite.
    #[error("grid origin ({x}, {y}) or the extent it spans is not finite")]
    InvalidOrigin {
        /// Origin x.
        x: f64,
        /// Origin y.
        y: f64,
    },
    /// An extent's max corner is not strictly above its min corner along an axis with more than one sample.
    #[error("extent min [{min_x}, {min_y}] must be finite and below max [{max_x}, {max_y}]")]
    InvalidExtent {
        /// Minimum x.
        min_x: f64,
        /// Minimum y.
        min_y: f64,
        /// Maximum x.
        max_x: f64,
        /// Maximum y.
        max_y: f64,
    },
    /// A geographic grid reaches beyond the poles.
    #[error("geographic grid spans latitudes [{min_lat}, {max_lat}], outside [-90, 90]")]
    LatitudeOutOfRange {
        /// Southernmost sample latitude, degrees.
        min_lat: f64,
        /// Northernmost sample latitude, degrees.
        max_lat: f64,
    },
    /// The sample vector's length does not match the grid.
    #[error("grid of {nx}x{ny} needs {expected} samples, got {found}")]
    SampleCountMismatch {
        /// Samples along x.
        nx: usize,
        /// Samples along y.
        ny: usize,
        /// `nx * ny`.
        expected: usize,
        /// Length that was given.
        found: usize,
    },
    /// A sample is infinite (NaN is accepted and means no-data).
    #[error("sample ({i}, {j}) is {value}: elevations must be finite (use NaN for no-data)")]
    NonFiniteSample {
        /// Column.
        i: usize,
        /// Row.
        j: usize,
        /// The offending value.
        value: f32,
    },
    /// Two heightfields combined cell by cell do not share the same grid.
    #[error("grids differ: {left_nx}x{left_ny} vs {right_nx}x{right_ny} (or their extents differ)")]
    GridMismatch {
        /// Left grid samples along x.
        left_nx: usize,
        /// Left grid samples along y.
        left_ny: usize,
        /// Right grid samples along x.
        right_nx: usize,
        /// Right grid samples along y.
        right_ny: usize,
    },
    /// A serialized no-data run lies outside the grid.
    #[error("no-data run starting at {start} with length {len} exceeds the {total} samples of the grid")]
    NoDataRunOutOfRange {
        /// First sample of the run.
        start: usize,
        /// Run length.
        len: usize,
        /// Samples in the grid.
        total: usize,
    },
    /// A units name that is none of metres, degrees, feet, US survey feet.
    #[error("unknown units {name:?}: use metres, degrees, feet or us_survey_feet")]
    UnknownUnits {
        /// The name given.
        name: String,
    },
    /// A coordinate reference system that cannot be used.
    #[error("invalid coordinate reference system: {reason}")]
    InvalidCrs {
        /// What is wrong with it.
        reason: String,
    },
}
