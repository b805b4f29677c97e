//! Vector terrains after Perche et al., "Vector-based Terrain Modelling" (CGF 2025): the
//! elevation is a sum of generalized Gaussian primitives `g(p) = a·exp(−½·d(p)^β)`,
//! `d = ‖A⁻¹(p − c)‖`, `A = R(θ)S(σx, σy)` (§3.2), independent of any resolution.
//!
//! - [`Gaussian`], [`VectorTerrain`] (serde; a base elevation, the primitives, detail layers) and
//!   an [`Atlas`] of saved [`Landform`]s (§5.2).
//!   Loading from JSON validates them ([`VectorTerrain::validate`] names NaN, `σ ≤ 0` or `β ≤ 0`
//!   by primitive index, and caps the count at [`MAX_PRIMITIVES`]); the optional `schemars`
//!   feature derives their JSON Schemas for `relief` scenes.
//! - [`rasterize`] (§6.1): any resolution and window of the plane (a [`GridSpec`]), primitives
//!   binned by the rows their support covers, bands in parallel, f32 sums in primitive order, so
//!   the bytes are the same for any thread count. The loops along rows are dispatched through
//!   `pulp` (a maintained safe SIMD crate: runtime CPU detection without `unsafe` here) to
//!   AVX-512 or AVX2 where the CPU has it, with the same bytes as the plain build. Each
//!   primitive's support is chosen so its truncated tail is below `tolerance·|a|` (the paper's
//!   fixed 3σ leaves a 1.1 % step for `β = 2` and far more for small `β`). [`rasterize_exact`] is
//!   the untruncated f64 reference.
//!
//! - [`TerrainQuery`] ([`VectorTerrain::query`]): elevation, gradient and normal at any point
//!   with no raster, single or batched, through a bounding volume hierarchy (`obvhs`).
//! - [`vectorize`] (§4): a DEM becomes primitives by multi-level initialisation (the paper's
//!   five scales, amplitudes from the smoothed residual), then Adam on the analytic gradient of
//!   `α₁ℓ₁ + α₂ℓ_grad + (1−α₁−α₂)(1−SSIM)` with clone / split / prune, a progress callback that
//!   can cancel, and iteration, time and loss budgets. The paper's LPIPS term needs pre-trained
//!   VGG weights a terrain library cannot ship, so a gradient-domain ℓ₁ (slope differences) takes
//!   its place: it weighs the same crests and breaks of slope and has an exact gradient.
//!   [`LossTerms`] report ℓ₁ with the relief spanning 2 (the paper's `[−1, 1]`);
//!   [`VectorizeReport::l1_of_relief`] gives the fit's error in Table 3's unit (the relief
//!   spanning 1, as the authors' code measures it).
//! - [`DetailLayer`] (§3.2): detail primitives at Poisson-disc centres (`relief-poisson-sampling`,
//!   so placement is seeded and blue-noise) with procedural-noise or error-map amplitude; an
//!   error-map layer restores the vectorized DEM to f32 rounding.
//! - Landform tools (§5.2): [`Region`] (circle, lasso), [`stamp`] with damping, [`copy`],
//!   [`cut`], [`paste`], [`delete`], [`twist`], [`squeeze`]. Crest tools (§5.1): [`Skeleton`]
//!   (edge collapse, attachment, [`Skeleton::move_node`], [`Skeleton::scale_amplitude`]); its
//!   crest cells come from hydrology's flow routing on the inverted DEM, which the `relief`
//!   facade supplies (`relief::vector::crest_skeleton`) because hydrology sits above this crate.
//!   [`Gaussian::transformed`] re-splits a primitive under any linear map (Appendix A).
//! - Editing sessions: a [`Tool`] is one landform or crest tool as data; [`Tool::apply`] replays
//!   it, asking a [`ToolContext`] for what lies outside this crate (atlas files, the crest
//!   skeleton, sized by [`SkeletonOptions`]).
//!
//! The inner loops use branch-free f32 `exp`/`log2` polynomials (module `fastmath`, tested
//! against the standard library) so that the compiler vectorizes them. Their Horner steps are
//! `mul_add`: one fused instruction on CPUs with FMA (every x86-64 since 2013, every aarch64),
//! a slow but bit-identical library call on the rest, so a terrain rasterizes to the same
//! bytes on every machine.
//!
//! # Example
//! ```
//! use glam::DVec2;
//! use relief_gaussian_terrain::{Gaussian, RasterOptions, VectorTerrain, rasterize};
//! use relief_heightfield::{Extent, GridSpec};
//!
//! // A ridge (elongated, flat-topped β = 4) and a carved hollow beside it.
//! let terrain = VectorTerrain::new(vec![
//!     Gaussian { center: [500.0, 500.0], sigma: [300.0, 60.0], theta: 0.5, amplitude: 800.0, beta: 4.0 },
//!     Gaussian::round(DVec2::new(700.0, 300.0), 80.0, -150.0),
//! ]);
//! terrain.validate()?;
//! // The same terrain at two resolutions agrees where their samples coincide.
//! let coarse = GridSpec::from_extent(65, 65, Extent::new(DVec2::ZERO, DVec2::splat(1000.0)))?;
//! let fine = GridSpec::from_extent(129, 129, Extent::new(DVec2::ZERO, DVec2::splat(1000.0)))?;
//! let (a, b) = (rasterize(&terrain, &coarse, &RasterOptions::default())?, rasterize(&terrain, &fine, &RasterOptions::default())?);
//! assert!((a.value(32, 32) - b.value(64, 64)).abs() < 1e-3);
//! assert!(a.value(32, 32) > 700.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod detail;
mod error;
mod fastmath;
mod kernel;
mod loss;
mod primitive;
mod query;
mod raster;
mod region;
mod skeleton;
mod terrain;
mod tool;
mod vectorize;

pub use detail::{DetailLayer, DetailSource, Ground, Modulation};
pub use error::GaussianError;
pub use loss::{LossTerms, LossWeights};
pub use primitive::{DEFAULT_TOLERANCE, Gaussian};
pub use query::{Sample, TerrainQuery};
pub use raster::{MAX_RASTER_CELLS, RasterOptions, rasterize, rasterize_exact};
pub use region::{
    Placement, Region, StampMode, copy, cut, damp_around, delete, paste, smoothstep, squeeze, stamp, twist,
};
pub use relief_heightfield::{GridSpec, Heightfield};
pub use skeleton::{Attachment, Skeleton, SkeletonOptions};
pub use terrain::{Atlas, Landform, MAX_PRIMITIVES, VectorTerrain};
pub use tool::{Tool, ToolContext, ToolError};
pub use vectorize::{Densify, Progress, VectorizeOptions, VectorizeReport, Vectorized, vectorize};

/// The crate README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExample;
