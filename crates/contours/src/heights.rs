use crate::{ContoursError, Histogram};

/// Nodes ranked by a growth (plain data, e.g. from `relief-eden-growth`): the order, where each
/// level's ranks end, and the explicit contour height of each level if the user gave one.
#[derive(Debug, Clone, Copy)]
pub struct Ranking<'a> {
    /// Inside nodes by increasing rank (lowest ground first).
    pub order: &'a [u32],
    /// `level_ends[l]` is the end (exclusive) of level `l + 1`'s ranks; the last equals `order.len()`.
    pub level_ends: &'a [usize],
    /// Explicit height of each level's boundary contour (`None`: free), one per level.
    pub level_heights: &'a [Option<f64>],
}

/// Heights of every node of the mesh and of the contours that bound each level.
#[derive(Debug, Clone, PartialEq)]
pub struct Heights {
    /// Height per node; nodes outside Ω (not in the ranking) are at [`Heights::outside`].
    pub heights: Vec<f64>,
    /// Height of the contour bounding each level from below (`[0]` is the coastline): the explicit
    /// height when given, else midway between the highest node below and the lowest node of the level.
    pub level_boundaries: Vec<f64>,
    /// Height given to nodes outside Ω: `h0 − ε`, just below the lowest inside node (§4.4), so the
    /// lowest contour closes around Ω.
    pub outside: f64,
}

/// Assigns heights from ranks by histogram quantiles: the node of rank `i` among `N` gets
/// `F⁻¹((i + ½)/N)` — the noise-free limit of the paper's sample-then-sort (§4.4), so the
/// heights match the histogram exactly and increase with rank (no endorheic basin can appear).
///
/// Explicit level heights split the histogram: the levels between two given heights share that
/// slice of the distribution, so every given contour is a true iso-contour at its height.
///
/// # Errors
/// [`ContoursError::InvalidRanking`] when the ranking is inconsistent with `num_nodes`, repeats a
/// node or its levels do not add up; [`ContoursError::InvalidLevelRequest`] when an explicit height
/// lies outside the histogram's range or heights do not increase.
pub fn assign_heights(
    num_nodes: usize,
    ranking: &Ranking<'_>,
    histogram: &Histogram,
) -> Result<Heights, ContoursError> {
    check_ranking(num_nodes, ranking)?;
    let anchors = anchors(ranking, histogram)?;
    let Ranking { order, level_ends, level_heights } = *ranking;
    let mut heights = quantile_heights(num_nodes, order, &anchors, histogram);
    let h0 = heights[order[0] as usize];
    let top = heights[order[order.len() - 1] as usize];
    let eps = if top > h0 { 1e-3 * (top - h0) } else { 1e-3 * h0.abs().max(1.0) };
    let outside = h0 - eps;
    for h in heights.iter_mut().filter(|h| h.is_nan()) {
        *h = outside;
    }
    let level_boundaries = (0..level_ends.len())
        .map(|l| {
            let start = if l == 0 { 0 } else { level_ends[l - 1] };
            level_heights[l].unwrap_or_else(|| {
                let below = if start == 0 { outside } else { heights[order[start - 1] as usize] };
                let first = order.get(start).map_or(below, |&v| heights[v as usize]);
                0.5 * (below + first)
            })
        })
        .collect();
    Ok(Heights { heights, level_boundaries, outside })
}

/// Checks that `ranking` ranks each of `num_nodes` nodes at most once, some at all, and that its
/// level ends increase to the number of ranked nodes, one per level height.
fn check_ranking(num_nodes: usize, ranking: &Ranking<'_>) -> Result<(), ContoursError> {
    let Ranking { order, level_ends, level_heights } = *ranking;
    let bad = |reason: String| Err(ContoursError::InvalidRanking { reason });
    if order.is_empty() {
        return bad("no ranked node".into());
    }
    if level_ends.len() != level_heights.len() || level_ends.last() != Some(&order.len()) {
        return bad(format!(
            "{} level ends and {} level heights for {} ranked nodes",
            level_ends.len(),
            level_heights.len(),
            order.len()
        ));
    }
    if level_ends.windows(2).any(|w| w[1] < w[0]) {
        return bad("level ends decrease".into());
    }
    let mut seen = vec![false; num_nodes];
    for &v in order {
        match seen.get_mut(v as usize) {
            None => return bad(format!("node {v} does not exist ({num_nodes} nodes)")),
            Some(s) if *s => return bad(format!("node {v} is ranked twice")),
            Some(s) => *s = true,
        }
    }
    Ok(())
}

/// The explicit level heights as anchors `(first rank of the level, height)`, checked to be
/// finite, inside the histogram's range and increasing.
fn anchors(ranking: &Ranking<'_>, histogram: &Histogram) -> Result<Vec<(usize, f64)>, ContoursError> {
    let mut anchors: Vec<(usize, f64)> = Vec::new();
    for (l, h) in ranking.level_heights.iter().enumerate() {
        let Some(h) = *h else { continue };
        if !h.is_finite() {
            return Err(ContoursError::NonFinite { what: "level height", value: h });
        }
        if h < histogram.min() || h > histogram.max() {
            return Err(ContoursError::InvalidLevelRequest {
                reason: format!(
                    "level {} has height {h}, outside the histogram's [{}, {}]",
                    l + 1,
                    histogram.min(),
                    histogram.max()
                ),
            });
        }
        if let Some(&(_, prev)) = anchors.last()
            && h <= prev
        {
            return Err(ContoursError::InvalidLevelRequest {
                reason: format!("level {} has height {h}, not above the previous given height {prev}", l + 1),
            });
        }
        anchors.push((if l == 0 { 0 } else { ranking.level_ends[l - 1] }, h));
    }
    Ok(anchors)
}

/// Heights of the ranked nodes (NaN for the others): the ranks between two anchors are mapped onto
/// their slice of the distribution, rank `i` of `m` in the slice `[f0, f1]` of the CDF getting
/// `F⁻¹(f0 + (i + ½)/m·(f1 − f0))`.
fn quantile_heights(num_nodes: usize, order: &[u32], anchors: &[(usize, f64)], histogram: &Histogram) -> Vec<f64> {
    let mut bounds: Vec<(usize, f64)> = vec![(0, 0.0)];
    for &(rank, h) in anchors {
        let f = histogram.cdf(h);
        match bounds.last_mut() {
            Some(last) if last.0 == rank => last.1 = f,
            _ => bounds.push((rank, f)),
        }
    }
    bounds.push((order.len(), 1.0));
    let mut heights = vec![f64::NAN; num_nodes];
    for w in bounds.windows(2) {
        let ((r0, f0), (r1, f1)) = (w[0], w[1]);
        let m = (r1 - r0) as f64;
        for (i, &v) in order[r0..r1].iter().enumerate() {
            heights[v as usize] = histogram.quantile(f0 + (i as f64 + 0.5) / m * (f1 - f0));
        }
    }
    heights
}
