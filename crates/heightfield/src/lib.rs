//! The grid type every relief crate shares: a [`Heightfield`] of f32 elevations over a [`GridSpec`]
//! (extent, cell size, metres, feet or geographic degrees) labelled with its [`Crs`], with no-data cells, bilinear sampling,
//! gradients, slopes, normals, resampling and statistics.
//!
//! This crate implements no paper section itself; it is the common currency of all of them (the
//! contours paper's §4.4 reconstruction, the multigrid diffusion grids of Hnaidi et al., the
//! rasterized Gaussian terrains of Perche et al., the DEMs of Argudo et al.'s orometry).
//!
//! Conventions, fixed here once for the whole workspace:
//! - samples are *node-registered*: sample `(i, j)` sits at `origin + (i·dx, j·dy)`; the extent
//!   runs from the first to the last sample;
//! - row `j = 0` is the south edge, storage is row-major; readers of north-up files flip rows;
//! - no-data is NaN, every other sample is finite ([`Heightfield::samples`]);
//! - [`Units::Degrees`] grids are (longitude, latitude) and measure ground distances in metres with
//!   the WGS84 radii at each row's latitude, so slopes of an SRTM tile are true slopes.
//!
//! Shared grid utilities: [`distance_transform`] (exact Euclidean, O(samples)),
//! [`fill_depressions`] (Priority-Flood+ε), the [`noise`] module (seeded gradient noise and fBm)
//! that the generators share, and [`rounding`] (`floor` and `ceil` bit for bit without libm).
//!
//! The types are serde types ([`Extent`] checks its corners as it deserializes, [`GridSpec`] and
//! [`Heightfield`] their invariants); the optional `schemars` feature derives their JSON Schemas
//! for the `relief` scene format.
//!
//! ```
//! use glam::DVec2;
//! use relief_heightfield::{Extent, GridSpec, Heightfield};
//!
//! // A 1 km square sampled every 10 m, holding a tilted plane h = 0.1·x.
//! let grid = GridSpec::from_extent(101, 101, Extent::new(DVec2::ZERO, DVec2::splat(1000.0)))?;
//! let plane = Heightfield::from_fn(grid, |p| (0.1 * p.x) as f32)?;
//! assert_eq!(plane.sample_bilinear(DVec2::new(505.0, 3.0)), Some(50.5));
//! let g = plane.gradient(50, 50).unwrap();
//! assert!((g.x - 0.1).abs() < 1e-6 && g.y.abs() < 1e-9);
//! let half = plane.resample(51, 51)?;
//! assert_eq!(half.min_max(), Some((0.0, 100.0)));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod crs;
mod distance;
mod error;
mod fill;
mod grid;
mod heightfield;
pub mod noise;
pub mod rounding;

pub use crs::Crs;
pub use distance::{DistanceScratch, distance_transform, distance_transform_seeded, distance_transform_seeded_with};
pub use error::HeightfieldError;
pub use fill::{FillRules, fill_depressions, fill_depressions_with};
pub use grid::{Extent, GridSpec, MAX_SAMPLES, Units, metres_per_degree};
pub use heightfield::{Heightfield, Statistics};

/// The crate README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExample;
