//! ESRI ASCII grids (`.asc`): a `key value` header, then `nrows` rows of `ncols` numbers, north row
//! first; the CRS, if any, lives in a sibling `.prj`.

use std::fmt::Write as _;

use glam::DVec2;
use relief_heightfield::{GridSpec, Heightfield};

use crate::error::clip;
use crate::format::is_asc_header_key as is_header_key;
use crate::{IoErrorKind, Limits};

/// Whitespace-separated tokens with line numbers, straight from the bytes (no copy of the file).
struct Tokens<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> Tokens<'a> {
    fn next(&mut self) -> Option<(&'a [u8], usize)> {
        let b = self.bytes;
        while self.pos < b.len() && b[self.pos].is_ascii_whitespace() {
            if b[self.pos] == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
        if self.pos == b.len() {
            return None;
        }
        let start = self.pos;
        while self.pos < b.len() && !b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        Some((&b[start..self.pos], self.line))
    }
}

#[derive(Default)]
struct Header {
    ncols: Option<u64>,
    nrows: Option<u64>,
    x: Option<(f64, bool)>, // (value, is_corner)
    y: Option<(f64, bool)>,
    cellsize: Option<f64>,
    dx: Option<f64>,
    dy: Option<f64>,
    nodata: Option<f64>,
}

fn text(tok: &[u8]) -> String {
    clip(&String::from_utf8_lossy(tok))
}

fn parse_header(t: &mut Tokens<'_>) -> Result<Header, IoErrorKind> {
    let mut h = Header::default();
    loop {
        let (pos, line) = (t.pos, t.line);
        let Some((tok, _)) = t.next() else { break };
        let key = tok.to_ascii_lowercase();
        if !is_header_key(&key) {
            (t.pos, t.line) = (pos, line);
            break;
        }
        let key = String::from_utf8_lossy(&key).into_owned();
        let bad = |what: &str| IoErrorKind::InvalidMetadata(format!("line {}: header key {key} {what}", line + 1));
        let Some((val, _)) = t.next() else { return Err(bad("has no value")) };
        let val_str = std::str::from_utf8(val).map_err(|_| bad("has a non-ASCII value"))?;
        let num = || -> Result<f64, IoErrorKind> {
            val_str.parse::<f64>().map_err(|_| bad(&format!("has value {:?}, not a number", text(val))))
        };
        let count = || -> Result<u64, IoErrorKind> {
            // GDAL writes integers; tolerate "403.0" but not "403.5".
            let v = num()?;
            (v >= 1.0 && v.fract() == 0.0 && v < 1e19)
                .then_some(v as u64)
                .ok_or_else(|| bad(&format!("must be a positive integer, got {val_str}")))
        };
        let slot_taken = match key.as_str() {
            "ncols" => h.ncols.replace(count()?).is_some(),
            "nrows" => h.nrows.replace(count()?).is_some(),
            "xllcorner" => h.x.replace((num()?, true)).is_some(),
            "xllcenter" => h.x.replace((num()?, false)).is_some(),
            "yllcorner" => h.y.replace((num()?, true)).is_some(),
            "yllcenter" => h.y.replace((num()?, false)).is_some(),
            "cellsize" => h.cellsize.replace(num()?).is_some(),
            "dx" => h.dx.replace(num()?).is_some(),
            "dy" => h.dy.replace(num()?).is_some(),
            _ => h.nodata.replace(num()?).is_some(),
        };
        if slot_taken {
            return Err(bad("appears twice (or both its corner and center forms do)"));
        }
    }
    Ok(h)
}

/// Decodes a grid in metres; the caller applies the `.prj` units.
pub(crate) fn decode(bytes: &[u8], limits: Limits) -> Result<Heightfield, IoErrorKind> {
    let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    let mut t = Tokens { bytes, pos: 0, line: 0 };
    let h = parse_header(&mut t)?;
    let missing = |k: &str| IoErrorKind::InvalidMetadata(format!("header has no {k}"));
    let ncols = h.ncols.ok_or_else(|| missing("ncols"))?;
    let nrows = h.nrows.ok_or_else(|| missing("nrows"))?;
    let (x, x_corner) = h.x.ok_or_else(|| missing("xllcorner or xllcenter"))?;
    let (y, y_corner) = h.y.ok_or_else(|| missing("yllcorner or yllcenter"))?;
    let cell = match (h.cellsize, h.dx, h.dy) {
        (Some(c), None, None) => DVec2::splat(c),
        (None, Some(dx), Some(dy)) => DVec2::new(dx, dy),
        (None, _, _) => return Err(missing("cellsize (or dx and dy)")),
        (Some(_), _, _) => return Err(IoErrorKind::InvalidMetadata("header has both cellsize and dx/dy".to_owned())),
    };
    let cells = limits.check(ncols, nrows)?;
    let (nx, ny) = (ncols as usize, nrows as usize);
    // Corner registration: the lower-left sample sits half a cell in from the corner.
    let origin = DVec2::new(if x_corner { x + 0.5 * cell.x } else { x }, if y_corner { y + 0.5 * cell.y } else { y });
    let grid = GridSpec::new(nx, ny, origin, cell).map_err(|e| IoErrorKind::InvalidMetadata(e.to_string()))?;

    // Every value but the last needs at least two bytes (a digit and a separator): a header that
    // announces more cells than that is lying, and gets no allocation of its size.
    let rest = (bytes.len() - t.pos) as u64;
    let plausible = cells as u64 <= rest / 2 + 1;
    let mut samples = Vec::with_capacity(if plausible { cells } else { 0 });
    let nodata = h.nodata.map(|v| v as f32);
    let mut found = 0u64;
    while found < cells as u64 {
        let k = found as usize;
        let (row, col) = (k / nx + 1, k % nx + 1);
        let Some((tok, line)) = t.next() else {
            return Err(IoErrorKind::MissingValues { expected: cells as u64, found, row, col });
        };
        let v = parse_value(tok);
        let Some(v) = v else {
            return Err(IoErrorKind::InvalidToken { line: line + 1, row, col, token: text(tok) });
        };
        if plausible {
            samples.push(if Some(v) == nodata { f32::NAN } else { v });
        }
        found += 1;
    }
    if let Some((tok, line)) = t.next() {
        return Err(IoErrorKind::TrailingData { line: line + 1, token: text(tok) });
    }
    if !plausible {
        // Unreachable in practice: the loop above runs out of tokens first.
        return Err(IoErrorKind::HeaderMismatch(format!("{cells} values cannot fit in {rest} bytes")));
    }
    crate::meta::flip_rows(&mut samples, nx);
    Ok(Heightfield::from_samples(grid, samples)?)
}

/// A finite number (or NaN) from a value token; `None` for anything else, ±∞ included.
#[inline]
fn parse_value(tok: &[u8]) -> Option<f32> {
    // Fast path for the whole numbers most DEMs hold: up to 7 digits are exact in f32.
    let (neg, digits) = match tok.split_first() {
        Some((b'-', rest)) => (true, rest),
        _ => (false, tok),
    };
    if !digits.is_empty() && digits.len() <= 7 && digits.iter().all(u8::is_ascii_digit) {
        let n = digits.iter().fold(0u32, |acc, d| acc * 10 + u32::from(d - b'0')) as f32;
        return Some(if neg { -n } else { n });
    }
    std::str::from_utf8(tok).ok()?.parse::<f32>().ok().filter(|v| !v.is_infinite())
}

/// A NODATA value that no valid sample equals.
fn pick_no_data(hf: &Heightfield) -> f32 {
    let mut candidate = -9999.0f32;
    while hf.samples().contains(&candidate) {
        candidate -= 1.0;
    }
    candidate
}

/// Appends the shortest decimal that parses back to exactly `v` (Schubfach via `zmij`), without
/// the `.0` of whole numbers.
#[inline]
fn push_f32(s: &mut String, buf: &mut zmij::Buffer, v: f32) {
    let text = buf.format_finite(v);
    s.push_str(text.strip_suffix(".0").unwrap_or(text));
}

/// Encodes with `xllcenter`/`yllcenter` (our node-registered origin, exactly) and every value in
/// the shortest text that parses back to the same f32, so the round trip is bit-exact.
pub(crate) fn encode(hf: &Heightfield) -> Vec<u8> {
    let g = hf.grid();
    let mut s = String::with_capacity(128 + hf.samples().len() * 8);
    // `write!` into a String cannot fail.
    let _ = write!(s, "ncols {}\nnrows {}\nxllcenter {}\nyllcenter {}\n", g.nx(), g.ny(), g.origin().x, g.origin().y);
    let c = g.cell_size();
    let _ = if c.x == c.y { writeln!(s, "cellsize {}", c.x) } else { writeln!(s, "dx {}\ndy {}", c.x, c.y) };
    let nodata = hf.has_no_data().then(|| pick_no_data(hf));
    if let Some(nd) = nodata {
        let _ = writeln!(s, "NODATA_value {nd}");
    }
    let mut buf = zmij::Buffer::new();
    for j in (0..g.ny()).rev() {
        for (i, &v) in hf.row(j).iter().enumerate() {
            if i > 0 {
                s.push(' ');
            }
            // `nodata` is set whenever a sample is NaN, so only finite values reach the formatter.
            push_f32(&mut s, &mut buf, if v.is_nan() { nodata.unwrap_or(0.0) } else { v });
        }
        s.push('\n');
    }
    s.into_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Heightfield, IoErrorKind> {
        decode(text.as_bytes(), Limits::default())
    }

    #[test]
    fn corner_registration_moves_the_origin_half_a_cell_in() {
        let hf = parse("ncols 2\nnrows 2\nxllcorner 100\nyllcorner 200\ncellsize 10\n1 2\n3 4\n").unwrap();
        assert_eq!(hf.grid().origin(), DVec2::new(105.0, 205.0));
        let hf = parse("ncols 2\nnrows 2\nxllcenter 100\nyllcorner 200\ncellsize 10\n1 2\n3 4\n").unwrap();
        assert_eq!(hf.grid().origin(), DVec2::new(100.0, 205.0));
        // North row first in the file.
        assert_eq!((hf.value(0, 1), hf.value(0, 0)), (1.0, 3.0));
    }

    #[test]
    fn keys_are_case_insensitive_in_any_order_with_dx_dy() {
        let hf = parse(
            "NROWS 1\r\nDY 2.5\r\nXLLCENTER -1\r\nNCols 3\r\nyllcenter 4\r\ndx 0.5\r\nnodata_VALUE -1\r\n7 -1 9\r\n",
        )
        .unwrap();
        assert_eq!((hf.nx(), hf.ny()), (3, 1));
        assert_eq!(hf.grid().cell_size(), DVec2::new(0.5, 2.5));
        assert_eq!(hf.grid().origin(), DVec2::new(-1.0, 4.0));
        assert!(hf.is_no_data(1, 0));
        assert_eq!(hf.value(2, 0), 9.0);
    }

    #[test]
    fn header_errors_are_metadata_errors() {
        let bad = |t: &str| matches!(parse(t), Err(IoErrorKind::InvalidMetadata(_)));
        assert!(bad("ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\ndx 1\n5\n"), "cellsize and dx");
        assert!(bad("ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\n5\n"), "no cell size");
        assert!(bad("ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize -1\n5\n"), "negative cell");
        assert!(bad("ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1e-320\n5 6\n"), "subnormal cell");
        assert!(bad("ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize\n"), "value missing");
        assert!(bad("ncols 0\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n"), "zero columns");
    }

    #[test]
    fn encoding_picks_a_nodata_value_absent_from_the_data() {
        let grid = GridSpec::new(3, 1, DVec2::ZERO, DVec2::ONE).unwrap();
        let hf = Heightfield::from_samples(grid, vec![-9999.0, f32::NAN, -10000.0]).unwrap();
        let text = String::from_utf8(encode(&hf)).unwrap();
        assert!(text.contains("NODATA_value -10001\n"), "{text}");
        assert_eq!(parse(&text).unwrap(), hf);
    }
}
