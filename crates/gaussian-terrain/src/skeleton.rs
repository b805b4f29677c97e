//! Skeleton tools (§5.1): a crest graph, its simplification by edge collapse, primitives
//! attached to its edges, and deformations propagated along it with the attenuation
//! `αᵢ = s(1 − l(π(cᵢ))/d_m)`.
//!
//! The crest cells come from a river detection on the inverted DEM, which is the hydrology
//! crate's job; this crate sits below it, so [`Skeleton::from_flow`] takes the crest cells and
//! their downstream links (the `relief` facade's `crest_skeleton` computes them from a DEM).
//! Links follow the flow on the inverted DEM, so the initial graph is a forest.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::{DMat2, DVec2};
use serde::{Deserialize, Serialize};

use crate::primitive::stretch_along;
use crate::region::smoothstep;
use crate::{GaussianError, VectorTerrain};

/// A geometric graph used as a manipulation skeleton: nodes in the plane, undirected edges.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Skeleton {
    /// Node positions `[x, y]`.
    pub nodes: Vec<[f64; 2]>,
    /// Edges as node index pairs.
    pub edges: Vec<[usize; 2]>,
}

/// How a crest skeleton is extracted from a terrain rasterized on a grid (§5.1): crest cells are
/// those draining at least `min_cells` cells on the inverted DEM, and the graph is simplified by
/// edge collapse at node spacing `spacing`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct SkeletonOptions {
    /// Flow accumulation (cells, on the inverted DEM) that makes a crest cell (default: 0.2 % of
    /// the raster's cells, at least 4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_cells: Option<u32>,
    /// Node spacing after edge collapse, world units (default: 3 % of the grid's longer side).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spacing: Option<f64>,
}

impl SkeletonOptions {
    /// `(min_cells, spacing)` for a raster of `cells` samples whose longer side spans `size`
    /// world units, defaults filled in.
    pub fn resolve(&self, cells: usize, size: f64) -> (u32, f64) {
        let min_cells = self.min_cells.unwrap_or_else(|| (cells / 500).max(4) as u32);
        (min_cells, self.spacing.unwrap_or(0.03 * size))
    }
}

/// Where a primitive hangs on the skeleton: its centre's projection on an edge.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Attachment {
    /// The edge.
    pub edge: usize,
    /// Position of the projection along the edge, 0 at its first node, 1 at its second.
    pub t: f64,
    /// Distance from the centre to its projection.
    pub distance: f64,
}

#[derive(PartialEq)]
struct Candidate {
    length: f64,
    a: usize,
    b: usize,
    stamp: (u32, u32),
}

impl Eq for Candidate {}

impl PartialOrd for Candidate {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Candidate {
    // A min-heap on length, ties broken by the node indices: deterministic.
    fn cmp(&self, other: &Self) -> Ordering {
        other.length.total_cmp(&self.length).then_with(|| (other.a, other.b).cmp(&(self.a, self.b)))
    }
}

impl Skeleton {
    /// The crest graph: one node per crest cell at `points[k]`, an edge to its downstream
    /// neighbour `down[k]` on the inverted DEM when that is a crest cell too.
    ///
    /// # Errors
    /// [`GaussianError::InvalidSkeleton`] when the lengths differ, a link points outside the
    /// list or a point is not finite.
    pub fn from_flow(points: &[DVec2], down: &[Option<usize>]) -> Result<Self, GaussianError> {
        if points.len() != down.len() {
            return Err(GaussianError::InvalidSkeleton { reason: "points and links differ in length" });
        }
        if points.iter().any(|p| !p.is_finite()) {
            return Err(GaussianError::InvalidSkeleton { reason: "a point is not finite" });
        }
        let mut edges = Vec::new();
        for (k, d) in down.iter().enumerate() {
            if let Some(d) = *d {
                if d >= points.len() {
                    return Err(GaussianError::InvalidSkeleton { reason: "a link points past the list" });
                }
                if d != k {
                    edges.push([k.min(d), k.max(d)]);
                }
            }
        }
        edges.sort_unstable();
        edges.dedup();
        Ok(Self { nodes: points.iter().map(DVec2::to_array).collect(), edges })
    }

    /// Checks indices and coordinates.
    ///
    /// # Errors
    /// [`GaussianError::InvalidSkeleton`].
    pub fn validate(&self) -> Result<(), GaussianError> {
        if self.nodes.iter().flatten().any(|v| !v.is_finite()) {
            return Err(GaussianError::InvalidSkeleton { reason: "a node is not finite" });
        }
        if self.edges.iter().flatten().any(|&k| k >= self.nodes.len()) {
            return Err(GaussianError::InvalidSkeleton { reason: "an edge names a missing node" });
        }
        Ok(())
    }

    fn node(&self, k: usize) -> DVec2 {
        DVec2::from(self.nodes[k])
    }

    /// Edge collapse (§5.1): while an edge is shorter than `d0`, its two nodes merge into one at
    /// their weighted mean (weights count the cells merged). The paper's text says "larger";
    /// merging the short edges is what gives the evenly spaced nodes it describes.
    #[must_use]
    pub fn simplified(&self, d0: f64) -> Skeleton {
        let n = self.nodes.len();
        let mut pos: Vec<DVec2> = (0..n).map(|k| self.node(k)).collect();
        let mut weight = vec![1.0f64; n];
        let mut alive = vec![true; n];
        let mut stamp = vec![0u32; n];
        let mut adjacency: Vec<Vec<usize>> = vec![Vec::new(); n];
        for &[a, b] in &self.edges {
            if a != b {
                adjacency[a].push(b);
                adjacency[b].push(a);
            }
        }
        let mut heap = BinaryHeap::new();
        for &[a, b] in &self.edges {
            if a != b {
                heap.push(Candidate { length: pos[a].distance(pos[b]), a, b, stamp: (0, 0) });
            }
        }
        while let Some(Candidate { length, a, b, stamp: s }) = heap.pop() {
            if !(alive[a] && alive[b]) || s != (stamp[a], stamp[b]) || !adjacency[a].contains(&b) {
                continue;
            }
            if length >= d0 {
                break;
            }
            // Merge b into a.
            let w = weight[a] + weight[b];
            pos[a] = (pos[a] * weight[a] + pos[b] * weight[b]) / w;
            weight[a] = w;
            alive[b] = false;
            let moved: Vec<usize> = std::mem::take(&mut adjacency[b]);
            for c in moved {
                adjacency[c].retain(|&x| x != b);
                if c != a && !adjacency[a].contains(&c) {
                    adjacency[a].push(c);
                    adjacency[c].push(a);
                }
            }
            adjacency[a].retain(|&x| x != b);
            // Old candidates with `a` are stale now; the pairs (a, c) are queued afresh.
            stamp[a] += 1;
            for &c in &adjacency[a].clone() {
                let (x, y) = (a.min(c), a.max(c));
                heap.push(Candidate { length: pos[a].distance(pos[c]), a: x, b: y, stamp: (stamp[x], stamp[y]) });
            }
        }
        let mut index = vec![usize::MAX; n];
        let mut nodes = Vec::new();
        for k in 0..n {
            if alive[k] {
                index[k] = nodes.len();
                nodes.push(pos[k].to_array());
            }
        }
        let index = &index;
        let mut edges: Vec<[usize; 2]> = (0..n)
            .filter(|&k| alive[k])
            .flat_map(|k| adjacency[k].iter().filter(move |&&c| c > k).map(move |&c| [index[k], index[c]]))
            .collect();
        edges.sort_unstable();
        Skeleton { nodes, edges }
    }

    /// The node nearest to `p`, if any.
    pub fn nearest_node(&self, p: DVec2) -> Option<usize> {
        (0..self.nodes.len())
            .min_by(|&a, &b| self.node(a).distance_squared(p).total_cmp(&self.node(b).distance_squared(p)))
    }

    /// Attaches every primitive of `terrain` to its nearest edge (§5.1); `None` when the
    /// skeleton has no edge.
    pub fn attach(&self, terrain: &VectorTerrain) -> Vec<Option<Attachment>> {
        terrain
            .primitives
            .iter()
            .map(|g| {
                let c = DVec2::from(g.center);
                let mut best: Option<Attachment> = None;
                for (e, &[a, b]) in self.edges.iter().enumerate() {
                    let (pa, pb) = (self.node(a), self.node(b));
                    let d = pb - pa;
                    let t = if d.length_squared() > 0.0 {
                        ((c - pa).dot(d) / d.length_squared()).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    let distance = c.distance(pa + d * t);
                    if best.is_none_or(|b| distance < b.distance) {
                        best = Some(Attachment { edge: e, t, distance });
                    }
                }
                best
            })
            .collect()
    }

    /// Graph distances from node `from` along the edges (Dijkstra); ∞ where unreachable.
    pub fn graph_distances(&self, from: usize) -> Vec<f64> {
        let n = self.nodes.len();
        let mut adjacency: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        for &[a, b] in &self.edges {
            let l = self.node(a).distance(self.node(b));
            adjacency[a].push((b, l));
            adjacency[b].push((a, l));
        }
        let mut dist = vec![f64::INFINITY; n];
        if from >= n {
            return dist;
        }
        dist[from] = 0.0;
        let mut heap = BinaryHeap::new();
        heap.push(Candidate { length: 0.0, a: from, b: from, stamp: (0, 0) });
        while let Some(Candidate { length, a, .. }) = heap.pop() {
            if length > dist[a] {
                continue;
            }
            for &(b, l) in &adjacency[a] {
                if length + l < dist[b] {
                    dist[b] = length + l;
                    heap.push(Candidate { length: dist[b], a: b, b, stamp: (0, 0) });
                }
            }
        }
        dist
    }

    /// Attenuations of the nodes and of the attached primitives for a change at node `node`:
    /// `α = s(1 − l/d_m)` with `l` the graph distance (to the projection, for primitives) and
    /// `d_m` the given reach or, by default, the largest finite graph distance (§5.1).
    fn attenuation(&self, node: usize, attached: &[Option<Attachment>], reach: Option<f64>) -> (Vec<f64>, Vec<f64>) {
        let dist = self.graph_distances(node);
        let d_m = reach
            .unwrap_or_else(|| dist.iter().copied().filter(|d| d.is_finite()).fold(0.0, f64::max))
            .max(f64::MIN_POSITIVE);
        let alpha = |l: f64| if l.is_finite() { smoothstep(1.0 - l / d_m) } else { 0.0 };
        let nodes: Vec<f64> = dist.iter().map(|&l| alpha(l)).collect();
        let prims = attached
            .iter()
            .map(|a| {
                a.map_or(0.0, |a| {
                    let [p, q] = self.edges[a.edge];
                    let len = self.node(p).distance(self.node(q));
                    alpha((dist[p] + a.t * len).min(dist[q] + (1.0 - a.t) * len))
                })
            })
            .collect();
        (nodes, prims)
    }

    /// Move (§5.1): node `node` moves by `v`, every node by `αⱼ·v`; each attached primitive
    /// follows its edge: its centre keeps its offset from its projection, turned by the edge's
    /// rotation and stretched along the edge by the edge's change of length (Appendix A).
    /// Primitives on edges that did not move keep their exact bits. Returns how many moved.
    ///
    /// # Errors
    /// [`GaussianError::InvalidSkeleton`] for a missing node, an attachment list of the wrong
    /// length, or a non-finite `v` or reach.
    pub fn move_node(
        &mut self,
        terrain: &mut VectorTerrain,
        attached: &[Option<Attachment>],
        node: usize,
        v: DVec2,
        reach: Option<f64>,
    ) -> Result<usize, GaussianError> {
        self.check(terrain, attached, node)?;
        if !v.is_finite() || reach.is_some_and(|r| !(r.is_finite() && r > 0.0)) {
            return Err(GaussianError::InvalidSkeleton { reason: "the move and its reach must be finite (reach > 0)" });
        }
        let (node_alpha, prim_alpha) = self.attenuation(node, attached, reach);
        let before = self.clone();
        for (p, a) in self.nodes.iter_mut().zip(&node_alpha) {
            if *a > 0.0 {
                *p = (DVec2::from(*p) + v * *a).to_array();
            }
        }
        let mut moved = 0;
        for (g, (a, &alpha)) in terrain.primitives.iter_mut().zip(attached.iter().zip(&prim_alpha)) {
            let Some(a) = a else { continue };
            let [p, q] = self.edges[a.edge];
            let (p0, q0, p1, q1) = (before.node(p), before.node(q), self.node(p), self.node(q));
            if alpha == 0.0 || (p0 == p1 && q0 == q1) {
                continue;
            }
            let (e0, e1) = (q0 - p0, q1 - p1);
            let (pi0, pi1) = (p0 + e0 * a.t, p1 + e1 * a.t);
            let m = if e0.length_squared() > 0.0 && e1.length_squared() > 0.0 {
                let turn = DMat2::from_angle(e0.angle_to(e1));
                let dir = e0.normalize();
                let k = e1.length() / e0.length();
                turn * stretch_along(dir, k)
            } else {
                DMat2::IDENTITY
            };
            *g = g.transformed(m, pi1 - m * pi0);
            moved += 1;
        }
        Ok(moved)
    }

    /// Amplitude modification (§5.1): `a'ᵢ = aᵢ·(αᵢ·u + 1)` for the primitives attached around
    /// node `node`, `u ≥ −1` (−1 flattens the node's surroundings, 1 doubles them). Returns how
    /// many changed.
    ///
    /// # Errors
    /// As [`Self::move_node`], and for `u < −1`.
    pub fn scale_amplitude(
        &self,
        terrain: &mut VectorTerrain,
        attached: &[Option<Attachment>],
        node: usize,
        u: f64,
        reach: Option<f64>,
    ) -> Result<usize, GaussianError> {
        self.check(terrain, attached, node)?;
        if !(u.is_finite() && u >= -1.0) || reach.is_some_and(|r| !(r.is_finite() && r > 0.0)) {
            return Err(GaussianError::InvalidSkeleton {
                reason: "the factor must be ≥ −1 and the reach finite and > 0",
            });
        }
        let (_, prim_alpha) = self.attenuation(node, attached, reach);
        let mut changed = 0;
        for (g, &alpha) in terrain.primitives.iter_mut().zip(&prim_alpha) {
            if alpha > 0.0 {
                g.amplitude *= alpha * u + 1.0;
                changed += 1;
            }
        }
        Ok(changed)
    }

    fn check(
        &self,
        terrain: &VectorTerrain,
        attached: &[Option<Attachment>],
        node: usize,
    ) -> Result<(), GaussianError> {
        self.validate()?;
        if node >= self.nodes.len() {
            return Err(GaussianError::InvalidSkeleton { reason: "no such node" });
        }
        if attached.len() != terrain.primitives.len() || attached.iter().flatten().any(|a| a.edge >= self.edges.len()) {
            return Err(GaussianError::InvalidSkeleton {
                reason: "attachments do not match this terrain and skeleton",
            });
        }
        Ok(())
    }
}
