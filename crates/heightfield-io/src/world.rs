//! ESRI world files (`.tfw`, `.tifw`, `.wld`): six numbers placing an image without geo tags —
//! pixel width A, rotations D and B, pixel height E (negative for north-up), and the centre (C, F)
//! of the upper-left pixel, one per line in the order A, D, B, E, C, F.

use std::path::{Path, PathBuf};

use glam::DVec2;
use relief_heightfield::{GridSpec, Heightfield};

use crate::IoErrorKind;

/// The world files that may sit beside `path`, in the order GDAL tries them.
pub(crate) fn candidates(path: &Path) -> Vec<PathBuf> {
    ["tfw", "tifw", "wld"].iter().map(|ext| path.with_extension(ext)).collect()
}

/// `hf` placed by the world file `text`: cell size (A, −E), the south-west sample at
/// (C, F + E·(ny − 1)). Units stay as they were (metres): a world file names no CRS.
pub(crate) fn place(hf: Heightfield, text: &str) -> Result<Heightfield, IoErrorKind> {
    let bad = |m: String| IoErrorKind::InvalidMetadata(format!("world file: {m}"));
    let values: Vec<f64> = text
        .split_whitespace()
        .map(|t| t.parse::<f64>().map_err(|_| bad(format!("{t:?} is not a number"))))
        .collect::<Result<_, _>>()?;
    let [a, d, b, e, c, f] = values[..] else {
        return Err(bad(format!("{} numbers, expected 6 (A, D, B, E, C, F)", values.len())));
    };
    if values.iter().any(|v| !v.is_finite()) {
        return Err(bad("a value is not finite".to_owned()));
    }
    if d != 0.0 || b != 0.0 {
        return Err(IoErrorKind::Unsupported("a rotated world file (D or B not 0)".to_owned()));
    }
    if !(a > 0.0 && e < 0.0) {
        return Err(IoErrorKind::Unsupported(format!("pixel size ({a}, {e}): only north-up rasters are read")));
    }
    let ny = hf.ny();
    let origin = DVec2::new(c, f + e * (ny.saturating_sub(1)) as f64);
    let grid = GridSpec::new(hf.nx(), ny, origin, DVec2::new(a, -e))?.with_units(hf.grid().units())?;
    Ok(Heightfield::from_samples(grid, hf.into_samples())?)
}
