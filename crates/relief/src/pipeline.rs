//! Scene → terrain: the steps of the contours pipeline (graph, growth, heights, contours, edits,
//! reconstruction) and the writing of every output, with progress reports and a run summary.
//!
//! Every scene value is checked before the expensive work starts, and a bad one fails with a
//! [`ReliefError::Scene`] naming its JSON path (`generator.contours.regions[2].polygon`,
//! `edits[1].radius`, …), whichever step discovers it.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use glam::DVec2;
use serde::Serialize;

use crate::ReliefError;
use crate::budget::{Budget, Env};
use crate::contours::{
    Contour, ContourSet, ContoursError, Histogram, Interpolation, Ranking, Smoothing, Summit, assign_heights,
    evenly_spaced_levels, extract_dem, extract_tin, interval_levels, reconstruct_interpolated, reconstruct_stairs,
};
use crate::diffusion::{
    self, Constraint, DiffusionError, FeatureCurve, SolveOptions, SolveReport, Solver, TerrainOptions,
};
use crate::eden_growth::{
    EdenError, FbmProbability, Graph, GraphOptions, LabelMap, ProbabilityMap, RasterProbability, Region, RegionTree,
    Sampling, Uniform, grow,
};
use crate::gaussian_terrain::{RasterOptions, rasterize};
use crate::heightfield::noise::Fbm;
use crate::heightfield::{Extent, GridSpec, Heightfield, fill_depressions};
use crate::hydrology::{self, D8, Field, HydrologyError, Outlets, StreamPower, Thermal};
use crate::io::Format;
use crate::island::{Island, IslandError};
use crate::poisson_sampling::{Polygon, Rect};
use crate::scene::{
    ContoursGenerator, DiffusionGenerator, Edit, GaussianGenerator, Generator, HistogramSource, IslandGenerator,
    Levels, OrometryGenerator, OrometrySource, Outputs, PostProcess, Probability, ReconstructionMode, Rectangle, Scene,
    SolverSpec, TreeEdit,
};
use crate::tin::PointLocator;
use crate::vector;
use crate::warp::{PathOptions, PathWarp, Profile, SlopeModulation, Warp, WarpError, warp_polyline, warp_raster};
use rayon::prelude::*;

/// Default node count when a scene gives neither `particles` nor `radius`.
pub const DEFAULT_PARTICLES: usize = 50_000;

/// Largest raster side a scene may ask for.
pub const MAX_RESOLUTION: usize = 16_384;

/// Most contour levels a scene may ask for.
pub const MAX_LEVELS: usize = 10_000;

/// Width of the SVG drawing, in pixels.
const SVG_WIDTH: u32 = 1024;

/// Receives the pipeline's progress: each step starts, then finishes. Steps are named
/// `"inputs"`, `"graph"`, `"growth"`, `"heights"`, `"contours"`, `"edits"`, `"reconstruction"` and
/// `"write"`. The unit type `()` ignores everything.
pub trait Progress {
    /// `step` starts.
    fn start(&mut self, step: &'static str);
    /// `step` finished after `elapsed`.
    fn finish(&mut self, step: &'static str, elapsed: Duration);
}

impl Progress for () {
    fn start(&mut self, _: &'static str) {}
    fn finish(&mut self, _: &'static str, _: Duration) {}
}

/// The time one step took.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Timing {
    /// The step.
    pub step: &'static str,
    /// Milliseconds.
    pub ms: f64,
}

/// Forwards to the caller's [`Progress`] and keeps the timings for the summary.
struct Timer<'a> {
    progress: &'a mut dyn Progress,
    timings: Vec<Timing>,
}

impl Timer<'_> {
    fn step<T>(&mut self, step: &'static str, f: impl FnOnce() -> T) -> T {
        self.progress.start(step);
        let start = Instant::now();
        let out = f();
        let elapsed = start.elapsed();
        self.progress.finish(step, elapsed);
        self.timings.push(Timing { step, ms: elapsed.as_secs_f64() * 1e3 });
        out
    }
}

/// Graph statistics of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GraphSummary {
    /// Nodes in Ω ⊕ B(4r).
    pub nodes: usize,
    /// Nodes inside Ω (ranked by the growth).
    pub inside: usize,
    /// Poisson-disc radius, world units.
    pub radius: f64,
    /// Nodes raised to fill enclosed basins the scene did not mark as depressions.
    pub filled_nodes: usize,
    /// Nesting levels of the input (1 = the coastline alone).
    pub levels: u16,
}

/// Contour statistics of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContourSummary {
    /// Levels extracted (the requested ones plus the input contours' own).
    pub levels: usize,
    /// Contours after the edits.
    pub contours: usize,
    /// Their vertices.
    pub vertices: usize,
}

/// Raster statistics of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RasterSummary {
    /// Samples along x.
    pub nx: usize,
    /// Samples along y.
    pub ny: usize,
    /// World rectangle of the samples.
    pub domain: Rectangle,
    /// Lowest sample.
    pub min: f32,
    /// Highest sample.
    pub max: f32,
    /// Height of the coastline: lower samples are sea.
    pub sea_level: f64,
}

/// Drainage of the final heightfield (`relief-hydrology`; the sea and the map border drain).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DrainageSummary {
    /// Closed basins (water cannot leave them): craters the scene asked for, or none.
    pub closed_basins: usize,
    /// Water they hold up to their spill levels, m³ (in world units cubed).
    pub closed_volume: f64,
    /// Largest Strahler order of the D8 stream network (streams from 0.5 % of the land area).
    pub max_strahler: u8,
}

/// How well the elevations match the scene's histogram: Kolmogorov–Smirnov distances (the largest
/// gap between the cumulative distributions; 0 is a perfect match).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HistogramMatch {
    /// Over the graph nodes inside Ω (≤ 1/(2N) by construction).
    pub nodes: f64,
    /// Over the raster samples on land (at or above sea level), after edits and reconstruction.
    pub raster: f64,
}

/// What a run did: the scene, counts, histogram match and timings (written as `summary.json`).
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// Version of relief that ran.
    pub relief_version: &'static str,
    /// The scene as read (defaults filled in).
    pub scene: Scene,
    /// Graph statistics (contour generator only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub graph: Option<GraphSummary>,
    /// Contour statistics.
    pub contours: ContourSummary,
    /// Raster statistics.
    pub heightfield: RasterSummary,
    /// Histogram match errors (contour generator only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub histogram_match: Option<HistogramMatch>,
    /// How the diffusion solve went (diffusion generator only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub diffusion: Option<SolveReport>,
    /// The island's final shape (island generator only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub island: Option<IslandSummary>,
    /// The vector terrain after its tools (gaussian generator only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gaussian: Option<GaussianSummary>,
    /// The divide tree and its match to the target (orometry generator only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub orometry: Option<OrometrySummary>,
    /// Closed basins and stream order of the final heightfield.
    pub drainage: DrainageSummary,
    /// Time per step, in order (they vary from run to run, unlike everything else).
    pub timings_ms: Vec<Timing>,
}

/// What an orometry scene ended with.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OrometrySummary {
    /// Peaks in the divide tree (after edits).
    pub peaks: usize,
    /// Saddles in the divide tree.
    pub saddles: usize,
    /// Earth mover's distance between the tree's prominence histogram and the target's.
    pub prominence_emd: f64,
    /// Largest bin difference between the tree's prominence histogram and the target's.
    pub prominence_max_bin_error: f64,
    /// Largest bin difference between the tree's dominance histogram and the target's.
    pub dominance_max_bin_error: f64,
    /// The tree itself (written by `outputs.divide_tree`, not into the summary).
    #[serde(skip)]
    pub tree: crate::orometry::DivideTree,
}

/// What a gaussian scene ended with.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GaussianSummary {
    /// Gaussian primitives after the tools.
    pub primitives: usize,
}

/// What an island scene ended with.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IslandSummary {
    /// Vertices of the coastline.
    pub coast_vertices: usize,
    /// Area inside the coastline, world units².
    pub area: f64,
    /// Hills placed.
    pub hills: usize,
    /// Perturbations the filters added.
    pub perturbations: usize,
}

/// A generated terrain: the heightfield, the contours it was rebuilt from, and the run summary.
#[derive(Debug, Clone)]
pub struct Terrain {
    /// The reconstructed heightfield.
    pub heightfield: Heightfield,
    /// The contours after the edits.
    pub contours: ContourSet,
    /// The histogram the elevations follow.
    pub histogram: Histogram,
    /// Height of the coastline.
    pub sea_level: f64,
    /// The run summary (timings cover generation; [`write_outputs`] adds its own).
    pub summary: Summary,
}

/// Reads a scene file.
///
/// # Errors
/// [`ReliefError::File`] when it cannot be read, [`ReliefError::Scene`] when it is not a valid scene.
pub fn load_scene(path: impl AsRef<Path>) -> Result<Scene, ReliefError> {
    let path = path.as_ref();
    let text =
        crate::budget::read_json_text(path).map_err(|source| ReliefError::File { path: path.to_owned(), source })?;
    Scene::from_json(&text)
}

/// Generates the terrain of `scene`; relative paths in it resolve against `base_dir` (the scene
/// file's directory).
///
/// # Errors
/// [`ReliefError::Scene`] naming the JSON path of any invalid value; [`ReliefError::Io`] when an
/// input file cannot be read.
pub fn generate(scene: &Scene, base_dir: &Path, progress: &mut dyn Progress) -> Result<Terrain, ReliefError> {
    generate_with(scene, base_dir, &Budget::default(), progress)
}

/// [`generate`] under an explicit [`Budget`]: a scene asking for more cells, particles,
/// primitives or peaks fails before the work that would allocate them.
///
/// # Errors
/// As [`generate`], and [`ReliefError::OverBudget`].
pub fn generate_with(
    scene: &Scene,
    base_dir: &Path,
    budget: &Budget,
    progress: &mut dyn Progress,
) -> Result<Terrain, ReliefError> {
    budget.check(scene)?;
    let env = &Env { dir: base_dir, budget: *budget };
    let mut timer = Timer { progress, timings: Vec::new() };
    match &scene.generator {
        Generator::Contours(generator) => generate_contours(scene, generator, env, &mut timer),
        Generator::Diffusion(generator) => generate_diffusion(scene, generator, &mut timer),
        Generator::Island(generator) => generate_island(scene, generator, &mut timer),
        Generator::Gaussian(generator) => generate_gaussian(scene, generator, env, &mut timer),
        Generator::Orometry(generator) => generate_orometry(scene, generator, env, &mut timer),
    }
}

/// The contours paper's pipeline.
fn generate_contours(
    scene: &Scene,
    generator: &ContoursGenerator,
    env: &Env<'_>,
    timer: &mut Timer<'_>,
) -> Result<Terrain, ReliefError> {
    let inputs = timer.step("inputs", || Inputs::prepare(scene, generator, env))?;
    let graph = timer.step("graph", || inputs.graph(scene.seed))?;
    let growth = timer.step("growth", || {
        grow(&graph, inputs.probability.as_ref(), growth_seed(scene.seed)).map_err(|e| eden_error(&e))
    })?;
    let heights = timer.step("heights", || {
        let level_ends: Vec<usize> = (1..=growth.levels()).map(|l| growth.level_range(l).end).collect();
        let ranking =
            Ranking { order: growth.order(), level_ends: &level_ends, level_heights: &graph.level_heights()[1..] };
        assign_heights(graph.tin().num_points(), &ranking, &inputs.histogram)
            .map_err(|e| ReliefError::scene(HISTOGRAM, e))
    })?;
    let sea_level = heights.level_boundaries[0];
    let contours = timer.step("contours", || {
        let mut levels = inputs.levels.clone();
        levels.extend_from_slice(&heights.level_boundaries);
        extract_tin(graph.tin(), &heights.heights, &merge_levels(levels))
            .map_err(|e| ReliefError::pipeline("contours", e))
    })?;
    let tolerance = graph.radius() / 20.0;
    let contours = timer.step("edits", || apply_edits(contours, &inputs.edits, &inputs.warps, tolerance))?;
    let heightfield = timer.step("reconstruction", || {
        let grid = &inputs.grid;
        let drain = scene.reconstruction.drain;
        let hf = match scene.reconstruction.mode {
            ReconstructionMode::Stairs => reconstruct_stairs(&contours, grid, heights.outside),
            ReconstructionMode::Interpolated => {
                let locator = PointLocator::new(graph.tin());
                let warps = &inputs.warps;
                let surface = |p: DVec2| {
                    let q = if warps.is_empty() { p } else { warps.inverse(p) };
                    locator.interpolate(q, &heights.heights).ok().flatten().unwrap_or(heights.outside)
                };
                let options = Interpolation { summit: Summit::Surface(&surface), drain };
                reconstruct_interpolated(&contours, grid, heights.outside, &options)
            }
            ReconstructionMode::Tin => {
                return tin_raster(&graph, &heights.heights, heights.outside, &contours, &inputs, drain, sea_level);
            }
        };
        hf.map_err(|e| ReliefError::pipeline("reconstruction", e))
    })?;
    let (heightfield, drainage) = finish(scene, heightfield, sea_level, timer)?;
    let land: Vec<f64> =
        heightfield.samples().iter().filter(|v| f64::from(**v) >= sea_level).map(|&v| f64::from(v)).collect();
    let inside: Vec<f64> = growth.order().iter().map(|&v| heights.heights[v as usize]).collect();
    let (min, max) = heightfield.min_max().unwrap_or((f32::NAN, f32::NAN));
    let extent = inputs.grid.extent();
    let summary = Summary {
        relief_version: env!("CARGO_PKG_VERSION"),
        scene: scene.clone(),
        graph: Some(GraphSummary {
            nodes: graph.tin().num_points(),
            inside: graph.inside_count(),
            radius: graph.radius(),
            filled_nodes: graph.filled_nodes(),
            levels: graph.max_level(),
        }),
        contours: ContourSummary {
            levels: contours.levels().len(),
            contours: contours.len(),
            vertices: contours.vertex_count(),
        },
        heightfield: RasterSummary {
            nx: inputs.grid.nx(),
            ny: inputs.grid.ny(),
            domain: Rectangle { min: extent.min.to_array(), max: extent.max.to_array() },
            min,
            max,
            sea_level,
        },
        histogram_match: Some(HistogramMatch {
            nodes: inputs.histogram.ks_distance(&inside),
            raster: if land.is_empty() { 1.0 } else { inputs.histogram.ks_distance(&land) },
        }),
        diffusion: None,
        island: None,
        gaussian: None,
        orometry: None,
        drainage,
        timings_ms: std::mem::take(&mut timer.timings),
    };
    Ok(Terrain { heightfield, contours, histogram: inputs.histogram, sea_level, summary })
}

/// Post-processes and the drainage summary, shared by every generator.
fn finish(
    scene: &Scene,
    heightfield: Heightfield,
    sea_level: f64,
    timer: &mut Timer<'_>,
) -> Result<(Heightfield, DrainageSummary), ReliefError> {
    let heightfield = if scene.post.is_empty() {
        heightfield
    } else {
        timer.step("post-process", || post_process(heightfield, &scene.post, sea_level))?
    };
    let drainage = timer.step("drainage", || drainage_summary(&heightfield, sea_level))?;
    Ok((heightfield, drainage))
}

const DIFFUSION: &str = "generator.diffusion";

/// Feature curves diffused into a terrain (Hnaidi et al. 2010), then contours drawn from it.
fn generate_diffusion(
    scene: &Scene,
    generator: &DiffusionGenerator,
    timer: &mut Timer<'_>,
) -> Result<Terrain, ReliefError> {
    let (curves, grid, options) = timer.step("inputs", || diffusion_inputs(scene, generator))?;
    let terrain =
        timer.step("diffusion", || diffusion::generate(&curves, &grid, &options).map_err(|e| diffusion_error(&e)))?;
    let report = terrain.report;
    let (lo, _) = terrain.heightfield.min_max().unwrap_or((0.0, 0.0));
    let sea_level = generator.sea_level.unwrap_or(f64::from(lo) - 1.0);
    let extras = Extras { diffusion: Some(report), ..Extras::default() };
    raster_terrain(scene, terrain.heightfield, sea_level, &generator.levels, DIFFUSION, extras, timer)
}

/// What a raster generator adds to the summary.
#[derive(Default)]
struct Extras {
    diffusion: Option<SolveReport>,
    island: Option<IslandSummary>,
    gaussian: Option<GaussianSummary>,
    orometry: Option<OrometrySummary>,
}

/// The shared end of the raster generators (diffusion, island): post-processing and drainage
/// ([`finish`]), then contours at `levels` and the summary. `path` is the generator's JSON path.
fn raster_terrain(
    scene: &Scene,
    heightfield: Heightfield,
    sea_level: f64,
    levels_spec: &Levels,
    path: &'static str,
    extras: Extras,
    timer: &mut Timer<'_>,
) -> Result<Terrain, ReliefError> {
    let grid = *heightfield.grid();
    let (heightfield, drainage) = finish(scene, heightfield, sea_level, timer)?;
    let samples: Vec<f64> = heightfield.samples().iter().map(|&v| f64::from(v)).collect();
    let histogram = Histogram::from_samples(samples).map_err(|e| ReliefError::pipeline(path, e))?;
    let contours = timer.step("contours", || {
        let levels = levels(levels_spec, &histogram, &format!("{path}.levels"))?;
        extract_dem(&heightfield, &levels).map_err(|e| ReliefError::pipeline("contours", e))
    })?;
    let (min, max) = heightfield.min_max().unwrap_or((f32::NAN, f32::NAN));
    let extent = grid.extent();
    let summary = Summary {
        relief_version: env!("CARGO_PKG_VERSION"),
        scene: scene.clone(),
        graph: None,
        contours: ContourSummary {
            levels: contours.levels().len(),
            contours: contours.len(),
            vertices: contours.vertex_count(),
        },
        heightfield: RasterSummary {
            nx: grid.nx(),
            ny: grid.ny(),
            domain: Rectangle { min: extent.min.to_array(), max: extent.max.to_array() },
            min,
            max,
            sea_level,
        },
        histogram_match: None,
        diffusion: extras.diffusion,
        island: extras.island,
        gaussian: extras.gaussian,
        orometry: extras.orometry,
        drainage,
        timings_ms: std::mem::take(&mut timer.timings),
    };
    Ok(Terrain { heightfield, contours, histogram, sea_level, summary })
}

const ISLAND: &str = "generator.island";

/// A sketched island (Puig-Centelles et al.): the start state, then the scene's operations.
fn generate_island(scene: &Scene, generator: &IslandGenerator, timer: &mut Timer<'_>) -> Result<Terrain, ReliefError> {
    let extent = match &scene.domain {
        Some(d) => rectangle(d, "domain")?,
        None => Extent::new(DVec2::ZERO, DVec2::splat(1000.0)),
    };
    let grid = raster_grid(scene, extent)?;
    let built = timer.step("island", || {
        let mut island = Island::new(grid, generator.settings, scene.seed).map_err(|e| island_error(&e))?;
        island.replay(&generator.operations).map_err(|e| island_error(&e))?;
        Ok::<_, ReliefError>(island)
    })?;
    let summary = IslandSummary {
        coast_vertices: built.coastline().len(),
        area: built.area(),
        hills: built.hills().len(),
        perturbations: built.filters().len(),
    };
    let extras = Extras { island: Some(summary), ..Extras::default() };
    // Sea is exactly 0 and land at least `land_floor`: half the floor parts them.
    let sea_level = 0.5 * generator.settings.land_floor;
    raster_terrain(scene, built.heightfield(), sea_level, &generator.levels, ISLAND, extras, timer)
}

const GAUSSIAN: &str = "generator.gaussian";

/// A vector terrain (Perche et al. 2025): the source, the tools in order, then the raster.
fn generate_gaussian(
    scene: &Scene,
    generator: &GaussianGenerator,
    env: &Env<'_>,
    timer: &mut Timer<'_>,
) -> Result<Terrain, ReliefError> {
    let mut terrain =
        timer.step("source", || vector::load_source(&generator.source, env, &format!("{GAUSSIAN}.source")))?;
    env.budget.primitives(terrain.len() as u64, &format!("{GAUSSIAN}.source"))?;
    let extent = match &scene.domain {
        Some(d) => rectangle(d, "domain")?,
        None => vector::default_extent(&terrain),
    };
    let grid = raster_grid(scene, extent)?;
    timer.step("tools", || vector::apply_operations(&mut terrain, generator, &grid, env, GAUSSIAN))?;
    let heightfield = timer.step("rasterize", || {
        rasterize(&terrain, &grid, &RasterOptions::default()).map_err(|e| ReliefError::scene(GAUSSIAN, e))
    })?;
    let (lo, _) = heightfield.min_max().unwrap_or((0.0, 0.0));
    let extras = Extras { gaussian: Some(GaussianSummary { primitives: terrain.len() }), ..Extras::default() };
    raster_terrain(scene, heightfield, f64::from(lo) - 1.0, &generator.levels, GAUSSIAN, extras, timer)
}

const OROMETRY: &str = "generator.orometry";

/// Reads a control map and stretches it over `extent` (its own georeferencing is ignored: maps
/// are usually images).
fn control_map(
    path: Option<&PathBuf>,
    env: &Env<'_>,
    extent: Extent,
    at: &str,
) -> Result<Option<Heightfield>, ReliefError> {
    let Some(path) = path else { return Ok(None) };
    let map = env.read(path).map_err(|e| ReliefError::scene(at, e))?;
    let grid = GridSpec::from_extent(map.nx(), map.ny(), extent).map_err(|e| ReliefError::scene(at, e))?;
    Heightfield::from_samples(grid, map.into_samples()).map(Some).map_err(|e| ReliefError::scene(at, e))
}

/// Applies one divide tree edit.
fn edit_tree(tree: &mut crate::orometry::DivideTree, edit: &TreeEdit) -> Result<(), crate::orometry::OrometryError> {
    use crate::orometry::TreePeak;
    match *edit {
        TreeEdit::InsertPeak { position, elevation, connect_to, saddle, saddle_elevation } => tree
            .insert_peak(
                TreePeak { position: DVec2::from(position), elevation },
                connect_to,
                (DVec2::from(saddle), saddle_elevation),
            )
            .map(|_| ()),
        TreeEdit::MovePeak { peak, position, elevation } => tree.move_peak(peak, DVec2::from(position), elevation),
        TreeEdit::MoveSaddle { saddle, position, elevation } => {
            tree.move_saddle(saddle, DVec2::from(position), elevation)
        }
        TreeEdit::DeletePeak { peak } => tree.delete_peak(peak),
        TreeEdit::DeleteRidge { saddle } => tree.delete_ridge(saddle),
    }
}

/// Orometric synthesis (Argudo et al. 2019): target descriptor, divide tree, edits, terrain.
fn generate_orometry(
    scene: &Scene,
    generator: &OrometryGenerator,
    env: &Env<'_>,
    timer: &mut Timer<'_>,
) -> Result<Terrain, ReliefError> {
    use crate::orometry::{
        AnalysisOptions, ControlMaps, Descriptor, Histogram, TreePeak, generate_tree, terrain_from_tree,
    };
    let Some(domain) = &scene.domain else {
        return Err(ReliefError::scene("domain", "an orometry scene needs a domain in metres"));
    };
    let extent = rectangle(domain, "domain")?;
    let grid = raster_grid(scene, extent)?;
    let target = timer.step("inputs", || -> Result<Descriptor, ReliefError> {
        let at = format!("{OROMETRY}.source");
        let descriptor = match &generator.source {
            OrometrySource::Dem { path, min_prominence, sea_level } => {
                let dem = env.read(path).map_err(|e| ReliefError::scene(&at, e))?;
                let options = AnalysisOptions { sea_level: *sea_level, min_prominence: *min_prominence };
                Descriptor::of(&dem, &options).map_err(|e| ReliefError::scene(&at, e))?.1
            }
            OrometrySource::Descriptor { path } => {
                let d: Descriptor = vector::read_json(&env.join(path), &at)?;
                d.validate().map_err(|e| ReliefError::scene(&at, e))?;
                d
            }
        };
        Ok(descriptor)
    })?;
    let controls = ControlMaps {
        peak_density: control_map(generator.peak_density.as_ref(), env, extent, &format!("{OROMETRY}.peak_density"))?,
        elevation: control_map(generator.elevation.as_ref(), env, extent, &format!("{OROMETRY}.elevation"))?,
    };
    let pinned: Vec<TreePeak> = generator
        .pinned
        .iter()
        .map(|p| TreePeak { position: DVec2::from(p.position), elevation: p.elevation })
        .collect();
    let tree_options = crate::orometry::TreeOptions { seed: scene.seed, ..generator.tree.clone() };
    let peaks = tree_options.peak_count(&target, extent, pinned.len());
    env.budget.peaks(peaks as u64, &format!("{OROMETRY}.tree.peaks"))?;
    let mut tree = timer.step("divide tree", || {
        generate_tree(&target, extent, &controls, &pinned, &tree_options).map_err(|e| ReliefError::scene(OROMETRY, e))
    })?;
    for (i, edit) in generator.edits.iter().enumerate() {
        edit_tree(&mut tree, edit).map_err(|e| ReliefError::scene(format!("{OROMETRY}.edits[{i}]"), e))?;
    }
    let base = target.domain.min_elevation;
    let terrain_options =
        crate::orometry::TerrainOptions { seed: growth_seed(scene.seed), ..generator.terrain.clone() };
    // The routing raster at λ/2 and the refined ridges count as cells (an invalid λ is left to the
    // synthesis's own check, which names it).
    let lambda = terrain_options.lambda_m;
    if lambda.is_finite() && lambda > 0.0 {
        let mesh = terrain_options.mesh_samples(&tree, grid.extent());
        let mesh = if mesh.is_finite() { mesh as u64 } else { u64::MAX };
        env.budget.cells(mesh, &format!("{OROMETRY}.terrain.lambda_m"))?;
    }
    let heightfield = timer.step("terrain", || {
        terrain_from_tree(&tree, base, &grid, &terrain_options, |_, _| {}).map_err(|e| ReliefError::scene(OROMETRY, e))
    })?;
    let oro = tree.orometry(base);
    let prominence = Histogram::uniform(0.0, 2000.0, 20).filled(oro.prominence.iter().copied());
    let dominance = Histogram::uniform(0.0, 1.0, 20).filled(oro.dominance(&tree, target.domain.datum));
    let summary = OrometrySummary {
        peaks: tree.peaks.len(),
        saddles: tree.saddles.len(),
        prominence_emd: prominence.emd(&target.prominence).unwrap_or(f64::NAN),
        prominence_max_bin_error: prominence.max_bin_error(&target.prominence).unwrap_or(f64::NAN),
        dominance_max_bin_error: dominance.max_bin_error(&target.dominance).unwrap_or(f64::NAN),
        tree,
    };
    let extras = Extras { orometry: Some(summary), ..Extras::default() };
    raster_terrain(scene, heightfield, base - 1.0, &generator.levels, OROMETRY, extras, timer)
}

/// An island error as a scene error at the JSON path it comes from.
fn island_error(e: &IslandError) -> ReliefError {
    match e {
        IslandError::Operation { index, source } => ReliefError::scene(format!("{ISLAND}.operations[{index}]"), source),
        IslandError::InvalidParameter { name, .. } => ReliefError::scene(format!("{ISLAND}.settings.{name}"), e),
        IslandError::Grid { .. } => ReliefError::scene("reconstruction.resolution", e),
        _ => ReliefError::scene(ISLAND, e),
    }
}

/// Curves, grid and options of a diffusion scene, checked.
fn diffusion_inputs(
    scene: &Scene,
    g: &DiffusionGenerator,
) -> Result<(Vec<FeatureCurve>, GridSpec, TerrainOptions), ReliefError> {
    if g.curves.is_empty() {
        return Err(ReliefError::scene(format!("{DIFFUSION}.curves"), "give at least one curve"));
    }
    let curves: Vec<FeatureCurve> = g
        .curves
        .iter()
        .map(|c| FeatureCurve {
            points: c.points.iter().map(|&p| DVec2::from(p)).collect(),
            constraints: c
                .constraints
                .iter()
                .map(|k| Constraint {
                    u: k.u,
                    elevation: k.elevation.map(|e| diffusion::Elevation { h: e.h, r: e.r }),
                    slope: k.slope.map(|s| diffusion::Slope { a: s.a, b: s.b, theta: s.theta, phi: s.phi }),
                    noise: k.noise.map(|n| diffusion::Noise { amplitude: n.amplitude, roughness: n.roughness }),
                })
                .collect(),
        })
        .collect();
    for (k, c) in curves.iter().enumerate() {
        c.validate(k).map_err(|e| diffusion_error(&e))?;
    }
    let extent = if let Some(d) = &scene.domain {
        rectangle(d, "domain")?
    } else {
        let points = curves.iter().flat_map(|c| c.points.iter().copied());
        let (lo, hi) = points.fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), p| (lo.min(p), hi.max(p)));
        let hi = hi.max(lo + DVec2::ONE);
        default_domain(Rect::new(lo, hi), scene.reconstruction.resolution)
    };
    let grid = raster_grid(scene, extent)?;
    let solve = SolveOptions {
        solver: match g.solver {
            SolverSpec::Multigrid => Solver::Multigrid,
            SolverSpec::JacobiPyramid => Solver::JacobiPyramid,
        },
        tolerance: g.tolerance,
        max_iterations: None,
    };
    let options = TerrainOptions {
        solve,
        noise_wavelength: g.noise_wavelength.unwrap_or(0.0),
        noise_octaves: g.noise_octaves,
        seed: scene.seed,
    };
    Ok((curves, grid, options))
}

/// A diffusion error as a scene error at the JSON path it comes from.
fn diffusion_error(e: &DiffusionError) -> ReliefError {
    let curve = |c: usize| format!("{DIFFUSION}.curves[{c}]");
    match e {
        DiffusionError::ControlPoints { curve: c, .. } | DiffusionError::NonFinitePoint { curve: c, .. } => {
            ReliefError::scene(format!("{}.points", curve(*c)), e)
        }
        DiffusionError::NoConstraints { curve: c } => ReliefError::scene(format!("{}.constraints", curve(*c)), e),
        DiffusionError::InvalidConstraint { curve: c, constraint, field, .. } => {
            let group = match *field {
                "u" => String::new(),
                "h" | "r" => ".elevation".into(),
                "amplitude" | "roughness" => ".noise".into(),
                _ => ".slope".into(),
            };
            ReliefError::scene(format!("{}.constraints[{constraint}]{group}.{field}", curve(*c)), e)
        }
        DiffusionError::NoElevation => ReliefError::scene(format!("{DIFFUSION}.curves"), e),
        DiffusionError::InvalidOption { name, .. } => ReliefError::scene(format!("{DIFFUSION}.{name}"), e),
        DiffusionError::GridTooSmall { .. } => ReliefError::scene("reconstruction.resolution", e),
        other => ReliefError::pipeline("diffusion", other),
    }
}

/// Writes the outputs of `terrain` under `out_dir` (created if needed) and returns the files
/// written, in order. Every file is written atomically. The summary, written last, includes the
/// time spent writing the others.
///
/// # Errors
/// [`ReliefError::Scene`] for an output path with an unknown extension (checked before anything is
/// written), [`ReliefError::Io`] / [`ReliefError::File`] when a file cannot be written.
pub fn write_outputs(
    terrain: &Terrain,
    outputs: &Outputs,
    out_dir: &Path,
    progress: &mut dyn Progress,
) -> Result<Vec<PathBuf>, ReliefError> {
    check_outputs(outputs)?;
    std::fs::create_dir_all(out_dir).map_err(|source| ReliefError::File { path: out_dir.to_owned(), source })?;
    let mut timer = Timer { progress, timings: Vec::new() };
    let extent = terrain.heightfield.extent();
    let written = timer.step("write", || -> Result<Vec<PathBuf>, ReliefError> {
        let mut written = Vec::new();
        for p in &outputs.heightfield {
            let path = out_dir.join(p);
            crate::io::write(&path, &terrain.heightfield)?;
            written.push(path);
        }
        if let Some(p) = &outputs.contours_geojson {
            let path = out_dir.join(p);
            crate::io::write_atomic(&path, crate::export::contours_geojson(&terrain.contours).as_bytes())?;
            written.push(path);
        }
        if let Some(p) = &outputs.contours_svg {
            let path = out_dir.join(p);
            let svg = crate::export::contours_svg(&terrain.contours, &extent, SVG_WIDTH);
            crate::io::write_atomic(&path, svg.as_bytes())?;
            written.push(path);
        }
        if let (Some(p), Some(o)) = (&outputs.divide_tree, &terrain.summary.orometry) {
            let path = out_dir.join(p);
            crate::io::write_atomic(&path, crate::export::divide_tree_geojson(&o.tree, None).as_bytes())?;
            written.push(path);
        }
        if let Some(p) = &outputs.preview {
            let path = out_dir.join(p);
            let image =
                crate::export::preview_image(&terrain.heightfield, Some(&terrain.contours), Some(terrain.sea_level));
            crate::io::write_rgb_png(&path, &image)?;
            written.push(path);
        }
        Ok(written)
    })?;
    let mut written = written;
    if let Some(p) = &outputs.summary {
        let path = out_dir.join(p);
        let mut summary = terrain.summary.clone();
        summary.timings_ms.extend(timer.timings);
        let mut text = serde_json::to_string_pretty(&summary).map_err(|e| ReliefError::pipeline("summary", e))?;
        text.push('\n');
        crate::io::write_atomic(&path, text.as_bytes())?;
        written.push(path);
    }
    Ok(written)
}

/// Generates `scene` and writes its outputs under `out_dir`: [`generate`] then [`write_outputs`].
///
/// # Errors
/// As [`generate`] and [`write_outputs`].
pub fn run(
    scene: &Scene,
    base_dir: &Path,
    out_dir: &Path,
    progress: &mut dyn Progress,
) -> Result<(Terrain, Vec<PathBuf>), ReliefError> {
    run_with(scene, base_dir, out_dir, &Budget::default(), progress)
}

/// [`run`] under an explicit [`Budget`] (see [`generate_with`]).
///
/// # Errors
/// As [`generate_with`] and [`write_outputs`].
pub fn run_with(
    scene: &Scene,
    base_dir: &Path,
    out_dir: &Path,
    budget: &Budget,
    progress: &mut dyn Progress,
) -> Result<(Terrain, Vec<PathBuf>), ReliefError> {
    check_outputs(&scene.outputs)?;
    let terrain = generate_with(scene, base_dir, budget, progress)?;
    let written = write_outputs(&terrain, &scene.outputs, out_dir, progress)?;
    Ok((terrain, written))
}

/// Seed of the growth, decorrelated from the sampling's.
fn growth_seed(seed: u64) -> u64 {
    seed ^ 0x9E37_79B9_7F4A_7C15
}

const GENERATOR: &str = "generator.contours";
const HISTOGRAM: &str = "generator.contours.histogram";
const PROBABILITY: &str = "generator.contours.probability";

/// Everything a scene asks for, parsed and checked.
struct Inputs {
    source: Source,
    sampling: Sampling,
    histogram: Histogram,
    probability: Box<dyn ProbabilityMap>,
    levels: Vec<f64>,
    edits: Vec<PreparedEdit>,
    /// The warps among the edits, in order (for backward mapping).
    warps: Chain,
    grid: GridSpec,
    /// The budget's particle cap, which a radius's estimated count is checked against.
    max_particles: u64,
}

enum Source {
    Regions(RegionTree),
    Labels(LabelMap),
}

enum PreparedEdit {
    Smooth(Smoothing),
    Warp(usize),
}

impl Inputs {
    fn prepare(scene: &Scene, g: &ContoursGenerator, env: &Env<'_>) -> Result<Self, ReliefError> {
        let sampling = match (g.particles, g.radius) {
            (Some(_), Some(_)) => return Err(ReliefError::scene(GENERATOR, "give `particles` or `radius`, not both")),
            (Some(0), None) => return Err(ReliefError::scene(format!("{GENERATOR}.particles"), "must be at least 1")),
            (Some(n), None) => Sampling::Particles(n),
            (None, Some(r)) if !(r.is_finite() && r > 0.0) => {
                return Err(ReliefError::scene(format!("{GENERATOR}.radius"), format!("{r} must be finite and > 0")));
            }
            (None, Some(r)) => Sampling::Radius(r),
            (None, None) => Sampling::Particles(DEFAULT_PARTICLES),
        };
        let source = match (&g.label_image, g.regions.is_empty()) {
            (Some(_), false) => return Err(ReliefError::scene(GENERATOR, "give `regions` or `label_image`, not both")),
            (None, true) => {
                return Err(ReliefError::scene(
                    format!("{GENERATOR}.regions"),
                    "give at least one region (or `label_image`)",
                ));
            }
            (None, false) => Source::Regions(region_tree(g)?),
            (Some(label), true) => {
                let at = format!("{GENERATOR}.label_image");
                let image = env.read_gray(&label.path).map_err(|e| ReliefError::scene(format!("{at}.path"), e))?;
                let grid = place(image.nx(), image.ny(), &label.extent, &format!("{at}.extent"))?;
                let labels = LabelMap::from_values(grid, image.samples())
                    .map_err(|e| ReliefError::scene(format!("{at}.path"), e))?
                    .with_depressions(label.depressions);
                Source::Labels(labels)
            }
        };
        let histogram = histogram(&g.histogram, env)?;
        let levels = levels(&g.levels, &histogram, "generator.contours.levels")?;
        let extent = match (&scene.domain, &source) {
            (Some(d), _) => rectangle(d, "domain")?,
            (None, Source::Labels(l)) => l.grid().extent(),
            (None, Source::Regions(t)) => default_domain(t.omega().bounds(), scene.reconstruction.resolution),
        };
        let grid = raster_grid(scene, extent)?;
        let probability = probability(&g.probability, env, &extent, scene.seed)?;
        let (edits, warps) = edits(&scene.edits)?;
        Ok(Self {
            source,
            sampling,
            histogram,
            probability,
            levels,
            edits,
            warps,
            grid,
            max_particles: env.budget.max_particles,
        })
    }

    fn graph(&self, seed: u64) -> Result<Graph, ReliefError> {
        let options = GraphOptions {
            sampling: self.sampling,
            max_particles: self.max_particles,
            ..GraphOptions::particles(1).with_seed(seed)
        };
        let graph = match &self.source {
            Source::Regions(tree) => Graph::from_regions(tree, &options),
            Source::Labels(labels) => Graph::from_labels(labels, &options),
        };
        graph.map_err(|e| {
            let at = match (&e, self.sampling) {
                (EdenError::RegionTooSmall { .. } | EdenError::LevelTooSmall { .. }, _)
                    if matches!(self.source, Source::Labels(_)) =>
                {
                    format!("{GENERATOR}.label_image.path")
                }
                (EdenError::RegionTooSmall { region, .. }, _) => format!("{GENERATOR}.regions[{region}].polygon"),
                (EdenError::TooManyParticles { .. }, Sampling::Radius(_)) => format!("{GENERATOR}.radius"),
                (EdenError::TooManyParticles { .. }, Sampling::Particles(_)) => format!("{GENERATOR}.particles"),
                _ => GENERATOR.to_owned(),
            };
            ReliefError::scene(at, e)
        })
    }
}

/// The scene path an [`EdenError`] is about.
fn eden_error(e: &EdenError) -> ReliefError {
    let region = |i: usize, field: &str| format!("{GENERATOR}.regions[{i}]{field}");
    let at = match *e {
        EdenError::NoRegions | EdenError::HeightsNotIncreasing { .. } => format!("{GENERATOR}.regions"),
        EdenError::RegionsOverlap { b, .. } => region(b, ".polygon"),
        EdenError::HoleInRaisedRegion { region: i, .. } => region(i, ".polygon.holes"),
        EdenError::DepressionNotNested { region: i, .. } | EdenError::DepressionWithChildren { region: i, .. } => {
            region(i, ".depression")
        }
        EdenError::InvalidHeight { region: i, .. } | EdenError::ConflictingHeights { b: i, .. } => region(i, ".height"),
        EdenError::RegionTooSmall { region: i, .. } => region(i, ".polygon"),
        EdenError::InvalidProbability { .. }
        | EdenError::ZeroProbability
        | EdenError::InvalidProbabilityParameters { .. } => PROBABILITY.to_owned(),
        _ => GENERATOR.to_owned(),
    };
    ReliefError::scene(at, e)
}

fn region_tree(g: &ContoursGenerator) -> Result<RegionTree, ReliefError> {
    let ring = |r: &[[f64; 2]]| r.iter().map(|&p| DVec2::from_array(p)).collect::<Vec<_>>();
    let mut regions = Vec::with_capacity(g.regions.len());
    for (i, spec) in g.regions.iter().enumerate() {
        let polygon = Polygon::new(ring(&spec.polygon.exterior), spec.polygon.holes.iter().map(|h| ring(h)).collect())
            .map_err(|e| ReliefError::scene(format!("{GENERATOR}.regions[{i}].polygon"), e))?;
        let mut region = Region::new(polygon);
        if let Some(h) = spec.height {
            region = region.with_height(h);
        }
        if spec.depression {
            region = region.as_depression();
        }
        regions.push(region);
    }
    RegionTree::new(regions).map_err(|e| eden_error(&e))
}

/// A checked rectangle.
fn rectangle(r: &Rectangle, at: &str) -> Result<Extent, ReliefError> {
    let (min, max) = (DVec2::from_array(r.min), DVec2::from_array(r.max));
    if !(min.is_finite() && max.is_finite() && min.cmplt(max).all()) {
        return Err(ReliefError::scene(at, format!("min {:?} must be finite and below max {:?}", r.min, r.max)));
    }
    Ok(Extent::new(min, max))
}

/// A grid of `nx × ny` pixel centres spanning `r`.
fn place(nx: usize, ny: usize, r: &Rectangle, at: &str) -> Result<GridSpec, ReliefError> {
    GridSpec::from_extent(nx, ny, rectangle(r, at)?).map_err(|e| ReliefError::scene(at, e))
}

/// Ω's bounds grown by 5 % of their larger side, then widened to the resolution's aspect ratio so
/// cells are square.
/// The raster of `extent` at the scene's resolution, checked.
fn raster_grid(scene: &Scene, extent: Extent) -> Result<GridSpec, ReliefError> {
    let [nx, ny] = scene.reconstruction.resolution;
    if !(2..=MAX_RESOLUTION).contains(&nx) || !(2..=MAX_RESOLUTION).contains(&ny) {
        return Err(ReliefError::scene(
            "reconstruction.resolution",
            format!("{nx} x {ny}: each side must be in 2..={MAX_RESOLUTION}"),
        ));
    }
    GridSpec::from_extent(nx, ny, extent).map_err(|e| ReliefError::scene("domain", e))
}

fn default_domain(bounds: Rect, [nx, ny]: [usize; 2]) -> Extent {
    let size = bounds.size();
    let grown = bounds.grow(0.05 * size.max_element());
    let (centre, mut half) = (0.5 * (grown.min + grown.max), 0.5 * grown.size());
    let aspect = (nx.max(2) - 1) as f64 / (ny.max(2) - 1) as f64;
    if half.x / half.y < aspect {
        half.x = half.y * aspect;
    } else {
        half.y = half.x / aspect;
    }
    Extent::new(centre - half, centre + half)
}

fn histogram(source: &HistogramSource, env: &Env<'_>) -> Result<Histogram, ReliefError> {
    let err = |e: ContoursError| ReliefError::scene(HISTOGRAM, e);
    match source {
        HistogramSource::Bins { edges, weights } => Histogram::from_bins(edges.clone(), weights.clone()).map_err(err),
        HistogramSource::Samples(s) => Histogram::from_samples(s.clone()).map_err(err),
        HistogramSource::Uniform { min, max } => Histogram::uniform(*min, *max).map_err(err),
        HistogramSource::Dem(path) => {
            let dem = env.read(path).map_err(|e| ReliefError::scene(format!("{HISTOGRAM}.dem"), e))?;
            let samples: Vec<f64> = dem.samples().iter().filter(|v| v.is_finite()).map(|&v| f64::from(v)).collect();
            Histogram::from_samples(samples).map_err(|e| ReliefError::scene(format!("{HISTOGRAM}.dem"), e))
        }
    }
}

fn levels(levels: &Levels, histogram: &Histogram, at: &str) -> Result<Vec<f64>, ReliefError> {
    let (lo, hi) = (histogram.min(), histogram.max());
    match levels {
        Levels::Count(n) if *n > MAX_LEVELS => {
            Err(ReliefError::scene(at, format!("{n} levels, more than {MAX_LEVELS}")))
        }
        Levels::Count(n) => evenly_spaced_levels(lo, hi, *n).map_err(|e| ReliefError::scene(at, e)),
        Levels::Interval(m) => interval_levels(lo, hi, *m, 0.0, MAX_LEVELS).map_err(|e| ReliefError::scene(at, e)),
        Levels::Heights(h) => {
            if let Some(k) = h.iter().position(|v| !v.is_finite()) {
                return Err(ReliefError::scene(format!("{at}.heights[{k}]"), format!("{} is not finite", h[k])));
            }
            if h.len() > MAX_LEVELS {
                return Err(ReliefError::scene(at, format!("{} levels, more than {MAX_LEVELS}", h.len())));
            }
            Ok(h.clone())
        }
    }
}

/// Sorted, with levels closer than a billionth of the range merged (the input contours' heights
/// win over a requested level that coincides with one).
fn merge_levels(mut levels: Vec<f64>) -> Vec<f64> {
    levels.sort_by(f64::total_cmp);
    let range = levels.last().copied().unwrap_or(0.0) - levels.first().copied().unwrap_or(0.0);
    let eps = 1e-9 * range.max(1.0);
    levels.dedup_by(|a, b| (*a - *b).abs() <= eps);
    levels
}

fn probability(
    p: &Probability,
    env: &Env<'_>,
    domain: &Extent,
    seed: u64,
) -> Result<Box<dyn ProbabilityMap>, ReliefError> {
    let err = |e: EdenError| ReliefError::scene(PROBABILITY, e);
    Ok(match p {
        Probability::Uniform => Box::new(Uniform),
        Probability::Fbm { octaves, frequency, lacunarity, gain, contrast } => {
            let fbm = Fbm { octaves: *octaves, frequency: *frequency, lacunarity: *lacunarity, gain: *gain, seed };
            Box::new(FbmProbability::new(fbm, *contrast).map_err(err)?)
        }
        Probability::Image { path, extent, exponent } => {
            let image = env.read_gray(path).map_err(|e| ReliefError::scene(format!("{PROBABILITY}.image.path"), e))?;
            let grid = match extent {
                Some(r) => place(image.nx(), image.ny(), r, &format!("{PROBABILITY}.image.extent"))?,
                None => GridSpec::from_extent(image.nx(), image.ny(), *domain)
                    .map_err(|e| ReliefError::scene(format!("{PROBABILITY}.image.path"), e))?,
            };
            let mut samples = image.into_samples();
            // Transparent pixels read as no-data; they are places the growth should not prefer.
            samples.iter_mut().filter(|v| v.is_nan()).for_each(|v| *v = 0.0);
            let field = Heightfield::from_samples(grid, samples).map_err(|e| ReliefError::pipeline("inputs", e))?;
            Box::new(RasterProbability::new(field, *exponent).map_err(err)?)
        }
    })
}

/// The edits in order, each warp built (and so checked) now, before any heavy work.
fn edits(edits: &[Edit]) -> Result<(Vec<PreparedEdit>, Chain), ReliefError> {
    let mut prepared = Vec::with_capacity(edits.len());
    let mut warps: Vec<Box<dyn Warp>> = Vec::new();
    let points = |s: &[[f64; 2]]| s.iter().map(|&p| DVec2::from_array(p)).collect::<Vec<_>>();
    for (i, edit) in edits.iter().enumerate() {
        let at = |field: &str| format!("edits[{i}].{field}");
        match edit {
            Edit::Smooth { alpha, k, iterations } => {
                let s = Smoothing { alpha: *alpha, k: *k, iterations: *iterations };
                if !(*alpha > 0.0 && *alpha <= 1.0) {
                    return Err(ReliefError::scene(at("smooth.alpha"), format!("{alpha} must be in (0, 1]")));
                }
                if *k == 0 {
                    return Err(ReliefError::scene(at("smooth.k"), "must be at least 1"));
                }
                prepared.push(PreparedEdit::Smooth(s));
            }
            Edit::Warp { stroke, radius, strength, exponent } => {
                let profile = Profile::power(*exponent).map_err(|e| ReliefError::scene(at("warp.exponent"), e))?;
                let options = PathOptions { radius: *radius, strength: *strength, profile, segment: None };
                let warp = PathWarp::new(&points(stroke), &options).map_err(|e| {
                    let field = match e {
                        WarpError::InvalidRadius { .. } => "warp.radius",
                        WarpError::InvalidStrength { .. } => "warp.strength",
                        _ => "warp.stroke",
                    };
                    ReliefError::scene(at(field), e)
                })?;
                prepared.push(PreparedEdit::Warp(warps.len()));
                warps.push(Box::new(warp));
            }
            Edit::Slope { point, curve, radius, strength } => {
                let slope = match (point, curve) {
                    (Some(p), None) => SlopeModulation::point(DVec2::from_array(*p), *radius, *strength),
                    (None, Some(c)) => SlopeModulation::curve(&points(c), *radius, *strength),
                    _ => return Err(ReliefError::scene(at("slope"), "give `point` or `curve` (exactly one)")),
                };
                let slope = slope.map_err(|e| {
                    let field = match e {
                        WarpError::InvalidRadius { .. }
                        | WarpError::CurvatureTooHigh { .. }
                        | WarpError::CurveTooClose { .. } => "slope.radius",
                        WarpError::InvalidStrength { .. } => "slope.strength",
                        _ if point.is_some() => "slope.point",
                        _ => "slope.curve",
                    };
                    ReliefError::scene(at(field), e)
                })?;
                prepared.push(PreparedEdit::Warp(warps.len()));
                warps.push(Box::new(slope));
            }
        }
    }
    Ok((prepared, Chain(warps)))
}

/// The warps of a scene, applied in order: `forward` folds them first to last, `inverse` last to
/// first.
struct Chain(Vec<Box<dyn Warp>>);

impl Chain {
    fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

impl Warp for Chain {
    fn forward(&self, p: DVec2) -> DVec2 {
        self.0.iter().fold(p, |p, w| w.forward(p))
    }

    fn inverse(&self, q: DVec2) -> DVec2 {
        self.0.iter().rev().fold(q, |q, w| w.inverse(q))
    }

    fn support(&self) -> Option<[DVec2; 2]> {
        self.0.iter().try_fold([DVec2::INFINITY, DVec2::NEG_INFINITY], |[lo, hi], w| {
            w.support().map(|[a, b]| [lo.min(a), hi.max(b)])
        })
    }
}

/// Applies the edits to the contours in order.
///
/// A warp is a bijection, so warped contours never cross — but their polylines only follow the
/// warped curves to within a tolerance (adaptive subdivision), and where a warp squeezes
/// neighbouring contours closer than that, the approximations could touch. Each warped set is
/// therefore checked, and warped again from the same input with a quarter of the tolerance until
/// it is clean (smoothing guarantees this by construction).
fn apply_edits(
    mut set: ContourSet,
    edits: &[PreparedEdit],
    warps: &Chain,
    tolerance: f64,
) -> Result<ContourSet, ReliefError> {
    const REFINEMENTS: u32 = 6;
    for edit in edits {
        set = match edit {
            PreparedEdit::Smooth(s) => set.smoothed(s).map_err(|e| ReliefError::pipeline("edits", e))?,
            PreparedEdit::Warp(k) => {
                let warp: &dyn Warp = &*warps.0[*k];
                let mut tol = tolerance;
                let mut round = 0;
                loop {
                    let warped = warp_set(&set, warp, tol)?;
                    match warped.check_invariants() {
                        Ok(()) => break warped,
                        Err(e) if round == REFINEMENTS => {
                            return Err(ReliefError::pipeline("edits", format!("warp {k}: {e} at tolerance {tol}")));
                        }
                        Err(_) => {}
                    }
                    tol *= 0.25;
                    round += 1;
                }
            }
        };
    }
    Ok(set)
}

/// Every contour of `set` warped to within `tolerance`.
fn warp_set(set: &ContourSet, warp: &dyn Warp, tolerance: f64) -> Result<ContourSet, ReliefError> {
    let contours: Vec<Contour> = set
        .contours()
        .par_iter()
        .map(|c| {
            let points =
                warp_polyline(warp, &c.points, c.closed, tolerance).map_err(|e| ReliefError::pipeline("edits", e))?;
            Ok(Contour { points, ..c.clone() })
        })
        .collect::<Result<_, ReliefError>>()?;
    ContourSet::new(set.levels().to_vec(), contours).map_err(|e| ReliefError::pipeline("edits", e))
}

/// The TIN itself as the terrain: rasterized (no-data beyond its hull reads as `outside`), warped
/// by backward mapping, and optionally drained with the sea, the border and every pit contour's
/// inside as outlets.
fn tin_raster(
    graph: &Graph,
    heights: &[f64],
    outside: f64,
    contours: &ContourSet,
    inputs: &Inputs,
    drain: bool,
    sea_level: f64,
) -> Result<Heightfield, ReliefError> {
    let grid = &inputs.grid;
    let mut hf = graph.tin().rasterize(heights, grid).map_err(|e| ReliefError::pipeline("reconstruction", e))?;
    hf.fill_no_data(outside as f32).map_err(|e| ReliefError::pipeline("reconstruction", e))?;
    if !inputs.warps.is_empty() {
        let source = hf;
        let samples = warp_raster(
            &inputs.warps,
            grid.nx(),
            grid.ny(),
            |i, j| grid.position(i, j),
            |p| source.sample_bilinear_clamped(p).unwrap_or(outside as f32),
        );
        hf = Heightfield::from_samples(*grid, samples).map_err(|e| ReliefError::pipeline("reconstruction", e))?;
    }
    if drain {
        let pits = pit_mask(contours, grid);
        let nx = grid.nx();
        let sea = sea_level as f32;
        let values = hf.samples().to_vec();
        fill_depressions(&mut hf, |i, j| {
            let k = j * nx + i;
            i == 0 || j == 0 || i + 1 == nx || j + 1 == grid.ny() || values[k] < sea || pits[k]
        });
    }
    Ok(hf)
}

/// Runs the scene's post-processes in order; the sea and the border are the base level.
fn post_process(mut hf: Heightfield, post: &[PostProcess], sea_level: f64) -> Result<Heightfield, ReliefError> {
    let outlets = Outlets::new().with_sea_level(sea_level as f32);
    for (k, step) in post.iter().enumerate() {
        let named = |kind: &str, e: HydrologyError| match e {
            HydrologyError::InvalidParameter { name, .. } => ReliefError::scene(format!("post[{k}].{kind}.{name}"), e),
            e => ReliefError::pipeline("post-process", e),
        };
        match *step {
            PostProcess::StreamPower { iterations, erodibility, uplift, m, n, dt } => {
                let sp = StreamPower {
                    erodibility: Field::Uniform(erodibility),
                    uplift: Field::Uniform(uplift),
                    m,
                    n,
                    dt,
                    outlets,
                };
                sp.run(&mut hf, iterations, |_| {}).map_err(|e| named("stream_power", e))?;
            }
            PostProcess::Thermal { talus_deg, rate, iterations } => {
                Thermal { talus_deg, rate, iterations }.run(&mut hf, |_| {}).map_err(|e| named("thermal", e))?;
            }
            PostProcess::Fill {} => hf = hydrology::fill(&hf, outlets).map_err(|e| named("fill", e))?,
        }
    }
    Ok(hf)
}

/// Closed basins and stream order of `hf` with the sea and the border as outlets.
fn drainage_summary(hf: &Heightfield, sea_level: f64) -> Result<DrainageSummary, ReliefError> {
    let fail = |e: HydrologyError| ReliefError::pipeline("drainage", e);
    let outlets = Outlets::new().with_sea_level(sea_level as f32);
    let closed = hydrology::depressions(hf, outlets).map_err(fail)?;
    let routed = D8::new(&closed.filled).map_err(fail)?;
    let sea = sea_level as f32;
    let land_area: f64 =
        (0..hf.ny()).map(|j| hf.row(j).iter().filter(|&&v| v > sea).count() as f64 * hf.grid().cell_area_m2(j)).sum();
    let streams = routed.streams(0.005 * land_area).map_err(fail)?;
    let max_strahler = routed.strahler(&streams).map_err(fail)?.into_iter().max().unwrap_or(0);
    Ok(DrainageSummary {
        closed_basins: closed.basins.len(),
        closed_volume: closed.basins.iter().map(|b| b.volume_m3).sum(),
        max_strahler,
    })
}

/// The samples inside a closed clockwise contour (around a pit).
fn pit_mask(set: &ContourSet, grid: &GridSpec) -> Vec<bool> {
    let mut mask = vec![false; grid.len()];
    for c in set.contours().iter().filter(|c| c.closed && !c.is_counter_clockwise()) {
        let Ok(polygon) = Polygon::from_exterior(c.points.clone()) else { continue };
        let b = c.bounds();
        let (lo, hi) = (grid.grid_coords(b.min).ceil(), grid.grid_coords(b.max).floor());
        let (i0, j0) = (lo.x.max(0.0) as usize, lo.y.max(0.0) as usize);
        let (i1, j1) = (hi.x.min((grid.nx() - 1) as f64), hi.y.min((grid.ny() - 1) as f64));
        if i1 < 0.0 || j1 < 0.0 {
            continue;
        }
        for j in j0..=j1 as usize {
            for i in i0..=i1 as usize {
                if polygon.contains(grid.position(i, j)) {
                    mask[grid.index(i, j)] = true;
                }
            }
        }
    }
    mask
}

/// Every heightfield output has a known extension.
fn check_outputs(outputs: &Outputs) -> Result<(), ReliefError> {
    for (i, p) in outputs.heightfield.iter().enumerate() {
        if Format::from_extension(p).is_none() {
            return Err(ReliefError::scene(
                format!("outputs.heightfield[{i}]"),
                format!("{}: unknown extension (use .exr, .png, .r16, .r32, .asc, .tif or .hgt)", p.display()),
            ));
        }
    }
    Ok(())
}
