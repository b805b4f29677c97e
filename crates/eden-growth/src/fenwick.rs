//! The growth frontier B: weighted random selection in O(log N) with a Fenwick tree of integer
//! weights (exact sums, so selection never drifts), plus a list for uniform selection when every
//! frontier weight is zero.

use rand::RngExt;

const ABSENT: u32 = u32::MAX;

pub(crate) struct Frontier<'w> {
    tree: Vec<u64>,
    weight: &'w [u64],
    total: u64,
    members: Vec<u32>,
    pos: Vec<u32>,
}

impl<'w> Frontier<'w> {
    /// An empty frontier over nodes `0..weight.len()` with the given per-node weights.
    pub(crate) fn new(weight: &'w [u64]) -> Self {
        let n = weight.len();
        Self { tree: vec![0; n + 1], weight, total: 0, members: Vec::new(), pos: vec![ABSENT; n] }
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.members.is_empty()
    }

    pub(crate) fn contains(&self, v: u32) -> bool {
        self.pos[v as usize] != ABSENT
    }

    fn add(&mut self, v: u32, delta: u64, add: bool) {
        let mut i = v as usize + 1;
        while i < self.tree.len() {
            if add {
                self.tree[i] += delta;
            } else {
                self.tree[i] -= delta;
            }
            i += i & i.wrapping_neg();
        }
    }

    pub(crate) fn insert(&mut self, v: u32) {
        if self.contains(v) {
            return;
        }
        self.pos[v as usize] = self.members.len() as u32;
        self.members.push(v);
        let w = self.weight[v as usize];
        if w > 0 {
            self.add(v, w, true);
            self.total += w;
        }
    }

    pub(crate) fn remove(&mut self, v: u32) {
        let k = self.pos[v as usize];
        if k == ABSENT {
            return;
        }
        self.members.swap_remove(k as usize);
        if let Some(&moved) = self.members.get(k as usize) {
            self.pos[moved as usize] = k;
        }
        self.pos[v as usize] = ABSENT;
        let w = self.weight[v as usize];
        if w > 0 {
            self.add(v, w, false);
            self.total -= w;
        }
    }

    /// A member drawn with probability ∝ its weight (uniformly when all weights are zero).
    pub(crate) fn sample(&self, rng: &mut impl RngExt) -> u32 {
        if self.total == 0 {
            return self.members[rng.random_range(0..self.members.len())];
        }
        // Descend to the first index whose prefix sum exceeds u.
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
        idx as u32
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
}
