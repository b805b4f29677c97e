//! Headerless raw heightmaps: r16 (little-endian u16, quantised) and r32 (little-endian f32), north
//! row first, with geometry and min/max in a JSON sidecar `<file>.json`.

use relief_heightfield::Heightfield;

use crate::meta::{Metadata, Quantiser, flip_rows, plain_grid};
use crate::{IoErrorKind, Limits};

/// Bytes per sample of the two raw encodings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum RawKind {
    R16,
    R32,
}

impl RawKind {
    fn bytes(self) -> usize {
        match self {
            RawKind::R16 => 2,
            RawKind::R32 => 4,
        }
    }

    fn name(self) -> &'static str {
        match self {
            RawKind::R16 => "r16",
            RawKind::R32 => "r32",
        }
    }
}

/// Where the dimensions come from, in order of precedence.
pub(crate) struct Shape<'a> {
    pub sidecar: Option<&'a Metadata>,
    pub dims: Option<(usize, usize)>,
    /// Named in the error when neither is available and the length is not square.
    pub sidecar_path: std::path::PathBuf,
}

pub(crate) fn decode(
    bytes: &[u8],
    kind: RawKind,
    shape: &Shape<'_>,
    limits: Limits,
) -> Result<Heightfield, IoErrorKind> {
    let bps = kind.bytes();
    if let Some(m) = shape.sidecar
        && m.encoding != kind.name()
    {
        return Err(IoErrorKind::HeaderMismatch(format!(
            "sidecar describes {} data, the file is read as {}",
            m.encoding,
            kind.name()
        )));
    }
    let (nx, ny) = match (shape.sidecar, shape.dims) {
        (Some(m), dims) => {
            if let Some((x, y)) = dims
                && (x as u64, y as u64) != (m.nx, m.ny)
            {
                return Err(IoErrorKind::HeaderMismatch(format!(
                    "sidecar says {}x{}, ReadOptions::raw_dims says {x}x{y}",
                    m.nx, m.ny
                )));
            }
            (m.nx, m.ny)
        }
        (None, Some((x, y))) => (x as u64, y as u64),
        (None, None) => {
            if bytes.is_empty() {
                return Err(IoErrorKind::Truncated { expected_bytes: None, found_bytes: 0 });
            }
            let n = (bytes.len() / bps) as u64;
            let side = n.isqrt();
            if !bytes.len().is_multiple_of(bps) || side * side != n {
                return Err(IoErrorKind::MissingSidecar { sidecar: shape.sidecar_path.clone() });
            }
            (side, side)
        }
    };
    let cells = limits.check(nx, ny)?;
    let expected = (cells as u64).saturating_mul(bps as u64);
    let found = bytes.len() as u64;
    if found < expected {
        return Err(IoErrorKind::Truncated { expected_bytes: Some(expected), found_bytes: found });
    }
    if found > expected {
        return Err(IoErrorKind::WrongSize { found_bytes: found, accepted_bytes: vec![expected] });
    }
    let (nx, ny) = (nx as usize, ny as usize);
    let grid = match shape.sidecar {
        Some(m) => m.grid(nx, ny)?,
        None => plain_grid(nx, ny)?,
    };
    let mut samples = match kind {
        RawKind::R16 => {
            let codes = bytes.chunks_exact(2).map(|c| u32::from(u16::from_le_bytes([c[0], c[1]])));
            match shape.sidecar {
                Some(m) => {
                    let q = m.quantiser(u32::from(u16::MAX))?;
                    let mut out = Vec::with_capacity(cells);
                    for c in codes {
                        out.push(q.decode(c)?);
                    }
                    out
                }
                None => codes.map(|c| c as f32 / f32::from(u16::MAX)).collect(),
            }
        }
        RawKind::R32 => bytes.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect(),
    };
    flip_rows(&mut samples, nx);
    let crs = shape.sidecar.and_then(|m| m.crs.clone());
    Ok(Heightfield::from_samples(grid, samples)?.with_crs(crs))
}

/// The file's bytes and the sidecar record; r16 is quantised over `range` (the field's min and
/// max by default), r32 ignores it.
pub(crate) fn encode(
    hf: &Heightfield,
    kind: RawKind,
    range: Option<(f32, f32)>,
) -> Result<(Vec<u8>, Metadata), IoErrorKind> {
    let mut out = Vec::with_capacity(hf.samples().len() * kind.bytes());
    Ok(match kind {
        RawKind::R16 => {
            let q = Quantiser::for_field_in(hf, u32::from(u16::MAX), range)?;
            for j in (0..hf.ny()).rev() {
                for &v in hf.row(j) {
                    out.extend_from_slice(&(q.encode(v) as u16).to_le_bytes());
                }
            }
            (out, Metadata::describe_in(hf, "r16", true, range))
        }
        RawKind::R32 => {
            for j in (0..hf.ny()).rev() {
                for &v in hf.row(j) {
                    out.extend_from_slice(&v.to_le_bytes());
                }
            }
            (out, Metadata::describe(hf, "r32", false))
        }
    })
}
