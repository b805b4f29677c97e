//! How a quantised file (16- or 8-bit PNG, `.r16`) maps its integer codes to elevations, for
//! tools that show or check it (`relief info`) and for users writing their own importer.

use std::path::Path;

use crate::meta::Metadata;
use crate::{Format, IoError, IoErrorKind, Limits};

/// The linear map of a quantised file: code `lowest_code` stands for `min`, `highest_code` for
/// `max`, codes between them for `min + (code − lowest_code) · step()`.
///
/// Files relief writes carry the map in their metadata (a PNG `relief` text chunk, a raw file's
/// `<file>.json` sidecar); code 0 is then no-data when the field has any, and the codes start at 1.
/// A file without metadata (from an image editor, a Unity `.raw`) reads as `code / max_code`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantisation {
    /// Bits per code: 8 or 16.
    pub bits: u8,
    /// The code that stands for `min`: 1 when code 0 is no-data, else 0.
    pub lowest_code: u32,
    /// The code that stands for `max`: `2^bits − 1`.
    pub highest_code: u32,
    /// The elevation of `lowest_code`.
    pub min: f64,
    /// The elevation of `highest_code`.
    pub max: f64,
    /// The code read as no-data, if any (0 in relief's files, a PNG's tRNS gray level in others).
    pub no_data_code: Option<u32>,
    /// Whether the map comes from relief's metadata; `false` for a plain image read as
    /// `code / max_code` in `[0, 1]`.
    pub from_metadata: bool,
}

impl Quantisation {
    /// The elevation between two successive codes: the files' vertical resolution.
    #[must_use]
    pub fn step(&self) -> f64 {
        (self.max - self.min) / f64::from(self.highest_code.saturating_sub(self.lowest_code).max(1))
    }

    fn from_metadata(meta: &Metadata, bits: u8) -> Self {
        let max_code = (1u32 << bits) - 1;
        Self {
            bits,
            lowest_code: u32::from(meta.no_data_code.is_some()),
            highest_code: max_code,
            min: meta.min.unwrap_or(0.0),
            max: meta.max.unwrap_or(0.0),
            no_data_code: meta.no_data_code,
            from_metadata: true,
        }
    }

    fn plain(bits: u8, no_data_code: Option<u32>) -> Self {
        let max_code = (1u32 << bits) - 1;
        Self { bits, lowest_code: 0, highest_code: max_code, min: 0.0, max: 1.0, no_data_code, from_metadata: false }
    }
}

/// The code-to-elevation map of the heightfield at `path`: `Some` for a grayscale PNG or an
/// `.r16` file, `None` for formats that store elevations themselves (EXR, r32, ASCII grid,
/// `GeoTIFF`, HGT).
///
/// ```
/// # use glam::DVec2;
/// # use relief_heightfield::{GridSpec, Heightfield};
/// use relief_heightfield_io::{WriteOptions, quantisation, write_with};
///
/// # let hf = Heightfield::from_fn(GridSpec::new(8, 8, DVec2::ZERO, DVec2::ONE)?, |p| p.x as f32)?;
/// let dir = tempfile::tempdir()?;
/// let path = dir.path().join("h.r16");
/// write_with(&path, &hf, &WriteOptions::default().with_range(-100.0, 2500.0))?;
/// let q = quantisation(&path)?.unwrap();
/// assert_eq!((q.min, q.max, q.lowest_code, q.highest_code), (-100.0, 2500.0, 0, 65535));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// As [`read`](crate::read): the file or its sidecar cannot be read or is malformed.
pub fn quantisation(path: impl AsRef<Path>) -> Result<Option<Quantisation>, IoError> {
    let path = path.as_ref();
    let bytes = crate::read_input(path, Limits::default())?;
    quantisation_of(path, &bytes)
}

/// [`quantisation`] of the file at `path` whose contents, `bytes`, are already read.
pub(crate) fn quantisation_of(path: &Path, bytes: &[u8]) -> Result<Option<Quantisation>, IoError> {
    match Format::detect(path, bytes) {
        #[cfg(feature = "png")]
        Some(Format::Png16 | Format::Png8) if crate::png_gray::colour_bits(bytes).is_some() => {
            Ok(crate::png_gray::colour_bits(bytes).map(|bits| Quantisation::plain(bits, None)))
        }
        // JPEG, BMP and WebP: 8-bit codes, never with relief metadata.
        Some(Format::Image) => Ok(Some(Quantisation::plain(8, None))),
        #[cfg(feature = "png")]
        Some(Format::Png16 | Format::Png8) => {
            let image =
                crate::png_gray::read_gray(bytes, Limits::default()).map_err(|kind| IoError::new(path, kind))?;
            Ok(Some(match &image.meta {
                Some(meta) => Quantisation::from_metadata(meta, image.bits),
                None => Quantisation::plain(image.bits, image.transparent),
            }))
        }
        Some(Format::R16) => {
            let sidecar_path = crate::raw_sidecar_path(path);
            let sidecar = crate::read_small_text(&sidecar_path, 1 << 20)?
                .map(|text| Metadata::from_json(&text))
                .transpose()
                .map_err(|k| IoError::new(&sidecar_path, k))?;
            match sidecar {
                Some(meta) if meta.encoding != "r16" => Err(IoError::new(
                    &sidecar_path,
                    IoErrorKind::HeaderMismatch(format!("sidecar describes {} data, not r16", meta.encoding)),
                )),
                Some(meta) => Ok(Some(Quantisation::from_metadata(&meta, 16))),
                None => Ok(Some(Quantisation::plain(16, None))),
            }
        }
        _ => Ok(None),
    }
}
