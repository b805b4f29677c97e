//! Ridge lines: each edge of the divide tree drawn along the DEM's cells, peak → saddle → peak.
//!
//! An edge of the full tree (between two ascent basins) climbs from its saddle cell by steepest
//! ascent into each basin (the highest higher neighbour at every step, the pointers the flood's
//! basins are made of) up to the two basins' peaks. An edge of a pruned tree stands for a path of
//! full-tree edges: from its kept end through the dropped peaks merged into it, across its saddle,
//! and on through the dropped peaks merged into the other end. Both are traced here: the first
//! from the DEM, the second by concatenating the lines of the edges contracted away
//! ([`crate::divide::contract`]).

use crate::divide::Ridge;

/// A step of a traced path: a ridge and the peak it is walked from.
type Hop = (u32, u32);

/// Per surviving ridge, the ridges its line is made of, from its first kept end to its second:
/// the contracted ridges from that end to the ridge's own near peak, the ridge, then those from
/// its far peak to the other end. `ends` is [`crate::divide::contract`]'s result.
pub(crate) fn chains(ridges: &[Ridge], ends: &[Option<[u32; 2]>], keep: &[bool]) -> Vec<Option<Vec<Hop>>> {
    let n = keep.len();
    let mut around: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (e, r) in ridges.iter().enumerate().filter(|(e, _)| ends[*e].is_none()) {
        around[r.near as usize].push(e as u32);
        around[r.far as usize].push(e as u32);
    }
    // Each dropped peak's step towards the kept peak it merged into: the contracted ridges of a
    // kept peak's group form a tree around it.
    let mut toward: Vec<Option<Hop>> = vec![None; n];
    let mut seen = keep.to_vec();
    let mut stack: Vec<u32> = (0..n as u32).filter(|&p| keep[p as usize]).collect();
    while let Some(p) = stack.pop() {
        for &e in &around[p as usize] {
            let r = ridges[e as usize];
            let q = if r.near == p { r.far } else { r.near };
            if !std::mem::replace(&mut seen[q as usize], true) {
                toward[q as usize] = Some((e, q));
                stack.push(q);
            }
        }
    }
    let walk = |mut x: u32| {
        let mut hops = Vec::new();
        while let Some((e, from)) = toward[x as usize] {
            hops.push((e, from));
            let r = ridges[e as usize];
            x = if r.near == from { r.far } else { r.near };
        }
        hops
    };
    ridges
        .iter()
        .zip(ends)
        .enumerate()
        .map(|(e, (r, end))| {
            end.map(|_| {
                let mut hops: Vec<Hop> = walk(r.near)
                    .into_iter()
                    .rev()
                    .map(|(f, from)| {
                        let s = ridges[f as usize];
                        (f, if s.near == from { s.far } else { s.near })
                    })
                    .collect();
                hops.push((e as u32, r.near));
                hops.extend(walk(r.far));
                hops
            })
        })
        .collect()
}

/// The line of a chain of hops: each ridge's line (given from its near peak to its far peak) in
/// the direction walked, joined without repeating the peaks where they meet, and without the
/// spurs where the way down from a pruned peak retraces the way up to it (so the result is the
/// same however the chain was grouped).
pub(crate) fn join<T: Copy + PartialEq>(ridges: &[Ridge], hops: &[Hop], mut line: impl FnMut(u32) -> Vec<T>) -> Vec<T> {
    let mut out: Vec<T> = Vec::new();
    for &(e, from) in hops {
        let mut piece = line(e);
        if ridges[e as usize].near != from {
            piece.reverse();
        }
        for p in piece {
            let n = out.len();
            if n >= 2 && out[n - 2] == p {
                out.pop();
            } else if out.last() != Some(&p) {
                out.push(p);
            }
        }
    }
    out
}

/// Steepest ascent on the DEM: each land cell's highest higher neighbour, in the strict order
/// (elevation, then the earlier cell).
pub(crate) struct Ascent<'a> {
    pub(crate) z: &'a [f32],
    pub(crate) nx: usize,
    pub(crate) ny: usize,
}

impl Ascent<'_> {
    /// Whether cell `a` is higher than cell `b` in the strict order.
    fn higher(&self, a: usize, b: usize) -> bool {
        let (za, zb) = (self.z[a], self.z[b]);
        !za.is_nan() && (za > zb || (za == zb && a < b))
    }

    /// The higher neighbours of `c`, highest first.
    fn higher_neighbours(&self, c: usize) -> Vec<usize> {
        let (i, j) = ((c % self.nx) as i64, (c / self.nx) as i64);
        let mut up: Vec<usize> = (-1..=1)
            .flat_map(|dj| (-1..=1).map(move |di| (i + di, j + dj)))
            .filter(|&(x, y)| (x, y) != (i, j) && x >= 0 && y >= 0 && x < self.nx as i64 && y < self.ny as i64)
            .map(|(x, y)| y as usize * self.nx + x as usize)
            .filter(|&w| self.higher(w, c))
            .collect();
        up.sort_by(|&a, &b| if self.higher(a, b) { std::cmp::Ordering::Less } else { std::cmp::Ordering::Greater });
        up
    }

    /// The cells from `c` up to the local maximum its steepest ascent reaches, both included.
    fn climb(&self, mut c: usize) -> Vec<u32> {
        let mut path = vec![c as u32];
        while let Some(&next) = self.higher_neighbours(c).first() {
            path.push(next as u32);
            c = next;
        }
        path
    }

    /// The cells from saddle cell `c` up to the peak at cell `peak`: its own steepest ascent if
    /// that ends there, else the steepest ascent from the highest neighbour whose does (the way
    /// into the other basin); a straight step if none does.
    fn climb_to(&self, c: usize, peak: u32) -> Vec<u32> {
        let own = self.climb(c);
        if own.last() == Some(&peak) {
            return own;
        }
        for w in self.higher_neighbours(c) {
            let path = self.climb(w);
            if path.last() == Some(&peak) {
                return std::iter::once(c as u32).chain(path).collect();
            }
        }
        vec![c as u32, peak]
    }

    /// A full-tree ridge's cells, from the near peak's cell through the saddle cell to the far
    /// peak's.
    pub(crate) fn ridge(&self, saddle: usize, near_peak: u32, far_peak: u32) -> Vec<u32> {
        let mut line = self.climb_to(saddle, near_peak);
        line.reverse();
        line.extend(self.climb_to(saddle, far_peak).into_iter().skip(1));
        line
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::divide::{contract, ridge};

    #[test]
    fn a_pruned_ridge_runs_through_the_peaks_merged_into_its_ends() {
        // K0 —a— P1 —b— K2, P1 dropped: it merges across its higher ridge `a` into K0, and the
        // surviving ridge `b` is drawn K0 → a → P1 → b → K2.
        let ridges = [ridge(1, 0, 1), ridge(1, 2, 5)];
        let keep = [true, false, true];
        let ends = contract(&ridges, &keep, [1]);
        assert_eq!(ends, [None, Some([0, 2])]);
        let chains = chains(&ridges, &ends, &keep);
        assert_eq!(chains[0], None);
        assert_eq!(chains[1].as_deref(), Some(&[(0, 0), (1, 1)][..]));
        // Lines given near → far: ridge 0 from P1 to K0, ridge 1 from P1 to K2.
        let lines = [vec!['p', 'x', 'k'], vec!['p', 'y', 'K']];
        assert_eq!(
            join(&ridges, chains[1].as_ref().unwrap(), |e| lines[e as usize].clone()),
            ['k', 'x', 'p', 'y', 'K']
        );
        // Where the way on retraces the way up to the pruned peak, the spur goes.
        let lines = [vec!['p', 'x', 'k'], vec!['p', 'x', 'y', 'K']];
        assert_eq!(join(&ridges, chains[1].as_ref().unwrap(), |e| lines[e as usize].clone()), ['k', 'x', 'y', 'K']);
    }

    #[test]
    fn ridges_climb_by_steepest_ascent_into_each_basin() {
        // One row: peak 9 at cell 1, saddle 4 at cell 3, peak 7 at cell 5.
        let z = [1.0, 9.0, 6.0, 4.0, 5.0, 7.0, 2.0];
        let ascent = Ascent { z: &z, nx: 7, ny: 1 };
        assert_eq!(ascent.ridge(3, 1, 5), [1, 2, 3, 4, 5]);
        assert_eq!(ascent.ridge(3, 5, 1), [5, 4, 3, 2, 1]);
    }
}
