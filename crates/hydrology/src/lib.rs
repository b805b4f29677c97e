//! Hydrology of heightfields: closed depressions, flow routing, drainage area, stream networks,
//! erosion and terrain descriptors.
//!
//! - [`depressions`], [`fill`], [`has_endorheic_basins`]: Priority-Flood (Barnes, Lehman & Mulla
//!   2014) finds every closed basin with its pit, fill level, spill cell and volume, or fills them
//!   (with ε-descent on flats so routing never stalls). [`endorheic_nodes`] runs the same check on a
//!   graph, e.g. a TIN's node heights and CSR adjacency. This is the check behind the contours
//!   paper's "no endorheic regions" (§3.1) that every generator's tests call.
//! - [`D8`] (steepest descent, true ground distances, also on geographic grids) with drainage area,
//!   flow accumulation, stream extraction and Strahler order; [`mfd_drainage_area`] for multiple
//!   flow directions (Freeman 1991, Quinn et al. 1991).
//! - [`StreamPower`]: the implicit stream-power law of Braun & Willett (2013), O(N) per step, with
//!   uplift and erodibility maps; [`Thermal`] talus erosion. Post-processes for any generator:
//!   both are serde types in the shape of `relief` scenes' `post` entries (the optional `schemars`
//!   feature derives their JSON Schemas), and [`HydrologyError::location`] names the parameter an
//!   error is about.
//! - [`Descriptors`]: histograms of elevation, slope and drainage area ([`CountHistogram`]: counts
//!   in equal-width bins) and the maximum Strahler order, with an earth mover's distance between
//!   two terrains (contours paper §6.5). [`earth_movers_distance`] is the one EMD of the
//!   workspace: `∫|F₁ − F₂|` over piecewise-linear or step CDFs, which
//!   [`CountHistogram::wasserstein`] and `relief_orometry`'s descriptor distance both call.
//!
//! The filling itself lives in `relief-heightfield` ([`relief_heightfield::fill_depressions_with`])
//! because the contour reconstruction needs it and may not depend on this crate; here it gains
//! outlets (sea level, no-data as sea or wall), basin labels and everything downstream.
//!
//! ```
//! use glam::DVec2;
//! use relief_heightfield::{GridSpec, Heightfield};
//! use relief_hydrology::{D8, NoData, Outlets, depressions, fill, has_endorheic_basins};
//!
//! // A 64 × 64 cone with a crater: water on the crater floor cannot leave.
//! let grid = GridSpec::new(64, 64, DVec2::ZERO, DVec2::splat(10.0))?;
//! let dem = Heightfield::from_fn(grid, |p| {
//!     let r = (p - DVec2::splat(315.0)).length();
//!     (if r < 60.0 { 200.0 + r } else { 320.0 - r }) as f32
//! })?;
//! assert!(has_endorheic_basins(&dem, NoData::Outlet));
//! let basins = depressions(&dem, Outlets::new())?;
//! assert_eq!(basins.basins.len(), 1);
//! assert!(basins.basins[0].fill_level > 250.0);
//!
//! // Filled, every drop reaches the border; D8 drainage sums to the whole map.
//! let filled = fill(&dem, Outlets::new())?;
//! assert!(!has_endorheic_basins(&filled, NoData::Outlet));
//! let flow = D8::new(&filled)?;
//! let outlets: f64 = flow.sinks().map(|(i, j)| flow.drainage_area()[j * 64 + i]).sum();
//! assert!((outlets - 64.0 * 64.0 * 100.0).abs() < 1e-6);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]

mod artefacts;
mod depressions;
mod descriptors;
mod emd;
mod erosion;
mod error;
mod flow;
mod grid8;

pub use artefacts::{Artefacts, measure as measure_artefacts, measure_with_basins as measure_artefacts_with_basins};
pub use depressions::{Basin, Depressions, NoData, Outlets, depressions, endorheic_nodes, fill, has_endorheic_basins};
pub use descriptors::{CountHistogram, DescriptorDistance, DescriptorOptions, Descriptors, MAX_BINS};
pub use emd::{CdfShape, earth_movers_distance};
pub use erosion::{Field, StreamPower, Thermal};
pub use error::HydrologyError;
pub use flow::{D8, Mfd, NO_RECEIVER, mfd_drainage_area, strahler};
pub use relief_heightfield as heightfield;

/// The crate README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExample;
