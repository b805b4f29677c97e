//! Single-band `GeoTIFF` via the `tiff` crate: read 8–64-bit integer and float samples (with the
//! band scale and offset GDAL keeps in its metadata tag applied), write f32 with
//! `ModelPixelScale`, `ModelTiepoint`, `GeoKeyDirectory` (`PixelIsPoint`) and `GDAL_NODATA`.

use std::io::{Cursor, Seek, Write};

use glam::DVec2;
use relief_heightfield::{Crs, GridSpec, Heightfield, Units};
use tiff::decoder::{Decoder, DecodingResult};
use tiff::encoder::colortype::{ColorType as EncodeColor, Gray32Float, GrayI16};
use tiff::encoder::compression::DeflateLevel;
use tiff::encoder::{Compression, Predictor, TiffEncoder, TiffKind, TiffKindBig, TiffKindStandard};
use tiff::tags::{PhotometricInterpretation, SampleFormat, Tag};
use tiff::{ColorType, TiffError};

use crate::error::decode_io;
use crate::meta::{flip_rows, north_up, plain_grid};
use crate::tiff_lzma;
use crate::{IoErrorKind, Limits, TiffSample};

/// `GeoKey` ids and values (`GeoTIFF` 1.0 §6.3).
const GT_MODEL_TYPE: u16 = 1024;
const GT_RASTER_TYPE: u16 = 1025;
const GEOGRAPHIC_TYPE: u16 = 2048;
const MODEL_PROJECTED: u16 = 1;
const MODEL_GEOGRAPHIC: u16 = 2;
const RASTER_PIXEL_IS_AREA: u16 = 1;
const RASTER_PIXEL_IS_POINT: u16 = 2;
/// The no-data code of Int16 output, as SRTM and GDAL use it.
const I16_NO_DATA: i16 = -32768;
const GT_CITATION: u16 = 1026;
const GEOG_ANGULAR_UNITS: u16 = 2054;
const PROJECTED_CS_TYPE: u16 = 3072;
const PROJ_LINEAR_UNITS: u16 = 3076;
const GCS_WGS_84: u16 = 4326;
/// "User-defined" in every `GeoKey` that holds an EPSG code.
const USER_DEFINED: u16 = 32767;
const ANGULAR_DEGREE: u16 = 9102;
/// `GeoAsciiParamsTag`, where ASCII `GeoKey` values live.
const GEO_ASCII_PARAMS: u16 = 34737;
/// TIFF compression code of LERC (Esri's limited-error raster compression).
const LERC: u16 = 34887;
/// `Predictor` value of the floating-point predictor (TIFF Technical Note 3).
const FLOATING_POINT_PREDICTOR: u16 = 3;
/// GDAL's private tag holding band metadata as XML (scale, offset, statistics).
const GDAL_METADATA: u16 = 42112;

fn tiff_error(e: TiffError, found: usize) -> IoErrorKind {
    match e {
        TiffError::IoError(e) => decode_io(&e, found),
        TiffError::UnsupportedError(u) => IoErrorKind::Unsupported(format!("TIFF {u}")),
        TiffError::LimitsExceeded => {
            IoErrorKind::Decode("the TIFF decoder's memory limit was exceeded (raise Limits::max_cells)".to_owned())
        }
        other => IoErrorKind::Decode(other.to_string()),
    }
}

/// The geo tags read from the first image directory.
#[derive(Default)]
struct GeoTags {
    scale: Option<Vec<f64>>,
    tiepoint: Option<Vec<f64>>,
    transform: Option<Vec<f64>>,
    keys: Option<Vec<u16>>,
    nodata: Option<String>,
    /// GDAL's metadata XML (tag 42112), where band scale and offset live.
    metadata: Option<String>,
}

impl GeoTags {
    fn read<R: std::io::Read + Seek>(dec: &mut Decoder<R>, found: usize) -> Result<Self, IoErrorKind> {
        let err = |e| tiff_error(e, found);
        let doubles = |dec: &mut Decoder<R>, tag| -> Result<Option<Vec<f64>>, IoErrorKind> {
            dec.find_tag(tag).map_err(err)?.map(|v| v.into_f64_vec().map_err(err)).transpose()
        };
        Ok(Self {
            scale: doubles(dec, Tag::ModelPixelScaleTag)?,
            tiepoint: doubles(dec, Tag::ModelTiepointTag)?,
            transform: doubles(dec, Tag::ModelTransformationTag)?,
            keys: dec
                .find_tag(Tag::GeoKeyDirectoryTag)
                .map_err(err)?
                .map(|v| v.into_u16_vec().map_err(err))
                .transpose()?,
            nodata: dec.find_tag(Tag::GdalNodata).map_err(err)?.map(|v| v.into_string().map_err(err)).transpose()?,
            metadata: dec
                .find_tag(Tag::Unknown(GDAL_METADATA))
                .map_err(err)?
                .map(|v| v.into_string().map_err(err))
                .transpose()?,
        })
    }

    /// The band's `(scale, offset)` from GDAL's metadata (elevation = code × scale + offset),
    /// `(1, 0)` when it gives none.
    fn scale_offset(&self) -> Result<(f64, f64), IoErrorKind> {
        let Some(xml) = &self.metadata else { return Ok((1.0, 0.0)) };
        let item = |role: &str| -> Result<Option<f64>, IoErrorKind> {
            let Some(at) = xml.find(&format!("role=\"{role}\"")) else { return Ok(None) };
            let rest = &xml[at..];
            let text = rest.find('>').and_then(|a| rest[a + 1..].find('<').map(|b| &rest[a + 1..a + 1 + b]));
            let value = text.map(str::trim).unwrap_or_default();
            match value.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(Some(v)),
                _ => {
                    Err(IoErrorKind::InvalidMetadata(format!("GDAL metadata {role} {value:?} is not a finite number")))
                }
            }
        };
        let (scale, offset) = (item("scale")?.unwrap_or(1.0), item("offset")?.unwrap_or(0.0));
        if scale == 0.0 {
            return Err(IoErrorKind::InvalidMetadata("GDAL metadata scale is 0".to_owned()));
        }
        Ok((scale, offset))
    }

    /// The inline value of `GeoKey` `id` (keys stored in other tags are not needed here).
    fn key(&self, id: u16) -> Option<u16> {
        let keys = self.keys.as_deref()?;
        let n = usize::from(*keys.get(3)?);
        keys.get(4..4 + 4 * n)?.chunks_exact(4).find(|k| k[0] == id && k[1] == 0).map(|k| k[3])
    }

    fn nodata(&self) -> Result<Option<f64>, IoErrorKind> {
        let Some(s) = &self.nodata else { return Ok(None) };
        let s = s.trim_matches(|c: char| c == '\0' || c.is_whitespace());
        s.parse::<f64>()
            .map(Some)
            .map_err(|_| IoErrorKind::InvalidMetadata(format!("GDAL_NODATA {s:?} is not a number")))
    }

    fn grid(&self, nx: usize, ny: usize) -> Result<GridSpec, IoErrorKind> {
        let bad = |m: String| IoErrorKind::InvalidMetadata(m);
        // (sx, sy, raster i, raster j, model x, model y) of one tiepoint.
        let placement = match (&self.scale, &self.tiepoint, &self.transform) {
            (Some(s), Some(t), _) => {
                if s.len() < 2 || t.len() < 6 {
                    return Err(bad(format!("ModelPixelScale has {} values and ModelTiepoint {}", s.len(), t.len())));
                }
                (s[0], s[1], t[0], t[1], t[3], t[4])
            }
            (_, _, Some(m)) if m.len() == 16 => {
                if m[1] != 0.0 || m[4] != 0.0 {
                    return Err(IoErrorKind::Unsupported("rotated or sheared ModelTransformation".to_owned()));
                }
                (m[0], -m[5], 0.0, 0.0, m[3], m[7])
            }
            (_, _, Some(m)) => return Err(bad(format!("ModelTransformation has {} values, not 16", m.len()))),
            _ => return plain_grid(nx, ny),
        };
        let (sx, sy, ti, tj, tx, ty) = placement;
        if !(sx > 0.0 && sy > 0.0 && sx.is_finite() && sy.is_finite()) {
            return Err(IoErrorKind::Unsupported(format!("pixel scale ({sx}, {sy}): only north-up rasters are read")));
        }
        // PixelIsArea (the default) puts raster (0, 0) at the corner of the first pixel, whose
        // centre — our sample — is half a pixel in; PixelIsPoint puts it on the sample itself.
        let half = if self.key(GT_RASTER_TYPE) == Some(RASTER_PIXEL_IS_POINT) { 0.0 } else { 0.5 };
        // Our origin is the south-west sample, raster (half, ny − 1 + half); subtracting the
        // tiepoint's raster position first keeps a tiepoint placed on that sample exact.
        let origin = DVec2::new(tx + (half - ti) * sx, ty - ((ny - 1) as f64 + half - tj) * sy);
        GridSpec::new(nx, ny, origin, DVec2::new(sx, sy))
            .and_then(|g| g.with_units(self.units()))
            .map_err(|e| bad(e.to_string()))
    }

    /// The EPSG-coded CRS the geo keys name (`GeographicTypeGeoKey` for a geographic model,
    /// `ProjectedCSTypeGeoKey` otherwise), `None` when user-defined or absent.
    fn crs(&self) -> Option<Crs> {
        let code = if self.key(GT_MODEL_TYPE) == Some(MODEL_GEOGRAPHIC) {
            self.key(GEOGRAPHIC_TYPE)
        } else {
            self.key(PROJECTED_CS_TYPE)
        }?;
        crate::crs::from_epsg(u32::from(code)).ok()
    }

    /// Degrees for a geographic model; for a projected one the linear units key, else the units of
    /// the CRS, else metres.
    fn units(&self) -> Units {
        if self.key(GT_MODEL_TYPE) == Some(MODEL_GEOGRAPHIC) {
            return Units::Degrees;
        }
        match self.key(PROJ_LINEAR_UNITS) {
            Some(code) if linear_units(code).is_some() => linear_units(code).unwrap_or_default(),
            _ => self.crs().and_then(|c| c.units()).unwrap_or(Units::Metres),
        }
    }
}

/// The EPSG unit-of-measure code of a planar unit (metre 9001, foot 9002, US survey foot 9003).
fn linear_unit_code(units: Units) -> Option<u16> {
    match units {
        Units::Metres => Some(9001),
        Units::Feet => Some(9002),
        Units::UsSurveyFeet => Some(9003),
        Units::Degrees => None,
    }
}

fn linear_units(code: u16) -> Option<Units> {
    [Units::Metres, Units::Feet, Units::UsSurveyFeet].into_iter().find(|&u| linear_unit_code(u) == Some(code))
}

/// The `GeoKeyDirectory` (and the `GeoAsciiParams` it points into, if any) for a grid in `units`
/// labelled `crs`: its EPSG code when it has one; a user-defined CRS named in `GTCitationGeoKey`
/// otherwise; WGS 84 for an unlabelled geographic grid.
fn geo_keys(units: Units, crs: Option<&Crs>, pixel_is_area: bool) -> (Vec<u16>, Option<String>) {
    let crs = crs.cloned().map(Crs::identified);
    let crs = crs.as_ref();
    let geographic = units == Units::Degrees;
    // A geographic CRS on a grid relabelled to linear units (`--units`) is no projected CRS code:
    // it goes as a user-defined one, named, as any CRS without a code.
    let code = crs
        .and_then(Crs::epsg)
        .and_then(|c| u16::try_from(c).ok())
        .filter(|&c| c != USER_DEFINED)
        .filter(|_| geographic || crs.and_then(Crs::units) != Some(Units::Degrees));
    let model = if geographic { MODEL_GEOGRAPHIC } else { MODEL_PROJECTED };
    let raster = if pixel_is_area { RASTER_PIXEL_IS_AREA } else { RASTER_PIXEL_IS_POINT };
    let mut entries: Vec<[u16; 4]> = vec![[GT_MODEL_TYPE, 0, 1, model], [GT_RASTER_TYPE, 0, 1, raster]];
    let citation = crs.filter(|_| code.is_none()).map(|c| format!("{}|", c.name()));
    if let Some(text) = &citation {
        let len = u16::try_from(text.len()).unwrap_or(u16::MAX);
        entries.push([GT_CITATION, GEO_ASCII_PARAMS, len, 0]);
    }
    if geographic {
        let gcs = match (code, crs) {
            (Some(c), _) => c,
            (None, None) => GCS_WGS_84,
            (None, Some(_)) => USER_DEFINED,
        };
        entries.push([GEOGRAPHIC_TYPE, 0, 1, gcs]);
        entries.push([GEOG_ANGULAR_UNITS, 0, 1, ANGULAR_DEGREE]);
    } else {
        if let Some(c) = code.or(crs.map(|_| USER_DEFINED)) {
            entries.push([PROJECTED_CS_TYPE, 0, 1, c]);
        }
        if let Some(u) = linear_unit_code(units) {
            entries.push([PROJ_LINEAR_UNITS, 0, 1, u]);
        }
    }
    let n = u16::try_from(entries.len()).unwrap_or(0);
    let keys = [1, 1, 0, n].into_iter().chain(entries.into_iter().flatten()).collect();
    (keys, citation)
}

/// Band `b` (1-based) of samples interleaved `n` to a pixel.
fn one_band(all: DecodingResult, n: usize, b: usize) -> DecodingResult {
    fn pick<T>(v: Vec<T>, n: usize, b: usize) -> Vec<T> {
        v.into_iter().skip(b - 1).step_by(n).collect()
    }
    match all {
        DecodingResult::U8(v) => DecodingResult::U8(pick(v, n, b)),
        DecodingResult::U16(v) => DecodingResult::U16(pick(v, n, b)),
        DecodingResult::U32(v) => DecodingResult::U32(pick(v, n, b)),
        DecodingResult::U64(v) => DecodingResult::U64(pick(v, n, b)),
        DecodingResult::I8(v) => DecodingResult::I8(pick(v, n, b)),
        DecodingResult::I16(v) => DecodingResult::I16(pick(v, n, b)),
        DecodingResult::I32(v) => DecodingResult::I32(pick(v, n, b)),
        DecodingResult::I64(v) => DecodingResult::I64(pick(v, n, b)),
        DecodingResult::F16(v) => DecodingResult::F16(pick(v, n, b)),
        DecodingResult::F32(v) => DecodingResult::F32(pick(v, n, b)),
        DecodingResult::F64(v) => DecodingResult::F64(pick(v, n, b)),
    }
}

/// An RGB(A), palette or gray + alpha TIFF read as one value per pixel through the `image` crate
/// (gray-equal channels, a named channel, or luma for masks), placed by its geo tags.
fn colour_image<R: std::io::Read + Seek>(
    bytes: &[u8],
    dec: &mut Decoder<R>,
    read: &TiffRead,
    colortype: ColorType,
    spp: u16,
) -> Result<(Heightfield, bool), IoErrorKind> {
    let refuse = || {
        IoErrorKind::Unsupported(format!(
            "TIFF of {colortype:?} with {spp} samples per pixel: pick the band that holds elevations (--band N)"
        ))
    };
    #[cfg(feature = "images")]
    {
        let Some(gray) = read.gray else { return Err(refuse()) };
        let hf = crate::pixels::decode(bytes, read.limits).map_err(|_| refuse())?.to_heightfield(gray)?;
        let geo = GeoTags::read(dec, bytes.len())?;
        let placed = geo.scale.is_some() || geo.tiepoint.is_some() || geo.transform.is_some();
        let grid = geo.grid(hf.nx(), hf.ny())?;
        Ok((Heightfield::from_samples(grid, hf.into_samples())?.with_crs(geo.crs()), placed))
    }
    #[cfg(not(feature = "images"))]
    {
        let _ = (bytes, dec, read);
        Err(refuse())
    }
}

/// Converts decoded codes to f32 elevations (`code × scale + offset`, in f64), mapping the no-data
/// code to NaN.
fn to_f32<T: Copy>(v: Vec<T>, nodata: Option<f64>, (scale, offset): (f64, f64), f: impl Fn(T) -> f64) -> Vec<f32> {
    // Without a scale the codes pass through untouched (keeping −0.0, which `x · 1 + 0` would not).
    let identity = scale == 1.0 && offset == 0.0;
    let elevation = |x: f64| if identity { x as f32 } else { (x * scale + offset) as f32 };
    match nodata {
        None => v.into_iter().map(|x| elevation(f(x))).collect(),
        Some(nd) => v
            .into_iter()
            .map(|x| {
                let x = f(x);
                // Float rasters often carry a nodata string that only matches after rounding to f32.
                if x == nd || x as f32 == nd as f32 { f32::NAN } else { elevation(x) }
            })
            .collect(),
    }
}

/// How to read a `GeoTIFF` (from [`crate::ReadOptions`]).
pub(crate) struct TiffRead {
    pub limits: Limits,
    /// The band (1-based) of a multi-band file.
    pub band: Option<u16>,
    /// What an RGB(A) or palette image becomes; `None` refuses it (no `images` feature).
    #[cfg(feature = "images")]
    pub gray: Option<crate::pixels::Gray>,
    #[cfg(not(feature = "images"))]
    pub gray: Option<()>,
}

pub(crate) fn decode(bytes: &[u8], read: &TiffRead) -> Result<Heightfield, IoErrorKind> {
    decode_placed(bytes, read).map(|(hf, _)| hf)
}

/// As [`decode`], also saying whether the file placed itself (geo tags): without them its grid
/// is in pixels from the origin, and a world file beside it may place it.
pub(crate) fn decode_placed(bytes: &[u8], read: &TiffRead) -> Result<(Heightfield, bool), IoErrorKind> {
    let (found, limits) = (bytes.len(), read.limits);
    let err = |e| tiff_error(e, found);
    let mut tiff_limits = tiff::decoder::Limits::default();
    // f64 is the widest sample type we convert.
    tiff_limits.decoding_buffer_size = limits.byte_budget(8, 0);
    let mut dec = Decoder::new(Cursor::new(bytes)).map_err(err)?.with_limits(tiff_limits);
    let (w, h) = dec.dimensions().map_err(err)?;
    let cells = limits.check(u64::from(w), u64::from(h))?;
    let spp = dec.find_tag_unsigned::<u16>(Tag::SamplesPerPixel).map_err(err)?.unwrap_or(1);
    let colortype = dec.colortype().map_err(err)?;
    let band = match (spp, read.band) {
        (1, None | Some(1)) if matches!(colortype, ColorType::Gray(_)) => None,
        (n, Some(b)) if b == 0 || b > n => {
            return Err(IoErrorKind::InvalidMetadata(format!("band {b}: the TIFF has bands 1 to {n}")));
        }
        (n, Some(b)) if n > 1 => Some((usize::from(n), usize::from(b))),
        _ => return colour_image(bytes, &mut dec, read, colortype, spp),
    };
    if band.is_some() && dec.find_tag_unsigned::<u16>(Tag::PlanarConfiguration).map_err(err)? == Some(2) {
        return Err(IoErrorKind::Unsupported(
            "multi-band TIFF with separate planes (PlanarConfiguration 2)".to_owned(),
        ));
    }
    let compression = dec.find_tag_unsigned::<u16>(Tag::Compression).map_err(err)?.unwrap_or(1);
    if compression == LERC {
        return Err(IoErrorKind::Unsupported(
            "LERC-compressed TIFF (GDAL's COMPRESS=LERC): re-save it with `gdal_translate -co COMPRESS=DEFLATE`"
                .to_owned(),
        ));
    }
    let bits = match dec.find_tag(Tag::BitsPerSample).map_err(err)? {
        Some(v) => v.into_u16_vec().map_err(err)?.first().copied().unwrap_or(1),
        None => 1,
    };
    if compression == 1 {
        // Uncompressed: the file must hold every sample before we allocate for them.
        let needed = (cells as u64).saturating_mul(u64::from(bits) * u64::from(spp)) / 8;
        if (found as u64) < needed {
            return Err(IoErrorKind::Truncated { expected_bytes: Some(needed), found_bytes: found as u64 });
        }
    }
    let geo = GeoTags::read(&mut dec, found)?;
    let placed = geo.scale.is_some() || geo.tiepoint.is_some() || geo.transform.is_some();
    let grid = geo.grid(w as usize, h as usize)?;
    let nd = geo.nodata()?;
    // Stored codes become elevations; no-data is matched on the codes, as GDAL does.
    let so = geo.scale_offset()?;
    let decoded = if compression == tiff_lzma::LZMA {
        if band.is_some() {
            return Err(IoErrorKind::Unsupported("multi-band LZMA TIFF".to_owned()));
        }
        DecodingResult::F64(tiff_lzma::read_samples(&mut dec, bytes, err)?)
    } else {
        dec.read_image().map_err(err)?
    };
    let decoded = match band {
        Some((n, b)) => one_band(decoded, n, b),
        None => decoded,
    };
    let mut samples = match decoded {
        DecodingResult::F32(v) => to_f32(v, nd, so, f64::from),
        DecodingResult::F64(v) => to_f32(v, nd, so, |x| x),
        DecodingResult::F16(v) => to_f32(v, nd, so, |x| f64::from(x.to_f32())),
        DecodingResult::U8(v) => to_f32(v, nd, so, f64::from),
        DecodingResult::I8(v) => to_f32(v, nd, so, f64::from),
        DecodingResult::U16(v) => to_f32(v, nd, so, f64::from),
        DecodingResult::I16(v) => to_f32(v, nd, so, f64::from),
        DecodingResult::U32(v) => to_f32(v, nd, so, f64::from),
        DecodingResult::I32(v) => to_f32(v, nd, so, f64::from),
        DecodingResult::U64(v) => to_f32(v, nd, so, |x| x as f64),
        DecodingResult::I64(v) => to_f32(v, nd, so, |x| x as f64),
    };
    if samples.len() != cells {
        return Err(IoErrorKind::HeaderMismatch(format!("TIFF is {w}x{h} but decoded to {} samples", samples.len())));
    }
    flip_rows(&mut samples, w as usize);
    Ok((Heightfield::from_samples(grid, samples)?.with_crs(geo.crs()), placed))
}

/// f32 samples already passed through the floating-point predictor (TIFF Technical Note 3):
/// 32-bit IEEE samples as far as the file says, handed to the encoder as the `u32`s whose native
/// bytes are the predicted bytes, so that it writes them unchanged.
struct PredictedF32;

impl EncodeColor for PredictedF32 {
    type Inner = u32;
    const TIFF_VALUE: PhotometricInterpretation = PhotometricInterpretation::BlackIsZero;
    const BITS_PER_SAMPLE: &'static [u16] = &[32];
    const SAMPLE_FORMAT: &'static [SampleFormat] = &[SampleFormat::IEEEFP];

    fn horizontal_predict(row: &[u32], result: &mut Vec<u32>) {
        // The encoder runs with `Predictor::None`; the prediction is done in `float_predicted`.
        result.extend_from_slice(row);
    }
}

/// TIFF predictor 3 on north-up rows of f32 samples, as libtiff and GDAL apply it: each row's
/// bytes are regrouped into planes from the most significant byte to the least (so the slowly
/// varying sign and exponent bytes sit together), then each byte is replaced by its difference
/// from the byte before it. Elevation rows then deflate to about half of their plain size.
fn float_predicted(rows: &[f32], width: usize) -> Vec<u32> {
    let mut out = Vec::with_capacity(rows.len());
    let mut planes = vec![0u8; 4 * width];
    for row in rows.chunks_exact(width) {
        for (i, v) in row.iter().enumerate() {
            for (b, byte) in v.to_be_bytes().into_iter().enumerate() {
                planes[b * width + i] = byte;
            }
        }
        for k in (1..planes.len()).rev() {
            planes[k] = planes[k].wrapping_sub(planes[k - 1]);
        }
        out.extend(planes.chunks_exact(4).map(|c| u32::from_ne_bytes([c[0], c[1], c[2], c[3]])));
    }
    out
}

fn write_image<W: Write + Seek, K: TiffKind>(
    mut enc: TiffEncoder<W, K>,
    hf: &Heightfield,
    settings: TiffWrite,
) -> Result<(), TiffError> {
    let (w, h) = (hf.nx() as u32, hf.ny() as u32);
    match (settings.sample, settings.compress) {
        (TiffSample::F32, true) => {
            let mut image = enc.new_image::<PredictedF32>(w, h)?;
            // The encoder wrote `Predictor` 1 (none); the samples it is given are predicted.
            image.encoder().write_tag(Tag::Predictor, FLOATING_POINT_PREDICTOR)?;
            write_geo_tags(image.encoder(), hf, settings)?;
            image.write_data(&float_predicted(&north_up(hf, |_, _, v| v), w as usize))
        }
        (TiffSample::F32, false) => {
            let mut image = enc.new_image::<Gray32Float>(w, h)?;
            write_geo_tags(image.encoder(), hf, settings)?;
            image.write_data(&north_up(hf, |_, _, v| v))
        }
        (TiffSample::I16, compress) => {
            let predictor = if compress { Predictor::Horizontal } else { Predictor::None };
            let mut enc = enc.with_predictor(predictor);
            let mut image = enc.new_image::<GrayI16>(w, h)?;
            write_geo_tags(image.encoder(), hf, settings)?;
            // Range checked in `encode`; NaN becomes the no-data code.
            image.write_data(&north_up(hf, |_, _, v| if v.is_nan() { I16_NO_DATA } else { v.round() as i16 }))
        }
    }
}

fn write_geo_tags<W: Write + Seek, K: TiffKind>(
    dir: &mut tiff::encoder::DirectoryEncoder<'_, W, K>,
    hf: &Heightfield,
    settings: TiffWrite,
) -> Result<(), TiffError> {
    let g = hf.grid();
    let (s, o) = (g.cell_size(), g.origin());
    dir.write_tag(Tag::ModelPixelScaleTag, &[s.x, s.y, 0.0][..])?;
    // The tiepoint sits on the south-west sample so that reading it back gives our origin exactly:
    // the sample itself for PixelIsPoint, the outer corner of its cell (raster position
    // (0, ny)) for PixelIsArea.
    let tie = if settings.pixel_is_area {
        [0.0, hf.ny() as f64, 0.0, o.x - 0.5 * s.x, o.y - 0.5 * s.y, 0.0]
    } else {
        [0.0, (hf.ny() - 1) as f64, 0.0, o.x, o.y, 0.0]
    };
    dir.write_tag(Tag::ModelTiepointTag, &tie[..])?;
    let (keys, ascii) = geo_keys(g.units(), hf.crs(), settings.pixel_is_area);
    dir.write_tag(Tag::GeoKeyDirectoryTag, &keys[..])?;
    if let Some(text) = ascii {
        dir.write_tag(Tag::Unknown(GEO_ASCII_PARAMS), text.as_str())?;
    }
    if hf.has_no_data() {
        let nodata = match settings.sample {
            TiffSample::F32 => "nan".to_owned(),
            TiffSample::I16 => I16_NO_DATA.to_string(),
        };
        dir.write_tag(Tag::GdalNodata, nodata.as_str())?;
    }
    Ok(())
}

/// How a `GeoTIFF` is written (from [`crate::WriteOptions`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct TiffWrite {
    pub sample: TiffSample,
    /// DEFLATE, after the floating-point predictor (f32, GDAL's `PREDICTOR=3`) or the horizontal
    /// one (integers, `PREDICTOR=2`).
    pub compress: bool,
    pub pixel_is_area: bool,
}

/// Encodes `hf` as `settings` say.
pub(crate) fn encode(hf: &Heightfield, settings: TiffWrite) -> Result<Vec<u8>, IoErrorKind> {
    let (nx, ny) = (hf.nx(), hf.ny());
    if u32::try_from(nx).is_err() || u32::try_from(ny).is_err() {
        return Err(IoErrorKind::Unsupported(format!("{nx}x{ny} exceeds the TIFF size limit")));
    }
    if settings.sample == TiffSample::I16 {
        check_i16(hf)?;
    }
    let enc_err = |e: TiffError| IoErrorKind::Encode(e.to_string());
    let compression =
        if settings.compress { Compression::Deflate(DeflateLevel::Balanced) } else { Compression::Uncompressed };
    let mut out = Cursor::new(Vec::new());
    // Classic TIFF addresses 4 GiB; leave room for the directory and switch to BigTIFF beyond.
    if (nx * ny) as u64 * 4 < u64::from(u32::MAX) - (1 << 20) {
        let enc = TiffEncoder::<_, TiffKindStandard>::new_generic(&mut out).map_err(enc_err)?;
        write_image(enc.with_compression(compression), hf, settings)
    } else {
        let enc = TiffEncoder::<_, TiffKindBig>::new_generic(&mut out).map_err(enc_err)?;
        write_image(enc.with_compression(compression), hf, settings)
    }
    .map_err(enc_err)?;
    Ok(out.into_inner())
}

/// Every valid sample must round into Int16 without meeting the no-data code.
fn check_i16(hf: &Heightfield) -> Result<(), IoErrorKind> {
    let (min, max) = (f64::from(I16_NO_DATA) + 1.0, f64::from(i16::MAX));
    for (k, &v) in hf.samples().iter().enumerate() {
        let r = f64::from(v).round();
        if !v.is_nan() && !(min..=max).contains(&r) {
            let (i, j) = hf.grid().coords(k);
            return Err(IoErrorKind::OutOfRange { i, j, value: v, min, max });
        }
    }
    Ok(())
}
