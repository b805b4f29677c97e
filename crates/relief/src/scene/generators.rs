//! The generators a scene can name: which library runs, on which inputs. Their parameters are
//! library types; the fields of their own are the inputs that are files (a DEM, a painted map,
//! an atlas) and the contour levels drawn from the result.

use std::path::PathBuf;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::HistogramSource;
use crate::contours::Levels;
use crate::diffusion::presets::Preset;
use crate::diffusion::{FeatureCurve, SolveOptions, Solver, TerrainOptions as DiffusionOptions};
use crate::eden_growth::{FbmProbability, Fronts, Region};
use crate::gaussian_terrain::{SkeletonOptions, Tool, VectorTerrain};
use crate::heightfield::Extent;
use crate::island::{IslandSettings, Operation};
use crate::orometry::{TerrainOptions, TreeEdit, TreeOptions, TreePeak};

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

impl Generator {
    /// The contour levels drawn from a raster generator's result; `None` for the contour
    /// generator, whose contours are its own output.
    pub fn raster_levels(&self) -> Option<&Levels> {
        match self {
            Self::Contours(_) => None,
            Self::Diffusion(g) => Some(&g.levels),
            Self::Island(g) => Some(&g.levels),
            Self::Gaussian(g) => Some(&g.levels),
            Self::Orometry(g) => Some(&g.levels),
        }
    }

    /// The JSON path of the generator (`generator.contours`, …), the prefix of its values' paths.
    pub fn path(&self) -> &'static str {
        match self {
            Self::Contours(_) => "generator.contours",
            Self::Diffusion(_) => "generator.diffusion",
            Self::Island(_) => "generator.island",
            Self::Gaussian(_) => "generator.gaussian",
            Self::Orometry(_) => "generator.orometry",
        }
    }
}

/// Contours drawn from a raster generator's result by default: 20 evenly spaced levels.
fn raster_levels() -> Levels {
    Levels::Count(20)
}

/// Parameters of iso-contour generation (the contours paper).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ContoursGenerator {
    /// Nested input contours (give these or `label_image`). Depth is nesting; a height applies
    /// to its whole depth level; `depression` marks a crater or lake.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub regions: Vec<Region>,
    /// A label image: each gray level one nested region, the darkest outside (give this or `regions`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label_image: Option<LabelImage>,
    /// Contours to regrow from, instead of `regions` or `label_image`: a DEM's (closed along its
    /// border) or a GeoJSON's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contours: Option<ContourInput>,
    /// About this many graph nodes inside the domain (default 50 000 when `radius` is absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub particles: Option<usize>,
    /// Poisson-disc radius in world units, instead of `particles`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Target distribution of elevations. Default, when regions give heights to the coastline
    /// and at least one level inside it: one bin per slice between the given heights, weighted
    /// by the area the slice's levels cover (so the fit is exact), the top bin one height step
    /// above the highest given height.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub histogram: Option<HistogramSource>,
    /// How readily the growth advances where (default uniform).
    #[serde(default)]
    pub probability: Probability,
    /// Coarse-to-fine generation (the contours paper's §6.6): coarser growths first, each with
    /// `factor` times fewer nodes, whose order steers the next; the last runs at the full count.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub multilevel: Option<Multilevel>,
    /// How nested levels grow: `"double"` (the paper's double front, default) or `"per_region"`
    /// (Fig. 12's baseline: each level from its lower boundary alone).
    #[serde(default, skip_serializing_if = "is_double")]
    pub fronts: Fronts,
    /// Which contours to extract, besides the input contours' own levels (default 30 evenly
    /// spaced levels).
    #[serde(default = "contour_levels")]
    pub levels: Levels,
}

#[allow(clippy::trivially_copy_pass_by_ref, reason = "serde's skip_serializing_if passes a reference")]
fn is_double(fronts: &Fronts) -> bool {
    *fronts == Fronts::Double
}

fn contour_levels() -> Levels {
    Levels::Count(30)
}

/// A label image placed in the world.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LabelImage {
    /// The image (any PNG colour type, or any heightfield format), relative to the scene file.
    pub path: PathBuf,
    /// Where the image lies in the world (its pixel centres span this rectangle).
    pub extent: Extent,
    /// Keep enclosed lower areas as depressions (craters) instead of filling them.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub depressions: bool,
    /// What each colour means, outside first: without it the colours that form regions are the
    /// levels, darkest outside. Other colours (anti-aliased edges, specks) always snap to the
    /// nearest level around them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub levels: Option<Vec<LabelLevelSpec>>,
}

/// Multi-level generation: `passes − 1` coarse growths, then the final one.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, try_from = "MultilevelJson")]
pub struct Multilevel {
    /// Growths in all, 2 to 6 (the last at the scene's own node count).
    pub passes: u32,
    /// How many times fewer nodes each coarser pass has (default 4: twice the radius).
    pub factor: f64,
    /// How strongly a coarse order steers the next growth: `exp(−contrast · u)` for the coarse
    /// rank share `u` (default 6).
    pub contrast: f64,
}

/// Multi-level generation: `passes − 1` coarse growths, then the final one.
#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(rename = "Multilevel")]
struct MultilevelJson {
    /// Growths in all, 2 to 6 (the last at the scene's own node count).
    passes: u32,
    /// How many times fewer nodes each coarser pass has (> 1; default 4: twice the radius).
    #[serde(default = "default_factor")]
    factor: f64,
    /// How strongly a coarse order steers the next growth (≥ 0; default 6).
    #[serde(default = "default_contrast")]
    contrast: f64,
}

fn default_factor() -> f64 {
    4.0
}

fn default_contrast() -> f64 {
    6.0
}

impl TryFrom<MultilevelJson> for Multilevel {
    type Error = String;
    fn try_from(j: MultilevelJson) -> Result<Self, String> {
        if !(2..=6).contains(&j.passes) {
            return Err(format!("passes {} must be 2 to 6", j.passes));
        }
        if !(j.factor.is_finite() && j.factor > 1.0) {
            return Err(format!("factor {} must be finite and > 1", j.factor));
        }
        if !(j.contrast.is_finite() && j.contrast >= 0.0) {
            return Err(format!("contrast {} must be finite and ≥ 0", j.contrast));
        }
        Ok(Self { passes: j.passes, factor: j.factor, contrast: j.contrast })
    }
}

/// Contours a scene regrows terrain from (the contours paper's Fig. 24): every closed contour a
/// nested region at its height, pits as depressions.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ContourInput {
    /// A DEM (any heightfield format) whose contours to take; they are closed along its border,
    /// its lowest elevation is the coast (or, when that elevation is flat sea, on 1 % of the
    /// samples or more, its lowest land elevation, so the sea stays sea), and the summary
    /// compares the result with it (§6.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dem: Option<PathBuf>,
    /// A GeoJSON of contour lines (closed rings, or lines cut by the map's edge) or polygons with
    /// an elevation property; a previous run's `contours.geojson` works as it is.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geojson: Option<PathBuf>,
    /// DEM: contour spacing (default: 10 intervals over its range, rounded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interval: Option<f64>,
    /// DEM: these contour heights instead of an interval.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heights: Option<Vec<f64>>,
    /// GeoJSON: the property holding each feature's elevation (default: the first present of
    /// `elevation`, `ELEV`, `elev`, `height`, `z`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub property: Option<String>,
}

/// One row of a label image's colour table: a colour, and the level it marks. Rows go from the
/// outside (row 0) inward and upward.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LabelLevelSpec {
    /// The colour: `"#rrggbb"` (or `"#rgb"`), or a gray value in [0, 1] as the image reads
    /// (8-bit 128 is 0.502, 16-bit values keep their precision). Matches within 4 8-bit steps.
    pub value: LabelValue,
    /// Height of this level's contour, in metres; rows with heights must increase.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    /// This colour marks depressions (craters, lake basins) inside the level around them.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub depression: bool,
}

/// A colour of a label image: a `"#rrggbb"` string or a gray value in [0, 1].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum LabelValue {
    /// A gray value in [0, 1].
    Gray(f64),
    /// `"#rrggbb"` or `"#rgb"`.
    Color(String),
}

impl LabelValue {
    /// RGB in [0, 1].
    ///
    /// # Errors
    /// Why the value is not a colour: a gray outside [0, 1], a string not `#rrggbb` or `#rgb`.
    pub fn rgb(&self) -> Result<[f32; 3], String> {
        match self {
            Self::Gray(v) if (0.0..=1.0).contains(v) => Ok([*v as f32; 3]),
            Self::Gray(v) => Err(format!("gray value {v} is outside [0, 1]")),
            Self::Color(s) => parse_hex(s).ok_or_else(|| format!("{s:?} is not a colour: use \"#rrggbb\" or \"#rgb\"")),
        }
    }
}

fn parse_hex(s: &str) -> Option<[f32; 3]> {
    let digits = s.strip_prefix('#')?;
    if !digits.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    let channel = |k: usize, width: usize| {
        let v = u8::from_str_radix(&digits[k * width..(k + 1) * width], 16).ok()?;
        Some(f32::from(if width == 1 { v * 17 } else { v }) / 255.0)
    };
    let width = match digits.len() {
        3 => 1,
        6 => 2,
        _ => return None,
    };
    Some([channel(0, width)?, channel(1, width)?, channel(2, width)?])
}

/// Where the growth advances first (= lower ground).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Probability {
    /// Every frontier node equally likely: contours follow the distance to the border.
    #[default]
    Uniform,
    /// `exp(contrast · fbm(p))`: organic, fingered contours; the fBm is seeded by the scene.
    Fbm(FbmProbability),
    /// A painted map (any PNG colour type, or a heightfield), brighter = grown earlier.
    Image {
        /// The image, relative to the scene file.
        path: PathBuf,
        /// Where it lies in the world (default: the output domain).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        extent: Option<Extent>,
        /// Values are raised to this power (default 1; the paper's river map uses 4).
        #[serde(default = "unit_exponent")]
        exponent: f64,
    },
}

fn unit_exponent() -> f64 {
    1.0
}

/// Feature curves diffused into a terrain (Hnaidi et al. 2010). The solver fields are those of
/// [`SolveOptions`] and [`DiffusionOptions`], whose defaults they take.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DiffusionGenerator {
    /// The feature curves (with `presets`, at least one).
    #[serde(default)]
    pub curves: Vec<FeatureCurve>,
    /// Landforms by name (`ridge`, `multiple_ridges`, `riverbed`, `cliff`, `hill`, `crack`), each
    /// expanded into its curves after `curves`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub presets: Vec<Preset>,
    /// Solver of the diffusion equations (default multigrid).
    #[serde(default)]
    pub solver: Solver,
    /// Relative residual at which the solve stops (default 1e-4).
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
    /// At most this many iterations after the start: V-cycles (multigrid, default 60) or finest
    /// Jacobi sweeps after the pyramid (`jacobi_pyramid`, default 20 000). `0` with
    /// `jacobi_pyramid` is the paper's own fixed budget: 5·(l − i) sweeps on each level i of l,
    /// whatever residual that leaves (the run then warns that it stopped above the tolerance).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_iterations: Option<usize>,
    /// Wavelength of the first detail-noise octave, world units (default: 1/16 of the domain).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise_wavelength: Option<f64>,
    /// Octaves of the detail noise (default 4, as the paper).
    #[serde(default = "default_noise_octaves")]
    pub noise_octaves: u32,
    /// Ground below this is drawn as sea and drains (default: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sea_level: Option<f64>,
    /// What holds the domain's border. Default: free (the paper), unless the curves alone would
    /// make the terrain flat (one elevation, no slope constraint): then the border is held at
    /// `sea_level` (or 0) with no detail noise, so that a first curve stands out. A scene with no
    /// elevation at all (noise or slopes only, as the paper's Fig. 8) has its border held at
    /// `sea_level` (or 0) as the base level, the noise left to the curves.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub border: Option<Border>,
    /// Contours drawn from the result (default 20 evenly spaced levels).
    #[serde(default = "raster_levels")]
    pub levels: Levels,
}

impl DiffusionGenerator {
    /// The curves, then those of each preset in order: what is diffused (before any border).
    pub fn all_curves(&self) -> Vec<FeatureCurve> {
        let presets = self.presets.iter().flat_map(Preset::curves);
        self.curves.iter().cloned().chain(presets).collect()
    }
}

/// The domain's border in a diffusion scene.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Border {
    /// Nothing holds it (the paper): the ground there is whatever the curves diffuse to.
    Free,
    /// Held like a curve running round the domain.
    Held {
        /// Elevation along the border.
        elevation: f64,
        /// Detail-noise amplitude along the border (default: free), 0 to fade the noise out
        /// away from the curves.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        noise: Option<f64>,
    },
}

fn default_tolerance() -> f64 {
    SolveOptions::default().tolerance
}
fn default_noise_octaves() -> u32 {
    DiffusionOptions::default().noise_octaves
}

/// Parameters and editing history of a sketched island. The domain defaults to a 1000 × 1000
/// square from the origin; the raster is `reconstruction.resolution`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct IslandGenerator {
    /// Island height, snap distance, land floor and perturbation sizes.
    #[serde(default)]
    pub settings: IslandSettings,
    /// The start coastline traced from an image (a map or a paint-program mask used as a guide,
    /// the paper's §4.3 and Fig. 10) instead of the circle: the first operation of the session.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coastline_image: Option<CoastlineImage>,
    /// The operations, replayed in order on the start state (a circle of radius 0.4 × the
    /// domain's shorter side, centred, over a cone of `settings.height`; or `coastline_image`).
    #[serde(default)]
    pub operations: Vec<Operation>,
    /// Contours drawn from the result (default 20 evenly spaced levels).
    #[serde(default = "raster_levels")]
    pub levels: Levels,
}

/// An image whose land outline becomes an island's coastline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CoastlineImage {
    /// The image (any PNG colour type, read as gray levels, or any heightfield format), relative to
    /// the scene file.
    pub path: PathBuf,
    /// Where the image lies in the world (its pixel centres span this rectangle; default: the
    /// scene's domain).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extent: Option<Extent>,
    /// Which side of the outline is land (default `light`: light land on a dark sea, as label
    /// images have it).
    #[serde(default)]
    pub land: LandTone,
    /// The gray level of the coastline, 0 (black) to 1 (white) (default: halfway between the
    /// image's darkest and lightest pixels, so anti-aliased edges split evenly).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub threshold: Option<f64>,
}

/// Which tone of a coastline image is land.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum LandTone {
    /// Land is lighter than the threshold.
    #[default]
    Light,
    /// Land is darker than the threshold (a dark island drawn on white paper).
    Dark,
}

/// A vector terrain and the tools applied to it. The domain defaults to the source terrain's
/// recorded domain, else its primitives' supports (before the tools run); the raster is
/// `reconstruction.resolution`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GaussianGenerator {
    /// Where the primitives come from.
    pub source: GaussianSource,
    /// Tool operations, applied in order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub operations: Vec<Tool>,
    /// How the crest skeleton of the crest tools is extracted.
    #[serde(default)]
    pub skeleton: SkeletonOptions,
    /// Contours drawn from the result (default 20 evenly spaced levels).
    #[serde(default = "raster_levels")]
    pub levels: Levels,
}

/// The starting primitives of a `gaussian` generator.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum GaussianSource {
    /// A vector terrain written in the scene: `primitives`, and optionally `base`, `floor`,
    /// `domain`, `details`, and the `units` and `crs` its coordinates are in (the raster's
    /// labels; planar metres by default).
    Primitives(VectorTerrain),
    /// A vector terrain saved as JSON (`relief vectorize` writes them, with the DEM's units and
    /// CRS, which the raster keeps).
    Terrain {
        /// The file, relative to the scene.
        #[schemars(with = "String")]
        path: PathBuf,
    },
    /// A DEM (any format `relief` reads) vectorized first. A scene fit is smaller than
    /// `relief vectorize`'s by default: 2000 primitives on a 256-sample grid.
    Dem {
        /// The file, relative to the scene.
        #[schemars(with = "String")]
        path: PathBuf,
        /// Most primitives (default 2000).
        #[serde(default = "dem_primitives")]
        primitives: usize,
        /// Optimisation steps (default 260).
        #[serde(default = "dem_iterations")]
        iterations: usize,
        /// Working-grid resolution (default 256).
        #[serde(default = "dem_resolution")]
        resolution: usize,
        /// Keep the fit within the DEM's elevation range, with a flat floor where its lowest
        /// ground is flat (default true; false fits the paper's plain sum) —
        /// [`crate::gaussian_terrain::VectorizeOptions::keep_range`].
        #[serde(default = "super::default_true", skip_serializing_if = "is_true")]
        keep_range: bool,
        /// Add error-map detail primitives at this Poisson spacing in DEM cells, so the vector
        /// terrain restores the DEM (2 restores it to f32 rounding; default none) —
        /// [`crate::gaussian_terrain::VectorizeOptions::detail_spacing`].
        #[serde(default, skip_serializing_if = "Option::is_none")]
        details: Option<f64>,
        /// The range of the primitives' exponent β, `[min, max]` (default `[0.6, 8]`; `[2, 4]`
        /// is the paper's kernel, faster on large grids for a little more error) —
        /// [`crate::gaussian_terrain::VectorizeOptions::beta_range`].
        #[serde(default, skip_serializing_if = "Option::is_none")]
        beta_range: Option<[f64; 2]>,
        /// Fill the DEM's no-data samples before the fit: `"min"` at its lowest elevation (a
        /// country masked beyond its border, a sea stored as no-data; the fit's floor then holds
        /// that ground flat) or at an elevation. Default none: a DEM with no-data is refused.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        fill_no_data: Option<NoDataFill>,
    },
}

/// What a DEM's no-data samples are filled with: `"min"` or an elevation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
#[serde(untagged)]
pub enum NoDataFill {
    /// This elevation.
    Elevation(f64),
    /// `"min"`: the DEM's lowest elevation.
    Lowest(Lowest),
}

/// The word `"min"` of [`NoDataFill::Lowest`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Lowest {
    /// The lowest elevation.
    Min,
}

impl NoDataFill {
    /// Fills `dem`'s no-data samples; the elevation used.
    ///
    /// # Errors
    /// Why nothing can fill them: every sample is no-data (`"min"` has no lowest to take), or
    /// the elevation is not a finite `f32`.
    pub fn fill(self, dem: &mut crate::heightfield::Heightfield) -> Result<f32, String> {
        let value = match self {
            Self::Elevation(v) if (v as f32).is_finite() => v as f32,
            Self::Elevation(v) => return Err(format!("{v} is beyond the elevations a heightfield holds (f32)")),
            Self::Lowest(Lowest::Min) => {
                dem.min_max().ok_or("every sample is no-data: there is no lowest elevation")?.0
            }
        };
        dem.fill_no_data(value).map_err(|e| e.to_string())?;
        Ok(value)
    }
}

impl<'de> Deserialize<'de> for NoDataFill {
    /// A number, or the word `"min"`; anything else is refused with what the field takes (an
    /// untagged enum's own error names no value).
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error as _;
        match serde_json::Value::deserialize(d)? {
            serde_json::Value::Number(n) => {
                n.as_f64().map(Self::Elevation).ok_or_else(|| D::Error::custom("an elevation out of range"))
            }
            serde_json::Value::String(word) => word.parse().map_err(D::Error::custom),
            other => Err(D::Error::custom(format!("{other}: give \"min\" or an elevation"))),
        }
    }
}

impl std::str::FromStr for NoDataFill {
    type Err = String;

    /// `min`, or an elevation.
    fn from_str(text: &str) -> Result<Self, String> {
        if text.eq_ignore_ascii_case("min") {
            return Ok(Self::Lowest(Lowest::Min));
        }
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(Self::Elevation(v)),
            _ => Err(format!("{text}: give `min` or a finite elevation")),
        }
    }
}

#[allow(clippy::trivially_copy_pass_by_ref, reason = "serde's skip_serializing_if passes a reference")]
fn is_true(b: &bool) -> bool {
    *b
}

fn dem_primitives() -> usize {
    2000
}
fn dem_iterations() -> usize {
    crate::gaussian_terrain::VectorizeOptions::default().iterations
}
fn dem_resolution() -> usize {
    256
}

/// An orometric synthesis (Argudo et al. 2019, §5–6).
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
    /// A type map `C_T` (§7.2): several terrain types, each with its own orometry, in one
    /// synthesis. Without it, `source` applies everywhere.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub types: Option<OrometryTypes>,
    /// Peaks placed before synthesis, kept at their positions and heights.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pinned: Vec<TreePeak>,
    /// Divide tree generation (§5); its seed is replaced by the scene's.
    #[serde(default)]
    pub tree: TreeOptions,
    /// Terrain generation (§6); its seed is replaced by the scene's.
    #[serde(default)]
    pub terrain: TerrainOptions,
    /// Divide tree edits after generation, applied in order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub edits: Vec<TreeEdit>,
    /// Contours drawn from the result (default 20 evenly spaced levels).
    #[serde(default = "raster_levels")]
    pub levels: Levels,
}

/// A type map `C_T` of an `orometry` generator: where each terrain type lies.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OrometryTypes {
    /// The map (any format `relief` reads, e.g. a grayscale PNG painted by hand; stretched over
    /// the domain). Its values, from its lowest to its highest, fall into as many equal bands as
    /// there are types: the lowest band takes the generator's `source`, the next ones `sources`
    /// in order (two types: dark and light; three: dark, mid-gray and light). Anti-aliased edges
    /// fall into the nearer band.
    #[schemars(with = "String")]
    pub map: PathBuf,
    /// The orometry of each further type (`use_tree` cannot be given here).
    pub sources: Vec<OrometrySource>,
}

/// The target orometry of an `orometry` generator.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum OrometrySource {
    /// A DEM (any format `relief` reads) analysed first, with the analysis options of
    /// [`crate::orometry::AnalysisOptions`].
    Dem {
        /// The file, relative to the scene.
        #[schemars(with = "String")]
        path: PathBuf,
        /// Peaks at least this prominent count (default 30 m, the usual summit-list cut).
        #[serde(default = "summit_prominence")]
        min_prominence: f64,
        /// Ground at or below this is sea.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        sea_level: Option<f32>,
        /// Build the terrain on the DEM's own divide tree (pruned at `min_prominence`) instead of
        /// a generated one: the paper's "T2" (§7), a real tree turned into a new terrain. The
        /// tree is stretched from the DEM's extent over the domain; pinned peaks and control
        /// maps, which shape a generated tree, cannot be given with it; edits still apply.
        #[serde(default, skip_serializing_if = "std::ops::Not::not")]
        use_tree: bool,
    },
    /// A descriptor saved as JSON (`relief analyze --descriptor` writes them).
    Descriptor {
        /// The file, relative to the scene.
        #[schemars(with = "String")]
        path: PathBuf,
    },
}

fn summit_prominence() -> f64 {
    30.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heightfield::{GridSpec, Heightfield};

    fn dem() -> Heightfield {
        let grid = GridSpec::new(2, 2, glam::DVec2::ZERO, glam::DVec2::ONE).unwrap();
        Heightfield::from_samples(grid, vec![f32::NAN, 5.0, 7.0, f32::NAN]).unwrap()
    }

    /// `min` (any case) or a finite number; infinities and words are refused with what is taken.
    #[test]
    fn no_data_fills_parse() {
        assert_eq!("MIN".parse(), Ok(NoDataFill::Lowest(Lowest::Min)));
        assert_eq!("-3.5".parse(), Ok(NoDataFill::Elevation(-3.5)));
        for bad in ["inf", "NaN", "max", ""] {
            let err = bad.parse::<NoDataFill>().unwrap_err();
            assert!(err.contains("give `min` or a finite elevation"), "{bad}: {err}");
        }
    }

    /// `min` fills at the lowest valid sample, an elevation at itself; an elevation beyond f32
    /// and a DEM with no valid sample are refused.
    #[test]
    fn no_data_fills_fill() {
        let mut d = dem();
        assert_eq!(NoDataFill::Lowest(Lowest::Min).fill(&mut d), Ok(5.0));
        assert_eq!(d.samples(), [5.0, 5.0, 7.0, 5.0]);
        let mut d = dem();
        assert_eq!(NoDataFill::Elevation(-2.0).fill(&mut d), Ok(-2.0));
        assert_eq!(d.samples(), [-2.0, 5.0, 7.0, -2.0]);
        let err = NoDataFill::Elevation(1e39).fill(&mut dem()).unwrap_err();
        assert!(err.contains("beyond the elevations a heightfield holds"), "{err}");
        let grid = GridSpec::new(2, 1, glam::DVec2::ZERO, glam::DVec2::ONE).unwrap();
        let mut empty = Heightfield::from_samples(grid, vec![f32::NAN; 2]).unwrap();
        assert!(NoDataFill::Lowest(Lowest::Min).fill(&mut empty).unwrap_err().contains("every sample is no-data"));
    }
}
