//! Iso-contours as a terrain representation (Huftier et al. 2025): heights assigned to a growth
//! order by histogram quantiles (§4.4), marching-triangle extraction of many levels in one pass
//! (§4.4), the contour tree of their nesting (§3.1), smoothing that never makes contours cross
//! (§5.1), and reconstruction to a [`relief_heightfield::Heightfield`] — stairs and Hormann's
//! interpolation (§3.2). The same extraction turns a raster DEM into contours (like `gdal_contour`).
//!
//! Main types: [`Histogram`] and [`assign_heights`] (from a [`Ranking`] — plain data, e.g. the
//! order of `relief-eden-growth`), [`extract_tin`] / [`extract_dem`] → [`ContourSet`] of
//! [`Contour`]s (checked by [`ContourSet::check_invariants`]), [`Levels`] (a count, an interval or
//! heights, resolved over a range), [`Smoothing`], [`reconstruct_stairs`] /
//! [`reconstruct_interpolated`].
//!
//! [`Histogram`], [`Levels`] and [`Smoothing`] are serde types in the JSON shape of `relief`
//! scenes and check their values as they deserialize; the optional `schemars` feature derives
//! their JSON Schemas. [`ContoursError::location`] names the parameter an error is about.
//!
//! Beyond the paper: crossings are linear interpolation on the mesh edge shared by two triangles,
//! computed once per edge so polylines close exactly; all levels come out of a single pass over the
//! triangles (O(N + output), not O(K·N)); a node exactly at a level counts as above it and its
//! crossings are nudged off it, so contours never touch.
//!
//! On a raster DEM ([`extract_dem`]) the lines are those `gdal_contour` draws, point for point
//! (checked against GDAL 3.6's output, holes and borders included): marching squares between
//! sample centres with GDAL's fixed saddle rule and tie fudge, and squares with a corner outside
//! the raster or without data split into quarters, so lines run on to the raster's outer edge and
//! end half-way to no-data. They are linked by the identity of the edges they cross, row by row,
//! so nothing but the lines is kept (less memory than GDAL at every interval measured). The nesting tree is O(n log n) in the closed rings: a bounding-volume
//! hierarchy over their boxes, from [`obvhs`] (the design card's BVH crate: a well-tested PLOC
//! builder with point traversal, rather than a hand-written R-tree), answers "which boxes hold this
//! point", and only those rings get the exact test.
//!
//! ```
//! use glam::DVec2;
//! use relief_contours::{Histogram, Ranking, assign_heights, evenly_spaced_levels, extract_tin};
//! use relief_eden_growth::{Graph, GraphOptions, Region, RegionTree, Uniform, grow};
//! use relief_tin::poisson_sampling::Polygon;
//!
//! let tree = RegionTree::new(vec![Region::new(Polygon::circle(DVec2::ZERO, 1000.0, 64)?)])?;
//! let graph = Graph::from_regions(&tree, &GraphOptions::particles(4_000).with_seed(1))?;
//! let growth = grow(&graph, &Uniform, 1)?;
//! let level_ends = [growth.order().len()];
//! let ranking = Ranking { order: growth.order(), level_ends: &level_ends, level_heights: &[None] };
//! let heights = assign_heights(graph.tin().num_points(), &ranking, &Histogram::uniform(0.0, 500.0)?)?;
//!
//! let contours = extract_tin(graph.tin(), &heights.heights, &evenly_spaced_levels(0.0, 500.0, 9)?)?;
//! contours.check_invariants()?;
//! assert!(contours.contours().iter().all(|c| c.closed));
//! assert_eq!(contours.nests_by_level(), Ok(()));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod closing;
mod contour;
mod error;
mod extract;
mod geometry;
mod heights;
mod histogram;
mod levels;
mod reconstruct;
mod smooth;
mod squares;

pub use contour::{Contour, ContourSet};
pub use error::ContoursError;
pub use extract::extract_tin;
pub use heights::{Heights, Ranking, assign_heights};
pub use histogram::{Histogram, HistogramSpec};
pub use levels::{Levels, MAX_LEVELS, evenly_spaced_levels, interval_levels};
pub use reconstruct::{Interpolation, Summit, reconstruct_interpolated, reconstruct_stairs};
pub use smooth::{Smoothing, smooth_heights};
pub use squares::extract_dem;

/// The crate README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExample;
