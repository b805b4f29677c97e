//! The inputs the fuzz targets (`fuzz/`) exercise, as plain functions, so that the targets and
//! the regression tests over `fixtures/bad/` decode bytes the same way. Not part of the stable API.

use glam::DVec2;

use crate::eden_growth::{EdenError, Graph, GraphOptions, LabelMap, MaskOptions, Region, RegionTree, Sampling};
use crate::heightfield::{GridSpec, Heightfield};
use crate::io::{Format, IoError, Limits, ReadOptions};
use crate::poisson_sampling::Polygon;
use crate::{ReliefError, Scene};

/// The cell cap of [`read`]: small, so that an allocation beyond it would show.
pub const MAX_CELLS: u64 = 1 << 20;

/// Decodes `bytes` as `format` under [`MAX_CELLS`].
///
/// # Errors
/// The reader's typed error.
pub fn read(bytes: &[u8], format: Format) -> Result<Heightfield, IoError> {
    let name = match format {
        Format::Hgt => "N00E000.hgt".to_owned(),
        other => format!("fuzz.{}", other.extension()),
    };
    let options = ReadOptions::default().with_limits(Limits::default().with_max_cells(MAX_CELLS));
    crate::io::read_bytes(bytes, format, name, &options)
}

/// Parses `bytes` as a scene file.
///
/// # Errors
/// [`ReliefError::Scene`] for text that is not UTF-8 or not a valid scene.
pub fn scene_json(bytes: &[u8]) -> Result<Scene, ReliefError> {
    let text = std::str::from_utf8(bytes).map_err(|e| ReliefError::at("", e))?;
    Scene::from_json(text)
}

/// A small label image (bytes 0 and 1 give the size, 1 to 48 pixels a side; the rest the gray
/// values, 0 past the end), cleaned as a drawn mask, and its growth graph at 64 particles.
///
/// # Errors
/// [`ReliefError::Scene`] at `label_image` wrapping the [`EdenError`]: a map that is not a label
/// map, or a level that holds no node.
pub fn label_image(bytes: &[u8]) -> Result<Graph, ReliefError> {
    let fail = |e: EdenError| ReliefError::at("label_image", e);
    let (nx, ny, rest) = match bytes {
        [a, b, rest @ ..] => (usize::from(a % 48) + 1, usize::from(b % 48) + 1, rest),
        _ => (1, 1, &[][..]),
    };
    let grid = GridSpec::new(nx, ny, DVec2::ZERO, DVec2::ONE).map_err(|e| ReliefError::at("label_image", e))?;
    let pixels: Vec<[f32; 4]> = (0..nx * ny)
        .map(|k| {
            let v = f32::from(rest.get(k).copied().unwrap_or(0)) / 255.0;
            [v, v, v, 1.0]
        })
        .collect();
    let options = MaskOptions { levels: None, sampling: Sampling::Particles(64) };
    let labels = LabelMap::from_mask(grid, &pixels, &options)
        .map_err(fail)?
        .with_depressions(rest.first().is_some_and(|v| v & 1 == 1));
    Graph::from_labels(&labels, &GraphOptions::particles(64)).map_err(fail)
}

/// Up to four polygons with vertices on a byte grid (so edges touch, cross and repeat often):
/// per polygon a head byte (low bits: 3 to 15 vertices; bit 6: a height from the low 6 bits;
/// bit 7: a depression) then the vertices' coordinate bytes; their region tree and growth graph
/// at 64 particles.
///
/// # Errors
/// [`ReliefError::Scene`] at `regions[i].polygon` for an invalid polygon, at `regions` wrapping
/// the [`EdenError`] for an invalid region set or a region that holds no node.
pub fn polygon_regions(bytes: &[u8]) -> Result<Graph, ReliefError> {
    let mut bytes = bytes.iter().copied();
    let mut regions = Vec::new();
    for _ in 0..4 {
        let Some(head) = bytes.next() else { break };
        let n = 3 + usize::from(head % 13);
        let ring: Vec<DVec2> =
            (0..n).map_while(|_| Some(DVec2::new(f64::from(bytes.next()?), f64::from(bytes.next()?)))).collect();
        let polygon = Polygon::from_exterior(ring)
            .map_err(|e| ReliefError::at(format!("regions[{}].polygon", regions.len()), e))?;
        let mut region = Region::new(polygon);
        if head & 0x80 != 0 {
            region = region.as_depression();
        }
        if head & 0x40 != 0 {
            region = region.with_height(f64::from(head & 0x3f));
        }
        regions.push(region);
    }
    let fail = |e: EdenError| ReliefError::at("regions", e);
    Graph::from_regions(&RegionTree::new(regions).map_err(fail)?, &GraphOptions::particles(64)).map_err(fail)
}
