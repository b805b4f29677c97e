//! File formats and their detection from magic bytes and extensions.

use std::fmt;
use std::path::Path;

/// A heightfield file format.
///
/// Every variant exists whatever the cargo features; reading or writing a format whose feature is
/// off fails with [`crate::IoErrorKind::FormatDisabled`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Format {
    /// 8-bit grayscale PNG, quantised over the field's min/max (`.png`).
    Png8,
    /// 16-bit grayscale PNG, quantised over the field's min/max (`.png`, the default on write).
    Png16,
    /// `OpenEXR`, one f32 channel (`.exr`).
    Exr,
    /// Headerless little-endian u16, quantised, with a JSON sidecar (`.r16`, `.raw`).
    R16,
    /// Headerless little-endian f32 with a JSON sidecar (`.r32`).
    R32,
    /// ESRI ASCII grid (`.asc`) with an optional `.prj`.
    Asc,
    /// SRTM tile: 1201² or 3601² big-endian i16 (`.hgt`).
    Hgt,
    /// Single-band `GeoTIFF` (`.tif`, `.tiff`).
    GeoTiff,
    /// A JPEG, BMP or WebP image (read only, through the `image` crate): one gray value per pixel
    /// in `[0, 1]` (8-bit `code / 255`) on a plain grid, like a PNG without metadata.
    Image,
}

impl Format {
    /// Every format that is written as well as read, in documentation order ([`Format::Image`]
    /// is read only).
    pub const ALL: [Format; 8] =
        [Format::Png8, Format::Png16, Format::Exr, Format::R16, Format::R32, Format::Asc, Format::Hgt, Format::GeoTiff];

    /// The format a file name's extension names (case-insensitive); `.png` means [`Format::Png16`]
    /// (on read, 8 or 16 bits is taken from the PNG header either way).
    pub fn from_extension(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "png" => Format::Png16,
            "exr" => Format::Exr,
            "r16" | "raw" => Format::R16,
            "r32" => Format::R32,
            "asc" => Format::Asc,
            "hgt" => Format::Hgt,
            "tif" | "tiff" => Format::GeoTiff,
            "jpg" | "jpeg" | "bmp" | "webp" => Format::Image,
            _ => return None,
        })
    }

    /// The format of a file from its first bytes (16 are plenty), falling back on its extension.
    ///
    /// Magic bytes win over a wrong extension: PNG (`\x89PNG`), `OpenEXR` (`76 2f 31 01`), TIFF and
    /// `BigTIFF` (`II*\0`, `MM\0*`, `II+\0`, `MM\0+`), and ESRI ASCII grids (text whose first word is
    /// a header key such as `ncols`, case-insensitive). Raw and `.hgt` files have no magic and
    /// are recognised by extension only.
    pub fn detect(path: &Path, first_bytes: &[u8]) -> Option<Format> {
        Self::from_magic(first_bytes).or_else(|| Self::from_extension(path))
    }

    fn from_magic(b: &[u8]) -> Option<Format> {
        if b.starts_with(b"\x89PNG\r\n\x1a\n") {
            return Some(Format::Png16);
        }
        if b.starts_with(&[0x76, 0x2f, 0x31, 0x01]) {
            return Some(Format::Exr);
        }
        if [b"II*\0", b"MM\0*", b"II+\0", b"MM\0+"].iter().any(|m| b.starts_with(*m)) {
            return Some(Format::GeoTiff);
        }
        if is_image(b) {
            return Some(Format::Image);
        }
        let text = b.strip_prefix(b"\xef\xbb\xbf").unwrap_or(b);
        let start = text.iter().position(|c| !c.is_ascii_whitespace())?;
        let word: Vec<u8> = text[start..]
            .iter()
            .take_while(|c| c.is_ascii_alphabetic() || **c == b'_')
            .map(u8::to_ascii_lowercase)
            .collect();
        is_asc_header_key(&word).then_some(Format::Asc)
    }

    /// The usual file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Png8 | Format::Png16 => "png",
            Format::Exr => "exr",
            Format::R16 => "r16",
            Format::R32 => "r32",
            Format::Asc => "asc",
            Format::Hgt => "hgt",
            Format::GeoTiff => "tif",
            Format::Image => "jpg",
        }
    }

    /// The cargo feature that provides this format, if it needs one.
    /// Whether relief writes this format (every one but [`Format::Image`]).
    pub fn is_writable(self) -> bool {
        self != Format::Image
    }

    pub(crate) fn feature(self) -> Option<&'static str> {
        match self {
            Format::Png8 | Format::Png16 => Some("png"),
            Format::Exr => Some("exr"),
            Format::GeoTiff => Some("geotiff"),
            Format::Image => Some("images"),
            Format::R16 | Format::R32 | Format::Asc | Format::Hgt => None,
        }
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Format::Png8 => "8-bit PNG",
            Format::Png16 => "16-bit PNG",
            Format::Exr => "OpenEXR",
            Format::R16 => "raw r16",
            Format::R32 => "raw r32",
            Format::Asc => "ESRI ASCII grid",
            Format::Hgt => "SRTM HGT",
            Format::GeoTiff => "GeoTIFF",
            Format::Image => "image (JPEG, BMP, WebP)",
        })
    }
}

/// The keys of an ESRI ASCII grid header, lower case. Detection knows them (a text file starting
/// with one is an ASCII grid), and so does the reader.
/// JPEG (`FF D8 FF`), WebP (`RIFF….WEBP`) or a BMP whose info header has one of the sizes the
/// format defines (two bytes `BM` alone could start a raw heightmap).
fn is_image(b: &[u8]) -> bool {
    let bmp_header = b.get(14..18).map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]));
    b.starts_with(&[0xff, 0xd8, 0xff])
        || (b.starts_with(b"RIFF") && b.get(8..12) == Some(b"WEBP"))
        || (b.starts_with(b"BM") && matches!(bmp_header, Some(12 | 40 | 52 | 56 | 64 | 108 | 124)))
}

const ASC_KEYS: [&[u8]; 10] = [
    b"ncols",
    b"nrows",
    b"xllcorner",
    b"xllcenter",
    b"yllcorner",
    b"yllcenter",
    b"cellsize",
    b"dx",
    b"dy",
    b"nodata_value",
];

/// Whether `word` (lower case) is an ESRI ASCII grid header key.
pub(crate) fn is_asc_header_key(word: &[u8]) -> bool {
    ASC_KEYS.contains(&word)
}
