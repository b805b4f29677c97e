//! The growth frontier B: weighted random selection in O(log |B|) with a Fenwick tree of integer
//! weights (exact sums, so selection never drifts), plus uniform selection when every frontier
//! weight is zero.
//!
//! The tree is indexed by position in the frontier, not by node id: members are kept compact
//! (removal moves the last member into the hole), so the tree has the size of the frontier — a
//! few thousand entries that stay in cache — instead of the size of the graph, whose lower levels
//! would miss the cache on every draw once the graph passes a few hundred thousand nodes.

use rand::RngExt;

const ABSENT: u32 = u32::MAX;

pub(crate) struct Frontier<'w> {
    /// Fenwick tree over positions `0..capacity`, 1-based.
    tree: Vec<u64>,
    weight: &'w [u64],
    total: u64,
    members: Vec<u32>,
    pos: Vec<u32>,
}

impl<'w> Frontier<'w> {
    /// An empty frontier over nodes `0..weight.len()` with the given per-node weights.
    pub(crate) fn new(weight: &'w [u64]) -> Self {
        Self { tree: vec![0; 1025], weight, total: 0, members: Vec::new(), pos: vec![ABSENT; weight.len()] }
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.members.is_empty()
    }

    pub(crate) fn contains(&self, v: u32) -> bool {
        self.pos[v as usize] != ABSENT
    }

    fn add(&mut self, position: usize, delta: u64) {
        let mut i = position + 1;
        while i < self.tree.len() {
            self.tree[i] += delta;
            i += i & i.wrapping_neg();
        }
    }

    fn sub(&mut self, position: usize, delta: u64) {
        let mut i = position + 1;
        while i < self.tree.len() {
            self.tree[i] -= delta;
            i += i & i.wrapping_neg();
        }
    }

    /// Doubles the tree's capacity, rebuilding it from the members' weights in O(capacity).
    fn grow(&mut self) {
        let cap = 2 * (self.tree.len() - 1);
        let mut tree = vec![0u64; cap + 1];
        for (k, &v) in self.members.iter().enumerate() {
            tree[k + 1] = self.weight[v as usize];
        }
        for i in 1..=cap {
            let parent = i + (i & i.wrapping_neg());
            if parent <= cap {
                tree[parent] += tree[i];
            }
        }
        self.tree = tree;
    }

    pub(crate) fn insert(&mut self, v: u32) {
        if self.contains(v) {
            return;
        }
        let k = self.members.len();
        if k + 1 >= self.tree.len() {
            self.grow();
        }
        self.pos[v as usize] = k as u32;
        self.members.push(v);
        let w = self.weight[v as usize];
        if w > 0 {
            self.add(k, w);
            self.total += w;
        }
    }

    pub(crate) fn remove(&mut self, v: u32) {
        let k = self.pos[v as usize];
        if k == ABSENT {
            return;
        }
        let (k, last) = (k as usize, self.members.len() - 1);
        let w = self.weight[v as usize];
        if k != last {
            // The last member moves into the hole.
            let u = self.members[last];
            let wu = self.weight[u as usize];
            self.members[k] = u;
            self.pos[u as usize] = k as u32;
            self.sub(last, wu);
            self.add(k, wu);
        }
        self.sub(k, w);
        self.members.pop();
        self.pos[v as usize] = ABSENT;
        self.total -= w;
    }

    /// A member drawn with probability ∝ its weight (uniformly when all weights are zero).
    pub(crate) fn sample(&self, rng: &mut impl RngExt) -> u32 {
        if self.total == 0 {
            return self.members[rng.random_range(0..self.members.len())];
        }
        // Descend to the first position whose prefix sum exceeds u.
        let mut u = rng.random_range(0..self.total);
        let mut idx = 0usize;
        let mut step = (self.tree.len() - 1).next_power_of_two();
        while step > 0 {
            let next = idx + step;
            if next < self.tree.len() && self.tree[next] <= u {
                u -= self.tree[next];
                idx = next;
            }
            step >>= 1;
        }
        self.members[idx]
    }
}

#[cfg(test)]
mod tests {
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    use super::*;

    #[test]
    fn sampling_follows_the_weights_and_removal_is_exact() {
        let weight = [0u64, 1, 3, 0, 6];
        let mut f = Frontier::new(&weight);
        for v in 0..5 {
            f.insert(v);
        }
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let mut hits = [0usize; 5];
        for _ in 0..10_000 {
            hits[f.sample(&mut rng) as usize] += 1;
        }
        assert_eq!((hits[0], hits[3]), (0, 0), "zero-weight members are never drawn while others weigh");
        assert!((hits[4] as f64 / hits[1] as f64 - 6.0).abs() < 1.0, "{hits:?}");
        f.remove(4);
        f.remove(2);
        f.remove(1);
        // Only zero-weight members left: uniform among them.
        let drawn: Vec<u32> = (0..100).map(|_| f.sample(&mut rng)).collect();
        assert!(drawn.contains(&0) && drawn.contains(&3) && drawn.iter().all(|&v| v == 0 || v == 3));
        f.remove(0);
        f.remove(3);
        assert!(f.is_empty());
        assert!(f.tree.iter().all(|&t| t == 0), "tree returns to zero: reusable");
    }

    #[test]
    fn growing_past_the_initial_capacity_keeps_the_sums() {
        let weight: Vec<u64> = (0..5000).map(|v| v % 7).collect();
        let mut f = Frontier::new(&weight);
        for v in 0..5000 {
            f.insert(v);
        }
        for v in (0..5000).step_by(3) {
            f.remove(v);
        }
        let expected: u64 = (0..5000u32).filter(|v| v % 3 != 0).map(|v| u64::from(v % 7)).sum();
        assert_eq!(f.total, expected);
        // Every prefix sum of the tree matches the members' weights in position order.
        let mut acc = 0;
        for (k, &v) in f.members.iter().enumerate() {
            acc += weight[v as usize];
            let (mut i, mut s) = (k + 1, 0);
            while i > 0 {
                s += f.tree[i];
                i -= i & i.wrapping_neg();
            }
            assert_eq!(s, acc, "prefix {k}");
        }
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        assert!((0..1000).all(|_| {
            let v = f.sample(&mut rng);
            !v.is_multiple_of(3) && !v.is_multiple_of(7)
        }));
    }
}
