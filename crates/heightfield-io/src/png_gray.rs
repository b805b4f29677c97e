//! 8- and 16-bit grayscale PNG heightmaps, quantised over the field's min/max, with the real
//! elevations and geometry in a `relief` tEXt chunk.

use std::io::Cursor;

use relief_heightfield::Heightfield;

use crate::error::decode_io;
use crate::meta::{Metadata, Quantiser, flip_rows, plain_grid};
use crate::{IoErrorKind, Limits};

/// Keyword of the text chunk holding the JSON [`Metadata`].
pub(crate) const KEYWORD: &str = "relief";

fn decode_error(e: png::DecodingError, found: usize) -> IoErrorKind {
    match e {
        png::DecodingError::IoError(e) => decode_io(&e, found),
        png::DecodingError::LimitsExceeded => {
            IoErrorKind::Decode("the PNG decoder's memory limit was exceeded (raise Limits::max_cells)".to_owned())
        }
        other => IoErrorKind::Decode(other.to_string()),
    }
}

/// The `relief` metadata of a decoded PNG, if any (tEXt, zTXt or iTXt).
fn find_metadata(info: &png::Info<'_>) -> Result<Option<Metadata>, IoErrorKind> {
    let bad = |e: png::DecodingError| IoErrorKind::InvalidMetadata(format!("relief text chunk: {e}"));
    if let Some(t) = info.uncompressed_latin1_text.iter().find(|t| t.keyword == KEYWORD) {
        return Metadata::from_json(&t.text).map(Some);
    }
    if let Some(t) = info.compressed_latin1_text.iter().find(|t| t.keyword == KEYWORD) {
        // Metadata is a few hundred bytes; a chunk that inflates past 64 KiB is not ours.
        let mut t = t.clone();
        t.decompress_text_with_limit(1 << 16).map_err(bad)?;
        return Metadata::from_json(&t.get_text().map_err(bad)?).map(Some);
    }
    if let Some(t) = info.utf8_text.iter().find(|t| t.keyword == KEYWORD) {
        let mut t = t.clone();
        t.decompress_text_with_limit(1 << 16).map_err(bad)?;
        return Metadata::from_json(&t.get_text().map_err(bad)?).map(Some);
    }
    Ok(None)
}

/// A zeroed buffer for the image `reader` announces (`w` × `h` of `unit`), refused before it is
/// allocated when the file (`found` bytes) is too short to hold it: deflate cannot compress better
/// than about 1032:1, so a shorter file is lying about its size.
fn frame_buffer<R: std::io::BufRead + std::io::Seek>(
    reader: &png::Reader<R>,
    (w, h): (u32, u32),
    found: usize,
    limits: Limits,
    unit: &str,
) -> Result<Vec<u8>, IoErrorKind> {
    let len = reader
        .output_buffer_size()
        .ok_or_else(|| IoErrorKind::TooLarge { cells: u64::from(w) * u64::from(h), limit: limits.max_cells })?;
    if (found as u64).saturating_mul(1032) < len as u64 {
        return Err(IoErrorKind::HeaderMismatch(format!(
            "header announces {w}x{h} {unit} ({len} bytes) but the file holds only {found} bytes"
        )));
    }
    Ok(vec![0u8; len])
}

/// A grayscale PNG's codes, as read: bit depth, size, the raw big-endian frame, the `relief`
/// metadata and the tRNS gray level, if any.
pub(crate) struct GrayImage {
    pub bits: u8,
    pub width: usize,
    pub height: usize,
    buf: Vec<u8>,
    pub meta: Option<Metadata>,
    pub transparent: Option<u32>,
}

impl GrayImage {
    /// The code of sample `k` (row-major, north row first).
    fn code(&self, k: usize) -> u32 {
        let b = &self.buf;
        if self.bits == 8 { u32::from(b[k]) } else { u32::from(u16::from_be_bytes([b[2 * k], b[2 * k + 1]])) }
    }
}

/// For a PNG that is not plain 8/16-bit gray (colour, palette, alpha, or gray under 8 bits),
/// its codes' bit depth as read (16, else 8); `None` for plain gray, or when the header cannot be
/// read (the gray reader then reports why).
pub(crate) fn colour_bits(bytes: &[u8]) -> Option<u8> {
    let mut decoder = png::Decoder::new_with_limits(Cursor::new(bytes), png::Limits { bytes: 1 << 20 });
    let h = decoder.read_header_info().ok()?;
    let bits = h.bit_depth as u8;
    (h.color_type != png::ColorType::Grayscale || bits < 8).then_some(if bits == 16 { 16 } else { 8 })
}

/// Reads an 8- or 16-bit grayscale PNG's codes and text chunks; any other kind is refused.
pub(crate) fn read_gray(bytes: &[u8], limits: Limits) -> Result<GrayImage, IoErrorKind> {
    let found = bytes.len();
    let budget = png::Limits { bytes: limits.byte_budget(2, 16 << 20) };
    let mut decoder = png::Decoder::new_with_limits(Cursor::new(bytes), budget);
    let header = decoder.read_header_info().map_err(|e| decode_error(e, found))?;
    let (w, h) = (header.width, header.height);
    limits.check(u64::from(w), u64::from(h))?;
    let bits = match (header.color_type, header.bit_depth) {
        (png::ColorType::Grayscale, png::BitDepth::Eight) => 8,
        (png::ColorType::Grayscale, png::BitDepth::Sixteen) => 16,
        (ct, bd) => {
            return Err(IoErrorKind::Unsupported(format!(
                "PNG is {ct:?} at {} bits per sample; heightmaps must be 8- or 16-bit grayscale (colour and alpha images are read only as masks and probability maps)",
                bd as u8
            )));
        }
    };
    let mut reader = decoder.read_info().map_err(|e| decode_error(e, found))?;
    let mut buf = frame_buffer(&reader, (w, h), found, limits, "samples")?;
    reader.next_frame(&mut buf).map_err(|e| decode_error(e, found))?;
    // Reads the chunks after the image data too (a text chunk may follow IDAT) and catches files
    // cut before IEND.
    reader.finish().map_err(|e| decode_error(e, found))?;
    let info = reader.info();
    let meta = find_metadata(info)?;
    let transparent =
        info.trns.as_deref().filter(|t| t.len() >= 2).map(|t| u32::from(u16::from_be_bytes([t[0], t[1]])));
    Ok(GrayImage { bits, width: w as usize, height: h as usize, buf, meta, transparent })
}

pub(crate) fn decode(bytes: &[u8], limits: Limits) -> Result<Heightfield, IoErrorKind> {
    let image = read_gray(bytes, limits)?;
    let (nx, ny) = (image.width, image.height);
    let max_code = (1u32 << image.bits) - 1;
    let code = |k| image.code(k);
    let (grid, mut samples) = if let Some(m) = &image.meta {
        let grid = m.grid(nx, ny)?;
        let q = m.quantiser(max_code)?;
        let mut samples = Vec::with_capacity(nx * ny);
        for k in 0..nx * ny {
            samples.push(q.decode(code(k))?);
        }
        (grid, samples)
    } else {
        // A plain grayscale image: code / max_code, with the tRNS gray level (if any) as no-data.
        let transparent = image.transparent;
        let scale = max_code as f32;
        let samples = (0..nx * ny)
            .map(|k| match code(k) {
                c if Some(c) == transparent => f32::NAN,
                c => c as f32 / scale,
            })
            .collect();
        (plain_grid(nx, ny)?, samples)
    };
    flip_rows(&mut samples, nx);
    let crs = image.meta.and_then(|m| m.crs);
    Ok(Heightfield::from_samples(grid, samples)?.with_crs(crs))
}

/// A `bits`-bit PNG of `hf`, quantised over `range` (the field's min and max by default).
pub(crate) fn encode(hf: &Heightfield, bits: u8, range: Option<(f32, f32)>) -> Result<Vec<u8>, IoErrorKind> {
    let enc_err = |e: png::EncodingError| IoErrorKind::Encode(e.to_string());
    let (nx, ny) = (hf.nx(), hf.ny());
    let (w, h) = (u32::try_from(nx), u32::try_from(ny));
    let (Ok(w), Ok(h)) = (w, h) else {
        return Err(IoErrorKind::Unsupported(format!("{nx}x{ny} exceeds the PNG size limit")));
    };
    let max_code = (1u32 << bits) - 1;
    let q = Quantiser::for_field_in(hf, max_code, range)?;
    let meta = Metadata::describe_in(hf, if bits == 8 { "png8" } else { "png16" }, true, range);
    let mut data = Vec::with_capacity(nx * ny * usize::from(bits / 8));
    for j in (0..ny).rev() {
        for &v in hf.row(j) {
            let c = q.encode(v);
            if bits == 8 {
                data.push(c as u8);
            } else {
                data.extend_from_slice(&(c as u16).to_be_bytes());
            }
        }
    }
    let mut out = Vec::with_capacity(data.len() / 2 + 1024);
    let mut encoder = png::Encoder::new(&mut out, w, h);
    encoder.set_color(png::ColorType::Grayscale);
    encoder.set_depth(if bits == 8 { png::BitDepth::Eight } else { png::BitDepth::Sixteen });
    // fdeflate: several times faster than zlib level 6 for a few percent larger files.
    encoder.set_compression(png::Compression::Fast);
    encoder.add_text_chunk(KEYWORD.to_owned(), meta.to_json()).map_err(enc_err)?;
    let mut writer = encoder.write_header().map_err(enc_err)?;
    writer.write_image_data(&data).map_err(enc_err)?;
    writer.finish().map_err(enc_err)?;
    Ok(out)
}

/// Decodes any PNG (gray, gray + alpha, RGB, RGBA, palette, any bit depth) as luma in [0, 1]
/// (ITU-R BT.601 weights for colour), fully transparent pixels as no-data, on a plain grid
/// (origin 0, cell 1, rows flipped to south-first): label masks and probability maps.
pub(crate) fn decode_luma(bytes: &[u8], limits: Limits) -> Result<Heightfield, IoErrorKind> {
    let found = bytes.len();
    let budget = png::Limits { bytes: limits.byte_budget(8, 16 << 20) };
    let mut decoder = png::Decoder::new_with_limits(Cursor::new(bytes), budget);
    decoder.set_transformations(png::Transformations::EXPAND);
    let header = decoder.read_header_info().map_err(|e| decode_error(e, found))?;
    let (w, h) = (header.width, header.height);
    limits.check(u64::from(w), u64::from(h))?;
    let mut reader = decoder.read_info().map_err(|e| decode_error(e, found))?;
    let mut buf = frame_buffer(&reader, (w, h), found, limits, "pixels")?;
    let frame = reader.next_frame(&mut buf).map_err(|e| decode_error(e, found))?;
    let (color, depth) = (frame.color_type, frame.bit_depth);
    let channels = color.samples();
    let wide = depth == png::BitDepth::Sixteen;
    let max = if wide { 65535.0 } else { 255.0 };
    let sample = |k: usize| -> f32 {
        if wide { f32::from(u16::from_be_bytes([buf[2 * k], buf[2 * k + 1]])) } else { f32::from(buf[k]) }
    };
    let (nx, ny) = (w as usize, h as usize);
    let mut values: Vec<f32> = (0..nx * ny)
        .map(|p| {
            let base = p * channels;
            let (luma, alpha) = match color {
                png::ColorType::Grayscale => (sample(base), max),
                png::ColorType::GrayscaleAlpha => (sample(base), sample(base + 1)),
                png::ColorType::Rgb => {
                    (0.299 * sample(base) + 0.587 * sample(base + 1) + 0.114 * sample(base + 2), max)
                }
                // Indexed images arrive expanded to RGB(A); anything else is RGBA.
                _ => (0.299 * sample(base) + 0.587 * sample(base + 1) + 0.114 * sample(base + 2), sample(base + 3)),
            };
            if alpha == 0.0 { f32::NAN } else { luma / max }
        })
        .collect();
    flip_rows(&mut values, nx);
    Heightfield::from_samples(plain_grid(nx, ny)?, values).map_err(IoErrorKind::InvalidData)
}

/// Encodes an 8-bit RGB image (used by the shaded-relief preview).
pub(crate) fn encode_rgb(width: u32, height: u32, pixels: &[u8]) -> Result<Vec<u8>, IoErrorKind> {
    let enc_err = |e: png::EncodingError| IoErrorKind::Encode(e.to_string());
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Fast);
    let mut writer = encoder.write_header().map_err(enc_err)?;
    writer.write_image_data(pixels).map_err(enc_err)?;
    writer.finish().map_err(enc_err)?;
    Ok(out)
}
