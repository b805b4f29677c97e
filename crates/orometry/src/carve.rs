//! Keeps a synthesized terrain's divide tree the tree it was built from: a descending sweep over
//! the grid, in the spirit of the prominence analysis, that cuts every premature join.
//!
//! Sweeping the samples from the highest down, the land above the current level falls into
//! components, each holding some of the tree's peaks. Where a sample would join components whose
//! peaks the tree only joins at a lower saddle, the terrain has a bridge above that saddle (two
//! flanks meeting over a col, say) which would raise the col and cut the lower peak's
//! prominence. The sample is lowered to just under the next saddle of the tree and met again
//! there; the tree's own saddles are the only joins left. Samples without a tree peak (noise
//! bumps) join freely.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use rayon::prelude::*;
use relief_heightfield::Heightfield;

use crate::analysis::for_neighbours;
use crate::tree::DivideTree;
use crate::union_find::find;

/// How far under a tree saddle a cut sample is lowered, metres: the tree's saddle stays the
/// highest join.
const CUT_DEPTH: f32 = 0.25;

const NONE: u32 = u32::MAX;

/// A sample in the sweep's queue: highest first, then lowest index.
#[derive(PartialEq)]
struct Item(f32, u32);

impl Eq for Item {}

impl Ord for Item {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0.total_cmp(&other.0).then(other.1.cmp(&self.1))
    }
}

impl PartialOrd for Item {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Lowers every sample of `hf` that joins, above the tree's saddle between them, land holding
/// peaks of `tree` the tree keeps apart there. `peak_cells` are the samples of the tree's peaks,
/// by index (`None` for one that is not on a sample). Nothing goes below `base`. No-data samples
/// are left alone and never join anything. Returns how many samples were lowered.
pub(crate) fn separate(hf: &mut Heightfield, tree: &DivideTree, peak_cells: &[Option<usize>], base: f64) -> usize {
    let (nx, ny) = (hf.nx(), hf.ny());
    let n = nx * ny;
    let mut peak_at = vec![NONE; n];
    for (k, c) in peak_cells.iter().enumerate() {
        if let Some(c) = *c {
            peak_at[c] = k as u32;
        }
    }
    let mut saddles: Vec<(f64, [u32; 2])> = tree.saddles.iter().map(|s| (s.elevation, s.peaks)).collect();
    saddles.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut next_saddle = 0;
    let mut tree_uf: Vec<u32> = (0..tree.peaks.len() as u32).collect();
    let samples = hf.samples_mut();
    // Every sample sorted once, highest first (rows of keys in parallel); the few cut samples go
    // to a heap and are merged in at their new heights.
    let mut sorted: Vec<Item> =
        samples.par_iter().enumerate().filter(|(_, v)| !v.is_nan()).map(|(k, &v)| Item(v, k as u32)).collect();
    sorted.par_sort_unstable_by(|a, b| b.cmp(a));
    let mut sorted = sorted.into_iter().peekable();
    let mut cut: BinaryHeap<Item> = BinaryHeap::new();
    // Per sample: its component's parent (NONE until swept); per root: a tree peak in it.
    let mut parent = vec![NONE; n];
    let mut peak_of = vec![NONE; n];
    let mut lowered = 0;
    let mut roots: Vec<u32> = Vec::with_capacity(8);
    loop {
        let from_cut = match (cut.peek(), sorted.peek()) {
            (Some(a), Some(b)) => a > b,
            (Some(_), None) => true,
            (None, Some(_)) => false,
            (None, None) => break,
        };
        let Some(Item(h, c)) = (if from_cut { cut.pop() } else { sorted.next() }) else { break };
        // Each unswept sample is queued once: a cut sample's entry was taken to cut it.
        let c = c as usize;
        while next_saddle < saddles.len() && saddles[next_saddle].0 >= f64::from(h) {
            let [a, b] = saddles[next_saddle].1;
            let (ra, rb) = (find(&mut tree_uf, a), find(&mut tree_uf, b));
            tree_uf[ra as usize] = rb;
            next_saddle += 1;
        }
        roots.clear();
        for_neighbours(c % nx, c / nx, nx, ny, |w| {
            if parent[w] != NONE {
                let r = find(&mut parent, w as u32);
                if !roots.contains(&r) {
                    roots.push(r);
                }
            }
        });
        let mut peak = peak_at[c];
        let mut premature = false;
        for &r in &roots {
            let p = peak_of[r as usize];
            if p == NONE {
                continue;
            }
            if peak == NONE {
                peak = p;
            } else if find(&mut tree_uf, peak) != find(&mut tree_uf, p) {
                premature = true;
            }
        }
        if premature {
            let below = saddles.get(next_saddle).map_or(base, |s| s.0) as f32 - CUT_DEPTH;
            let v = below.max(base as f32).min(h);
            if v < h {
                samples[c] = v;
                lowered += 1;
                cut.push(Item(v, c as u32));
                continue;
            }
        }
        parent[c] = c as u32;
        for &r in &roots {
            parent[r as usize] = c as u32;
        }
        peak_of[c] = peak;
    }
    lowered
}

#[cfg(test)]
mod tests {
    use glam::DVec2;
    use relief_heightfield::GridSpec;

    use super::*;
    use crate::tree::{TreePeak, TreeSaddle};
    use crate::{AnalysisOptions, analyze};

    /// Two summits, A (100 m) and B (90 m), on a 5 × 3 grid whose middle row is a ridge with a
    /// col of `col` between them; the tree says they meet at 50 m.
    fn two_summits(col: f32) -> (Heightfield, DivideTree, Vec<Option<usize>>) {
        let grid = GridSpec::new(5, 3, DVec2::ZERO, DVec2::ONE).unwrap();
        let mut v = vec![10.0; 15];
        v[5..10].copy_from_slice(&[100.0, 85.0, col, 85.0, 90.0]);
        let peak = |x: f64, elevation| TreePeak { position: DVec2::new(x, 1.0), elevation };
        let tree = DivideTree {
            peaks: vec![peak(0.0, 100.0), peak(4.0, 90.0)],
            saddles: vec![TreeSaddle { position: DVec2::new(2.0, 1.0), elevation: 50.0, peaks: [0, 1] }],
        };
        (Heightfield::from_samples(grid, v).unwrap(), tree, vec![Some(5), Some(9)])
    }

    fn prominence_of_b(hf: &Heightfield) -> f64 {
        let oro = analyze(hf, &AnalysisOptions::default()).unwrap();
        oro.peaks.iter().find(|p| p.elevation == 90.0).unwrap().prominence
    }

    #[test]
    fn a_col_above_the_trees_saddle_is_cut_to_just_under_it() {
        let (mut hf, tree, peaks) = two_summits(80.0);
        assert_eq!(prominence_of_b(&hf), 10.0);
        assert_eq!(separate(&mut hf, &tree, &peaks, 0.0), 1);
        assert_eq!(hf.samples()[7], 50.0 - CUT_DEPTH);
        // Nothing else moves, and B has the tree's prominence (less the cut's depth below it).
        let mut others = hf.samples().iter().enumerate().filter(|&(k, _)| k != 7);
        assert!(others.all(|(k, &v)| v == two_summits(80.0).0.samples()[k]));
        assert_eq!(prominence_of_b(&hf), 40.0 + f64::from(CUT_DEPTH));
    }

    #[test]
    fn a_col_at_or_below_the_trees_saddle_and_bumps_without_tree_peaks_stay() {
        for col in [50.0, 30.0] {
            let (mut hf, tree, peaks) = two_summits(col);
            assert_eq!(separate(&mut hf, &tree, &peaks, 0.0), 0);
            assert_eq!(hf.samples()[7], col);
        }
        // Without B in the tree, its summit is a bump that joins A freely.
        let (mut hf, tree, _) = two_summits(80.0);
        assert_eq!(separate(&mut hf, &tree, &[Some(5), None], 0.0), 0);
    }

    #[test]
    fn cuts_stop_at_the_base() {
        let (mut hf, tree, peaks) = two_summits(80.0);
        assert_eq!(separate(&mut hf, &tree, &peaks, 70.0), 1);
        assert_eq!(hf.samples()[7], 70.0);
    }
}
