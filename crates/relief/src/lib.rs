//! relief turns a few strokes of user intent — coastlines, nested contours, feature curves,
//! divide trees — into real terrain. This facade re-exports every relief crate under one name, so
//! an application depends on `relief` alone (each crate can also be used on its own), and adds what
//! composes them: the versioned JSON [`scene`] format, the [`pipeline`] that runs a scene end to end
//! with progress and a run summary, resource [`budget`]s, and [`export`] of contours and divide
//! trees as GeoJSON, SVG and CSV.
//!
//! | module | crate | what it does |
//! |---|---|---|
//! | [`heightfield`] | `relief-heightfield` | the shared grid type, sampling, gradients, noise, distance transform, depression filling |
//! | [`poisson_sampling`] | `relief-poisson-sampling` | blue-noise points in polygons and extended domains, polygons and exact predicates |
//! | [`tin`] | `relief-tin` | Delaunay TINs as flat arrays, location, interpolation, rasterization |
//! | [`io`] | `relief-heightfield-io` | PNG/EXR/RAW/ASC/HGT/GeoTIFF heightfields and shaded previews |
//! | [`eden_growth`] | `relief-eden-growth` | inward Open Eden Growth: region trees, label maps, probability maps |
//! | [`contours`] | `relief-contours` | histogram heights, contour levels and extraction, nesting, smoothing, reconstruction |
//! | [`warp`] | `relief-warp` | bijective coherent warps and slope modulation |
//! | [`hydrology`] | `relief-hydrology` | closed basins, the endorheic check, drainage, Strahler order, erosion, descriptors, earth mover's distance |
//! | [`diffusion`] | `relief-diffusion-multigrid` | feature curves diffused into terrain (Hnaidi et al. 2010) |
//! | [`island`] | `relief-island` | sketched islands: coastline strokes, hills, perturbation filters (Puig-Centelles et al.) |
//! | [`gaussian_terrain`] | `relief-gaussian-terrain` | vector terrains of generalized Gaussians: rasterize, vectorize, tools (Perche et al. 2025) |
//! | [`orometry`] | `relief-orometry` | prominence, divide trees, orometric descriptors and synthesis (Argudo et al. 2019) |
//! | [`engine`] | `relief-engine-export` | heightmaps for Unity, Unreal, Godot and Blender at their legal sizes, seam-free tiles, import numbers |
//!
//! Its own items: [`Scene`] (and the rest of [`scene`]), [`pipeline::generate`] / [`pipeline::run`]
//! with [`Progress`], [`Terrain`] and [`Summary`], [`Budget`], [`ReliefError`] with
//! [`SceneError`], and [`vector::crest_skeleton`]. Scenes embed the library types themselves (a
//! feature curve in a scene is a [`diffusion::FeatureCurve`]), so the scene format, the JSON Schema
//! and the libraries never disagree; an error names the JSON path of the value at fault and keeps
//! the library's error as its [`std::error::Error::source`].
//!
//! A scene is a few nested contours plus a histogram; [`pipeline::generate`] turns it into a
//! heightfield and its contours:
//!
//! ```
//! use relief::Scene;
//!
//! let scene = Scene::from_json(r#"{
//!   "version": 1,
//!   "seed": 3,
//!   "generator": { "contours": {
//!     "regions": [
//!       { "polygon": { "exterior": [[0, 0], [4000, 0], [4000, 3000], [0, 3000]] }, "height": 0 },
//!       { "polygon": { "exterior": [[1500, 1000], [2500, 1000], [2500, 2000], [1500, 2000]] } }
//!     ],
//!     "particles": 5000,
//!     "histogram": { "uniform": { "min": 0, "max": 800 } },
//!     "levels": { "count": 8 }
//!   } },
//!   "reconstruction": { "resolution": [128, 96] }
//! }"#)?;
//! let terrain = relief::pipeline::generate(&scene, std::path::Path::new("."), &mut ())?;
//! assert_eq!((terrain.heightfield.nx(), terrain.heightfield.ny()), (128, 96));
//! assert_eq!(terrain.contours.nests_by_level(), Ok(()));
//! // Elevations follow the histogram: the node heights exactly, the raster closely.
//! let fit = terrain.summary.histogram_match.as_ref().unwrap();
//! assert!(fit.nodes < 1e-3);
//! assert!(fit.raster < 0.1);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub use relief_contours as contours;
pub use relief_diffusion_multigrid as diffusion;
pub use relief_eden_growth as eden_growth;
pub use relief_engine_export as engine;
pub use relief_gaussian_terrain as gaussian_terrain;
pub use relief_heightfield as heightfield;
pub use relief_heightfield_io as io;
pub use relief_hydrology as hydrology;
pub use relief_island as island;
pub use relief_orometry as orometry;
pub use relief_poisson_sampling as poisson_sampling;
pub use relief_tin as tin;
pub use relief_warp as warp;

pub mod budget;
mod error;
pub mod export;
#[doc(hidden)]
pub mod harness;
pub mod overlay;
pub mod pipeline;
pub mod scene;
pub mod tools;
pub mod vector;

pub use budget::Budget;
pub use error::{ReliefError, SceneError};
pub use pipeline::{Progress, Summary, Terrain};
pub use scene::Scene;

/// The README's examples, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
struct ReadmeDoctests;

/// The crate README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExample;
