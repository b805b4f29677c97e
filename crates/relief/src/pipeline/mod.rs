//! Scene → terrain: the run reads a scene's inputs, has its generator produce a heightfield
//! (`Generated`), post-processes it, draws its contours, summarizes the run and writes every
//! output.
//!
//! ```text
//! inputs ─► generator (contours | diffusion | island | gaussian | orometry) ─► Generated
//!        ─► post-processes ─► drainage ─► contours (raster generators) ─► Summary ─► outputs
//! ```
//!
//! Each generator is a module of its own returning the same `Generated`; the summary is built
//! in one place (`Summary::new`). Every scene value is checked before the expensive work
//! starts, and a bad one fails with a [`ReliefError::Scene`] naming its JSON path
//! (`generator.contours.regions[2].polygon`, `edits[1].warp.radius`, …), whichever step finds it.

mod contour_input;
mod contour_tools;
mod contours;
mod diffusion;
mod edits;
mod gaussian;
mod inputs;
mod island;
mod labels;
mod orometry;
mod outputs;
mod post;
mod progress;
mod session;
mod summary;

use std::path::{Path, PathBuf};

pub use contours::DEFAULT_PARTICLES;
pub use inputs::MAX_RESOLUTION;
pub(crate) use outputs::layer_files;
pub use outputs::{check_outputs, write_outputs};
pub use progress::{Progress, Timing};
pub use session::EditSession;
pub use summary::{
    ContourSummary, DrainageSummary, GaussianSummary, GraphSummary, HistogramMatch, IslandSummary, OrometrySummary,
    RasterSummary, Summary, TerrainOrometry,
};

use crate::budget::{Budget, read_json_text};
use crate::contours::{ContourSet, Histogram, extract_dem};
use crate::diffusion::SolveReport;
use crate::eden_growth::MaskCleaning;
use crate::heightfield::Heightfield;
use crate::scene::{Generator, PostProcess, Scene};
use crate::{ReliefError, ReliefError as E};
use contour_input::ContourInputSummary;
use inputs::Env;
use progress::Timer;

/// What a generator produces: the heightfield, the sea level below which it is sea (`None`: no
/// sea), its contours when it draws them itself (the contour generator), and what it reports.
pub(crate) struct Generated {
    pub(crate) heightfield: Heightfield,
    pub(crate) sea_level: Option<f64>,
    pub(crate) contours: Option<ContourSet>,
    pub(crate) report: Report,
    /// What the user should know about the result (a poor fit, an input that had no effect).
    pub(crate) warnings: Vec<String>,
    /// The gaussian generator's vector terrain.
    pub(crate) vector: Option<VectorResult>,
    /// The island generator's layers.
    pub(crate) layers: Option<crate::island::IslandLayers>,
}

/// A gaussian scene's vector terrain after its tools, with how its crest skeleton is extracted.
#[derive(Debug, Clone)]
pub struct VectorResult {
    /// The terrain, its domain the scene's (so that reloading it rasterizes the same grid).
    pub terrain: crate::gaussian_terrain::VectorTerrain,
    /// The scene's skeleton options.
    pub skeleton: crate::gaussian_terrain::SkeletonOptions,
    /// What the scene's `copy` and `cut` tools kept, by name.
    pub atlas: crate::gaussian_terrain::Atlas,
}

/// The part of the summary only one generator knows.
pub(crate) enum Report {
    /// The growth graph, the target histogram and the KS distance of the node heights to it.
    Contours {
        graph: GraphSummary,
        histogram: Histogram,
        nodes_ks: f64,
        mask: Option<MaskCleaning>,
        contour_input: Option<ContourInputSummary>,
        /// The DEM contour input came from (its name and grid), to compare the result with.
        reference: Option<Box<(String, Heightfield)>>,
    },
    /// How the diffusion solve went.
    Diffusion(SolveReport),
    /// The island's final shape.
    Island(IslandSummary),
    /// The vector terrain after its tools.
    Gaussian(GaussianSummary),
    /// The divide tree and its match to the target.
    Orometry(OrometrySummary),
}

/// A generated terrain: the heightfield, its contours, and the run summary.
#[derive(Debug, Clone)]
pub struct Terrain {
    /// The final heightfield (after post-processing).
    pub heightfield: Heightfield,
    /// The contours: the contour generator's, after the edits; a raster generator's, drawn from
    /// the final heightfield.
    pub contours: ContourSet,
    /// The histogram the elevations follow: the contour scene's target, or the final
    /// heightfield's own elevations.
    pub histogram: Histogram,
    /// Elevation below which the terrain is sea; `None` when it has no sea.
    pub sea_level: Option<f64>,
    /// The run summary (timings cover generation; [`write_outputs`] adds its own).
    pub summary: Summary,
    /// The vector terrain of a gaussian scene (before any post step).
    pub vector: Option<VectorResult>,
    /// The layers of an island scene's heights (the paper's Fig. 13; before any post step).
    pub layers: Option<crate::island::IslandLayers>,
}

/// Reads a scene file.
///
/// # Errors
/// [`ReliefError::File`] when it cannot be read, [`ReliefError::Scene`] when it is not a valid scene.
pub fn load_scene(path: impl AsRef<Path>) -> Result<Scene, ReliefError> {
    let path = path.as_ref();
    let text = read_json_text(path).map_err(|source| ReliefError::File { path: path.to_owned(), source })?;
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
    let mut timer = Timer::new(progress);
    let generated = generate_raw(scene, base_dir, budget, &mut timer, None)?;
    finish(scene, generated, &mut timer)
}

/// A heightfield generated for an interactive preview (relief studio): what [`generate_with`]
/// computes, post steps included, without the analyses that only the summary and the outputs
/// use (drainage, the histogram, a raster generator's contours).
#[derive(Debug, Clone)]
pub struct Preview {
    /// The final heightfield, the same samples as [`Terrain::heightfield`].
    pub heightfield: Heightfield,
    /// Elevation below which the terrain is sea; `None` when it has no sea.
    pub sea_level: Option<f64>,
    /// What the user should know about the result, as in [`Summary::warnings`].
    pub warnings: Vec<String>,
    /// The steps' times.
    pub timings: Vec<Timing>,
    /// An orometry scene's divide tree (after its edits), whose peak and saddle indices the
    /// scene's tree edits take.
    pub divide_tree: Option<crate::orometry::DivideTree>,
}

/// [`generate_with`] for a preview: the same heightfield, sooner.
///
/// # Errors
/// As [`generate_with`].
pub fn preview_with(
    scene: &Scene,
    base_dir: &Path,
    budget: &Budget,
    progress: &mut dyn Progress,
) -> Result<Preview, ReliefError> {
    preview_raw(scene, base_dir, budget, progress, None)
}

/// [`preview_with`] within an editing session: what the session kept from its last previews is
/// reused where the scene only appends to it (an island's new operations are applied to the
/// island as it stood), and the session keeps this preview's state. The heightfield is the same
/// as [`preview_with`]'s.
///
/// # Errors
/// As [`generate_with`].
///
/// # Example
/// ```
/// use relief::pipeline::{EditSession, preview_in};
///
/// let mut scene = relief::Scene::from_json(include_str!("../../../../fixtures/scenes/volcano-island-sketch.json"))?;
/// scene.reconstruction.resolution = [64, 64];
/// let dir = std::path::Path::new(".");
/// let budget = relief::Budget::default();
/// let mut session = EditSession::new();
/// let first = preview_in(&mut session, &scene, dir, &budget, &mut ())?;
/// // The next edit: one more hill. Only it is applied.
/// let relief::scene::Generator::Island(island) = &mut scene.generator else { unreachable!() };
/// let hill = relief::island::Hill::round(glam::DVec2::new(2000.0, 2000.0), 400.0, 150.0);
/// island.operations.push(relief::island::Operation::AddHill(hill));
/// let second = preview_in(&mut session, &scene, dir, &budget, &mut ())?;
/// assert_eq!(second.heightfield, relief::pipeline::preview_with(&scene, dir, &budget, &mut ())?.heightfield);
/// assert_ne!(first.heightfield, second.heightfield);
/// # Ok::<(), relief::ReliefError>(())
/// ```
pub fn preview_in(
    session: &mut EditSession,
    scene: &Scene,
    base_dir: &Path,
    budget: &Budget,
    progress: &mut dyn Progress,
) -> Result<Preview, ReliefError> {
    session.begin();
    preview_raw(scene, base_dir, budget, progress, Some(session))
}

fn preview_raw(
    scene: &Scene,
    base_dir: &Path,
    budget: &Budget,
    progress: &mut dyn Progress,
    session: Option<&mut EditSession>,
) -> Result<Preview, ReliefError> {
    let mut timer = Timer::new(progress);
    let Generated { heightfield, sea_level, mut vector, warnings, report, .. } =
        generate_raw(scene, base_dir, budget, &mut timer, session)?;
    let heightfield = post(scene, heightfield, sea_level, &mut vector, &mut timer)?;
    let divide_tree = match report {
        Report::Orometry(orometry) => Some(orometry.tree),
        _ => None,
    };
    Ok(Preview { heightfield, sea_level, warnings, timings: std::mem::take(&mut timer.timings), divide_tree })
}

/// The generator's own steps, under the budget.
fn generate_raw(
    scene: &Scene,
    base_dir: &Path,
    budget: &Budget,
    timer: &mut Timer<'_>,
    session: Option<&mut EditSession>,
) -> Result<Generated, ReliefError> {
    budget.check(scene)?;
    let env = &Env { dir: base_dir, budget: *budget, inputs: &scene.inputs };
    match &scene.generator {
        Generator::Contours(g) => contours::generate(scene, g, env, timer),
        Generator::Diffusion(g) => diffusion::generate(scene, g, timer),
        Generator::Island(g) => island::generate(scene, g, env, timer, session),
        Generator::Gaussian(g) => gaussian::generate(scene, g, env, timer),
        Generator::Orometry(g) => orometry::generate(scene, g, env, timer),
    }
}

/// The scene's post steps on `heightfield` (a details step also updates the vector terrain).
fn post(
    scene: &Scene,
    heightfield: Heightfield,
    sea_level: Option<f64>,
    vector: &mut Option<VectorResult>,
    timer: &mut Timer<'_>,
) -> Result<Heightfield, ReliefError> {
    if scene.post.is_empty() {
        return Ok(heightfield);
    }
    let work = post::post_work(&scene.post);
    let terrain = vector.as_mut().map(|v| &mut v.terrain);
    timer.counted("post-process", work, |tick| {
        post::post_process(heightfield, &scene.post, sea_level, terrain, scene.seed, tick)
    })
}

/// The shared end of every run: post-processes, drainage, the contours of a raster generator at
/// its levels, and the summary.
fn finish(scene: &Scene, generated: Generated, timer: &mut Timer<'_>) -> Result<Terrain, ReliefError> {
    let Generated { heightfield, sea_level, contours, report, mut warnings, mut vector, layers } = generated;
    let detailed = matches!(scene.post.last(), Some(PostProcess::Details { .. }));
    let written = scene.outputs.vector_terrain.is_some() || scene.outputs.skeleton.is_some();
    if vector.is_some() && !scene.post.is_empty() && !detailed && written {
        warnings.push(
            "outputs.vector_terrain and outputs.skeleton hold the vector terrain before the post steps \
             (end post with a details step to carry them over)"
                .into(),
        );
    }
    let heightfield = post(scene, heightfield, sea_level, &mut vector, timer)?;
    let drainage = timer.step("drainage", || post::drainage(&heightfield, sea_level))?;
    let (contours, histogram) = match (contours, &report) {
        (Some(contours), Report::Contours { histogram, .. }) => (contours, histogram.clone()),
        (contours, _) => {
            let samples: Vec<f64> = heightfield.samples().iter().map(|&v| f64::from(v)).collect();
            let histogram = Histogram::from_samples(samples).map_err(|e| E::step("contours", e))?;
            let contours = match contours {
                Some(contours) => contours,
                None => timer.step("contours", || raster_contours(scene, &heightfield, &histogram))?,
            };
            (contours, histogram)
        }
    };
    let comparison = match &report {
        Report::Contours { reference: Some(reference), .. } => {
            let (name, dem) = reference.as_ref();
            Some(timer.step("comparison", || contour_input::compare(&heightfield, name, dem))?)
        }
        _ => None,
    };
    let timings = std::mem::take(&mut timer.timings);
    let mut summary = Summary::new(scene, report, &heightfield, &contours, sea_level, drainage, timings);
    summary.comparison = comparison;
    summary.warnings = warnings;
    Ok(Terrain { heightfield, contours, histogram, sea_level, summary, vector, layers })
}

/// The contours of a raster generator's heightfield at the generator's levels.
fn raster_contours(scene: &Scene, heightfield: &Heightfield, histogram: &Histogram) -> Result<ContourSet, ReliefError> {
    let levels = match scene.generator.raster_levels() {
        Some(levels) => levels
            .resolve(histogram.min(), histogram.max())
            .map_err(|e| E::located(&format!("{}.levels", scene.generator.path()), e))?,
        None => Vec::new(),
    };
    extract_dem(heightfield, &levels).map_err(|e| E::step("contours", e))
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
    outputs::check_outputs(&scene.outputs)?;
    let terrain = generate_with(scene, base_dir, budget, progress)?;
    let written = write_outputs(&terrain, &scene.outputs, out_dir, progress)?;
    Ok((terrain, written))
}
