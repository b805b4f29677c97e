//! The heightfields generated lately, by id, for the views and downloads to fetch.

use std::collections::VecDeque;
use std::sync::Arc;

use relief::heightfield::Heightfield;

/// The last few results, oldest first; ids rise from 1.
#[derive(Debug)]
pub(crate) struct Results {
    kept: VecDeque<(u64, Arc<Heightfield>)>,
    capacity: usize,
    max_bytes: u64,
    next: u64,
}

/// The bytes a kept heightfield's samples take.
fn bytes(hf: &Heightfield) -> u64 {
    hf.samples().len() as u64 * 4
}

impl Results {
    /// Keeps at most `capacity` results (at least one) taking at most `max_bytes` together (the
    /// newest is kept whatever its size: it was generated under the budget).
    pub(crate) fn new(capacity: usize, max_bytes: u64) -> Self {
        Self { kept: VecDeque::new(), capacity: capacity.max(1), max_bytes, next: 1 }
    }

    /// Keeps `hf`, dropping the oldest beyond the capacity or the bytes; its id.
    pub(crate) fn insert(&mut self, hf: Heightfield) -> u64 {
        let id = self.next;
        self.next += 1;
        let mut total = bytes(&hf);
        self.kept.push_back((id, Arc::new(hf)));
        // Newest first: keep while both caps hold.
        let keep = self
            .kept
            .iter()
            .rev()
            .take(self.capacity)
            .take_while(|(k, hf)| {
                if *k == id {
                    return true;
                }
                total += bytes(hf);
                total <= self.max_bytes
            })
            .count();
        let drop = self.kept.len() - keep;
        self.kept.drain(..drop);
        id
    }

    /// Result `id`, if still kept.
    pub(crate) fn get(&self, id: u64) -> Option<Arc<Heightfield>> {
        self.kept.iter().find(|(k, _)| *k == id).map(|(_, hf)| Arc::clone(hf))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief::heightfield::GridSpec;

    #[test]
    fn the_oldest_results_go_first() {
        let grid = GridSpec::new(2, 2, glam::DVec2::ZERO, glam::DVec2::ONE).unwrap();
        let mut results = Results::new(2, u64::MAX);
        let ids: Vec<u64> = (0..3).map(|k| results.insert(Heightfield::filled(grid, k as f32).unwrap())).collect();
        assert_eq!(ids, [1, 2, 3]);
        assert!(results.get(1).is_none());
        assert_eq!(results.get(2).unwrap().samples()[0], 1.0);
        assert_eq!(results.get(3).unwrap().samples()[0], 2.0);
        assert!(results.get(4).is_none());
    }

    #[test]
    fn results_beyond_the_byte_cap_go_oldest_first_but_the_newest_stays() {
        let hf = |n: usize| Heightfield::filled(GridSpec::new(n, n, glam::DVec2::ZERO, glam::DVec2::ONE).unwrap(), 1.0);
        // 16, 16 and 36 bytes under a cap of 40.
        let mut results = Results::new(10, 40);
        let a = results.insert(hf(2).unwrap());
        let b = results.insert(hf(2).unwrap());
        assert!(results.get(a).is_some() && results.get(b).is_some(), "32 bytes fit");
        let c = results.insert(hf(3).unwrap());
        assert!(results.get(a).is_none() && results.get(b).is_none(), "36 + 16 > 40");
        assert!(results.get(c).is_some());
        // Larger than the cap alone: kept, and everything older goes.
        let d = results.insert(hf(4).unwrap());
        assert!(results.get(c).is_none() && results.get(d).is_some());
        // Exactly at the cap.
        let mut results = Results::new(10, 32);
        let (e, f) = (results.insert(hf(2).unwrap()), results.insert(hf(2).unwrap()));
        assert!(results.get(e).is_some() && results.get(f).is_some());
    }
}
