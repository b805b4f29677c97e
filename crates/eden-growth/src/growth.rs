use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use relief_tin::Tin;
use serde::{Deserialize, Serialize};

use crate::fenwick::Frontier;
use crate::{EdenError, Graph, ProbabilityMap};

/// Rank of a node outside Ω.
pub const UNRANKED: u32 = u32::MAX;

/// Weights are P / max P scaled to this many units (exact integer sums in the frontier).
const WEIGHT_SCALE: f64 = (1u64 << 30) as f64;

/// The result of growth: every inside node's order index (its rank), lowest first.
///
/// Ranks are contiguous per level — all nodes of level ℓ come before all nodes of level ℓ + 1 — so
/// every input contour is an iso-contour of any height assignment increasing with rank. Every node
/// outside a marked depression has a neighbour of lower rank, or is one of the first [`Growth::seeds`]
/// nodes (∂G ∩ level 1, ranked first in id order as in Algorithm 1): no endorheic basin.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Growth {
    order: Vec<u32>,
    rank: Vec<u32>,
    level_offsets: Vec<u32>,
    seeds: u32,
}

impl Growth {
    /// Inside nodes by increasing rank.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// Rank of every node ([`UNRANKED`] outside Ω).
    pub fn ranks(&self) -> &[u32] {
        &self.rank
    }

    /// Ranks of level `l` (1-based): `order()[range]` are that level's nodes.
    pub fn level_range(&self, l: u16) -> std::ops::Range<usize> {
        let l = l as usize;
        self.level_offsets[l - 1] as usize..self.level_offsets[l] as usize
    }

    /// Number of levels.
    pub fn levels(&self) -> u16 {
        (self.level_offsets.len() - 1) as u16
    }

    /// The first `seeds` ranked nodes are ∂G ∩ level 1.
    pub fn seeds(&self) -> usize {
        self.seeds as usize
    }

    /// Verifies this growth against the graph it was grown on; unit and property tests call it.
    ///
    /// Checked, in O(nodes + edges) without allocating beyond one count per level:
    /// - sizes: one rank per graph node, one level range per graph level, each level's range as
    ///   long as the graph's count of nodes at that level;
    /// - every inside node gets exactly one rank: `order` lists each node of level ≥ 1 once and
    ///   no outside node, and [`Growth::ranks`] is its inverse ([`UNRANKED`] outside Ω);
    /// - all of level ℓ ranks below level ℓ + 1: each node's rank lies in its level's range (what
    ///   [`Growth::level_range`] and the contours' level ends rely on);
    /// - the first [`Growth::seeds`] ranks are exactly ∂G ∩ level 1;
    /// - no endorheic basin: every other node outside a marked depression has a neighbour of
    ///   lower rank or outside Ω.
    ///
    /// # Errors
    /// [`EdenError::GrowthMismatch`] when the growth's sizes do not fit `graph`, otherwise
    /// [`EdenError::BrokenGrowth`] naming the first offending node.
    pub fn check_invariants(&self, graph: &Graph) -> Result<(), EdenError> {
        self.check_sizes(graph)?;
        self.check_ranks(graph.levels())?;
        self.check_levels(graph.levels())?;
        self.check_seeds(graph)?;
        self.check_drainage(graph)
    }

    /// Ranks for every node; level ranges as long as the graph's levels, in order.
    fn check_sizes(&self, graph: &Graph) -> Result<(), EdenError> {
        let mismatch = |reason: String| Err(EdenError::GrowthMismatch { reason });
        let (n, ranks) = (graph.levels().len(), self.rank.len());
        if ranks != n {
            return mismatch(format!("{ranks} ranks for {n} nodes"));
        }
        let max = usize::from(graph.max_level());
        if self.level_offsets.len() != max + 1 {
            return mismatch(format!("{} levels, the graph {max}", self.level_offsets.len().saturating_sub(1)));
        }
        let mut count = vec![0usize; max + 1];
        for &l in graph.levels() {
            count[usize::from(l)] += 1;
        }
        let mut end = 0;
        for (l, (&offset, &nodes)) in self.level_offsets.iter().zip(&count).enumerate() {
            end += if l == 0 { 0 } else { nodes };
            if offset as usize != end {
                return mismatch(format!(
                    "ranks below level {} end at {offset}, but the graph has {end} nodes there",
                    l + 1
                ));
            }
        }
        if self.order.len() != end {
            return mismatch(format!("{} nodes in the order, {end} inside the graph", self.order.len()));
        }
        Ok(())
    }

    /// `order` lists distinct inside nodes and `rank` inverts it; outside nodes are unranked.
    /// With the order as long as the inside count, that makes it a permutation of the inside.
    fn check_ranks(&self, levels: &[u16]) -> Result<(), EdenError> {
        for (k, &v) in self.order.iter().enumerate() {
            let reason = match (levels.get(v as usize), self.rank.get(v as usize)) {
                (None, _) | (_, None) => format!("rank {k} names a node past the graph's {}", levels.len()),
                (Some(0), _) => format!("outside Ω but listed at rank {k}"),
                (_, Some(&r)) if r as usize != k => format!("listed at rank {k} but its rank is {r}"),
                _ => continue,
            };
            return Err(EdenError::BrokenGrowth { node: v, reason });
        }
        if let Some(v) = (0..levels.len()).find(|&v| levels[v] == 0 && self.rank[v] != UNRANKED) {
            let reason = format!("outside Ω but has rank {}", self.rank[v]);
            return Err(EdenError::BrokenGrowth { node: v as u32, reason });
        }
        Ok(())
    }

    /// Every node's rank lies in its level's range.
    fn check_levels(&self, levels: &[u16]) -> Result<(), EdenError> {
        for (k, &v) in self.order.iter().enumerate() {
            let l = levels[v as usize];
            let range = self.level_range(l);
            if !range.contains(&k) {
                let reason = format!("level {l} at rank {k}, outside level {l}'s ranks {range:?}");
                return Err(EdenError::BrokenGrowth { node: v, reason });
            }
        }
        Ok(())
    }

    /// The seeds are ∂G ∩ level 1, all of it.
    fn check_seeds(&self, graph: &Graph) -> Result<(), EdenError> {
        let (levels, boundary) = (graph.levels(), graph.boundary());
        let seeds = self.seeds();
        if seeds > self.order.len() {
            let reason = format!("{seeds} seeds but {} ranked nodes", self.order.len());
            return Err(EdenError::GrowthMismatch { reason });
        }
        let seed_node = |v: u32| levels[v as usize] == 1 && boundary.binary_search(&v).is_ok();
        if let Some((k, &v)) = self.order[..seeds].iter().enumerate().find(|&(_, &v)| !seed_node(v)) {
            let reason = format!("seed (rank {k}) but not on ∂G ∩ level 1");
            return Err(EdenError::BrokenGrowth { node: v, reason });
        }
        if let Some(&v) = boundary.iter().find(|&&v| levels[v as usize] == 1 && self.rank[v as usize] as usize >= seeds)
        {
            let reason = format!("on ∂G ∩ level 1 but ranked {} after the {seeds} seeds", self.rank[v as usize]);
            return Err(EdenError::BrokenGrowth { node: v, reason });
        }
        Ok(())
    }

    /// Every node but the seeds and those in marked depressions has a lower neighbour.
    fn check_drainage(&self, graph: &Graph) -> Result<(), EdenError> {
        let (tin, ranks) = (graph.tin(), &self.rank);
        for (k, &v) in self.order.iter().enumerate().skip(self.seeds()) {
            if graph.depressions()[v as usize] {
                continue;
            }
            if !tin.neighbors(v).iter().any(|&w| ranks[w as usize] == UNRANKED || (ranks[w as usize] as usize) < k) {
                let reason = format!(
                    "rank {k}, level {}: no neighbour ranks lower, an endorheic basin outside any marked depression",
                    graph.levels()[v as usize]
                );
                return Err(EdenError::BrokenGrowth { node: v, reason });
            }
        }
        Ok(())
    }
}

/// How the levels of a multi-region graph grow (contours paper §4.5, Fig. 12).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub enum Fronts {
    /// The paper's method: a level with higher ground inside it grows from its lower and upper
    /// boundaries at once and orders its nodes by `n⁻ / (n⁻ + n⁺)`, so its contours follow the
    /// ranges and valleys inside it.
    #[default]
    Double,
    /// Fig. 12's baseline: Algorithm 1 applied to each level alone, from its lower boundary,
    /// blind to what lies above it (cliffs where a level meets a higher one).
    PerRegion,
}

/// Inward Open Eden Growth over `graph` (Algorithm 1 of the contours paper), by depth level with
/// the double-front scoring of §4.5 when a level has higher ground inside it.
///
/// Frontier selection is weighted by `probability` through a Fenwick tree of integer weights —
/// O(N log N) in total instead of the paper's O(N √N) linear scan — and the new node is drawn
/// uniformly among the selected node's unranked neighbours. Deterministic for a given `seed`.
///
/// # Errors
/// [`EdenError::InvalidProbability`] for a negative or non-finite value at a node,
/// [`EdenError::ZeroProbability`] when the map is zero on every inside node.
pub fn grow(graph: &Graph, probability: &(impl ProbabilityMap + ?Sized), seed: u64) -> Result<Growth, EdenError> {
    grow_with(graph, probability, seed, Fronts::Double)
}

/// [`grow`] with the choice of [`Fronts`].
///
/// # Errors
/// As [`grow`].
pub fn grow_with(
    graph: &Graph,
    probability: &(impl ProbabilityMap + ?Sized),
    seed: u64,
    fronts: Fronts,
) -> Result<Growth, EdenError> {
    let tin = graph.tin();
    let n = tin.num_points();
    let levels = graph.levels();
    let weight = weights(graph, probability)?;
    let mut state = State {
        tin,
        levels,
        frontier: Frontier::new(&weight),
        stamp: vec![0; n],
        run: 0,
        rng: ChaCha8Rng::seed_from_u64(seed),
        free: Vec::with_capacity(16),
        fronts,
    };
    let mut order = Vec::with_capacity(graph.inside_count());
    let mut level_offsets = vec![0u32];
    let mut n_minus = vec![0u32; n];
    let mut n_plus = vec![0u32; n];
    let boundary = graph.boundary();
    let seeds = boundary.iter().filter(|&&v| levels[v as usize] == 1).count() as u32;
    for l in 1..=graph.max_level() {
        let members: Vec<u32> = (0..n as u32).filter(|&v| levels[v as usize] == l).collect();
        if !members.is_empty() {
            let level_order = state.level(l, &members, boundary, &mut n_minus, &mut n_plus);
            order.extend_from_slice(&level_order);
        }
        level_offsets.push(order.len() as u32);
    }
    let mut rank = vec![UNRANKED; n];
    for (k, &v) in order.iter().enumerate() {
        rank[v as usize] = k as u32;
    }
    Ok(Growth { order, rank, level_offsets, seeds })
}

/// Open Eden Growth over part of a triangulation: the `members` nodes, from those beside a
/// non-member inward (§4.2), weighted by `probability`. Returns the members in growth order;
/// members no boundary node reaches (a part walled off by non-members) follow in id order.
/// For tools that regrow a region of a generated terrain (filling a contour's inside).
///
/// # Errors
/// [`EdenError::InvalidProbability`] and [`EdenError::ZeroProbability`] as [`grow`];
/// [`EdenError::GrowthMismatch`] when `members` is not one flag per node.
pub fn grow_within(
    tin: &Tin,
    members: &[bool],
    probability: &(impl ProbabilityMap + ?Sized),
    seed: u64,
) -> Result<Vec<u32>, EdenError> {
    let n = tin.num_points();
    if members.len() != n {
        return Err(EdenError::GrowthMismatch { reason: format!("{} member flags for {n} nodes", members.len()) });
    }
    let levels: Vec<u16> = members.iter().map(|&m| u16::from(m)).collect();
    let weight = node_weights(tin.points(), &levels, probability)?;
    let mut state = State {
        tin,
        levels: &levels,
        frontier: Frontier::new(&weight),
        stamp: vec![0; n],
        run: 0,
        rng: ChaCha8Rng::seed_from_u64(seed),
        free: Vec::with_capacity(16),
        fronts: Fronts::Double,
    };
    let seeds: Vec<u32> = (0..n as u32)
        .filter(|&v| members[v as usize] && tin.neighbors(v).iter().any(|&w| !members[w as usize]))
        .collect();
    let mut order = Vec::with_capacity(levels.iter().filter(|&&l| l == 1).count());
    state.run(1, &seeds, true, |v| order.push(v));
    let run = state.run;
    order.extend((0..n as u32).filter(|&v| members[v as usize] && state.stamp[v as usize] != run));
    Ok(order)
}

/// P at every node, validated and quantised to integer weights.
fn weights(graph: &Graph, probability: &(impl ProbabilityMap + ?Sized)) -> Result<Vec<u64>, EdenError> {
    node_weights(graph.tin().points(), graph.levels(), probability)
}

/// P at `points`, validated (at least one node of level ≥ 1 positive) and quantised.
fn node_weights(
    points: &[glam::DVec2],
    levels: &[u16],
    probability: &(impl ProbabilityMap + ?Sized),
) -> Result<Vec<u64>, EdenError> {
    let raw: Vec<f64> = points.par_iter().map(|&p| probability.probability(p)).collect();
    if let Some(k) = raw.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
        return Err(EdenError::InvalidProbability { x: points[k].x, y: points[k].y, value: raw[k] });
    }
    let max = raw.iter().zip(levels).filter(|(_, l)| **l >= 1).map(|(v, _)| *v).fold(0.0, f64::max);
    if max <= 0.0 {
        return Err(EdenError::ZeroProbability);
    }
    let top = raw.iter().copied().fold(max, f64::max);
    // Positive probabilities stay positive however small: only an explicit 0 means "never first".
    Ok(raw.iter().map(|&v| if v > 0.0 { ((v / top * WEIGHT_SCALE) as u64).max(1) } else { 0 }).collect())
}

/// A node's double-front score (§4.5) from the steps `n⁻` and `n⁺` at which the lower and upper
/// fronts reached it (0: never) in a level of `m` nodes: `n⁻ / (n⁻ + n⁺)`; `n⁻ / m` where the
/// upper front never arrives (a local maximum); `(m − n⁺) / m` where the lower never does (a
/// depression); ½ for a node neither reaches.
fn score(n_minus: u32, n_plus: u32, m: usize) -> f64 {
    let (a, b, m) = (f64::from(n_minus), f64::from(n_plus), m as f64);
    match (n_minus, n_plus) {
        (0, 0) => 0.5,
        (_, 0) => a / m,
        (0, _) => (m - b) / m,
        _ => a / (a + b),
    }
}

struct State<'a> {
    tin: &'a Tin,
    levels: &'a [u16],
    frontier: Frontier<'a>,
    stamp: Vec<u32>,
    run: u32,
    rng: ChaCha8Rng,
    free: Vec<u32>,
    fronts: Fronts,
}

impl State<'_> {
    /// One growth over the nodes of level `l` from `seeds` (ranked first when `pre_assign`),
    /// calling `visit` for each node as it is reached. Returns nothing: the frontier empties.
    fn run(&mut self, l: u16, seeds: &[u32], pre_assign: bool, mut visit: impl FnMut(u32)) {
        self.run += 1;
        let run = self.run;
        for &s in seeds {
            if pre_assign {
                self.stamp[s as usize] = run;
                visit(s);
            }
            self.frontier.insert(s);
        }
        while !self.frontier.is_empty() {
            let b = self.frontier.sample(&mut self.rng);
            self.free.clear();
            let (stamp, levels) = (&self.stamp, self.levels);
            self.free.extend(
                self.tin.neighbors(b).iter().copied().filter(|&w| stamp[w as usize] != run && levels[w as usize] == l),
            );
            match self.free.len() {
                0 => self.frontier.remove(b),
                k => {
                    let p = if k == 1 { self.free[0] } else { self.free[self.rng.random_range(0..k)] };
                    self.stamp[p as usize] = run;
                    visit(p);
                    self.frontier.insert(p);
                    if k == 1 {
                        // b had one free neighbour left: it is exhausted now.
                        self.frontier.remove(b);
                    }
                }
            }
        }
    }

    /// Nodes adjacent to a member of level `l` whose level satisfies `pick`, by increasing id.
    fn adjacent(&mut self, members: &[u32], pick: impl Fn(u16) -> bool) -> Vec<u32> {
        self.run += 1;
        let run = self.run;
        let mut out = Vec::new();
        for &v in members {
            for &w in self.tin.neighbors(v) {
                if pick(self.levels[w as usize]) && self.stamp[w as usize] != run {
                    self.stamp[w as usize] = run;
                    out.push(w);
                }
            }
        }
        out.sort_unstable();
        out
    }

    /// The order of level `l`'s nodes.
    fn level(
        &mut self,
        l: u16,
        members: &[u32],
        boundary: &[u32],
        n_minus: &mut [u32],
        n_plus: &mut [u32],
    ) -> Vec<u32> {
        let m = members.len();
        // Lower front: ∂G for the first level (ranked first, Algorithm 1), lower ground otherwise.
        let (lower, pre_assign) = if l == 1 {
            (boundary.iter().copied().filter(|&v| self.levels[v as usize] == 1).collect(), true)
        } else {
            (self.adjacent(members, |lw| lw < l), false)
        };
        let upper = match self.fronts {
            Fronts::Double => self.adjacent(members, |lw| lw > l),
            Fronts::PerRegion => Vec::new(),
        };
        let mut step = 0u32;
        let mut minus_order = Vec::with_capacity(m);
        for &v in members {
            n_minus[v as usize] = 0;
        }
        self.run(l, &lower, pre_assign, |v| {
            step += 1;
            n_minus[v as usize] = step;
            minus_order.push(v);
        });
        if upper.is_empty() {
            // Highest level here: standard inward growth (§4.5, first special case).
            let mut order = minus_order;
            order.extend(members.iter().copied().filter(|&v| n_minus[v as usize] == 0));
            return order;
        }
        let mut step = 0u32;
        for &v in members {
            n_plus[v as usize] = 0;
        }
        self.run(l, &upper, false, |v| {
            step += 1;
            n_plus[v as usize] = step;
        });
        let (n_minus, n_plus) = (&*n_minus, &*n_plus);
        let score = |v: u32| score(n_minus[v as usize], n_plus[v as usize], m);
        self.final_pass(l, members, &lower, pre_assign, score)
    }

    /// The pass that fixes the order (§4.5): from the lower front, always rank the frontier node of
    /// lowest score next, so every ranked node has a lower-ranked neighbour. Members it cannot
    /// reach (depression basins) are merged in by score.
    fn final_pass(
        &mut self,
        l: u16,
        members: &[u32],
        lower: &[u32],
        pre_assign: bool,
        score: impl Fn(u32) -> f64,
    ) -> Vec<u32> {
        self.run += 1;
        let run = self.run;
        let mut order = Vec::with_capacity(members.len());
        let mut heap = BinaryHeap::new();
        let push =
            |v: u32, stamp: &mut [u32], heap: &mut BinaryHeap<Reverse<(u64, u32)>>, tin: &Tin, levels: &[u16]| {
                for &w in tin.neighbors(v) {
                    if levels[w as usize] == l && stamp[w as usize] != run {
                        stamp[w as usize] = run;
                        // Scores are in [0, 1]: their bit patterns order like the values.
                        heap.push(Reverse((score(w).to_bits(), w)));
                    }
                }
            };
        for &s in lower {
            if pre_assign {
                self.stamp[s as usize] = run;
                order.push(s);
            }
        }
        for &s in lower {
            push(s, &mut self.stamp, &mut heap, self.tin, self.levels);
        }
        while let Some(Reverse((_, v))) = heap.pop() {
            order.push(v);
            push(v, &mut self.stamp, &mut heap, self.tin, self.levels);
        }
        if order.len() == members.len() {
            return order;
        }
        // Basins: interleave by score with the reachable nodes' relative positions, after the
        // seeds, which Algorithm 1 ranks first whatever the scores.
        let seeds = if pre_assign { lower.len() } else { 0 };
        let reached = (order.len() - seeds).max(1) as f64;
        let mut keyed: Vec<(f64, u32)> =
            order[seeds..].iter().enumerate().map(|(k, &v)| ((k as f64 + 0.5) / reached, v)).collect();
        keyed.extend(members.iter().copied().filter(|&v| self.stamp[v as usize] != run).map(|v| (score(v), v)));
        keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        order.truncate(seeds);
        order.extend(keyed.into_iter().map(|(_, v)| v));
        order
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec2;
    use relief_tin::poisson_sampling::Polygon;

    use super::*;
    use crate::{GraphOptions, Region, RegionTree, Uniform};

    /// A disc with a raised middle: two levels, a seed ring, a summit.
    fn grown() -> (Graph, Growth) {
        let coast = Region::new(Polygon::circle(DVec2::ZERO, 1000.0, 48).unwrap());
        let range = Region::new(Polygon::circle(DVec2::ZERO, 400.0, 32).unwrap());
        let tree = RegionTree::new(vec![coast, range]).unwrap();
        let graph = Graph::from_regions(&tree, &GraphOptions::particles(1_500).with_seed(4)).unwrap();
        let growth = grow(&graph, &Uniform, 9).unwrap();
        growth.check_invariants(&graph).unwrap();
        (graph, growth)
    }

    /// Swaps the ranks of the nodes at ranks `a` and `b`, keeping `order` and `rank` inverse.
    fn swap_ranks(g: &mut Growth, a: usize, b: usize) {
        g.order.swap(a, b);
        g.rank[g.order[a] as usize] = a as u32;
        g.rank[g.order[b] as usize] = b as u32;
    }

    #[track_caller]
    fn broken_at(graph: &Graph, growth: &Growth, node: u32, needle: &str) {
        match growth.check_invariants(graph) {
            Err(EdenError::BrokenGrowth { node: at, reason }) => {
                assert_eq!(at, node, "{reason}");
                assert!(reason.contains(needle), "{needle:?} not in {reason:?}");
            }
            other => panic!("expected node {node} ({needle}), got {other:?}"),
        }
    }

    #[test]
    fn double_front_scores() {
        // Both fronts: the share of the way from the lower boundary.
        assert_eq!(score(3, 1, 10), 0.75);
        assert_eq!(score(1, 3, 10), 0.25);
        // Only the lower front (a local maximum): its step over the level's size.
        assert_eq!(score(4, 0, 10), 0.4);
        // Only the upper front (a depression): ordered downward from the upper boundary.
        assert_eq!(score(0, 4, 10), 0.6);
        assert_eq!(score(0, 0, 10), 0.5);
    }

    #[test]
    fn corrupted_growths_fail_their_invariants() {
        let (graph, good) = grown();
        let (seeds, l1) = (good.seeds(), good.level_range(1));
        let (last, top) = (good.order.len() - 1, *good.order.last().unwrap());

        // Level 1's last node, deep inland by the range, ranked first after the seeds: nothing
        // ranks below it there.
        let mut bad = good.clone();
        swap_ranks(&mut bad, seeds, l1.end - 1);
        broken_at(&graph, &bad, bad.order[seeds], "endorheic basin");

        // A level-2 node among level 1.
        let mut bad = good.clone();
        swap_ranks(&mut bad, l1.end - 1, last);
        broken_at(&graph, &bad, top, "outside level 2's ranks");

        // A node ranked twice, another never.
        let mut bad = good.clone();
        bad.order[seeds + 1] = bad.order[seeds];
        broken_at(&graph, &bad, good.order[seeds], "listed at rank");

        // An outside node with a rank.
        let mut bad = good.clone();
        let outside = graph.levels().iter().position(|&l| l == 0).unwrap();
        bad.rank[outside] = 3;
        broken_at(&graph, &bad, outside as u32, "outside Ω but has rank 3");

        // One seed fewer: the last ∂G node is ranked after the seeds.
        let mut bad = good.clone();
        bad.seeds -= 1;
        broken_at(&graph, &bad, good.order[seeds - 1], "after the");

        // A non-boundary node among the seeds.
        let mut bad = good.clone();
        swap_ranks(&mut bad, 0, seeds);
        broken_at(&graph, &bad, good.order[seeds], "not on ∂G");

        // Level ranges that do not fit, and a growth of another graph.
        let mut bad = good.clone();
        bad.level_offsets[1] -= 1;
        assert!(matches!(bad.check_invariants(&graph), Err(EdenError::GrowthMismatch { .. })));
        let coast = Region::new(Polygon::circle(DVec2::ZERO, 1000.0, 48).unwrap());
        let other = Graph::from_regions(&RegionTree::new(vec![coast]).unwrap(), &GraphOptions::particles(700)).unwrap();
        let err = good.check_invariants(&other).unwrap_err();
        assert!(matches!(err, EdenError::GrowthMismatch { .. }), "{err}");
    }
}
