//! Bijective warps of the plane for editing terrains made of contours: coherent warping along a
//! stroke and slope modulation around a point or a curve (Huftier et al. 2025, §5.2–5.3 and
//! Appendices A–C), their compositions, and their application to points, polylines (adaptive
//! subdivision), contour sets and rasters (backward mapping through the exact inverse).
//!
//! Main types: the [`Warp`] trait (forward, inverse, Jacobian), [`PathWarp`] with [`PathOptions`]
//! and a displacement [`Profile`], [`SlopeModulation`], [`Composition`]; functions
//! [`warp_points`], [`warp_polyline`], [`warp_polylines`], [`warp_raster`]. Everything works on
//! plain `DVec2` data; the `relief` facade applies warps to contour sets and heightfields.
//!
//! [`PathWarp`] and [`SlopeModulation`] serialize as the parameters they are built from (the
//! `warp` and `slope` edits of `relief` scenes: `{ "stroke": …, "radius": r, "strength": μ }`);
//! deserializing builds them, so a warp read from JSON is valid, and a bad value is named by its
//! field. The optional `schemars` feature derives those JSON forms' schemas;
//! [`WarpError::location`] names the field an error is about.
//!
//! Bijectivity is enforced, never assumed: a stroke's segment length is chosen from (or checked
//! against) Appendix B's bound, the slope-modulation strength must lie in (−1, 3), and a curve whose
//! reach is below the radius is rejected with the offending place named.
//!
//! ```
//! use glam::DVec2;
//! use relief_warp::{PathOptions, PathWarp, SlopeModulation, Warp, warp_polyline};
//!
//! // Drag the terrain 300 m east along a stroke, with discs of radius 150 m.
//! let stroke = [DVec2::new(0.0, 0.0), DVec2::new(300.0, 0.0)];
//! let warp = PathWarp::new(&stroke, &PathOptions::new(150.0, 1.0))?;
//! let p = DVec2::new(10.0, 20.0);
//! let q = warp.forward(p);
//! assert!(q.x > p.x && (warp.inverse(q) - p).length() < 1e-9);
//!
//! // Steepen the slope around a summit, then warp a contour through both edits.
//! let steeper = SlopeModulation::point(DVec2::new(500.0, 0.0), 200.0, 1.5)?;
//! let ring: Vec<DVec2> = (0..64).map(|k| 100.0 * DVec2::from_angle(k as f64 * 0.0982)).collect();
//! let warped = warp_polyline(&warp, &ring, true, 0.5)?;
//! assert!(warped.len() >= ring.len());
//! assert_eq!(steeper.forward(DVec2::new(900.0, 0.0)), DVec2::new(900.0, 0.0)); // outside: identity
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod apply;
mod curve;
mod error;
mod json;
mod path;
mod profile;
mod slope;
mod warp;

pub use apply::{MAX_POLYLINE_POINTS, warp_points, warp_polyline, warp_polylines, warp_raster};
pub use error::WarpError;
pub use path::{MAX_DISCS, PathOptions, PathWarp};
pub use profile::Profile;
pub use slope::SlopeModulation;
pub use warp::{Composition, Warp};

/// The crate README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExample;
