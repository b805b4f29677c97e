//! The scene file: a versioned JSON description of a terrain — seed, domain, generator, edits,
//! reconstruction, post-processes and outputs. `docs/scene.schema.json` is the JSON Schema
//! generated from these types.
//!
//! The scene types are the library types: a feature curve in a scene *is* a
//! [`relief_diffusion_multigrid::FeatureCurve`], a warp edit a [`relief_warp::PathWarp`], a region
//! a [`relief_eden_growth::Region`]. What this module adds is only what composes them — which
//! generator runs, where input files are, what is written — and the few values that name a
//! file. Unknown fields are errors; every error names the JSON path of the offending value;
//! relative paths resolve against the scene file's directory.

mod files;
mod generators;
mod histogram;
mod inputs;

use std::path::PathBuf;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::ReliefError;
use crate::contours::Smoothing;
use crate::error::SceneError;
use crate::heightfield::Extent;
use crate::hydrology::{StreamPower, Thermal};
use crate::warp::{PathWarp, SlopeModulation};

pub use generators::{
    Border, CoastlineImage, ContourInput, ContoursGenerator, DiffusionGenerator, GaussianGenerator, GaussianSource,
    Generator, IslandGenerator, LabelImage, LabelLevelSpec, LabelValue, LandTone, Lowest, Multilevel, NoDataFill,
    OrometryGenerator, OrometrySource, OrometryTypes, Probability,
};
pub use histogram::HistogramSource;
pub use inputs::InputOptions;

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
    /// World rectangle of the outputs (raster and drawings). Default: the generator's inputs'
    /// bounds grown by 5 %.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub domain: Option<Extent>,
    /// How the terrain is generated.
    pub generator: Generator,
    /// How the input files are read, for what they do not say themselves (heightmap vertical
    /// range, cell size, CRS, band, …).
    #[serde(default, skip_serializing_if = "InputOptions::is_empty")]
    pub inputs: InputOptions,
    /// Edits applied, in order, to the generated contours (contour generator only).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub edits: Vec<Edit>,
    /// How the contours become a heightfield, and the raster size of every generator.
    #[serde(default)]
    pub reconstruction: Reconstruction,
    /// Post-processes run, in order, on the heightfield (erosion, filling).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub post: Vec<PostProcess>,
    /// What to write.
    #[serde(default)]
    pub outputs: Outputs,
}

/// An edit of the generated contours (the contours paper, §5). The contour tools (`fill`,
/// `delete`, `paste`, `cut`) act on the generated terrain first, in their order; smoothing, warps
/// and slope modulation then act on its contours, in theirs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Edit {
    /// Smoothing (§5.1), never making contours cross.
    Smooth(Smoothing),
    /// Coherent warping along a stroke (§5.2).
    Warp(PathWarp),
    /// Slope modulation around a point or a curve (§5.3).
    Slope(SlopeModulation),
    /// Regrow the inside of the contour at `at` (§6.6's filling tool): its shape grows anew from
    /// the contour inward, its elevations keep their distribution.
    Fill(ContourPick),
    /// Delete the contour at `at` with every contour inside it: its inside becomes a low dome
    /// (or a shallow basin, for a pit) between the contour and the next level.
    Delete(ContourPick),
    /// Copy the relief inside the contour at `at` (its height above the contour) onto the
    /// terrain at `to`.
    Paste(ContourMove),
    /// As `paste`, and delete the original.
    Cut(ContourMove),
}

/// Which generated contour a tool takes: the innermost closed one around `at`, or, with `height`,
/// the one around `at` whose height is nearest it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ContourPick {
    /// A point inside the contour, world units.
    pub at: [f64; 2],
    /// Take the contour around `at` of height nearest this.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
}

/// A contour picked and where its relief goes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ContourMove {
    /// A point inside the contour, world units.
    pub at: [f64; 2],
    /// Take the contour around `at` of height nearest this.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    /// Where `at` goes: the relief moves by `to − at`.
    pub to: [f64; 2],
}

/// A post-process of the heightfield (`relief-hydrology`). The sea (cells below the sea level)
/// and the map border are the base level water drains to.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum PostProcess {
    /// Fluvial erosion: the implicit stream-power law ∂h/∂t = U − K·A^m·S^n (Braun & Willett 2013).
    StreamPower(StreamPower),
    /// Thermal erosion: slopes steeper than the talus angle shed material downhill.
    Thermal(Thermal),
    /// Priority-Flood+ε filling: every land cell drains to the sea or the border again (keeps
    /// nothing closed, not even craters).
    Fill {},
    /// Perche et al.'s Fig. 15 loop (gaussian generator only): what the steps before changed on
    /// the raster (erosion) becomes detail primitives of the vector terrain, which then
    /// reproduces the processed raster and carries the change to any resolution
    /// (`outputs.vector_terrain`).
    Details {
        /// Spacing of the detail primitives, in cells (default 1.5: dense enough that the
        /// error map is read back everywhere).
        #[serde(default = "default_detail_spacing")]
        spacing: f64,
    },
}

fn default_detail_spacing() -> f64 {
    1.5
}

/// How the heightfield is rebuilt, and its size.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Reconstruction {
    /// Method (default interpolated; contour generator only).
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
    /// `[min, max]`: the elevations the 16-bit outputs (.png, .r16) map their lowest and highest
    /// codes to, for engines that import heightmaps with one fixed height scale (default: the
    /// terrain's own min and max). A terrain reaching outside it is an error, never clamped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range: Option<[f32; 2]>,
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
    /// The vector terrain after the tools, as JSON (gaussian generator only): a scene's
    /// `source: { "kind": "terrain", "path": … }` reloads it, its domain set to this scene's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vector_terrain: Option<PathBuf>,
    /// The crest skeleton of the result as GeoJSON (gaussian generator only): nodes as points
    /// with the `id` a crest tool's `node` takes and their elevation, edges as lines. It is the
    /// skeleton the crest tools of a scene that reloads `vector_terrain` on the same grid
    /// extract.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub skeleton: Option<PathBuf>,
    /// The landforms the scene's `copy` and `cut` tools kept, as an atlas JSON that a `paste`'s
    /// `atlas` reads (gaussian generator only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub atlas: Option<PathBuf>,
    /// The layers the final grid adds up, as the island paper's Fig. 13 shows them (island
    /// generator only): `layers.exr` writes `layers-base.exr` (the coastline's heights),
    /// `layers-hills.exr` and `layers-filters.exr` (the sums of the hills and of the
    /// perturbations), in the heightfield format of the extension.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub island_layers: Option<PathBuf>,
    /// Heightmaps for game engines and DCC tools, each into its own folder: the engine's file
    /// format at its legal size, tiles sharing their edges, and `NAME.import.json` with the numbers
    /// its import dialog asks for (see `relief_engine_export`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub engines: Vec<EngineOutput>,
    /// The terrain as a glTF 2.0 binary mesh (`.glb`), decimated to an error bound.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh: Option<MeshOutput>,
    /// Run summary: parameters, counts, timings, histogram match error.
    #[serde(default = "default_summary")]
    pub summary: Option<PathBuf>,
}

/// One engine export of the terrain (`outputs.engines[]`), as `relief export` writes it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EngineOutput {
    /// The engine: `unity`, `unreal`, `godot` or `blender`.
    #[serde(rename = "for")]
    pub engine: crate::engine::Engine,
    /// The folder, relative to the output directory (default: the engine's name).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dir: Option<PathBuf>,
    /// Samples per side, one of the engine's legal sizes (default: the nearest one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<usize>,
    /// Tiles of this many samples per side, sharing their edges (default: one heightmap).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tile: Option<usize>,
    /// Splat maps beside each heightmap (`{}` for the defaults): layer weights (ground, rock,
    /// snow, water) and the raw slope, elevation, convexity and flow masks.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub splat: Option<crate::engine::SplatOptions>,
}

/// The terrain as a glTF mesh (`outputs.mesh`), as `relief export --for gltf` writes it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MeshOutput {
    /// The `.glb` file, relative to the output directory (default `terrain.glb`).
    #[serde(default = "default_mesh_file")]
    pub file: PathBuf,
    /// No sample farther than this from the mesh, metres (default: 0.1 % of the height range).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_error_m: Option<f64>,
    /// At most this many triangles (default 500 000).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_triangles: Option<usize>,
    /// Hypsometric vertex colours (default `true`).
    #[serde(default = "default_true")]
    pub colours: bool,
}

impl MeshOutput {
    /// The library's options.
    pub fn options(&self) -> crate::engine::MeshOptions {
        let defaults = crate::engine::MeshOptions::default();
        crate::engine::MeshOptions {
            max_error_m: self.max_error_m,
            max_triangles: self.max_triangles.unwrap_or(defaults.max_triangles),
            colours: self.colours,
        }
    }
}

fn default_mesh_file() -> PathBuf {
    PathBuf::from("terrain.glb")
}

impl EngineOutput {
    /// The folder it writes into, relative to the output directory.
    pub fn folder(&self) -> PathBuf {
        self.dir.clone().unwrap_or_else(|| PathBuf::from(self.engine.name()))
    }

    /// The library's options.
    pub fn options(&self) -> crate::engine::ExportOptions {
        crate::engine::ExportOptions {
            size: self.size,
            tile: self.tile,
            splat: self.splat,
            ..crate::engine::ExportOptions::default()
        }
    }
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
            range: None,
            contours_geojson: default_geojson(),
            contours_svg: default_svg(),
            preview: default_preview(),
            divide_tree: None,
            vector_terrain: None,
            skeleton: None,
            atlas: None,
            island_layers: None,
            engines: Vec::new(),
            mesh: None,
            summary: default_summary(),
        }
    }
}

impl Scene {
    /// Parses a scene from JSON, naming the JSON path of any error.
    ///
    /// # Errors
    /// [`ReliefError::Scene`] with the path of the offending value (unknown fields included); its
    /// source is the `serde_json::Error` (with line and column) or, for an unsupported version, a
    /// [`SceneError`].
    pub fn from_json(text: &str) -> Result<Self, ReliefError> {
        let de = &mut serde_json::Deserializer::from_str(text);
        let scene: Scene = serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            // "." is the whole document; "?" a syntax error before any value.
            let path = if path == "." || path == "?" { String::new() } else { path };
            ReliefError::at(path, e.into_inner())
        })?;
        if scene.version != SCENE_VERSION {
            let found = scene.version;
            return Err(ReliefError::at("version", SceneError::UnsupportedVersion { found, supported: SCENE_VERSION }));
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

/// The demo scene, embedded in the binary.
pub const DEMO_SCENE: &str = include_str!("../../scenes/demo.json");
