//! From feature curves to a terrain (§4): rasterize, diffuse the elevation (guided by the slope
//! constraints) and the noise parameters, synthesise the multi-fractal detail, add.

use std::ops::ControlFlow;

use glam::DVec2;
use rayon::prelude::*;
use relief_heightfield::noise::{NoiseLattice, NoiseRow, gradient_noise};
use relief_heightfield::{GridSpec, Heightfield};
use serde::{Deserialize, Serialize};

use crate::DiffusionError;
use crate::curve::FeatureCurve;
use crate::maps::ConstraintMaps;
use crate::parameters::noise_parameters;
use crate::solver::{DiffusionProblem, SolveOptions, SolveReport};

/// Options of [`generate`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TerrainOptions {
    /// How the elevation (and the noise parameters) are solved.
    pub solve: SolveOptions,
    /// Wavelength of the first noise octave, world units (default 0: 1/16 of the larger side).
    pub noise_wavelength: f64,
    /// Octaves of the multi-fractal noise (the paper's n + 1 = 4).
    pub noise_octaves: u32,
    /// Seed of the noise.
    pub seed: u64,
}

impl Default for TerrainOptions {
    fn default() -> Self {
        Self { solve: SolveOptions::default(), noise_wavelength: 0.0, noise_octaves: 4, seed: 0 }
    }
}

/// What [`generate`] produces.
#[derive(Debug, Clone)]
pub struct FeatureTerrain {
    /// Smooth elevation plus detail.
    pub heightfield: Heightfield,
    /// The smooth elevation alone (the diffusion's solution).
    pub smooth: Heightfield,
    /// How the elevation solve went.
    pub report: SolveReport,
    /// The rasterized constraints.
    pub maps: ConstraintMaps,
}

/// Where a generation is, as [`generate_observed`] reports it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Stage {
    /// The constraints are painted; `done` of `total` windows of crossing slope bands are filled.
    Holes {
        /// Windows filled.
        done: usize,
        /// Windows in all (0 when no slope bands cross).
        total: usize,
    },
    /// The elevation solve after its start (`iteration` 0) and after `iteration` V-cycles
    /// (`BiCGStab` iterations, or Jacobi sweeps in batches of 50, as
    /// [`crate::SolveReport::iterations`] counts them).
    Elevation {
        /// Iterations so far.
        iteration: usize,
    },
    /// The noise amplitude (`field` 0) or roughness (`field` 1) solve, counted as the elevation's.
    Noise {
        /// 0: amplitude, 1: roughness.
        field: usize,
        /// Iterations so far.
        iteration: usize,
    },
}

/// Generates the terrain of `curves` on `grid`.
///
/// # Errors
/// The validation errors of the curves, [`DiffusionError::NoElevation`],
/// [`DiffusionError::GridTooSmall`], [`DiffusionError::InvalidOption`].
pub fn generate(
    curves: &[FeatureCurve],
    grid: &GridSpec,
    options: &TerrainOptions,
) -> Result<FeatureTerrain, DiffusionError> {
    generate_observed(curves, grid, options, |_| ControlFlow::Continue(()))
}

/// [`generate`], calling `observe` as it goes: after each batch of hole windows and each
/// iteration of the three solves (see [`Stage`]). [`ControlFlow::Break`] stops the generation
/// there, within one iteration: what a progress bar or a cancel button needs on a generation of
/// seconds. The result does not depend on the callback.
///
/// ```
/// use std::ops::ControlFlow;
/// use glam::DVec2;
/// use relief_diffusion_multigrid::{DiffusionError, Stage, TerrainOptions, generate_observed, presets};
/// use relief_heightfield::GridSpec;
///
/// let grid = GridSpec::new(65, 65, DVec2::ZERO, DVec2::splat(20.0))?;
/// let ridge = presets::ridge(&[DVec2::new(200.0, 640.0), DVec2::new(1080.0, 640.0)], 200.0, 600.0, 200.0, 25.0, 300.0);
/// // A cancel button pressed while the elevation is being solved.
/// let mut seen = Vec::new();
/// let stop = generate_observed(&[ridge], &grid, &TerrainOptions::default(), |stage| {
///     seen.push(stage);
///     if matches!(stage, Stage::Elevation { .. }) { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
/// });
/// assert_eq!(stop.err(), Some(DiffusionError::Cancelled));
/// assert_eq!(seen.last(), Some(&Stage::Elevation { iteration: 0 }));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// Those of [`generate`]; [`DiffusionError::Cancelled`] when `observe` breaks.
pub fn generate_observed(
    curves: &[FeatureCurve],
    grid: &GridSpec,
    options: &TerrainOptions,
    mut observe: impl FnMut(Stage) -> ControlFlow<()>,
) -> Result<FeatureTerrain, DiffusionError> {
    if !(options.noise_wavelength.is_finite() && options.noise_wavelength >= 0.0) {
        return Err(DiffusionError::InvalidOption {
            name: "noise_wavelength",
            value: options.noise_wavelength,
            reason: "must be finite and ≥ 0 (0: automatic)",
        });
    }
    if options.noise_octaves > 16 {
        return Err(DiffusionError::InvalidOption {
            name: "noise_octaves",
            value: f64::from(options.noise_octaves),
            reason: "at most 16",
        });
    }
    let span = grid.extent().size().max_element();
    if options.noise_wavelength > 0.0 && options.noise_wavelength < 1e-6 * span {
        return Err(DiffusionError::InvalidOption {
            name: "noise_wavelength",
            value: options.noise_wavelength,
            reason: "is below a millionth of the domain: the noise would alias to nothing",
        });
    }
    let maps =
        ConstraintMaps::rasterize_observed(curves, grid, &mut |done, total| observe(Stage::Holes { done, total }))?;
    let (values, report) = DiffusionProblem::elevation(&maps)?
        .solve_observed(&options.solve, &mut |iteration| observe(Stage::Elevation { iteration }))?;
    let smooth = Heightfield::from_samples(*grid, values).map_err(|_| DiffusionError::InvalidOption {
        name: "constraints",
        value: f64::NAN,
        reason: "produced a non-finite elevation",
    })?;
    let nx = grid.nx();
    let mut heightfield = smooth.clone();
    let parameters =
        noise_parameters(&maps, &options.solve, &mut |field, iteration| observe(Stage::Noise { field, iteration }))?;
    if let Some([amplitude, roughness]) = parameters {
        let size = grid.extent().size();
        let wavelength =
            if options.noise_wavelength > 0.0 { options.noise_wavelength } else { size.x.max(size.y) / 16.0 };
        let detail = Detail::new(wavelength, options.noise_octaves, options.seed, grid);
        let samples = heightfield.samples_mut();
        samples.par_chunks_mut(nx).enumerate().for_each_init(
            || RowNoise::new(nx),
            |scratch, (j, row)| {
                let line = detail.row(grid.position(0, j).y);
                let k = j * nx..(j + 1) * nx;
                let noise = line.samples(|i| grid.position(i, j).x, &roughness[k.clone()], scratch);
                for ((h, &a), &n) in row.iter_mut().zip(&amplitude[k]).zip(noise) {
                    let a = f64::from(a.max(0.0));
                    if a > 0.0 {
                        *h += (a * n) as f32;
                    }
                }
            },
        );
    }
    Ok(FeatureTerrain { heightfield, smooth, report, maps })
}

/// The multi-fractal noise of §4.3: N = A·Σₖ 2^(−k(1−R))·S(2ᵏ·p), S gradient (Perlin) noise.
#[derive(Debug, Clone)]
struct Detail {
    wavelength: f64,
    seed: u64,
    /// Per octave, its gradient lattice over the grid when that has fewer points than the grid has
    /// samples (most octaves: then each lattice corner serves many samples); else `None`, hashed.
    lattices: Vec<Option<NoiseLattice>>,
}

impl Detail {
    fn new(wavelength: f64, octaves: u32, seed: u64, grid: &GridSpec) -> Self {
        let extent = grid.extent();
        let lattices = (0..octaves)
            .map(|k| {
                let f = Self::frequency(k);
                // The same operations as `sample`, so the lattice covers every point it is asked for.
                let (lo, hi) = (extent.min / wavelength * f, extent.max / wavelength * f);
                let cells = (hi - lo).ceil() + 2.0;
                (cells.x * cells.y <= grid.len() as f64)
                    .then(|| NoiseLattice::new(lo, hi, Self::octave_seed(seed, k)))
                    .flatten()
            })
            .collect();
        Self { wavelength, seed, lattices }
    }

    fn frequency(k: u32) -> f64 {
        f64::from(1u32 << k.min(30))
    }

    fn octave_seed(seed: u64, k: u32) -> u64 {
        seed.wrapping_add(u64::from(k))
    }

    /// The noise along the line of ordinate `y` (world units), each octave's work for the line
    /// done once.
    fn row(&self, y: f64) -> DetailRow<'_> {
        let qy = y / self.wavelength;
        let octaves = (0..)
            .zip(&self.lattices)
            .map(|(k, lattice)| {
                let y = qy * Self::frequency(k);
                match lattice {
                    Some(lattice) => Octave::Stored(lattice.row(y)),
                    None => Octave::Hashed { y, seed: Self::octave_seed(self.seed, k) },
                }
            })
            .collect();
        DetailRow { wavelength: self.wavelength, octaves }
    }
}

/// One octave of [`Detail`] along a line.
enum Octave<'a> {
    /// From the octave's lattice.
    Stored(NoiseRow<'a>),
    /// Hashed: the line's ordinate in octave coordinates, and the octave's seed.
    Hashed { y: f64, seed: u64 },
}

/// [`Detail`] along the line of one ordinate, from [`Detail::row`]: the same values as sampling
/// each point on its own, bit for bit.
struct DetailRow<'a> {
    wavelength: f64,
    octaves: Vec<Octave<'a>>,
}

impl DetailRow<'_> {
    /// Σₖ 2^(−k(1−R))·S(2ᵏ p / wavelength) without the amplitude, at abscissae `x(i)` (world
    /// units) with roughness `roughness[i]` clamped to [0, 1], for every `i` of `roughness`;
    /// octave by octave, in `scratch`'s storage.
    fn samples<'s>(&self, x: impl Fn(usize) -> f64, roughness: &[f32], scratch: &'s mut RowNoise) -> &'s [f64] {
        let n = roughness.len();
        let RowNoise { qx, step, weight, sum, xs, noise } = scratch;
        for (i, &r) in roughness.iter().enumerate() {
            qx[i] = x(i) / self.wavelength;
            // 2^(−k(1−R)) as powers of one factor: one `powf` per sample rather than per octave.
            step[i] = 2f64.powf(-(1.0 - f64::from(r.clamp(0.0, 1.0))));
        }
        weight[..n].fill(1.0);
        sum[..n].fill(0.0);
        for (k, octave) in (0..).zip(&self.octaves) {
            let f = Detail::frequency(k);
            for (x, &q) in xs[..n].iter_mut().zip(&qx[..n]) {
                *x = q * f;
            }
            match octave {
                Octave::Stored(row) => row.samples(&xs[..n], &mut noise[..n]),
                Octave::Hashed { y, seed } => {
                    for (s, &x) in noise[..n].iter_mut().zip(&xs[..n]) {
                        *s = gradient_noise(DVec2::new(x, *y), *seed);
                    }
                }
            }
            for ((sum, weight), (&s, &step)) in sum[..n].iter_mut().zip(&mut weight[..n]).zip(noise.iter().zip(&*step))
            {
                *sum += *weight * s;
                *weight *= step;
            }
        }
        &sum[..n]
    }
}

/// The per-sample storage [`DetailRow::samples`] works in, for rows of up to `len` samples.
struct RowNoise {
    qx: Vec<f64>,
    step: Vec<f64>,
    weight: Vec<f64>,
    sum: Vec<f64>,
    xs: Vec<f64>,
    noise: Vec<f64>,
}

impl RowNoise {
    fn new(len: usize) -> Self {
        let v = || vec![0.0; len];
        Self { qx: v(), step: v(), weight: v(), sum: v(), xs: v(), noise: v() }
    }
}
