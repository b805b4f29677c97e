//! The heightfields generated lately, by id, for the views and downloads to fetch.

use std::collections::VecDeque;
use std::sync::Arc;

use relief::heightfield::Heightfield;

/// The last few results, oldest first; ids rise from 1.
#[derive(Debug)]
pub(crate) struct Results {
    kept: VecDeque<(u64, Arc<Heightfield>)>,
    capacity: usize,
    next: u64,
}

impl Results {
    /// Keeps at most `capacity` results (at least one).
    pub(crate) fn new(capacity: usize) -> Self {
        Self { kept: VecDeque::new(), capacity: capacity.max(1), next: 1 }
    }

    /// Keeps `hf`, dropping the oldest beyond the capacity; its id.
    pub(crate) fn insert(&mut self, hf: Heightfield) -> u64 {
        let id = self.next;
        self.next += 1;
        if self.kept.len() == self.capacity {
            self.kept.pop_front();
        }
        self.kept.push_back((id, Arc::new(hf)));
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
        let mut results = Results::new(2);
        let ids: Vec<u64> = (0..3).map(|k| results.insert(Heightfield::filled(grid, k as f32).unwrap())).collect();
        assert_eq!(ids, [1, 2, 3]);
        assert!(results.get(1).is_none());
        assert_eq!(results.get(2).unwrap().samples()[0], 1.0);
        assert_eq!(results.get(3).unwrap().samples()[0], 2.0);
        assert!(results.get(4).is_none());
    }
}
