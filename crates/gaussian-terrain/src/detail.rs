//! Detail primitives (§3.2): `δᵢ(p) = a(p)·exp(−½‖p − cᵢ‖²/σ²)` at Poisson-placed centres, their
//! amplitude `a(p)` read from procedural noise or from the vectorization's error map ΔT.
//!
//! The paper sizes the Poisson radius so that the fall-offs overlap a little and hopes their sum
//! stays near 1. Here a layer adds `a(p)·min(1, Σᵢ wᵢ(p))`: where the centres cover the plane
//! (everywhere inside the sampled rectangle, since every point there lies within one Poisson
//! radius of a centre and σ is 1.25 radii) the weights saturate and the layer adds exactly
//! `a(p)`, so an error-map layer restores the DEM it was made from to f32 rounding; outside,
//! the layer fades out smoothly instead of leaving a seam.

use glam::DVec2;
use relief_heightfield::noise::Fbm;
use relief_heightfield::{GridSpec, Heightfield};
use relief_poisson_sampling::{PoissonDisc, Rect};
use serde::{Deserialize, Serialize};

use crate::kernel::raster_samples;
use crate::{Gaussian, GaussianError};

/// σ of the detail fall-offs, in Poisson radii.
const SIGMA_PER_RADIUS: f64 = 1.25;

/// The ground under a detail: the elevation and slope of the terrain's Gaussians (base
/// included, detail layers not) at the point.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Ground {
    /// Elevation, world units.
    pub elevation: f64,
    /// Gradient magnitude `|∇h|` (rise over run).
    pub slope: f64,
}

/// How procedural detail follows the topography (§3.2: noise "modulated according to the
/// terrain's topography … elevation and slope"): the amplitude is multiplied by a smoothstep
/// ramp of each ground property given, `s((v − from)/(to − from))`, 0 at `from` and full at
/// `to` (so `[2000, 500]` fades detail out with height).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct Modulation {
    /// Elevation ramp `[from, to]`, world units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elevation: Option<[f64; 2]>,
    /// Slope ramp `[from, to]`, as gradient magnitudes (rise over run: 1 is 45°).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slope: Option<[f64; 2]>,
}

impl Modulation {
    /// Whether it modulates nothing (the default).
    pub fn is_none(&self) -> bool {
        self.elevation.is_none() && self.slope.is_none()
    }

    /// The factor `m` on `ground`, in `[0, 1]`.
    pub fn factor(&self, ground: Ground) -> f64 {
        let ramp = |v: f64, [from, to]: [f64; 2]| crate::smoothstep((v - from) / (to - from));
        self.elevation.map_or(1.0, |r| ramp(ground.elevation, r)) * self.slope.map_or(1.0, |r| ramp(ground.slope, r))
    }

    fn is_valid(&self) -> bool {
        [self.elevation, self.slope].into_iter().flatten().all(|[a, b]| a.is_finite() && b.is_finite() && a != b)
    }
}

/// Where a detail layer's amplitude `a(p)` comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub enum DetailSource {
    /// Procedural: `a(p) = amplitude · fbm(p) · m(p)` (seeded gradient noise, about
    /// ±amplitude), `m` the [`Modulation`] by the ground's elevation and slope (1 by default).
    Noise {
        /// Peak amplitude, elevation units.
        amplitude: f64,
        /// The noise (octaves, frequency in cycles per world unit, seed, …).
        fbm: Fbm,
        /// How the amplitude follows the terrain (default: it does not).
        #[serde(default, skip_serializing_if = "Modulation::is_none")]
        modulation: Modulation,
    },
    /// Data-driven: `a(p)` is the error map ΔT = T − T̃ of a vectorization, read bilinearly
    /// (0 outside the map).
    ErrorMap {
        /// ΔT on the DEM's grid.
        map: Heightfield,
    },
}

/// A layer of detail primitives: Poisson-placed centres sharing one isotropic σ, and the source
/// of their amplitude.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct DetailLayer {
    /// Centres `[x, y]`, world units.
    pub centers: Vec<[f64; 2]>,
    /// σ of every fall-off, world units (> 0).
    pub sigma: f64,
    /// The amplitude `a(p)`.
    pub source: DetailSource,
}

impl DetailLayer {
    /// Detail primitives over `area` at Poisson spacing `radius` (seeded), σ = 1.25·radius.
    ///
    /// # Errors
    /// [`GaussianError::InvalidOption`] for a radius that is not finite and positive, or an
    /// area that would take more than `max_centres` centres.
    pub fn poisson(
        area: (DVec2, DVec2),
        radius: f64,
        seed: u64,
        max_centres: usize,
        source: DetailSource,
    ) -> Result<Self, GaussianError> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(GaussianError::InvalidOption { name: "detail radius", value: radius, reason: "must be > 0" });
        }
        let size = area.1 - area.0;
        // Bridson packs about 0.7 / r² points per unit area; refuse before sampling.
        let expected = (size.x.max(0.0) * size.y.max(0.0)) / (radius * radius);
        if expected.is_nan() || expected > max_centres as f64 {
            return Err(GaussianError::InvalidOption {
                name: "detail radius",
                value: radius,
                reason: "too small for the area: more detail centres than the primitive budget",
            });
        }
        let rect = Rect::new(area.0, area.1);
        let centers = PoissonDisc::new(radius)
            .and_then(|p| p.with_seed(seed).sample(&rect))
            .map_err(|_| GaussianError::InvalidOption {
                name: "detail radius",
                value: radius,
                reason: "the Poisson sampler refused it",
            })?
            .into_iter()
            .map(|p| p.to_array())
            .collect();
        Ok(Self { centers, sigma: SIGMA_PER_RADIUS * radius, source })
    }

    /// Checks σ, the centres and the source.
    ///
    /// # Errors
    /// [`GaussianError::NotFinite`] or [`GaussianError::InvalidPrimitive`] naming `layer`.
    pub fn validate(&self, layer: usize) -> Result<(), GaussianError> {
        if !self.sigma.is_finite() || self.centers.iter().flatten().any(|v| !v.is_finite()) {
            return Err(GaussianError::NotFinite { index: layer, what: "detail layer sigma or centre" });
        }
        if self.sigma <= 0.0 {
            return Err(GaussianError::InvalidPrimitive {
                index: layer,
                what: "detail sigma",
                value: self.sigma,
                reason: "must be > 0",
            });
        }
        if let DetailSource::Noise { amplitude, fbm, modulation } = &self.source
            && (!amplitude.is_finite() || !fbm.is_valid() || !modulation.is_valid())
        {
            return Err(GaussianError::NotFinite { index: layer, what: "detail noise" });
        }
        Ok(())
    }

    /// `a(p)` over `ground` (which only a modulated noise layer reads).
    pub fn amplitude_at(&self, p: DVec2, ground: Ground) -> f64 {
        match &self.source {
            DetailSource::Noise { amplitude, fbm, modulation } => {
                let m = if modulation.is_none() { 1.0 } else { modulation.factor(ground) };
                amplitude * fbm.sample(p) * m
            }
            DetailSource::ErrorMap { map } => map.sample_bilinear(p).map_or(0.0, f64::from),
        }
    }

    pub(crate) fn falloffs(&self) -> Vec<Gaussian> {
        self.centers.iter().map(|&c| Gaussian::round(DVec2::from(c), self.sigma, 1.0)).collect()
    }

    /// Whether the amplitude depends on the ground.
    pub fn is_modulated(&self) -> bool {
        matches!(&self.source, DetailSource::Noise { modulation, .. } if !modulation.is_none())
    }

    /// The layer's value at `p` over `ground` (exact, O(centres)): `a(p)·min(1, Σ wᵢ(p))`.
    pub fn value(&self, p: DVec2, ground: Ground) -> f64 {
        let w: f64 = self.falloffs().iter().map(|g| g.value(p)).sum();
        self.amplitude_at(p, ground) * w.min(1.0)
    }

    /// Adds the layer to `samples` laid out on `grid`; `ground` holds the Gaussians' raster
    /// (base included) when a layer is modulated, its slope taken by central differences.
    pub(crate) fn add_to(&self, grid: &GridSpec, samples: &mut [f32], ground: Option<&[f32]>, tolerance: f64) {
        let weights = raster_samples(&self.falloffs(), grid, tolerance);
        for (k, (s, w)) in samples.iter_mut().zip(weights).enumerate() {
            if w > 0.0 {
                let (i, j) = grid.coords(k);
                let under =
                    ground.filter(|_| self.is_modulated()).map_or(Ground::default(), |g| grid_ground(grid, g, i, j));
                *s += (self.amplitude_at(grid.position(i, j), under) as f32) * w.min(1.0);
            }
        }
    }
}

/// The ground at sample `(i, j)` of `heights` on `grid`: its elevation, and the slope by central
/// differences (one-sided at the border).
fn grid_ground(grid: &GridSpec, heights: &[f32], i: usize, j: usize) -> Ground {
    let (nx, ny) = (grid.nx(), grid.ny());
    let at = |i: usize, j: usize| f64::from(heights[j * nx + i]);
    let cell = grid.cell_size();
    let (i0, i1, j0, j1) = (i.saturating_sub(1), (i + 1).min(nx - 1), j.saturating_sub(1), (j + 1).min(ny - 1));
    let dx = if i1 > i0 { (at(i1, j) - at(i0, j)) / ((i1 - i0) as f64 * cell.x) } else { 0.0 };
    let dy = if j1 > j0 { (at(i, j1) - at(i, j0)) / ((j1 - j0) as f64 * cell.y) } else { 0.0 };
    Ground { elevation: at(i, j), slope: dx.hypot(dy) }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Grid slopes are central differences inside (exact for a parabola) and one-sided at the
    /// border.
    #[test]
    fn grid_ground_takes_central_differences() {
        let grid =
            GridSpec::from_extent(11, 5, relief_heightfield::Extent::new(DVec2::ZERO, DVec2::new(10.0, 4.0))).unwrap();
        let heights: Vec<f32> = (0..grid.len()).map(|k| (k % 11) as f32 * (k % 11) as f32).collect();
        let g = grid_ground(&grid, &heights, 5, 2);
        assert_eq!((g.elevation, g.slope), (25.0, 10.0));
        assert_eq!(grid_ground(&grid, &heights, 0, 0).slope, 1.0);
        assert_eq!(grid_ground(&grid, &heights, 10, 4).slope, 19.0);
    }
}
