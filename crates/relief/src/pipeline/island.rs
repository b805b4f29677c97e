//! A sketched island (Puig-Centelles et al.): the start state, then the scene's operations.

use glam::DVec2;

use super::inputs::{Env, raster_grid};
use super::progress::Timer;
use super::session::{EditSession, IslandKey};
use super::summary::IslandSummary;
use super::{Generated, Report};
use crate::contours::extract_dem;
use crate::error::SceneError;
use crate::heightfield::{Extent, GridSpec, Heightfield};
use crate::island::{EditKind, Hill, Island, IslandError, Operation};
use crate::scene::{CoastlineImage, IslandGenerator, LandTone, Scene};
use crate::{ReliefError, ReliefError as E};

const GENERATOR: &str = "generator.island";

/// The island generator's run. Sea is exactly 0 and land at least `land_floor`, so half the floor
/// is the sea level. With a `session`, the operations after those of an island it kept are
/// applied to that island, and the new island is kept.
pub(super) fn generate(
    scene: &Scene,
    g: &IslandGenerator,
    env: &Env<'_>,
    timer: &mut Timer<'_>,
    session: Option<&mut EditSession>,
) -> Result<Generated, ReliefError> {
    let extent = scene.domain.unwrap_or_else(|| Extent::new(DVec2::ZERO, DVec2::splat(1000.0)));
    let traced = g.coastline_image.as_ref().map(|image| traced_coastline(image, extent, env)).transpose()?;
    let grid = raster_grid(scene, extent)?;
    // The grid is the scene's resolution: the one error not about the generator's own values.
    let fail = |e: IslandError| match e {
        IslandError::Grid { .. } => E::at("reconstruction.resolution", e),
        e => E::located(GENERATOR, e),
    };
    // A session's kept island resumes (not with a traced coastline: its image may have changed).
    let key = IslandKey { grid, settings: g.settings, seed: scene.seed };
    let session = session.filter(|_| traced.is_none());
    let resumed = session.as_deref().and_then(|s| s.resume_island(&key, &g.operations));
    let resumed_from = resumed.as_ref().map_or(0, |r| r.0);
    let (island, mut warnings) = timer.counted("island", g.operations.len() as u64, |tick| {
        let (start, mut island, mut warnings) = match resumed {
            Some(resumed) => resumed,
            None => (0, Island::new(grid, g.settings, scene.seed).map_err(fail)?, Vec::new()),
        };
        // (A traced coastline never resumes: `start` is 0 here.)
        if let Some(points) = &traced {
            island.set_coastline(points).map_err(|e| E::at(format!("{GENERATOR}.coastline_image"), e))?;
        }
        if start > 0 {
            tick.reach(start as u64);
        }
        for (index, op) in g.operations.iter().enumerate().skip(start) {
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
            tick.check()?;
        }
        Ok::<_, ReliefError>((island, warnings))
    })?;
    let stroke_warnings = warnings.clone();
    warnings.extend(island.hills().iter().enumerate().filter_map(|(k, hill)| hill_warning(&island, k, hill)));
    let report = Report::Island(IslandSummary {
        coast_vertices: island.coastline().len(),
        area: island.area(),
        hills: island.hills().len(),
        perturbations: island.filters().len(),
    });
    let sea_level = Some(0.5 * g.settings.land_floor);
    let (heightfield, layers) = (island.heightfield(), island.layers());
    if let Some(session) = session {
        session.keep_island(key, &g.operations, island, stroke_warnings, resumed_from);
    }
    Ok(Generated { heightfield, sea_level, contours: None, report, warnings, vector: None, layers: Some(layers) })
}

/// The outline of the largest piece of land in `spec`'s image, counter-clockwise and closed (its
/// first point repeated), traced by marching squares at the threshold gray level: the image's
/// pixel centres span `spec.extent` (or the scene's domain). The image is framed by a pixel of
/// sea, so land running off its edge (a cropped map) ends in a straight coast half a pixel
/// beyond it. Errors name `generator.island.coastline_image`: an unreadable image, a flat one,
/// no land.
fn traced_coastline(spec: &CoastlineImage, domain: Extent, env: &Env<'_>) -> Result<Vec<DVec2>, ReliefError> {
    let at = format!("{GENERATOR}.coastline_image");
    let bad = |rule: &'static str, value: String| E::at(at.clone(), SceneError::OutOfRange { value, rule });
    let image = env.read_gray(&spec.path).map_err(|e| E::at(format!("{at}.path"), e))?;
    let grid = GridSpec::from_extent(image.nx(), image.ny(), spec.extent.unwrap_or(domain))
        .map_err(|e| E::at(format!("{at}.extent"), e))?;
    let gray = Heightfield::from_samples(grid, image.into_samples()).map_err(|e| E::at(format!("{at}.path"), e))?;
    let (lo, hi) = gray.min_max().ok_or_else(|| bad("an image with pixels", "no pixel".into()))?;
    let (lo, hi) = (f64::from(lo), f64::from(hi));
    let threshold = spec.threshold.unwrap_or(0.5 * (lo + hi));
    if !(threshold > lo && threshold < hi) {
        let value = format!("threshold {threshold} for gray levels {lo} to {hi}");
        return Err(bad("a threshold strictly between the image's darkest and lightest pixels", value));
    }
    // Light land: its outlines run counter-clockwise (higher inside); dark land: clockwise.
    let light = spec.land == LandTone::Light;
    let sign = if light { 1.0 } else { -1.0 };
    let framed = framed(&gray, if light { lo } else { hi } as f32).map_err(|e| E::at(at.clone(), e))?;
    let set = extract_dem(&framed, &[threshold]).map_err(|e| E::at(at.clone(), e))?;
    let outline = set
        .contours()
        .iter()
        .filter(|c| c.closed && sign * c.signed_area() > 0.0)
        .max_by(|a, b| a.signed_area().abs().total_cmp(&b.signed_area().abs()));
    let Some(outline) = outline else {
        return Err(bad("an image with land in it", format!("no pixel on the land side of {threshold}")));
    };
    let mut points = outline.points.clone();
    if sign < 0.0 {
        points.reverse();
    }
    points.push(points[0]);
    Ok(points)
}

/// `hf` with a one-sample frame of `sea` around it (the grid grown by a cell on every side).
fn framed(hf: &Heightfield, sea: f32) -> Result<Heightfield, crate::heightfield::HeightfieldError> {
    let (nx, ny) = (hf.nx(), hf.ny());
    let cell = hf.grid().cell_size();
    let grid = GridSpec::new(nx + 2, ny + 2, hf.grid().origin() - cell, cell)?;
    let mut samples = vec![sea; (nx + 2) * (ny + 2)];
    for (j, row) in hf.samples().chunks(nx).enumerate() {
        samples[(j + 1) * (nx + 2) + 1..(j + 1) * (nx + 2) + 1 + nx].copy_from_slice(row);
    }
    Heightfield::from_samples(grid, samples)
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
