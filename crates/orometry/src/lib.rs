//! Orometry of DEMs after Argudo et al., "Orometry-based Terrain Analysis and Synthesis"
//! (SIGGRAPH Asia 2019), §4.1: peaks, key saddles, prominence, dominance, relative prominence
//! and elevation, relevance, isolation and the divide tree, with the conventions of summit lists
//! (Kirmse & de Ferranti 2017) for plateaus, map edges, the sea and no-data (see [`analyze`]).
//!
//! - [`analyze`] floods the DEM from the top with a union–find (sort O(N log N), then
//!   near-linear): every cell that joins two components is a saddle where the lower component's
//!   peak meets its key saddle. Ties break by row-major index, so results are deterministic and
//!   independent of the thread count.
//! - Isolation searches a pyramid of block maxima best-first (module `isolation`), opening only
//!   blocks that hold higher ground.
//! - [`Orometry::pruned`] cuts the divide tree at a prominence threshold (Fig. 6).
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
mod error;
mod isolation;

pub use analysis::{AnalysisOptions, MAX_CELLS, Orometry, Peak, Saddle, analyze};
pub use error::OrometryError;
pub use isolation::Isolation;
