//! LZMA-compressed `GeoTIFF` (compression 34925, GDAL's `COMPRESS=LZMA`), which the `tiff` crate
//! refuses: the strips or tiles are located through its tag reader, each chunk is an xz stream
//! (delta filter + LZMA2) whose LZMA2 data `lzma-rs` decodes, and the predictors (2: horizontal, 3: floating point) are undone here.
//! Samples come out as f64 in raster order, for the same conversion as every other `GeoTIFF`.

use std::io::{Cursor, Read, Seek};

use tiff::decoder::Decoder;
use tiff::tags::Tag;

use crate::IoErrorKind;

/// The TIFF compression code of LZMA.
pub(crate) const LZMA: u16 = 34925;

/// Sample layout of the single band.
#[derive(Clone, Copy)]
struct Layout {
    width: usize,
    height: usize,
    /// Bytes per sample: 1, 2, 4 or 8.
    bytes: usize,
    /// TIFF `SampleFormat`: 1 unsigned, 2 signed, 3 IEEE float.
    format: u16,
    predictor: u16,
    big_endian: bool,
}

/// One chunk (strip or tile): where its pixels go and where its bytes are.
struct Chunk {
    x0: usize,
    y0: usize,
    /// Samples per chunk row (the tile width, or the image width for strips).
    w: usize,
    /// Rows the chunk holds.
    h: usize,
    offset: u64,
    len: u64,
}

/// Decodes every sample of an LZMA `GeoTIFF` as f64, north row first.
pub(crate) fn read_samples<R: Read + Seek>(
    dec: &mut Decoder<R>,
    file: &[u8],
    err: impl Fn(tiff::TiffError) -> IoErrorKind,
) -> Result<Vec<f64>, IoErrorKind> {
    let (w, h) = dec.dimensions().map_err(&err)?;
    let unsigned = |dec: &mut Decoder<R>, tag| dec.find_tag_unsigned::<u32>(tag).map_err(&err);
    let bits = unsigned(dec, Tag::BitsPerSample)?.unwrap_or(1);
    let layout = Layout {
        width: w as usize,
        height: h as usize,
        bytes: match bits {
            8 | 16 | 32 | 64 => bits as usize / 8,
            b => return Err(IoErrorKind::Unsupported(format!("LZMA TIFF with {b}-bit samples"))),
        },
        format: unsigned(dec, Tag::SampleFormat)?.unwrap_or(1) as u16,
        predictor: unsigned(dec, Tag::Predictor)?.unwrap_or(1) as u16,
        big_endian: file.starts_with(b"MM"),
    };
    if !(1..=3).contains(&layout.format) || (layout.format == 3 && layout.bytes < 4) {
        return Err(IoErrorKind::Unsupported(format!("LZMA TIFF sample format {}", layout.format)));
    }
    let mut out = vec![0.0; layout.width * layout.height];
    for chunk in chunks(dec, &layout, &err)? {
        let start = usize::try_from(chunk.offset).unwrap_or(usize::MAX);
        let end = start.saturating_add(usize::try_from(chunk.len).unwrap_or(usize::MAX));
        let Some(packed) = file.get(start..end) else {
            return Err(IoErrorKind::Truncated { expected_bytes: Some(end as u64), found_bytes: file.len() as u64 });
        };
        let mut raw = inflate(packed, chunk.w * chunk.h * layout.bytes)?;
        unpredict(&mut raw, &layout, chunk.w);
        place(&raw, &layout, &chunk, &mut out);
    }
    Ok(out)
}

/// The image's strips or tiles.
fn chunks<R: Read + Seek>(
    dec: &mut Decoder<R>,
    l: &Layout,
    err: &impl Fn(tiff::TiffError) -> IoErrorKind,
) -> Result<Vec<Chunk>, IoErrorKind> {
    let list = |dec: &mut Decoder<R>, tag| -> Result<Option<Vec<u64>>, IoErrorKind> {
        dec.find_tag(tag).map_err(err)?.map(|v| v.into_u64_vec().map_err(err)).transpose()
    };
    let bad = |m: &str| IoErrorKind::InvalidMetadata(format!("LZMA TIFF: {m}"));
    let (tiled, cw, ch, offsets, counts) = if let Some(offsets) = list(dec, Tag::TileOffsets)? {
        let tw = dec.find_tag_unsigned::<u32>(Tag::TileWidth).map_err(err)?.ok_or_else(|| bad("no TileWidth"))?;
        let th = dec.find_tag_unsigned::<u32>(Tag::TileLength).map_err(err)?.ok_or_else(|| bad("no TileLength"))?;
        (true, tw as usize, th as usize, offsets, list(dec, Tag::TileByteCounts)?)
    } else {
        let rows = dec.find_tag_unsigned::<u32>(Tag::RowsPerStrip).map_err(err)?.unwrap_or(u32::MAX);
        let offsets = list(dec, Tag::StripOffsets)?.ok_or_else(|| bad("no StripOffsets"))?;
        (false, l.width, (rows as usize).min(l.height), offsets, list(dec, Tag::StripByteCounts)?)
    };
    let counts = counts.ok_or_else(|| bad("no byte counts"))?;
    if cw == 0 || ch == 0 {
        return Err(bad("zero-sized chunks"));
    }
    let across = l.width.div_ceil(cw);
    let expected = across * l.height.div_ceil(ch);
    if offsets.len() != expected || counts.len() != expected {
        return Err(bad(&format!("{} offsets and {} byte counts for {expected} chunks", offsets.len(), counts.len())));
    }
    Ok((0..expected)
        .map(|k| {
            let (x0, y0) = ((k % across) * cw, (k / across) * ch);
            // A strip holds only the rows left; a tile is always whole (padded past the edge).
            let h = if tiled { ch } else { ch.min(l.height - y0) };
            Chunk { x0, y0, w: cw, h, offset: offsets[k], len: counts[k] }
        })
        .collect())
}

/// An xz stream inflated to exactly `size` bytes; a stream that would give more is refused as it
/// decodes, so a hostile chunk cannot exhaust memory.
///
/// libtiff writes each chunk as one xz block whose filter chain is a byte-delta filter before
/// LZMA2; `lzma-rs` decodes LZMA2 but not the delta filter, so the block header is read here and
/// the delta undone after.
fn inflate(packed: &[u8], size: usize) -> Result<Vec<u8>, IoErrorKind> {
    struct Capped(Vec<u8>, usize);
    impl std::io::Write for Capped {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            if self.0.len() + buf.len() > self.1 {
                return Err(std::io::Error::other("chunk inflates past its size"));
            }
            self.0.extend_from_slice(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    let bad = |m: String| IoErrorKind::Decode(format!("LZMA chunk: {m}"));
    let block = XzBlock::parse(packed).ok_or_else(|| bad("not an xz stream libtiff writes".to_owned()))?;
    let mut out = Capped(Vec::with_capacity(size), size);
    lzma_rs::lzma2_decompress(&mut Cursor::new(&packed[block.data..]), &mut out).map_err(|e| bad(e.to_string()))?;
    let mut out = out.0;
    if out.len() != size {
        return Err(bad(format!("{} bytes, not {size}", out.len())));
    }
    if let Some(dist) = block.delta {
        for k in dist..out.len() {
            out[k] = out[k].wrapping_add(out[k - dist]);
        }
    }
    Ok(out)
}

/// The first block of an xz stream: where its LZMA2 data starts and the delta filter's distance.
struct XzBlock {
    data: usize,
    delta: Option<usize>,
}

impl XzBlock {
    const MAGIC: [u8; 6] = [0xfd, b'7', b'z', b'X', b'Z', 0];
    const DELTA: u64 = 0x03;
    const LZMA2: u64 = 0x21;

    fn parse(s: &[u8]) -> Option<Self> {
        // Stream header: magic, 2 flag bytes, CRC32; then the block header.
        if s.get(..6)? != Self::MAGIC {
            return None;
        }
        let at = 12;
        let header_len = (usize::from(*s.get(at)?) + 1) * 4;
        let header = s.get(at..at + header_len)?;
        let flags = header[1];
        let mut k = 2;
        // Optional compressed and uncompressed sizes.
        for bit in [0x40, 0x80] {
            if flags & bit != 0 {
                vli(header, &mut k)?;
            }
        }
        let mut delta = None;
        let mut lzma2 = false;
        for _ in 0..=(flags & 3) {
            let id = vli(header, &mut k)?;
            let props_len = usize::try_from(vli(header, &mut k)?).ok()?;
            let props = header.get(k..k + props_len)?;
            k += props_len;
            match id {
                Self::DELTA if props_len == 1 && !lzma2 => delta = Some(usize::from(props[0]) + 1),
                Self::LZMA2 => lzma2 = true,
                _ => return None,
            }
        }
        lzma2.then_some(Self { data: at + header_len, delta })
    }
}

/// A variable-length integer of the xz format, advancing `k`.
fn vli(s: &[u8], k: &mut usize) -> Option<u64> {
    let mut value = 0u64;
    for shift in (0..63).step_by(7) {
        let b = *s.get(*k)?;
        *k += 1;
        value |= u64::from(b & 0x7f) << shift;
        if b & 0x80 == 0 {
            return Some(value);
        }
    }
    None
}

/// Undoes the predictor on each chunk row of `w` samples. Predictor 3 leaves the samples
/// big-endian whatever the file's byte order.
fn unpredict(raw: &mut [u8], l: &Layout, w: usize) {
    let b = l.bytes;
    for row in raw.chunks_exact_mut(w * b) {
        match l.predictor {
            2 => {
                for i in 1..w {
                    let (prev, cur) = row.split_at_mut(i * b);
                    let sum = word(&prev[(i - 1) * b..], b, l.big_endian).wrapping_add(word(cur, b, l.big_endian));
                    put_word(&mut cur[..b], sum, l.big_endian);
                }
            }
            3 => {
                for k in 1..row.len() {
                    row[k] = row[k].wrapping_add(row[k - 1]);
                }
                let planes = row.to_vec();
                for i in 0..w {
                    for p in 0..b {
                        row[i * b + p] = planes[p * w + i];
                    }
                }
            }
            _ => {}
        }
    }
}

/// The `b`-byte unsigned word at the start of `s`.
fn word(s: &[u8], b: usize, big: bool) -> u64 {
    let mut v = [0u8; 8];
    if big {
        v[8 - b..].copy_from_slice(&s[..b]);
        u64::from_be_bytes(v)
    } else {
        v[..b].copy_from_slice(&s[..b]);
        u64::from_le_bytes(v)
    }
}

fn put_word(s: &mut [u8], value: u64, big: bool) {
    let b = s.len();
    if big {
        s.copy_from_slice(&value.to_be_bytes()[8 - b..]);
    } else {
        s.copy_from_slice(&value.to_le_bytes()[..b]);
    }
}

/// Copies the chunk's samples that fall inside the image into `out`.
fn place(raw: &[u8], l: &Layout, c: &Chunk, out: &mut [f64]) {
    let b = l.bytes;
    // The floating-point predictor leaves big-endian bytes.
    let big = l.big_endian || l.predictor == 3;
    for r in 0..c.h.min(l.height.saturating_sub(c.y0)) {
        for i in 0..c.w.min(l.width.saturating_sub(c.x0)) {
            let s = &raw[(r * c.w + i) * b..];
            let bits = word(s, b, big);
            let value = match (l.format, b) {
                (3, 4) => f64::from(f32::from_bits(bits as u32)),
                (3, _) => f64::from_bits(bits),
                // Sign-extend from the sample's width.
                (2, _) => ((bits << (64 - 8 * b)) as i64 >> (64 - 8 * b)) as f64,
                _ => bits as f64,
            };
            out[(c.y0 + r) * l.width + c.x0 + i] = value;
        }
    }
}
