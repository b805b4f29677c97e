use std::ops::Range;

use glam::DVec2;
use rayon::prelude::*;
use relief_heightfield::{GridSpec, Heightfield};

use crate::{Tin, TinError};

/// Grid rows per parallel work item. Fixed, so the partition never depends on the thread count
/// (the result does not either: see [`Tin::rasterize`]).
const BAND_ROWS: usize = 16;

/// How far beyond a triangle, in cells, a sample still takes its plane: a millionth, enough for
/// the rounding of `origin + i·cell` (a grid built on the hull's extent may put its last sample
/// an ulp outside it) and far too little to reach past a real gap.
const SLACK: f64 = 1e-6;

impl Tin {
    /// Rasterizes per-node `values` onto `grid` by linear interpolation in each triangle, in
    /// parallel over bands of rows.
    ///
    /// Samples outside the mesh are no-data (those within a millionth of a cell of it, the grid's
    /// rounding of a hull on its edge, take the nearest triangle's plane); a NaN node value makes its triangles no-data. Each
    /// triangle is scan-converted row by row; where two triangles meet, both compute the crossing
    /// of their shared edge with the same formula on the same inputs, so no sample between them is
    /// missed. A sample covered by several triangles (on a shared edge) takes the value of the
    /// highest-index triangle, in every band, so the result is bit-identical to
    /// [`Tin::rasterize_serial`] whatever the number of threads.
    ///
    /// # Errors
    /// [`TinError::ValueCountMismatch`] or [`TinError::NonFiniteValue`] (±∞).
    pub fn rasterize(&self, values: &[f64], grid: &GridSpec) -> Result<Heightfield, TinError> {
        self.check_raster_values(values)?;
        let nx = grid.nx();
        let bands = grid.ny().div_ceil(BAND_ROWS);
        // Bin triangles by the bands their (slightly widened) row range touches, in index order.
        let spans: Vec<Range<usize>> = (0..self.num_triangles() as u32).map(|t| self.row_span(t, grid)).collect();
        let mut offsets = vec![0u32; bands + 1];
        for span in spans.iter().filter(|s| !s.is_empty()) {
            for b in span.start / BAND_ROWS..=(span.end - 1) / BAND_ROWS {
                offsets[b + 1] += 1;
            }
        }
        for b in 0..bands {
            offsets[b + 1] += offsets[b];
        }
        let mut fill = offsets.clone();
        let mut binned = vec![0u32; offsets[bands] as usize];
        for (t, span) in spans.iter().enumerate().filter(|(_, s)| !s.is_empty()) {
            for b in span.start / BAND_ROWS..=(span.end - 1) / BAND_ROWS {
                binned[fill[b] as usize] = t as u32;
                fill[b] += 1;
            }
        }
        let mut samples = vec![f32::NAN; grid.len()];
        samples.par_chunks_mut(BAND_ROWS * nx).enumerate().for_each(|(b, out)| {
            let rows = b * BAND_ROWS..(b * BAND_ROWS + out.len() / nx);
            for &t in &binned[offsets[b] as usize..offsets[b + 1] as usize] {
                self.scan_triangle(t, values, grid, rows.clone(), out);
            }
        });
        Heightfield::from_samples(*grid, samples).map_err(|e| TinError::Invariant(e.to_string()))
    }

    /// [`Tin::rasterize`] on one thread, triangle by triangle over the whole grid: the reference
    /// the parallel version must reproduce bit for bit.
    ///
    /// # Errors
    /// As [`Tin::rasterize`].
    pub fn rasterize_serial(&self, values: &[f64], grid: &GridSpec) -> Result<Heightfield, TinError> {
        self.check_raster_values(values)?;
        let mut samples = vec![f32::NAN; grid.len()];
        for t in 0..self.num_triangles() as u32 {
            self.scan_triangle(t, values, grid, 0..grid.ny(), &mut samples);
        }
        Heightfield::from_samples(*grid, samples).map_err(|e| TinError::Invariant(e.to_string()))
    }

    fn check_raster_values(&self, values: &[f64]) -> Result<(), TinError> {
        self.check_values(values)?;
        match values.iter().position(|v| v.is_infinite()) {
            Some(node) => Err(TinError::NonFiniteValue { node, value: values[node] }),
            None => Ok(()),
        }
    }

    /// Grid rows that may hold samples of triangle `t`, widened by one row each way so rounding
    /// in the row bound never drops a row; the exact test happens per row.
    fn row_span(&self, t: u32, grid: &GridSpec) -> Range<usize> {
        let pts = self.triangle_points(t);
        let (lo, hi) = pts.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p.y), hi.max(p.y)));
        let (oy, dy) = (grid.origin().y, grid.cell_size().y);
        let j0 = ((lo - oy) / dy).ceil() - 1.0;
        let j1 = ((hi - oy) / dy).floor() + 1.0;
        let last = (grid.ny() - 1) as f64;
        if j1 < 0.0 || j0 > last {
            return 0..0;
        }
        (j0.max(0.0) as usize)..(j1.min(last) as usize + 1)
    }

    /// Writes triangle `t`'s samples on grid rows `rows` into `out`, which holds rows
    /// `rows.start..` of the grid.
    fn scan_triangle(&self, t: u32, values: &[f64], grid: &GridSpec, rows: Range<usize>, out: &mut [f32]) {
        let tri = self.triangles()[t as usize];
        let pts = tri.map(|v| self.points()[v as usize]);
        let h = tri.map(|v| values[v as usize]);
        // The plane through the three corners: h = h0 + g·(p − p0).
        let (d1, d2) = (pts[1] - pts[0], pts[2] - pts[0]);
        let det = d1.perp_dot(d2);
        let (e1, e2) = (h[1] - h[0], h[2] - h[0]);
        let g = DVec2::new(e1 * d2.y - e2 * d1.y, d1.x * e2 - d2.x * e1) / det;
        let span = self.row_span(t, grid);
        let (first_row, nx) = (rows.start, grid.nx());
        let (ox, dx) = (grid.origin().x, grid.cell_size().x);
        let (y_lo, y_hi) =
            pts.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p.y), hi.max(p.y)));
        let slack = grid.cell_size() * SLACK;
        for j in span.start.max(rows.start)..span.end.min(rows.end) {
            let y = grid.position(0, j).y;
            // A row a rounding error beyond the triangle's corner (the grid's last row, whose
            // `origin + (n − 1)·cell` may overshoot the extent the hull was built on) meets it there.
            let y_on = y.clamp(y_lo, y_hi);
            if (y - y_on).abs() > slack.y {
                continue;
            }
            let Some((xl, xr)) = row_interval(tri, pts, y_on) else { continue };
            let i0 = ((xl - slack.x - ox) / dx).ceil().max(0.0);
            let i1 = ((xr + slack.x - ox) / dx).floor().min((nx - 1) as f64);
            if i1 < i0 {
                continue;
            }
            let (i0, i1) = (i0 as usize, i1 as usize);
            let row = &mut out[(j - first_row) * nx..(j - first_row + 1) * nx];
            for (i, sample) in row.iter_mut().enumerate().take(i1 + 1).skip(i0) {
                let p = DVec2::new(grid.position(i, j).x, y);
                *sample = (h[0] + g.dot(p - pts[0])) as f32;
            }
        }
    }
}

/// The x-interval where the horizontal line `y` meets the triangle, or `None`.
///
/// Each edge's crossing is computed from its endpoints ordered by node index, so the two triangles
/// sharing an edge get bit-identical crossings and leave no gap between them; a line through a
/// corner returns the corner's exact x.
fn row_interval(tri: [u32; 3], pts: [DVec2; 3], y: f64) -> Option<(f64, f64)> {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for k in 0..3 {
        let (ka, kb) = if tri[k] < tri[(k + 1) % 3] { (k, (k + 1) % 3) } else { ((k + 1) % 3, k) };
        let (a, b) = (pts[ka], pts[kb]);
        if y < a.y.min(b.y) || y > a.y.max(b.y) {
            continue;
        }
        let xs = if a.y == b.y {
            [a.x, b.x]
        } else if y == a.y {
            [a.x; 2]
        } else if y == b.y {
            [b.x; 2]
        } else {
            [a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y); 2]
        };
        for x in xs {
            lo = lo.min(x);
            hi = hi.max(x);
        }
    }
    (lo <= hi).then_some((lo, hi))
}
