use glam::DVec2;
use relief_tin::heightfield::Heightfield;
use relief_tin::heightfield::noise::Fbm;
use serde::{Deserialize, Serialize};

use relief_tin::PointLocator;

use crate::{EdenError, Graph, Growth, UNRANKED};

/// The probability map P of the contours paper (§4.2): how readily growth advances from a frontier
/// node at `p`. Only ratios matter; values must be finite and ≥ 0, and a node with P = 0 is chosen
/// only when every frontier node has P = 0.
///
/// Closures `Fn(DVec2) -> f64 + Sync` are probability maps.
pub trait ProbabilityMap: Sync {
    /// Relative probability at `p`.
    fn probability(&self, p: DVec2) -> f64;
}

impl<F: Fn(DVec2) -> f64 + Sync> ProbabilityMap for F {
    fn probability(&self, p: DVec2) -> f64 {
        self(p)
    }
}

/// Uniform selection: contours follow the distance to the border (§4.2).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Uniform;

impl ProbabilityMap for Uniform {
    fn probability(&self, _p: DVec2) -> f64 {
        1.0
    }
}

/// `P(p) = exp(contrast · fbm(p))`: organic, fractal growth fronts (Fig. 23). `contrast` 0 is
/// uniform; 3–6 gives strongly fingered contours.
///
/// In JSON: `{ "frequency": f, "contrast": c, "octaves": 6, "lacunarity": 2, "gain": 0.5 }` (the
/// last three optional, with these defaults); deserializing checks it like [`FbmProbability::new`].
/// The fBm's seed is not part of it: whoever runs the growth supplies it
/// ([`FbmProbability::with_seed`]; a scene uses its own seed).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "FbmJson", into = "FbmJson")]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct FbmProbability {
    fbm: Fbm,
    contrast: f64,
}

/// The JSON form of an [`FbmProbability`].
#[derive(Clone, Copy, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema), schemars(rename = "FbmProbability"))]
struct FbmJson {
    /// Octaves (≥ 1; default 6).
    #[serde(default = "default_octaves")]
    octaves: u32,
    /// Frequency of the first octave, cycles per world unit (finite, > 0).
    frequency: f64,
    /// Frequency ratio between octaves (default 2).
    #[serde(default = "default_lacunarity")]
    lacunarity: f64,
    /// Amplitude ratio between octaves (≥ 0; default 0.5).
    #[serde(default = "default_gain")]
    gain: f64,
    /// Contrast: 0 is uniform, 3–6 strongly fingered (finite).
    contrast: f64,
}

fn default_octaves() -> u32 {
    Fbm::default().octaves
}
fn default_lacunarity() -> f64 {
    Fbm::default().lacunarity
}
fn default_gain() -> f64 {
    Fbm::default().gain
}

impl TryFrom<FbmJson> for FbmProbability {
    type Error = EdenError;
    fn try_from(j: FbmJson) -> Result<Self, EdenError> {
        let fbm = Fbm { octaves: j.octaves, frequency: j.frequency, lacunarity: j.lacunarity, gain: j.gain, seed: 0 };
        Self::new(fbm, j.contrast)
    }
}

impl From<FbmProbability> for FbmJson {
    fn from(p: FbmProbability) -> Self {
        let Fbm { octaves, frequency, lacunarity, gain, .. } = p.fbm;
        Self { octaves, frequency, lacunarity, gain, contrast: p.contrast }
    }
}

impl FbmProbability {
    /// The same map with the fBm seeded by `seed`.
    #[must_use]
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.fbm.seed = seed;
        self
    }

    /// An fBm probability map.
    ///
    /// # Errors
    /// [`EdenError::InvalidProbabilityParameters`] for invalid fBm parameters or a non-finite
    /// contrast.
    pub fn new(fbm: Fbm, contrast: f64) -> Result<Self, EdenError> {
        if !fbm.is_valid() {
            return Err(EdenError::InvalidProbabilityParameters {
                reason: format!("fBm needs octaves ≥ 1, finite positive frequency and lacunarity, gain ≥ 0: {fbm:?}"),
            });
        }
        if !contrast.is_finite() {
            return Err(EdenError::InvalidProbabilityParameters {
                reason: format!("contrast {contrast} is not finite"),
            });
        }
        Ok(Self { fbm, contrast })
    }
}

impl ProbabilityMap for FbmProbability {
    fn probability(&self, p: DVec2) -> f64 {
        (self.contrast * self.fbm.sample(p)).exp()
    }
}

/// A raster probability map (a painted image, Fig. 11): bilinear values, clamped at the edges,
/// raised to `exponent` (the authors' river map is used to the power 4). No-data reads as 0.
#[derive(Debug, Clone, PartialEq)]
pub struct RasterProbability {
    field: Heightfield,
    exponent: f64,
}

impl RasterProbability {
    /// A raster map.
    ///
    /// # Errors
    /// [`EdenError::InvalidProbabilityParameters`] when a sample is negative or the exponent is
    /// not finite and positive.
    pub fn new(field: Heightfield, exponent: f64) -> Result<Self, EdenError> {
        if !(exponent.is_finite() && exponent > 0.0) {
            return Err(EdenError::InvalidProbabilityParameters {
                reason: format!("exponent {exponent} must be finite and > 0"),
            });
        }
        if let Some(k) = field.samples().iter().position(|&v| v < 0.0) {
            let (i, j) = field.grid().coords(k);
            return Err(EdenError::InvalidProbabilityParameters {
                reason: format!("raster sample ({i}, {j}) is {}; probabilities must be >= 0", field.samples()[k]),
            });
        }
        Ok(Self { field, exponent })
    }
}

impl ProbabilityMap for RasterProbability {
    fn probability(&self, p: DVec2) -> f64 {
        self.field.sample_bilinear_clamped(p).map_or(0.0, |v| f64::from(v).powf(self.exponent))
    }
}

#[cfg(test)]
mod tests {
    use relief_tin::heightfield::GridSpec;

    use super::*;

    #[test]
    fn probability_maps_evaluate_their_formulas() {
        let p = DVec2::new(123.0, -45.0);
        let closure = |q: DVec2| q.x + 2.0 * q.y;
        assert_eq!(closure.probability(p), 33.0);
        assert_eq!(Uniform.probability(p), 1.0);
        let fbm = Fbm { octaves: 3, frequency: 0.01, lacunarity: 2.0, gain: 0.5, seed: 9 };
        let map = FbmProbability::new(fbm, 2.5).unwrap();
        assert_eq!(map.probability(p), (2.5 * fbm.sample(p)).exp());
        let field = Heightfield::from_fn(GridSpec::new(3, 3, DVec2::ZERO, DVec2::ONE).unwrap(), |q| (q.x + q.y) as f32)
            .unwrap();
        let raster = RasterProbability::new(field, 3.0).unwrap();
        assert!((raster.probability(DVec2::new(1.0, 0.5)) - 1.5f64.powi(3)).abs() < 1e-12);
    }

    #[test]
    fn an_fbm_map_reads_its_json_with_the_fbm_defaults_and_takes_its_seed_from_the_caller() {
        let read: FbmProbability = serde_json::from_str(r#"{ "frequency": 0.002, "contrast": 3 }"#).unwrap();
        let defaults = Fbm { frequency: 0.002, seed: 0, ..Fbm::default() };
        assert_eq!(read, FbmProbability::new(defaults, 3.0).unwrap());
        assert_eq!((defaults.octaves, defaults.lacunarity, defaults.gain), (6, 2.0, 0.5));
        // The seed is not part of the JSON form.
        let seeded = read.with_seed(42);
        assert_eq!(seeded, FbmProbability::new(Fbm { seed: 42, ..defaults }, 3.0).unwrap());
        let text = serde_json::to_string(&seeded).unwrap();
        assert_eq!(text, r#"{"octaves":6,"frequency":0.002,"lacunarity":2.0,"gain":0.5,"contrast":3.0}"#);
        assert_eq!(serde_json::from_str::<FbmProbability>(&text).unwrap(), read);
        for bad in [
            r#"{ "frequency": -1, "contrast": 3 }"#,
            r#"{ "frequency": 1, "contrast": 3, "octaves": 0 }"#,
            r#"{ "frequency": 1, "contrast": 3, "seed": 4 }"#,
            r#"{ "contrast": 3 }"#,
        ] {
            assert!(serde_json::from_str::<FbmProbability>(bad).is_err(), "{bad}");
        }
    }
}

/// The order of a coarser growth as the probability map of a finer one: the multi-level
/// generation of the contours paper's §6.6, where a large Poisson radius sets the large-scale
/// structure and smaller ones refine it. At `p`, `exp(−contrast · u)` with `u` the share of the
/// coarse growth's ranks below the coarse node ranks around `p` (interpolated over the coarse
/// TIN; 0 outside Ω): what the coarse pass grew first, the fine pass prefers.
#[derive(Debug, Clone)]
pub struct CoarseOrder<'a> {
    locator: PointLocator<'a>,
    share: Vec<f64>,
    contrast: f64,
}

impl<'a> CoarseOrder<'a> {
    /// The order of `growth` over `graph`, with `contrast` ≥ 0 (0: no preference).
    ///
    /// # Errors
    /// [`EdenError::InvalidProbabilityParameters`] for a negative or non-finite contrast,
    /// [`EdenError::GrowthMismatch`] when `growth` is not of `graph`.
    pub fn new(graph: &'a Graph, growth: &Growth, contrast: f64) -> Result<Self, EdenError> {
        if !(contrast.is_finite() && contrast >= 0.0) {
            return Err(EdenError::InvalidProbabilityParameters {
                reason: format!("coarse-order contrast {contrast} must be finite and ≥ 0"),
            });
        }
        let n = graph.tin().num_points();
        if growth.ranks().len() != n {
            let reason = format!("{} ranks for {n} nodes", growth.ranks().len());
            return Err(EdenError::GrowthMismatch { reason });
        }
        let total = growth.order().len().max(1) as f64;
        let share =
            growth.ranks().iter().map(|&r| if r == UNRANKED { 0.0 } else { (f64::from(r) + 0.5) / total }).collect();
        Ok(Self { locator: PointLocator::new(graph.tin()), share, contrast })
    }
}

impl ProbabilityMap for CoarseOrder<'_> {
    fn probability(&self, p: DVec2) -> f64 {
        let u = self.locator.interpolate(p, &self.share).ok().flatten().unwrap_or(0.0);
        (-self.contrast * u).exp()
    }
}
