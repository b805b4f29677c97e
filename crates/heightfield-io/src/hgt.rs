//! SRTM `.hgt` tiles: 1201² (3″) or 3601² (1″) big-endian i16 samples, north row first, −32768 for
//! voids; the file name (`N36W085.hgt`) gives the tile's south-west corner in whole degrees.

use std::path::Path;

use glam::DVec2;
use relief_heightfield::{GridSpec, Heightfield};

use crate::meta::flip_rows;
use crate::{IoErrorKind, Limits};

/// Sample value marking a void.
pub(crate) const VOID: i16 = i16::MIN;
/// Samples per side of the two tile resolutions.
pub(crate) const SIDES: [usize; 2] = [1201, 3601];

/// South-west corner (longitude, latitude) named by a tile name such as `N36W085` at the start of
/// the file name (case-insensitive; suffixes like `.SRTMGL1.hgt` are ignored).
pub(crate) fn tile_origin(path: &Path) -> Option<DVec2> {
    let name = path.file_name()?.to_str()?.as_bytes();
    if name.len() < 7 {
        return None;
    }
    let digits = |s: &[u8]| -> Option<f64> {
        s.iter().try_fold(0.0, |acc, c| c.is_ascii_digit().then(|| acc * 10.0 + f64::from(c - b'0')))
    };
    let lat = match name[0].to_ascii_uppercase() {
        b'N' => 1.0,
        b'S' => -1.0,
        _ => return None,
    } * digits(&name[1..3])?;
    let lon = match name[3].to_ascii_uppercase() {
        b'E' => 1.0,
        b'W' => -1.0,
        _ => return None,
    } * digits(&name[4..7])?;
    ((-90.0..=89.0).contains(&lat) && (-180.0..=179.0).contains(&lon)).then_some(DVec2::new(lon, lat))
}

fn accepted_sizes() -> Vec<u64> {
    SIDES.iter().map(|&n| 2 * (n * n) as u64).collect()
}

/// Decodes a tile; `origin` overrides the corner the file name gives.
pub(crate) fn decode(
    bytes: &[u8],
    name: &Path,
    origin: Option<DVec2>,
    limits: Limits,
) -> Result<Heightfield, IoErrorKind> {
    let Some(&n) = SIDES.iter().find(|&&n| bytes.len() == 2 * n * n) else {
        return Err(IoErrorKind::WrongSize { found_bytes: bytes.len() as u64, accepted_bytes: accepted_sizes() });
    };
    limits.check(n as u64, n as u64)?;
    let origin = origin.or_else(|| tile_origin(name)).ok_or_else(|| {
        IoErrorKind::InvalidMetadata(
            "cannot place the tile: the file name must start with a tile name such as N36W085 \
             (or set ReadOptions::origin)"
                .to_owned(),
        )
    })?;
    let cell = 1.0 / (n - 1) as f64;
    let grid = GridSpec::geographic(n, n, origin, DVec2::splat(cell))
        .map_err(|e| IoErrorKind::InvalidMetadata(format!("tile origin {origin}: {e}")))?;
    let mut samples: Vec<f32> = bytes
        .chunks_exact(2)
        .map(|c| match i16::from_be_bytes([c[0], c[1]]) {
            VOID => f32::NAN,
            v => f32::from(v),
        })
        .collect();
    flip_rows(&mut samples, n);
    Ok(Heightfield::from_samples(grid, samples)?)
}

/// Encodes a 1201² or 3601² field; when `name` is a tile name, the grid must sit on that tile.
pub(crate) fn encode(hf: &Heightfield, name: Option<&Path>) -> Result<Vec<u8>, IoErrorKind> {
    let (nx, ny) = (hf.nx(), hf.ny());
    if nx != ny || !SIDES.contains(&nx) {
        return Err(IoErrorKind::Unsupported(format!(
            ".hgt holds 1201x1201 or 3601x3601 samples, this grid is {nx}x{ny}"
        )));
    }
    if let Some(corner) = name.and_then(tile_origin) {
        let g = hf.grid();
        let cell = 1.0 / (nx - 1) as f64;
        let near = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol;
        let fits = near(g.origin().x, corner.x, 1e-7)
            && near(g.origin().y, corner.y, 1e-7)
            && near(g.cell_size().x, cell, cell * 1e-6)
            && near(g.cell_size().y, cell, cell * 1e-6);
        if !fits {
            return Err(IoErrorKind::HeaderMismatch(format!(
                "the file name places the tile at ({}, {}) with {cell:.9}° cells, the grid starts at {} with \
                 cells of {}",
                corner.x,
                corner.y,
                g.origin(),
                g.cell_size()
            )));
        }
    }
    let (lo, hi) = (f64::from(VOID) + 1.0, f64::from(i16::MAX));
    let mut out = Vec::with_capacity(2 * nx * ny);
    for j in (0..ny).rev() {
        for (i, &v) in hf.row(j).iter().enumerate() {
            let code = if v.is_nan() {
                VOID
            } else {
                let r = f64::from(v).round();
                if !(lo..=hi).contains(&r) {
                    return Err(IoErrorKind::OutOfRange { i, j, value: v, min: lo, max: hi });
                }
                r as i16
            };
            out.extend_from_slice(&code.to_be_bytes());
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tile_names_give_the_south_west_corner() {
        let o = |s: &str| tile_origin(Path::new(s));
        assert_eq!(o("N36W085.hgt"), Some(DVec2::new(-85.0, 36.0)));
        assert_eq!(o("/data/srtm/s01e179.SRTMGL1.hgt"), Some(DVec2::new(179.0, -1.0)));
        assert_eq!(o("S90W180.hgt"), Some(DVec2::new(-180.0, -90.0)));
        assert_eq!(o("N90E000.hgt"), None, "a tile cannot start at the pole");
        assert_eq!(o("N36W85.hgt"), None);
        assert_eq!(o("X36W085.hgt"), None);
        assert_eq!(o("N3aW085.hgt"), None);
        assert_eq!(o("tile.hgt"), None);
    }

    #[test]
    fn voids_become_no_data_and_rows_flip() {
        let n = 1201;
        let mut bytes = vec![0u8; 2 * n * n];
        bytes[..2].copy_from_slice(&VOID.to_be_bytes()); // north-west corner
        bytes[2..4].copy_from_slice(&(-12i16).to_be_bytes());
        let hf = decode(&bytes, Path::new("N00E010.hgt"), None, Limits::default()).unwrap();
        assert!(hf.is_no_data(0, n - 1));
        assert_eq!(hf.value(1, n - 1), -12.0);
        assert_eq!(hf.no_data_count(), 1);
        assert_eq!(hf.grid().extent().max, DVec2::new(11.0, 1.0));
    }
}
