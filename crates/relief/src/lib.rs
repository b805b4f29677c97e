//! relief turns a few strokes of user intent — coastlines, nested contours, feature curves,
//! divide trees — into real terrain. This facade re-exports every relief crate under one name, so
//! an application depends on `relief` alone; each crate can also be used on its own.
//!
//! | module | crate | what it does |
//! |---|---|---|
//! | [`heightfield`] | `relief-heightfield` | the shared grid type, sampling, gradients, noise, distance transform |
//! | [`poisson_sampling`] | `relief-poisson-sampling` | blue-noise points in polygons and extended domains |
//! | [`tin`] | `relief-tin` | Delaunay TINs as flat arrays, location, interpolation, rasterization |
//! | [`io`] | `relief-heightfield-io` | PNG/EXR/RAW/ASC/HGT/GeoTIFF heightfields and shaded previews |
//!
//! ```
//! use relief::heightfield::{Extent, GridSpec, Heightfield};
//! use relief::poisson_sampling::{PoissonDisc, Polygon};
//! use relief::tin::Tin;
//! use glam::DVec2;
//!
//! // Sample an island, triangulate it, give every node its distance to the centre as depth.
//! let island = Polygon::circle(DVec2::ZERO, 100.0, 64)?;
//! let points = PoissonDisc::new(5.0)?.with_seed(3).sample(&island)?;
//! let tin = Tin::new(points)?;
//! let heights: Vec<f64> = tin.points().iter().map(|p| 100.0 - p.length()).collect();
//! let grid = GridSpec::from_extent(64, 64, Extent::new(DVec2::splat(-100.0), DVec2::splat(100.0)))?;
//! let dem: Heightfield = tin.rasterize(&heights, &grid)?;
//! assert!(dem.min_max().unwrap().1 > 90.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub use relief_heightfield as heightfield;
pub use relief_heightfield_io as io;
pub use relief_poisson_sampling as poisson_sampling;
pub use relief_tin as tin;
