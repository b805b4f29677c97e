//! Delaunay triangulated irregular networks (TINs) as compact flat arrays — nodes, counter-clockwise
//! triangles, triangle neighbours, CSR vertex adjacency, boundary flags — with point location,
//! barycentric interpolation and parallel rasterization of per-node values to a [`Heightfield`](relief_heightfield::Heightfield).
//!
//! This is the graph the contours paper grows on (Huftier et al. 2025, §4.3: "a Delaunay
//! triangulation … gives the graph G"; §4.4 extracts iso-contours from it), and the mesh the
//! orometry synthesis (Argudo et al. 2019, §6) interpolates. The triangulation itself is spade's;
//! this crate copies it into plain arrays that every later crate shares, so no spade handle leaks
//! out and a `Tin` serialises as points plus triangles.
//!
//! Cost: copying is parallel and reads spade's faces once, then walks the vertex fans on the flat
//! arrays in triangle order. Measured in pairs on a shared 2-core machine
//! (`cargo run --release -p relief-tin --example wrapper_overhead -- N`), `Tin::new` takes 1.24× spade's
//! `bulk_load` alone at 100k points and 1.27× at 1M (target < 1.3×).
//!
//! Main types: [`Tin`] (build with [`Tin::new`] or [`Tin::from_parts`]; verify with
//! [`Tin::check_invariants`]), [`Location`], [`PointLocator`]. The polygon and sampling types of
//! `relief-poisson-sampling` and the grid types of `relief-heightfield` are re-exported as
//! [`poisson_sampling`] and [`heightfield`] for crates that build on the TIN.
//!
//! ```
//! use glam::DVec2;
//! use relief_tin::{Location, Tin};
//! use relief_tin::heightfield::{Extent, GridSpec};
//! use relief_tin::poisson_sampling::{PoissonDisc, Rect};
//!
//! let square = Rect::new(DVec2::ZERO, DVec2::splat(100.0));
//! let points = PoissonDisc::new(4.0)?.with_seed(1).sample(&square)?;
//! let tin = Tin::new(points)?;
//! tin.check_invariants()?;
//! assert!(tin.is_delaunay());
//!
//! // A cone, interpolated and rasterized on a 1 m grid.
//! let height: Vec<f64> = tin.points().iter().map(|p| 50.0 - p.distance(DVec2::splat(50.0))).collect();
//! assert!(matches!(tin.locate(DVec2::new(50.0, 50.0)), Location::Inside { .. }));
//! let grid = GridSpec::from_extent(101, 101, Extent::new(DVec2::ZERO, DVec2::splat(100.0)))?;
//! let dem = tin.rasterize(&height, &grid)?;
//! assert!(dem.min_max().unwrap().1 > 45.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod approximate;
mod error;
mod locate;
mod predicates;
mod raster;
mod tin;

pub use approximate::{Approximated, Approximation, approximate};
pub use error::TinError;
pub use locate::{Location, PointLocator};
pub use tin::{MAX_POINTS, NO_TRIANGLE, Tin};

/// The shared grid types (re-exported `relief-heightfield`).
pub use relief_heightfield as heightfield;
/// Blue-noise sampling and polygon domains (re-exported `relief-poisson-sampling`).
pub use relief_poisson_sampling as poisson_sampling;

/// The crate README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExample;
