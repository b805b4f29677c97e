//! Feature-curve terrains by diffusion (Hnaidi, Guérin, Akkouche, Peytavie & Galin 2010, "Feature
//! based terrain generation using diffusion equation").
//!
//! - [`FeatureCurve`] (§3.1): a piecewise cubic Bézier spline with [`Constraint`] points at curve
//!   parameter u carrying any subset of elevation (h, r), slope (a, b, θ, φ) and noise (A, R);
//!   attributes interpolate linearly along the curve, h by a cubic spline. [`presets`] builds the
//!   landforms of §3.2: ridge, multiple ridges, riverbed, cliff, hill, crack. Curves are serde
//!   types in the shape of `relief` scenes and check every value as they deserialize, with the
//!   rules [`FeatureCurve::validate`] applies to curves built in code; the optional `schemars`
//!   feature derives their JSON Schemas, and [`DiffusionError::location`] turns an error's curve,
//!   constraint and field into a JSON path (`curves[3].constraints[1].slope.theta`).
//! - [`ConstraintMaps`] (§4.1): the curves rasterized at any resolution into elevation, gradient
//!   (norm and direction) and noise maps, with the paper's rule for crossing slope bands: leave
//!   them empty and fill them by diffusion.
//! - [`DiffusionProblem`] (§4.2, §5.2): the per-sample relaxation `F = α·F_L + β·F_G + (1−α−β)·F_I`
//!   as a linear system, solved either by the paper's coarse-to-fine Jacobi pyramid or by a real
//!   multigrid (full multigrid start, then V-cycles, W below the finest level for the elevation;
//!   red-black Gauss–Seidel in parallel), both to a relative-residual tolerance with a
//!   [`SolveReport`]. Its vertex-centred coarse hierarchy has an invariant checker,
//!   [`DiffusionProblem::check_invariants`], that the tests call.
//!   The row kernel of the sweeps is dispatched at run time to the widest vector instructions
//!   the CPU has through `pulp` (a maintained safe SIMD crate, so this crate keeps
//!   `forbid(unsafe_code)`); it has no fused operation, so the bits are the same everywhere.
//! - [`generate`] (§4.3): the smooth elevation plus multi-fractal detail driven by the diffused
//!   amplitude and roughness; deterministic for a seed, identical for any thread count.
//!   [`generate_observed`] reports each [`Stage`] (hole windows filled, each solve's iterations)
//!   and stops within an iteration when its callback breaks, for progress bars and cancel buttons
//!   on generations of seconds.
//!
//! ```
//! use glam::DVec2;
//! use relief_diffusion_multigrid::{TerrainOptions, generate, presets};
//! use relief_heightfield::GridSpec;
//!
//! // A 2 km ridge rising to 800 m, flanks at 25° over 400 m, on a 129² grid of 20 m cells.
//! let grid = GridSpec::new(129, 129, DVec2::ZERO, DVec2::splat(20.0))?;
//! let ridge = presets::ridge(&[DVec2::new(280.0, 1280.0), DVec2::new(2280.0, 1280.0)], 300.0, 800.0, 300.0, 25.0, 400.0);
//! let base = presets::hill(&[DVec2::new(0.0, 0.0), DVec2::new(2560.0, 0.0)], 0.0, 0.0);
//! let terrain = generate(&[ridge, base], &grid, &TerrainOptions::default())?;
//! assert!(terrain.report.converged);
//! let crest = terrain.heightfield.get(64, 64).unwrap();
//! assert!((crest - 800.0).abs() < 1.0, "{crest}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]

mod curve;
mod error;
mod maps;
mod parameters;
pub mod presets;
mod raster;
mod solver;
mod terrain;

pub use curve::{Constraint, Elevation, FeatureCurve, Noise, Slope};
pub use error::DiffusionError;
pub use maps::{CellKind, ConstraintMaps};
pub use raster::MAX_STATIONS;
pub use relief_heightfield as heightfield;
pub use solver::{DiffusionProblem, SolveOptions, SolveReport, Solver};
pub use terrain::{FeatureTerrain, Stage, TerrainOptions, generate, generate_observed};

/// The crate README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExample;
