//! The scene file: a versioned JSON description of a terrain — seed, domain, generator, edits,
//! reconstruction and outputs. Unknown fields are errors, every error names its JSON path, and
//! relative paths resolve against the scene file's directory. `docs/scene.schema.json` is the
//! JSON Schema generated from these types.

use std::path::PathBuf;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::ReliefError;

/// The scene format version this library reads.
pub const SCENE_VERSION: u32 = 1;

/// A terrain to generate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Format version: must be 1.
    pub version: u32,
    /// What the scene is, for people (ignored by the pipeline).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// Seed of every random choice (sampling, growth, noise): same seed, same bytes.
    #[serde(default)]
    pub seed: u64,
    /// World rectangle of the outputs (raster and drawings). Default: the regions' bounds grown by 5 %.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub domain: Option<Rectangle>,
    /// How the terrain is generated.
    pub generator: Generator,
    /// Edits applied, in order, to the generated contours.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub edits: Vec<Edit>,
    /// How the contours become a heightfield.
    #[serde(default)]
    pub reconstruction: Reconstruction,
    /// Post-processes run, in order, on the reconstructed heightfield (erosion, filling).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub post: Vec<PostProcess>,
    /// What to write.
    #[serde(default)]
    pub outputs: Outputs,
}

/// An axis-aligned rectangle in world units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Rectangle {
    /// Minimum corner `[x, y]`.
    pub min: [f64; 2],
    /// Maximum corner `[x, y]`.
    pub max: [f64; 2],
}

/// A terrain generator.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Generator {
    /// Iso-contour generation by inward Open Eden Growth (Huftier et al. 2025).
    Contours(ContoursGenerator),
    /// Feature curves with elevation, slope and noise constraints, diffused into a terrain
    /// (Hnaidi et al. 2010).
    Diffusion(DiffusionGenerator),
    /// A sketched island (Puig-Centelles et al.): a circular coast over a cone, then coastline
    /// strokes, hills and filters replayed in order.
    Island(IslandGenerator),
    /// A vector terrain of generalized Gaussian primitives (Perche et al. 2025): primitives from
    /// the scene, a saved terrain or a vectorized DEM, then landform and crest tools in order.
    Gaussian(GaussianGenerator),
    /// Orometric synthesis (Argudo et al. 2019): a divide tree generated from the orometry of a
    /// reference DEM (or a saved descriptor), optionally steered by control maps and pinned peaks
    /// and edited, then turned into terrain. Needs a `domain` in metres; seeds come from the
    /// scene's `seed`.
    Orometry(OrometryGenerator),
}

/// An orometric synthesis (§5–6).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OrometryGenerator {
    /// Where the target orometry comes from.
    pub source: OrometrySource,
    /// Peak density control map `C_P` (any format `relief` reads; stretched over the domain).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<String>")]
    pub peak_density: Option<PathBuf>,
    /// Coarse elevation control map `C_H` in metres (stretched over the domain).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<String>")]
    pub elevation: Option<PathBuf>,
    /// Peaks placed before synthesis, kept at their positions and heights.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pinned: Vec<PinnedPeak>,
    /// Divide tree generation (§5); its seed is replaced by the scene's.
    #[serde(default)]
    pub tree: relief_orometry::TreeOptions,
    /// Terrain generation (§6); its seed is replaced by the scene's.
    #[serde(default)]
    pub terrain: relief_orometry::TerrainOptions,
    /// Divide tree edits after generation, applied in order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub edits: Vec<TreeEdit>,
    /// Contours drawn from the result (default 20 evenly spaced levels).
    #[serde(default = "default_diffusion_levels")]
    pub levels: Levels,
}

/// The target orometry of an `orometry` generator.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum OrometrySource {
    /// A DEM (any format `relief` reads) analysed first.
    Dem {
        /// The file, relative to the scene.
        #[schemars(with = "String")]
        path: PathBuf,
        /// Peaks at least this prominent count (default 30 m, the usual summit-list cut).
        #[serde(default = "default_min_prominence")]
        min_prominence: f64,
        /// Ground at or below this is sea.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        sea_level: Option<f32>,
    },
    /// A descriptor saved as JSON (`relief analyze --descriptor` writes them).
    Descriptor {
        /// The file, relative to the scene.
        #[schemars(with = "String")]
        path: PathBuf,
    },
}

fn default_min_prominence() -> f64 {
    30.0
}

/// A peak placed before synthesis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PinnedPeak {
    /// Position `[x, y]`, metres.
    pub position: [f64; 2],
    /// Elevation, metres.
    pub elevation: f64,
}

/// One edit of a generated divide tree (§7.2). Indices refer to the tree as it is when the edit
/// runs (the summary's tree, then each edit in turn).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "op", rename_all = "snake_case", deny_unknown_fields)]
pub enum TreeEdit {
    /// Add a peak joined to `connect_to` through a new saddle.
    InsertPeak {
        /// Position `[x, y]`.
        position: [f64; 2],
        /// Elevation.
        elevation: f64,
        /// The peak its ridge leads to.
        connect_to: u32,
        /// The new saddle's position.
        saddle: [f64; 2],
        /// The new saddle's elevation (not above either peak).
        saddle_elevation: f64,
    },
    /// Move a peak, optionally changing its elevation.
    MovePeak {
        /// The peak.
        peak: u32,
        /// New position.
        position: [f64; 2],
        /// New elevation.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        elevation: Option<f64>,
    },
    /// Move a saddle, optionally changing its elevation.
    MoveSaddle {
        /// The saddle.
        saddle: u32,
        /// New position.
        position: [f64; 2],
        /// New elevation.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        elevation: Option<f64>,
    },
    /// Delete a peak; its neighbours stay joined.
    DeletePeak {
        /// The peak.
        peak: u32,
    },
    /// Delete a ridge (its saddle), splitting the tree.
    DeleteRidge {
        /// The saddle.
        saddle: u32,
    },
}

/// A vector terrain and the tool operations applied to it. The domain defaults to the
/// primitives' supports (after the operations); the raster is `reconstruction.resolution`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GaussianGenerator {
    /// Where the primitives come from.
    pub source: GaussianSource,
    /// Tool operations, applied in order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub operations: Vec<GaussianOperation>,
    /// How the crest skeleton of the crest operations is extracted.
    #[serde(default)]
    pub skeleton: SkeletonSpec,
    /// Contours drawn from the result (default 20 evenly spaced levels).
    #[serde(default = "default_diffusion_levels")]
    pub levels: Levels,
}

/// The starting primitives of a `gaussian` generator.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum GaussianSource {
    /// Primitives written in the scene.
    Primitives {
        /// The primitives.
        primitives: Vec<relief_gaussian_terrain::Gaussian>,
        /// Constant elevation under them (default 0).
        #[serde(default)]
        base: f64,
    },
    /// A vector terrain saved as JSON (`relief vectorize` writes them).
    Terrain {
        /// The file, relative to the scene.
        #[schemars(with = "String")]
        path: PathBuf,
    },
    /// A DEM (any format `relief` reads) vectorized first.
    Dem {
        /// The file, relative to the scene.
        #[schemars(with = "String")]
        path: PathBuf,
        /// Most primitives (default 2000).
        #[serde(default = "default_dem_primitives")]
        primitives: usize,
        /// Optimisation steps (default 200).
        #[serde(default = "default_dem_iterations")]
        iterations: usize,
        /// Working-grid resolution (default 256).
        #[serde(default = "default_dem_resolution")]
        resolution: usize,
    },
}

fn default_dem_primitives() -> usize {
    2000
}
fn default_dem_iterations() -> usize {
    200
}
fn default_dem_resolution() -> usize {
    256
}

/// One tool operation on a vector terrain (§5).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "op", rename_all = "snake_case", deny_unknown_fields)]
pub enum GaussianOperation {
    /// Move (or copy) the primitives centred in `region` to `placement`, damping the primitives
    /// under the destination within `damping` of its border (∞: vanish them all).
    Stamp {
        /// The selection.
        region: relief_gaussian_terrain::Region,
        /// Where the region's anchor goes, turned and scaled.
        placement: relief_gaussian_terrain::Placement,
        /// Move (default) or copy.
        #[serde(default)]
        mode: relief_gaussian_terrain::StampMode,
        /// Damping radius, world units.
        damping: f64,
    },
    /// Paste a landform from an atlas file with a circular footprint of radius `footprint`.
    Paste {
        /// The atlas JSON, relative to the scene.
        #[schemars(with = "String")]
        atlas: PathBuf,
        /// The landform's name.
        landform: String,
        /// Footprint radius around the landform's anchor, world units.
        footprint: f64,
        /// Where the anchor goes, turned and scaled.
        placement: relief_gaussian_terrain::Placement,
        /// Damping radius, world units.
        damping: f64,
    },
    /// Delete the primitives centred in `region`.
    Delete {
        /// The selection.
        region: relief_gaussian_terrain::Region,
    },
    /// Twist the primitives in `region` about its anchor by up to `angle` radians.
    Twist {
        /// The region.
        region: relief_gaussian_terrain::Region,
        /// Rotation at the region's rim before fall-off, radians.
        angle: f64,
        /// Fall-off width inside the border, world units.
        falloff: f64,
    },
    /// Squeeze: move the primitives in `region` by `by`, faded towards the border.
    Squeeze {
        /// The region.
        region: relief_gaussian_terrain::Region,
        /// Translation `[x, y]`.
        by: [f64; 2],
        /// Fall-off width inside the border, world units.
        falloff: f64,
    },
    /// Move the crest skeleton's node nearest `near` by `by`; the rest of the crest follows
    /// with the graph attenuation.
    MoveCrest {
        /// A point near the node.
        near: [f64; 2],
        /// Translation `[x, y]`.
        by: [f64; 2],
        /// Graph distance the change reaches (default: the whole graph).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        reach: Option<f64>,
    },
    /// Scale the amplitude around the crest node nearest `near`: `a' = a(α·factor + 1)`.
    RaiseCrest {
        /// A point near the node.
        near: [f64; 2],
        /// `u ≥ −1`: 1 doubles the crest there, −1 flattens it.
        factor: f64,
        /// Graph distance the change reaches (default: the whole graph).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        reach: Option<f64>,
    },
}

/// Crest skeleton extraction (§5.1).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SkeletonSpec {
    /// Flow accumulation (cells, on the inverted DEM) that makes a crest cell (default: 0.2 %
    /// of the raster's cells).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_cells: Option<u32>,
    /// Node spacing after edge collapse, world units (default: 3 % of the domain's longer side).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spacing: Option<f64>,
}

/// Parameters and editing history of a sketched island. The domain defaults to a 1000 × 1000
/// square from the origin; the raster is `reconstruction.resolution`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct IslandGenerator {
    /// Island height, snap distance, land floor and perturbation sizes.
    #[serde(default)]
    pub settings: relief_island::IslandSettings,
    /// The operations, replayed in order on the start state (a circle of radius 0.4 × the
    /// domain's shorter side, centred, over a cone of `settings.height`).
    #[serde(default)]
    pub operations: Vec<relief_island::Operation>,
    /// Contours drawn from the result (default 20 evenly spaced levels).
    #[serde(default = "default_diffusion_levels")]
    pub levels: Levels,
}

/// Parameters of feature-curve diffusion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DiffusionGenerator {
    /// The feature curves (at least one must carry an elevation).
    pub curves: Vec<CurveSpec>,
    /// Solver of the diffusion equations (default multigrid).
    #[serde(default)]
    pub solver: SolverSpec,
    /// Relative residual at which the solve stops (default 1e-4).
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
    /// Wavelength of the first detail-noise octave, world units (default: 1/16 of the domain).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise_wavelength: Option<f64>,
    /// Octaves of the detail noise (default 4, as the paper).
    #[serde(default = "default_noise_octaves")]
    pub noise_octaves: u32,
    /// Ground below this is drawn as sea and drains (default: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sea_level: Option<f64>,
    /// Contours drawn from the result (default 20 evenly spaced levels).
    #[serde(default = "default_diffusion_levels")]
    pub levels: Levels,
}

fn default_tolerance() -> f64 {
    1e-4
}
fn default_noise_octaves() -> u32 {
    4
}
fn default_diffusion_levels() -> Levels {
    Levels::Count(20)
}

/// Which diffusion solver runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum SolverSpec {
    /// Full multigrid, then red-black Gauss–Seidel V-cycles (`BiCGStab` preconditioned by the
    /// V-cycle takes over if they stall).
    #[default]
    Multigrid,
    /// The paper's coarse-to-fine Jacobi pyramid, then Jacobi to the tolerance.
    JacobiPyramid,
}

/// A feature curve: a piecewise cubic Bézier spline with constraint points.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CurveSpec {
    /// Control points `[x, y]`: 2 (a segment) or 3k + 1 (p₀, c₀, c₁, p₁, …).
    pub points: Vec<[f64; 2]>,
    /// Constraint points along the curve.
    pub constraints: Vec<ConstraintSpec>,
}

/// A constraint point at curve parameter `u` (0 at the start, 1 at the end, by arc length).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ConstraintSpec {
    /// Position along the curve, in [0, 1].
    pub u: f64,
    /// Strict elevation `h` over a band of half-width `r`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elevation: Option<ElevationSpec>,
    /// Slopes: `theta` degrees over `a` on the left, `phi` over `b` on the right (positive falls away).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slope: Option<SlopeSpec>,
    /// Detail noise amplitude and roughness (in [0, 1]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise: Option<NoiseSpec>,
}

/// Elevation constraint.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ElevationSpec {
    /// Elevation.
    pub h: f64,
    /// Half-width of the band (default 0: the curve itself).
    #[serde(default)]
    pub r: f64,
}

/// Slope constraint.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SlopeSpec {
    /// Extent on the left.
    pub a: f64,
    /// Extent on the right.
    pub b: f64,
    /// Angle on the left, degrees in (−90, 90).
    pub theta: f64,
    /// Angle on the right, degrees in (−90, 90).
    pub phi: f64,
}

/// Noise constraint.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NoiseSpec {
    /// Amplitude, elevation units.
    pub amplitude: f64,
    /// Roughness in [0, 1].
    pub roughness: f64,
}

/// Parameters of iso-contour generation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ContoursGenerator {
    /// Nested input contours (give these or `label_image`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub regions: Vec<RegionSpec>,
    /// A label image: each gray level one nested region, the darkest outside (give this or `regions`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label_image: Option<LabelImage>,
    /// About this many graph nodes inside the domain (default 50 000 when `radius` is absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub particles: Option<usize>,
    /// Poisson-disc radius in world units, instead of `particles`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Target distribution of elevations.
    pub histogram: HistogramSource,
    /// How readily the growth advances where (default uniform).
    #[serde(default)]
    pub probability: Probability,
    /// Which contours to extract (default 30 evenly spaced levels).
    #[serde(default)]
    pub levels: Levels,
}

/// One input contour.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RegionSpec {
    /// The closed contour.
    pub polygon: PolygonSpec,
    /// Its elevation (applies to every region at the same nesting depth).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    /// A crater or lake: the inside is ordered downward from the rim.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub depression: bool,
}

/// A polygon: an exterior ring and optional holes, as `[x, y]` vertices (closed implicitly).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PolygonSpec {
    /// Exterior ring.
    pub exterior: Vec<[f64; 2]>,
    /// Holes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub holes: Vec<Vec<[f64; 2]>>,
}

/// A label image placed in the world.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LabelImage {
    /// The image (any PNG colour type, or any heightfield format), relative to the scene file.
    pub path: PathBuf,
    /// Where the image lies in the world (its pixel centres span this rectangle).
    pub extent: Rectangle,
    /// Keep enclosed lower areas as depressions (craters) instead of filling them.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub depressions: bool,
}

/// Where the target elevation distribution comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum HistogramSource {
    /// Bins: `edges` (n + 1, increasing) and `weights` (n).
    Bins {
        /// Bin edges.
        edges: Vec<f64>,
        /// Relative weights.
        weights: Vec<f64>,
    },
    /// Sample elevations.
    Samples(Vec<f64>),
    /// Uniform between two heights.
    Uniform {
        /// Lowest height.
        min: f64,
        /// Highest height.
        max: f64,
    },
    /// The elevations of a real DEM (any heightfield-io format), relative to the scene file.
    Dem(PathBuf),
}

/// A probability map.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Probability {
    /// Every frontier node equally likely: contours follow the distance to the border.
    #[default]
    Uniform,
    /// `exp(contrast · fbm(p))`: organic, fingered contours.
    Fbm {
        /// Octaves (default 6).
        #[serde(default = "default_octaves")]
        octaves: u32,
        /// Frequency of the first octave in cycles per world unit.
        frequency: f64,
        /// Frequency ratio between octaves (default 2).
        #[serde(default = "default_lacunarity")]
        lacunarity: f64,
        /// Amplitude ratio between octaves (default 0.5).
        #[serde(default = "default_gain")]
        gain: f64,
        /// Contrast: 0 is uniform, 3–6 strongly fingered.
        contrast: f64,
    },
    /// A painted map (any PNG colour type, or a heightfield), brighter = grown earlier.
    Image {
        /// The image, relative to the scene file.
        path: PathBuf,
        /// Where it lies in the world (default: the output domain).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        extent: Option<Rectangle>,
        /// Values are raised to this power (default 1; the paper's river map uses 4).
        #[serde(default = "default_exponent")]
        exponent: f64,
    },
}

fn default_octaves() -> u32 {
    6
}
fn default_lacunarity() -> f64 {
    2.0
}
fn default_gain() -> f64 {
    0.5
}
fn default_exponent() -> f64 {
    1.0
}

/// Which contour levels to extract (input contours' own levels are always added).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Levels {
    /// This many levels evenly spaced over the histogram's range.
    Count(usize),
    /// Multiples of this interval within the histogram's range.
    Interval(f64),
    /// These heights.
    Heights(Vec<f64>),
}

impl Default for Levels {
    fn default() -> Self {
        Self::Count(30)
    }
}

/// An edit of the generated contours.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Edit {
    /// Smoothing (§5.1), never making contours cross.
    Smooth {
        /// Strength α in (0, 1] (default 0.5).
        #[serde(default = "default_alpha")]
        alpha: f64,
        /// Neighbours on each side (default 2).
        #[serde(default = "default_k")]
        k: usize,
        /// Passes (default 4).
        #[serde(default = "default_iterations")]
        iterations: u32,
    },
    /// Coherent warping along a stroke (§5.2).
    Warp {
        /// The stroke, `[x, y]` points from start to end.
        stroke: Vec<[f64; 2]>,
        /// Radius of influence in world units.
        radius: f64,
        /// Strength μ in [0, 1] (default 1).
        #[serde(default = "default_strength")]
        strength: f64,
        /// Exponent k of the profile (4x(1 − x))^k (default 2).
        #[serde(default = "default_exponent_k")]
        exponent: u32,
    },
    /// Slope modulation around a point or a curve (§5.3).
    Slope {
        /// Centre point (give this or `curve`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        point: Option<[f64; 2]>,
        /// Curve (give this or `point`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        curve: Option<Vec<[f64; 2]>>,
        /// Radius of influence in world units.
        radius: f64,
        /// Strength μ in (−1, 3): positive steepens near the curve, negative flattens.
        strength: f64,
    },
}

fn default_alpha() -> f64 {
    0.5
}
fn default_k() -> usize {
    2
}
fn default_iterations() -> u32 {
    4
}
fn default_strength() -> f64 {
    1.0
}
fn default_exponent_k() -> u32 {
    2
}

/// A post-process of the heightfield (`relief-hydrology`). The sea (cells below the coastline
/// height) and the map border are the base level water drains to.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum PostProcess {
    /// Fluvial erosion: the implicit stream-power law ∂h/∂t = U − K·A^m·S^n (Braun & Willett 2013).
    StreamPower {
        /// Time steps (default 20).
        #[serde(default = "default_erosion_steps")]
        iterations: usize,
        /// Erodibility K (default 2·10⁻⁵, with A in m² and years).
        #[serde(default = "default_erodibility")]
        erodibility: f64,
        /// Uplift rate, metres per year (default 0).
        #[serde(default)]
        uplift: f64,
        /// Drainage-area exponent m (default 0.4).
        #[serde(default = "default_m")]
        m: f64,
        /// Slope exponent n (default 1).
        #[serde(default = "default_n")]
        n: f64,
        /// Time step, years (default 1000).
        #[serde(default = "default_dt")]
        dt: f64,
    },
    /// Thermal erosion: slopes steeper than the talus angle shed material downhill.
    Thermal {
        /// Angle of repose, degrees (default 33).
        #[serde(default = "default_talus")]
        talus_deg: f64,
        /// Share of the excess moved per iteration, in (0, 0.5] (default 0.25).
        #[serde(default = "default_rate")]
        rate: f64,
        /// Iterations (default 50).
        #[serde(default = "default_thermal_iterations")]
        iterations: usize,
    },
    /// Priority-Flood+ε filling: every land cell drains to the sea or the border again (keeps
    /// nothing closed, not even craters).
    Fill {},
}

fn default_erosion_steps() -> usize {
    20
}
fn default_erodibility() -> f64 {
    2e-5
}
fn default_m() -> f64 {
    0.4
}
fn default_n() -> f64 {
    1.0
}
fn default_dt() -> f64 {
    1000.0
}
fn default_talus() -> f64 {
    33.0
}
fn default_rate() -> f64 {
    0.25
}
fn default_thermal_iterations() -> usize {
    50
}

/// How the heightfield is rebuilt.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Reconstruction {
    /// Method (default interpolated).
    #[serde(default)]
    pub mode: ReconstructionMode,
    /// Raster size `[nx, ny]` (default 1024 × 1024).
    #[serde(default = "default_resolution")]
    pub resolution: [usize; 2],
    /// Make the raster drain (no one-cell pits from valleys narrower than a cell; default on).
    #[serde(default = "default_true")]
    pub drain: bool,
}

fn default_resolution() -> [usize; 2] {
    [1024, 1024]
}
fn default_true() -> bool {
    true
}

impl Default for Reconstruction {
    fn default() -> Self {
        Self { mode: ReconstructionMode::default(), resolution: default_resolution(), drain: true }
    }
}

/// Reconstruction method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ReconstructionMode {
    /// Hormann's interpolation between nested contours: smooth, continuous.
    #[default]
    Interpolated,
    /// Terraces: the height of the innermost contour.
    Stairs,
    /// The generated TIN itself, rasterized (warps applied by backward mapping).
    Tin,
}

/// Output files, relative to the output directory. An empty value disables an output.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Outputs {
    /// Heightfield files; the extension picks the format (.exr, .png, .r16, .r32, .asc, .tif, .hgt).
    #[serde(default = "default_heightfields")]
    pub heightfield: Vec<PathBuf>,
    /// Contours as GeoJSON line strings with an `elevation` property.
    #[serde(default = "default_geojson")]
    pub contours_geojson: Option<PathBuf>,
    /// Contours as SVG.
    #[serde(default = "default_svg")]
    pub contours_svg: Option<PathBuf>,
    /// Shaded-relief preview with the contours drawn on it.
    #[serde(default = "default_preview")]
    pub preview: Option<PathBuf>,
    /// The divide tree as GeoJSON (orometry generator only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub divide_tree: Option<PathBuf>,
    /// Run summary: parameters, counts, timings, histogram match error.
    #[serde(default = "default_summary")]
    pub summary: Option<PathBuf>,
}

fn default_heightfields() -> Vec<PathBuf> {
    vec![PathBuf::from("terrain.exr"), PathBuf::from("terrain.png")]
}
#[allow(clippy::unnecessary_wraps, reason = "serde default for an Option field")]
fn default_geojson() -> Option<PathBuf> {
    Some(PathBuf::from("contours.geojson"))
}
#[allow(clippy::unnecessary_wraps, reason = "serde default for an Option field")]
fn default_svg() -> Option<PathBuf> {
    Some(PathBuf::from("contours.svg"))
}
#[allow(clippy::unnecessary_wraps, reason = "serde default for an Option field")]
fn default_preview() -> Option<PathBuf> {
    Some(PathBuf::from("preview.png"))
}
#[allow(clippy::unnecessary_wraps, reason = "serde default for an Option field")]
fn default_summary() -> Option<PathBuf> {
    Some(PathBuf::from("summary.json"))
}

impl Default for Outputs {
    fn default() -> Self {
        Self {
            heightfield: default_heightfields(),
            contours_geojson: default_geojson(),
            contours_svg: default_svg(),
            preview: default_preview(),
            divide_tree: None,
            summary: default_summary(),
        }
    }
}

impl Scene {
    /// Parses a scene from JSON, naming the JSON path of any error.
    ///
    /// # Errors
    /// [`ReliefError::Scene`] with the path of the offending value (unknown fields included).
    pub fn from_json(text: &str) -> Result<Self, ReliefError> {
        let de = &mut serde_json::Deserializer::from_str(text);
        let scene: Scene = serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner();
            ReliefError::scene(if path == "." { String::new() } else { path }, strip_position(&inner.to_string()))
        })?;
        if scene.version != SCENE_VERSION {
            return Err(ReliefError::scene(
                "version",
                format!("version {} is not supported (this build reads {SCENE_VERSION})", scene.version),
            ));
        }
        Ok(scene)
    }

    /// The scene as pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// The built-in demo scene (`relief demo`): a wavy island with two ranges, a raised summit and a
    /// crater, fBm growth, smoothing and a ravine warp.
    ///
    /// # Panics
    /// Never: the embedded scene is checked by the tests.
    pub fn demo() -> Self {
        Self::from_json(DEMO_SCENE).expect("the embedded demo scene is valid")
    }

    /// The JSON Schema of the format.
    pub fn json_schema() -> String {
        serde_json::to_string_pretty(&schemars::schema_for!(Scene)).unwrap_or_default()
    }
}

/// `serde_json` appends " at line L column C"; the JSON path is more useful, and stays.
fn strip_position(message: &str) -> String {
    message.find(" at line ").map_or_else(|| message.to_owned(), |k| message[..k].to_owned())
}

/// The demo scene, embedded in the binary.
pub const DEMO_SCENE: &str = include_str!("../scenes/demo.json");
