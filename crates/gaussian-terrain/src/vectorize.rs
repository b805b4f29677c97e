//! Vectorization of a DEM (§4): multi-level initialisation, then Adam on the analytic gradient of
//! the loss (module `loss`) with clone / split / prune regularisation, then optionally a detail
//! layer from the error map for a near-exact recovery.
//!
//! The fit runs on a working grid (the DEM, bilinearly reduced to at most
//! [`VectorizeOptions::resolution`] samples along its longer side, smoothed first when reduced
//! by more than 2×): this is the paper's "fixed cell size c to compute the loss terms". Inside,
//! positions are in working-grid samples and elevations are normalized to `[0, 2]` (the span of
//! the paper's `[−1, 1]`) above the DEM's minimum, which becomes [`VectorTerrain::base`].

use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use glam::{DMat2, DVec2};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use relief_heightfield::{GridSpec, Heightfield};
use serde::{Deserialize, Serialize};

use crate::fastmath::{exp_neg, exp2_signed, log2};
use crate::kernel::{Prepared, Span, raster_samples};
use crate::loss::{Loss, LossTerms, LossWeights};
use crate::{Gaussian, GaussianError, MAX_PRIMITIVES, VectorTerrain};

/// The paper's initial scales, as fractions of the domain, for about 10 000 primitives (§4).
const LEVELS: [f64; 5] = [0.06, 0.04, 0.03, 0.02, 0.01];
/// Share of the budget placed by the initialisation; densification adds the rest and replaces
/// what pruning removes. 0.9 rather than 0.8: the steps move primitives rather than wait for
/// them (Jacksboro at 1024², 200 steps, with the step sizes of `Param::new`: ℓ₁ 3.84e-3,
/// against 4.29e-3 before both). 0.95 fitted a little closer (3.74e-3) but left densification
/// no room on small budgets, whose levels round their counts up to the whole budget.
const INIT_SHARE: f64 = 0.9;
/// Tail tolerance of the fit's last fifth (the settling steps) and of its pruning: the
/// rendering default, so that the tails a render adds are the tails the fit saw (a fit at 10⁻²
/// throughout leaves a 50 % larger ℓ₁ at render).
const FIT_TOLERANCE: f64 = crate::DEFAULT_TOLERANCE;
/// Tail tolerance while densification places primitives (the first four fifths of the steps):
/// a support of 3.03 rather than 3.72 σ for β = 2, two thirds of the samples, so those steps
/// cost about 30 % less; the settling fifth at [`FIT_TOLERANCE`] then fits the tails. On
/// Jacksboro at 1024² with 10 000 primitives and 350 steps: ℓ₁ 2.99e-3 → 2.98e-3, 80.8 → 58.8 s;
/// on the small real DEMs of `docs/benchmarks.md`, up to 6 % more ℓ₁ for the same steps and
/// 1–6 % less for the same time (270 steps against 200). 3·10⁻² fitted as closely for the same steps and faster still, but no
/// closer for the same time; 10⁻² or 3·10⁻² until the last tenth, no closer or 11 % worse;
/// 10⁻¹, 2.7× worse (docs/benchmarks.md).
const PLACING_TOLERANCE: f64 = 1e-2;
/// Default bounds on β while fitting ([`VectorizeOptions::beta_range`]; β below would make the
/// gradient blow up at the centre).
const BETA_RANGE: [f64; 2] = [0.6, 8.0];

/// How to vectorize.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct VectorizeOptions {
    /// The most Gaussian primitives (default 10 000): 90 % are placed by the initialisation,
    /// densification adds up to this many, pruning removes.
    pub primitives: usize,
    /// Samples along the working grid's longer side (default 512; the DEM's own size if smaller).
    pub resolution: usize,
    /// Optimisation steps (default 260: what 200 cost before the placing steps cut their tails
    /// short, [`vectorize`]).
    pub iterations: usize,
    /// Stop after this much wall time (none by default). A time budget makes the result depend
    /// on the machine's speed; iteration budgets are deterministic. With a time budget or a
    /// target loss every step fits the tails a render adds; a fit that runs its iterations
    /// places its primitives with shorter tails first, about 30 % faster (see [`vectorize`]).
    pub time_budget: Option<Duration>,
    /// Stop once the total loss is at or below this (none by default).
    pub target_loss: Option<f64>,
    /// Adam's step size, 10⁻² as in the paper: per step, at most about 18.75 × this of a
    /// primitive's scale for its centre, 5.625 × this for ln σ, θ and ln β, and 1.875 × this for
    /// the amplitude in normalized elevation (the relief spans 2); this for every parameter of
    /// the authors' parametrisation with [`VectorizeOptions::uniform_steps`].
    pub learning_rate: f64,
    /// Loss weights `α₁`, `α₂` (SSIM gets the rest).
    pub weights: LossWeights,
    /// Clone / split / prune every this many steps (default 50; 0 never).
    pub densify_every: usize,
    /// The most elongated a primitive may be (`t_e`, default 20): the paper prunes those beyond
    /// it after the fit; here every step holds the primitives within it, so that the pruning
    /// never removes one the others lean on.
    pub max_elongation: f64,
    /// Prune primitives whose |amplitude| is below this, in normalized units (`t_a`, default 10⁻³).
    pub min_amplitude: f64,
    /// Add a detail layer reading the error map, its Poisson spacing in DEM cells (default
    /// `None`: no details; 2 restores the DEM to within f32 rounding).
    pub detail_spacing: Option<f64>,
    /// How densification picks the primitives to clone or split (default
    /// [`Densify::Error`]).
    pub densify: Densify,
    /// The paper's Adam as its authors' code runs it (default `false`: per-parameter steps
    /// scaled to each primitive, a second moment that forgets in about 20 steps and a learning
    /// rate decaying to a tenth; see `docs/benchmarks.md` for the comparison on real DEMs).
    ///
    /// Their Adam takes one step size, `learning_rate`, for every parameter of their own
    /// parametrisation, keeps it constant, and uses PyTorch's moment decays (0.9, 0.999). Their
    /// parameters are activated: a centre is `tanh` of its parameter across the domain's
    /// `[−1, 1]`, σ a sigmoid times a softplus scale, θ `π·tanh`, heights span `[0, 1]`, the
    /// exponent is `1 +` a sigmoid. Adam's step is the same whatever a parameter's scale, so a
    /// step of `learning_rate` in theirs is, in ours, `learning_rate` times the activation's
    /// derivative: for a centre, half the working grid's width times `1 − u²` (`u` its position
    /// in `[−1, 1]`, so about 0.5 % of the width per step in the middle, less near the edges);
    /// 1.4 × for ln σ (1 from the scale, about 0.4 from the axis's sigmoid at its initial
    /// values), 1 × for θ (π·sech² averaged over their initial angles), 2 × for the amplitude
    /// (our normalized relief spans 2) and 0.15 × for ln β (their exponent's sigmoid at its
    /// initial values).
    pub uniform_steps: bool,
    /// The range of the exponent β while fitting, `0.5 ≤ min ≤ max` (default `[0.6, 8]`: peaked
    /// to flat-topped; the initial exponents, drawn in `[1.8, 2.5)`, are clamped into it).
    /// The paper's kernel `exp(−(½d²)^β′)` with `β′ = 1 + sigmoid ∈ (1, 2)` is ours with
    /// `β = 2β′` (and σ rescaled), so `[2, 4]` restricts the fit to the paper's shapes.
    pub beta_range: [f64; 2],
    /// Keep the fit within the DEM's elevation range and its flat ground flat (default
    /// `true`): samples beyond the range are penalised in the loss, errors over flat ground
    /// (lakes, plateaus) weigh more, and when at least 1 % of the DEM lies at its minimum (a sea,
    /// a filled no-data area) the fit is raised to that minimum wherever it falls below, recorded
    /// as the terrain's [`VectorTerrain::floor`], so such ground stays exactly flat instead of
    /// carrying the ripples of primitives cancelling each other (and, in the last fifth of the
    /// steps, a larger flat weight trims what leaks over it from above). `false` fits the plain sum,
    /// as the paper does.
    pub keep_range: bool,
    /// Seed of the initial placement.
    pub seed: u64,
}

/// How densification (§4) chooses the primitives it clones or splits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Densify {
    /// Those under the largest mean absolute error, weighted by their fall-off (default).
    #[default]
    Error,
    /// Those with the largest mean positional gradient since the last densification, as
    /// 3D Gaussian splatting (Kerbl et al. 2023) and the paper choose them.
    PositionalGradient,
}

impl Default for VectorizeOptions {
    fn default() -> Self {
        Self {
            primitives: 10_000,
            resolution: 512,
            iterations: 260,
            time_budget: None,
            target_loss: None,
            learning_rate: 1e-2,
            weights: LossWeights::default(),
            densify_every: 50,
            max_elongation: 20.0,
            min_amplitude: 1e-3,
            detail_spacing: None,
            densify: Densify::Error,
            uniform_steps: false,
            beta_range: BETA_RANGE,
            keep_range: true,
            seed: 0,
        }
    }
}

impl VectorizeOptions {
    fn validate(&self) -> Result<(), GaussianError> {
        let bad = |name, value: f64, reason| Err(GaussianError::InvalidOption { name, value, reason });
        if self.primitives == 0 || self.primitives > MAX_PRIMITIVES {
            return bad("primitives", self.primitives as f64, "must be in 1..=4194304 (2^22)");
        }
        if self.resolution < 2 {
            return bad("resolution", self.resolution as f64, "must be at least 2");
        }
        if !(self.learning_rate.is_finite() && self.learning_rate > 0.0) {
            return bad("learning_rate", self.learning_rate, "must be > 0");
        }
        let w = self.weights;
        if !(w.l1 >= 0.0 && w.gradient >= 0.0 && w.ssim() >= -1e-12) {
            return bad("weights", w.l1 + w.gradient, "α₁, α₂ must be ≥ 0 with α₁ + α₂ ≤ 1");
        }
        if self.max_elongation.is_nan() || self.max_elongation <= 1.0 {
            return bad("max_elongation", self.max_elongation, "must be > 1");
        }
        if !(self.min_amplitude >= 0.0 && self.min_amplitude.is_finite()) {
            return bad("min_amplitude", self.min_amplitude, "must be ≥ 0");
        }
        let [b0, b1] = self.beta_range;
        if !(b0.is_finite() && b1.is_finite() && 0.5 <= b0 && b0 <= b1) {
            return bad(
                "beta_range",
                if b0.is_finite() && b0 >= 0.5 { b1 } else { b0 },
                "must satisfy 0.5 ≤ min ≤ max",
            );
        }
        if let Some(s) = self.detail_spacing
            && !(s.is_finite() && s > 0.0)
        {
            return bad("detail_spacing", s, "must be > 0");
        }
        Ok(())
    }
}

/// Where a running vectorization stands, passed to the progress callback once per step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Steps done.
    pub iteration: usize,
    /// The step budget.
    pub iterations: usize,
    /// Primitives now.
    pub primitives: usize,
    /// The loss at this step (working grid, normalized elevation).
    pub loss: LossTerms,
    /// Wall time since the start.
    pub elapsed: Duration,
}

/// What [`vectorize`] reached.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VectorizeReport {
    /// Steps run.
    pub iterations: usize,
    /// Gaussian primitives kept.
    pub primitives: usize,
    /// Loss at the last step on the working grid (normalized elevation, the paper's units).
    pub loss: LossTerms,
    /// Mean absolute error of the Gaussians alone against the DEM, at the DEM's resolution,
    /// normalized like `loss.l1`: of the relief's half-range (the relief spanning `[−1, 1]`, as
    /// the paper's §4 words it). [`VectorizeReport::l1_of_relief`] gives it in Table 3's unit.
    pub l1_normalized: f64,
    /// The same in elevation units.
    pub l1: f64,
    /// Mean absolute error with the detail layer (equal to `l1` without one), elevation units.
    pub l1_with_details: f64,
    /// Wall time.
    pub seconds: f64,
    /// Why it stopped: "iterations", "time", "loss" or "cancelled".
    pub stopped_by: String,
}

impl VectorizeReport {
    /// The mean absolute error of the Gaussians alone as a fraction of the DEM's relief (the
    /// relief spanning `[0, 1]`), half of [`l1_normalized`](Self::l1_normalized). This is the
    /// unit of the paper's Table 3 as its authors' code computes it: their optimisation and
    /// metrics read a 16-bit PNG divided by its largest value and take PyTorch's `L1Loss` of
    /// that, so their ℓ₁ of 2.21·10⁻³ at 11k primitives compares with this figure.
    ///
    /// ```
    /// use relief_gaussian_terrain::{LossTerms, VectorizeReport};
    ///
    /// // A fit that left 2 m of mean error on a DEM with 1 000 m of relief:
    /// let report = VectorizeReport {
    ///     iterations: 260,
    ///     primitives: 10_000,
    ///     loss: LossTerms::default(),
    ///     l1_normalized: 0.004,
    ///     l1: 2.0,
    ///     l1_with_details: 2.0,
    ///     seconds: 50.0,
    ///     stopped_by: "iterations".into(),
    /// };
    /// assert_eq!(report.l1_of_relief(), 0.002);
    /// ```
    pub fn l1_of_relief(&self) -> f64 {
        self.l1_normalized / 2.0
    }
}

/// A vectorized DEM and how well it fits.
#[derive(Debug, Clone, PartialEq)]
pub struct Vectorized {
    /// The vector terrain (world units of the DEM's grid).
    pub terrain: VectorTerrain,
    /// Figures of the fit.
    pub report: VectorizeReport,
}

/// Adam's decay of its second moment (the mean squared gradient) with the per-parameter steps.
/// PyTorch's 0.999 ([`PAPER_BETA2`]) remembers the large gradients of the first steps for
/// hundreds of steps, so every parameter's step shrinks as the fit settles, on top of the
/// learning rate's decay; 0.95 forgets them in about 20 steps, so the steps keep their size
/// until the schedule lowers it, and 1.5× the step sizes then pay. Together, on Jacksboro at
/// 1024² with 10 000 primitives and 350 steps: ℓ₁ 3.33e-3 → 2.99e-3 (β₂ 0.95 alone 3.14e-3;
/// larger steps alone had fitted worse). On the real DEMs of the fidelity tables, 4–12 % lower
/// at both densities; 2× the steps fitted closer at a DEM's own resolution but up to 8 % worse
/// on a working grid coarser than the DEM (`docs/benchmarks.md`).
const BETA2: f64 = 0.95;
/// PyTorch's default second-moment decay, the paper's Adam ([`VectorizeOptions::uniform_steps`]).
const PAPER_BETA2: f64 = 0.999;

/// Optimizer state of one primitive: parameters `(cx, cy, ln σx, ln σy, θ, a, ln β)` in working
/// samples and normalized elevation, Adam's moments, per-parameter step scales.
#[derive(Debug, Clone, Copy)]
struct Param {
    x: [f64; 7],
    m: [f64; 7],
    v: [f64; 7],
    step: [f64; 7],
    /// Adam's second-moment decay ([`BETA2`], or [`PAPER_BETA2`] with uniform steps).
    beta2: f64,
    t: u32,
    /// Σ |∂ℓ/∂c| since the last densification ([`Densify::PositionalGradient`]).
    positional: f64,
}

impl Param {
    fn new(center: DVec2, sigma: [f64; 2], theta: f64, amplitude: f64, beta: f64, options: &VectorizeOptions) -> Self {
        let (lr, scale) = (options.learning_rate, (sigma[0] * sigma[1]).sqrt());
        let x = [center.x, center.y, sigma[0].ln(), sigma[1].ln(), theta, amplitude, beta.ln()];
        // Per-step sizes for Adam (whose steps are about `lr` in units of these), at the
        // default `lr`: the centre 18.75 % of the primitive's scale, ln σ / θ / ln β 5.625 %,
        // the amplitude 1.875 × `lr` in normalized elevation (the paper's raw parameters take
        // `lr`).
        // Tuned on the tests' DEMs, where they reach a 2–8× lower ℓ₁ than a uniform `lr` in the
        // same number of steps, then scaled by 1.25 on the real DEMs of `docs/benchmarks.md`
        // together with the initial share (ℓ₁ 2–10 % lower on every DEM there but Luxembourg,
        // within 1.5 % on it), then by 1.5 with `BETA2` (2× and 3× had fitted no better alone).
        let (s, a) = (5.625 * lr, 1.875 * lr);
        let (step, beta2) = if options.uniform_steps {
            // The centre's two entries are the learning rate alone: `adam` multiplies them by
            // the derivative of the authors' tanh at the current position.
            ([lr, lr, 1.4 * lr, 1.4 * lr, lr, 2.0 * lr, 0.15 * lr], PAPER_BETA2)
        } else {
            ([18.75 * lr * scale, 18.75 * lr * scale, s, s, s, a, s], BETA2)
        };
        Self { x, m: [0.0; 7], v: [0.0; 7], step, beta2, t: 0, positional: 0.0 }
    }

    fn gaussian(&self) -> Gaussian {
        let x = &self.x;
        Gaussian {
            center: [x[0], x[1]],
            sigma: [x[2].exp(), x[3].exp()],
            theta: x[4],
            amplitude: x[5],
            beta: x[6].exp(),
        }
    }

    /// The step sizes of this update: the stored ones, but with the paper's steps (`half` the
    /// working grid's half extents, [`Bounds::tanh_half`]) the centre's is the learning rate
    /// times the derivative of the authors' `tanh` positions, `half` times `1 − u²` (`u` the
    /// position in `[−1, 1]`, kept off its ends as `tanh` keeps it).
    fn steps(&self, half: Option<DVec2>) -> [f64; 7] {
        let mut step = self.step;
        if let Some(half) = half {
            for k in 0..2 {
                let u = (self.x[k] / half[k] - 1.0).clamp(-0.999, 0.999);
                step[k] *= half[k] * (1.0 - u * u);
            }
        }
        step
    }

    fn adam(&mut self, grad: &[f64; 7], bounds: &Bounds) {
        const B1: f64 = 0.9;
        let b2 = self.beta2;
        self.t += 1;
        let (c1, c2) = (1.0 - B1.powi(self.t as i32), 1.0 - b2.powi(self.t as i32));
        let steps = self.steps(bounds.tanh_half);
        let moments = self.m.iter_mut().zip(self.v.iter_mut());
        for (((x, (m, v)), g), step) in self.x.iter_mut().zip(moments).zip(grad).zip(&steps) {
            *m = B1 * *m + (1.0 - B1) * g;
            *v = b2 * *v + (1.0 - b2) * g * g;
            *x -= bounds.decay * step * (*m / c1) / ((*v / c2).sqrt() + 1e-12);
        }
        let (max_ln_sigma, max_ln_elongation) = (bounds.max_ln_sigma, bounds.max_ln_elongation);
        // Elongation stays within the pruning's `t_e`, the area (σx·σy) kept: a primitive that
        // grew longer would be pruned after the fit, and whatever it cancelled would show (on
        // Luxembourg, a thin negative primitive along the filled border, 23:1, left a bump of
        // 2.8 % of the relief when pruned).
        let [a, b] = [self.x[2], self.x[3]];
        if (a - b).abs() > max_ln_elongation {
            let (mid, half) = (0.5 * (a + b), 0.5 * max_ln_elongation * (a - b).signum());
            (self.x[2], self.x[3]) = (mid + half, mid - half);
        }
        self.x[2] = self.x[2].clamp(-3.0, max_ln_sigma);
        self.x[3] = self.x[3].clamp(-3.0, max_ln_sigma);
        self.x[6] = self.x[6].clamp(bounds.ln_beta[0], bounds.ln_beta[1]);
    }
}

/// What an Adam update of [`Param`] needs besides its gradient.
#[derive(Debug, Clone, Copy)]
struct Bounds {
    /// The learning rate's decay at this step (1 with the paper's constant rate).
    decay: f64,
    /// ln σ stays within `[−3, max_ln_sigma]`.
    max_ln_sigma: f64,
    /// |ln σx − ln σy| stays within this (the elongation limit `t_e`).
    max_ln_elongation: f64,
    /// ln β stays within these ([`VectorizeOptions::beta_range`]).
    ln_beta: [f64; 2],
    /// With the paper's steps ([`VectorizeOptions::uniform_steps`]), half the working grid's
    /// extent along x and y in samples, the scale of the authors' `tanh` positions.
    tanh_half: Option<DVec2>,
}

impl Bounds {
    /// The bounds of a fit on `pixels`, with the learning rate's decay at 1.
    fn new(options: &VectorizeOptions, pixels: &GridSpec) -> Self {
        let (wx, wy) = (pixels.nx(), pixels.ny());
        let [b0, b1] = options.beta_range;
        Self {
            decay: 1.0,
            max_ln_sigma: ((wx.max(wy) - 1) as f64).ln(),
            max_ln_elongation: max_ln_elongation(options),
            ln_beta: [b0.ln(), b1.ln()],
            tanh_half: options.uniform_steps.then(|| 0.5 * DVec2::new(wx as f64, wy as f64)),
        }
    }
}

/// Converts `dem` into a [`VectorTerrain`] of at most `options.primitives` Gaussians (§4),
/// calling `progress` after every step (return [`ControlFlow::Break`] to stop early and keep
/// the fit so far).
///
/// The first four fifths of the steps place primitives (densification) on supports cut at
/// 10⁻² of their amplitude, the last fifth fits them at the render's 10⁻³
/// ([`crate::DEFAULT_TOLERANCE`]): the placing steps cost about 30 % less, and the last fifth
/// fits the tails a render adds (the loss `progress` sees before then is that of the shorter
/// tails). A fit cancelled before its last fifth keeps tails it did not fit; one with a time
/// budget or a target loss, which may stop at any step, fits them at every step.
///
/// Deterministic for a given seed and iteration budget, for any thread count.
///
/// # Errors
/// [`GaussianError::InvalidOption`] for bad options, [`GaussianError::EmptyDem`] for a DEM with
/// fewer than 2 × 2 samples or no valid sample, [`GaussianError::DemHasNoData`] when some samples
/// are no-data (fill them first).
///
/// # Example
/// ```
/// use std::ops::ControlFlow;
/// use glam::DVec2;
/// use relief_gaussian_terrain::{Gaussian, RasterOptions, VectorTerrain, VectorizeOptions, rasterize, vectorize};
/// use relief_heightfield::{Extent, GridSpec};
///
/// // A DEM made of two hills, vectorized with 50 primitives.
/// let truth = VectorTerrain::new(vec![
///     Gaussian::round(DVec2::new(30.0, 30.0), 8.0, 100.0),
///     Gaussian::round(DVec2::new(70.0, 60.0), 12.0, 60.0),
/// ]);
/// let grid = GridSpec::from_extent(64, 64, Extent::new(DVec2::ZERO, DVec2::splat(100.0)))?;
/// let dem = rasterize(&truth, &grid, &RasterOptions::default())?;
/// let options = VectorizeOptions { primitives: 50, iterations: 60, ..VectorizeOptions::default() };
/// let fit = vectorize(&dem, &options, |_| ControlFlow::Continue(()))?;
/// assert!(fit.report.l1 < 2.0, "mean error {} m", fit.report.l1);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn vectorize(
    dem: &Heightfield,
    options: &VectorizeOptions,
    mut progress: impl FnMut(&Progress) -> ControlFlow<()>,
) -> Result<Vectorized, GaussianError> {
    options.validate()?;
    let started = Instant::now();
    let (lo, hi) = check_dem(dem)?;
    let range = f64::from(hi) - f64::from(lo);
    let mut report = VectorizeReport {
        iterations: 0,
        primitives: 0,
        loss: LossTerms::default(),
        l1_normalized: 0.0,
        l1: 0.0,
        l1_with_details: 0.0,
        seconds: 0.0,
        stopped_by: "iterations".into(),
    };
    let ext = dem.extent();
    let mut terrain = VectorTerrain {
        base: f64::from(lo),
        domain: Some([ext.min.to_array(), ext.max.to_array()]),
        ..VectorTerrain::default()
    }
    .in_frame_of(dem);
    if range <= 0.0 {
        // A flat DEM is its base.
        report.seconds = started.elapsed().as_secs_f64();
        return Ok(Vectorized { terrain, report });
    }

    // The working grid and the normalized target on it.
    let work = working_dem(dem, options.resolution)?;
    let target: Vec<f32> =
        work.samples().iter().map(|&h| (2.0 * (f64::from(h) - f64::from(lo)) / range) as f32).collect();
    let pixels = GridSpec::new(work.nx(), work.ny(), DVec2::ZERO, DVec2::ONE)?;
    let floored = options.keep_range && lies_flat_at_minimum(dem, lo);
    if floored {
        terrain.floor = Some(f64::from(lo));
    }
    let fit = fit(&target, &pixels, options, floored, started, &mut progress);
    report.stopped_by = fit.stopped_by.into();
    let kept: Vec<Gaussian> =
        fit.params.iter().map(Param::gaussian).filter(|g| keep(g, options, &pixels, FIT_TOLERANCE)).collect();

    terrain.primitives = to_world(&kept, &work, range);
    measure_and_add_details(dem, &mut terrain, &mut report, options, range)?;
    report.iterations = fit.iterations;
    report.primitives = terrain.primitives.len();
    report.loss = fit.loss;
    report.seconds = started.elapsed().as_secs_f64();
    Ok(Vectorized { terrain, report })
}

/// The DEM's elevation range `(min, max)`, once it is known to be at least 2 × 2 samples with no
/// no-data.
fn check_dem(dem: &Heightfield) -> Result<(f32, f32), GaussianError> {
    let (nx, ny) = (dem.nx(), dem.ny());
    if nx < 2 || ny < 2 {
        return Err(GaussianError::EmptyDem { nx, ny });
    }
    if dem.has_no_data() {
        return Err(GaussianError::DemHasNoData { count: dem.no_data_count() });
    }
    dem.min_max().ok_or(GaussianError::EmptyDem { nx, ny })
}

/// Whether at least 1 % of the DEM lies exactly at its minimum `lo` (a sea, a filled no-data
/// area): the fit then gets a floor there.
fn lies_flat_at_minimum(dem: &Heightfield, lo: f32) -> bool {
    let at = dem.samples().iter().filter(|&&h| h == lo).count();
    at * 100 >= dem.samples().len()
}

/// Where the optimisation stopped: the primitives' optimizer states, the steps run, the loss at
/// the last step and why it stopped (as [`VectorizeReport::stopped_by`]).
struct Fit {
    params: Vec<Param>,
    iterations: usize,
    loss: LossTerms,
    stopped_by: &'static str,
}

/// The optimisation on the working grid `pixels` (§4): the multi-level initialisation, then Adam
/// steps with a learning rate decaying to a tenth over the budget, densifying every
/// `options.densify_every` steps but in the last fifth, until [`stop_reason`] says otherwise.
/// With `floored`, the approximation is raised to 0 (the DEM's minimum) where it falls below,
/// and samples so raised pass no gradient back; the floor's flat ground gets the flat weight in
/// the last fifth only.
fn fit(
    target: &[f32],
    pixels: &GridSpec,
    options: &VectorizeOptions,
    floored: bool,
    started: Instant,
    progress: &mut impl FnMut(&Progress) -> ControlFlow<()>,
) -> Fit {
    let (wx, wy) = (pixels.nx(), pixels.ny());
    let mut params = initialise(target, pixels, options);
    let mut objective = Loss::new(target, wx, wy);
    let mut grad = Vec::new();
    // Flat ground weighs more (`hold_flats`). Ground flat at the floor is held from below by
    // the floor itself; from above only once densification is over (the last fifth), where all
    // flat ground weighs more again and trims what the land's primitives leak over it without
    // reshaping the layout.
    let flats = if options.keep_range { flat_samples(target, wx, wy) } else { Vec::new() };
    let above_floor: Vec<u32> =
        if floored { flats.iter().copied().filter(|&k| target[k as usize] > 0.0).collect() } else { flats.clone() };
    let mut bounds = Bounds::new(options, pixels);
    let mut iteration = 0;
    loop {
        let settling = settles(iteration, options);
        let tolerance = step_tolerance(iteration, options);
        let prims: Vec<Gaussian> = params.iter().map(Param::gaussian).collect();
        let mut approx = raster_samples(&prims, pixels, tolerance);
        let below: Vec<bool> = if floored { raise_to_floor(&mut approx) } else { Vec::new() };
        let terms = objective.evaluate(&approx, &options.weights, Some(&mut grad));
        grad.par_iter_mut().zip(&below).filter(|(_, b)| **b).for_each(|(g, _)| *g = 0.0);
        if options.keep_range {
            penalize_out_of_range(&approx, &mut grad);
            if settling {
                hold_flats(&approx, target, &flats, SETTLING_FLAT_WEIGHT, &mut grad);
            } else {
                hold_flats(&approx, target, &above_floor, FLAT_WEIGHT, &mut grad);
            }
        }
        let state = Progress {
            iteration,
            iterations: options.iterations,
            primitives: params.len(),
            loss: terms,
            elapsed: started.elapsed(),
        };
        if let Some(stopped_by) = stop_reason(&state, options, progress) {
            return Fit { params, iterations: iteration, loss: terms, stopped_by };
        }
        // Densification after this step ranks by the error under each primitive: only then is
        // it summed.
        let next = iteration + 1;
        let densifying =
            options.densify_every > 0 && next % options.densify_every == 0 && next * 5 <= options.iterations * 4;
        let err: Option<Vec<f32>> = (densifying && options.densify == Densify::Error)
            .then(|| approx.iter().zip(target).map(|(a, b)| (a - b).abs()).collect());
        let back = backward(&prims, pixels, &grad, err.as_deref(), tolerance);
        // Learning rate decays exponentially to a tenth over the budget; the paper's is constant.
        if !options.uniform_steps {
            bounds.decay = 0.1f64.powf(iteration as f64 / options.iterations.max(1) as f64);
        }
        params.par_iter_mut().zip(&back).for_each(|(p, b)| {
            p.positional += b.grad[0].hypot(b.grad[1]);
            p.adam(&b.grad, &bounds);
        });
        iteration = next;
        if densifying {
            densify(&mut params, &back, options, pixels);
        }
    }
}

/// Whether step `iteration` is one of the settling steps, the last fifth of the budget: no more
/// densification, all flat ground weighed by [`SETTLING_FLAT_WEIGHT`], the tails fitted at
/// [`FIT_TOLERANCE`].
fn settles(iteration: usize, options: &VectorizeOptions) -> bool {
    iteration * 5 >= options.iterations * 4
}

/// The tail tolerance of step `iteration`: [`PLACING_TOLERANCE`] before the settling steps,
/// [`FIT_TOLERANCE`] in them. A fit that may stop on a time budget or a target loss takes
/// [`FIT_TOLERANCE`] throughout, so that wherever it stops its tails are those a render adds
/// (and its loss the loss of that render).
fn step_tolerance(iteration: usize, options: &VectorizeOptions) -> f64 {
    let may_stop_early = options.time_budget.is_some() || options.target_loss.is_some();
    if may_stop_early || settles(iteration, options) { FIT_TOLERANCE } else { PLACING_TOLERANCE }
}

/// Raises the samples of `approx` below the floor (0, the DEM's minimum) to it, and says which
/// were raised.
fn raise_to_floor(approx: &mut [f32]) -> Vec<bool> {
    approx
        .par_iter_mut()
        .map(|a| {
            let below = *a < 0.0;
            if below {
                *a = 0.0;
            }
            below
        })
        .collect()
}

/// Weight of the range penalty, against ℓ₁'s `α₁` = 0.5: an excess beyond the DEM's range costs
/// five times what the same error inside it does.
const RANGE_WEIGHT: f64 = 8.0;

/// Adds the gradient of `RANGE_WEIGHT · mean(max(0, a − 2) + max(0, −a))` to `grad`: samples of
/// the approximation above the DEM's top or below its bottom (normalized 2 and 0) are pushed
/// back, so that a fit does not overshoot the range the DEM spans (a peak above the summit, a
/// hollow below the lowest valley) to lower its error next to it.
fn penalize_out_of_range(approx: &[f32], grad: &mut [f32]) {
    let k = (RANGE_WEIGHT / approx.len() as f64) as f32;
    grad.par_iter_mut().zip(approx).for_each(|(g, &a)| {
        if a > 2.0 {
            *g += k;
        } else if a < 0.0 {
            *g -= k;
        }
    });
}

/// The samples of `target` whose 3 × 3 neighbourhood is exactly flat (sea, lakes, filled
/// no-data): indices, ascending.
fn flat_samples(target: &[f32], nx: usize, ny: usize) -> Vec<u32> {
    let mut out = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let h = target[j * nx + i];
            let flat = (j.saturating_sub(1)..(j + 2).min(ny))
                .all(|jj| (i.saturating_sub(1)..(i + 2).min(nx)).all(|ii| target[jj * nx + ii] == h));
            if flat {
                out.push((j * nx + i) as u32);
            }
        }
    }
    out
}

/// Weight of the extra ℓ₁ on flat ground, against ℓ₁'s `α₁` = 0.5 everywhere: an error over a
/// lake costs nine times what it costs on a slope (4 cuts the largest error over the open flat
/// of Jacksboro and the Salish topobathy 3–7×, for at most 1.3 % more ℓ₁; docs/benchmarks.md).
const FLAT_WEIGHT: f64 = 4.0;

/// The flat weight in the last fifth of the steps, once densification is over, on all flat
/// ground (the floor's too). Without it, primitives that follow a coast or a border in a
/// small fit could leave bumps over the open flat beside it: at 10 primitives per 1000
/// samples, Luxembourg's filled border kept one above 1 % of the relief in 9 fits of 36 seeds
/// (up to 26 %) with `FLAT_WEIGHT` there, in 1 of 36 (2.8 %) with this, for 2.7 % more ℓ₁ on
/// that DEM and at most 0.5 % on the others (1.2 % at 4× that density; docs/benchmarks.md). That
/// last one came from the pruning after the fit, which now never fires on elongation
/// ([`Param::adam`]): none of the 36 is above 0.5 % since.
const SETTLING_FLAT_WEIGHT: f64 = 32.0;

/// Adds the gradient of `weight · Σ_flat |a − t| / n` (`n` all the samples): errors over
/// flat ground cost more than the same errors on slopes, so ground the DEM holds flat (a lake,
/// a plateau) does not ripple.
fn hold_flats(approx: &[f32], target: &[f32], flats: &[u32], weight: f64, grad: &mut [f32]) {
    let k = (weight / approx.len() as f64) as f32;
    for &f in flats {
        let f = f as usize;
        let e = approx[f] - target[f];
        if e != 0.0 {
            grad[f] += k * e.signum();
        }
    }
}

/// Reports `state` to `progress`, then says whether the fit stops before another step and why:
/// "cancelled" (the callback broke), "iterations", "time" or "loss" (the budgets, in that order).
fn stop_reason(
    state: &Progress,
    options: &VectorizeOptions,
    progress: &mut impl FnMut(&Progress) -> ControlFlow<()>,
) -> Option<&'static str> {
    if progress(state).is_break() {
        Some("cancelled")
    } else if state.iteration >= options.iterations {
        Some("iterations")
    } else if options.time_budget.is_some_and(|b| state.elapsed >= b) {
        Some("time")
    } else if options.target_loss.is_some_and(|t| state.loss.total <= t) {
        Some("loss")
    } else {
        None
    }
}

/// The fitted primitives in world units: `x = origin + cell ⊙ p` (a non-square cell re-splits
/// each ellipse, Appendix A), amplitudes × range/2.
fn to_world(kept: &[Gaussian], work: &Heightfield, range: f64) -> Vec<Gaussian> {
    let to_world = DMat2::from_diagonal(work.grid().cell_size());
    let origin = work.grid().origin();
    kept.iter()
        .map(|g| {
            let mut w = g.transformed(to_world, origin);
            w.amplitude = g.amplitude * range / 2.0;
            w
        })
        .collect()
}

/// Measures the fit at the DEM's resolution and, when asked, adds the error-map detail layer
/// ([`VectorTerrain::add_error_details`]).
fn measure_and_add_details(
    dem: &Heightfield,
    terrain: &mut VectorTerrain,
    report: &mut VectorizeReport,
    options: &VectorizeOptions,
    range: f64,
) -> Result<(), GaussianError> {
    let mean_error = |terrain: &VectorTerrain| -> Result<f64, GaussianError> {
        let approx = crate::rasterize(terrain, dem.grid(), &crate::RasterOptions::default())?;
        let sum: f64 = dem.samples().iter().zip(approx.samples()).map(|(h, a)| f64::from((h - a).abs())).sum();
        Ok(sum / dem.samples().len() as f64)
    };
    report.l1 = mean_error(terrain)?;
    report.l1_normalized = 2.0 * report.l1 / range;
    report.l1_with_details = report.l1;
    if let Some(spacing) = options.detail_spacing {
        terrain.add_error_details(dem, spacing, options.seed ^ 0x00de_7a11)?;
        report.l1_with_details = mean_error(terrain)?;
    }
    Ok(())
}

/// The DEM on a grid of at most `resolution` samples along its longer side (smoothed first when
/// reduced by more than 2×, so the bilinear reduction does not alias).
fn working_dem(dem: &Heightfield, resolution: usize) -> Result<Heightfield, GaussianError> {
    let (nx, ny) = (dem.nx(), dem.ny());
    let long = nx.max(ny);
    if long <= resolution {
        return Ok(dem.clone());
    }
    let f = (resolution - 1) as f64 / (long - 1) as f64;
    let (mx, my) = (((nx - 1) as f64 * f).round() as usize + 1, ((ny - 1) as f64 * f).round() as usize + 1);
    let source = if f < 0.5 {
        let smooth = blur(dem.samples(), nx, ny, 0.5 / f);
        Heightfield::from_samples(*dem.grid(), smooth)?
    } else {
        dem.clone()
    };
    Ok(source.resample(mx.max(2), my.max(2))?)
}

/// Separable Gaussian blur of σ samples, edges clamped.
fn blur(f: &[f32], nx: usize, ny: usize, sigma: f64) -> Vec<f32> {
    let r = (3.0 * sigma).ceil() as isize;
    let w: Vec<f32> = (-r..=r).map(|d| (-(d * d) as f64 / (2.0 * sigma * sigma)).exp() as f32).collect();
    let sum: f32 = w.iter().sum();
    let w: Vec<f32> = w.iter().map(|v| v / sum).collect();
    let clamp = |k: isize, n: usize| k.clamp(0, n as isize - 1) as usize;
    let mut rows = vec![0.0f32; nx * ny];
    rows.par_chunks_mut(nx).enumerate().for_each(|(j, out)| {
        let src = &f[j * nx..(j + 1) * nx];
        for (i, o) in out.iter_mut().enumerate() {
            *o = w.iter().enumerate().map(|(k, wk)| wk * src[clamp(i as isize + k as isize - r, nx)]).sum();
        }
    });
    let mut out = vec![0.0f32; nx * ny];
    out.par_chunks_mut(nx).enumerate().for_each(|(j, o)| {
        for (k, wk) in w.iter().enumerate() {
            let jj = clamp(j as isize + k as isize - r, ny);
            for (a, b) in o.iter_mut().zip(&rows[jj * nx..(jj + 1) * nx]) {
                *a += wk * b;
            }
        }
    });
    out
}

/// `∫ exp(−½ r^β) r dr` over `[0, ∞)`, so that a primitive's volume is `2π σx σy a` times it
/// (1 for β = 2). Simpson's rule on the support.
fn radial_mass(beta: f64) -> f64 {
    let end = (2.0 * 40.0f64).powf(1.0 / beta); // e^−40 beyond
    let steps = 1000;
    let h = end / f64::from(steps);
    let f = |r: f64| r * (-0.5 * r.powf(beta)).exp();
    let mut s = f(0.0) + f(end);
    for k in 1..steps {
        s += f(f64::from(k) * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
    }
    s * h / 3.0
}

/// Multi-level initialisation (§4): five scales from coarse to fine, each level's primitives on
/// a jittered grid with amplitudes from the smoothed residual of the levels before, so that each
/// level alone reproduces that residual at its scale.
fn initialise(target: &[f32], pixels: &GridSpec, options: &VectorizeOptions) -> Vec<Param> {
    let (nx, ny) = (pixels.nx(), pixels.ny());
    let budget = ((options.primitives as f64) * INIT_SHARE).max(1.0);
    let weight: f64 = LEVELS.iter().map(|s| 1.0 / (s * s)).sum();
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    let mut params: Vec<Param> = Vec::new();
    let mut current = vec![0.0f32; nx * ny];
    let (w, h) = ((nx - 1) as f64, (ny - 1) as f64);
    for s in LEVELS {
        // Counts ∝ 1/s², so the levels' spacings keep the paper's ratios 6 : 4 : 3 : 2 : 1 and
        // 10 000 primitives give about its scales; σ is half the spacing, where a grid of
        // Gaussians sums to a plane within 1.4 % (closer spacing only multiplies the overlap).
        let count = (budget / (s * s) / weight).round().max(1.0);
        let spacing = (w.max(1.0) * h.max(1.0) / count).sqrt().max(0.5);
        let sigma = (0.5 * spacing).max(1.0);
        // Jittered grid of about `count` cells over the domain.
        let (cols, rows) = ((w / spacing).ceil().max(1.0) as usize, (h / spacing).ceil().max(1.0) as usize);
        let (dx, dy) = (w / cols as f64, h / rows as f64);
        let residual: Vec<f32> = target.iter().zip(&current).map(|(t, c)| t - c).collect();
        let smooth = blur(&residual, nx, ny, sigma);
        let before = params.len();
        for r in 0..rows {
            for c in 0..cols {
                let p = DVec2::new(
                    (c as f64 + rng.random_range(0.0..1.0)) * dx,
                    (r as f64 + rng.random_range(0.0..1.0)) * dy,
                );
                let beta = rng.random_range(1.8f64..2.5).clamp(options.beta_range[0], options.beta_range[1]);
                let theta: f64 = rng.random_range(0.0..std::f64::consts::PI);
                let (i, j) = (p.x.round() as usize, p.y.round() as usize);
                let value = f64::from(smooth[j.min(ny - 1) * nx + i.min(nx - 1)]);
                // Level sum ≈ Σ a·g ≈ (a / cell area) · volume of one primitive.
                let amplitude = value * dx * dy / (std::f64::consts::TAU * sigma * sigma * radial_mass(beta));
                params.push(Param::new(p, [sigma, sigma], theta, amplitude, beta, options));
            }
        }
        let level: Vec<Gaussian> = params[before..].iter().map(Param::gaussian).collect();
        let add = raster_samples(&level, pixels, FIT_TOLERANCE);
        current.iter_mut().zip(add).for_each(|(c, a)| *c += a);
    }
    params.retain(|p| keep(&p.gaussian(), options, pixels, FIT_TOLERANCE));
    within_budget(params, options.primitives)
}

/// `params` cut to the `budget` largest by volume (|a|·σx·σy), in their order: the levels'
/// jittered grids round their counts up, which a small budget may not hold.
fn within_budget(params: Vec<Param>, budget: usize) -> Vec<Param> {
    if params.len() <= budget {
        return params;
    }
    let volumes: Vec<f64> = params
        .iter()
        .map(|p| {
            let g = p.gaussian();
            (g.amplitude * g.sigma[0] * g.sigma[1]).abs()
        })
        .collect();
    let mut order: Vec<usize> = (0..params.len()).collect();
    order.sort_by(|&a, &b| volumes[b].total_cmp(&volumes[a]).then(a.cmp(&b)));
    order.truncate(budget);
    order.sort_unstable();
    order.into_iter().map(|k| params[k]).collect()
}

/// The largest |ln σx − ln σy| the fit lets a primitive reach ([`Param::adam`]): the pruning's
/// `t_e`, a hair inside, so that rounding cannot tip a clamped primitive over [`keep`]'s test.
fn max_ln_elongation(options: &VectorizeOptions) -> f64 {
    options.max_elongation.ln() - 1e-9
}

/// Whether a primitive survives pruning (§4): 3σ above one working cell, elongation at most
/// `t_e`, |a| at least `t_a`, and some of its support on the working grid.
fn keep(g: &Gaussian, options: &VectorizeOptions, pixels: &GridSpec, tolerance: f64) -> bool {
    let (small, large) = (g.sigma[0].min(g.sigma[1]), g.sigma[0].max(g.sigma[1]));
    3.0 * small > 1.0
        && large / small <= options.max_elongation
        && g.amplitude.abs() >= options.min_amplitude
        && Prepared::new(g, tolerance).rows(pixels).is_some()
}

/// Lanes of the backward pass's partial sums.
const LANES: usize = 16;

/// Per-primitive results of the backward pass.
struct Back {
    /// ∂ℓ/∂(cx, cy, ln σx, ln σy, θ, a, ln β).
    grad: [f64; 7],
    /// Mean absolute error under the primitive, weighted by its fall-off (0 when the backward
    /// pass was given no error map).
    error: f64,
}

/// The loss gradient of every primitive from the per-sample gradient `dl` (module `loss`):
/// `∂ℓ/∂θₖ = Σ_p dl(p)·∂g/∂θₖ(p)` over the support, primitives in parallel; with the
/// per-sample error `err`, also each primitive's fall-off-weighted error (densification's rank).
fn backward(prims: &[Gaussian], pixels: &GridSpec, dl: &[f32], err: Option<&[f32]>, tolerance: f64) -> Vec<Back> {
    let arch = pulp::Arch::new();
    prims
        .par_iter()
        .map(|g| {
            let p = Prepared::new(g, tolerance);
            let acc = arch.dispatch(Sums { p: &p, pixels, dl, err });
            let (u, v) = g.inverse_axes();
            let f = -g.amplitude * g.beta / 4.0;
            let dc = -2.0 * f * (acc[1] * u + acc[2] * v);
            let (sx, sy) = (g.sigma[0], g.sigma[1]);
            let grad = [
                dc.x,
                dc.y,
                -2.0 * f * acc[3],
                -2.0 * f * acc[4],
                2.0 * f * acc[5] * (sy / sx - sx / sy),
                acc[0],
                f * std::f64::consts::LN_2 * acc[6],
            ];
            Back { grad, error: if acc[8] > 0.0 { acc[7] / acc[8] } else { 0.0 } }
        })
        .collect()
}

/// One primitive's sums over its support for [`backward`]: `Σ G·e`, `Σ w·X`, `Σ w·Y`, `Σ w·X²`,
/// `Σ w·Y²`, `Σ w·XY`, `Σ G·e·q·log2 r` with `w = G·e·q/r`, then `Σ G·err` and `Σ G` for the
/// fall-off-weighted error. Run as a `pulp` operation, so the fused multiply-adds of the fast
/// transcendentals are the CPU's instructions (and the lanes its vectors) rather than the
/// software fallback a build for the baseline x86-64 would call.
struct Sums<'a> {
    p: &'a Prepared,
    pixels: &'a GridSpec,
    dl: &'a [f32],
    err: Option<&'a [f32]>,
}

impl pulp::WithSimd for Sums<'_> {
    type Output = [f64; 9];

    #[allow(
        clippy::inline_always,
        reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
    )]
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> [f64; 9] {
        let Sums { p, pixels, dl, err } = self;
        // Without an error map the error sums are skipped (`dl` stands in for the map, unread).
        match err {
            Some(err) => support_sums::<true>(p, pixels, dl, err),
            None => support_sums::<false>(p, pixels, dl, dl),
        }
    }
}

/// [`Sums`] over the support of `p`, the error sums only when `ERROR`.
#[allow(
    clippy::inline_always,
    reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
)]
#[inline(always)]
fn support_sums<const ERROR: bool>(p: &Prepared, pixels: &GridSpec, dl: &[f32], err: &[f32]) -> [f64; 9] {
    let nx = pixels.nx();
    let mut acc = [0.0f64; 9];
    let Some((j0, j1)) = p.rows(pixels) else { return acc };
    let hb = p.half_beta;
    for j in j0..=j1 {
        let Some(Span { i0, i1, x: lx, y: ly, sx, sy }) = p.span(pixels, j) else { continue };
        // Whole vectors of LANES samples widened within the row (the rasterizer's spans): read
        // in place, the lanes outside the span masked out.
        let width = (i1 - i0 + 1).next_multiple_of(LANES).min(nx);
        let lo = i0.min(nx - width);
        let (first, last) = ((i0 - lo) as i32, (i1 - lo) as i32);
        let row = j * nx + lo;
        let (dl, err) = (&dl[row..row + width], &err[row..row + width]);
        // LANES partial sums so that the loop vectorizes (a single f32 accumulator is a serial
        // dependency the compiler must keep in order).
        let mut lanes = [[0.0f32; LANES]; 9];
        let (whole, rest) = (dl.chunks_exact(LANES), err.chunks_exact(LANES));
        let (dl_tail, err_tail) = (whole.remainder(), rest.remainder());
        let span = (lx, ly, sx, sy, hb);
        for (c, (gv, ev)) in whole.zip(rest).enumerate() {
            let (gv, ev) = (gv.try_into().expect("whole vector"), ev.try_into().expect("whole vector"));
            add_lanes::<ERROR>(&mut lanes, (c * LANES) as i32 - first, (gv, ev), span, (first, last));
        }
        if !dl_tail.is_empty() {
            // A span widened to the whole row, which is not a whole number of vectors: the tail
            // padded with zeros.
            let (mut gv, mut ev) = ([0.0f32; LANES], [0.0f32; LANES]);
            gv[..dl_tail.len()].copy_from_slice(dl_tail);
            ev[..err_tail.len()].copy_from_slice(err_tail);
            let t0 = (width - dl_tail.len()) as i32 - first;
            add_lanes::<ERROR>(&mut lanes, t0, (&gv, &ev), span, (first, last));
        }
        for (a, l) in acc.iter_mut().zip(lanes) {
            *a += f64::from(l.iter().sum::<f32>());
        }
    }
    acc
}

/// Adds one vector of [`LANES`] samples to a row's partial sums (see [`Sums`]): `t0` is the
/// first lane's step from the span's start, `gv` and `ev` the samples' loss gradient and error,
/// `(lx, ly, sx, sy)` the span's local coordinates and step, `hb` the exponent β/2; lanes whose
/// step is outside `0..=last − first` add nothing. The error sums only when `ERROR`.
#[allow(
    clippy::inline_always,
    reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
)]
#[inline(always)]
fn add_lanes<const ERROR: bool>(
    lanes: &mut [[f32; LANES]; 9],
    t0: i32,
    (gv, ev): (&[f32; LANES], &[f32; LANES]),
    (lx, ly, sx, sy, hb): (f32, f32, f32, f32, f32),
    (first, last): (i32, i32),
) {
    for l in 0..LANES {
        let step = t0 + l as i32;
        let t = step as f32;
        let (x, y) = (lx + t * sx, ly + t * sy);
        let r = (x * x + y * y).max(1e-20);
        let l2 = log2(r);
        let q = exp2_signed(hb * l2);
        let inside = step >= 0 && step <= last - first;
        let e = if inside { exp_neg(-0.5 * q) } else { 0.0 };
        let ge = gv[l] * e;
        let w = ge * q / r;
        lanes[0][l] += ge;
        lanes[1][l] += w * x;
        lanes[2][l] += w * y;
        lanes[3][l] += w * x * x;
        lanes[4][l] += w * y * y;
        lanes[5][l] += w * x * y;
        lanes[6][l] += ge * q * l2;
        if ERROR {
            lanes[7][l] += e * ev[l];
            lanes[8][l] += e;
        }
    }
}

/// Regularisation (§4, after Kerbl et al. 2023): prune, then split the large and clone the small
/// primitives under the largest errors, up to the budget (5 % of it per round).
fn densify(params: &mut Vec<Param>, back: &[Back], options: &VectorizeOptions, pixels: &GridSpec) {
    let (w, h) = ((pixels.nx() - 1).max(1) as f64, (pixels.ny() - 1).max(1) as f64);
    // σ of the finest initial level (see `initialise`).
    let weight: f64 = LEVELS.iter().map(|s| 1.0 / (s * s)).sum();
    let finest_count = (options.primitives as f64 * INIT_SHARE) / (LEVELS[4] * LEVELS[4]) / weight;
    let finest = 0.5 * (w * h / finest_count.max(1.0)).sqrt();
    let mut order: Vec<usize> =
        (0..params.len()).filter(|&k| keep(&params[k].gaussian(), options, pixels, FIT_TOLERANCE)).collect();
    let kept = order.len();
    let room = options.primitives.saturating_sub(kept).min((options.primitives / 20).max(1));
    let score: Vec<f64> = match options.densify {
        Densify::Error => back.iter().map(|b| b.error).collect(),
        // Children start at 0 and old primitives sum over the whole interval: the interval is
        // the same for all that are candidates, so the sum ranks as the mean does.
        Densify::PositionalGradient => params.iter().map(|p| p.positional).collect(),
    };
    order.sort_by(|&a, &b| score[b].total_cmp(&score[a]).then(a.cmp(&b)));
    let grow: Vec<usize> = order.iter().copied().take(room).collect();
    let mut chosen = vec![false; params.len()];
    for &k in &grow {
        chosen[k] = true;
    }
    let mut alive = vec![false; params.len()];
    for &k in &order {
        alive[k] = true;
    }
    let mut next = Vec::with_capacity(kept + room);
    for (k, p) in params.iter().enumerate() {
        if !alive[k] {
            continue;
        }
        if !chosen[k] {
            next.push(Param { positional: 0.0, ..*p });
            continue;
        }
        let g = p.gaussian();
        let major = usize::from(g.sigma[1] > g.sigma[0]);
        let axis = DVec2::from_angle(g.theta + if major == 1 { std::f64::consts::FRAC_PI_2 } else { 0.0 });
        let c = DVec2::from(g.center);
        let mut sigma = g.sigma;
        let (offset, amplitude) = if g.sigma[major] > 2.0 * finest {
            // Split along the major axis, matching the first two moments: children at ±0.6σ
            // with σ × 0.8 there, amplitude 0.625 a each (the volume is kept).
            sigma[major] *= 0.8;
            (0.6 * g.sigma[major], 0.625 * g.amplitude)
        } else {
            // Clone: two halves a quarter σ apart, so they can separate.
            (0.25 * g.sigma[major], 0.5 * g.amplitude)
        };
        for side in [-1.0, 1.0] {
            let child = c + axis * offset * side;
            next.push(Param::new(child, sigma, g.theta, amplitude, g.beta, options));
        }
    }
    *params = next;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::loss::loss;

    /// Placing steps cut the tails at 10⁻², the settling fifth at the render's tolerance, and a
    /// fit that may stop at any step (a time budget, a target loss) at the render's throughout.
    #[test]
    fn tails_are_cut_short_only_while_placing_in_a_fit_that_runs_its_steps() {
        let options = VectorizeOptions { iterations: 100, ..VectorizeOptions::default() };
        const { assert!(PLACING_TOLERANCE > FIT_TOLERANCE) };
        assert_eq!(FIT_TOLERANCE, crate::DEFAULT_TOLERANCE);
        assert_eq!(step_tolerance(0, &options), PLACING_TOLERANCE);
        assert_eq!(step_tolerance(79, &options), PLACING_TOLERANCE);
        assert_eq!(step_tolerance(80, &options), FIT_TOLERANCE);
        assert_eq!(step_tolerance(99, &options), FIT_TOLERANCE);
        let timed = VectorizeOptions { time_budget: Some(Duration::from_secs(60)), ..options };
        assert_eq!(step_tolerance(0, &timed), FIT_TOLERANCE);
        let targeted = VectorizeOptions { target_loss: Some(1e-3), ..options };
        assert_eq!(step_tolerance(0, &targeted), FIT_TOLERANCE);
    }

    /// 3DGS densification: the primitive with the largest accumulated positional gradient is the
    /// one that grows, and every primitive starts the next interval's sum from zero (a sum that
    /// kept growing would rank old primitives above new ones for ever).
    #[test]
    fn positional_densification_grows_the_largest_sum_and_restarts_every_sum() {
        let options = VectorizeOptions { primitives: 3, densify: Densify::PositionalGradient, ..Default::default() };
        let pixels = GridSpec::new(64, 64, DVec2::ZERO, DVec2::ONE).expect("grid");
        let at = |x: f64, positional: f64| Param {
            positional,
            ..Param::new(DVec2::new(x, 32.0), [4.0, 4.0], 0.0, 0.5, 2.0, &options)
        };
        let mut params = vec![at(16.0, 1.0), at(48.0, 5.0)];
        let back: Vec<Back> = (0..2).map(|_| Back { grad: [0.0; 7], error: 0.0 }).collect();
        densify(&mut params, &back, &options, &pixels);
        assert_eq!(params.len(), 3, "one room left in the budget: one primitive becomes two");
        assert_eq!(params[0].x[0], 16.0, "the smaller sum stays as it was");
        assert!(
            params[1..].iter().all(|p| (p.x[0] - 48.0).abs() < 4.0 && p.x[0] != 48.0),
            "the larger sum becomes two (here a clone)"
        );
        assert!(params.iter().all(|p| p.positional == 0.0), "every sum restarts after densification");
    }

    /// The range penalty's gradient: `RANGE_WEIGHT / n` up above 2, down below 0, nothing
    /// inside (0 and 2 included).
    #[test]
    fn the_range_penalty_pushes_back_only_beyond_the_range() {
        let approx = [-0.5f32, 0.0, 1.0, 2.0, 2.5];
        let mut grad = [1.0f32; 5];
        penalize_out_of_range(&approx, &mut grad);
        let k = (RANGE_WEIGHT / 5.0) as f32;
        assert_eq!(grad, [1.0 - k, 1.0, 1.0, 1.0, 1.0 + k]);
    }

    /// Flat samples are those whose 3 × 3 neighbourhood (clipped at the edges) is equal; the
    /// flat weight pushes their error back by `weight / n` and leaves exact ones alone.
    #[test]
    fn flat_ground_is_found_and_held() {
        // 4 × 3: a flat left part (0.5) and a slope on the right.
        let target = [0.5f32, 0.5, 0.5, 0.9, 0.5, 0.5, 0.5, 1.0, 0.5, 0.5, 0.5, 1.1];
        assert_eq!(flat_samples(&target, 4, 3), vec![0, 1, 4, 5, 8, 9]);
        let approx = [0.6f32, 0.5, 0.5, 0.9, 0.4, 0.5, 0.5, 1.0, 0.5, 0.5, 0.5, 1.1];
        let mut grad = [0.0f32; 12];
        hold_flats(&approx, &target, &[0, 4, 8], FLAT_WEIGHT, &mut grad);
        let k = (FLAT_WEIGHT / 12.0) as f32;
        assert_eq!(grad, [k, 0.0, 0.0, 0.0, -k, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    }

    /// The floor is recorded when 1 % of the samples lie at the minimum, not below that.
    #[test]
    fn a_floor_needs_one_percent_at_the_minimum() {
        let grid = GridSpec::new(10, 10, DVec2::ZERO, DVec2::ONE).expect("grid");
        let dem = |at_min: usize| {
            Heightfield::from_fn_indexed(grid, |i, j| if j * 10 + i < at_min { 0.0 } else { 1.0 + i as f32 })
                .expect("dem")
        };
        assert!(lies_flat_at_minimum(&dem(1), 0.0));
        assert!(lies_flat_at_minimum(&dem(5), 0.0));
        let big = GridSpec::new(20, 10, DVec2::ZERO, DVec2::ONE).expect("grid");
        let two = Heightfield::from_fn_indexed(big, |i, j| if j * 20 + i < 2 { 0.0 } else { 5.0 }).expect("dem");
        let one = Heightfield::from_fn_indexed(big, |i, j| if j * 20 + i < 1 { 0.0 } else { 5.0 }).expect("dem");
        assert!(lies_flat_at_minimum(&two, 0.0));
        assert!(!lies_flat_at_minimum(&one, 0.0));
    }

    /// Steps that stretch a primitive along one axis and thin it along the other leave it as an
    /// unclamped Adam would until the pruning's elongation, then stop there with the area of the
    /// unclamped step and the same long axis, and the primitive stays kept.
    #[test]
    fn adam_holds_the_elongation_the_pruning_keeps() {
        let options = VectorizeOptions::default();
        let pixels = GridSpec::new(200, 200, DVec2::ZERO, DVec2::ONE).expect("grid");
        let limit = max_ln_elongation(&options);
        for long in [2, 3] {
            let mut p = Param::new(DVec2::splat(100.0), [3.0, 3.0], 0.3, 0.5, 2.0, &options);
            let mut free = p;
            let mut grad = [0.0; 7];
            (grad[long], grad[5 - long]) = (-1.0, 1.0);
            let mut clamped = 0;
            for _ in 0..400 {
                let area = p.x[2] + p.x[3];
                p.adam(&grad, &Bounds { max_ln_elongation: limit, ..bounds(&options) });
                free.adam(&grad, &bounds(&options));
                let [sx, sy] = p.gaussian().sigma;
                let (big, small) = if long == 2 { (sx, sy) } else { (sy, sx) };
                assert!(big / small <= options.max_elongation, "elongation {}", big / small);
                if (free.x[2] - free.x[3]).abs() <= limit {
                    assert_eq!(p.x, free.x, "clamped below the limit");
                } else {
                    clamped += 1;
                    assert!(big / small > 0.999 * options.max_elongation, "elongation {}", big / small);
                    // Both axes moved by the same step, in opposite senses: ln σx + ln σy unchanged.
                    assert!((p.x[2] + p.x[3] - area).abs() < 1e-12, "area changed");
                }
            }
            assert!(clamped > 100, "the clamp held {clamped} steps");
            assert!(keep(&p.gaussian(), &options, &pixels, FIT_TOLERANCE));
        }
    }

    /// The bounds of a fit on a 200 × 200 working grid, the learning rate undecayed, the
    /// elongation unlimited.
    fn bounds(options: &VectorizeOptions) -> Bounds {
        let pixels = GridSpec::new(200, 200, DVec2::ZERO, DVec2::ONE).expect("grid");
        Bounds { max_ln_elongation: f64::INFINITY, ..Bounds::new(options, &pixels) }
    }

    /// Adam's first step moves each parameter by its step size: ours moves a primitive's centre
    /// by 18.75 × the learning rate of its scale (four times as far for one four times as wide),
    /// its ln σ, θ and ln β by 5.625 × and its amplitude by 1.875 × the learning rate whatever
    /// its size; the paper's moves each parameter by the learning rate in the authors' units,
    /// whatever the primitive's size: the centre by it times half the grid's width in the
    /// middle (100 samples of 200), three quarters of that halfway to the edge, ln σ by 1.4 ×,
    /// θ 1 ×, the amplitude 2 × (their heights span 1, ours 2) and ln β 0.15 × it.
    #[test]
    fn our_steps_scale_with_the_primitive() {
        let lr = VectorizeOptions::default().learning_rate;
        let first_step = |at: f64, sigma: f64, uniform_steps: bool| -> [f64; 7] {
            let options = VectorizeOptions { uniform_steps, ..VectorizeOptions::default() };
            let mut p = Param::new(DVec2::new(at, 100.0), [sigma, sigma], 0.3, 0.5, 2.0, &options);
            let before = p.x;
            p.adam(&[1.0; 7], &bounds(&options));
            std::array::from_fn(|k| before[k] - p.x[k])
        };
        let close = |a: f64, b: f64| (a - b).abs() < 1e-9 * b.abs();
        let (small, large) = (first_step(100.0, 2.0, false), first_step(100.0, 8.0, false));
        for (k, want) in
            [(0, 18.75 * 2.0), (1, 18.75 * 2.0), (2, 5.625), (3, 5.625), (4, 5.625), (5, 1.875), (6, 5.625)]
        {
            assert!(close(small[k], want * lr), "parameter {k} moved {}", small[k]);
            let scale = if k < 2 { 4.0 } else { 1.0 };
            assert!(close(large[k], scale * small[k]), "parameter {k} moved {} and {}", small[k], large[k]);
        }
        let paper = [100.0, 100.0, 1.4, 1.4, 1.0, 2.0, 0.15];
        for sigma in [2.0, 8.0] {
            let moved = first_step(100.0, sigma, true);
            for k in 0..7 {
                assert!(close(moved[k], paper[k] * lr), "σ {sigma}: parameter {k} moved {}", moved[k]);
            }
        }
        let off_centre = first_step(150.0, 2.0, true);
        assert!(close(off_centre[0], 75.0 * lr), "moved {} at u = 0.5", off_centre[0]);
        assert!(close(off_centre[1], 100.0 * lr), "moved {} at v = 0", off_centre[1]);
    }

    /// Each option is refused just past its bound, by name and with the offending value, and
    /// taken at the bound.
    #[test]
    fn options_are_checked_at_their_bounds() {
        use crate::loss::LossWeights;
        let base = VectorizeOptions::default();
        let refused = |o: VectorizeOptions| match o.validate() {
            Err(GaussianError::InvalidOption { name, value, .. }) => Some((name, value)),
            _ => None,
        };
        let taken = [
            VectorizeOptions { primitives: MAX_PRIMITIVES, ..base.clone() },
            VectorizeOptions { resolution: 2, ..base.clone() },
            VectorizeOptions { learning_rate: 1e-300, ..base.clone() },
            VectorizeOptions { weights: LossWeights { l1: 0.5, gradient: 0.5 }, ..base.clone() },
            VectorizeOptions { max_elongation: 1.0 + 1e-9, ..base.clone() },
            VectorizeOptions { min_amplitude: 0.0, ..base.clone() },
            VectorizeOptions { beta_range: [0.5, 0.5], ..base.clone() },
            VectorizeOptions { detail_spacing: Some(1e-300), ..base.clone() },
        ];
        for o in taken {
            assert_eq!(refused(o.clone()), None, "{o:?}");
        }
        let nan = f64::NAN;
        let cases = [
            (
                VectorizeOptions { primitives: MAX_PRIMITIVES + 1, ..base.clone() },
                "primitives",
                (MAX_PRIMITIVES + 1) as f64,
            ),
            (VectorizeOptions { resolution: 1, ..base.clone() }, "resolution", 1.0),
            (VectorizeOptions { learning_rate: 0.0, ..base.clone() }, "learning_rate", 0.0),
            (VectorizeOptions { learning_rate: f64::INFINITY, ..base.clone() }, "learning_rate", f64::INFINITY),
            (VectorizeOptions { weights: LossWeights { l1: 0.6, gradient: 0.5 }, ..base.clone() }, "weights", 1.1),
            (VectorizeOptions { max_elongation: 1.0, ..base.clone() }, "max_elongation", 1.0),
            (VectorizeOptions { max_elongation: nan, ..base.clone() }, "max_elongation", nan),
            (VectorizeOptions { min_amplitude: f64::INFINITY, ..base.clone() }, "min_amplitude", f64::INFINITY),
            (VectorizeOptions { beta_range: [4.0, 2.0], ..base.clone() }, "beta_range", 2.0),
            (VectorizeOptions { beta_range: [0.4, 2.0], ..base.clone() }, "beta_range", 0.4),
            (VectorizeOptions { beta_range: [f64::INFINITY, 2.0], ..base.clone() }, "beta_range", f64::INFINITY),
            (VectorizeOptions { beta_range: [2.0, f64::INFINITY], ..base.clone() }, "beta_range", f64::INFINITY),
            (VectorizeOptions { detail_spacing: Some(0.0), ..base.clone() }, "detail_spacing", 0.0),
            (VectorizeOptions { detail_spacing: Some(f64::INFINITY), ..base.clone() }, "detail_spacing", f64::INFINITY),
        ];
        for (o, name, value) in cases {
            let got = refused(o.clone()).unwrap_or_else(|| panic!("taken: {o:?}"));
            let same = got.1 == value || (got.1.is_nan() && value.is_nan()) || (got.1 - value).abs() < 1e-12;
            assert!(got.0 == name && same, "{o:?}: refused as {got:?}, not ({name}, {value})");
        }
    }

    /// The exponent stays within the options' range, the paper's `[2, 4]` as ours.
    #[test]
    fn adam_holds_beta_within_its_range() {
        for (range, up) in [([0.6, 8.0], true), ([0.6, 8.0], false), ([2.0, 4.0], true), ([2.0, 4.0], false)] {
            let options = VectorizeOptions { beta_range: range, ..VectorizeOptions::default() };
            let mut p = Param::new(DVec2::splat(100.0), [3.0, 3.0], 0.3, 0.5, 3.0, &options);
            let mut grad = [0.0; 7];
            grad[6] = if up { -1.0 } else { 1.0 };
            for _ in 0..2000 {
                p.adam(&grad, &bounds(&options));
            }
            let want = if up { range[1] } else { range[0] };
            assert!((p.gaussian().beta - want).abs() < 1e-9, "{range:?}: β {}", p.gaussian().beta);
        }
    }

    /// Once the gradient falls tenfold, our Adam's steps regain their full size (its second
    /// moment forgets the first steps' large gradients, an e-fold every 20 steps); 150 steps
    /// later the paper's (PyTorch's β₂ = 0.999) still moves a fifth of its step.
    #[test]
    fn our_adam_forgets_the_first_steps_gradients() {
        let moved = |uniform_steps: bool| {
            let options = VectorizeOptions { uniform_steps, ..VectorizeOptions::default() };
            let mut p = Param::new(DVec2::splat(100.0), [3.0, 3.0], 0.3, 0.5, 2.0, &options);
            let mut grad = [0.0; 7];
            for k in 0..200 {
                grad[5] = if k < 50 { 1.0 } else { 0.1 };
                p.adam(&grad, &bounds(&options));
            }
            let before = p.x[5];
            p.adam(&grad, &bounds(&options));
            (before - p.x[5]) / p.step[5]
        };
        let (ours, paper) = (moved(false), moved(true));
        assert!((0.9..=1.1).contains(&ours), "ours moved {ours} of a step");
        assert!(paper > 0.0 && paper < 0.3, "the paper's moved {paper} of a step");
    }

    #[test]
    fn radial_mass_is_one_for_the_ordinary_gaussian() {
        assert!((radial_mass(2.0) - 1.0).abs() < 1e-7);
        // β = 1: ∫ r e^(−r/2) dr = 4.
        assert!((radial_mass(1.0) - 4.0).abs() < 1e-4);
    }

    /// The analytic parameter gradient against central differences of the whole loss.
    #[test]
    fn parameter_gradient_matches_finite_differences() {
        let pixels = GridSpec::new(40, 36, DVec2::ZERO, DVec2::ONE).expect("grid");
        let target: Vec<f32> = (0..40 * 36)
            .map(|k| {
                let (i, j) = ((k % 40) as f32, (k / 40) as f32);
                0.3 + 0.2 * (0.2 * i).sin() * (0.17 * j).cos()
            })
            .collect();
        let prims = vec![
            Gaussian { center: [18.0, 15.0], sigma: [7.0, 4.0], theta: 0.6, amplitude: 1.4, beta: 2.7 },
            Gaussian { center: [25.0, 22.0], sigma: [5.0, 6.5], theta: -0.3, amplitude: 0.9, beta: 1.6 },
        ];
        let weights = LossWeights::default();
        // A tolerance tight enough that the cut tail is below the differences' resolution.
        let total = |prims: &[Gaussian]| {
            let x = raster_samples(prims, &pixels, 1e-12);
            loss(&x, &target, 40, 36, &weights, false).0.total
        };
        let x = raster_samples(&prims, &pixels, 1e-12);
        let (_, dl) = loss(&x, &target, 40, 36, &weights, true);
        let err = vec![0.0; x.len()];
        let back = backward(&prims, &pixels, &dl, Some(&err), 1e-12);
        let options = VectorizeOptions::default();
        for (index, g) in prims.iter().enumerate() {
            let p = Param::new(DVec2::from(g.center), g.sigma, g.theta, g.amplitude, g.beta, &options);
            for k in 0..7 {
                let h = 1e-3;
                let (mut plus, mut minus) = (prims.clone(), prims.clone());
                let (mut pp, mut pm) = (p, p);
                pp.x[k] += h;
                pm.x[k] -= h;
                plus[index] = pp.gaussian();
                minus[index] = pm.gaussian();
                let fd = (total(&plus) - total(&minus)) / (2.0 * h);
                let an = back[index].grad[k];
                assert!(
                    (fd - an).abs() <= 0.03 * an.abs().max(fd.abs()) + 2e-5,
                    "primitive {index}, parameter {k}: analytic {an}, finite {fd}"
                );
            }
        }
    }

    /// The backward pass sums over each primitive's support only: lanes of a vector that fall
    /// before or after a row's span (a support at the row's end, a row that is not a whole
    /// number of vectors) add nothing, however large the gradient and error there, and the
    /// fall-off-weighted error is that of the support.
    #[test]
    fn backward_sums_over_the_support_only() {
        let (nx, ny) = (70, 12);
        let pixels = GridSpec::new(nx, ny, DVec2::ZERO, DVec2::ONE).expect("grid");
        let prims = [
            Gaussian { center: [20.3, 5.2], sigma: [3.0, 2.0], theta: 0.4, amplitude: 1.0, beta: 2.5 },
            Gaussian { center: [64.6, 6.1], sigma: [2.5, 3.0], theta: -0.7, amplitude: -0.5, beta: 1.4 },
        ];
        let tolerance = 1e-3;
        let position = |k: usize| DVec2::new((k % nx) as f64, (k / nx) as f64);
        let far = |k: usize| {
            prims.iter().all(|g| g.distance_squared(position(k)) > 2.0 * g.support_radius(tolerance).powi(2))
        };
        // A huge gradient and error far outside both supports; inside, the error is the column.
        let dl: Vec<f32> = (0..nx * ny).map(|k| if far(k) { 1e6 } else { 0.0 }).collect();
        let err: Vec<f32> = (0..nx * ny).map(|k| if far(k) { 1e6 } else { (k % nx) as f32 }).collect();
        let back = backward(&prims, &pixels, &dl, Some(&err), tolerance);
        for (g, b) in prims.iter().zip(&back) {
            assert!(b.grad.iter().all(|&d| d == 0.0), "{:?}", b.grad);
            let r2 = g.support_radius(tolerance).powi(2);
            let (mut weighted, mut total) = (0.0, 0.0);
            for (k, &e) in err.iter().enumerate() {
                let s = g.distance_squared(position(k));
                if s <= r2 {
                    let fall = (-0.5 * s.powf(0.5 * g.beta)).exp();
                    (weighted, total) = (weighted + fall * f64::from(e), total + fall);
                }
            }
            assert!((b.error - weighted / total).abs() < 1e-3 * b.error, "{} against {}", b.error, weighted / total);
        }
        // Without the error map, the same gradients and no error.
        let without = backward(&prims, &pixels, &dl, None, tolerance);
        for (b, w) in back.iter().zip(&without) {
            assert_eq!((b.grad, w.error), (w.grad, 0.0));
        }
    }

    /// The initialisation never places more than the budget: the levels' jittered grids round
    /// their counts up, so a small budget is cut to its most voluminous primitives.
    #[test]
    fn initialisation_keeps_within_the_budget() {
        let pixels = GridSpec::new(50, 40, DVec2::ZERO, DVec2::ONE).expect("grid");
        let target: Vec<f32> = (0..50 * 40).map(|k| 0.5 + 0.4 * ((k % 50) as f32 * 0.2).sin()).collect();
        let mut cut = 0;
        for primitives in 1..=60 {
            let options = VectorizeOptions { primitives, ..VectorizeOptions::default() };
            let params = initialise(&target, &pixels, &options);
            assert!(!params.is_empty() && params.len() <= primitives, "{} for a budget of {primitives}", params.len());
            cut += usize::from(params.len() == primitives);
        }
        // The cut is needed: many budgets are filled exactly.
        assert!(cut > 10, "{cut}");
        // The cut keeps the most voluminous, in their order.
        let all = initialise(&target, &pixels, &VectorizeOptions { primitives: 200, ..VectorizeOptions::default() });
        let volume = |p: &Param| {
            let g = p.gaussian();
            (g.amplitude * g.sigma[0] * g.sigma[1]).abs()
        };
        let kept = within_budget(all.clone(), 7);
        let mut volumes: Vec<f64> = all.iter().map(volume).collect();
        volumes.sort_by(|a, b| b.total_cmp(a));
        let smallest_kept = kept.iter().map(volume).fold(f64::INFINITY, f64::min);
        assert_eq!((kept.len(), smallest_kept), (7, volumes[6]));
        let positions: Vec<usize> =
            kept.iter().map(|k| all.iter().position(|p| p.x == k.x).expect("a kept primitive")).collect();
        assert!(positions.is_sorted(), "{positions:?}");
    }

    /// The backward pass visits exactly the rasterizer's samples: weighting each sample by the
    /// inverse of the primitive's rasterized value makes its amplitude gradient `Σ dl·g` count
    /// them, so a span cut short or run long by one sample shows (spans of every length mod 16,
    /// a row that is not a whole number of vectors).
    #[test]
    fn backward_visits_the_rasterizers_samples() {
        let (nx, ny) = (70, 40);
        let pixels = GridSpec::new(nx, ny, DVec2::ZERO, DVec2::ONE).expect("grid");
        for (k, sigma) in [3.0, 5.5, 9.0, 14.0].into_iter().enumerate() {
            let g = Gaussian {
                center: [35.2, 19.7],
                sigma: [sigma, 0.6 * sigma],
                theta: 0.3 * k as f64,
                amplitude: 1.0,
                beta: 1.7,
            };
            let raster = raster_samples(&[g], &pixels, FIT_TOLERANCE);
            let dl: Vec<f32> = raster.iter().map(|&v| if v > 0.0 { 1.0 / v } else { 0.0 }).collect();
            let count = raster.iter().filter(|&&v| v > 0.0).count() as f64;
            let back = backward(&[g], &pixels, &dl, None, FIT_TOLERANCE);
            assert!((back[0].grad[5] - count).abs() < 1e-3 * count, "{} against {count} samples", back[0].grad[5]);
        }
    }

    /// The cut ranks by volume |a|·σx·σy: a negative primitive counts by its magnitude, and a
    /// tall narrow one against a low wide one by the product.
    #[test]
    fn the_budget_keeps_the_largest_volumes() {
        let options = VectorizeOptions::default();
        let param = |amplitude: f64, sigma: f64| Param::new(DVec2::ZERO, [sigma, sigma], 0.0, amplitude, 2.0, &options);
        // Volumes 10, 9 and 16.
        let params = vec![param(10.0, 1.0), param(1.0, 3.0), param(-4.0, 2.0)];
        let kept: Vec<f64> = within_budget(params, 2).iter().map(|p| p.gaussian().amplitude).collect();
        assert_eq!(kept, [10.0, -4.0]);
    }
}
