//! Sketch-based island terrains after Puig-Centelles et al., "Sketch-based terrain modeling for
//! islands" (§3 and §5): a closed coastline edited by strokes, elliptic-paraboloid hills and
//! seeded perturbation filters, kept as three grids whose sum is the terrain.
//!
//! - [`Island::stroke`] (§3.1): a stroke is split where it meets the coast; a piece through the
//!   land cuts off what lies left of the stroke, a piece outside adds the area it encloses when
//!   drawn clockwise and keeps only that area when drawn counter-clockwise. One stroke may do
//!   several operations, one per pair of consecutive crossings.
//! - Heights (§3.2): after a coastline change `H = H_o(1 − W) + H_n·W`,
//!   `W = ½ + ½·tanh(D_o² − D_n)`, so land next to unchanged coast keeps its heights and land next
//!   to new coast rises from sea level. Distances come from a labelled Euclidean distance
//!   transform (relief-heightfield) at half resolution over the coast's bounds, its labels
//!   corrected by two sweeps, then measured exactly to the labelled coast edges (within half
//!   a cell of the true distance in the tests), so a full silhouette update at 1024² takes
//!   about 40 ms, not the paper's 8 s. Coast off the grid counts too.
//! - [`Hill`] (§3.3): `z = h·(1 − x²/a² − y²/b²)` inside the rotated ellipse; negative heights
//!   make craters and lakes. Filters (§3.4): perturbations of the same shape, wider than tall,
//!   count proportional to the island's area, stored so they re-apply after every edit.
//! - Incremental updates (§5): a hill or filter edit recomputes only the samples under the
//!   primitives it touches, row by row over each paraboloid's span; a batch of filters is one
//!   parallel pass. [`Island::rebuild`] recomputes everything and gives the same bytes.
//! - Sea samples are exactly 0, land samples at least `land_floor`.
//! - [`Operation`] lists replay an editing session (the facade's `island` scene kind).
//!
//! The optional `schemars` feature derives JSON Schemas for the scene types, so the facade's
//! scene schema can document them without a mirrored copy.
//!
//! ```
//! use glam::DVec2;
//! use relief_heightfield::{Extent, GridSpec};
//! use relief_island::{Hill, Island, IslandSettings};
//!
//! let grid = GridSpec::from_extent(129, 129, Extent::new(DVec2::ZERO, DVec2::splat(1000.0)))?;
//! let mut island = Island::new(grid, IslandSettings::default(), 7)?;
//! // Cut the western third off: a stroke drawn upwards removes what lies on its left.
//! island.stroke(&[DVec2::new(350.0, -10.0), DVec2::new(350.0, 1010.0)])?;
//! assert!(!island.land()[grid.index(20, 64)] && island.land()[grid.index(80, 64)]);
//! // A volcano: a hill and a smaller hollow in its middle.
//! island.add_hill(Hill::round(DVec2::new(600.0, 500.0), 200.0, 150.0))?;
//! island.add_hill(Hill::round(DVec2::new(600.0, 500.0), 60.0, -60.0))?;
//! let t = island.terrain();
//! assert!(t[grid.index(77, 64)] < t[grid.index(84, 64)]);
//! assert_eq!(t[0], 0.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![forbid(unsafe_code)]

mod error;
mod geometry;
mod hill;
mod island;

pub use error::IslandError;
pub use geometry::EditKind;
pub use hill::Hill;
pub use island::{
    Island, IslandLayers, IslandSettings, MAX_CELLS, MAX_EXTENT, MAX_FILTERS, MAX_HEIGHT, NewHeights, Operation,
};

/// The crate README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExample;
