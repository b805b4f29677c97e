//! A bucket grid of points for nearest-neighbour queries (dart throwing, nearest higher peaks).

use glam::DVec2;
use relief_heightfield::Extent;

/// Points bucketed on a uniform grid for nearest-neighbour queries.
pub(crate) struct PointGrid {
    origin: DVec2,
    cell: f64,
    nx: usize,
    ny: usize,
    buckets: Vec<Vec<u32>>,
}

impl PointGrid {
    /// Buckets over `extent` sized for about `expected` points.
    pub(crate) fn new(extent: &Extent, expected: usize) -> Self {
        let size = extent.size().max(DVec2::splat(1e-9));
        let cell = (size.x * size.y / expected.max(1) as f64).sqrt().max(size.max_element() / 1024.0);
        let nx = (size.x / cell).ceil() as usize + 1;
        let ny = (size.y / cell).ceil() as usize + 1;
        Self { origin: extent.min, cell, nx, ny, buckets: vec![Vec::new(); nx * ny] }
    }

    fn cell_of(&self, p: DVec2) -> (usize, usize) {
        let g = ((p - self.origin) / self.cell).floor();
        (g.x.clamp(0.0, (self.nx - 1) as f64) as usize, g.y.clamp(0.0, (self.ny - 1) as f64) as usize)
    }

    /// Stores point `k` at `p`.
    pub(crate) fn insert(&mut self, k: u32, p: DVec2) {
        let (i, j) = self.cell_of(p);
        self.buckets[j * self.nx + i].push(k);
    }

    /// The nearest stored point to `p` (the lowest index among equals) and its distance;
    /// `points` holds every stored point's position by index.
    pub(crate) fn nearest(&self, p: DVec2, points: &[DVec2]) -> Option<(u32, f64)> {
        let (ci, cj) = self.cell_of(p);
        let mut best: Option<(u32, f64)> = None;
        let max_ring = self.nx.max(self.ny);
        for ring in 0..=max_ring {
            // Every point in ring r is at least (r − 1)·cell away.
            if let Some((_, d)) = best
                && d < (ring as f64 - 1.0) * self.cell
            {
                break;
            }
            let (i0, i1) = (ci as isize - ring as isize, ci as isize + ring as isize);
            let (j0, j1) = (cj as isize - ring as isize, cj as isize + ring as isize);
            for j in j0..=j1 {
                if j < 0 || j >= self.ny as isize {
                    continue;
                }
                let step = if j == j0 || j == j1 { 1 } else { (i1 - i0).max(1) };
                let mut i = i0;
                while i <= i1 {
                    if i >= 0 && i < self.nx as isize {
                        for &k in &self.buckets[j as usize * self.nx + i as usize] {
                            let d = points[k as usize].distance(p);
                            if best.is_none_or(|(bk, bd)| d < bd || (d == bd && k < bk)) {
                                best = Some((k, d));
                            }
                        }
                    }
                    i += step;
                }
            }
        }
        best
    }
}
