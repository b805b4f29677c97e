//! `OpenEXR`: one f32 channel `Y`, north row first, NaN for no-data; the grid geometry in one
//! custom text attribute `relief.grid`: `"<origin x> <origin y> <cell x> <cell y> <units>"`, the
//! numbers written in Rust's shortest round-trip form so they read back exactly, then, when the
//! field has a CRS, a second line holding it as JSON.
//!
//! One attribute, not five: `exr` keeps custom attributes in a `HashMap`, whose iteration order —
//! and so the header's bytes — would change from run to run with several. Files from earlier
//! versions, with the geometry in `relief.origin_x`, `relief.origin_y`, `relief.cell_size_x`,
//! `relief.cell_size_y` (doubles) and `relief.units` (text), still read.

use std::io::Cursor;

use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Compression, Encoding, FlatSamples, Image, Layer, LayerAttributes,
    MetaData, ReadChannels, ReadLayers, SampleType, SmallVec, Text, WritableImage, read,
};
use glam::DVec2;
use relief_heightfield::{Crs, GridSpec, Heightfield, Units};

use crate::error::decode_io;
use crate::meta::{flip_rows, north_up, plain_grid};
use crate::{IoErrorKind, Limits};

const ORIGIN_X: &str = "relief.origin_x";
const ORIGIN_Y: &str = "relief.origin_y";
const CELL_X: &str = "relief.cell_size_x";
const CELL_Y: &str = "relief.cell_size_y";
const UNITS: &str = "relief.units";
const GRID: &str = "relief.grid";
/// Channel names accepted, in order of preference, when a file has more than one.
const PREFERRED: [&str; 4] = ["Y", "height", "Z", "R"];

fn exr_error(e: exr::error::Error, found: usize) -> IoErrorKind {
    match e {
        exr::error::Error::Io(e) => decode_io(&e, found),
        // exr turns `UnexpectedEof` into this message.
        exr::error::Error::Invalid(m) if m.contains("missing bytes") => {
            IoErrorKind::Truncated { expected_bytes: None, found_bytes: found as u64 }
        }
        exr::error::Error::NotSupported(m) => IoErrorKind::Unsupported(format!("OpenEXR {m}")),
        other => IoErrorKind::Decode(other.to_string()),
    }
}

fn sample_bytes(t: SampleType) -> u64 {
    match t {
        SampleType::F16 => 2,
        SampleType::F32 | SampleType::U32 => 4,
    }
}

pub(crate) fn decode(bytes: &[u8], limits: Limits) -> Result<Heightfield, IoErrorKind> {
    let found = bytes.len();
    let meta = MetaData::read_from_buffered(Cursor::new(bytes), false).map_err(|e| exr_error(e, found))?;
    // Check every layer's data window before a single pixel buffer is allocated.
    for header in &meta.headers {
        let size = header.layer_size;
        let cells = limits.check(size.0 as u64, size.1 as u64)?;
        // Every channel is decoded before the height channel is picked: the samples of all of
        // them count against the limit.
        let channels = header.channels.list.len().max(1) as u64;
        limits.check((size.0 as u64).saturating_mul(channels), size.1 as u64)?;
        if header.compression == Compression::Uncompressed {
            let per_cell: u64 = header.channels.list.iter().map(|c| sample_bytes(c.sample_type)).sum();
            let needed = (cells as u64).saturating_mul(per_cell);
            if (found as u64) < needed {
                return Err(IoErrorKind::Truncated { expected_bytes: Some(needed), found_bytes: found as u64 });
            }
        }
    }
    let Some(header) = meta.headers.iter().find(|h| !h.deep) else {
        return Err(IoErrorKind::Unsupported("OpenEXR file holds only deep data".to_owned()));
    };
    let names: Vec<String> = header.channels.list.iter().map(|c| c.name.to_string()).collect();
    let pick = if names.len() == 1 {
        Some(names[0].clone())
    } else {
        PREFERRED.iter().find(|p| names.iter().any(|n| n == *p)).map(|p| (*p).to_owned())
    };
    let Some(pick) = pick else {
        return Err(IoErrorKind::Unsupported(format!(
            "OpenEXR channels [{}]: expected one channel, or one named {}",
            names.join(", "),
            PREFERRED.join(", ")
        )));
    };

    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| exr_error(e, found))?;
    let mut layer = image.layer_data;
    let (nx, ny) = (layer.size.0, layer.size.1);
    let Some(index) = layer.channel_data.list.iter().position(|c| c.name.to_string() == pick) else {
        return Err(IoErrorKind::HeaderMismatch(format!("channel {pick} is missing from the decoded layer")));
    };
    let channel = layer.channel_data.list.swap_remove(index);
    if channel.sampling != exr::math::Vec2(1, 1) {
        return Err(IoErrorKind::Unsupported(format!("OpenEXR channel {pick} is subsampled")));
    }
    let mut samples: Vec<f32> = match channel.sample_data {
        FlatSamples::F32(v) => v,
        FlatSamples::F16(v) => v.iter().map(|h| h.to_f32()).collect(),
        FlatSamples::U32(v) => v.iter().map(|&u| u as f32).collect(),
    };
    if samples.len() != nx * ny {
        return Err(IoErrorKind::HeaderMismatch(format!(
            "layer is {nx}x{ny} but channel {pick} holds {} samples",
            samples.len()
        )));
    }
    flip_rows(&mut samples, nx);
    let (grid, crs) = geometry(&layer.attributes, nx, ny)?;
    Ok(Heightfield::from_samples(grid, samples)?.with_crs(crs))
}

/// The grid and CRS the layer's attributes describe.
fn geometry(attrs: &LayerAttributes, nx: usize, ny: usize) -> Result<(GridSpec, Option<Crs>), IoErrorKind> {
    match attrs.other.get(&Text::from(GRID)) {
        None => {}
        Some(AttributeValue::Text(t)) => return parse_grid(&t.to_string(), nx, ny),
        Some(other) => return Err(IoErrorKind::InvalidMetadata(format!("attribute {GRID} is {other:?}, not text"))),
    }
    let get = |name: &str| -> Result<Option<f64>, IoErrorKind> {
        match attrs.other.get(&Text::from(name)) {
            None => Ok(None),
            Some(AttributeValue::F64(v)) => Ok(Some(*v)),
            Some(AttributeValue::F32(v)) => Ok(Some(f64::from(*v))),
            Some(other) => Err(IoErrorKind::InvalidMetadata(format!("attribute {name} is {other:?}, not a number"))),
        }
    };
    let values = [get(ORIGIN_X)?, get(ORIGIN_Y)?, get(CELL_X)?, get(CELL_Y)?];
    let units = match attrs.other.get(&Text::from(UNITS)) {
        None => Units::Metres,
        Some(AttributeValue::Text(t)) if t.eq("metres") => Units::Metres,
        Some(AttributeValue::Text(t)) if t.eq("degrees") => Units::Degrees,
        Some(other) => {
            return Err(IoErrorKind::InvalidMetadata(format!(
                "attribute {UNITS} is {other:?}, expected \"metres\" or \"degrees\""
            )));
        }
    };
    match values {
        [None, None, None, None] => Ok((plain_grid(nx, ny)?, None)),
        [Some(ox), Some(oy), Some(cx), Some(cy)] => GridSpec::new(nx, ny, DVec2::new(ox, oy), DVec2::new(cx, cy))
            .and_then(|g| g.with_units(units))
            .map(|g| (g, None))
            .map_err(|e| IoErrorKind::InvalidMetadata(e.to_string())),
        _ => Err(IoErrorKind::InvalidMetadata(format!(
            "the relief geometry attributes must all be present: {ORIGIN_X}, {ORIGIN_Y}, {CELL_X}, {CELL_Y}"
        ))),
    }
}

/// Reads `"<origin x> <origin y> <cell x> <cell y> <units>"`, optionally followed by a line with
/// the CRS as JSON (`{"epsg": …, "wkt": …}`).
fn parse_grid(text: &str, nx: usize, ny: usize) -> Result<(GridSpec, Option<Crs>), IoErrorKind> {
    let bad = || {
        IoErrorKind::InvalidMetadata(format!(
            "attribute {GRID} is {text:?}; expected \"<origin x> <origin y> <cell x> <cell y> <units>\""
        ))
    };
    let (line, crs) = text.split_once('\n').unwrap_or((text, ""));
    let parts: Vec<&str> = line.split_whitespace().collect();
    let [ox, oy, cx, cy, units] = parts[..] else { return Err(bad()) };
    let number = |s: &str| s.parse::<f64>().map_err(|_| bad());
    let units: Units = units.parse().map_err(|_| bad())?;
    let crs = match crs.trim() {
        "" => None,
        json => Some(
            serde_json::from_str::<Crs>(json)
                .map_err(|e| IoErrorKind::InvalidMetadata(format!("attribute {GRID}: CRS {e}")))?,
        ),
    };
    let grid = GridSpec::new(nx, ny, DVec2::new(number(ox)?, number(oy)?), DVec2::new(number(cx)?, number(cy)?))
        .and_then(|g| g.with_units(units))
        .map_err(|e| IoErrorKind::InvalidMetadata(e.to_string()))?;
    Ok((grid, crs))
}

/// Encodes uncompressed, or with ZIP over 16-line blocks when `compress` is set.
pub(crate) fn encode(hf: &Heightfield, compress: bool) -> Result<Vec<u8>, IoErrorKind> {
    let g = hf.grid();
    let data = north_up(hf, |_, _, v| v);
    let channel = AnyChannel::new("Y", FlatSamples::F32(data));
    let mut attrs = LayerAttributes::default();
    let (o, c) = (g.origin(), g.cell_size());
    let mut grid = format!("{} {} {} {} {}", o.x, o.y, c.x, c.y, g.units().name());
    if let Some(crs) = hf.crs() {
        // One attribute keeps the header's bytes reproducible (see the module docs).
        grid.push('\n');
        grid.push_str(&serde_json::to_string(crs).unwrap_or_default());
    }
    attrs.other.insert(Text::from(GRID), AttributeValue::Text(Text::from(grid.as_str())));
    let encoding = if compress { Encoding::SMALL_LOSSLESS } else { Encoding::UNCOMPRESSED };
    let layer = Layer::new((hf.nx(), hf.ny()), attrs, encoding, AnyChannels::sort(SmallVec::from_vec(vec![channel])));
    let mut out = Cursor::new(Vec::new());
    // SMALL_LOSSLESS writes lines in increasing order, so the parallel writer's output is
    // reproducible (checked by the round-trip tests).
    Image::from_layer(layer).write().to_buffered(&mut out).map_err(|e| IoErrorKind::Encode(e.to_string()))?;
    Ok(out.into_inner())
}
