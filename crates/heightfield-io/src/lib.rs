//! Reads and writes [`Heightfield`]s in the common DEM and heightmap formats, and renders
//! shaded-relief previews. Every reader checks its header against [`Limits`] before it allocates,
//! every error names the file and the problem ([`IoError`]), and every write is atomic.
//!
//! This crate implements no paper section; it is how the algorithms of the other relief crates meet
//! real terrain (SRTM tiles, `GeoTIFF` DEMs) and game-engine heightmaps. The main entry points are
//! [`read`] / [`write()`] (format from magic bytes or extension), their `_with` variants taking
//! [`ReadOptions`] / [`WriteOptions`], the in-memory [`read_bytes`] / [`write_bytes`], and
//! [`shaded_relief`] / [`write_preview_png`], and [`quantisation`] (how a 16-bit file's codes map
//! to metres). The types around them: [`Format`], [`Limits`],
//! [`IoError`] with its [`IoErrorKind`], [`ShadeOptions`] and [`RgbImage`].
//!
//! | Format | Extension | Samples | What is stored | Round trip |
//! |---|---|---|---|---|
//! | [`Format::Png16`] | `.png` | 16-bit gray | codes over `[min, max]` + `relief` tEXt JSON (min, max, geometry, units) | within one step `(max − min)/65535` |
//! | [`Format::Png8`] | `.png` | 8-bit gray | as PNG16 | within one step `(max − min)/255` |
//! | [`Format::Exr`] | `.exr` | f32 channel `Y` | NaN no-data; geometry in `relief.*` header attributes | bit-exact |
//! | [`Format::R16`] | `.r16`, `.raw` | little-endian u16 | codes as PNG16; `<file>.json` sidecar | within one step |
//! | [`Format::R32`] | `.r32` | little-endian f32 | NaN no-data; `<file>.json` sidecar | bit-exact |
//! | [`Format::Asc`] | `.asc` | decimal text | header + shortest round-trip decimals; `.prj` for units | bit-exact |
//! | [`Format::Hgt`] | `.hgt` | big-endian i16, 1201² or 3601² | −32768 voids; tile corner from the file name | exact for whole metres |
//! | [`Format::GeoTiff`] | `.tif`, `.tiff` | f32 or i16, DEFLATE + predictor (reads u8–i64, f16–f64; DEFLATE, LZW, `PackBits`, ZSTD, LZMA; a band of a multi-band file) | `ModelPixelScale`, `ModelTiepoint`, `GeoKeys`, `GDAL_NODATA` | bit-exact (f32) |
//! | [`Format::Image`] | `.jpg`, `.bmp`, `.webp` | read only, 8-bit | nothing: a plain image, like a PNG without metadata | — |
//!
//! Quantised formats reserve code 0 for no-data when the field has any; a field without the
//! metadata (a PNG from an image editor, a Unity `.raw`) reads as `code / max_code` in `[0, 1]`
//! on a grid with origin 0 and cell size 1. Formats without geometry (plain PNG, raw without
//! sidecar, EXR/TIFF without our attributes or geo tags) read with origin 0, cell size 1, metres;
//! [`ReadOptions::units`] and [`ReadOptions::origin`] override what a file says.
//!
//! Coordinate reference systems are kept, not reprojected: a field read from a `GeoTIFF` (its
//! EPSG-coded `GeoKey`s), an ASCII grid's `.prj` (WKT 1, WKT 2 or ESRI WKT) or a file relief wrote
//! carries its [`Crs`] ([`Heightfield::crs`]) and the grid takes its units from it (metres, feet,
//! US survey feet, degrees). Every writer labels its output the same way: `GeoTIFF` keys (a
//! user-defined CRS keeps its name and units), the `.prj` beside an ASCII grid, the metadata of
//! PNG, raw and EXR files. EPSG codes get their WKT from the `crs-definitions` tables (generated from
//! the EPSG registry: thousands of definitions nobody should type by hand); a WKT without a code
//! that defines WGS 84, NAD83, NAD27 or ETRS89 in degrees (ESRI's `GCS_WGS_1984` `.prj`) gets its
//! EPSG code, as GDAL reads it ([`Crs::identified`]). An ASCII grid without
//! `.prj` whose extent fits ±180° × ±90° with cells under an arc-minute reads in degrees, with a
//! [`ReadNote`] ([`read_with_notes`]); [`ReadOptions::crs`] / [`ReadOptions::units`] override
//! ([`parse_crs`] reads `EPSG:n`, WKT or a `.prj` path).
//!
//! Conventions: files are north-up (first row = north), while a [`GridSpec`] stores row `j = 0` in
//! the south, so readers and writers flip rows. Grids are node-registered: `GeoTIFF`s are written
//! `PixelIsPoint`, ASCII grids with `xllcenter`/`yllcenter`, and `PixelIsArea` / `xllcorner`
//! inputs are moved half a cell in. No-data is NaN in memory.
//!
//! Grayscale PNG and single-band TIFF go through the `png` and `tiff` crates directly (16-bit
//! codes, text chunks, geo tags, f32 samples that `image` 0.25 cannot read); everything else an
//! image can be — JPEG, BMP, WebP, palette/RGB/RGBA PNG and TIFF, 1-bit gray — goes through
//! `image` ([`Channel`], [`ReadOptions::channel`]): a heightmap must then be gray (equal
//! channels) or name its channel, a mask or probability map reads as luma. LZMA `GeoTIFF` strips
//! are inflated with `lzma-rs` (the `tiff` crate has no LZMA). Each codec sits behind a cargo
//! feature (`png`, `exr`, `geotiff`, `images`, all default); raw, ASCII grid and HGT need no
//! dependency.
//!
//! ```
//! use glam::DVec2;
//! use relief_heightfield::{GridSpec, Heightfield};
//! use relief_heightfield_io::{Format, read, write};
//!
//! let grid = GridSpec::new(64, 48, DVec2::new(500_000.0, 4_100_000.0), DVec2::splat(30.0))?;
//! let hill = Heightfield::from_fn(grid, |p| {
//!     let d = (p - DVec2::new(501_000.0, 4_100_700.0)).length();
//!     (800.0 - 0.3 * d) as f32
//! })?;
//! let dir = tempfile::tempdir()?;
//!
//! // Float formats round-trip bit for bit, geometry included (`.asc` writes a `.prj` beside it).
//! let path = dir.path().join("hill.asc");
//! write(&path, &hill)?;
//! assert_eq!(read(&path)?, hill);
//!
//! // 16-bit formats restore metres to within one quantisation step (`.r16` keeps min, max and
//! // geometry in `hill.r16.json`; a `.png` keeps them in a text chunk).
//! let raw = dir.path().join("hill.r16");
//! write(&raw, &hill)?;
//! let back = read(&raw)?;
//! let (lo, hi) = hill.min_max().unwrap();
//! let step = (hi - lo) / 65535.0;
//! assert_eq!(back.grid(), hill.grid());
//! assert!(back.samples().iter().zip(hill.samples()).all(|(a, b)| (a - b).abs() <= step));
//! assert_eq!(Format::detect(&raw, &[0x12, 0x34]), Some(Format::R16));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod asc;
mod atomic;
pub use atomic::abandoned;
mod codes;
mod crs;
mod error;
#[cfg(feature = "geotiff")]
mod geotiff;
mod hgt;
mod limits;
mod meta;
#[cfg(feature = "exr")]
mod openexr;
#[cfg(feature = "images")]
mod pixels;
#[cfg(feature = "png")]
mod png_gray;
mod preview;
mod raw;
#[cfg(feature = "geotiff")]
mod tiff_lzma;
#[cfg(feature = "geotiff")]
mod world;

mod format;

use std::ffi::OsString;
use std::io::Read as _;
use std::path::{Path, PathBuf};

use glam::DVec2;
use relief_heightfield::{Crs, GridSpec, Heightfield, Units};

pub use codes::{Quantisation, quantisation};
pub use crs::parse_crs;
pub use error::{CapError, IoError, IoErrorKind};
pub use format::Format;
pub use limits::Limits;
#[cfg(feature = "images")]
pub use pixels::Channel;
pub use preview::{NO_DATA_RGB, RgbImage, ShadeOptions, hypsometric_tint, shaded_relief};

use raw::RawKind;

/// How to read a file. `ReadOptions::default()` detects the format and applies [`Limits::default`].
#[derive(Debug, Clone, PartialEq, Default)]
#[non_exhaustive]
pub struct ReadOptions {
    /// Caps on what the header may make the reader allocate.
    pub limits: Limits,
    /// Read as this format instead of detecting it from magic bytes and extension.
    pub format: Option<Format>,
    /// `(nx, ny)` of a raw file without a sidecar. Without either, a raw file must hold a square
    /// number of samples (as Unity and Unreal heightmaps do).
    pub raw_dims: Option<(usize, usize)>,
    /// Units to give the grid, overriding the file (`.prj`, geo keys, metadata) and the CRS.
    pub units: Option<Units>,
    /// Coordinate reference system to label the grid with, overriding the file's; its units
    /// (from its WKT, looked up for a bare EPSG code) become the grid's unless
    /// [`ReadOptions::units`] is given too. Nothing is reprojected.
    pub crs: Option<Crs>,
    /// Position of sample `(0, 0)` (the south-west sample), overriding the file; needed for a `.hgt`
    /// tile whose file name is not a tile name such as `N36W085`.
    pub origin: Option<DVec2>,
    /// Distance between samples `(x, y)`, overriding the file (a heightmap image has none: it
    /// reads at 1 unit per sample).
    pub cell_size: Option<DVec2>,
    /// The elevations a plain 8/16-bit image's (or a sidecar-less `.r16`'s) lowest and highest
    /// codes stand for: codes map linearly onto `[min, max]` instead of `[0, 1]`. Refused for files
    /// that store elevations (float formats, or codes with their range recorded).
    pub z_range: Option<(f64, f64)>,
    /// The channel of a colour image that holds the values (a heightmap must otherwise be gray:
    /// equal channels; a mask or probability map otherwise reads as luma).
    #[cfg(feature = "images")]
    pub channel: Option<Channel>,
    /// The band (1-based) of a multi-band `GeoTIFF` to read; without it such a file is read only
    /// when it is a gray-equal RGB(A) image.
    pub band: Option<u16>,
}

impl ReadOptions {
    /// The same options with other limits.
    #[must_use]
    pub fn with_limits(mut self, limits: Limits) -> Self {
        self.limits = limits;
        self
    }

    /// The same options forcing `format`.
    #[must_use]
    pub fn with_format(mut self, format: Format) -> Self {
        self.format = Some(format);
        self
    }

    /// The same options with raw dimensions `nx × ny`.
    #[must_use]
    pub fn with_raw_dims(mut self, nx: usize, ny: usize) -> Self {
        self.raw_dims = Some((nx, ny));
        self
    }

    /// The same options forcing `units`.
    #[must_use]
    pub fn with_units(mut self, units: Units) -> Self {
        self.units = Some(units);
        self
    }

    /// The same options labelling the grid with `crs` (see [`ReadOptions::crs`]).
    #[must_use]
    pub fn with_crs(mut self, crs: Crs) -> Self {
        self.crs = Some(crs);
        self
    }

    /// The same options placing sample `(0, 0)` at `origin`.
    #[must_use]
    pub fn with_origin(mut self, origin: DVec2) -> Self {
        self.origin = Some(origin);
        self
    }

    /// The same options with samples `cell_size` apart.
    #[must_use]
    pub fn with_cell_size(mut self, cell_size: DVec2) -> Self {
        self.cell_size = Some(cell_size);
        self
    }

    /// The same options reading `channel` of colour images.
    #[cfg(feature = "images")]
    #[must_use]
    pub fn with_channel(mut self, channel: Channel) -> Self {
        self.channel = Some(channel);
        self
    }

    /// The same options reading band `band` (1-based) of a multi-band `GeoTIFF`.
    #[must_use]
    pub fn with_band(mut self, band: u16) -> Self {
        self.band = Some(band);
        self
    }

    /// The same options mapping a plain image's codes onto `[min, max]`.
    #[must_use]
    pub fn with_z_range(mut self, min: f64, max: f64) -> Self {
        self.z_range = Some((min, max));
        self
    }
}

/// How to write a file. `WriteOptions::default()` takes the format from the extension, deflates
/// `GeoTIFF`s (f32 with the floating-point predictor, as GDAL's `COMPRESS=DEFLATE PREDICTOR=3`)
/// and writes `OpenEXR` uncompressed.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[non_exhaustive]
pub struct WriteOptions {
    /// Write this format whatever the extension (e.g. [`Format::Png8`], which `.png` alone does
    /// not select).
    pub format: Option<Format>,
    /// Compress the float formats: ZIP (16-line blocks) for `OpenEXR`; for `GeoTIFF` DEFLATE after
    /// the floating-point predictor (f32) or the horizontal one (Int16), which GDAL and every
    /// GIS reads.
    ///
    /// `None` (the default) means on for `GeoTIFF` (a whole-metre DEM shrinks to about a quarter of
    /// its plain f32 size and a resampled one to about 60 %, each a little smaller than GDAL's
    /// `DEFLATE` + `PREDICTOR=3` output, for about three times the write time) and off for `OpenEXR` (the low
    /// mantissa bits of generated terrain are noise, so on a 4096² field ZIP saves about 10% for
    /// 35× the write time). PNG is always deflated (with the fast `fdeflate` level); raw, ASCII
    /// and `.hgt` have no compression.
    pub compress: Option<bool>,
    /// The `GeoTIFF` sample type (default f32). [`TiffSample::I16`] rounds to whole units, as
    /// SRTM tiles store them, with −32768 for no-data; a sample that does not fit is an
    /// [`IoErrorKind::OutOfRange`] error.
    pub tiff_sample: TiffSample,
    /// Write `GeoTIFF`s `PixelIsArea` (the raster's corner at the outer edge of the first cell,
    /// GDAL's default) instead of `PixelIsPoint` (on the first sample). Both place every sample
    /// at the same coordinates for GDAL and for this crate; `PixelIsArea` suits tools that ignore
    /// the raster type.
    pub pixel_is_area: bool,
    /// The elevations the quantised formats (PNG, r16) map their first and last codes to, in
    /// metres: a fixed vertical range for engines that import a heightmap with one height scale.
    /// `None` (the default) quantises over the field's own min and max. A sample outside the range
    /// is an [`IoErrorKind::OutOfRange`] error, never clamped; the range is recorded in the file's
    /// metadata, so reading it back gives metres.
    pub range: Option<(f32, f32)>,
}

impl WriteOptions {
    /// The same options forcing `format`.
    #[must_use]
    pub fn with_format(mut self, format: Format) -> Self {
        self.format = Some(format);
        self
    }

    /// The same options quantising over the fixed elevations `min..=max` (see
    /// [`WriteOptions::range`]).
    #[must_use]
    pub fn with_range(mut self, min: f32, max: f32) -> Self {
        self.range = Some((min, max));
        self
    }

    /// The same options with compression of the float formats on or off.
    #[must_use]
    pub fn with_compress(mut self, compress: bool) -> Self {
        self.compress = Some(compress);
        self
    }

    /// The same options writing `GeoTIFF` samples as `sample`.
    #[must_use]
    pub fn with_tiff_sample(mut self, sample: TiffSample) -> Self {
        self.tiff_sample = sample;
        self
    }

    /// The same options writing `GeoTIFF`s `PixelIsArea` (`true`) or `PixelIsPoint`.
    #[must_use]
    pub fn with_pixel_is_area(mut self, area: bool) -> Self {
        self.pixel_is_area = area;
        self
    }
}

/// The sample type of a written `GeoTIFF`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum TiffSample {
    /// 32-bit float, exact for every field.
    #[default]
    F32,
    /// 16-bit signed integer: whole units, −32768 for no-data (half the size of f32).
    I16,
}

/// Reads a heightfield, detecting the format from magic bytes, then the extension.
///
/// # Errors
/// Any [`IoErrorKind`]: [`IoErrorKind::Io`] for a missing file, [`IoErrorKind::UnknownFormat`],
/// [`IoErrorKind::TooLarge`] for a header over [`Limits::default`], and the format's own decoding
/// errors. The error's [`IoError::path`] names the file (or the sidecar at fault).
pub fn read(path: impl AsRef<Path>) -> Result<Heightfield, IoError> {
    read_with(path, &ReadOptions::default())
}

/// Reads a heightfield with explicit options.
///
/// Sidecars are read from beside the file: `<file>.json` for raw formats, `<stem>.prj` for ASCII
/// grids (degrees when it describes a geographic CRS), and for a `GeoTIFF` without geo tags a
/// world file (`<stem>.tfw`, `.tifw` or `.wld`), as GDAL reads them.
///
/// # Errors
/// As [`read`].
pub fn read_with(path: impl AsRef<Path>, options: &ReadOptions) -> Result<Heightfield, IoError> {
    read_with_notes(path, options).map(|(hf, _)| hf)
}

/// Something a reader assumed because the file did not say it; a command should show it to the
/// user, who can override it ([`ReadOptions::units`], [`ReadOptions::crs`]).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum ReadNote {
    /// An ASCII grid without a `.prj` was read in degrees: its extent fits within ±180° × ±90°
    /// and its cells are finer than an arc-minute, which no metric DEM of useful size has.
    GuessedDegrees {
        /// The cell size, in the file's units.
        cell_size: f64,
    },
}

impl std::fmt::Display for ReadNote {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ReadNote::GuessedDegrees { cell_size } => write!(
                f,
                "no .prj: read as geographic degrees (cell size {cell_size} fits only degrees); \
                 give --units metres or --crs EPSG:n if that is wrong"
            ),
        }
    }
}

/// As [`read_with`], also returning what the reader had to assume ([`ReadNote`]).
///
/// # Errors
/// As [`read`].
pub fn read_with_notes(path: impl AsRef<Path>, options: &ReadOptions) -> Result<(Heightfield, Vec<ReadNote>), IoError> {
    let path = path.as_ref();
    let at = |kind| IoError::new(path, kind);
    let bytes = read_input(path, options.limits)?;
    let format =
        options.format.or_else(|| Format::detect(path, &bytes)).ok_or_else(|| at(IoErrorKind::UnknownFormat))?;
    let mut notes = Vec::new();
    let hf = match format {
        Format::R16 | Format::R32 => {
            let sidecar_path = raw_sidecar_path(path);
            let sidecar = read_small_text(&sidecar_path, 1 << 20)?
                .map(|text| meta::Metadata::from_json(&text))
                .transpose()
                .map_err(|k| IoError::new(&sidecar_path, k))?;
            let shape = raw::Shape { sidecar: sidecar.as_ref(), dims: options.raw_dims, sidecar_path };
            raw::decode(&bytes, raw_kind(format), &shape, options.limits).map_err(at)?
        }
        Format::Asc => {
            let hf = asc::decode(&bytes, options.limits).map_err(at)?;
            let prj = path.with_extension("prj");
            let guess = options.units.is_none() && options.crs.is_none() && crs::looks_geographic(hf.grid());
            if read_small_text(&prj, 1 << 16)?.is_none() && guess {
                notes.push(ReadNote::GuessedDegrees { cell_size: hf.grid().cell_size().x });
                override_grid(hf, &ReadOptions::default().with_units(Units::Degrees)).map_err(at)?
            } else {
                labelled_by_prj(hf, path, options)?
            }
        }
        #[cfg(feature = "geotiff")]
        Format::GeoTiff => {
            let (hf, placed) = geotiff::decode_placed(&bytes, &tiff_read(options, false)).map_err(at)?;
            if placed { hf } else { placed_by_world_file(hf, path)? }
        }
        _ => decode_bytes(&bytes, format, path, options).map_err(at)?,
    };
    let hf = override_grid(hf, options).map_err(at)?;
    let hf = match options.z_range {
        Some(range) => stretch_codes(hf, range, path, &bytes)?,
        None => hf,
    };
    Ok((hf, notes))
}

/// `hf` labelled with the CRS and units of the `.prj` beside `path`, if there is one and the
/// options do not override them.
fn labelled_by_prj(hf: Heightfield, path: &Path, options: &ReadOptions) -> Result<Heightfield, IoError> {
    let prj_path = path.with_extension("prj");
    let Some(prj) = read_small_text(&prj_path, 1 << 16)? else { return Ok(hf) };
    if options.units.is_some() || options.crs.is_some() {
        return Ok(hf);
    }
    let (crs, units) = crs::read_prj(&prj);
    let hf = override_grid(hf, &ReadOptions::default().with_units(units)).map_err(|k| IoError::new(&prj_path, k))?;
    Ok(hf.with_crs(crs))
}

/// A plain image's `[0, 1]` code values mapped onto `[min, max]` ([`ReadOptions::z_range`]).
fn stretch_codes(hf: Heightfield, (min, max): (f64, f64), path: &Path, bytes: &[u8]) -> Result<Heightfield, IoError> {
    let at = |kind| IoError::new(path, kind);
    if !(min.is_finite() && max.is_finite() && min < max) {
        return Err(at(IoErrorKind::InvalidMetadata(format!("z range {min}..{max}: give finite min < max"))));
    }
    match codes::quantisation_of(path, bytes)? {
        Some(q) if !q.from_metadata => {}
        Some(q) => {
            return Err(at(IoErrorKind::InvalidMetadata(format!(
                "its codes already stand for {}..{} (recorded with the file): a z range is for plain images",
                q.min, q.max
            ))));
        }
        None => {
            return Err(at(IoErrorKind::InvalidMetadata(
                "it stores elevations: a z range is for plain 8/16-bit images and .r16 files".to_owned(),
            )));
        }
    }
    let grid = *hf.grid();
    let samples = hf.into_samples().into_iter().map(|v| (min + f64::from(v) * (max - min)) as f32).collect();
    Heightfield::from_samples(grid, samples).map_err(|e| at(e.into()))
}

/// `hf` (a TIFF without geo tags) placed by the first world file found beside `path`, if any.
#[cfg(feature = "geotiff")]
fn placed_by_world_file(hf: Heightfield, path: &Path) -> Result<Heightfield, IoError> {
    for candidate in world::candidates(path) {
        if let Some(text) = read_small_text(&candidate, 1 << 12)? {
            return world::place(hf, &text).map_err(|k| IoError::new(&candidate, k));
        }
    }
    Ok(hf)
}

/// Decodes a file held in memory; `name` appears in errors and, for `.hgt`, gives the tile corner.
///
/// `options.format` is ignored in favour of `format`, and `options.z_range` too (whether codes
/// have a recorded range is known from the file and its sidecars). Sidecars are not consulted: a raw file
/// needs [`ReadOptions::raw_dims`] (or a square size) and reads as in [`Format::R16`]'s
/// no-metadata convention; an ASCII grid reads in metres unless [`ReadOptions::units`] says
/// otherwise. Suitable for fuzzing: no input makes it panic or allocate beyond its limits.
///
/// # Errors
/// As [`read`], with `name` as the error's path.
pub fn read_bytes(
    bytes: &[u8],
    format: Format,
    name: impl AsRef<Path>,
    options: &ReadOptions,
) -> Result<Heightfield, IoError> {
    let name = name.as_ref();
    let at = |kind| IoError::new(name, kind);
    let hf = decode_bytes(bytes, format, name, options).map_err(at)?;
    override_grid(hf, options).map_err(at)
}

/// How many cells the file held in `bytes` announces, read from its header without decoding
/// a sample: the check a server makes on an upload before keeping it (a 486 KB PNG may announce
/// 16000² pixels, gigabytes once decoded).
///
/// Every reader compares the header's size with [`Limits::max_cells`] before it allocates, so
/// this reads under a limit of zero cells and takes the size from that refusal. A raw file has no
/// header: its cells are its length over the sample size (a partial last sample does not count).
///
/// # Errors
/// As [`read_bytes`], for a header that cannot be read (a decoding problem beyond the header is
/// not seen).
pub fn announced_cells(
    bytes: &[u8],
    format: Format,
    name: impl AsRef<Path>,
    options: &ReadOptions,
) -> Result<u64, IoError> {
    let name = name.as_ref();
    if let Some(bytes_per_sample) = match format {
        Format::R16 => Some(2),
        Format::R32 => Some(4),
        _ => None,
    } {
        return Ok(bytes.len() as u64 / bytes_per_sample);
    }
    let header_only = ReadOptions { limits: Limits::default().with_max_cells(0), ..options.clone() };
    match decode_bytes(bytes, format, name, &header_only) {
        Err(IoErrorKind::TooLarge { cells, .. }) => Ok(cells),
        Err(kind) => Err(IoError::new(name, kind)),
        Ok(hf) => Ok(hf.samples().len() as u64),
    }
}

fn decode_bytes(bytes: &[u8], format: Format, name: &Path, options: &ReadOptions) -> Result<Heightfield, IoErrorKind> {
    let limits = options.limits;
    match format {
        #[cfg(all(feature = "png", feature = "images"))]
        Format::Png8 | Format::Png16 if png_gray::colour_bits(bytes).is_some() => {
            pixels::decode(bytes, limits)?.to_heightfield(pixels::Gray::Strict(options.channel))
        }
        #[cfg(feature = "png")]
        Format::Png8 | Format::Png16 => png_gray::decode(bytes, limits),
        #[cfg(feature = "exr")]
        Format::Exr => openexr::decode(bytes, limits),
        #[cfg(feature = "geotiff")]
        Format::GeoTiff => geotiff::decode(bytes, &tiff_read(options, false)),
        #[cfg(feature = "images")]
        Format::Image => pixels::decode(bytes, limits)?.to_heightfield(pixels::Gray::Strict(options.channel)),
        Format::R16 | Format::R32 => {
            let shape = raw::Shape { sidecar: None, dims: options.raw_dims, sidecar_path: raw_sidecar_path(name) };
            raw::decode(bytes, raw_kind(format), &shape, limits)
        }
        Format::Asc => asc::decode(bytes, limits),
        Format::Hgt => hgt::decode(bytes, name, options.origin, limits),
        #[allow(unreachable_patterns, reason = "reached only when a codec feature is off")]
        _ => Err(disabled(format)),
    }
}

/// Writes a heightfield atomically, the format taken from the extension (`.png` → 16-bit).
///
/// Raw formats also write `<file>.json`, ASCII grids `<stem>.prj`; each file is replaced
/// atomically on its own (the data file first), not the pair together.
///
/// # Errors
/// [`IoErrorKind::UnknownFormat`] for an unknown extension, [`IoErrorKind::Io`] when the directory
/// is missing or not writable, [`IoErrorKind::OutOfRange`] / [`IoErrorKind::Unsupported`] when the
/// format cannot hold the field (`.hgt` above 32767 m or not 1201²/3601²).
pub fn write(path: impl AsRef<Path>, hf: &Heightfield) -> Result<(), IoError> {
    write_with(path, hf, &WriteOptions::default())
}

/// Writes a heightfield atomically with explicit options.
///
/// # Errors
/// As [`write()`].
pub fn write_with(path: impl AsRef<Path>, hf: &Heightfield, options: &WriteOptions) -> Result<(), IoError> {
    let path = path.as_ref();
    let at = |kind| IoError::new(path, kind);
    let format =
        options.format.or_else(|| Format::from_extension(path)).ok_or_else(|| at(IoErrorKind::UnknownFormat))?;
    match format {
        Format::R16 | Format::R32 => {
            let (bytes, meta) = raw::encode(hf, raw_kind(format), options.range).map_err(at)?;
            atomic::write(path, &bytes)?;
            // The sidecar holds the CRS too; no `.prj`, which would collide with an `.asc` of the
            // same stem, and GIS tools read no headerless raw without a header of their own.
            atomic::write(&raw_sidecar_path(path), meta.to_json().as_bytes())
        }
        Format::Asc => {
            atomic::write(path, &asc::encode(hf))?;
            atomic::write(&path.with_extension("prj"), crs::prj_text(hf.crs(), hf.grid().units()).as_bytes())
        }
        Format::Hgt => atomic::write(path, &hgt::encode(hf, Some(path)).map_err(at)?),
        _ => atomic::write(path, &encode_bytes(hf, format, options).map_err(at)?),
    }
}

/// Encodes a heightfield in memory, with [`WriteOptions::default`].
///
/// Only the main file: raw formats lose their `.json` sidecar (so an r16 read back is normalised
/// to `[0, 1]` on a plain grid) and ASCII grids their `.prj`; `.hgt` skips the check that the grid
/// sits on the tile its file name names.
///
/// # Errors
/// As [`write()`], with `<memory>` as the error's path.
pub fn write_bytes(hf: &Heightfield, format: Format) -> Result<Vec<u8>, IoError> {
    encode_bytes(hf, format, &WriteOptions::default()).map_err(|k| IoError::new("<memory>", k))
}

fn encode_bytes(hf: &Heightfield, format: Format, options: &WriteOptions) -> Result<Vec<u8>, IoErrorKind> {
    // Only some codecs read them; with those features off they are unused.
    let range = options.range;
    let _ = range;
    match format {
        #[cfg(feature = "png")]
        Format::Png8 => png_gray::encode(hf, 8, range),
        #[cfg(feature = "png")]
        Format::Png16 => png_gray::encode(hf, 16, range),
        #[cfg(feature = "exr")]
        Format::Exr => openexr::encode(hf, options.compress.unwrap_or(false)),
        #[cfg(feature = "geotiff")]
        Format::GeoTiff => geotiff::encode(
            hf,
            geotiff::TiffWrite {
                sample: options.tiff_sample,
                compress: options.compress.unwrap_or(true),
                pixel_is_area: options.pixel_is_area,
            },
        ),
        Format::R16 | Format::R32 => Ok(raw::encode(hf, raw_kind(format), range)?.0),
        Format::Asc => Ok(asc::encode(hf)),
        Format::Hgt => hgt::encode(hf, None),
        Format::Image => Err(IoErrorKind::Unsupported(
            "JPEG, BMP and WebP are read only (lossy or 8-bit): write .png, .tif or .exr".to_owned(),
        )),
        #[allow(unreachable_patterns, reason = "reached only when a codec feature is off")]
        _ => Err(disabled(format)),
    }
}

/// Writes a [`shaded_relief`] of `hf` as an RGB PNG, atomically.
///
/// # Errors
/// [`IoErrorKind::Io`] when the file cannot be written, [`IoErrorKind::Unsupported`] or
/// [`IoErrorKind::Encode`] if the image is too large for PNG.
#[cfg(feature = "png")]
pub fn write_preview_png(path: impl AsRef<Path>, hf: &Heightfield, options: &ShadeOptions) -> Result<(), IoError> {
    write_rgb_png(path, &shaded_relief(hf, options))
}

/// Writes an RGB image (a preview, possibly with overlays drawn on it) as an 8-bit PNG, atomically.
///
/// # Errors
/// [`IoErrorKind::Unsupported`] for images beyond PNG's size limit, or an I/O error.
#[cfg(feature = "png")]
pub fn write_rgb_png(path: impl AsRef<Path>, image: &RgbImage) -> Result<(), IoError> {
    let path = path.as_ref();
    let too_big = || IoError::new(path, IoErrorKind::Unsupported("image exceeds the PNG size limit".to_owned()));
    let w = u32::try_from(image.width).map_err(|_| too_big())?;
    let h = u32::try_from(image.height).map_err(|_| too_big())?;
    if image.pixels.len() != 3 * image.width * image.height {
        return Err(IoError::new(
            path,
            IoErrorKind::Encode(format!("{} bytes for a {w}x{h} RGB image", image.pixels.len())),
        ));
    }
    let bytes = png_gray::encode_rgb(w, h, &image.pixels).map_err(|k| IoError::new(path, k))?;
    atomic::write(path, &bytes)
}

/// Writes `bytes` to `path` atomically: a temporary file in the same directory, synced, then
/// renamed over the target, so readers see the old file or the whole new one, never a part.
///
/// # Errors
/// An I/O error naming `path`.
pub fn write_atomic(path: impl AsRef<Path>, bytes: &[u8]) -> Result<(), IoError> {
    atomic::write(path.as_ref(), bytes)
}

/// As [`write_atomic`], with the contents streamed by `fill` through a buffered writer, so that a
/// large output (a contour map's GeoJSON, say) is never held in memory whole.
///
/// ```
/// use std::io::Write as _;
///
/// let dir = tempfile::tempdir()?;
/// let path = dir.path().join("lines.txt");
/// relief_heightfield_io::write_atomic_with(&path, |w| (0..3).try_for_each(|k| writeln!(w, "line {k}")))?;
/// assert_eq!(std::fs::read_to_string(&path)?, "line 0\nline 1\nline 2\n");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// As [`write_atomic`], or the error `fill` returns; either way no file appears under `path`.
pub fn write_atomic_with(
    path: impl AsRef<Path>,
    fill: impl FnOnce(&mut dyn std::io::Write) -> std::io::Result<()>,
) -> Result<(), IoError> {
    atomic::write_with(path.as_ref(), fill)
}

/// A grayscale view of an image file, for label masks and probability maps: any PNG colour type
/// (gray, gray + alpha, RGB, RGBA, palette) as luma in [0, 1] with fully transparent pixels as
/// no-data, on a plain grid (origin 0, cell 1, row 0 south); any other format reads as a
/// heightfield ([`read_with`]).
///
/// # Errors
/// As [`read`].
pub fn read_gray_image(path: impl AsRef<Path>, options: &ReadOptions) -> Result<Heightfield, IoError> {
    let path = path.as_ref();
    #[allow(unused_variables, reason = "unused when no image codec is compiled in")]
    let at = |kind| IoError::new(path, kind);
    let bytes = read_input(path, options.limits)?;
    match options.format.or_else(|| Format::detect(path, &bytes)) {
        #[cfg(feature = "images")]
        Some(Format::Png8 | Format::Png16 | Format::Image) if options.channel.is_some() => {
            pixels::decode(&bytes, options.limits)
                .and_then(|p| p.to_heightfield(pixels::Gray::Lenient(options.channel)))
                .map_err(at)
        }
        #[cfg(feature = "png")]
        Some(Format::Png8 | Format::Png16) => png_gray::decode_luma(&bytes, options.limits).map_err(at),
        #[cfg(feature = "images")]
        Some(Format::Image) => pixels::decode(&bytes, options.limits)
            .and_then(|p| p.to_heightfield(pixels::Gray::Lenient(None)))
            .map_err(at),
        #[cfg(feature = "geotiff")]
        Some(Format::GeoTiff) => geotiff::decode(&bytes, &tiff_read(options, true)).map_err(at),
        _ => read_with(path, options),
    }
}

/// An image's colours: RGBA in [0, 1] per pixel, row-major with row 0 south, on a plain grid
/// (origin 0, cell 1), as [`read_color_image`] returns it.
#[derive(Debug, Clone, PartialEq)]
pub struct ColorImage {
    /// The pixel grid (origin 0, cell 1).
    pub grid: GridSpec,
    /// Red, green, blue and alpha of each pixel, south row first.
    pub pixels: Vec<[f32; 4]>,
}

/// The colours of an image file, for label masks whose regions are told apart by colour: any PNG
/// colour type (16-bit precision kept) and anything else the `image` crate decodes. Other formats
/// (and builds without the `images` feature) read as [`read_gray_image`] does, each value as a gray
/// pixel and no-data as transparent.
///
/// # Errors
/// As [`read`].
pub fn read_color_image(path: impl AsRef<Path>, options: &ReadOptions) -> Result<ColorImage, IoError> {
    let path = path.as_ref();
    #[cfg(feature = "images")]
    {
        let bytes = read_input(path, options.limits)?;
        if let Some(Format::Png8 | Format::Png16 | Format::Image) =
            options.format.or_else(|| Format::detect(path, &bytes))
        {
            let at = |kind| IoError::new(path, kind);
            let decoded = pixels::decode(&bytes, options.limits).map_err(at)?;
            let (grid, pixels) = decoded.into_south_up().map_err(at)?;
            return Ok(ColorImage { grid, pixels });
        }
    }
    let gray = read_gray_image(path, options)?;
    let pixels = gray.samples().iter().map(|&v| if v.is_nan() { [0.0; 4] } else { [v, v, v, 1.0] }).collect();
    Ok(ColorImage { grid: *gray.grid(), pixels })
}

/// How a `GeoTIFF` is read: limits, band, and what a colour image becomes (`lenient`: luma, for
/// masks; else gray-equal channels, for heightmaps).
#[cfg(feature = "geotiff")]
fn tiff_read(options: &ReadOptions, lenient: bool) -> geotiff::TiffRead {
    #[cfg(feature = "images")]
    let gray =
        Some(if lenient { pixels::Gray::Lenient(options.channel) } else { pixels::Gray::Strict(options.channel) });
    #[cfg(not(feature = "images"))]
    let gray = {
        let _ = lenient;
        None
    };
    geotiff::TiffRead { limits: options.limits, band: options.band, gray }
}

fn disabled(format: Format) -> IoErrorKind {
    IoErrorKind::FormatDisabled { format, feature: format.feature().unwrap_or("default") }
}

fn raw_kind(format: Format) -> RawKind {
    if format == Format::R32 { RawKind::R32 } else { RawKind::R16 }
}

/// The files [`write_with`] writes besides `path` in `format`: a raw file's JSON sidecar
/// (`terrain.r16` → `terrain.r16.json`), an ASCII grid's `.prj`.
pub fn companion_files(path: &Path, format: Format) -> Vec<PathBuf> {
    match format {
        Format::R16 | Format::R32 => vec![raw_sidecar_path(path)],
        Format::Asc => vec![path.with_extension("prj")],
        _ => Vec::new(),
    }
}

/// `terrain.r16` → `terrain.r16.json`.
fn raw_sidecar_path(path: &Path) -> PathBuf {
    let mut s: OsString = path.as_os_str().to_owned();
    s.push(".json");
    PathBuf::from(s)
}

/// The bytes of a regular file of at most `max` bytes: a directory, device or pipe is refused at
/// once (so `/dev/zero` or a FIFO cannot read forever), and an oversized file from its size,
/// before anything is read. Every file this crate reads (grids, sidecars, `.prj` files) comes
/// through here, and callers with their own inputs (JSON scenes, say) may use it too.
///
/// # Errors
/// [`CapError`]: the operating system's error, not a regular file, or too large.
pub fn read_capped(path: impl AsRef<Path>, max: u64) -> Result<Vec<u8>, CapError> {
    let file = std::fs::File::open(path.as_ref()).map_err(CapError::Io)?;
    let meta = file.metadata().map_err(CapError::Io)?;
    if !meta.is_file() {
        return Err(CapError::NotAFile);
    }
    if meta.len() > max {
        return Err(CapError::TooLarge { bytes: meta.len(), max });
    }
    let mut bytes = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
    // `take`: a file that grows while it is read still stops at the cap.
    file.take(max.saturating_add(1)).read_to_end(&mut bytes).map_err(CapError::Io)?;
    if bytes.len() as u64 > max {
        return Err(CapError::TooLarge { bytes: bytes.len() as u64, max });
    }
    Ok(bytes)
}

/// A heightfield file's bytes, refused from its size alone when no grid within `limits` could
/// need that many (32 bytes per cell, the widest ASCII value with its separator, plus 1 MiB of
/// header).
fn read_input(path: &Path, limits: Limits) -> Result<Vec<u8>, IoError> {
    let limit = limits.byte_budget(32, 1 << 20) as u64;
    read_capped(path, limit).map_err(|e| {
        let kind = match e {
            CapError::Io(e) => IoErrorKind::Io(e),
            CapError::NotAFile => IoErrorKind::NotAFile,
            CapError::TooLarge { bytes, .. } => IoErrorKind::FileTooLarge { bytes, limit, max_cells: limits.max_cells },
        };
        IoError::new(path, kind)
    })
}

/// A sidecar's text, `None` if it does not exist; at most `max` bytes are accepted.
fn read_small_text(path: &Path, max: u64) -> Result<Option<String>, IoError> {
    let at = |kind| IoError::new(path, kind);
    let bytes = match read_capped(path, max) {
        Ok(bytes) => bytes,
        Err(CapError::Io(e)) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(CapError::Io(e)) => return Err(at(IoErrorKind::Io(e))),
        Err(CapError::NotAFile) => return Err(at(IoErrorKind::NotAFile)),
        Err(CapError::TooLarge { .. }) => {
            return Err(at(IoErrorKind::InvalidMetadata(format!("sidecar is larger than {max} bytes"))));
        }
    };
    let text = String::from_utf8(bytes)
        .map_err(|e| at(IoErrorKind::Io(std::io::Error::new(std::io::ErrorKind::InvalidData, e))))?;
    Ok(Some(text))
}

/// Applies the origin, cell size, CRS and units overrides of [`ReadOptions`]; a CRS given
/// without units brings its own.
fn override_grid(hf: Heightfield, options: &ReadOptions) -> Result<Heightfield, IoErrorKind> {
    let (origin, cell) = (options.origin, options.cell_size);
    let crs = options.crs.clone().map(crs::complete);
    let units = options.units.or_else(|| crs.as_ref().and_then(Crs::units));
    if origin.is_none() && units.is_none() && cell.is_none() && crs.is_none() {
        return Ok(hf);
    }
    let g = *hf.grid();
    let grid = GridSpec::new(g.nx(), g.ny(), origin.unwrap_or(g.origin()), cell.unwrap_or(g.cell_size()))
        .and_then(|n| n.with_units(units.unwrap_or(g.units())))
        .map_err(|e| IoErrorKind::InvalidMetadata(e.to_string()))?;
    let kept = crs.or_else(|| hf.crs().cloned());
    Ok(Heightfield::from_samples(grid, hf.into_samples())?.with_crs(kept))
}

/// The crate README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExample;
