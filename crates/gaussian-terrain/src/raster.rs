//! Rasterizing a vector terrain (§6.1): the base, the primitives through the binned kernel
//! (module `kernel`) and the detail layers, at any resolution and window; and the untruncated f64
//! reference.

use rayon::prelude::*;
use relief_heightfield::{GridSpec, Heightfield};

use crate::kernel::raster_samples;
use crate::{DetailLayer, GaussianError, VectorTerrain};

/// The largest output grid: 2²⁸ samples (a 16384² grid, 1 GiB of f32).
pub const MAX_RASTER_CELLS: usize = 1 << 28;

/// How to rasterize.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RasterOptions {
    /// Each primitive is cut off where it falls below `tolerance·|a|` (default 10⁻³); see
    /// [`crate::Gaussian::support_radius`]. In `(0, 1)`.
    pub tolerance: f64,
}

impl Default for RasterOptions {
    fn default() -> Self {
        Self { tolerance: crate::DEFAULT_TOLERANCE }
    }
}

/// Evaluates `terrain` at every sample of `grid` (any resolution, any window of the plane):
/// the base plus the primitives truncated at their support radius, raised to the floor if any,
/// plus the detail layers (error at most
/// `tolerance · Σ|a|` over the primitives reaching a sample, plus f32 rounding).
///
/// # Errors
/// The terrain's [`VectorTerrain::validate`] errors; [`GaussianError::InvalidOption`] for a
/// tolerance outside `(0, 1)`; [`GaussianError::GridTooLarge`] above [`MAX_RASTER_CELLS`];
/// [`GaussianError::Raster`] when a sum overflows f32.
///
/// # Example
/// ```
/// use glam::DVec2;
/// use relief_gaussian_terrain::{Gaussian, RasterOptions, VectorTerrain, rasterize};
/// use relief_heightfield::{Extent, GridSpec};
///
/// let terrain = VectorTerrain::new(vec![Gaussian::round(DVec2::new(50.0, 50.0), 10.0, 100.0)]);
/// let grid = GridSpec::from_extent(101, 101, Extent::new(DVec2::ZERO, DVec2::splat(100.0)))?;
/// let h = rasterize(&terrain, &grid, &RasterOptions::default())?;
/// assert!((h.value(50, 50) - 100.0).abs() < 1e-3);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn rasterize(
    terrain: &VectorTerrain,
    grid: &GridSpec,
    options: &RasterOptions,
) -> Result<Heightfield, GaussianError> {
    let tolerance = options.tolerance;
    if !(tolerance > 0.0 && tolerance < 1.0) {
        return Err(GaussianError::InvalidOption { name: "tolerance", value: tolerance, reason: "must be in (0, 1)" });
    }
    terrain.validate()?;
    let (nx, ny) = (grid.nx(), grid.ny());
    if grid.len() > MAX_RASTER_CELLS {
        return Err(GaussianError::GridTooLarge { nx, ny, limit: MAX_RASTER_CELLS });
    }
    let mut samples = raster_samples(&terrain.primitives, grid, tolerance);
    if terrain.base != 0.0 {
        let base = terrain.base as f32;
        samples.par_iter_mut().for_each(|s| *s += base);
    }
    if let Some(floor) = terrain.floor {
        let floor = floor as f32;
        samples.par_iter_mut().for_each(|s| *s = s.max(floor));
    }
    let ground = terrain.details.iter().any(DetailLayer::is_modulated).then(|| samples.clone());
    for layer in &terrain.details {
        layer.add_to(grid, &mut samples, ground.as_deref(), tolerance);
    }
    Ok(Heightfield::from_samples(*grid, samples)?)
}

/// The reference: every primitive at every sample, untruncated, summed in f64. O(primitives ×
/// samples): for tests and small grids.
///
/// # Errors
/// As [`rasterize`] (the tolerance is not used).
pub fn rasterize_exact(terrain: &VectorTerrain, grid: &GridSpec) -> Result<Heightfield, GaussianError> {
    terrain.validate()?;
    let (nx, ny) = (grid.nx(), grid.ny());
    if grid.len() > MAX_RASTER_CELLS {
        return Err(GaussianError::GridTooLarge { nx, ny, limit: MAX_RASTER_CELLS });
    }
    Ok(Heightfield::from_fn(*grid, |p| terrain.height_at(p) as f32)?)
}
