//! Erosion post-processes: the implicit stream-power law (Braun & Willett 2013) and thermal
//! (talus) erosion.

use rayon::prelude::*;
use relief_heightfield::Heightfield;
use serde::{Deserialize, Serialize};

use crate::error::check_param;
use crate::flow::{D8, NO_RECEIVER};
use crate::grid8::Grid8;
use crate::{HydrologyError, Outlets, fill};

/// A per-cell parameter: one value everywhere, or a map with one value per cell. In JSON, a
/// number or an array of numbers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub enum Field {
    /// The same value on every cell.
    Uniform(f64),
    /// One value per cell, row-major like the heightfield.
    Map(Vec<f64>),
}

impl Field {
    #[inline]
    fn at(&self, k: usize) -> f64 {
        match self {
            Self::Uniform(v) => *v,
            Self::Map(m) => m[k],
        }
    }

    fn check(&self, name: &'static str, cells: usize, reason: &'static str) -> Result<(), HydrologyError> {
        match self {
            Self::Uniform(v) => check_param(name, *v, |v| v >= 0.0, reason),
            Self::Map(m) if m.len() != cells => {
                Err(HydrologyError::LengthMismatch { what: name, expected: cells, found: m.len() })
            }
            Self::Map(m) => m.iter().try_for_each(|&v| check_param(name, v, |v| v >= 0.0, reason)),
        }
    }
}

/// The stream-power law ∂h/∂t = U − K·A^m·S^n, integrated implicitly along D8 receivers
/// (Braun & Willett 2013): unconditionally stable, O(N) per step. A run is `iterations` steps.
///
/// In JSON every field is optional (the defaults below); `outlets` is not part of it, because
/// where water leaves depends on the terrain the run is applied to (a scene's sea and border).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct StreamPower {
    /// Time steps of a [`StreamPower::run`] (default 20).
    pub iterations: usize,
    /// Erodibility K (per year, in units that make K·A^m·S^n metres per year with A in m²;
    /// default 2·10⁻⁵).
    pub erodibility: Field,
    /// Uplift rate U, metres per year (default 0).
    pub uplift: Field,
    /// Drainage-area exponent m (default 0.4).
    pub m: f64,
    /// Slope exponent n (default 1).
    pub n: f64,
    /// Time step, years (default 1000).
    pub dt: f64,
    /// Where water leaves the terrain: these cells are the fixed base level.
    #[serde(skip)]
    pub outlets: Outlets,
}

impl Default for StreamPower {
    /// 20 steps of K = 2·10⁻⁵, no uplift, m = 0.4, n = 1 (m/n = 0.4, the usual concavity),
    /// dt = 1000 years.
    fn default() -> Self {
        Self {
            iterations: 20,
            erodibility: Field::Uniform(2e-5),
            uplift: Field::Uniform(0.0),
            m: 0.4,
            n: 1.0,
            dt: 1000.0,
            outlets: Outlets::default(),
        }
    }
}

impl StreamPower {
    fn check(&self, cells: usize) -> Result<(), HydrologyError> {
        self.erodibility.check("erodibility", cells, "must be finite and ≥ 0")?;
        self.uplift.check("uplift", cells, "must be finite and ≥ 0")?;
        check_param("m", self.m, |m| m >= 0.0, "must be finite and ≥ 0")?;
        check_param("n", self.n, |n| n > 0.0, "must be finite and > 0")?;
        check_param("dt", self.dt, |dt| dt > 0.0, "must be finite and > 0")
    }

    /// One implicit step. Water is routed on a Priority-Flood+ε copy, so it crosses depressions,
    /// but the depressions themselves are not filled: a cell whose receiver stands higher (a lake
    /// floor) only uplifts. Outlets stay fixed — sinks of the routing, and every cell at or below
    /// the outlets' sea level (the base level: a sloping sea floor is not carved); no-data stays
    /// no-data; no cell ends above its height plus uplift·dt, and none ends below its receiver.
    ///
    /// # Errors
    /// [`HydrologyError::InvalidParameter`] / [`HydrologyError::LengthMismatch`] for bad
    /// parameters, [`HydrologyError::AllNoData`].
    pub fn step(&self, hf: &mut Heightfield) -> Result<(), HydrologyError> {
        self.steps(hf, 1, |_| {})
    }

    /// [`StreamPower::iterations`] implicit steps, calling `progress(done)` after each.
    ///
    /// # Errors
    /// As [`StreamPower::step`].
    pub fn run(&self, hf: &mut Heightfield, progress: impl FnMut(usize)) -> Result<(), HydrologyError> {
        self.steps(hf, self.iterations, progress)
    }

    fn steps(&self, hf: &mut Heightfield, steps: usize, mut progress: impl FnMut(usize)) -> Result<(), HydrologyError> {
        self.check(hf.grid().len())?;
        for done in 1..=steps {
            let routed = D8::new(&fill(hf, self.outlets)?)?;
            let (receivers, dist, area) = (routed.receivers(), routed.distances(), routed.drainage_area());
            let z = hf.samples_mut();
            // The sea is base level like the routing's sinks: rivers do not carve below it.
            let sea = self.outlets.sea_level;
            for &k in routed.order() {
                let k = k as usize;
                let r = receivers[k];
                if r == NO_RECEIVER || z[k].is_nan() || sea.is_some_and(|s| z[k] <= s) {
                    continue;
                }
                let h0 = f64::from(z[k]) + self.uplift.at(k) * self.dt;
                let hr = f64::from(z[r as usize]);
                if h0 <= hr {
                    z[k] = h0 as f32;
                    continue;
                }
                let f = self.erodibility.at(k) * self.dt * area[k].powf(self.m) / f64::from(dist[k]).powf(self.n);
                let h = if self.n == 1.0 { (h0 + f * hr) / (1.0 + f) } else { newton(h0, hr, f, self.n) };
                // f32 rounding must not lift a cell above h0 nor sink it under its receiver.
                z[k] = (h.clamp(hr, h0) as f32).clamp(z[r as usize], h0 as f32);
            }
            progress(done);
        }
        Ok(())
    }
}

/// Solves x − h0 + f·(x − hr)^n = 0 for x in [hr, h0] by safeguarded Newton iterations.
fn newton(h0: f64, hr: f64, f: f64, n: f64) -> f64 {
    let (mut lo, mut hi, mut x) = (hr, h0, h0);
    for _ in 0..50 {
        let s = x - hr;
        let g = x - h0 + f * s.powf(n);
        if g > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        let dg = 1.0 + n * f * s.powf(n - 1.0);
        let mut next = x - g / dg;
        if !(next > lo && next < hi && next.is_finite()) {
            next = 0.5 * (lo + hi);
        }
        if (next - x).abs() <= 1e-9 * (1.0 + x.abs()) {
            return next;
        }
        x = next;
    }
    x
}

/// Thermal (talus) erosion: wherever the slope to a neighbour exceeds the talus angle, a share of
/// the excess height slides down to it. Each iteration reads the old field and writes a new one
/// (parallel over rows, identical to serial); material moves between valid cells only, so the
/// total volume is conserved and no-data stays no-data.
/// In JSON every field is optional (the defaults below).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct Thermal {
    /// Angle of repose, degrees (default 33°).
    pub talus_deg: f64,
    /// Share of the largest excess moved per iteration, in (0, 0.5] (default 0.25).
    pub rate: f64,
    /// Iterations (default 50).
    pub iterations: usize,
}

impl Default for Thermal {
    fn default() -> Self {
        Self { talus_deg: 33.0, rate: 0.25, iterations: 50 }
    }
}

impl Thermal {
    /// Runs the iterations on `hf`, calling `progress(done)` after each.
    ///
    /// # Errors
    /// [`HydrologyError::InvalidParameter`] for a talus angle outside [0°, 90°) or a rate outside (0, 0.5].
    pub fn run(&self, hf: &mut Heightfield, mut progress: impl FnMut(usize)) -> Result<(), HydrologyError> {
        check_param("talus_deg", self.talus_deg, |a| (0.0..90.0).contains(&a), "must be in [0°, 90°)")?;
        check_param("rate", self.rate, |r| r > 0.0 && r <= 0.5, "must be in (0, 0.5]")?;
        let g = Grid8::new(hf.grid());
        let tan = self.talus_deg.to_radians().tan();
        let nx = g.nx;
        // Per cell: what it sheds in total, and that amount over the sum of its excesses (the share
        // of each excess that moves).
        let mut out = vec![(0.0f64, 0.0f64); g.len()];
        for done in 1..=self.iterations {
            let z = hf.samples();
            out.par_chunks_mut(nx).enumerate().for_each(|(j, row)| {
                for (i, o) in row.iter_mut().enumerate() {
                    *o = shed(&g, z, j * nx + i, tan, self.rate);
                }
            });
            let next: Vec<f32> = (0..g.len())
                .into_par_iter()
                .with_min_len(4096)
                .map(|k| {
                    if z[k].is_nan() {
                        return z[k];
                    }
                    let mut h = f64::from(z[k]) - out[k].0;
                    g.each(k, |w, dir, _| {
                        let share = out[w].1;
                        if share > 0.0 {
                            // Measured from the sender's row, exactly as the sender measured it.
                            let e = f64::from(z[w] - z[k]) - tan * g.dist(w, (dir + 4) % 8);
                            if e > 0.0 {
                                h += share * e;
                            }
                        }
                    });
                    h as f32
                })
                .collect();
            hf.samples_mut().copy_from_slice(&next);
            progress(done);
        }
        Ok(())
    }
}

/// What cell `k` sheds: `(amount, amount / sum of its excesses)`, amount = rate · largest excess.
fn shed(g: &Grid8, z: &[f32], k: usize, tan: f64, rate: f64) -> (f64, f64) {
    if z[k].is_nan() {
        return (0.0, 0.0);
    }
    let (mut total, mut largest) = (0.0f64, 0.0f64);
    g.each(k, |w, _, d| {
        let e = f64::from(z[k] - z[w]) - tan * d;
        if e > 0.0 {
            total += e;
            largest = largest.max(e);
        }
    });
    if total > 0.0 { (rate * largest, rate * largest / total) } else { (0.0, 0.0) }
}
