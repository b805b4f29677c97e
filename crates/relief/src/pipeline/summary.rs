//! What a run did: the scene, counts, histogram match and timings, written as `summary.json`.
//! [`Summary::new`] is the one place it is assembled.

use serde::Serialize;

use super::Report;
use super::contour_input::{Comparison, ContourInputSummary};
use super::progress::Timing;
use crate::contours::{ContourSet, Histogram};
use crate::diffusion::SolveReport;
use crate::eden_growth::{MaskCleaning, hex};
use crate::heightfield::{Extent, Heightfield};
use crate::orometry::DivideTree;
use crate::scene::Scene;

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
    /// What reading contour input did (contour generator from `contours` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contour_input: Option<ContourInputSummary>,
    /// The terrain against the DEM its contours came from (§6.5 of the contours paper).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub comparison: Option<Comparison>,
    /// What reading the label image changed (contour generator from a label image only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub label_image: Option<MaskSummary>,
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
    /// What the user should know about the result: a poor histogram fit (with a histogram that
    /// fits), an input that had no effect. The CLI prints them as warnings.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// The files the run wrote, relative to its output folder, this summary last (empty until
    /// [`super::write_outputs`] writes them). A later run into the same folder removes those it
    /// does not write again.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub files: Vec<std::path::PathBuf>,
    /// Time per step, in order (they vary from run to run, unlike everything else).
    pub timings_ms: Vec<Timing>,
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

/// What reading a drawn label image changed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MaskSummary {
    /// The colour of each level, outside first (`#rrggbb`, or `transparent`).
    pub levels: Vec<String>,
    /// Pixels of no level's colour (anti-aliased edges, specks) that took a neighbouring level.
    pub snapped_pixels: usize,
    /// Patches smaller than this many pixels were merged into their surroundings.
    pub min_patch_pixels: usize,
    /// How many patches were merged.
    pub merged_count: usize,
    /// The first 100 merged patches, smallest first.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub merged: Vec<MergedSummary>,
}

/// A patch of a label image merged into the level around it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MergedSummary {
    /// Its centroid, world units.
    pub at: [f64; 2],
    /// Its size, pixels.
    pub pixels: usize,
    /// Its colour.
    pub color: String,
    /// The colour of the level it joined.
    pub into: String,
}

impl From<&MaskCleaning> for MaskSummary {
    fn from(c: &MaskCleaning) -> Self {
        Self {
            levels: c
                .colors
                .iter()
                .enumerate()
                .map(|(l, &k)| if l == 0 && c.transparent_outside { "transparent".to_owned() } else { hex(k) })
                .collect(),
            snapped_pixels: c.snapped_pixels,
            min_patch_pixels: c.min_patch_pixels,
            merged_count: c.merged_count,
            merged: c
                .merged
                .iter()
                .map(|m| MergedSummary {
                    at: m.at.to_array(),
                    pixels: m.pixels,
                    color: hex(m.color),
                    into: hex(m.into),
                })
                .collect(),
        }
    }
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
    pub domain: Extent,
    /// Lowest sample.
    pub min: f32,
    /// Highest sample.
    pub max: f32,
    /// Sea level: lower samples are sea (the contour generator's coastline, a diffusion scene's
    /// `sea_level`, half an island's land floor); `null` when the terrain has no sea.
    pub sea_level: Option<f64>,
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
    /// Measures of what generated terrain shows and real ground does not (a border trench,
    /// closed pits, one-cell slots, planar facets): `cargo xtask artefacts` prints them for
    /// every gallery scene.
    pub artefacts: crate::hydrology::Artefacts,
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

/// What an orometry scene ended with.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OrometrySummary {
    /// Peaks in the divide tree (after edits).
    pub peaks: usize,
    /// Saddles in the divide tree.
    pub saddles: usize,
    /// Terrain types: 1, or the type map's count. With a type map, the target every comparison
    /// here is made against is the first type's (the generator's `source`), so they include how
    /// far the other types are from it.
    pub types: usize,
    /// Earth mover's distance between the tree's prominence histogram and the target's.
    pub prominence_emd: f64,
    /// Largest bin difference between the tree's prominence histogram and the target's.
    pub prominence_max_bin_error: f64,
    /// Largest bin difference between the tree's dominance histogram and the target's.
    pub dominance_max_bin_error: f64,
    /// The generated terrain analysed again and compared with the target (§7 measures its errors
    /// on the terrain, not on the tree); `None` when the terrain has no land to analyse.
    pub terrain: Option<TerrainOrometry>,
    /// The tree itself (written by `outputs.divide_tree`, not into the summary).
    #[serde(skip)]
    pub tree: DivideTree,
}

/// The orometry of a generated terrain against its target: what the paper's §7 reports.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TerrainOrometry {
    /// The prominence threshold the terrain was analysed at (the target DEM's, or the least
    /// prominent peak of the tree for a descriptor target).
    pub min_prominence: f64,
    /// The sea level the terrain was analysed with (the target DEM's).
    pub sea_level: Option<f32>,
    /// Peaks of the terrain at least that prominent.
    pub peaks: usize,
    /// Peaks the target has.
    pub target_peaks: usize,
    /// Peaks per km² on the terrain.
    pub density_per_km2: f64,
    /// Peaks per km² in the target.
    pub target_density_per_km2: f64,
    /// Per Table 1 feature, in `relief_orometry::FEATURES` order: its name, the earth mover's
    /// distance between the terrain's histogram and the target's, and their largest bin difference.
    pub features: Vec<(String, f64, f64)>,
}

impl TerrainOrometry {
    /// The largest bin difference of one feature.
    pub fn max_bin_error(&self, feature: &str) -> Option<f64> {
        self.features.iter().find(|f| f.0 == feature).map(|f| f.2)
    }
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

impl Summary {
    /// The summary of a run of `scene`: what the generator reported, the final heightfield and
    /// contours, the drainage, and the steps' timings so far.
    pub(super) fn new(
        scene: &Scene,
        report: Report,
        heightfield: &Heightfield,
        contours: &ContourSet,
        sea_level: Option<f64>,
        drainage: DrainageSummary,
        timings_ms: Vec<Timing>,
    ) -> Self {
        let (min, max) = heightfield.min_max().unwrap_or((f32::NAN, f32::NAN));
        let mut summary = Self {
            relief_version: env!("CARGO_PKG_VERSION"),
            scene: scene.clone(),
            graph: None,
            label_image: None,
            contour_input: None,
            comparison: None,
            contours: ContourSummary {
                levels: contours.levels().len(),
                contours: contours.len(),
                vertices: contours.vertex_count(),
            },
            heightfield: RasterSummary {
                nx: heightfield.nx(),
                ny: heightfield.ny(),
                domain: heightfield.extent(),
                min,
                max,
                sea_level,
            },
            histogram_match: None,
            diffusion: None,
            island: None,
            gaussian: None,
            orometry: None,
            drainage,
            warnings: Vec::new(),
            files: Vec::new(),
            timings_ms,
        };
        match report {
            Report::Contours { graph, histogram, nodes_ks, mask, contour_input, reference: _ } => {
                summary.graph = Some(graph);
                summary.contour_input = contour_input;
                summary.label_image = mask.as_ref().map(MaskSummary::from);
                summary.histogram_match =
                    Some(HistogramMatch { nodes: nodes_ks, raster: land_ks(&histogram, heightfield, sea_level) });
            }
            Report::Diffusion(report) => summary.diffusion = Some(report),
            Report::Island(island) => summary.island = Some(island),
            Report::Gaussian(gaussian) => summary.gaussian = Some(gaussian),
            Report::Orometry(orometry) => summary.orometry = Some(orometry),
        }
        summary
    }
}

/// The KS distance between `histogram` and the raster samples on land (1 when there is none).
fn land_ks(histogram: &Histogram, heightfield: &Heightfield, sea_level: Option<f64>) -> f64 {
    let sea = sea_level.unwrap_or(f64::NEG_INFINITY);
    let land: Vec<f64> = heightfield.samples().iter().map(|&v| f64::from(v)).filter(|&v| v >= sea).collect();
    if land.is_empty() { 1.0 } else { histogram.ks_distance(&land) }
}
