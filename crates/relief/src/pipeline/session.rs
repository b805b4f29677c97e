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
