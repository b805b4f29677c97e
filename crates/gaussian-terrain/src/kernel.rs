//! The rasterizer's kernel (§6.1): primitives binned by the rows their support covers (a loose
//! grid along y, bands of 16 rows), bands evaluated in parallel, each sample summing the
//! primitives over it in index order. Every band is computed on its own, so the bytes do not
//! depend on the thread count. [`crate::rasterize`], the detail layers and the vectorizer's fit
//! all sum primitives through it.

use glam::DVec2;
use rayon::prelude::*;
use relief_heightfield::GridSpec;

use crate::Gaussian;
use crate::fastmath::{exp_neg, falloff};

/// Rows per band of the binning.
const BAND: usize = 16;

/// A primitive ready to evaluate: inverse axes, support, f32 amplitude and exponent.
pub(crate) struct Prepared {
    center: DVec2,
    u: DVec2,
    v: DVec2,
    /// Squared support radius, `d` units.
    r2: f64,
    pub(crate) amplitude: f32,
    pub(crate) half_beta: f32,
    ordinary: bool,
    lo: DVec2,
    hi: DVec2,
    /// `d²` along a row is `a·x'² + 2b·dy·x' + c·dy²` (`x'`, `dy` from the centre): `a`,
    /// `1/a`, `b`, `c`.
    a: f64,
    inv_a: f64,
    b: f64,
    c: f64,
}

impl Prepared {
    pub(crate) fn new(g: &Gaussian, tolerance: f64) -> Self {
        let (u, v) = g.inverse_axes();
        let r = g.support_radius(tolerance);
        let (lo, hi) = g.bounds(tolerance);
        Prepared {
            center: DVec2::from(g.center),
            u,
            v,
            r2: r * r,
            amplitude: g.amplitude as f32,
            half_beta: (0.5 * g.beta) as f32,
            ordinary: g.beta == 2.0,
            lo,
            hi,
            a: u.x * u.x + v.x * v.x,
            inv_a: 1.0 / (u.x * u.x + v.x * v.x),
            b: u.x * u.y + v.x * v.y,
            c: u.y * u.y + v.y * v.y,
        }
    }

    /// The grid rows `j0..=j1` the support reaches, if any.
    pub(crate) fn rows(&self, grid: &GridSpec) -> Option<(usize, usize)> {
        let (nx, ny) = (grid.nx(), grid.ny());
        let (a, b) = (grid.grid_coords(self.lo), grid.grid_coords(self.hi));
        if b.x < 0.0 || a.x > (nx - 1) as f64 || b.y < 0.0 || a.y > (ny - 1) as f64 {
            return None;
        }
        let (j0, j1) = (a.y.ceil().max(0.0) as usize, b.y.floor().min((ny - 1) as f64));
        (j1 >= j0 as f64).then_some((j0, j1 as usize))
    }

    /// The samples of row `j` inside the support: `i0..=i1`, with the local coordinates at `i0`
    /// and their step per sample (f32: they are a few σ at most, so f32 holds them to 1e-7).
    #[inline]
    pub(crate) fn span(&self, grid: &GridSpec, j: usize) -> Option<Span> {
        let origin = grid.origin();
        let cell = grid.cell_size();
        let y = origin.y + j as f64 * cell.y;
        let dy = y - self.center.y;
        // d² along the row is A·x'² + 2B·x' + C (x' = x − centre.x); inside where it is below r².
        let bq = dy * self.b;
        let c = dy * dy * self.c - self.r2;
        let disc = bq * bq - self.a * c;
        if disc < 0.0 {
            return None;
        }
        let root = disc.sqrt();
        let (x0, x1) = (self.center.x + (-bq - root) * self.inv_a, self.center.x + (-bq + root) * self.inv_a);
        let last = (grid.nx() - 1) as f64;
        let (g0, g1) = (((x0 - origin.x) / cell.x).ceil().max(0.0), ((x1 - origin.x) / cell.x).floor().min(last));
        if g1 < g0 {
            return None;
        }
        let (i0, i1) = (g0 as usize, g1 as usize);
        let d = DVec2::new(origin.x + i0 as f64 * cell.x, y) - self.center;
        Some(Span {
            i0,
            i1,
            x: d.dot(self.u) as f32,
            y: d.dot(self.v) as f32,
            sx: (cell.x * self.u.x) as f32,
            sy: (cell.x * self.v.x) as f32,
        })
    }
}

/// One row's stretch of a primitive's support: samples `i0..=i1`; the local coordinates of
/// sample `i0 + k` are `(x + k·sx, y + k·sy)`.
#[derive(Clone, Copy)]
pub(crate) struct Span {
    pub(crate) i0: usize,
    pub(crate) i1: usize,
    pub(crate) x: f32,
    pub(crate) y: f32,
    pub(crate) sx: f32,
    pub(crate) sy: f32,
}

/// The truncated sum of `primitives` at every sample of `grid` (no validation: callers check),
/// binned by bands of rows, bands in parallel, primitives summed in order.
pub(crate) fn raster_samples(primitives: &[Gaussian], grid: &GridSpec, tolerance: f64) -> Vec<f32> {
    raster_samples_on(pulp::Arch::new(), primitives, grid, tolerance)
}

/// [`raster_samples`] on the instruction set `arch` (tests compare the vector build with
/// `pulp::Arch::Scalar`).
fn raster_samples_on(arch: pulp::Arch, primitives: &[Gaussian], grid: &GridSpec, tolerance: f64) -> Vec<f32> {
    let (nx, ny) = (grid.nx(), grid.ny());
    let prepared: Vec<Prepared> = primitives.par_iter().map(|g| Prepared::new(g, tolerance)).collect();
    // Bin by band: primitive indices in order, so every sample sums them in order.
    let bands = ny.div_ceil(BAND);
    let spans: Vec<Option<(usize, usize)>> = prepared.par_iter().map(|p| p.rows(grid)).collect();
    let mut start = vec![0usize; bands + 1];
    for &(j0, j1) in spans.iter().flatten() {
        for b in j0 / BAND..=j1 / BAND {
            start[b + 1] += 1;
        }
    }
    for b in 0..bands {
        start[b + 1] += start[b];
    }
    let mut fill = start.clone();
    let mut members = vec![Member { index: 0, j0: 0, j1: 0 }; start[bands]];
    for (k, (j0, j1)) in spans.iter().enumerate().filter_map(|(k, s)| s.map(|s| (k, s))) {
        for b in j0 / BAND..=j1 / BAND {
            members[fill[b]] = Member { index: k as u32, j0: j0 as u32, j1: j1 as u32 };
            fill[b] += 1;
        }
    }
    let mut samples = vec![0.0f32; grid.len()];
    samples.par_chunks_mut(nx * BAND).enumerate().for_each(|(b, band)| {
        let members = &members[start[b]..start[b + 1]];
        arch.dispatch(Band { b, samples: band, members, prepared: &prepared, grid });
    });
    samples
}

/// A primitive in a band's bin, with the grid rows it covers (kept beside the index so that a
/// band reads them in order rather than from a table indexed at random).
#[derive(Clone, Copy)]
struct Member {
    index: u32,
    j0: u32,
    j1: u32,
}

/// One band's work as a `pulp` operation: dispatched to the widest vector instructions the CPU
/// has (AVX-512 or AVX2 where present), so the loops along rows use them. The bytes are those of
/// the plain build: the loops only run side by side what the plain build runs one by one, Rust
/// never fuses `a·b + c` on its own, and the explicit `mul_add`s are fused on both builds.
struct Band<'a> {
    b: usize,
    samples: &'a mut [f32],
    members: &'a [Member],
    prepared: &'a [Prepared],
    grid: &'a GridSpec,
}

impl pulp::WithSimd for Band<'_> {
    type Output = ();

    #[allow(
        clippy::inline_always,
        reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
    )]
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let Band { b, samples: band, members, prepared, grid } = self;
        let nx = grid.nx();
        for m in members {
            let p = &prepared[m.index as usize];
            let rows = (m.j0 as usize).max(b * BAND)..=(m.j1 as usize).min(b * BAND + BAND - 1);
            // The rows' spans first, then the samples of each: the spans' square roots and
            // roundings run back to back instead of each behind a row loop's last branch (this
            // took 5-8 % off the 1024²/60k raster on 2026-12-03).
            let mut spans: [Option<Span>; BAND] = Default::default();
            for j in rows.clone() {
                spans[j - b * BAND] = p.span(grid, j);
            }
            for j in rows {
                let r = j - b * BAND;
                if let Some(span) = spans[r] {
                    add_span(p, span, &mut band[r * nx..(r + 1) * nx], S::F32_LANES);
                }
            }
        }
    }
}

/// Adds primitive `p` along one grid row, over the samples of its `span` there. The loop runs
/// over whole vectors of `lanes` samples (the dispatched register's f32 count: 16 with AVX-512,
/// 8 with AVX2; widened within the row, so short spans need no scalar remainder); samples
/// outside the span keep their bits exactly, so the width changes the speed, never the sums.
#[allow(
    clippy::inline_always,
    reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
)]
#[inline(always)]
fn add_span(p: &Prepared, span: Span, row: &mut [f32], lanes: usize) {
    let Span { i0, i1, x: lx, y: ly, sx, sy } = span;
    let amp = p.amplitude;
    let width = (i1 - i0 + 1).next_multiple_of(lanes).min(row.len());
    let lo = i0.min(row.len() - width);
    let out = &mut row[lo..lo + width];
    // Local coordinates step from sample i0; a sample k of `out` is i0 + (k − shift).
    let (first, last) = ((i0 - lo) as i32, (i1 - lo) as i32);
    if p.ordinary {
        for (k, o) in out.iter_mut().enumerate() {
            let k = k as i32;
            let t = (k - first) as f32;
            let (x, y) = (lx + t * sx, ly + t * sy);
            let v = *o + amp * exp_neg(-0.5 * (x * x + y * y));
            *o = if k >= first && k <= last { v } else { *o };
        }
    } else {
        let hb = p.half_beta;
        for (k, o) in out.iter_mut().enumerate() {
            let k = k as i32;
            let t = (k - first) as f32;
            let (x, y) = (lx + t * sx, ly + t * sy);
            let v = *o + amp * falloff(x * x + y * y, hb);
            *o = if k >= first && k <= last { v } else { *o };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The vector build (AVX-512 or AVX2 where the CPU has it) gives the bits of the plain one:
    /// the loops only run side by side, and `mul_add` is fused on both.
    #[test]
    fn vector_and_scalar_builds_agree_bit_for_bit() {
        let primitives: Vec<Gaussian> = (0..300)
            .map(|k| {
                let t = f64::from(k);
                Gaussian {
                    center: [(t * 37.0) % 100.0, (t * 61.0) % 100.0],
                    sigma: [1.0 + (t * 0.7) % 6.0, 0.5 + (t * 0.3) % 4.0],
                    theta: t * 0.37,
                    amplitude: if k % 3 == 0 { -5.0 } else { 10.0 + t * 0.01 },
                    beta: [2.0, 1.3, 3.7, 0.8][k as usize % 4],
                }
            })
            .collect();
        let extent = relief_heightfield::Extent::new(DVec2::ZERO, DVec2::splat(100.0));
        let grid = GridSpec::from_extent(203, 157, extent).unwrap();
        let fast = raster_samples(&primitives, &grid, 1e-3);
        let plain = raster_samples_on(pulp::Arch::Scalar, &primitives, &grid, 1e-3);
        assert!(fast.iter().zip(&plain).all(|(a, b)| a.to_bits() == b.to_bits()));
        assert!(fast.iter().any(|v| *v != 0.0));
    }
}
