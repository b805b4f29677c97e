//! The landform and crest tools (§5) as data: a [`Tool`] is one editing operation, so a list of
//! them is an editing session that saves as JSON and replays with [`Tool::apply`].

use std::path::{Path, PathBuf};

use glam::DVec2;
use serde::{Deserialize, Serialize};

use crate::{GaussianError, Landform, Placement, Region, Skeleton, StampMode, VectorTerrain, paste, squeeze, stamp};

/// One tool operation on a vector terrain (§5). In JSON, an object tagged by `"op"`:
/// `{ "op": "twist", "region": …, "angle": 0.5, "falloff": 40 }`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "op", rename_all = "snake_case", deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub enum Tool {
    /// Move (or copy) the primitives centred in `region` to `placement`, damping the primitives
    /// under the destination within `damping` of its border (∞: vanish them all) — [`stamp`].
    Stamp {
        /// The selection.
        region: Region,
        /// Where the region's anchor goes, turned and scaled.
        placement: Placement,
        /// Move (default) or copy.
        #[serde(default)]
        mode: StampMode,
        /// Damping radius, world units.
        damping: f64,
    },
    /// Paste a landform from an atlas file (or, without `atlas`, from the session's own atlas
    /// that `copy` and `cut` fill) with a circular footprint of radius `footprint` around its
    /// anchor — [`paste`].
    Paste {
        /// The atlas JSON; a relative path is resolved by whoever applies the tool (a scene
        /// resolves it against the scene file's directory). Absent: the session's atlas.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        #[cfg_attr(feature = "schemars", schemars(with = "Option<String>"))]
        atlas: Option<PathBuf>,
        /// The landform's name.
        landform: String,
        /// Footprint radius around the landform's anchor, world units.
        footprint: f64,
        /// Where the anchor goes, turned and scaled.
        placement: Placement,
        /// Damping radius, world units.
        damping: f64,
    },
    /// Save the primitives centred in `region` to the session's atlas as `name`, anchored at
    /// the region's anchor (a later `paste` without `atlas` takes it; a scene's
    /// `outputs.atlas` writes the session's atlas) — [`crate::copy`].
    Copy {
        /// The selection.
        region: Region,
        /// The landform's name (a later copy of the same name replaces it).
        name: String,
    },
    /// [`Tool::Copy`], then delete the selection — [`crate::cut`].
    Cut {
        /// The selection.
        region: Region,
        /// The landform's name (a later copy of the same name replaces it).
        name: String,
    },
    /// Delete the primitives centred in `region` — [`crate::delete`].
    Delete {
        /// The selection.
        region: Region,
    },
    /// Twist the primitives in `region` about its anchor by up to `angle` radians —
    /// [`crate::twist`].
    Twist {
        /// The region.
        region: Region,
        /// Rotation at the region's rim before fall-off, radians.
        angle: f64,
        /// Fall-off width inside the border, world units.
        falloff: f64,
    },
    /// Squeeze: move the primitives in `region` by `by`, faded towards the border — [`squeeze`].
    Squeeze {
        /// The region.
        region: Region,
        /// Translation `[x, y]`.
        by: [f64; 2],
        /// Fall-off width inside the border, world units.
        falloff: f64,
    },
    /// Move a crest skeleton node (`node`, or the one nearest `near`) by `by`; the rest of the
    /// crest follows with the graph attenuation — [`Skeleton::move_node`].
    MoveCrest {
        /// A point near the node (give this or `node`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        near: Option<[f64; 2]>,
        /// The node's id: its index in the skeleton a scene's `outputs.skeleton` exports.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        node: Option<usize>,
        /// Translation `[x, y]`.
        by: [f64; 2],
        /// Graph distance the change reaches (default: the whole graph).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        reach: Option<f64>,
        /// Influence radius around the convex hull of the moved primitives: the others there
        /// are damped so the moved crest does not pile onto them — [`crate::damp_around`]
        /// (default: none).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        damping: Option<f64>,
    },
    /// Scale the amplitude around a crest node (`node`, or the one nearest `near`):
    /// `a' = a(α·factor + 1)` — [`Skeleton::scale_amplitude`].
    RaiseCrest {
        /// A point near the node (give this or `node`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        near: Option<[f64; 2]>,
        /// The node's id: its index in the skeleton a scene's `outputs.skeleton` exports.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        node: Option<usize>,
        /// `u ≥ −1`: 1 doubles the crest there, −1 flattens it.
        factor: f64,
        /// Graph distance the change reaches (default: the whole graph).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        reach: Option<f64>,
    },
}

/// What the tools need beyond the terrain, supplied by whoever replays them: atlas files, the
/// session's own atlas and the crest skeleton (its crest cells come from flow routing, which
/// lives above this crate).
pub trait ToolContext {
    /// Why the context could not supply something (a file, a budget, the routing).
    type Error;

    /// The landform `name` of the atlas file `atlas` (`None`: the session's atlas, which
    /// [`ToolContext::keep`] fills), about to be pasted into `terrain`.
    ///
    /// # Errors
    /// The context's own, e.g. an unreadable atlas, no such landform, or a paste that would
    /// exceed a budget.
    fn landform(&mut self, atlas: Option<&Path>, name: &str, terrain: &VectorTerrain) -> Result<Landform, Self::Error>;

    /// Keeps a copied or cut landform in the session's atlas, replacing one of the same name.
    ///
    /// # Errors
    /// The context's own, e.g. an atlas over a budget.
    fn keep(&mut self, landform: Landform) -> Result<(), Self::Error>;

    /// The crest skeleton of `terrain` for the crest tools: extracted on first use, then kept
    /// (the tools edit it in place, so later crest edits follow earlier ones).
    ///
    /// # Errors
    /// The context's own.
    fn skeleton(&mut self, terrain: &VectorTerrain) -> Result<&mut Skeleton, Self::Error>;
}

/// Why [`Tool::apply`] failed: the tool refused its parameters, or the context failed.
#[derive(Debug)]
pub enum ToolError<E> {
    /// The tool's own error.
    Tool(GaussianError),
    /// The context's error.
    Context(E),
}

impl<E> From<GaussianError> for ToolError<E> {
    fn from(e: GaussianError) -> Self {
        Self::Tool(e)
    }
}

impl Tool {
    /// Applies the tool to `terrain`.
    ///
    /// # Errors
    /// [`ToolError::Tool`] with the tool function's error (an invalid region, a bad placement, a
    /// crest tool on a terrain without crest nodes); [`ToolError::Context`] with the context's.
    pub fn apply<C: ToolContext>(&self, terrain: &mut VectorTerrain, cx: &mut C) -> Result<(), ToolError<C::Error>> {
        match self {
            Self::Stamp { region, placement, mode, damping } => {
                stamp(terrain, region, placement, *mode, *damping)?;
            }
            Self::Paste { atlas, landform, footprint, placement, damping } => {
                let landform = cx.landform(atlas.as_deref(), landform, terrain).map_err(ToolError::Context)?;
                let footprint = Region::Circle { center: [0.0, 0.0], radius: *footprint };
                paste(terrain, &landform, &footprint, placement, *damping)?;
            }
            Self::Copy { region, name } => {
                cx.keep(crate::copy(terrain, region, name)?).map_err(ToolError::Context)?;
            }
            Self::Cut { region, name } => {
                cx.keep(crate::cut(terrain, region, name)?).map_err(ToolError::Context)?;
            }
            Self::Delete { region } => {
                crate::delete(terrain, region)?;
            }
            Self::Twist { region, angle, falloff } => {
                crate::twist(terrain, region, *angle, *falloff)?;
            }
            Self::Squeeze { region, by, falloff } => {
                squeeze(terrain, region, DVec2::from(*by), *falloff)?;
            }
            Self::MoveCrest { near, node, by, reach, damping } => {
                let skeleton = cx.skeleton(terrain).map_err(ToolError::Context)?;
                let (node, attached) = crest_node(skeleton, terrain, *near, *node)?;
                let before = damping.map(|_| terrain.primitives.clone());
                skeleton.move_node(terrain, &attached, node, DVec2::from(*by), *reach)?;
                if let (Some(radius), Some(before)) = (damping, before) {
                    let moved: Vec<usize> = (0..before.len()).filter(|&k| before[k] != terrain.primitives[k]).collect();
                    crate::damp_around(terrain, &moved, *radius)?;
                }
            }
            Self::RaiseCrest { near, node, factor, reach } => {
                let skeleton = cx.skeleton(terrain).map_err(ToolError::Context)?;
                let (node, attached) = crest_node(skeleton, terrain, *near, *node)?;
                skeleton.scale_amplitude(terrain, &attached, node, *factor, *reach)?;
            }
        }
        Ok(())
    }
}

/// The skeleton node a crest tool names (`node`, or the one nearest `near`: exactly one of
/// them) and the primitives' attachments to the skeleton.
fn crest_node(
    skeleton: &Skeleton,
    terrain: &VectorTerrain,
    near: Option<[f64; 2]>,
    node: Option<usize>,
) -> Result<(usize, Vec<Option<crate::Attachment>>), GaussianError> {
    if skeleton.nodes.is_empty() {
        return Err(GaussianError::InvalidSkeleton {
            reason: "the terrain has no crest skeleton (lower the skeleton's min_cells)",
        });
    }
    let node = match (near, node) {
        (Some(p), None) => skeleton.nearest_node(DVec2::from(p)).unwrap_or(0),
        (None, Some(id)) if id < skeleton.nodes.len() => id,
        (None, Some(id)) => {
            return Err(GaussianError::NoSuchNode { node: id, nodes: skeleton.nodes.len() });
        }
        _ => {
            return Err(GaussianError::InvalidSkeleton { reason: "a crest tool needs exactly one of near and node" });
        }
    };
    Ok((node, skeleton.attach(terrain)))
}
