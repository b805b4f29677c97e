//! The vectorization loss (§4) and its gradient with respect to every sample of the rasterized
//! approximation: `ℓ = α₁·ℓ₁ + α₂·ℓ_grad + (1 − α₁ − α₂)·(1 − SSIM)`.
//!
//! The paper's second term is LPIPS, a distance between VGG features. It needs pre-trained
//! network weights that a terrain library cannot ship or reproduce, so it is replaced here by a
//! gradient-domain ℓ₁ (the mean absolute difference of the slopes): like LPIPS it weighs ridges,
//! valleys and breaks of slope that a plain ℓ₁ under-counts, and it has an exact, cheap gradient.
//! Slopes are measured per 1/100 of the grid's longer side, so the term does not change with the
//! fitting resolution.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// SSIM's constants `a = 0.01²`, `b = 0.03²`, as the paper states them (§4).
const C1: f64 = 0.01 * 0.01;
const C2: f64 = 0.03 * 0.03;
/// SSIM window: uniform over 7 × 7 samples (scikit-image's default; the 11-tap Gaussian of
/// Wang et al. 2004 costs twice as much per step for the same role in the loss).
const RADIUS: usize = 3;

/// The weights `α₁` (ℓ₁) and `α₂` (gradient ℓ₁); SSIM gets `1 − α₁ − α₂`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LossWeights {
    /// `α₁`, default 0.5 (the paper's).
    pub l1: f64,
    /// `α₂`, default 0.25 (the paper's weight for LPIPS, which this term replaces).
    pub gradient: f64,
}

impl Default for LossWeights {
    fn default() -> Self {
        Self { l1: 0.5, gradient: 0.25 }
    }
}

impl LossWeights {
    /// The SSIM weight `1 − α₁ − α₂`.
    pub fn ssim(&self) -> f64 {
        1.0 - self.l1 - self.gradient
    }
}

/// The loss terms of one evaluation, in normalized elevation (the DEM mapped to `[0, 2]`, the
/// span of the `[−1, 1]` the paper's §4 normalizes to). The authors' code measures Table 3 with
/// the relief spanning `[0, 1]`, so its ℓ₁ compares with half of `l1` here (see
/// [`VectorizeReport::l1_of_relief`](crate::VectorizeReport::l1_of_relief)).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct LossTerms {
    /// Mean absolute error `ℓ₁`.
    pub l1: f64,
    /// Mean absolute slope error `ℓ_grad` (slopes per 1/100 of the longer side).
    pub gradient: f64,
    /// `1 − mean SSIM` over the 7 × 7 windows that fit in the grid (0 on grids under 7 samples).
    pub ssim: f64,
    /// The weighted total `ℓ`.
    pub total: f64,
}

const TAPS: usize = 2 * RADIUS + 1;

/// Valid-mode 7 × 7 box mean of an `nx × ny` field into `out`: `(nx − 6) × (ny − 6)` outputs;
/// `rows` is scratch.
fn filter_valid(f: &[f32], nx: usize, ny: usize, rows: &mut Vec<f32>, out: &mut Vec<f32>) {
    let w = 1.0 / TAPS as f32;
    let (ox, oy) = (nx - 2 * RADIUS, ny - 2 * RADIUS);
    sized(rows, ox * ny);
    rows.par_chunks_mut(ox).enumerate().for_each(|(j, out)| {
        let src = &f[j * nx..(j + 1) * nx];
        out.fill(0.0);
        for k in 0..TAPS {
            for (o, s) in out.iter_mut().zip(&src[k..]) {
                *o += w * s;
            }
        }
    });
    sized(out, ox * oy);
    out.par_chunks_mut(ox).enumerate().for_each(|(j, o)| {
        o.fill(0.0);
        for k in 0..TAPS {
            let src = &rows[(j + k) * ox..(j + k + 1) * ox];
            for (a, b) in o.iter_mut().zip(src) {
                *a += w * b;
            }
        }
    });
}

/// The adjoint of [`filter_valid`]: scatters a `(nx − 6) × (ny − 6)` field back onto `nx × ny`
/// in `out`; `rows` is scratch.
fn filter_adjoint(g: &[f32], nx: usize, ny: usize, rows: &mut Vec<f32>, out: &mut Vec<f32>) {
    let w = 1.0 / TAPS as f32;
    let (ox, oy) = (nx - 2 * RADIUS, ny - 2 * RADIUS);
    // Columns first (adjoint of the second pass), then rows.
    sized(rows, ox * ny);
    rows.par_chunks_mut(ox).enumerate().for_each(|(j, out)| {
        out.fill(0.0);
        for k in 0..TAPS {
            // Output row j0 = j − k contributed to input row j.
            if let Some(j0) = j.checked_sub(k).filter(|&j0| j0 < oy) {
                for (a, b) in out.iter_mut().zip(&g[j0 * ox..(j0 + 1) * ox]) {
                    *a += w * b;
                }
            }
        }
    });
    sized(out, nx * ny);
    out.par_chunks_mut(nx).enumerate().for_each(|(j, o)| {
        let src = &rows[j * ox..(j + 1) * ox];
        o.fill(0.0);
        for k in 0..TAPS {
            for (a, s) in o[k..].iter_mut().zip(src) {
                *a += w * s;
            }
        }
    });
}

/// `v` resized to `len`, reusing its allocation: its values are stale, for a caller that
/// writes every one (in parallel, where a fresh `vec![0; len]` or a `clear` and `resize` would
/// write them once more on one thread).
fn sized<T: Copy + Default>(v: &mut Vec<T>, len: usize) {
    v.resize(len, T::default());
}

/// Samples per parallel task in the loss's sample-wise passes (a fixed split, so a
/// sum over the tasks adds the same partial sums in the same order for any thread count).
const TASK: usize = 1 << 14;

/// `out[k] = a[k]·b[k]`, reusing `out`'s allocation.
fn product(a: &[f32], b: &[f32], out: &mut Vec<f32>) {
    sized(out, a.len());
    out.par_chunks_mut(TASK).zip(a.par_chunks(TASK).zip(b.par_chunks(TASK))).for_each(|(o, (a, b))| {
        for (o, (p, q)) in o.iter_mut().zip(a.iter().zip(b)) {
            *o = p * q;
        }
    });
}

/// The loss of `x` (the approximation) against `y` (the target), both `nx × ny` row-major, and
/// with `want_gradient` its derivative with respect to every sample of `x` (else an empty
/// vector).
#[cfg(test)]
pub(crate) fn loss(
    x: &[f32],
    y: &[f32],
    nx: usize,
    ny: usize,
    weights: &LossWeights,
    want_gradient: bool,
) -> (LossTerms, Vec<f32>) {
    let mut grad = Vec::new();
    let terms = Loss::new(y, nx, ny).evaluate(x, weights, want_gradient.then_some(&mut grad));
    (terms, grad)
}

/// The loss against one target, evaluated again and again (every step of a fit): the target's
/// own SSIM statistics are computed once, and every buffer is kept between evaluations, so a
/// step allocates nothing (with glibc's allocator, handing a fit's large buffers back to the
/// system each step and faulting them in again cost a quarter of its time).
pub(crate) struct Loss<'a> {
    y: &'a [f32],
    nx: usize,
    ny: usize,
    /// The target's 7 × 7 means and means of squares (empty on grids too small for SSIM).
    my: Vec<f32>,
    eyy: Vec<f32>,
    scratch: Scratch,
}

/// The buffers of one evaluation.
#[derive(Default)]
struct Scratch {
    e: Vec<f64>,
    grad: Vec<f64>,
    product: Vec<f32>,
    rows: Vec<f32>,
    mx: Vec<f32>,
    exx: Vec<f32>,
    exy: Vec<f32>,
    dm: Vec<f32>,
    dp: Vec<f32>,
    dq: Vec<f32>,
    gm: Vec<f32>,
    gp: Vec<f32>,
    gq: Vec<f32>,
}

impl<'a> Loss<'a> {
    /// The loss against `y`, an `nx × ny` row-major target.
    pub(crate) fn new(y: &'a [f32], nx: usize, ny: usize) -> Self {
        let mut scratch = Scratch::default();
        let (mut my, mut eyy) = (Vec::new(), Vec::new());
        if has_ssim(nx, ny) {
            filter_valid(y, nx, ny, &mut scratch.rows, &mut my);
            product(y, y, &mut scratch.product);
            filter_valid(&scratch.product, nx, ny, &mut scratch.rows, &mut eyy);
        }
        Self { y, nx, ny, my, eyy, scratch }
    }

    /// The loss of `x`, and with `grad` its derivative with respect to every sample of `x`
    /// written there.
    pub(crate) fn evaluate(&mut self, x: &[f32], weights: &LossWeights, grad: Option<&mut Vec<f32>>) -> LossTerms {
        let (nx, ny, y) = (self.nx, self.ny, self.y);
        let n = (nx * ny) as f64;
        let want_gradient = grad.is_some();
        let sc = &mut self.scratch;
        sized(&mut sc.e, nx * ny);
        let parts: Vec<f64> =
            sc.e.par_chunks_mut(TASK)
                .zip(x.par_chunks(TASK).zip(y.par_chunks(TASK)))
                .map(|(e, (x, y))| {
                    let mut sum = 0.0;
                    for (e, (a, b)) in e.iter_mut().zip(x.iter().zip(y)) {
                        *e = f64::from(*a) - f64::from(*b);
                        sum += e.abs();
                    }
                    sum
                })
                .collect();
        let l1 = parts.iter().sum::<f64>() / n;
        let e = &sc.e;
        sized(&mut sc.grad, if want_gradient { nx * ny } else { 0 });
        if want_gradient {
            // Written as `0 + …`, the bits a zeroed gradient would have after the addition.
            let k = weights.l1 / n;
            sc.grad.par_chunks_mut(TASK).zip(e.par_chunks(TASK)).for_each(|(g, e)| {
                for (g, e) in g.iter_mut().zip(e) {
                    *g = 0.0 + k * e.signum() * f64::from(u8::from(*e != 0.0));
                }
            });
        }

        // Slope differences per 1/100 of the longer side; rows in parallel, each writing only
        // its own gradient row, row sums added in order.
        let scale = (nx.max(ny) - 1).max(1) as f64 / 100.0;
        let sign = |t: f64| if t == 0.0 { 0.0 } else { t.signum() };
        let row_sum = |j: usize| -> f64 {
            let row = &e[j * nx..(j + 1) * nx];
            let mut sum: f64 = row.windows(2).map(|p| (p[1] - p[0]).abs()).sum();
            if j + 1 < ny {
                sum += row.iter().zip(&e[(j + 1) * nx..(j + 2) * nx]).map(|(a, b)| (b - a).abs()).sum::<f64>();
            }
            sum
        };
        let gsum: f64 = (0..ny).into_par_iter().map(row_sum).collect::<Vec<f64>>().iter().sum();
        if want_gradient {
            let k = weights.gradient * scale / n;
            sc.grad.par_chunks_mut(nx).enumerate().for_each(|(j, g)| {
                let row = &e[j * nx..(j + 1) * nx];
                for i in 0..nx {
                    let mut d = 0.0;
                    if i > 0 {
                        d += sign(row[i] - row[i - 1]);
                    }
                    if i + 1 < nx {
                        d -= sign(row[i + 1] - row[i]);
                    }
                    if j > 0 {
                        d += sign(row[i] - e[(j - 1) * nx + i]);
                    }
                    if j + 1 < ny {
                        d -= sign(e[(j + 1) * nx + i] - row[i]);
                    }
                    g[i] += k * d;
                }
            });
        }
        let gradient = scale * gsum / n;

        let ssim = if has_ssim(nx, ny) { self.ssim_term(x, weights, want_gradient) } else { 0.0 };
        let total = weights.l1 * l1 + weights.gradient * gradient + weights.ssim() * ssim;
        if let Some(out) = grad {
            sized(out, nx * ny);
            out.par_chunks_mut(TASK).zip(self.scratch.grad.par_chunks(TASK)).for_each(|(o, g)| {
                for (o, g) in o.iter_mut().zip(g) {
                    *o = *g as f32;
                }
            });
        }
        LossTerms { l1, gradient, ssim, total }
    }

    /// `1 − mean SSIM` over the valid windows; with `want_gradient`, adds `weights.ssim() ×`
    /// its gradient to the scratch gradient.
    fn ssim_term(&mut self, x: &[f32], weights: &LossWeights, want_gradient: bool) -> f64 {
        let (nx, ny, y) = (self.nx, self.ny, self.y);
        let (my, eyy) = (&self.my, &self.eyy);
        let sc = &mut self.scratch;
        filter_valid(x, nx, ny, &mut sc.rows, &mut sc.mx);
        product(x, x, &mut sc.product);
        filter_valid(&sc.product, nx, ny, &mut sc.rows, &mut sc.exx);
        product(x, y, &mut sc.product);
        filter_valid(&sc.product, nx, ny, &mut sc.rows, &mut sc.exy);
        let (mx, exx, exy) = (&sc.mx, &sc.exx, &sc.exy);
        let windows = mx.len();
        let count = windows as f64;
        for d in [&mut sc.dm, &mut sc.dp, &mut sc.dq] {
            sized(d, windows);
        }
        // d(1 − S)/d(μx, E[x²], E[xy]) per window, over the window count.
        let f = -weights.ssim() / count;
        let parts: Vec<f64> = (sc.dm.par_chunks_mut(TASK).zip(sc.dp.par_chunks_mut(TASK)))
            .zip(sc.dq.par_chunks_mut(TASK))
            .enumerate()
            .map(|(t, ((dm, dp), dq))| {
                let mut sum = 0.0;
                for (j, k) in (t * TASK..).take(dm.len()).enumerate() {
                    let (ux, uy) = (f64::from(mx[k]), f64::from(my[k]));
                    let a1 = 2.0 * ux * uy + C1;
                    let a2 = 2.0 * (f64::from(exy[k]) - ux * uy) + C2;
                    let b1 = ux * ux + uy * uy + C1;
                    let b2 = (f64::from(exx[k]) - ux * ux) + (f64::from(eyy[k]) - uy * uy) + C2;
                    let s = a1 * a2 / (b1 * b2);
                    sum += s;
                    dm[j] = (f * s * (2.0 * uy / a1 - 2.0 * uy / a2 - 2.0 * ux / b1 + 2.0 * ux / b2)) as f32;
                    dp[j] = (f * (-s / b2)) as f32;
                    dq[j] = (f * (2.0 * s / a2)) as f32;
                }
                sum
            })
            .collect();
        if want_gradient {
            filter_adjoint(&sc.dm, nx, ny, &mut sc.rows, &mut sc.gm);
            filter_adjoint(&sc.dp, nx, ny, &mut sc.rows, &mut sc.gp);
            filter_adjoint(&sc.dq, nx, ny, &mut sc.rows, &mut sc.gq);
            let (gm, gp, gq) = (&sc.gm, &sc.gp, &sc.gq);
            sc.grad.par_chunks_mut(TASK).enumerate().for_each(|(t, g)| {
                for (g, k) in g.iter_mut().zip(t * TASK..) {
                    *g += f64::from(gm[k] + 2.0 * x[k] * gp[k] + y[k] * gq[k]);
                }
            });
        }
        1.0 - parts.iter().sum::<f64>() / count
    }
}

/// Whether an `nx × ny` grid holds a 7 × 7 SSIM window.
fn has_ssim(nx: usize, ny: usize) -> bool {
    nx > 2 * RADIUS && ny > 2 * RADIUS
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(nx: usize, ny: usize, seed: f64) -> Vec<f32> {
        (0..nx * ny)
            .map(|k| {
                let (i, j) = ((k % nx) as f64, (k / nx) as f64);
                (0.8 + 0.5 * (0.31 * i + seed).sin() * (0.23 * j - seed).cos() + 0.01 * i) as f32
            })
            .collect()
    }

    /// SSIM needs one whole 7 × 7 window: it counts from 7 × 7 on, and is 0 on grids narrower
    /// or shorter than that.
    #[test]
    fn ssim_counts_from_one_whole_window() {
        let weights = LossWeights::default();
        for (nx, ny, counts) in [(7, 7, true), (20, 7, true), (6, 6, false), (20, 6, false), (6, 20, false)] {
            let (x, y) = (field(nx, ny, 0.3), field(nx, ny, 1.7));
            let (t, g) = loss(&x, &y, nx, ny, &weights, true);
            assert_eq!(t.ssim > 0.0, counts, "{nx} × {ny}: SSIM term {}", t.ssim);
            assert!(t.ssim.is_finite() && g.iter().all(|v| v.is_finite()), "{nx} × {ny}");
        }
    }

    #[test]
    fn identical_fields_have_zero_loss() {
        let y = field(20, 17, 0.3);
        let (t, _) = loss(&y, &y, 20, 17, &LossWeights::default(), false);
        assert_eq!(t.l1, 0.0);
        assert_eq!(t.gradient, 0.0);
        assert!(t.ssim.abs() < 1e-12, "{}", t.ssim);
        assert!(t.total.abs() < 1e-12);
        // ℓ₁ has no slope at an exact sample: its gradient is 0 there, not a sign.
        let (_, g) = loss(&y, &y, 20, 17, &LossWeights { l1: 1.0, gradient: 0.0 }, true);
        assert!(g.iter().all(|&v| v == 0.0), "{:?}", g.iter().find(|v| **v != 0.0));
    }

    /// The central difference of the whole loss at sample `k` of `x`, with a step of 10⁻².
    fn central_difference(x: &[f32], y: &[f32], nx: usize, ny: usize, weights: &LossWeights, k: usize) -> f64 {
        let h = 1e-2f32;
        let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
        xp[k] += h;
        xm[k] -= h;
        let total = |x: &[f32]| loss(x, y, nx, ny, weights, false).0.total;
        (total(&xp) - total(&xm)) / (2.0 * f64::from(h))
    }

    #[test]
    fn sample_gradient_matches_finite_differences() {
        let (nx, ny) = (19, 16);
        let y = field(nx, ny, 0.3);
        // Far from y everywhere, so ℓ₁'s kinks are not crossed by the differences.
        let x: Vec<f32> = field(nx, ny, 1.1).iter().map(|v| v + 3.0).collect();
        let weights = LossWeights { l1: 0.3, gradient: 0.2 };
        let (_, g) = loss(&x, &y, nx, ny, &weights, true);
        for k in [0, 7, nx * 5 + 6, nx * 8 + 9, nx * ny - 1] {
            let fd = central_difference(&x, &y, nx, ny, &weights, k);
            let an = f64::from(g[k]);
            // The SSIM windows are summed in f32.
            assert!((fd - an).abs() <= 1e-2 * an.abs().max(1e-3), "sample {k}: analytic {an}, finite {fd}");
        }
    }

    /// A grid of more than two parallel tasks: every task's samples and windows get their own
    /// errors and gradient (a task reading another's would fail the differences past the
    /// first), and ℓ₁ is the mean over them all.
    #[test]
    fn every_task_gets_its_own_samples() {
        let (nx, ny) = (200, 200);
        assert!(nx * ny > 2 * TASK && (nx - 6) * (ny - 6) > 2 * TASK);
        let y = field(nx, ny, 0.3);
        let x: Vec<f32> = field(nx, ny, 1.1).iter().map(|v| v + 3.0).collect();
        // No slope term: its kinks (slopes of the error crossing 0) would blur the differences.
        let weights = LossWeights { l1: 0.3, gradient: 0.0 };
        let (terms, g) = loss(&x, &y, nx, ny, &weights, true);
        let n = (nx * ny) as f64;
        let direct: f64 = x.iter().zip(&y).map(|(a, b)| (f64::from(*a) - f64::from(*b)).abs()).sum::<f64>() / n;
        assert!((terms.l1 - direct).abs() <= 1e-12 * direct, "ℓ₁ {} against {direct}", terms.l1);
        for k in [TASK + 5, TASK + 3 * nx + 17, 2 * TASK + 300, nx * ny - nx * 4 - 9] {
            let fd = central_difference(&x, &y, nx, ny, &weights, k);
            let an = f64::from(g[k]);
            assert!((fd - an).abs() <= 1e-2 * an.abs(), "sample {k}: analytic {an}, finite {fd}");
        }
    }
}
