//! Seeded, deterministic gradient noise (Perlin 2002's quintic fade, lattice gradients from a hash)
//! and fractional Brownian motion, shared by every crate that needs procedural detail.
//!
//! Hash-based rather than table-based: the gradient at lattice point `(i, j)` is a pure function of
//! `(i, j, seed)`, so noise needs no per-seed state, has no period, and is identical on every
//! platform and thread count.

use glam::DVec2;
use serde::{Deserialize, Serialize};

use crate::rounding::floor;

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
    noise_with(p, |i, j| gradient(i, j, seed))
}

/// Gradient noise at `p` with the lattice gradients from `gradient(i, j)`.
#[inline]
fn noise_with(p: DVec2, gradient: impl Fn(i64, i64) -> DVec2) -> f64 {
    let cell = DVec2::new(floor(p.x), floor(p.y));
    let (i, j) = (cell.x as i64, cell.y as i64);
    let f = p - cell;
    let corners = [gradient(i, j), gradient(i + 1, j), gradient(i, j + 1), gradient(i + 1, j + 1)];
    blend(f, fade(f.x), fade(f.y), corners)
}

/// The noise of a cell from the point's offset `f` in it, the fades `u`, `v` of its components
/// and the gradients at the cell's corners `(0, 0)`, `(1, 0)`, `(0, 1)`, `(1, 1)`.
#[inline]
fn blend(f: DVec2, u: f64, v: f64, [g00, g10, g01, g11]: [DVec2; 4]) -> f64 {
    let d00 = g00.dot(f);
    let bottom = d00 + u * (g10.dot(f - DVec2::X) - d00);
    let d01 = g01.dot(f - DVec2::Y);
    let top = d01 + u * (g11.dot(f - DVec2::ONE) - d01);
    std::f64::consts::SQRT_2 * (bottom + v * (top - bottom))
}

/// Most lattice points a [`NoiseLattice`] holds: 2²², 64 MiB of gradients.
pub const MAX_LATTICE_POINTS: usize = 1 << 22;

/// [`gradient_noise`] of one seed over a rectangle of the plane, with the lattice gradients there
/// computed once: the same values, bit for bit, without a hash, a sine and a cosine per lattice
/// corner of every sample. Worth it when many samples share each lattice cell (an octave coarser
/// than the grid it is sampled on); points outside the rectangle are hashed as usual.
///
/// ```
/// use glam::DVec2;
/// use relief_heightfield::noise::{NoiseLattice, gradient_noise};
///
/// let lattice = NoiseLattice::new(DVec2::ZERO, DVec2::splat(8.0), 7).expect("81 points");
/// for p in [DVec2::new(0.3, 5.9), DVec2::new(7.99, 0.01), DVec2::new(-3.5, 20.0)] {
///     assert_eq!(lattice.sample(p).to_bits(), gradient_noise(p, 7).to_bits());
/// }
/// ```
#[derive(Debug, Clone)]
pub struct NoiseLattice {
    /// Lattice coordinates of the first stored point.
    i0: i64,
    j0: i64,
    /// Stored points along each axis.
    nx: i64,
    ny: i64,
    seed: u64,
    /// Row-major gradients.
    gradients: Vec<DVec2>,
}

impl NoiseLattice {
    /// The lattice of `seed` over every cell that a point of the rectangle `lo`–`hi` falls in
    /// (corners included); `None` when a bound is not finite or it would hold more than
    /// [`MAX_LATTICE_POINTS`].
    pub fn new(lo: DVec2, hi: DVec2, seed: u64) -> Option<Self> {
        if !(lo.is_finite() && hi.is_finite()) {
            return None;
        }
        let (a, b) = (lo.min(hi).floor(), lo.max(hi).floor() + 1.0);
        let size = b - a + 1.0;
        if size.x * size.y > MAX_LATTICE_POINTS as f64 {
            return None;
        }
        let (i0, j0, nx, ny) = (a.x as i64, a.y as i64, size.x as i64, size.y as i64);
        let gradients = (0..ny).flat_map(|j| (0..nx).map(move |i| gradient(i0 + i, j0 + j, seed))).collect();
        Some(Self { i0, j0, nx, ny, seed, gradients })
    }

    /// [`gradient_noise`]`(p, seed)`.
    pub fn sample(&self, p: DVec2) -> f64 {
        noise_with(p, |i, j| self.gradient(i, j))
    }

    /// [`Self::sample`] along the line of ordinate `y`, with what depends on `y` alone (its
    /// lattice row, offset and fade) worked out once for the whole line: the same values, bit
    /// for bit, for about half the work per point.
    ///
    /// ```
    /// use glam::DVec2;
    /// use relief_heightfield::noise::NoiseLattice;
    ///
    /// let lattice = NoiseLattice::new(DVec2::ZERO, DVec2::splat(8.0), 7).expect("81 points");
    /// let row = lattice.row(2.7);
    /// for x in [0.0, 3.14, 7.99, 12.5] {
    ///     assert_eq!(row.sample(x).to_bits(), lattice.sample(DVec2::new(x, 2.7)).to_bits());
    /// }
    /// ```
    pub fn row(&self, y: f64) -> NoiseRow<'_> {
        let cell = floor(y);
        let (j, fy) = (cell as i64, y - cell);
        let b = j.wrapping_sub(self.j0);
        // Where both lattice rows of the line are stored, the offset of the first.
        let stored = (0..self.ny - 1).contains(&b).then(|| (b * self.nx) as usize);
        NoiseRow { lattice: self, j, fy, v: fade(fy), stored }
    }

    /// The gradient at lattice point `(i, j)`: stored, or hashed outside the rectangle.
    #[inline]
    fn gradient(&self, i: i64, j: i64) -> DVec2 {
        let (a, b) = (i.wrapping_sub(self.i0), j.wrapping_sub(self.j0));
        if (0..self.nx).contains(&a) && (0..self.ny).contains(&b) {
            self.gradients[(b * self.nx + a) as usize]
        } else {
            gradient(i, j, self.seed)
        }
    }
}

/// A [`NoiseLattice`] sampled along one line of constant ordinate: see [`NoiseLattice::row`].
#[derive(Debug, Clone, Copy)]
pub struct NoiseRow<'a> {
    lattice: &'a NoiseLattice,
    /// Lattice row below the line.
    j: i64,
    /// The line's offset above that row, and its fade.
    fy: f64,
    v: f64,
    /// Index of the stored gradient `(i0, j)` when rows `j` and `j + 1` are both stored.
    stored: Option<usize>,
}

impl NoiseRow<'_> {
    /// The lattice's noise at `(x, y)`, `y` the line's ordinate.
    #[inline]
    pub fn sample(&self, x: f64) -> f64 {
        let cell = floor(x);
        let f = DVec2::new(x - cell, self.fy);
        blend(f, fade(f.x), self.v, self.corners(cell))
    }

    /// [`Self::sample`] at each of `xs` into `out` (the same length), bit for bit, with each run
    /// of consecutive points in one lattice cell sharing its corners: a loop over a run has no
    /// lookup and no branch, and the compiler vectorizes it.
    ///
    /// ```
    /// use glam::DVec2;
    /// use relief_heightfield::noise::NoiseLattice;
    ///
    /// let lattice = NoiseLattice::new(DVec2::ZERO, DVec2::splat(8.0), 7).expect("81 points");
    /// let row = lattice.row(2.7);
    /// let xs: Vec<f64> = (0..100).map(|i| f64::from(i) * 0.1 - 1.0).collect();
    /// let mut out = vec![0.0; xs.len()];
    /// row.samples(&xs, &mut out);
    /// for (&x, v) in xs.iter().zip(&out) {
    ///     assert_eq!(v.to_bits(), row.sample(x).to_bits());
    /// }
    /// ```
    ///
    /// # Panics
    /// When `xs` and `out` differ in length.
    pub fn samples(&self, xs: &[f64], out: &mut [f64]) {
        assert_eq!(xs.len(), out.len(), "one output per point");
        let mut start = 0;
        while start < xs.len() {
            let cell = floor(xs[start]);
            let end = start + xs[start..].iter().take_while(|&&x| cell <= x && x < cell + 1.0).count().max(1);
            let corners = self.corners(cell);
            for (&x, out) in xs[start..end].iter().zip(&mut out[start..end]) {
                let f = DVec2::new(x - cell, self.fy);
                *out = blend(f, fade(f.x), self.v, corners);
            }
            start = end;
        }
    }

    /// The gradients at the corners of the line's lattice cell whose lower abscissa is `cell`.
    #[inline]
    fn corners(&self, cell: f64) -> [DVec2; 4] {
        let i = cell as i64;
        let (lattice, j) = (self.lattice, self.j);
        let a = i.wrapping_sub(lattice.i0);
        match self.stored {
            Some(row) if (0..lattice.nx - 1).contains(&a) => {
                let k = row + a as usize;
                let (below, above) = (&lattice.gradients[k..k + 2], &lattice.gradients[k + lattice.nx as usize..]);
                [below[0], below[1], above[0], above[1]]
            }
            _ => [
                lattice.gradient(i, j),
                lattice.gradient(i + 1, j),
                lattice.gradient(i, j + 1),
                lattice.gradient(i + 1, j + 1),
            ],
        }
    }
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
    fn a_lattice_gives_the_hashed_noise_bit_for_bit() {
        let lattice = NoiseLattice::new(DVec2::new(-3.2, 4.0), DVec2::new(5.5, 9.75), 11).unwrap();
        // Inside, on its edges and cells, and outside the rectangle (hashed there).
        for k in 0..10_000 {
            let p = DVec2::new(f64::from(k % 100) * 0.11 - 4.0, f64::from(k / 100) * 0.07 + 3.0);
            assert_eq!(lattice.sample(p).to_bits(), gradient_noise(p, 11).to_bits(), "{p}");
        }
        // Along rows: inside, on the last stored row and column, and outside on every side.
        for y in [2.5, 3.0, 4.0, 4.6, 9.0, 9.99, 10.0, 10.5, 11.2, -1.5] {
            let row = lattice.row(y);
            for k in 0..300 {
                let x = f64::from(k) * 0.047 - 5.0;
                let p = DVec2::new(x, y);
                assert_eq!(row.sample(x).to_bits(), lattice.sample(p).to_bits(), "{p}");
            }
            // In batches: rising, falling, on cell edges, jumping about, one point.
            let rising: Vec<f64> = (0..300).map(|k| f64::from(k) * 0.047 - 5.0).collect();
            let falling: Vec<f64> = rising.iter().rev().copied().collect();
            let edges: Vec<f64> =
                (-6..14).flat_map(|i| [f64::from(i) - 1e-12, f64::from(i), f64::from(i) + 0.5]).collect();
            let jumping: Vec<f64> = (0..300).map(|k| f64::from((k * 37) % 101) * 0.13 - 5.0).collect();
            for xs in [rising, falling, edges, jumping, vec![1.25], vec![]] {
                let mut out = vec![f64::NAN; xs.len()];
                row.samples(&xs, &mut out);
                for (&x, v) in xs.iter().zip(&out) {
                    assert_eq!(v.to_bits(), row.sample(x).to_bits(), "({x}, {y})");
                }
            }
        }
        assert!(NoiseLattice::new(DVec2::ZERO, DVec2::splat(f64::INFINITY), 1).is_none());
        assert!(NoiseLattice::new(DVec2::ZERO, DVec2::splat(1e4), 1).is_none(), "10⁸ points");
        let one = NoiseLattice::new(DVec2::splat(0.5), DVec2::splat(0.5), 1).unwrap();
        assert_eq!(one.gradients.len(), 4, "one cell: its four corners");
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

    #[test]
    fn the_hash_is_splitmix64s_finaliser() {
        // SplitMix64 seeded with 0: its first outputs (the reference implementation's vectors).
        let mut state = 0u64;
        for want in [0xe220_a839_7b1d_cdaf, 0x6e78_9e6a_a1b9_65f4, 0x06c4_5d18_8009_454f] {
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            assert_eq!(mix(state), want);
        }
    }

    #[test]
    fn the_noise_of_a_seed_does_not_change() {
        // A scene saved with a seed must regenerate the same terrain in later versions: these are
        // the values when this test was written (to 1e-12: other platforms' cos and sin may round apart).
        let pinned = [
            ((0.5, 0.5), 0, 9.800_309_842_751_763e-2),
            ((-3.25, 7.125), 42, -4.510_560_250_783_946_5e-1),
            ((1234.567, -89.01), 7, -5.873_139_004_915_592e-3),
            ((0.001, 2.999), u64::MAX, 4.757_220_678_650_004_4e-4),
        ];
        for ((x, y), seed, want) in pinned {
            let v = gradient_noise(DVec2::new(x, y), seed);
            assert!((v - want).abs() < 1e-12, "({x}, {y}) seed {seed}: {v:e}, was {want:e}");
        }
    }
}
