//! The crate's error type: which file, and what is wrong with it.

use std::fmt;
use std::path::{Path, PathBuf};

use relief_heightfield::HeightfieldError;
use thiserror::Error;

use crate::Format;

/// A read or write that failed: the file it concerned and the problem.
///
/// Displays as `<path>: <problem>`. In-memory calls ([`crate::read_bytes`], [`crate::write_bytes`])
/// carry the name they were given, or `<memory>`.
#[derive(Debug)]
pub struct IoError {
    path: PathBuf,
    kind: IoErrorKind,
}

impl IoError {
    /// An error about `path`.
    pub(crate) fn new(path: impl Into<PathBuf>, kind: IoErrorKind) -> Self {
        Self { path: path.into(), kind }
    }

    /// The file the error concerns (a sidecar such as `terrain.r16.json` when that is the culprit).
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// What went wrong.
    pub fn kind(&self) -> &IoErrorKind {
        &self.kind
    }

    /// Whether the file was refused for announcing (or holding) more than [`crate::Limits`]
    /// allows, before it was decoded.
    pub fn is_over_limit(&self) -> bool {
        matches!(self.kind, IoErrorKind::TooLarge { .. } | IoErrorKind::FileTooLarge { .. })
    }

    /// Consumes the error, returning what went wrong.
    pub fn into_kind(self) -> IoErrorKind {
        self.kind
    }
}

impl fmt::Display for IoError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.kind)
    }
}

impl std::error::Error for IoError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        // The kind's text, and with it the wrapped error's, is already part of our Display; expose
        // only what lies beneath, so `{:#}` chains do not print the same message twice.
        match &self.kind {
            IoErrorKind::Io(e) => e.source(),
            IoErrorKind::InvalidData(e) => e.source(),
            _ => None,
        }
    }
}

/// What went wrong, by category.
///
/// Dependency errors (png, exr, tiff) are never exposed as types: they are converted to
/// [`IoErrorKind::Decode`] / [`IoErrorKind::Encode`] messages, or to [`IoErrorKind::Truncated`]
/// when the decoder ran out of bytes.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum IoErrorKind {
    /// The operating system refused (missing file, missing directory, permissions, disk full).
    #[error("{0}")]
    Io(#[source] std::io::Error),
    /// Neither the magic bytes nor the extension name a known format.
    #[error(
        "unknown heightfield format: expected a .png, .exr, .r16, .raw, .r32, .asc, .hgt, .tif, .tiff, .jpg, .bmp or .webp file \
         (or set the format explicitly)"
    )]
    UnknownFormat,
    /// The format's cargo feature was compiled out.
    #[error("{format} support is disabled: enable the `{feature}` feature of relief-heightfield-io")]
    FormatDisabled {
        /// The format asked for.
        format: Format,
        /// The cargo feature that provides it.
        feature: &'static str,
    },
    /// The file ends before the data its header announces.
    #[error("file is truncated: {}", truncated_message(*.expected_bytes, *.found_bytes))]
    Truncated {
        /// Bytes the header implies, when the format lets us compute it.
        expected_bytes: Option<u64>,
        /// Bytes actually present.
        found_bytes: u64,
    },
    /// A headerless file whose length is none of the sizes the format allows.
    #[error("file holds {found_bytes} bytes, but this format needs {}", list_sizes(accepted_bytes))]
    WrongSize {
        /// Bytes present.
        found_bytes: u64,
        /// The byte lengths that would be valid.
        accepted_bytes: Vec<u64>,
    },
    /// Two parts of the file (or file and sidecar) disagree, e.g. metadata naming other dimensions
    /// than the image header.
    #[error("header does not match the data: {0}")]
    HeaderMismatch(String),
    /// The header announces more cells than [`crate::Limits::max_cells`] allows.
    #[error("{cells} cells exceed the limit of {limit} (raise Limits::max_cells to read it)")]
    TooLarge {
        /// Cells the header announces (saturated at `u64::MAX`); for a multi-channel OpenEXR file,
        /// cells × channels, as every channel is decoded.
        cells: u64,
        /// The configured limit.
        limit: u64,
    },
    /// The file is bigger than any grid within [`crate::Limits::max_cells`] could justify (32 bytes
    /// per cell plus 1 MiB), checked from its size before it is read.
    #[error(
        "the file is {bytes} bytes, more than the {limit} bytes a grid of at most {max_cells} cells needs (raise Limits::max_cells to read it)"
    )]
    FileTooLarge {
        /// The file's size.
        bytes: u64,
        /// The byte limit derived from the cell limit.
        limit: u64,
        /// The cell limit.
        max_cells: u64,
    },
    /// The path is a directory, device, pipe or socket: only regular files are read, so a scene
    /// naming `/dev/zero` or a FIFO fails at once instead of reading forever.
    #[error("not a regular file")]
    NotAFile,
    /// A valid file this crate does not handle (RGB PNG, multi-band TIFF, …), or a grid a format
    /// cannot hold (a 100×80 grid as `.hgt`).
    #[error("unsupported: {0}")]
    Unsupported(String),
    /// The decoder rejected the data (corrupt compressed stream, bad chunk, …).
    #[error("cannot decode: {0}")]
    Decode(String),
    /// The encoder failed.
    #[error("cannot encode: {0}")]
    Encode(String),
    /// A header, geo tag, metadata chunk or sidecar is missing a field or holds a nonsensical one.
    #[error("invalid metadata: {0}")]
    InvalidMetadata(String),
    /// A text grid's value is not a finite number.
    #[error("line {line}: value at row {row}, column {col} is not a number: {token:?}")]
    InvalidToken {
        /// Line of the file (1-based).
        line: usize,
        /// Data row in file order (1-based, row 1 = north).
        row: usize,
        /// Column (1-based, column 1 = west).
        col: usize,
        /// The offending text (shortened to 32 characters).
        token: String,
    },
    /// A text grid holds fewer values than its header announces.
    #[error("header announces {expected} values but the data ends after {found}: row {row}, column {col} is missing")]
    MissingValues {
        /// `ncols · nrows`.
        expected: u64,
        /// Values found.
        found: u64,
        /// First missing row (1-based, row 1 = north).
        row: usize,
        /// First missing column (1-based).
        col: usize,
    },
    /// Something follows the last value a text grid's header announces.
    #[error("line {line}: unexpected {token:?} after the last of the values the header announces")]
    TrailingData {
        /// Line of the file (1-based).
        line: usize,
        /// The first extra token (shortened to 32 characters).
        token: String,
    },
    /// The samples cannot form a [`relief_heightfield::Heightfield`] (±∞ in a float file, a grid
    /// geometry the heightfield rejects).
    #[error("{0}")]
    InvalidData(#[source] HeightfieldError),
    /// A sample cannot be stored in the target format (e.g. above 32767 m in `.hgt`).
    #[error("sample ({i}, {j}) = {value} is outside [{min}, {max}], the range this format can store")]
    OutOfRange {
        /// Column.
        i: usize,
        /// Row (0 = south).
        j: usize,
        /// The elevation.
        value: f32,
        /// Lowest storable value.
        min: f64,
        /// Highest storable value.
        max: f64,
    },
    /// A raw file's dimensions are unknown: no sidecar, no [`crate::ReadOptions::raw_dims`], and
    /// the length is not a square number of samples.
    #[error(
        "cannot tell the dimensions: no sidecar {} and the length is not a square number of samples \
         (set ReadOptions::raw_dims)", .sidecar.display()
    )]
    MissingSidecar {
        /// Where the sidecar was looked for.
        sidecar: PathBuf,
    },
}

impl From<HeightfieldError> for IoErrorKind {
    fn from(e: HeightfieldError) -> Self {
        IoErrorKind::InvalidData(e)
    }
}

fn truncated_message(expected: Option<u64>, found: u64) -> String {
    match expected {
        Some(e) => format!("expected {e} bytes, found {found}"),
        None => format!("data ends unexpectedly after {found} bytes"),
    }
}

fn list_sizes(sizes: &[u64]) -> String {
    let parts: Vec<String> = sizes.iter().map(u64::to_string).collect();
    match parts.len() {
        0 => "a different size".to_owned(),
        1 => format!("{} bytes", parts[0]),
        _ => format!("{} or {} bytes", parts[..parts.len() - 1].join(", "), parts[parts.len() - 1]),
    }
}

/// Shortens a token for an error message.
pub(crate) fn clip(token: &str) -> String {
    token.chars().take(32).collect()
}

/// A dependency's "ran out of bytes" or anything else, as our kind.
#[cfg_attr(
    not(any(feature = "png", feature = "exr", feature = "geotiff")),
    expect(dead_code, reason = "used by the codec modules only")
)]
pub(crate) fn decode_io(e: &std::io::Error, found_bytes: usize) -> IoErrorKind {
    if e.kind() == std::io::ErrorKind::UnexpectedEof {
        IoErrorKind::Truncated { expected_bytes: None, found_bytes: found_bytes as u64 }
    } else {
        IoErrorKind::Decode(e.to_string())
    }
}

/// Why [`crate::read_capped`] refused a file.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum CapError {
    /// The operating system refused (missing file, permissions, …).
    #[error("{0}")]
    Io(#[source] std::io::Error),
    /// A directory, device, pipe or socket: only regular files are read.
    #[error("not a regular file")]
    NotAFile,
    /// The file holds more than the cap allows (its size, or what was read when it grew).
    #[error("{bytes} bytes is more than the {max}-byte limit")]
    TooLarge {
        /// The file's size.
        bytes: u64,
        /// The cap.
        max: u64,
    },
}
