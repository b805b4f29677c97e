//! Deterministic synthetic vector terrains: benchmarks and tests need terrains of a given size
//! whose statistics resemble vectorized DEMs.

use glam::DVec2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

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
