//! What an interactive editor keeps between previews of one scene being edited, so that an
//! edit appended to the scene's history is applied to the terrain as it stood, as the papers'
//! editors do, instead of the whole history being replayed.

use crate::heightfield::GridSpec;
use crate::island::{Island, IslandSettings, Operation};

/// How many island states a session keeps: the latest, and the one before (so an undo right
/// after an edit is as quick as the edit).
const KEPT: usize = 2;

/// Islands above this many cells are not kept (each state holds about 25 bytes a cell: 25 MiB
/// at 1024²).
const MAX_KEPT_CELLS: usize = 1 << 20;

/// The state one editing session keeps between previews ([`super::preview_in`]).
///
/// Today it keeps islands: after a preview of an island scene, the island as its operations left
/// it. When the next scene has the same grid, settings and seed, no coastline image, and the
/// kept operations as the start of its own, only the operations after them are applied. The
/// result is the same, to the byte, as a replay of the whole history (islands are
/// deterministic and their state is whole), so a session only saves time. A session holds up to
/// two island states; islands over 2²⁰ cells (1024²) are not kept.
#[derive(Debug, Default)]
pub struct EditSession {
    islands: Vec<IslandState>,
    resumed: usize,
}

/// An island after `operations`, with the stroke warnings they gave.
#[derive(Debug)]
pub(crate) struct IslandState {
    key: IslandKey,
    operations: Vec<Operation>,
    pub(crate) island: Island,
    pub(crate) warnings: Vec<String>,
}

/// What an island's start depends on.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct IslandKey {
    pub(crate) grid: GridSpec,
    pub(crate) settings: IslandSettings,
    pub(crate) seed: u64,
}

impl EditSession {
    /// A session that keeps nothing yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// How many operations of `operations` a kept island has already applied (the longest kept
    /// start of them), with a copy of that island and its warnings.
    pub(crate) fn resume_island(
        &self,
        key: &IslandKey,
        operations: &[Operation],
    ) -> Option<(usize, Island, Vec<String>)> {
        self.islands
            .iter()
            .filter(|s| s.key == *key && operations.starts_with(&s.operations))
            .max_by_key(|s| s.operations.len())
            .map(|s| (s.operations.len(), s.island.clone(), s.warnings.clone()))
    }

    /// Keeps `island`, after `operations`, as the latest state (dropping the oldest beyond two);
    /// its preview started after the first `resumed` operations.
    pub(crate) fn keep_island(
        &mut self,
        key: IslandKey,
        operations: &[Operation],
        island: Island,
        warnings: Vec<String>,
        resumed: usize,
    ) {
        self.resumed = resumed;
        if key.grid.len() > MAX_KEPT_CELLS {
            self.islands.clear();
            return;
        }
        self.islands.retain(|s| s.key == key && s.operations.as_slice() != operations);
        self.islands.push(IslandState { key, operations: operations.to_vec(), island, warnings });
        if self.islands.len() > KEPT {
            self.islands.remove(0);
        }
    }

    /// A preview starts: nothing resumed yet.
    pub(crate) fn begin(&mut self) {
        self.resumed = 0;
    }

    /// How many operations the last preview took from a kept island rather than applied (0: it
    /// replayed them all, or it was no island).
    pub fn resumed(&self) -> usize {
        self.resumed
    }

    /// How many island states it holds.
    pub fn kept(&self) -> usize {
        self.islands.len()
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec2;

    use super::*;
    use crate::heightfield::Extent;

    fn state(nx: usize, ny: usize, seed: u64) -> (IslandKey, Island) {
        let grid = GridSpec::from_extent(nx, ny, Extent::new(DVec2::ZERO, DVec2::splat(1000.0))).unwrap();
        let settings = IslandSettings::default();
        (IslandKey { grid, settings, seed }, Island::new(grid, settings, seed).unwrap())
    }

    /// Islands up to 2²⁰ cells are kept, larger ones are not (and clear what was kept).
    #[test]
    fn islands_are_kept_up_to_the_cell_cap() {
        let mut session = EditSession::new();
        let (key, island) = state(1024, 1024, 1);
        session.keep_island(key, &[], island, Vec::new(), 0);
        assert_eq!(session.kept(), 1);
        let (key, island) = state(1025, 1024, 1);
        session.keep_island(key, &[], island, Vec::new(), 0);
        assert_eq!(session.kept(), 0);
    }

    /// A state of another start (seed, grid, settings) is dropped when a new one is kept; two of
    /// the same start stay; a third pushes out the oldest.
    #[test]
    fn only_states_of_the_latest_start_are_kept() {
        let mut session = EditSession::new();
        let filters = |coverage: f64| vec![Operation::AddFilters { coverage }; 1];
        let (key, island) = state(8, 8, 1);
        session.keep_island(key.clone(), &filters(1.0), island.clone(), Vec::new(), 0);
        session.keep_island(key.clone(), &filters(2.0), island.clone(), Vec::new(), 0);
        assert_eq!(session.kept(), 2);
        session.keep_island(key.clone(), &filters(3.0), island.clone(), Vec::new(), 0);
        assert_eq!(session.kept(), 2);
        assert!(session.resume_island(&key, &filters(1.0)).is_none(), "the oldest went");
        assert_eq!(session.resume_island(&key, &filters(3.0)).map(|r| r.0), Some(1));
        let (other, island) = state(8, 8, 2);
        session.keep_island(other.clone(), &filters(4.0), island, Vec::new(), 0);
        assert_eq!(session.kept(), 1);
        assert!(session.resume_island(&key, &filters(3.0)).is_none());
        assert!(session.resume_island(&other, &filters(4.0)).is_some());
    }
}
