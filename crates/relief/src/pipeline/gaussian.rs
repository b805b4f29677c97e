//! A vector terrain (Perche et al. 2025): the source primitives, the tools in order, then the
//! raster.

use std::ops::ControlFlow;
use std::path::Path;

use super::inputs::{Env, raster_grid};
use super::progress::{Tick, Timer};
use super::summary::GaussianSummary;
use super::{Generated, Report};
use crate::gaussian_terrain::{
    Atlas, Landform, RasterOptions, Skeleton, SkeletonOptions, ToolContext, ToolError, VectorTerrain, VectorizeOptions,
    rasterize, vectorize,
};
use crate::heightfield::{GridSpec, Heightfield};
use crate::scene::{GaussianGenerator, GaussianSource, NoDataFill, Scene};
use crate::vector::crest_skeleton;
use crate::{ReliefError, ReliefError as E};

const GENERATOR: &str = "generator.gaussian";

/// The gaussian generator's run. The domain defaults to the source primitives' supports.
pub(super) fn generate(
    scene: &Scene,
    g: &GaussianGenerator,
    env: &Env<'_>,
    timer: &mut Timer<'_>,
) -> Result<Generated, ReliefError> {
    let at = format!("{GENERATOR}.source");
    let iterations = match &g.source {
        GaussianSource::Dem { iterations, .. } => *iterations as u64,
        _ => 0,
    };
    let mut terrain = timer.counted("source", iterations, |tick| load_source(&g.source, env, &at, tick))?;
    env.budget.primitives(terrain.len() as u64, &at)?;
    // The raster is in the primitives' coordinates: a vectorized DEM's own (degrees for a
    // geographic DEM, with its CRS), or what the terrain records, else planar metres.
    let grid = raster_grid(scene, scene.domain.unwrap_or_else(|| terrain.extent()))?
        .with_units(terrain.units())
        .map_err(|e| E::at("domain", e))?;
    let crs = terrain.crs.clone();
    // The session's landforms are in the terrain's units; the written atlas says so.
    let mut atlas = Atlas { units: Some(terrain.units()), ..Atlas::default() };
    timer.counted("tools", g.operations.len() as u64, |tick| {
        apply_tools(&mut terrain, &mut atlas, g, &grid, env, tick)
    })?;
    let heightfield = timer
        .step("rasterize", || rasterize(&terrain, &grid, &RasterOptions::default()).map_err(|e| E::at(GENERATOR, e)))?
        .with_crs(crs);
    let report = Report::Gaussian(GaussianSummary { primitives: terrain.len() });
    let extent = grid.extent();
    terrain.domain = Some([extent.min.to_array(), extent.max.to_array()]);
    let vector = Some(super::VectorResult { terrain, skeleton: g.skeleton, atlas });
    Ok(Generated { heightfield, sea_level: None, contours: None, report, warnings: Vec::new(), vector, layers: None })
}

/// The starting vector terrain: written in the scene, read from a file, or fitted to a DEM (in
/// the DEM's units and CRS; each fitting iteration a unit of `tick`; a cancelled run stops the
/// fit).
fn load_source(
    source: &GaussianSource,
    env: &Env<'_>,
    at: &str,
    tick: &mut Tick<'_>,
) -> Result<VectorTerrain, ReliefError> {
    match source {
        GaussianSource::Primitives(terrain) => Ok(terrain.clone()),
        GaussianSource::Terrain { path } => env.read_json(path, &format!("{at}.path")),
        GaussianSource::Dem {
            path,
            primitives,
            iterations,
            resolution,
            keep_range,
            details,
            beta_range,
            fill_no_data,
        } => {
            let dem = read_dem(env, path, *fill_no_data, at)?;
            let defaults = VectorizeOptions::default();
            let options = VectorizeOptions {
                primitives: *primitives,
                iterations: *iterations,
                resolution: *resolution,
                keep_range: *keep_range,
                detail_spacing: *details,
                beta_range: beta_range.unwrap_or(defaults.beta_range),
                ..defaults
            };
            let fitted = vectorize(&dem, &options, |p| {
                tick.reach(p.iteration as u64);
                if tick.cancelled() { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
            })
            .map_err(|e| E::at(at, e))?;
            // A fit stopped early is not the scene's terrain.
            tick.check()?;
            fitted.terrain.validate().map_err(|e| E::at(at, e))?;
            Ok(fitted.terrain)
        }
    }
}

/// The DEM at `path` with its no-data filled as `fill` says; refused, naming `fill_no_data`,
/// when it has no-data and no fill.
fn read_dem(env: &Env<'_>, path: &Path, fill: Option<NoDataFill>, at: &str) -> Result<Heightfield, ReliefError> {
    let mut dem = env.read(path).map_err(|e| E::at(format!("{at}.path"), e))?;
    let count = dem.no_data_count();
    match fill {
        _ if count == 0 => {}
        Some(fill) => {
            fill.fill(&mut dem).map_err(|e| E::at(format!("{at}.fill_no_data"), e))?;
        }
        None => {
            let why = format!(
                "the DEM has {count} no-data samples: set `fill_no_data` to \"min\" (its lowest elevation) or an elevation"
            );
            return Err(E::at(format!("{at}.fill_no_data"), why));
        }
    }
    Ok(dem)
}

/// Applies the generator's tools in order, checking the primitive budget after each (a stamp at
/// most doubles the terrain, so the work stays bounded) and before a paste.
fn apply_tools(
    terrain: &mut VectorTerrain,
    atlas: &mut Atlas,
    g: &GaussianGenerator,
    grid: &GridSpec,
    env: &Env<'_>,
    tick: &mut Tick<'_>,
) -> Result<(), ReliefError> {
    let mut cx = Tools { env, grid, options: g.skeleton, skeleton: None, here: String::new(), atlas };
    for (index, tool) in g.operations.iter().enumerate() {
        cx.here = format!("{GENERATOR}.operations[{index}]");
        tool.apply(terrain, &mut cx).map_err(|e| match e {
            ToolError::Tool(e) => E::at(&cx.here, e),
            ToolError::Context(e) => e,
        })?;
        env.budget.primitives(terrain.len() as u64, &cx.here)?;
        tick.tick();
        tick.check()?;
    }
    Ok(())
}

/// What the tools need from the scene: atlas files and the crest skeleton.
struct Tools<'a> {
    env: &'a Env<'a>,
    grid: &'a GridSpec,
    options: SkeletonOptions,
    /// Extracted on the first crest tool, from the terrain as it stands, then edited in place.
    skeleton: Option<Skeleton>,
    /// The JSON path of the tool being applied.
    here: String,
    /// The session's atlas: what `copy` and `cut` kept.
    atlas: &'a mut Atlas,
}

impl ToolContext for Tools<'_> {
    type Error = ReliefError;

    fn landform(&mut self, atlas: Option<&Path>, name: &str, terrain: &VectorTerrain) -> Result<Landform, ReliefError> {
        let landform = match atlas {
            Some(path) => {
                let at = format!("{}.atlas", self.here);
                let atlas: Atlas = self.env.read_json(path, &at)?;
                // Pasted across units, a landform would come out scaled by their ratio.
                if let Some(units) = atlas.units
                    && units != terrain.units()
                {
                    let (theirs, ours) = (units.name(), terrain.units().name());
                    return Err(E::at(at, format!("its landforms are in {theirs}, the terrain in {ours}")));
                }
                atlas.get(name).cloned()
            }
            None => self.atlas.get(name).cloned(),
        }
        .map_err(|e| E::at(format!("{}.landform", self.here), e))?;
        let pasted = (terrain.len() + landform.primitives.len()) as u64;
        self.env.budget.primitives(pasted, &format!("{}.landform", self.here))?;
        Ok(landform)
    }

    fn keep(&mut self, landform: Landform) -> Result<(), ReliefError> {
        self.atlas.landforms.retain(|l| l.name != landform.name);
        self.atlas.landforms.push(landform);
        let kept = self.atlas.landforms.iter().map(|l| l.primitives.len() as u64).sum();
        self.env.budget.primitives(kept, &format!("{}.name", self.here))
    }

    fn skeleton(&mut self, terrain: &VectorTerrain) -> Result<&mut Skeleton, ReliefError> {
        let skeleton = if let Some(skeleton) = self.skeleton.take() {
            skeleton
        } else {
            let hf = rasterize(terrain, self.grid, &RasterOptions::default()).map_err(|e| E::at(&self.here, e))?;
            let size = self.grid.extent().size().max_element();
            let (min_cells, spacing) = self.options.resolve(self.grid.len(), size);
            crest_skeleton(&hf, min_cells, spacing)?
        };
        Ok(self.skeleton.insert(skeleton))
    }
}
