//! Depression filling by Priority-Flood+ε (Barnes, Lehman & Mulla 2014): the minimal raise that
//! makes every cell drain to an outlet along a strictly descending path.

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

/// Fills every depression of `hf` so each valid cell has a strictly descending 8-connected path to
/// an outlet: the grid border, a cell next to no-data, or a cell where `outlet(i, j)` is true
/// (sea, a lake meant to stay, a marked crater). A filled cell is raised to its spill height plus
/// the smallest f32 step per cell along the way (the "+ε" of Priority-Flood+ε), so flats drain too.
/// Returns the number of raised cells.
///
/// Cells that already have a strictly descending path to an outlet are never raised by
/// Priority-Flood, so an O(N) breadth-first search uphill from the outlets finds them first; the
/// priority queue (a radix heap: the flood pops keys in non-decreasing order) then only sees the
/// cells of actual depressions. A nearly drained raster costs little more than one pass.
pub fn fill_depressions(hf: &mut Heightfield, outlet: impl Fn(usize, usize) -> bool) -> usize {
    let (nx, ny) = (hf.nx(), hf.ny());
    let z = hf.samples_mut();
    let interior = |k: usize| {
        let (i, j) = (k % nx, k / nx);
        i > 0 && j > 0 && i + 1 < nx && j + 1 < ny
    };
    // Interior cells reach their neighbours by fixed offsets; border cells go the slow way.
    let stride = nx as isize;
    let offsets = [-1, 1, -stride, stride, -stride - 1, -stride + 1, stride - 1, stride + 1];
    let neighbours = |k: usize, out: &mut [usize; 8]| -> usize {
        if interior(k) {
            for (o, d) in out.iter_mut().zip(offsets) {
                *o = k.wrapping_add_signed(d);
            }
            return 8;
        }
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
    };
    let has_nan = z.iter().any(|v| v.is_nan());
    let mut nb = [0usize; 8];
    // Outlets (and no-data) never change.
    let mut drained: Vec<bool> = (0..z.len())
        .map(|k| {
            let (i, j) = (k % nx, k / nx);
            z[k].is_nan()
                || !interior(k)
                || outlet(i, j)
                || (has_nan && {
                    let c = neighbours(k, &mut nb);
                    nb[..c].iter().any(|&w| z[w].is_nan())
                })
        })
        .collect();
    // Uphill breadth-first search from the outlets that border other ground: a cell above a
    // drained neighbour drains through it.
    // Reachability only: any visiting order will do, so a stack.
    let mut queue = Vec::new();
    for k in 0..z.len() {
        if drained[k] && !z[k].is_nan() {
            let c = neighbours(k, &mut nb);
            if nb[..c].iter().any(|&w| !drained[w]) {
                queue.push(k);
            }
        }
    }
    while let Some(k) = queue.pop() {
        let c = neighbours(k, &mut nb);
        for &w in &nb[..c] {
            if !drained[w] && z[w] > z[k] {
                drained[w] = true;
                queue.push(w);
            }
        }
    }
    // Priority-Flood+ε over the depressions, seeded by the drained cells around them.
    let mut seeds: Vec<(u32, u32)> = (0..z.len())
        .filter(|&k| {
            drained[k] && !z[k].is_nan() && {
                let c = neighbours(k, &mut nb);
                nb[..c].iter().any(|&w| !drained[w])
            }
        })
        .map(|k| (key(z[k]), k as u32))
        .collect();
    if seeds.is_empty() {
        return 0;
    }
    // The radix heap needs its first key at or below every later one.
    seeds.sort_unstable();
    let mut heap = RadixHeap::new();
    heap.last = seeds[0].0;
    for (k, v) in seeds {
        heap.push(k, v);
    }
    let mut raised = 0;
    while let Some((_, k)) = heap.pop() {
        let h = z[k as usize];
        let c = neighbours(k as usize, &mut nb);
        for &w in &nb[..c] {
            if drained[w] {
                continue;
            }
            drained[w] = true;
            if z[w] <= h {
                z[w] = h.next_up();
                raised += 1;
            }
            heap.push(key(z[w]), w as u32);
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
}
