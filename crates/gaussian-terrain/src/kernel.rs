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
        let a = self.u.x * self.u.x + self.v.x * self.v.x;
        let bq = dy * (self.u.x * self.u.y + self.v.x * self.v.y);
        let c = dy * dy * (self.u.y * self.u.y + self.v.y * self.v.y) - self.r2;
        let disc = bq * bq - a * c;
        if disc < 0.0 {
            return None;
        }
        let root = disc.sqrt();
        let (x0, x1) = (self.center.x + (-bq - root) / a, self.center.x + (-bq + root) / a);
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
    let (nx, ny) = (grid.nx(), grid.ny());
    let prepared: Vec<Prepared> = primitives.iter().map(|g| Prepared::new(g, tolerance)).collect();
    // Bin by band: primitive indices in order, so every sample sums them in order.
    let bands = ny.div_ceil(BAND);
    let spans: Vec<Option<(usize, usize)>> = prepared.iter().map(|p| p.rows(grid)).collect();
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
    let mut members = vec![0u32; start[bands]];
    for (k, (j0, j1)) in spans.iter().enumerate().filter_map(|(k, s)| s.map(|s| (k, s))) {
        for b in j0 / BAND..=j1 / BAND {
            members[fill[b]] = k as u32;
            fill[b] += 1;
        }
    }
    let mut samples = vec![0.0f32; grid.len()];
    samples.par_chunks_mut(nx * BAND).enumerate().for_each(|(b, band)| {
        for &k in &members[start[b]..start[b + 1]] {
            let p = &prepared[k as usize];
            // Binned primitives always have rows.
            let Some((j0, j1)) = spans[k as usize] else { continue };
            let rows = j0.max(b * BAND)..=j1.min(b * BAND + BAND - 1);
            for j in rows {
                let r = j - b * BAND;
                add_span(p, grid, j, &mut band[r * nx..(r + 1) * nx]);
            }
        }
    });
    samples
}

/// Adds primitive `p` along grid row `j` over the samples inside its support.
#[inline]
fn add_span(p: &Prepared, grid: &GridSpec, j: usize, row: &mut [f32]) {
    let Some(Span { i0, i1, x: lx, y: ly, sx, sy }) = p.span(grid, j) else { return };
    let amp = p.amplitude;
    let out = &mut row[i0..=i1];
    if p.ordinary {
        for (k, o) in out.iter_mut().enumerate() {
            let t = k as i32 as f32;
            let (x, y) = (lx + t * sx, ly + t * sy);
            *o += amp * exp_neg(-0.5 * (x * x + y * y));
        }
    } else {
        let hb = p.half_beta;
        for (k, o) in out.iter_mut().enumerate() {
            let t = k as i32 as f32;
            let (x, y) = (lx + t * sx, ly + t * sy);
            *o += amp * falloff(x * x + y * y, hb);
        }
    }
}
