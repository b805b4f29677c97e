//! Orometry of DEMs after Argudo et al., "Orometry-based Terrain Analysis and Synthesis"
//! (SIGGRAPH Asia 2019), §4.1: peaks, key saddles, prominence, dominance, relative prominence
//! and elevation, relevance, isolation and the divide tree, with the conventions of summit lists
//! (Kirmse & de Ferranti 2017) for plateaus, map edges, the sea and no-data (see [`analyze`]).
//!
//! - [`analyze`] floods the DEM from the top: every cell that joins two components is a saddle
//!   where the lower component's peak meets its key saddle. It joins ascent basins rather than
//!   cells, sorting only the cells where basins meet (linear passes plus a sort of a few per cent
//!   of the map; 3601² in about 1.2 s on 2 cores). Ties break by row-major index, so results are deterministic and
//!   independent of the thread count.
//! - Isolation searches a pyramid of block maxima best-first (module `isolation`), opening only
//!   blocks that hold higher ground.
//! - The divide tree is built by adjacency, as §3 and akirmse/mountains define it (module
//!   `divide`): the flood's joins are a maximum spanning tree of the ascent basins, each saddle
//!   joining the two peaks whose basins meet there (not a peak and its prominence parent), and
//!   pruning merges a dropped peak into the neighbour across its highest saddle, the way
//!   akirmse's merge does. On the Jacksboro DEM, 182 of akirmse's 184 peaks ≥ 30 m are ours
//!   within a metre and 174 of its 183 ridges join the same peaks through the same saddle (± 1
//!   cell); the rest sit on the map's edge or on flat cols of equal height.
//! - [`Orometry::pruned`] cuts the divide tree at a prominence threshold (Fig. 6);
//!   [`Orometry::line_parents`] gives each peak's line parent beside its prominence parent;
//!   with [`AnalysisOptions::ridge_lines`] every saddle carries its ridge along the DEM's cells,
//!   peak → saddle → peak ([`Saddle::ridge`]).
//! - [`Dvt`] reads and writes akirmse's `.dvt` divide-tree files, so trees go through its tools
//!   and back; [`ProminenceBase::SeaLevel`] counts land-mass tops from the sea as it does, and
//!   [`AnalysisOptions::depressions`] gives anti-prominence (pits, bathymetry).
//! - [`Descriptor`] (§4.2, Table 1) summarizes a domain's peaks in ten [`FractionHistogram`]s
//!   (fractions over explicit bin edges); [`Descriptor::distance`] compares two (EMD in bins,
//!   circular for directions, and max bin error) and [`classify`] finds the nearest labelled
//!   reference. The EMD is [`relief_hydrology::earth_movers_distance`] over step CDFs in bin
//!   units, the same integral [`relief_hydrology::CountHistogram::wasserstein`] takes in value
//!   units.
//! - Synthesis: [`generate_tree`] builds a [`DivideTree`] that follows a descriptor (§5: dart
//!   throwing, multi-pass placement, Delaunay MST ridges, saddle heights by optimal assignment),
//!   [`terrain_from_tree`] turns a tree into a heightfield (§6: dual rivers, refinement, Poisson
//!   fill, constrained TIN, noise, erosion with uplift compensation, then a sweep that cuts any
//!   col the terrain raised above the tree's), and [`synthesize`] does both. Judged on the
//!   terrain, as §7 does: a 48 × 48 km range synthesized from the Jacksboro fixture's orometry and
//!   analysed again has maximum histogram errors of 1.2 % (prominence), 1.2 % (dominance) and
//!   3.1 % (isolation), against the paper's 2–3, 2–3 and 8 %. [`generate_typed_tree`] follows a
//!   type map `C_T` instead (§7.2): several descriptors, each in its own region, one tree.
//!   [`relief_tin`] triangulates and [`relief_hydrology`] erodes; `rand_chacha` seeds
//!   every random choice, so a seed gives identical bytes for any thread count.
//! - Editing (§7.2): [`TreeEdit`] (insert, move or delete peaks, saddles and ridges) as data,
//!   applied with [`DivideTree::apply`]. Trees, descriptors and edits are serde types that
//!   validate as they deserialize; the optional `schemars` feature derives the JSON Schemas of
//!   the synthesis options, pinned peaks and edits for `relief` scenes.
//!
//! # Example
//! ```
//! use glam::DVec2;
//! use relief_heightfield::{Extent, GridSpec, Heightfield};
//! use relief_orometry::{AnalysisOptions, analyze};
//!
//! // Two cones, 100 and 80 high, joined by a col at 40.
//! let grid = GridSpec::from_extent(61, 21, Extent::new(DVec2::ZERO, DVec2::new(60.0, 20.0)))?;
//! let dem = Heightfield::from_fn(grid, |p| {
//!     let a = 100.0 - 6.0 * p.distance(DVec2::new(15.0, 10.0));
//!     let b = 80.0 - 2.0 * p.distance(DVec2::new(45.0, 10.0));
//!     a.max(b).max(0.0) as f32
//! })?;
//! let oro = analyze(&dem, &AnalysisOptions::default())?;
//! let (high, low) = (&oro.peaks[0], &oro.peaks[1]);
//! assert_eq!((high.elevation, low.elevation), (100.0, 80.0));
//! assert!((low.prominence - 40.0).abs() < 0.5); // down to the col at 40
//! assert_eq!(low.parent, Some(0));
//! assert!(high.isolation.is_none()); // nothing is higher
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod analysis;
mod carve;
mod descriptor;
mod divide;
mod dvt;
mod edit;
mod error;
mod generate;
mod isolation;
mod network;
mod point_grid;
mod ridgeline;
mod rivers;
mod terrain;
mod tree;
mod types;
mod union_find;

pub use analysis::{AnalysisOptions, MAX_CELLS, Orometry, Peak, ProminenceBase, Saddle, analyze};
pub use descriptor::{
    DOMINANCE_GROUP_EDGES, Descriptor, DescriptorDistance, DomainStats, FEATURES, FractionHistogram, classify,
};
pub use dvt::{Dvt, DvtGrid};
pub use edit::TreeEdit;
pub use error::OrometryError;
pub use generate::{ControlMaps, MAX_PEAKS, TreeOptions, generate_tree};
pub use isolation::Isolation;
pub use terrain::{MAX_MESH_SAMPLES, TerrainOptions, terrain_from_tree};
pub use tree::{DivideTree, TreeOrometry, TreePeak, TreeSaddle};
pub use types::{MAX_TYPES, TypeMap, generate_typed_tree};

use relief_heightfield::{GridSpec, Heightfield};
use serde::{Deserialize, Serialize};

/// Options of the whole synthesis: the divide tree (§5), then the terrain (§6).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SynthesisOptions {
    /// Divide tree generation.
    pub tree: TreeOptions,
    /// Terrain generation.
    pub terrain: TerrainOptions,
}

/// Synthesizes a terrain on `grid` whose orometry follows `descriptor`: [`generate_tree`] over the
/// grid's extent, then [`terrain_from_tree`] with the descriptor's lowest elevation as the base.
/// Returns the divide tree and the heightfield.
///
/// # Errors
/// Those of [`generate_tree`] and [`terrain_from_tree`].
pub fn synthesize(
    descriptor: &Descriptor,
    grid: &GridSpec,
    controls: &ControlMaps,
    pinned: &[TreePeak],
    options: &SynthesisOptions,
    mut progress: impl FnMut(&str, f64),
) -> Result<(DivideTree, Heightfield), OrometryError> {
    let tree = generate_tree(descriptor, grid.extent(), controls, pinned, &options.tree)?;
    progress("divide tree", 1.0);
    let hf = terrain_from_tree(&tree, descriptor.domain.min_elevation, grid, &options.terrain, progress)?;
    Ok((tree, hf))
}

/// The crate README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExample;
