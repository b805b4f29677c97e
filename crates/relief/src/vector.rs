//! Vector terrains (Perche et al. 2025) in scenes: the sources of a `gaussian` generator, its
//! tool operations, and the crest skeleton, which needs the hydrology crate's flow routing on
//! the inverted DEM (`relief-gaussian-terrain` sits below hydrology, so the facade joins them).

use std::ops::ControlFlow;
use std::path::Path;

use glam::DVec2;
use relief_gaussian_terrain::{
    Atlas, GaussianError, RasterOptions, Region, Skeleton, VectorTerrain, VectorizeOptions, paste, rasterize, squeeze,
    stamp, twist,
};
use relief_heightfield::{Extent, GridSpec, Heightfield};
use relief_hydrology::{D8, NO_RECEIVER, Outlets};

use crate::ReliefError;
use crate::budget::Env;
use crate::scene::{GaussianGenerator, GaussianOperation, GaussianSource};

/// The crest skeleton of `hf` (§5.1): crest cells are those where the flow accumulation of the
/// inverted, depression-filled DEM reaches `min_cells` cells; each links to its downstream crest
/// neighbour; the graph is then simplified by edge collapse at spacing `d0`.
///
/// # Errors
/// [`ReliefError::Pipeline`] for an all-no-data field.
pub fn crest_skeleton(hf: &Heightfield, min_cells: u32, d0: f64) -> Result<Skeleton, ReliefError> {
    let fail = |e: &dyn std::fmt::Display| ReliefError::pipeline("skeleton", e);
    let inverted = hf.map(|v| -v).map_err(|e| fail(&e))?;
    let filled = relief_hydrology::fill(&inverted, Outlets::new()).map_err(|e| fail(&e))?;
    let routed = D8::new(&filled).map_err(|e| fail(&e))?;
    let accumulation = routed.accumulation();
    let grid = hf.grid();
    let mut index = vec![usize::MAX; grid.len()];
    let mut points = Vec::new();
    for (k, &a) in accumulation.iter().enumerate() {
        if a >= min_cells.max(1) {
            index[k] = points.len();
            let (i, j) = grid.coords(k);
            points.push(grid.position(i, j));
        }
    }
    let down: Vec<Option<usize>> = (0..grid.len())
        .filter(|&k| index[k] != usize::MAX)
        .map(|k| {
            let r = routed.receivers()[k];
            (r != NO_RECEIVER && index[r as usize] != usize::MAX).then(|| index[r as usize])
        })
        .collect();
    let full = Skeleton::from_flow(&points, &down).map_err(|e| fail(&e))?;
    Ok(full.simplified(d0))
}

/// The generator's starting vector terrain.
pub(crate) fn load_source(source: &GaussianSource, env: &Env<'_>, at: &str) -> Result<VectorTerrain, ReliefError> {
    let terrain = match source {
        GaussianSource::Primitives { primitives, base } => {
            VectorTerrain { base: *base, primitives: primitives.clone(), domain: None, details: Vec::new() }
        }
        GaussianSource::Terrain { path } => read_json(&env.join(path), &format!("{at}.path"))?,
        GaussianSource::Dem { path, primitives, iterations, resolution } => {
            let dem = env.read(path).map_err(|e| ReliefError::scene(format!("{at}.path"), e))?;
            let options = VectorizeOptions {
                primitives: *primitives,
                iterations: *iterations,
                resolution: *resolution,
                ..VectorizeOptions::default()
            };
            relief_gaussian_terrain::vectorize(&dem, &options, |_| ControlFlow::Continue(()))
                .map_err(|e| ReliefError::scene(at.to_string(), e))?
                .terrain
        }
    };
    terrain.validate().map_err(|e| ReliefError::scene(at.to_string(), e))?;
    Ok(terrain)
}

/// A JSON file of the scene, its read and parse errors named at the scene path `at`.
pub(crate) fn read_json<T: serde::de::DeserializeOwned>(path: &Path, at: &str) -> Result<T, ReliefError> {
    let fail = |e: &dyn std::fmt::Display| ReliefError::scene(at.to_string(), format!("{}: {e}", path.display()));
    let text = crate::budget::read_json_text(path).map_err(|e| fail(&e))?;
    serde_json::from_str(&text).map_err(|e| fail(&e))
}

/// The default domain of a vector terrain: its recorded domain, else its primitives' supports,
/// else 1000 × 1000.
pub fn default_extent(terrain: &VectorTerrain) -> Extent {
    if let Some([lo, hi]) = terrain.domain {
        return Extent::new(DVec2::from(lo), DVec2::from(hi));
    }
    let mut bounds: Option<(DVec2, DVec2)> = None;
    for g in &terrain.primitives {
        let (lo, hi) = g.bounds(relief_gaussian_terrain::DEFAULT_TOLERANCE);
        bounds = Some(bounds.map_or((lo, hi), |(a, b)| (a.min(lo), b.max(hi))));
    }
    match bounds {
        Some((lo, hi)) if (hi - lo).min_element() > 0.0 => Extent::new(lo, hi),
        _ => Extent::new(DVec2::ZERO, DVec2::splat(1000.0)),
    }
}

/// Applies the generator's operations in order; a crest operation extracts the skeleton from
/// the terrain as it stands (once, then edits it in place).
pub(crate) fn apply_operations(
    terrain: &mut VectorTerrain,
    generator: &GaussianGenerator,
    grid: &GridSpec,
    env: &Env<'_>,
    at: &str,
) -> Result<(), ReliefError> {
    let mut skeleton: Option<Skeleton> = None;
    for (index, op) in generator.operations.iter().enumerate() {
        let here = format!("{at}.operations[{index}]");
        let wrap = |e: GaussianError| ReliefError::scene(here.clone(), e);
        match op {
            GaussianOperation::Stamp { region, placement, mode, damping } => {
                stamp(terrain, region, placement, *mode, *damping).map_err(wrap)?;
            }
            GaussianOperation::Paste { atlas, landform, footprint, placement, damping } => {
                let atlas: Atlas = read_json(&env.join(atlas), &format!("{here}.atlas"))?;
                atlas.validate().map_err(wrap)?;
                let landform = atlas.get(landform).map_err(wrap)?;
                let pasted = (terrain.len() + landform.primitives.len()) as u64;
                env.budget.primitives(pasted, &format!("{here}.landform"))?;
                let footprint = Region::Circle { center: [0.0, 0.0], radius: *footprint };
                paste(terrain, landform, &footprint, placement, *damping).map_err(wrap)?;
            }
            GaussianOperation::Delete { region } => {
                relief_gaussian_terrain::delete(terrain, region).map_err(wrap)?;
            }
            GaussianOperation::Twist { region, angle, falloff } => {
                twist(terrain, region, *angle, *falloff).map_err(wrap)?;
            }
            GaussianOperation::Squeeze { region, by, falloff } => {
                squeeze(terrain, region, DVec2::from(*by), *falloff).map_err(wrap)?;
            }
            GaussianOperation::MoveCrest { near, by, reach } => {
                let s = crest(&mut skeleton, terrain, generator, grid, &here)?;
                let attached = s.attach(terrain);
                let node = s.nearest_node(DVec2::from(*near)).ok_or_else(|| no_crest(&here))?;
                s.move_node(terrain, &attached, node, DVec2::from(*by), *reach).map_err(wrap)?;
            }
            GaussianOperation::RaiseCrest { near, factor, reach } => {
                let s = crest(&mut skeleton, terrain, generator, grid, &here)?;
                let attached = s.attach(terrain);
                let node = s.nearest_node(DVec2::from(*near)).ok_or_else(|| no_crest(&here))?;
                s.scale_amplitude(terrain, &attached, node, *factor, *reach).map_err(wrap)?;
            }
        }
        // A stamp at most doubles the terrain, so checking after each tool keeps the work bounded.
        env.budget.primitives(terrain.len() as u64, &here)?;
    }
    Ok(())
}

fn no_crest(at: &str) -> ReliefError {
    ReliefError::scene(
        at.to_string(),
        "the terrain has no crest skeleton (lower generator.gaussian.skeleton.min_cells)",
    )
}

/// The skeleton, extracted on first use from the terrain rasterized at the scene's grid.
fn crest<'a>(
    skeleton: &'a mut Option<Skeleton>,
    terrain: &VectorTerrain,
    generator: &GaussianGenerator,
    grid: &GridSpec,
    at: &str,
) -> Result<&'a mut Skeleton, ReliefError> {
    if skeleton.is_none() {
        let hf =
            rasterize(terrain, grid, &RasterOptions::default()).map_err(|e| ReliefError::scene(at.to_string(), e))?;
        let spec = &generator.skeleton;
        let size = grid.extent().size().max_element();
        let min_cells = spec.min_cells.unwrap_or_else(|| (grid.len() / 500).max(4) as u32);
        let spacing = spec.spacing.unwrap_or(0.03 * size);
        *skeleton = Some(crest_skeleton(&hf, min_cells, spacing)?);
    }
    skeleton.as_mut().ok_or_else(|| no_crest(at))
}
