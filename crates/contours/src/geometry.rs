//! Segment queries for contour sets: candidate pairs for intersection tests and neighbourhood
//! queries, on top of the exact predicates and segment index of `relief-poisson-sampling`.

use glam::DVec2;
use relief_tin::poisson_sampling::{Rect, SegmentIndex as Grid, orient};

pub(crate) use relief_tin::poisson_sampling::segments_touch;

/// A segment index sized for `segments` (about two segments per cell).
pub(crate) struct SegmentIndex {
    grid: Grid,
}

impl SegmentIndex {
    pub(crate) fn new(segments: &[[DVec2; 2]]) -> Self {
        let bounds = segments.iter().fold(Rect::bounding(&[]), |b, s| b.union(&Rect::bounding(s)));
        let total: f64 = segments.iter().map(|[a, b]| a.distance(*b)).sum();
        let cell = if segments.is_empty() { 1.0 } else { (2.0 * total / segments.len() as f64).max(f64::MIN_POSITIVE) };
        let bounds = if bounds.is_valid() {
            bounds
        } else {
            Rect::new(bounds.min.min(DVec2::ZERO), bounds.min.min(DVec2::ZERO) + DVec2::ONE)
        };
        Self { grid: Grid::new(segments, bounds, cell, 4 * segments.len() + 64) }
    }

    /// Every pair `(a, b)`, `a < b`, of segments sharing a cell, each pair once.
    pub(crate) fn pairs(&self) -> Vec<(usize, usize)> {
        let mut pairs: Vec<(usize, usize)> = self
            .grid
            .cells()
            .flat_map(|cell| {
                cell.iter()
                    .enumerate()
                    .flat_map(move |(i, &a)| cell[i + 1..].iter().map(move |&b| (a.min(b) as usize, a.max(b) as usize)))
            })
            .filter(|(a, b)| a != b)
            .collect();
        pairs.sort_unstable();
        pairs.dedup();
        pairs
    }
}

/// A uniform grid of axis-aligned boxes: each box is listed in every cell it overlaps.
pub(crate) struct BoxIndex {
    origin: DVec2,
    inv_cell: f64,
    w: usize,
    h: usize,
    offsets: Vec<u32>,
    items: Vec<u32>,
}

impl BoxIndex {
    /// Indexes `boxes` (`[min, max]` corners) with cells of about `cell`, at most ~`4·len` cells.
    pub(crate) fn new(boxes: &[[DVec2; 2]], cell: f64) -> Self {
        let lo = boxes.iter().fold(DVec2::INFINITY, |m, b| m.min(b[0]));
        let hi = boxes.iter().fold(DVec2::NEG_INFINITY, |m, b| m.max(b[1]));
        let size = (hi - lo).max(DVec2::splat(f64::MIN_POSITIVE));
        let mut cell = cell.max(f64::MIN_POSITIVE);
        let max_cells = (4 * boxes.len()).max(64) as f64;
        while (size.x / cell).ceil() * (size.y / cell).ceil() > max_cells {
            cell *= 1.5;
        }
        let (w, h) = (((size.x / cell).ceil() as usize).max(1), ((size.y / cell).ceil() as usize).max(1));
        let mut index = Self { origin: lo, inv_cell: 1.0 / cell, w, h, offsets: vec![0; w * h + 1], items: Vec::new() };
        if boxes.is_empty() {
            return index;
        }
        for b in boxes {
            let (c0, c1) = index.span(b[0], b[1]);
            for r in c0.1..=c1.1 {
                for c in c0.0..=c1.0 {
                    index.offsets[r * w + c + 1] += 1;
                }
            }
        }
        for k in 0..w * h {
            index.offsets[k + 1] += index.offsets[k];
        }
        let mut fill = index.offsets.clone();
        index.items = vec![0; index.offsets[w * h] as usize];
        for (id, b) in boxes.iter().enumerate() {
            let (c0, c1) = index.span(b[0], b[1]);
            for r in c0.1..=c1.1 {
                for c in c0.0..=c1.0 {
                    index.items[fill[r * w + c] as usize] = id as u32;
                    fill[r * w + c] += 1;
                }
            }
        }
        index
    }

    /// Cells `(column, row)` of the corners of `[lo, hi]`, clamped to the grid.
    fn span(&self, lo: DVec2, hi: DVec2) -> ((usize, usize), (usize, usize)) {
        let cell = |p: DVec2| {
            let g = ((p - self.origin) * self.inv_cell).floor();
            ((g.x.max(0.0) as usize).min(self.w - 1), (g.y.max(0.0) as usize).min(self.h - 1))
        };
        (cell(lo), cell(hi))
    }

    /// Calls `f` for the boxes in cells overlapping `[lo, hi]` (possibly more than once) until it
    /// returns true; returns whether it did.
    pub(crate) fn any_near(&self, lo: DVec2, hi: DVec2, mut f: impl FnMut(u32) -> bool) -> bool {
        if self.items.is_empty() {
            return false;
        }
        let (c0, c1) = self.span(lo, hi);
        for r in c0.1..=c1.1 {
            for c in c0.0..=c1.0 {
                let k = r * self.w + c;
                if self.items[self.offsets[k] as usize..self.offsets[k + 1] as usize].iter().any(|&id| f(id)) {
                    return true;
                }
            }
        }
        false
    }
}

/// For consecutive segments `p–q` and `r–s` sharing one endpoint: whether they overlap beyond it
/// (collinear and folding back).
pub(crate) fn folds_back(p: DVec2, q: DVec2, r: DVec2, s: DVec2) -> bool {
    let (shared, a, b) = if q == r {
        (q, p, s)
    } else if s == p {
        (p, q, r)
    } else if p == r {
        (p, q, s)
    } else if q == s {
        (q, p, r)
    } else {
        return segments_touch(p, q, r, s);
    };
    orient(a, shared, b) == 0.0 && (a - shared).dot(b - shared) > 0.0
}
