//! Divide tree edits as data (§7.2): what a designer does to a generated tree before it becomes
//! terrain, saved and replayed with [`DivideTree::apply`].

use glam::DVec2;
use serde::{Deserialize, Serialize};

use crate::{DivideTree, OrometryError, TreePeak};

/// One edit of a divide tree. Indices refer to the tree as it is when the edit runs (after the
/// edits before it). In JSON, an object tagged by `"op"`: `{ "op": "delete_peak", "peak": 3 }`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "op", rename_all = "snake_case", deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub enum TreeEdit {
    /// Add a peak joined to `connect_to` through a new saddle ([`DivideTree::insert_peak`]).
    InsertPeak {
        /// Position `[x, y]`, metres.
        #[cfg_attr(feature = "schemars", schemars(with = "[f64; 2]"))]
        position: DVec2,
        /// Elevation, metres.
        elevation: f64,
        /// The peak its ridge leads to.
        connect_to: u32,
        /// The new saddle's position `[x, y]`.
        #[cfg_attr(feature = "schemars", schemars(with = "[f64; 2]"))]
        saddle: DVec2,
        /// The new saddle's elevation (not above either peak).
        saddle_elevation: f64,
    },
    /// Move a peak, optionally changing its elevation ([`DivideTree::move_peak`]).
    MovePeak {
        /// The peak.
        peak: u32,
        /// New position `[x, y]`.
        #[cfg_attr(feature = "schemars", schemars(with = "[f64; 2]"))]
        position: DVec2,
        /// New elevation.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        elevation: Option<f64>,
    },
    /// Move a saddle, optionally changing its elevation ([`DivideTree::move_saddle`]).
    MoveSaddle {
        /// The saddle.
        saddle: u32,
        /// New position `[x, y]`.
        #[cfg_attr(feature = "schemars", schemars(with = "[f64; 2]"))]
        position: DVec2,
        /// New elevation.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        elevation: Option<f64>,
    },
    /// Delete a peak; its neighbours stay joined ([`DivideTree::delete_peak`]).
    DeletePeak {
        /// The peak.
        peak: u32,
    },
    /// Delete a ridge (its saddle), splitting the tree ([`DivideTree::delete_ridge`]).
    DeleteRidge {
        /// The saddle.
        saddle: u32,
    },
}

impl DivideTree {
    /// Applies one edit; a refused edit leaves the tree unchanged.
    ///
    /// # Errors
    /// [`OrometryError::InvalidTree`] for an unknown peak or saddle, or a change that would leave
    /// a saddle above a peak it joins.
    pub fn apply(&mut self, edit: &TreeEdit) -> Result<(), OrometryError> {
        match *edit {
            TreeEdit::InsertPeak { position, elevation, connect_to, saddle, saddle_elevation } => {
                self.insert_peak(TreePeak { position, elevation }, connect_to, (saddle, saddle_elevation)).map(|_| ())
            }
            TreeEdit::MovePeak { peak, position, elevation } => self.move_peak(peak, position, elevation),
            TreeEdit::MoveSaddle { saddle, position, elevation } => self.move_saddle(saddle, position, elevation),
            TreeEdit::DeletePeak { peak } => self.delete_peak(peak),
            TreeEdit::DeleteRidge { saddle } => self.delete_ridge(saddle),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TreeSaddle;

    fn tree() -> DivideTree {
        let peak = |x: f64, elevation| TreePeak { position: DVec2::new(x, 0.0), elevation };
        DivideTree {
            peaks: vec![peak(0.0, 100.0), peak(10.0, 80.0), peak(20.0, 60.0)],
            saddles: vec![
                TreeSaddle { position: DVec2::new(5.0, 0.0), elevation: 50.0, peaks: [0, 1] },
                TreeSaddle { position: DVec2::new(15.0, 0.0), elevation: 40.0, peaks: [1, 2] },
            ],
        }
    }

    #[test]
    fn edits_read_from_json_do_what_the_tree_methods_do() {
        let edits: Vec<TreeEdit> = serde_json::from_str(
            r#"[
                {"op": "insert_peak", "position": [30, 0], "elevation": 70, "connect_to": 2, "saddle": [25, 0], "saddle_elevation": 45},
                {"op": "move_peak", "peak": 1, "position": [10, 3], "elevation": 85},
                {"op": "move_saddle", "saddle": 0, "position": [5, 1]},
                {"op": "delete_ridge", "saddle": 1},
                {"op": "delete_peak", "peak": 3}
            ]"#,
        )
        .unwrap();
        let mut applied = tree();
        let mut direct = tree();
        for edit in &edits {
            applied.apply(edit).unwrap();
        }
        direct
            .insert_peak(
                TreePeak { position: DVec2::new(30.0, 0.0), elevation: 70.0 },
                2,
                (DVec2::new(25.0, 0.0), 45.0),
            )
            .unwrap();
        direct.move_peak(1, DVec2::new(10.0, 3.0), Some(85.0)).unwrap();
        direct.move_saddle(0, DVec2::new(5.0, 1.0), None).unwrap();
        direct.delete_ridge(1).unwrap();
        direct.delete_peak(3).unwrap();
        assert_eq!(applied, direct);
        assert_eq!((applied.peaks.len(), applied.saddles.len()), (3, 1));
        // A refused edit leaves the tree as it was.
        let before = applied.clone();
        let above = TreeEdit::MoveSaddle { saddle: 0, position: DVec2::ZERO, elevation: Some(500.0) };
        assert!(applied.apply(&above).is_err());
        assert!(applied.apply(&TreeEdit::DeletePeak { peak: 9 }).is_err());
        assert_eq!(applied, before);
        // Round trip, and unknown fields refused.
        let text = serde_json::to_string(&edits).unwrap();
        assert_eq!(serde_json::from_str::<Vec<TreeEdit>>(&text).unwrap(), edits);
        assert!(serde_json::from_str::<TreeEdit>(r#"{"op": "delete_peak", "peak": 1, "ridge": 2}"#).is_err());
    }

    #[test]
    fn divide_trees_and_descriptors_read_from_json_are_validated() {
        let text = serde_json::to_string(&tree()).unwrap();
        assert_eq!(serde_json::from_str::<DivideTree>(&text).unwrap(), tree());
        // A saddle above the peaks it joins, or joining a missing peak, is refused on reading.
        let high = text.replace("\"elevation\":50.0", "\"elevation\":500.0");
        assert!(serde_json::from_str::<DivideTree>(&high).unwrap_err().to_string().contains("above peak"));
        let dangling = text.replace("[1,2]", "[1,7]");
        assert!(serde_json::from_str::<DivideTree>(&dangling).unwrap_err().to_string().contains("joins peaks 1 and 7"));
        let dem = relief_heightfield::Heightfield::from_fn(
            relief_heightfield::GridSpec::new(40, 40, DVec2::ZERO, DVec2::splat(30.0)).unwrap(),
            |p| 100.0 + 50.0 * ((p.x / 200.0).sin() * (p.y / 150.0).cos()) as f32,
        )
        .unwrap();
        let (_, descriptor) = crate::Descriptor::of(&dem, &crate::AnalysisOptions::default()).unwrap();
        let text = serde_json::to_string(&descriptor).unwrap();
        assert_eq!(serde_json::from_str::<crate::Descriptor>(&text).unwrap(), descriptor);
        let mut value: serde_json::Value = serde_json::from_str(&text).unwrap();
        value["prominence"]["fractions"][0] = serde_json::json!(7.0);
        let e = serde_json::from_value::<crate::Descriptor>(value).unwrap_err().to_string();
        assert!(e.contains("prominence"), "{e}");
    }
}
