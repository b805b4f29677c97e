//! Typed errors of island editing.

use thiserror::Error;

/// What went wrong while building or editing an [`crate::Island`].
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum IslandError {
    /// The grid is too small or too large.
    #[error("grid of {nx} × {ny} samples: {reason}")]
    Grid {
        /// Samples along x.
        nx: usize,
        /// Samples along y.
        ny: usize,
        /// Why it is refused.
        reason: &'static str,
    },
    /// A coordinate or parameter is NaN or infinite.
    #[error("{what} is not finite")]
    NotFinite {
        /// Which value.
        what: &'static str,
    },
    /// A coastline with fewer than three distinct points, or no area.
    #[error("the coastline needs at least three distinct points enclosing an area (got {points} points)")]
    DegenerateCoastline {
        /// Points given.
        points: usize,
    },
    /// The first and last points of a drawn coastline are farther apart than the snap distance.
    #[error("the coastline is open: its ends are {gap:.3} apart (close it to within {snap:.3})")]
    OpenCoastline {
        /// Distance between the ends.
        gap: f64,
        /// The snap distance.
        snap: f64,
    },
    /// Two edges of the coastline (drawn, or produced by a stroke) cross.
    #[error("the coastline crosses itself near ({x:.3}, {y:.3})")]
    SelfIntersecting {
        /// Where, roughly.
        x: f64,
        /// Where, roughly.
        y: f64,
    },
    /// A stroke with fewer than two points.
    #[error("a stroke needs at least two points")]
    ShortStroke,
    /// A stroke that neither crosses the coast nor starts and ends near it.
    #[error("the stroke never touches the coastline (it must cross it or start and end within {snap:.3} of it)")]
    StrokeMissesCoast {
        /// The snap distance.
        snap: f64,
    },
    /// An edit that would remove the whole island.
    #[error("the edit leaves no land inside the domain")]
    NoLand,
    /// Bad hill parameters.
    #[error("hill: {reason}")]
    InvalidHill {
        /// Why.
        reason: &'static str,
    },
    /// A hill index that does not exist.
    #[error("there is no hill {index} (the island has {count})")]
    NoSuchHill {
        /// The index asked for.
        index: usize,
        /// Hills present.
        count: usize,
    },
    /// Bad settings or filter parameters.
    #[error("{name} = {value}: {reason}")]
    InvalidParameter {
        /// Which parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// Why it is refused.
        reason: &'static str,
    },
    /// The island's state breaks one of its invariants ([`crate::Island::check_invariants`]):
    /// a bug, never the user's input.
    #[error("island invariant broken: {0}")]
    Invariant(String),
    /// An operation of a replayed list failed.
    #[error("operation {index}: {source}")]
    Operation {
        /// Index of the operation in the list.
        index: usize,
        /// What went wrong.
        source: Box<IslandError>,
    },
}

impl IslandError {
    /// Where the offending value is, as a JSON path relative to the inputs laid out as a scene's
    /// `island` generator lays them out: `operations[3]` for a failed operation (its message says
    /// what in it), `settings.height`…; empty when the error concerns the grid or the island as a
    /// whole. The `relief` facade prefixes it with the generator's path.
    pub fn location(&self) -> String {
        match self {
            Self::Operation { index, .. } => format!("operations[{index}]"),
            Self::InvalidParameter { name, .. } => format!("settings.{name}"),
            _ => String::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_error_is_located_as_an_island_generator_lays_out_its_inputs() {
        let failed = IslandError::Operation { index: 3, source: Box::new(IslandError::ShortStroke) };
        assert_eq!(failed.location(), "operations[3]");
        let setting = IslandError::InvalidParameter { name: "land_floor", value: -1.0, reason: "must be positive" };
        assert_eq!(setting.location(), "settings.land_floor");
        assert_eq!(IslandError::ShortStroke.location(), "");
        assert_eq!(IslandError::NoLand.location(), "");
    }
}
