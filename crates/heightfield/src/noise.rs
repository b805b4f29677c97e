//! Seeded, deterministic gradient noise (Perlin 2002's quintic fade, lattice gradients from a hash)
//! and fractional Brownian motion, shared by every crate that needs procedural detail.
//!
//! Hash-based rather than table-based: the gradient at lattice point `(i, j)` is a pure function of
//! `(i, j, seed)`, so noise needs no per-seed state, has no period, and is identical on every
//! platform and thread count.

use glam::DVec2;
use serde::{Deserialize, Serialize};

/// A 64-bit finaliser (`SplitMix64`'s), used to turn lattice coordinates and a seed into bits.
#[inline]
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Unit gradient at lattice point `(i, j)`.
#[inline]
fn gradient(i: i64, j: i64, seed: u64) -> DVec2 {
    let h = mix(
        mix(seed ^ (i as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15)) ^ (j as u64).wrapping_mul(0xc2b2_ae3d_27d4_eb4f)
    );
    let angle = (h >> 11) as f64 * (std::f64::consts::TAU / (1u64 << 53) as f64);
    DVec2::new(angle.cos(), angle.sin())
}

#[inline]
fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// 2-D gradient noise at `p` for `seed`, in about [−1, 1] (scaled by √2 from Perlin's ±√½), zero at
/// every lattice point, C² continuous.
pub fn gradient_noise(p: DVec2, seed: u64) -> f64 {
    let cell = p.floor();
    let (i, j) = (cell.x as i64, cell.y as i64);
    let f = p - cell;
    let dot = |di: i64, dj: i64| gradient(i + di, j + dj, seed).dot(f - DVec2::new(di as f64, dj as f64));
    let (u, v) = (fade(f.x), fade(f.y));
    let bottom = dot(0, 0) + u * (dot(1, 0) - dot(0, 0));
    let top = dot(0, 1) + u * (dot(1, 1) - dot(0, 1));
    std::f64::consts::SQRT_2 * (bottom + v * (top - bottom))
}

/// Fractional Brownian motion: a sum of octaves of [`gradient_noise`],
/// `Σₖ gainᵏ · noise(frequency · lacunarityᵏ · p)`, normalised by `Σₖ gainᵏ` to about [−1, 1].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct Fbm {
    /// Number of octaves (≥ 1).
    pub octaves: u32,
    /// Frequency of the first octave, in cycles per world unit.
    pub frequency: f64,
    /// Frequency ratio between successive octaves (usually 2).
    pub lacunarity: f64,
    /// Amplitude ratio between successive octaves (usually 0.5).
    pub gain: f64,
    /// Seed; octave `k` uses `seed + k` so octaves are uncorrelated.
    pub seed: u64,
}

impl Default for Fbm {
    fn default() -> Self {
        Self { octaves: 6, frequency: 1.0, lacunarity: 2.0, gain: 0.5, seed: 0 }
    }
}

impl Fbm {
    /// Whether the parameters are usable: at least one octave, finite positive frequency and
    /// lacunarity, finite non-negative gain.
    pub fn is_valid(&self) -> bool {
        self.octaves >= 1
            && self.frequency.is_finite()
            && self.frequency > 0.0
            && self.lacunarity.is_finite()
            && self.lacunarity > 0.0
            && self.gain.is_finite()
            && self.gain >= 0.0
    }

    /// The noise value at `p`, about [−1, 1].
    pub fn sample(&self, p: DVec2) -> f64 {
        let (mut sum, mut norm, mut amp, mut freq) = (0.0, 0.0, 1.0, self.frequency);
        for k in 0..self.octaves {
            sum += amp * gradient_noise(p * freq, self.seed.wrapping_add(u64::from(k)));
            norm += amp;
            amp *= self.gain;
            freq *= self.lacunarity;
        }
        if norm > 0.0 { sum / norm } else { 0.0 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_is_deterministic_bounded_and_zero_on_the_lattice() {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for k in 0..20_000 {
            let p = DVec2::new(f64::from(k % 200) * 0.173 - 17.0, f64::from(k / 200) * 0.311 - 9.0);
            let v = gradient_noise(p, 42);
            assert_eq!(v.to_bits(), gradient_noise(p, 42).to_bits());
            lo = lo.min(v);
            hi = hi.max(v);
        }
        assert!(lo > -1.0001 && hi < 1.0001, "range [{lo}, {hi}]");
        assert!(hi - lo > 1.0, "noise too flat: [{lo}, {hi}]");
        assert_eq!(gradient_noise(DVec2::new(3.0, -7.0), 1), 0.0);
        assert_ne!(gradient_noise(DVec2::new(0.5, 0.5), 1), gradient_noise(DVec2::new(0.5, 0.5), 2));
    }

    #[test]
    fn noise_is_continuous() {
        let p = DVec2::new(1.999_999_999, 0.3);
        let q = DVec2::new(2.000_000_001, 0.3);
        assert!((gradient_noise(p, 5) - gradient_noise(q, 5)).abs() < 1e-7);
    }

    #[test]
    fn fbm_is_normalised_and_validates() {
        let f = Fbm { octaves: 5, frequency: 0.01, seed: 9, ..Fbm::default() };
        assert!(f.is_valid());
        for k in 0..1000 {
            let v = f.sample(DVec2::new(f64::from(k) * 3.7, f64::from(k) * 1.3));
            assert!(v.abs() <= 1.0 + 1e-9, "{v}");
        }
        assert!(!Fbm { octaves: 0, ..Fbm::default() }.is_valid());
        assert!(!Fbm { frequency: f64::NAN, ..Fbm::default() }.is_valid());
    }
}
