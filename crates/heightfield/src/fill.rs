//! Depression filling by Priority-Flood+ε (Barnes, Lehman & Mulla 2014): the minimal raise that
//! makes every cell drain to an outlet along a strictly descending path.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::Heightfield;

/// A cell in the flood queue, lowest elevation first (ties by index, so the fill is deterministic).
#[derive(PartialEq)]
struct Cell(f32, usize);

impl Eq for Cell {}

impl PartialOrd for Cell {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Cell {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

const NEIGHBOURS: [(i64, i64); 8] = [(-1, 0), (1, 0), (0, -1), (0, 1), (-1, -1), (1, 1), (-1, 1), (1, -1)];

/// Fills every depression of `hf` so each valid cell has a strictly descending 8-connected path to
/// an outlet: the grid border, a cell next to no-data, or a cell where `outlet(i, j)` is true
/// (sea, a lake meant to stay, a marked crater). A filled cell is raised to its spill height plus
/// the smallest f32 step per cell along the way (the "+ε" of Priority-Flood+ε), so flats drain too.
/// Returns the number of raised cells. O(N log N).
pub fn fill_depressions(hf: &mut Heightfield, outlet: impl Fn(usize, usize) -> bool) -> usize {
    let (nx, ny) = (hf.nx(), hf.ny());
    let z = hf.samples_mut();
    let mut done = vec![false; z.len()];
    let mut heap = BinaryHeap::new();
    let neighbours = |k: usize| {
        let (i, j) = ((k % nx) as i64, (k / nx) as i64);
        NEIGHBOURS.iter().filter_map(move |&(di, dj)| {
            let (a, b) = (i + di, j + dj);
            (a >= 0 && b >= 0 && a < nx as i64 && b < ny as i64).then(|| b as usize * nx + a as usize)
        })
    };
    for k in 0..z.len() {
        if z[k].is_nan() {
            done[k] = true;
            continue;
        }
        let (i, j) = (k % nx, k / nx);
        let edge = i == 0 || j == 0 || i + 1 == nx || j + 1 == ny;
        if edge || outlet(i, j) || neighbours(k).any(|w| z[w].is_nan()) {
            done[k] = true;
            heap.push(Cell(z[k], k));
        }
    }
    let mut raised = 0;
    while let Some(Cell(h, k)) = heap.pop() {
        for w in neighbours(k) {
            if done[w] {
                continue;
            }
            done[w] = true;
            if z[w] <= h {
                z[w] = h.next_up();
                raised += 1;
            }
            heap.push(Cell(z[w], w));
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
