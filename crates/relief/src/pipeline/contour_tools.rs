//! What a contour scene does to its generated terrain before extracting the contours: crater
//! depths, and the contour tools of `relief::tools` in the scene's order.

use super::contours::growth_seed;
use super::edits::{Tool, ToolKind};
use super::progress::Tick;
use crate::contours::{ContourSet, Heights};
use crate::eden_growth::{Graph, ProbabilityMap, RegionTree};
use crate::{ReliefError, ReliefError as E, tools};

/// Gives each depression with a `depth` that depth: its nodes' heights below its rim (the contour
/// of the level around it) are scaled so the deepest lies `depth` under the rim, their order kept.
pub(super) fn set_crater_depths(tree: &RegionTree, graph: &Graph, heights: &mut Heights) {
    let points = graph.tin().points();
    for (i, region) in tree.regions().iter().enumerate() {
        let (Some(depth), Some(parent)) = (region.depth, tree.parent(i)) else { continue };
        let rim = heights.level_boundaries[usize::from(tree.depth(parent)) - 1];
        let b = region.polygon.bounds();
        let nodes: Vec<usize> = (0..points.len())
            .filter(|&v| graph.depressions()[v] && b.contains(points[v]) && region.polygon.contains(points[v]))
            .collect();
        let floor = nodes.iter().map(|&v| heights.heights[v]).fold(rim, f64::min);
        if floor >= rim {
            continue;
        }
        for v in nodes {
            let h = &mut heights.heights[v];
            *h = rim - depth * (rim - h.min(rim)) / (rim - floor);
        }
    }
}

/// Applies the scene's contour tools to the node heights in order, each picking its contour on
/// the contours of the heights as they are then.
pub(super) fn apply_tools(
    graph: &Graph,
    heights: &mut [f64],
    tools: &[(usize, Tool)],
    extract: &dyn Fn(&[f64]) -> Result<ContourSet, ReliefError>,
    probability: &dyn ProbabilityMap,
    seed: u64,
    tick: &mut Tick<'_>,
) -> Result<(), ReliefError> {
    let tin = graph.tin();
    for (k, &(i, tool)) in tools.iter().enumerate() {
        let at = format!("edits[{i}].{}", tool.kind.name());
        let set = extract(heights)?;
        let Some(c) = tools::pick(&set, tool.at, tool.height) else {
            let reason = format!("no closed contour around ({}, {})", tool.at.x, tool.at.y);
            return Err(E::at(format!("{at}.at"), reason));
        };
        let seed = growth_seed(seed) ^ (k as u64 + 1).wrapping_mul(0xA24B_AED4_963E_E407);
        let fail = |e| E::at(&at, e);
        match tool.kind {
            ToolKind::Fill => tools::fill(tin, heights, &set, c, probability, seed).map_err(fail)?,
            ToolKind::Delete => tools::delete(tin, heights, &set, c, probability, seed).map_err(fail)?,
            ToolKind::Paste => {
                let source = heights.to_vec();
                tools::paste(tin, heights, &source, &set, c, tool.to - tool.at)
            }
            ToolKind::Cut => {
                let source = heights.to_vec();
                tools::delete(tin, heights, &set, c, probability, seed).map_err(fail)?;
                tools::paste(tin, heights, &source, &set, c, tool.to - tool.at)
            }
        };
        tick.tick();
        tick.check()?;
    }
    Ok(())
}
