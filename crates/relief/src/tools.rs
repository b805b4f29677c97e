//! Contour editing tools on a generated terrain (the contours paper, §6.6): pick a contour, then
//! fill (regrow its inside), delete it with everything inside, or paste (cut) its relief
//! elsewhere. They change the heights of the graph's nodes; the contours are extracted again
//! from them, so nesting and the absence of crossings hold by construction.
//!
//! ```
//! use glam::DVec2;
//! use relief::contours::{Histogram, Ranking, assign_heights, extract_tin};
//! use relief::eden_growth::{Graph, GraphOptions, Region, RegionTree, Uniform, grow};
//! use relief::poisson_sampling::Polygon;
//! use relief::tools;
//!
//! // An island with a hill; delete the hill's 300 m contour and everything inside it.
//! let coast = Region::new(Polygon::circle(DVec2::ZERO, 1000.0, 64)?);
//! let hill = Region::new(Polygon::circle(DVec2::new(300.0, 0.0), 250.0, 32)?);
//! let graph = Graph::from_regions(&RegionTree::new(vec![coast, hill])?, &GraphOptions::particles(4_000))?;
//! let growth = grow(&graph, &Uniform, 1)?;
//! let ends: Vec<usize> = (1..=growth.levels()).map(|l| growth.level_range(l).end).collect();
//! let ranking = Ranking { order: growth.order(), level_ends: &ends, level_heights: &graph.level_heights()[1..] };
//! let histogram = Histogram::uniform(0.0, 600.0)?;
//! let mut heights = assign_heights(graph.tin().num_points(), &ranking, &histogram)?.heights;
//! let levels = [100.0, 200.0, 300.0, 400.0, 500.0];
//! let set = extract_tin(graph.tin(), &heights, &levels)?;
//! let pick = tools::pick(&set, DVec2::new(300.0, 0.0), Some(300.0)).expect("a contour around the hill");
//! assert_eq!(set.contours()[pick].height, 300.0);
//! let changed = tools::delete(graph.tin(), &mut heights, &set, pick, &Uniform, 7)?;
//! assert!(changed > 0);
//! let after = extract_tin(graph.tin(), &heights, &levels)?;
//! // Nothing above 300 m is left around the hill's centre.
//! let top = tools::pick(&after, DVec2::new(300.0, 0.0), Some(1000.0)).expect("the 300 m contour");
//! assert_eq!(after.contours()[top].height, 300.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use glam::DVec2;

use crate::contours::ContourSet;
use crate::eden_growth::{EdenError, ProbabilityMap, grow_within};
use crate::poisson_sampling::Polygon;
use crate::tin::{PointLocator, Tin};

/// A closed contour of `set` around `at`: the one whose height is nearest `height` when given
/// (the innermost of equals), else the innermost.
pub fn pick(set: &ContourSet, at: DVec2, height: Option<f64>) -> Option<usize> {
    let around = set
        .contours()
        .iter()
        .enumerate()
        .filter(|(_, c)| c.closed && c.bounds().contains(at))
        .filter(|(_, c)| Polygon::from_exterior(c.points.clone()).is_ok_and(|p| p.contains(at)));
    let key = |c: &crate::contours::Contour| (height.map_or(0.0, |h| (c.height - h).abs()), c.signed_area().abs());
    around.min_by(|a, b| key(a.1).partial_cmp(&key(b.1)).unwrap_or(std::cmp::Ordering::Equal)).map(|(k, _)| k)
}

/// Which nodes of `tin` lie inside contour `k` of `set`, shifted by `offset` (the nodes `q` with
/// `q − offset` inside).
fn inside(tin: &Tin, set: &ContourSet, k: usize, offset: DVec2) -> Vec<bool> {
    let c = &set.contours()[k];
    let Ok(polygon) = Polygon::from_exterior(c.points.clone()) else { return vec![false; tin.num_points()] };
    let b = c.bounds();
    tin.points()
        .iter()
        .map(|&q| {
            let p = q - offset;
            b.contains(p) && polygon.contains(p)
        })
        .collect()
}

/// The nodes inside contour `k` in a new growth order from the contour inward; `None` when it
/// holds none.
fn regrowth(
    tin: &Tin,
    set: &ContourSet,
    k: usize,
    probability: &(impl ProbabilityMap + ?Sized),
    seed: u64,
) -> Result<Option<Vec<u32>>, EdenError> {
    let members = inside(tin, set, k, DVec2::ZERO);
    if !members.iter().any(|&m| m) {
        return Ok(None);
    }
    grow_within(tin, &members, probability, seed).map(Some)
}

/// Regrows the inside of contour `k`: its nodes, grown anew from the contour inward (weighted by
/// `probability`), take their own heights again in rank order — the same elevations, a new shape.
/// Returns how many nodes changed.
///
/// # Errors
/// As [`grow_within`].
pub fn fill(
    tin: &Tin,
    heights: &mut [f64],
    set: &ContourSet,
    k: usize,
    probability: &(impl ProbabilityMap + ?Sized),
    seed: u64,
) -> Result<usize, EdenError> {
    let Some(order) = regrowth(tin, set, k, probability, seed)? else { return Ok(0) };
    let mut values: Vec<f64> = order.iter().map(|&v| heights[v as usize]).collect();
    values.sort_by(f64::total_cmp);
    let mut changed = 0;
    for (&v, h) in order.iter().zip(values) {
        changed += usize::from(heights[v as usize] != h);
        heights[v as usize] = h;
    }
    Ok(changed)
}

/// Deletes contour `k` and every contour inside it: its inside, regrown from the contour inward,
/// rises evenly from the contour's height to nine tenths of the way to the next level of `set`
/// above it (a pit is filled the same way). Returns how many nodes changed.
///
/// # Errors
/// As [`grow_within`].
pub fn delete(
    tin: &Tin,
    heights: &mut [f64],
    set: &ContourSet,
    k: usize,
    probability: &(impl ProbabilityMap + ?Sized),
    seed: u64,
) -> Result<usize, EdenError> {
    let Some(order) = regrowth(tin, set, k, probability, seed)? else { return Ok(0) };
    let h = set.contours()[k].height;
    let inside_max = order.iter().map(|&v| heights[v as usize]).fold(h, f64::max);
    let next = set.levels().iter().copied().find(|&l| l > h).unwrap_or(inside_max.max(h + 1.0));
    let n = order.len() as f64;
    for (rank, &v) in order.iter().enumerate() {
        heights[v as usize] = h + 0.9 * (next - h) * (rank as f64 + 1.0) / (n + 1.0);
    }
    Ok(order.len())
}

/// Adds the relief inside contour `k` (each point's height above the contour; below it, for a
/// pit) to the terrain at `offset` from it. The relief is read from `source`, the heights before
/// any change. Returns how many nodes changed.
pub fn paste(tin: &Tin, heights: &mut [f64], source: &[f64], set: &ContourSet, k: usize, offset: DVec2) -> usize {
    let c = &set.contours()[k];
    let raised = c.is_counter_clockwise();
    let targets = inside(tin, set, k, offset);
    let locator = PointLocator::new(tin);
    let mut changed = 0;
    for (v, _) in targets.iter().enumerate().filter(|(_, t)| **t) {
        let Ok(Some(z)) = locator.interpolate(tin.points()[v] - offset, source) else { continue };
        let bump = if raised { (z - c.height).max(0.0) } else { (z - c.height).min(0.0) };
        if bump != 0.0 {
            heights[v] += bump;
            changed += 1;
        }
    }
    changed
}
