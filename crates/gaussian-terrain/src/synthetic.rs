//! Deterministic synthetic vector terrains: benchmarks and tests need terrains of a given size
//! whose statistics resemble vectorized DEMs.

use glam::DVec2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use relief_heightfield::noise::Fbm;
use relief_heightfield::{Extent, GridSpec, Heightfield};

use crate::{DEFAULT_TOLERANCE, Gaussian, VectorTerrain};

/// `count` primitives over the square `[0, size]²`, seeded: random centres, rotations, aspect
/// ratios 1–4, steepness β in [1.2, 4] (a third exactly 2), signed amplitudes falling with
/// scale, and scales such that on average `depth` supports (at the default tolerance) cover
/// each point, the way a vectorized DEM's primitives shrink as their number grows.
pub fn random_terrain(count: usize, size: f64, depth: f64, seed: u64) -> VectorTerrain {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    // Mean support area = depth · size² / count; support radius ≈ 3.72 σ for β = 2.
    let radius = (depth * size * size / (count.max(1) as f64 * std::f64::consts::PI)).sqrt();
    let base = radius / Gaussian::round(DVec2::ZERO, 1.0, 1.0).support_radius(DEFAULT_TOLERANCE);
    let primitives = (0..count)
        .map(|_| {
            let scale = base * rng.random_range(0.5..1.5);
            let aspect: f64 = rng.random_range(1.0..4.0);
            // Keep the support area: σx·σy = scale².
            let (sx, sy) = (scale * aspect.sqrt(), scale / aspect.sqrt());
            let beta = if rng.random_bool(1.0 / 3.0) { 2.0 } else { rng.random_range(1.2..4.0) };
            let amplitude = rng.random_range(-0.3..1.0) * scale;
            Gaussian {
                center: [rng.random_range(0.0..size), rng.random_range(0.0..size)],
                sigma: [sx, sy],
                theta: rng.random_range(0.0..std::f64::consts::PI),
                amplitude,
                beta,
            }
        })
        .collect();
    VectorTerrain::new(primitives)
}

/// A seeded `n × n` test DEM over `[0, 1000]²`, elevations about 0–1000: fractional Brownian
/// motion (7 octaves) plus a ridged octave pair, so it has broad massifs, sharp crests and
/// valleys at every scale, like the real DEMs the paper vectorizes. For benchmarks and tests.
///
/// # Errors
/// Never for `n ≥ 2` (a grid of fewer samples is refused by [`GridSpec`]).
pub fn fbm_dem(n: usize, seed: u64) -> Result<Heightfield, crate::GaussianError> {
    let grid = GridSpec::from_extent(n, n, Extent::new(DVec2::ZERO, DVec2::splat(1000.0)))?;
    let base = Fbm { octaves: 7, frequency: 0.003, seed, ..Fbm::default() };
    let ridge = Fbm { octaves: 2, frequency: 0.006, seed: seed ^ 0x5eed, ..Fbm::default() };
    Ok(Heightfield::from_fn(grid, |p| {
        let crest = 1.0 - ridge.sample(p).abs();
        (500.0 + 450.0 * base.sample(p) + 250.0 * crest * crest) as f32
    })?)
}
