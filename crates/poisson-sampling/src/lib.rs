//! Deterministic blue-noise (Poisson-disc) point sets in rectangles, polygons with holes, arbitrary
//! predicate domains and the *extended domain* Ω ⊕ B(m), with a fixed radius.
//!
//! Implements the sampling step of the contours paper (Huftier et al. 2025, §4.3: "a Poisson disc
//! distribution over Ω ⊕ B(4r)", nodes tagged inside/outside Ω) with Bridson's algorithm.
//!
//! Main types: [`PoissonDisc`], [`Domain`] (what can be sampled: [`Rect`], [`Polygon`],
//! [`PolygonSet`], [`FnDomain`], [`ExtendedDomain`]), [`TaggedSamples`]. The polygon types and the
//! exact 2-D predicates ([`orient`], [`segments_touch`], [`SegmentIndex`]) and ring measures
//! ([`ring_contains`], [`signed_area`]) live here because this is the lowest crate that needs them;
//! `relief-tin` re-exports the crate for the crates above it.
//!
//! ```
//! use glam::DVec2;
//! use relief_poisson_sampling::{radius_for_count, PoissonDisc, Polygon, PolygonSet};
//!
//! // An island with a lagoon, sampled with about 2 000 points plus a 4r border outside it.
//! let island = Polygon::new(
//!     vec![DVec2::new(0.0, 0.0), DVec2::new(100.0, 0.0), DVec2::new(100.0, 60.0), DVec2::new(0.0, 60.0)],
//!     vec![vec![DVec2::new(40.0, 20.0), DVec2::new(60.0, 20.0), DVec2::new(50.0, 40.0)]],
//! )?;
//! let r = radius_for_count(island.area(), 2_000)?;
//! let omega = PolygonSet::from(island);
//! let samples = PoissonDisc::new(r)?.with_seed(42).sample_extended(&omega, 4.0 * r)?;
//! let inside = samples.inside_count();
//! assert!((1_700..2_300).contains(&inside), "{inside}");
//! assert!(samples.len() > inside); // the border ring outside Ω
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod domain;
mod error;
mod geometry;
mod sampler;

pub use domain::{Domain, ExtendedDomain, FnDomain};
pub use error::{PolygonError, SamplingError};
pub use geometry::{
    Polygon, PolygonSet, Rect, RingIndex, SegmentIndex, orient, ring_contains, segment_distance_sq, segments_touch,
    signed_area,
};
pub use sampler::{DEFAULT_ATTEMPTS, DEFAULT_MAX_POINTS, DENSITY, PoissonDisc, TaggedSamples, radius_for_count};

/// The crate README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExample;
