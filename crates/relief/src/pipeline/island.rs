//! A sketched island (Puig-Centelles et al.): the start state, then the scene's operations.

use glam::DVec2;

use super::inputs::raster_grid;
use super::progress::Timer;
use super::summary::IslandSummary;
use super::{Generated, Report};
use crate::heightfield::Extent;
use crate::island::{Island, IslandError};
use crate::scene::{IslandGenerator, Scene};
use crate::{ReliefError, ReliefError as E};

const GENERATOR: &str = "generator.island";

/// The island generator's run. Sea is exactly 0 and land at least `land_floor`, so half the floor
/// is the sea level.
pub(super) fn generate(scene: &Scene, g: &IslandGenerator, timer: &mut Timer<'_>) -> Result<Generated, ReliefError> {
    let extent = scene.domain.unwrap_or_else(|| Extent::new(DVec2::ZERO, DVec2::splat(1000.0)));
    let grid = raster_grid(scene, extent)?;
    // The grid is the scene's resolution: the one error not about the generator's own values.
    let fail = |e: IslandError| match e {
        IslandError::Grid { .. } => E::at("reconstruction.resolution", e),
        e => E::located(GENERATOR, e),
    };
    let island = timer.step("island", || {
        let mut island = Island::new(grid, g.settings, scene.seed).map_err(fail)?;
        island.replay(&g.operations).map_err(fail)?;
        Ok::<_, ReliefError>(island)
    })?;
    let report = Report::Island(IslandSummary {
        coast_vertices: island.coastline().len(),
        area: island.area(),
        hills: island.hills().len(),
        perturbations: island.filters().len(),
    });
    let sea_level = Some(0.5 * g.settings.land_floor);
    Ok(Generated { heightfield: island.heightfield(), sea_level, contours: None, report, warnings: Vec::new() })
}
