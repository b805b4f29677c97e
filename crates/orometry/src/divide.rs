//! The divide tree by adjacency (§3, and the tree akirmse/mountains builds): each saddle joins the
//! two peaks whose ridges meet there, not a peak and its prominence parent.
//!
//! The flood builds the full tree, over every ascent basin: the cell where two basins' components
//! first meet is a saddle on the ridge between the basins' peaks, and these joins, highest first,
//! are a maximum spanning tree of the basins. Pruning contracts it: a dropped peak is merged into
//! the neighbour across its highest saddle, that ridge goes, and its other ridges now lead to
//! that neighbour. Contracting the highest ridge keeps, between every pair of remaining peaks,
//! the same lowest saddle on the path between them (a path through the dropped peak crossed two
//! of its saddles, and the lower one remains), so the pruned tree is the divide tree of the peaks
//! kept, and a kept peak's key saddle stays in it.

use crate::union_find::find;

/// A ridge of a divide tree: a saddle and the two peaks on either side of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Ridge {
    /// The peak on the side of the peak whose key saddle this is (where there is one).
    pub(crate) near: u32,
    /// The peak across the saddle.
    pub(crate) far: u32,
    /// The saddle's place in the strict order of heights: smaller is higher.
    pub(crate) key: u64,
}

/// Prunes the divide tree over `keep.len()` peaks joined by `ridges`, dropping the peaks whose
/// `keep` flag is false, one after another in `order` (which lists them all). Returns, per ridge,
/// its ends as kept peaks, or `None` for a ridge contracted away. A dropped peak without ridges
/// simply goes.
pub(crate) fn contract(
    ridges: &[Ridge],
    keep: &[bool],
    order: impl IntoIterator<Item = usize>,
) -> Vec<Option<[u32; 2]>> {
    let n = keep.len();
    let mut around: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (e, r) in ridges.iter().enumerate() {
        around[r.near as usize].push(e as u32);
        around[r.far as usize].push(e as u32);
    }
    // Each dropped peak points to the peak it merged into.
    let mut merged: Vec<u32> = (0..n as u32).collect();
    let mut alive = vec![true; ridges.len()];
    for p in order {
        debug_assert!(!keep[p], "peak {p} is kept");
        let ridges_here: Vec<u32> = std::mem::take(&mut around[p]).into_iter().filter(|&e| alive[e as usize]).collect();
        let Some(&highest) = ridges_here.iter().min_by_key(|&&e| (ridges[e as usize].key, e)) else {
            continue;
        };
        alive[highest as usize] = false;
        let r = ridges[highest as usize];
        let (a, b) = (find(&mut merged, r.near), find(&mut merged, r.far));
        let other = if a as usize == p { b } else { a };
        merged[p] = other;
        let mut rest: Vec<u32> = ridges_here.into_iter().filter(|&e| alive[e as usize]).collect();
        let target = &mut around[other as usize];
        if rest.len() > target.len() {
            std::mem::swap(&mut rest, target);
        }
        target.extend(rest);
    }
    ridges
        .iter()
        .zip(&alive)
        .map(|(r, &alive)| alive.then(|| [find(&mut merged, r.near), find(&mut merged, r.far)]))
        .collect()
}

/// A ridge from its ends and key, for tests.
#[cfg(test)]
pub(crate) fn ridge(near: u32, far: u32, key: u64) -> Ridge {
    Ridge { near, far, key }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dropped_peak_merges_across_its_highest_saddle_and_keeps_the_lower() {
        // A —(key 5)— P —(key 2, higher)— B: dropping P leaves A joined to B through key 5.
        let ridges = [ridge(0, 1, 5), ridge(1, 2, 2)];
        let out = contract(&ridges, &[true, false, true], [1]);
        assert_eq!(out, [Some([0, 2]), None]);
        // The other way round, the saddle nearer A is the higher one and goes.
        let ridges = [ridge(0, 1, 2), ridge(1, 2, 5)];
        assert_eq!(contract(&ridges, &[true, false, true], [1]), [None, Some([0, 2])]);
    }

    #[test]
    fn chains_of_dropped_peaks_end_at_kept_ones() {
        // A star around dropped P (ridges to Q dropped, K1 and K2 kept) with Q's own ridge to K3.
        // P: ridges to Q (key 1), K1 (key 3), K2 (key 4); Q: ridge to K3 (key 6).
        let (p, q, k1, k2, k3) = (0, 1, 2, 3, 4);
        let ridges = [ridge(p, q, 1), ridge(p, k1, 3), ridge(p, k2, 4), ridge(q, k3, 6)];
        let keep = [false, false, true, true, true];
        for order in [[p as usize, q as usize], [q as usize, p as usize]] {
            let out = contract(&ridges, &keep, order);
            // P and Q together merge into K1 across the highest remaining saddle (key 3); the
            // ridges to K2 and K3 now start at K1.
            assert_eq!(out, [None, None, Some([k1, k2]), Some([k1, k3])], "{order:?}");
        }
    }
}
