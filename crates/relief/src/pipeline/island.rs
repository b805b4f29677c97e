//! A sketched island (Puig-Centelles et al.): the start state, then the scene's operations.

use glam::DVec2;

use super::inputs::raster_grid;
use super::progress::Timer;
use super::summary::IslandSummary;
use super::{Generated, Report};
use crate::heightfield::Extent;
use crate::island::{EditKind, Hill, Island, IslandError, Operation};
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
    let (island, mut warnings) = timer.counted("island", g.operations.len() as u64, |tick| {
        let mut island = Island::new(grid, g.settings, scene.seed).map_err(fail)?;
        let mut warnings = Vec::new();
        for (index, op) in g.operations.iter().enumerate() {
            let before = island.area();
            let kinds = match op {
                Operation::Stroke { points } => {
                    let points: Vec<DVec2> = points.iter().map(|&p| DVec2::from(p)).collect();
                    island.stroke(&points).map(Some)
                }
                op => island.apply(op).map(|()| None),
            }
            .map_err(|e| fail(IslandError::Operation { index, source: Box::new(e) }))?;
            warnings.extend(kinds.and_then(|kinds| stroke_warning(index, &kinds, before, island.area())));
            tick.tick();
        }
        Ok::<_, ReliefError>((island, warnings))
    })?;
    warnings.extend(island.hills().iter().enumerate().filter_map(|(k, hill)| hill_warning(&island, k, hill)));
    let report = Report::Island(IslandSummary {
        coast_vertices: island.coastline().len(),
        area: island.area(),
        hills: island.hills().len(),
        perturbations: island.filters().len(),
    });
    let sea_level = Some(0.5 * g.settings.land_floor);
    Ok(Generated { heightfield: island.heightfield(), sea_level, contours: None, report, warnings, vector: None })
}

/// A stroke that left less than half the land: most likely drawn the other way round from what
/// was meant, since its direction decides which side stays.
fn stroke_warning(index: usize, kinds: &[EditKind], before: f64, after: f64) -> Option<String> {
    if after >= 0.5 * before {
        return None;
    }
    let lost = 100.0 * (1.0 - after / before);
    let how = if kinds.contains(&EditKind::Cut) {
        "it cuts off the land left of its direction, here the larger part; draw it the other way to cut off the \
         smaller part"
    } else {
        "drawn counter-clockwise around sea, it makes the island the area it encloses; draw it clockwise to add \
         that area instead"
    };
    Some(format!("{GENERATOR}.operations[{index}]: the stroke removed {lost:.0} % of the land: {how}"))
}

/// A hill that changes nothing: outside the domain, or over sea only (hills raise land).
fn hill_warning(island: &Island, k: usize, hill: &Hill) -> Option<String> {
    let grid = island.grid();
    let (lo, hi) = hill.bounds();
    let extent = grid.extent();
    let [x, y] = hill.center;
    if hi.x < extent.min.x || hi.y < extent.min.y || lo.x > extent.max.x || lo.y > extent.max.y {
        return Some(format!("{GENERATOR}: hill {k} (centre {x}, {y}) lies outside the domain and changes nothing"));
    }
    let land = island.land();
    // The samples under the hill's bounds only.
    let (origin, cell) = (grid.origin(), grid.cell_size());
    let index = |v: f64, o: f64, c: f64, n: usize| (((v - o) / c).max(0.0) as usize).min(n - 1);
    let (i0, i1) = (index(lo.x, origin.x, cell.x, grid.nx()), index(hi.x, origin.x, cell.x, grid.nx()) + 1);
    let (j0, j1) = (index(lo.y, origin.y, cell.y, grid.ny()), index(hi.y, origin.y, cell.y, grid.ny()) + 1);
    let touches = (j0..=j1.min(grid.ny() - 1))
        .flat_map(|j| (i0..=i1.min(grid.nx() - 1)).map(move |i| (i, j)))
        .any(|(i, j)| land[j * grid.nx() + i] && hill.at(grid.position(i, j)) != 0.0);
    (!touches).then(|| {
        format!(
            "{GENERATOR}: hill {k} (centre {x}, {y}) lies in the sea and changes nothing (hills raise land only): \
             move it onto the island or grow the coast to it"
        )
    })
}
