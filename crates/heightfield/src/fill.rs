//! Depression filling by Priority-Flood+ε (Barnes, Lehman & Mulla 2014): the minimal raise that
//! makes every cell drain to an outlet along a strictly descending path (or, without ε, a
//! non-ascending one).

use crate::Heightfield;

/// A monotone priority queue keyed by `u32` (Ahuja et al.'s radix heap): O(1) push and amortised
/// O(log C) pop, valid because Priority-Flood never pushes a key below the last one popped.
/// Ties pop in a deterministic order (the order of the bucket vectors).
struct RadixHeap {
    last: u32,
    buckets: [Vec<(u32, u32)>; 33],
}

impl RadixHeap {
    fn new() -> Self {
        Self { last: 0, buckets: std::array::from_fn(|_| Vec::new()) }
    }

    fn bucket(&self, key: u32) -> usize {
        (32 - (key ^ self.last).leading_zeros()) as usize
    }

    fn push(&mut self, key: u32, value: u32) {
        debug_assert!(key >= self.last, "radix heap keys must not decrease");
        let b = self.bucket(key);
        self.buckets[b].push((key, value));
    }

    fn pop(&mut self) -> Option<(u32, u32)> {
        if self.buckets[0].is_empty() {
            let i = (1..33).find(|&i| !self.buckets[i].is_empty())?;
            let moved = std::mem::take(&mut self.buckets[i]);
            self.last = moved.iter().map(|e| e.0).min()?;
            for e in moved {
                let b = self.bucket(e.0);
                self.buckets[b].push(e);
            }
        }
        self.buckets[0].pop()
    }
}

/// Maps f32 to u32 preserving order (NaN excluded).
fn key(v: f32) -> u32 {
    let b = v.to_bits();
    if b & 0x8000_0000 != 0 { !b } else { b | 0x8000_0000 }
}

const NEIGHBOURS: [(i64, i64); 8] = [(-1, 0), (1, 0), (0, -1), (0, 1), (-1, -1), (1, 1), (-1, 1), (1, -1)];

/// Where water leaves the grid and how flats are treated by [`fill_depressions_with`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FillRules {
    /// Cells on the grid border are outlets (water leaves the map there).
    pub border_drains: bool,
    /// Cells next to no-data are outlets (no-data is sea); otherwise no-data is a wall.
    pub no_data_drains: bool,
    /// Priority-Flood+ε: raise filled cells and flats by one f32 step per cell so every cell gets
    /// a *strictly* descending path (what flow routing needs). Without it a depression is raised
    /// exactly to its spill height and flats are left flat (a non-ascending path suffices).
    pub epsilon: bool,
}

impl Default for FillRules {
    /// Border and no-data drain, ε on: what [`fill_depressions`] uses.
    fn default() -> Self {
        Self { border_drains: true, no_data_drains: true, epsilon: true }
    }
}

/// Fills every depression of `hf` so each valid cell has a strictly descending 8-connected path to
/// an outlet: the grid border, a cell next to no-data, or a cell where `outlet(i, j)` is true
/// (sea, a lake meant to stay, a marked crater). A filled cell is raised to its spill height plus
/// the smallest f32 step per cell along the way (the "+ε" of Priority-Flood+ε), so flats drain too.
/// Returns the number of raised cells. [`fill_depressions_with`] chooses other [`FillRules`].
pub fn fill_depressions(hf: &mut Heightfield, outlet: impl Fn(usize, usize) -> bool) -> usize {
    fill_depressions_with(hf, FillRules::default(), outlet)
}

/// [`fill_depressions`] under explicit [`FillRules`]. Cells that drain to no outlet at all (e.g.
/// with `border_drains` off and no outlet marked) are left as they are.
///
/// Cells that already have a descending path to an outlet are never raised by Priority-Flood, so
/// an O(N) breadth-first search uphill from the outlets finds them first; the priority queue (a
/// radix heap: the flood pops keys in non-decreasing order) then only sees the cells of actual
/// depressions. A nearly drained raster costs little more than one pass.
pub fn fill_depressions_with(hf: &mut Heightfield, rules: FillRules, outlet: impl Fn(usize, usize) -> bool) -> usize {
    let cells = Neighbourhood::new(hf.nx(), hf.ny());
    let z = hf.samples_mut();
    let mut drained = outlets(z, &cells, rules, outlet);
    // Zhou, Sun & Fu's (2016) refinement of Priority-Flood: a cell the flood reaches above the
    // flood level keeps its height, and so does everything strictly uphill of it (water there
    // runs down through it), so that whole slope is settled by a plain depth-first climb. Only a
    // settled cell that still borders unsettled ground no higher than itself enters the heap.
    // The outlets are settled first; on a drained raster that is one pass and the heap stays
    // empty. The heap starts at key 0, below every key, so it needs no sorted seeding.
    let mut heap = RadixHeap::new();
    let mut settler = Settler::new(rules.epsilon);
    for k in 0..z.len() {
        if drained[k] && !z[k].is_nan() {
            settler.settle(&cells, z, k, &mut drained, &mut heap);
        }
    }
    flood(z, &cells, rules.epsilon, &mut drained, &mut heap, &mut settler)
}

/// The 8-neighbourhood of a cell on an `nx × ny` grid: interior cells reach their neighbours by
/// fixed offsets, border cells go the slow way with bounds checks.
struct Neighbourhood {
    nx: usize,
    ny: usize,
    offsets: [isize; 8],
}

impl Neighbourhood {
    fn new(nx: usize, ny: usize) -> Self {
        let stride = nx as isize;
        Self { nx, ny, offsets: [-1, 1, -stride, stride, -stride - 1, -stride + 1, stride - 1, stride + 1] }
    }

    /// Whether cell `k` is off the grid border.
    #[inline]
    fn interior(&self, k: usize) -> bool {
        let (i, j) = (k % self.nx, k / self.nx);
        i > 0 && j > 0 && i + 1 < self.nx && j + 1 < self.ny
    }

    /// Writes the neighbours of cell `k` to the front of `out` and returns how many there are.
    #[inline]
    fn of(&self, k: usize, out: &mut [usize; 8]) -> usize {
        if self.interior(k) {
            for (o, d) in out.iter_mut().zip(self.offsets) {
                *o = k.wrapping_add_signed(d);
            }
            return 8;
        }
        let (nx, ny) = (self.nx, self.ny);
        let (i, j) = ((k % nx) as i64, (k / nx) as i64);
        let mut n = 0;
        for (di, dj) in NEIGHBOURS {
            let (a, b) = (i + di, j + dj);
            if a >= 0 && b >= 0 && a < nx as i64 && b < ny as i64 {
                out[n] = b as usize * nx + a as usize;
                n += 1;
            }
        }
        n
    }
}

/// The cells that never change, as the initial `drained` flags: no-data, and the outlets the
/// rules and `outlet(i, j)` name.
fn outlets(z: &[f32], cells: &Neighbourhood, rules: FillRules, outlet: impl Fn(usize, usize) -> bool) -> Vec<bool> {
    let has_nan = z.iter().any(|v| v.is_nan());
    let mut nb = [0usize; 8];
    (0..z.len())
        .map(|k| {
            let (i, j) = (k % cells.nx, k / cells.nx);
            z[k].is_nan()
                || (rules.border_drains && !cells.interior(k))
                || outlet(i, j)
                || (rules.no_data_drains && has_nan && {
                    let c = cells.of(k, &mut nb);
                    nb[..c].iter().any(|&w| z[w].is_nan())
                })
        })
        .collect()
}

/// The depth-first climb of Zhou et al.'s refinement, with its scratch stacks kept between calls
/// so the flood allocates nothing per cell.
struct Settler {
    /// Without ε, equal heights count as uphill: flats drain through a settled cell unchanged.
    epsilon: bool,
    climb: Vec<usize>,
    climbed: Vec<usize>,
    nb: [usize; 8],
}

impl Settler {
    fn new(epsilon: bool) -> Self {
        Self { epsilon, climb: Vec::new(), climbed: Vec::new(), nb: [0; 8] }
    }

    /// Settles `start` and everything uphill of it, then pushes the settled cells that still
    /// border unsettled ground onto the heap.
    fn settle(&mut self, cells: &Neighbourhood, z: &[f32], start: usize, drained: &mut [bool], heap: &mut RadixHeap) {
        let epsilon = self.epsilon;
        let uphill = |zw: f32, zu: f32| zw > zu || (!epsilon && zw == zu);
        self.climb.push(start);
        while let Some(u) = self.climb.pop() {
            self.climbed.push(u);
            let c = cells.of(u, &mut self.nb);
            for &v in &self.nb[..c] {
                if !drained[v] && uphill(z[v], z[u]) {
                    drained[v] = true;
                    self.climb.push(v);
                }
            }
        }
        // Only once the climb is done: a lower neighbour may have been climbed to another way.
        for u in self.climbed.drain(..) {
            let c = cells.of(u, &mut self.nb);
            if self.nb[..c].iter().any(|&v| !drained[v]) {
                heap.push(key(z[u]), u as u32);
            }
        }
    }
}

/// The flood proper: pops cells in non-decreasing height and raises (with ε: one f32 step above)
/// every undrained neighbour no higher than the cell; a higher neighbour is settled with its
/// slope. Returns the number of raised cells.
///
/// Barnes et al.'s pit queue: a cell raised (or levelled) by the flood cannot be lower than
/// anything still in the heap, so it is expanded right away, first in first out, without going
/// through the heap.
fn flood(
    z: &mut [f32],
    cells: &Neighbourhood,
    epsilon: bool,
    drained: &mut [bool],
    heap: &mut RadixHeap,
    settler: &mut Settler,
) -> usize {
    let mut pit = std::collections::VecDeque::new();
    let mut around = [0usize; 8];
    let mut raised = 0;
    loop {
        let k = match pit.pop_front() {
            Some(k) => k,
            None => match heap.pop() {
                Some((_, k)) => k as usize,
                None => break,
            },
        };
        let h = z[k];
        let c = cells.of(k, &mut around);
        for &w in &around[..c] {
            if drained[w] {
                continue;
            }
            drained[w] = true;
            if z[w] < h || (z[w] == h && epsilon) {
                // Clamped so a field that tops out at f32::MAX stays finite.
                z[w] = if epsilon { h.next_up().min(f32::MAX) } else { h };
                raised += 1;
                pit.push_back(w);
            } else if z[w] == h {
                pit.push_back(w);
            } else {
                settler.settle(cells, z, w, drained, heap);
            }
        }
    }
    raised
}

#[cfg(test)]
mod tests {
    use glam::DVec2;

    use super::*;
    use crate::GridSpec;

    #[test]
    fn a_pit_is_raised_to_its_spill_point_and_drains() {
        // A bowl: rim at 10, floor at 1, an outlet notch at 5 on the west edge.
        let grid = GridSpec::new(7, 7, DVec2::ZERO, DVec2::ONE).unwrap();
        let mut hf = Heightfield::from_fn_indexed(grid, |i, j| {
            if i == 0 && j == 3 {
                5.0
            } else if i == 0 || j == 0 || i == 6 || j == 6 {
                10.0
            } else {
                1.0
            }
        })
        .unwrap();
        let raised = fill_depressions(&mut hf, |_, _| false);
        assert_eq!(raised, 25);
        let v = hf.get(3, 3).unwrap();
        assert!(v > 5.0 && v < 5.001, "{v}");
        // Every interior cell has a strictly lower neighbour.
        for j in 1..6 {
            for i in 1..6 {
                let h = hf.get(i, j).unwrap();
                let lower = NEIGHBOURS
                    .iter()
                    .any(|&(a, b)| hf.get((i as i64 + a) as usize, (j as i64 + b) as usize).unwrap() < h);
                assert!(lower, "({i}, {j}) at {h} still a pit");
            }
        }
        // Filling twice changes nothing.
        let before = hf.clone();
        assert_eq!(fill_depressions(&mut hf, |_, _| false), 0);
        assert_eq!(hf, before);
    }

    #[test]
    fn outlets_keep_their_basins() {
        let grid = GridSpec::new(5, 5, DVec2::ZERO, DVec2::ONE).unwrap();
        let pit = Heightfield::from_fn_indexed(grid, |i, j| if (i, j) == (2, 2) { 0.0 } else { 3.0 }).unwrap();
        // Marked as an outlet, the pit stays and nothing around it needs raising.
        let mut kept = pit.clone();
        assert_eq!(fill_depressions(&mut kept, |i, j| (i, j) == (2, 2)), 0);
        assert_eq!(kept, pit);
        // Unmarked, it is filled to just above the plateau, and the flat plateau cells inside the
        // border get an ε slope so they drain too: 8 + 1 raised cells.
        let mut filled = pit.clone();
        assert_eq!(fill_depressions(&mut filled, |_, _| false), 9);
        let v = filled.get(2, 2).unwrap();
        assert!(v > 3.0 && v < 3.0001, "{v}");
    }

    #[test]
    fn without_epsilon_a_pit_fills_flat_and_flats_stay() {
        let grid = GridSpec::new(5, 5, DVec2::ZERO, DVec2::ONE).unwrap();
        let pit = Heightfield::from_fn_indexed(grid, |i, j| if (i, j) == (2, 2) { 0.0 } else { 3.0 }).unwrap();
        let rules = FillRules { epsilon: false, ..FillRules::default() };
        let mut filled = pit.clone();
        assert_eq!(fill_depressions_with(&mut filled, rules, |_, _| false), 1);
        assert_eq!(filled.get(2, 2), Some(3.0));
        assert!(filled.samples().iter().all(|&v| v == 3.0));
        // Walled in (no border outlet, nothing marked): nothing can drain, nothing is filled.
        let mut walled = pit.clone();
        let closed = FillRules { border_drains: false, ..rules };
        assert_eq!(fill_depressions_with(&mut walled, closed, |_, _| false), 0);
        assert_eq!(walled, pit);
        // One outlet corner drains the whole walled plateau; the pit fills to 3.
        assert_eq!(fill_depressions_with(&mut walled, closed, |i, j| (i, j) == (0, 0)), 1);
        assert_eq!(walled.get(2, 2), Some(3.0));
    }

    /// Textbook Priority-Flood without ε (Barnes et al. 2014, Algorithm 1): a binary heap seeded
    /// with every outlet, the unique minimal fill.
    fn reference_fill(hf: &Heightfield, border: bool) -> Vec<f32> {
        use std::cmp::Reverse;
        let (nx, ny) = (hf.nx(), hf.ny());
        let mut z = hf.samples().to_vec();
        let mut closed = vec![false; z.len()];
        let mut heap = std::collections::BinaryHeap::new();
        let nan_next = |k: usize| {
            let (i, j) = ((k % nx) as i64, (k / nx) as i64);
            NEIGHBOURS.iter().any(|&(a, b)| {
                let (x, y) = (i + a, j + b);
                x >= 0 && y >= 0 && x < nx as i64 && y < ny as i64 && z[y as usize * nx + x as usize].is_nan()
            })
        };
        for k in 0..z.len() {
            let (i, j) = (k % nx, k / nx);
            let edge = i == 0 || j == 0 || i + 1 == nx || j + 1 == ny;
            if z[k].is_nan() {
                closed[k] = true;
            } else if (border && edge) || nan_next(k) {
                closed[k] = true;
                heap.push(Reverse((key(z[k]), k)));
            }
        }
        while let Some(Reverse((_, k))) = heap.pop() {
            let (i, j) = ((k % nx) as i64, (k / nx) as i64);
            for (a, b) in NEIGHBOURS {
                let (x, y) = (i + a, j + b);
                if x < 0 || y < 0 || x >= nx as i64 || y >= ny as i64 {
                    continue;
                }
                let w = y as usize * nx + x as usize;
                if !closed[w] {
                    closed[w] = true;
                    z[w] = z[w].max(z[k]);
                    heap.push(Reverse((key(z[w]), w)));
                }
            }
        }
        z
    }

    proptest::proptest! {
        #[test]
        fn plain_fill_matches_textbook_priority_flood(
            nx in 1usize..12,
            ny in 1usize..12,
            cells in proptest::collection::vec(0u8..8, 144),
            border in proptest::bool::ANY,
        ) {
            let grid = GridSpec::new(nx, ny, DVec2::ZERO, DVec2::ONE).unwrap();
            let samples = (0..nx * ny).map(|k| if cells[k] == 7 { f32::NAN } else { f32::from(cells[k]) }).collect();
            let hf = Heightfield::from_samples(grid, samples).unwrap();
            let mut fast = hf.clone();
            let rules = FillRules { border_drains: border, epsilon: false, ..FillRules::default() };
            fill_depressions_with(&mut fast, rules, |_, _| false);
            let expected = reference_fill(&hf, border);
            for (k, (a, b)) in fast.samples().iter().zip(&expected).enumerate() {
                proptest::prop_assert!(a.to_bits() == b.to_bits(), "cell {}: {} vs {}", k, a, b);
            }
            // With ε the fill is never below the plain one and never raises a cell by more than
            // one f32 step per cell of the grid.
            let mut eps = hf.clone();
            fill_depressions_with(&mut eps, FillRules { epsilon: true, ..rules }, |_, _| false);
            for (a, b) in eps.samples().iter().zip(&expected) {
                proptest::prop_assert!(a.is_nan() && b.is_nan() || (a >= b && *a <= b + 1e-4));
            }
        }
    }
}
