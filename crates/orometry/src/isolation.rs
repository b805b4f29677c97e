//! Isolation (§4.1): the distance from a peak to the nearest strictly higher sample, found by a
//! best-first search down a pyramid of block maxima: a block whose maximum is not above the peak
//! is never opened, so a search visits O(log N) blocks plus those around the answer instead of
//! scanning rings of cells.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use relief_heightfield::Heightfield;
use serde::{Deserialize, Serialize};

/// Where a peak's nearest higher ground is.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Isolation {
    /// Ground distance, metres (grid units for grids in metres; degrees are converted at the
    /// peak's latitude).
    pub distance: f64,
    /// Direction, degrees clockwise from north (+y).
    pub azimuth: f64,
    /// World position `[x, y]` of the nearest higher sample.
    pub to: [f64; 2],
}

/// Block maxima: level 0 is the DEM (no-data as −∞), each level halves both sides.
pub(crate) struct Pyramid {
    levels: Vec<(usize, usize, Vec<f32>)>,
}

impl Pyramid {
    pub(crate) fn new(dem: &Heightfield) -> Self {
        let (nx, ny) = (dem.nx(), dem.ny());
        let base: Vec<f32> = dem.samples().iter().map(|&v| if v.is_nan() { f32::NEG_INFINITY } else { v }).collect();
        let mut levels = vec![(nx, ny, base)];
        while let Some((w, h, below)) = levels.last().filter(|(w, h, _)| *w > 1 || *h > 1) {
            let (w2, h2) = (w.div_ceil(2), h.div_ceil(2));
            let mut up = vec![f32::NEG_INFINITY; w2 * h2];
            for j in 0..*h {
                for i in 0..*w {
                    let v = below[j * w + i];
                    let slot = &mut up[(j / 2) * w2 + i / 2];
                    if v > *slot {
                        *slot = v;
                    }
                }
            }
            levels.push((w2, h2, up));
        }
        Self { levels }
    }
}

#[derive(PartialEq)]
struct Block {
    d2: f64,
    level: usize,
    bi: usize,
    bj: usize,
}

impl Eq for Block {}

impl PartialOrd for Block {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Block {
    // Min-heap on distance; ties: finer level, then row, then column (deterministic).
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .d2
            .total_cmp(&self.d2)
            .then_with(|| other.level.cmp(&self.level))
            .then_with(|| (other.bj, other.bi).cmp(&(self.bj, self.bi)))
    }
}

/// Half-width of the window scanned before the pyramid search.
const LOCAL: usize = 6;

fn found(dem: &Heightfield, cell: [usize; 2], i: usize, j: usize, d2: f64) -> Isolation {
    let grid = dem.grid();
    let to = grid.position(i, j);
    let v = (to - grid.position(cell[0], cell[1])) * grid.metres_per_unit(cell[1]);
    Isolation { distance: d2.sqrt(), azimuth: v.x.atan2(v.y).to_degrees().rem_euclid(360.0), to: to.to_array() }
}

/// The isolation of the sample `cell` at height `h`; `None` when nothing on the map is higher.
pub(crate) fn isolation(pyramid: &Pyramid, dem: &Heightfield, cell: [usize; 2], h: f32) -> Option<Isolation> {
    let grid = dem.grid();
    let m = grid.cell_size_m(cell[1]);
    let (pi, pj) = (cell[0] as f64, cell[1] as f64);
    let box_d2 = |level: usize, bi: usize, bj: usize| {
        let (nx, ny) = (pyramid.levels[0].0, pyramid.levels[0].1);
        let span = 1usize << level;
        let (i0, j0) = ((bi * span) as f64, (bj * span) as f64);
        let (i1, j1) = (((bi + 1) * span).min(nx) as f64 - 1.0, ((bj + 1) * span).min(ny) as f64 - 1.0);
        let dx = (i0 - pi).max(pi - i1).max(0.0) * m.x;
        let dy = (j0 - pj).max(pj - j1).max(0.0) * m.y;
        dx * dx + dy * dy
    };
    // Most minor peaks have higher ground within a few cells: scan that window first. A hit at
    // distance d is final when no cell outside the window can be nearer (d ≤ the window's reach).
    let (nx, ny, base) = (&pyramid.levels[0].0, &pyramid.levels[0].1, &pyramid.levels[0].2);
    let reach = LOCAL as f64 * m.x.min(m.y);
    let mut best: Option<(f64, usize, usize)> = None;
    for j in cell[1].saturating_sub(LOCAL)..=(cell[1] + LOCAL).min(ny - 1) {
        for i in cell[0].saturating_sub(LOCAL)..=(cell[0] + LOCAL).min(nx - 1) {
            if base[j * nx + i] > h {
                let (dx, dy) = ((i as f64 - pi) * m.x, (j as f64 - pj) * m.y);
                let d2 = dx * dx + dy * dy;
                if best.is_none_or(|(b, bj, bi)| d2 < b || (d2 == b && (j, i) < (bj, bi))) {
                    best = Some((d2, j, i));
                }
            }
        }
    }
    if let Some((d2, j, i)) = best
        && d2.sqrt() <= reach
    {
        return Some(found(dem, cell, i, j, d2));
    }
    let top = pyramid.levels.len() - 1;
    let mut heap = BinaryHeap::new();
    heap.push(Block { d2: box_d2(top, 0, 0), level: top, bi: 0, bj: 0 });
    while let Some(Block { d2, level, bi, bj }) = heap.pop() {
        let (w, _, values) = &pyramid.levels[level];
        if values[bj * w + bi] <= h {
            continue;
        }
        if level == 0 {
            return Some(found(dem, cell, bi, bj, d2));
        }
        let (cw, ch, _) = &pyramid.levels[level - 1];
        for (ci, cj) in [(2 * bi, 2 * bj), (2 * bi + 1, 2 * bj), (2 * bi, 2 * bj + 1), (2 * bi + 1, 2 * bj + 1)] {
            if ci < *cw && cj < *ch {
                heap.push(Block { d2: box_d2(level - 1, ci, cj), level: level - 1, bi: ci, bj: cj });
            }
        }
    }
    None
}
