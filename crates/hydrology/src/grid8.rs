//! The 8-neighbourhood of a grid cell with ground distances in metres (per row, so geographic
//! grids measure true distances at each latitude).

use relief_heightfield::GridSpec;

/// Neighbour directions `(di, dj)`: east first, counter-clockwise.
pub(crate) const DIRS: [(i32, i32); 8] = [(1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1)];

/// Grid shape and per-row metric.
pub(crate) struct Grid8 {
    pub(crate) nx: usize,
    pub(crate) ny: usize,
    /// Per row: distance to the neighbour in each of [`DIRS`], metres.
    dist: Vec<[f64; 8]>,
    /// Per row: the area one cell stands for, m².
    area: Vec<f64>,
}

impl Grid8 {
    pub(crate) fn new(grid: &GridSpec) -> Self {
        let (dist, area) = (0..grid.ny())
            .map(|j| {
                let c = grid.cell_size_m(j);
                let d = c.x.hypot(c.y);
                ([c.x, d, c.y, d, c.x, d, c.y, d], grid.cell_area_m2(j))
            })
            .unzip();
        Self { nx: grid.nx(), ny: grid.ny(), dist, area }
    }

    pub(crate) fn len(&self) -> usize {
        self.nx * self.ny
    }

    /// Area of cell `k`, m².
    #[inline]
    pub(crate) fn area(&self, k: usize) -> f64 {
        self.area[k / self.nx]
    }

    /// Per cell of `z`, the area it stands for in m² (0 on no-data): what drainage starts from.
    pub(crate) fn cell_areas(&self, z: &[f32]) -> Vec<f64> {
        z.iter().enumerate().map(|(k, v)| if v.is_nan() { 0.0 } else { self.area(k) }).collect()
    }

    /// Calls `f(neighbour, direction, distance)` for each in-grid neighbour of `k`.
    #[inline]
    pub(crate) fn each(&self, k: usize, mut f: impl FnMut(usize, usize, f64)) {
        let (i, j) = ((k % self.nx) as i64, (k / self.nx) as i64);
        let dist = &self.dist[j as usize];
        if i > 0 && j > 0 && i + 1 < self.nx as i64 && j + 1 < self.ny as i64 {
            let s = self.nx as isize;
            let offsets = [1, s + 1, s, s - 1, -1, -s - 1, -s, -s + 1];
            for (d, o) in offsets.into_iter().enumerate() {
                f(k.wrapping_add_signed(o), d, dist[d]);
            }
            return;
        }
        for (d, &(di, dj)) in DIRS.iter().enumerate() {
            let (a, b) = (i + i64::from(di), j + i64::from(dj));
            if a >= 0 && b >= 0 && a < self.nx as i64 && b < self.ny as i64 {
                f(b as usize * self.nx + a as usize, d, dist[d]);
            }
        }
    }

    /// Distance from `k` to its neighbour in direction `dir`, measured in `k`'s row.
    #[inline]
    pub(crate) fn dist(&self, k: usize, dir: usize) -> f64 {
        self.dist[k / self.nx][dir]
    }
}
