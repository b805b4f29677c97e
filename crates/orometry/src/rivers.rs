//! §6.1, the river network as the dual of the ridges.
//!
//! The refined ridge nodes, the map's border and sites in open country (every [`OPEN_STEP`]·λ,
//! away from the ridges) are triangulated (Delaunay, ridges kept as edges). Each triangle's Voronoi vertex (its circumcentre, pulled inside the triangle when it
//! falls outside) is a river node; two nodes are joined through the midpoint of their shared edge
//! unless that edge is a ridge (the paper's pruning of Voronoi edges that cross the ridges), and
//! triangles on the border drain out of the map there, at the flank surface's height beside the
//! ridges (never under the base). Each node's elevation is bounded by the
//! ridges around it: [`BELOW_RIDGE_M`] under the lowest point of the divide tree's paths between
//! its triangle's corners. A river runs between the ridges of its banks and joins them at its
//! own height, so it must stay under the col that joins them in the tree (the corners' own
//! heights would let it rise to join two branches above their saddle and raise the col).
//!
//! A priority flood from the outlets, rising along each link at the river slope and never above
//! a node's bound, orients the graph into a drainage tree (every node reached by the lowest
//! river that can reach it). The drainage areas of that tree then set the final profile
//! downstream to upstream with Flint's law, `s = s₁·(A / 1 km²)^(−θ)` (steep heads, gentle main
//! stems, the river slope of Génevaux et al. 2013), each node still within its bound and never
//! below its receiver. Channels draining at least [`TerrainOptions::river_area_km2`] become
//! rivers: segments refined below λ with the ridges' sideways jitter, each with the valley width
//! `c·A^exponent` of its drainage area.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashSet};

use glam::DVec2;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use relief_heightfield::Extent;
use relief_tin::{NO_TRIANGLE, Tin};

use crate::OrometryError;
use crate::network::{Network, border_points, dedup, jittered_leg, poisson_samples};
use crate::terrain::TerrainOptions;

/// How far below the lowest ridge node around it a river node stays at most, metres.
pub(crate) const BELOW_RIDGE_M: f64 = 1.0;

/// Spacing of the sites away from the ridges (on the border and in open country), in λ: the
/// outlets' spacing, and the size of the triangles where there are no ridges.
const OPEN_STEP: f64 = 15.0;

/// The river graph: triangles' Voronoi vertices and the border outlets after them, joined by
/// links through the midpoints of the edges they cross.
struct Graph {
    /// Node positions: one per triangle, then one per outlet.
    points: Vec<DVec2>,
    /// Highest elevation per node (outlets: their height).
    bound: Vec<f64>,
    /// Catchment area per node, m² (the triangle's own; outlets: 0).
    area: Vec<f64>,
    /// Links `(a, b, midpoint, length through it)`.
    links: Vec<(u32, u32, DVec2, f64)>,
    /// Per node, the links at it.
    adjacent: Vec<Vec<u32>>,
    /// Index of the first outlet.
    first_outlet: usize,
}

/// Total order on elevations for the flood's heap (NaN never reaches it).
#[derive(Clone, Copy, PartialEq)]
struct Key(f64);
impl Eq for Key {}
impl PartialOrd for Key {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Key {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// The dual river network of `ridges` over `extent` (see the module's docs), or an empty one
/// when there are no ridges. `ridge_at(p)` gives the distance from `p` to the nearest ridge and
/// that ridge point's height: open sites keep away from the ridges, and rivers leave the map at
/// the flank surface's height there, `h − s·d` (the flank slope `s`), never above the col their
/// banks share nor below `base`. (Leaving at the base everywhere would pull the land down to it
/// along the whole border, a rim of steep slopes around the map.)
pub(crate) fn dual_rivers(
    ridges: &Network,
    extent: Extent,
    base: f64,
    options: &TerrainOptions,
    rng: &mut ChaCha8Rng,
    ridge_at: impl Fn(DVec2) -> (f64, f64),
) -> Result<Network, OrometryError> {
    if ridges.segments.is_empty() {
        return Ok(Network::default());
    }
    let open = open_sites(extent, options.lambda_m, rng, |p| ridge_at(p).0)?;
    let flank = |p: DVec2| {
        let (d, h) = ridge_at(p);
        h - options.flank_slope * d
    };
    let graph = dual_graph(ridges, open, base, flank)?;
    let (order, receiver) = drain(&graph, |_| options.river_slope);
    let area = catchments(&graph, &order, &receiver);
    let slope = |n: usize| flint_slope(area[n], options);
    let height = profile(&graph, &order, &receiver, slope);
    Ok(emit(&graph, &order, &receiver, &height, &area, options, rng))
}

/// The sites away from the ridges: the border every [`OPEN_STEP`]·λ or less, and Poisson-disc
/// samples that far apart, more than half of it from any ridge (`ridge_distance`).
fn open_sites(
    extent: Extent,
    lambda: f64,
    rng: &mut ChaCha8Rng,
    ridge_distance: impl Fn(DVec2) -> f64,
) -> Result<Vec<DVec2>, OrometryError> {
    let spacing = OPEN_STEP * lambda;
    let mut open = border_points(extent, spacing);
    let inner = poisson_samples(extent, spacing, rng.random())?;
    open.extend(inner.into_iter().filter(|&p| ridge_distance(p) > 0.5 * spacing));
    Ok(open)
}

/// Flint's law at catchment `area` (m²): `s₁·(A / 1 km²)^(−θ)`, at most the flank slope.
fn flint_slope(area: f64, options: &TerrainOptions) -> f64 {
    let km2 = (area / 1e6).max(1e-6);
    (options.river_slope * km2.powf(-options.river_concavity)).min(options.flank_slope)
}

/// Triangulates the ridge nodes and the `open` sites (the border's and those in open country;
/// ridges kept as edges), and builds its dual graph without the links across ridges. An outlet
/// at `p` on the border has the height `outlet(p)`, kept between `base` and its triangle's bound.
fn dual_graph(
    ridges: &Network,
    open: Vec<DVec2>,
    base: f64,
    outlet: impl Fn(DVec2) -> f64,
) -> Result<Graph, OrometryError> {
    let mut points = ridges.points.clone();
    // Each vertex's index among the ridge nodes as its value, to find it again after `dedup`.
    let mut ids: Vec<f64> = (0..points.len()).map(|v| v as f64).collect();
    ids.extend(std::iter::repeat_n(f64::INFINITY, open.len()));
    points.extend(open);
    let (points, ids, constraints) = dedup(points, ids, ridges.segments.clone());
    let (tin, _skipped) = Tin::constrained(points, &constraints)?;
    let paths = PathMinima::new(ridges);
    let ridge_edges: HashSet<(u32, u32)> = constraints.iter().map(|&[a, b]| (a.min(b), a.max(b))).collect();
    let (pts, tris, nbrs) = (tin.points(), tin.triangles(), tin.triangle_neighbors());
    let mut graph = Graph {
        points: Vec::with_capacity(tris.len()),
        bound: Vec::with_capacity(tris.len()),
        area: Vec::with_capacity(tris.len()),
        links: Vec::new(),
        adjacent: vec![Vec::new(); tris.len()],
        first_outlet: tris.len(),
    };
    for t in tris {
        let [a, b, c] = t.map(|v| pts[v as usize]);
        graph.points.push(voronoi_vertex(a, b, c));
        let corners = t.map(|v| ids[v as usize]).into_iter().filter(|id| id.is_finite()).map(|id| id as u32);
        graph.bound.push(paths.lowest_between(corners) - BELOW_RIDGE_M);
        graph.area.push(0.5 * (b - a).perp_dot(c - a).abs());
    }
    for (t, tri) in tris.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
            let u = nbrs[t][k];
            if ridge_edges.contains(&(a.min(b), a.max(b))) || (u != NO_TRIANGLE && (u as usize) < t) {
                continue;
            }
            let mid = 0.5 * (pts[a as usize] + pts[b as usize]);
            let other = if u == NO_TRIANGLE {
                graph.points.push(mid);
                graph.bound.push(outlet(mid).min(graph.bound[t]).max(base));
                graph.area.push(0.0);
                graph.adjacent.push(Vec::new());
                graph.points.len() - 1
            } else {
                u as usize
            };
            let len = graph.points[t].distance(mid) + mid.distance(graph.points[other]);
            let id = graph.links.len() as u32;
            graph.links.push((t as u32, other as u32, mid, len));
            graph.adjacent[t].push(id);
            graph.adjacent[other].push(id);
        }
    }
    Ok(graph)
}

/// The lowest point of the refined ridge network's paths between nodes: the network is the
/// divide tree (a forest at worst), each segment as low as its lower end; binary lifting over a
/// breadth-first rooting of each component.
struct PathMinima {
    heights: Vec<f64>,
    depth: Vec<u32>,
    /// Component per node.
    component: Vec<u32>,
    /// `up[k][v]`: the ancestor 2^k levels above `v` (the root above itself).
    up: Vec<Vec<u32>>,
    /// `low[k][v]`: the lowest node height on the way from `v` up those 2^k levels, `v` included.
    low: Vec<Vec<f64>>,
}

impl PathMinima {
    fn new(net: &Network) -> Self {
        let n = net.points.len();
        let mut adjacent = vec![Vec::new(); n];
        for &[a, b] in &net.segments {
            adjacent[a as usize].push(b);
            adjacent[b as usize].push(a);
        }
        let (mut depth, mut component) = (vec![0u32; n], vec![u32::MAX; n]);
        let mut parent: Vec<u32> = (0..n as u32).collect();
        for root in 0..n {
            if component[root] != u32::MAX {
                continue;
            }
            component[root] = root as u32;
            let mut queue = std::collections::VecDeque::from([root as u32]);
            while let Some(v) = queue.pop_front() {
                for &w in &adjacent[v as usize] {
                    if component[w as usize] == u32::MAX {
                        component[w as usize] = root as u32;
                        parent[w as usize] = v;
                        depth[w as usize] = depth[v as usize] + 1;
                        queue.push_back(w);
                    }
                }
            }
        }
        let levels = (usize::BITS - n.max(1).leading_zeros()) as usize;
        let mut up = vec![parent];
        let mut low = vec![net.heights.clone()];
        for k in 1..levels {
            let (prev_up, prev_low) = (&up[k - 1], &low[k - 1]);
            let next_up: Vec<u32> = (0..n).map(|v| prev_up[prev_up[v] as usize]).collect();
            let next_low: Vec<f64> = (0..n).map(|v| prev_low[v].min(prev_low[prev_up[v] as usize])).collect();
            up.push(next_up);
            low.push(next_low);
        }
        Self { heights: net.heights.clone(), depth, component, up, low }
    }

    /// The lowest node on the path between `a` and `b`, both included; infinite if they lie in
    /// different components.
    fn between(&self, mut a: u32, mut b: u32) -> f64 {
        if self.component[a as usize] != self.component[b as usize] {
            return f64::INFINITY;
        }
        let mut lowest = self.heights[a as usize].min(self.heights[b as usize]);
        if self.depth[a as usize] < self.depth[b as usize] {
            std::mem::swap(&mut a, &mut b);
        }
        let climb = |v: &mut u32, k: usize, lowest: &mut f64| {
            *lowest = lowest.min(self.low[k][*v as usize]);
            *v = self.up[k][*v as usize];
        };
        let diff = self.depth[a as usize] - self.depth[b as usize];
        for k in 0..self.up.len() {
            if diff >> k & 1 == 1 {
                climb(&mut a, k, &mut lowest);
            }
        }
        if a == b {
            return lowest.min(self.heights[a as usize]);
        }
        for k in (0..self.up.len()).rev() {
            if self.up[k][a as usize] != self.up[k][b as usize] {
                climb(&mut a, k, &mut lowest);
                climb(&mut b, k, &mut lowest);
            }
        }
        // `a` and `b` are now children of their lowest common ancestor.
        let ancestor = self.up[0][a as usize];
        lowest.min(self.heights[a as usize]).min(self.heights[b as usize]).min(self.heights[ancestor as usize])
    }

    /// The lowest point of the paths between any two of `nodes` (a lone node's own height;
    /// infinite for none).
    fn lowest_between(&self, nodes: impl Iterator<Item = u32>) -> f64 {
        let nodes: Vec<u32> = nodes.collect();
        let mut lowest = f64::INFINITY;
        for (i, &a) in nodes.iter().enumerate() {
            lowest = lowest.min(self.heights[a as usize]);
            for &b in &nodes[i + 1..] {
                lowest = lowest.min(self.between(a, b));
            }
        }
        lowest
    }
}

/// The triangle's Voronoi vertex, its circumcentre, if that lies inside it; otherwise the
/// closest point of the triangle to it, moved a tenth of the way to the centroid so that it never
/// sits on an edge (a ridge). The centroid for a degenerate triangle.
fn voronoi_vertex(a: DVec2, b: DVec2, c: DVec2) -> DVec2 {
    let centroid = (a + b + c) / 3.0;
    let (ab, ac) = (b - a, c - a);
    let d = 2.0 * ab.perp_dot(ac);
    if d.abs() <= f64::EPSILON * ab.length_squared().max(ac.length_squared()) {
        return centroid;
    }
    let cc = a + DVec2::new(
        ac.y * ab.length_squared() - ab.y * ac.length_squared(),
        ab.x * ac.length_squared() - ac.x * ab.length_squared(),
    ) / d;
    let side = |p: DVec2, q: DVec2| (q - p).perp_dot(cc - p) * d.signum() >= 0.0;
    if side(a, b) && side(b, c) && side(c, a) {
        return cc;
    }
    let closest = [(a, b), (b, c), (c, a)]
        .map(|(p, q)| {
            let pq = q - p;
            p + pq * ((cc - p).dot(pq) / pq.length_squared()).clamp(0.0, 1.0)
        })
        .into_iter()
        .min_by(|p, q| p.distance_squared(cc).total_cmp(&q.distance_squared(cc)))
        .unwrap_or(centroid);
    closest.lerp(centroid, 0.1)
}

/// Per node, its receiver and the link to it (`None` for outlets and nodes no river reaches).
type Receivers = Vec<Option<(u32, u32)>>;

/// The priority flood from the outlets (at their heights): a node reached over a link of length `len`
/// from a node at `h` gets `max(h, min(bound, h + slope(node)·len))`, the lowest such value over
/// its links (outlets only drain); nodes settle lowest first (ties in the order they were reached). Returns the nodes
/// in settling order (receivers before their donors) and each node's receiver.
fn drain(graph: &Graph, slope: impl Fn(usize) -> f64) -> (Vec<u32>, Receivers) {
    let n = graph.points.len();
    let mut height = vec![f64::INFINITY; n];
    let mut receiver: Receivers = vec![None; n];
    let mut settled = vec![false; n];
    let mut heap = BinaryHeap::new();
    let mut seq = 0u64;
    for (o, h) in height.iter_mut().enumerate().skip(graph.first_outlet) {
        *h = graph.bound[o];
        heap.push(Reverse((Key(*h), seq, o as u32)));
        seq += 1;
    }
    let mut order = Vec::with_capacity(n);
    while let Some(Reverse((Key(h), _, node))) = heap.pop() {
        let node = node as usize;
        if std::mem::replace(&mut settled[node], true) {
            continue;
        }
        order.push(node as u32);
        for &l in &graph.adjacent[node] {
            let (a, b, _, len) = graph.links[l as usize];
            let m = if a as usize == node { b } else { a } as usize;
            let rise = h.max(graph.bound[m].min(h + slope(m) * len));
            if !settled[m] && m < graph.first_outlet && rise < height[m] {
                height[m] = rise;
                receiver[m] = Some((node as u32, l));
                heap.push(Reverse((Key(rise), seq, m as u32)));
                seq += 1;
            }
        }
    }
    (order, receiver)
}

/// Each node's catchment along the drainage tree: its triangle's area and all its donors'.
fn catchments(graph: &Graph, order: &[u32], receiver: &Receivers) -> Vec<f64> {
    let mut area = graph.area.clone();
    for &n in order.iter().rev() {
        if let Some((r, _)) = receiver[n as usize] {
            area[r as usize] += area[n as usize];
        }
    }
    area
}

/// River elevations along the drainage tree, downstream first: outlets at their heights, every
/// other node `max(h_r, min(bound, h_r + slope(node)·len))` above its receiver `r`.
fn profile(graph: &Graph, order: &[u32], receiver: &Receivers, slope: impl Fn(usize) -> f64) -> Vec<f64> {
    let mut height = graph.bound.clone();
    for &n in order {
        let n = n as usize;
        if let Some((r, l)) = receiver[n] {
            let below = height[r as usize];
            height[n] = below.max(graph.bound[n].min(below + slope(n) * graph.links[l as usize].3));
        }
    }
    height
}

/// The river network: the link to its receiver of each node draining at least
/// [`TerrainOptions::river_area_km2`], drawn node → shared edge's midpoint → receiver, heights
/// linear in the distance along it, refined below λ with sideways jitter, each piece with the
/// valley width of the node's catchment.
fn emit(
    graph: &Graph,
    order: &[u32],
    receiver: &Receivers,
    height: &[f64],
    area: &[f64],
    options: &TerrainOptions,
    rng: &mut ChaCha8Rng,
) -> Network {
    let mut rivers = Network::default();
    let mut node = vec![u32::MAX; graph.points.len()];
    let mut vertex = |n: usize, rivers: &mut Network| {
        if node[n] == u32::MAX {
            node[n] = rivers.push(graph.points[n], height[n]);
        }
        node[n]
    };
    for &n in order {
        let n = n as usize;
        let Some((r, l)) = receiver[n] else { continue };
        if area[n] < options.river_area_km2 * 1e6 {
            continue;
        }
        let r = r as usize;
        let (_, _, mid, len) = graph.links[l as usize];
        let up = graph.points[n].distance(mid);
        let h_mid = height[n] + (height[r] - height[n]) * (up / len.max(f64::MIN_POSITIVE));
        let width = options.valley_width_m * (area[n] / 1e6).powf(options.valley_exponent);
        let (a, b) = (vertex(n, &mut rivers), vertex(r, &mut rivers));
        let m = rivers.push(mid, h_mid);
        for [from, to] in [[a, m], [m, b]] {
            let before = rivers.segments.len();
            jittered_leg(&mut rivers, from, to, options.lambda_m, options.jitter, rng);
            rivers.widths.extend(std::iter::repeat_n(width, rivers.segments.len() - before));
        }
    }
    rivers
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    /// A straight ridge of three nodes across the middle of a 10 × 10 km map, 500 m high at its
    /// middle, 300 m at its ends.
    fn ridge() -> Network {
        let mut net = Network::default();
        let a = net.push(DVec2::new(2000.0, 5000.0), 300.0);
        let b = net.push(DVec2::new(5000.0, 5000.0), 500.0);
        let c = net.push(DVec2::new(8000.0, 5000.0), 300.0);
        net.segments.extend([[a, b], [b, c]]);
        net.saddles.extend([300.0, 300.0]);
        net
    }

    fn extent() -> Extent {
        Extent::new(DVec2::ZERO, DVec2::splat(10_000.0))
    }

    fn crosses(p: DVec2, q: DVec2, a: DVec2, b: DVec2) -> bool {
        let side = |x: DVec2, y: DVec2, z: DVec2| (y - x).perp_dot(z - x);
        side(p, q, a) * side(p, q, b) < 0.0 && side(a, b, p) * side(a, b, q) < 0.0
    }

    #[test]
    fn the_dual_never_crosses_a_ridge_and_drains_to_the_border_below_the_ridges() {
        let ridges = ridge();
        let options = TerrainOptions { jitter: 0.0, river_area_km2: 0.0, ..TerrainOptions::default() };
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let ridge_at = |p: DVec2| {
            (0..ridges.segments.len() as u32).map(|s| ridges.project(s, p)).min_by(|a, b| a.0.total_cmp(&b.0)).unwrap()
        };
        let rivers = dual_rivers(&ridges, extent(), 100.0, &options, &mut rng, ridge_at).unwrap();
        assert!(!rivers.segments.is_empty());
        for &[a, b] in &rivers.segments {
            let (p, q) = (rivers.points[a as usize], rivers.points[b as usize]);
            for &[c, d] in &ridges.segments {
                assert!(!crosses(p, q, ridges.points[c as usize], ridges.points[d as usize]), "{p} → {q}");
            }
            // Rivers flow downhill, segment by segment.
            assert!(rivers.heights[a as usize] >= rivers.heights[b as usize]);
        }
        // No river passes through a ridge (a link across one would go through its midpoint).
        for (s, _) in ridges.segments.iter().enumerate() {
            assert!(rivers.points.iter().all(|&p| ridges.project(s as u32, p).0 > 1.0));
        }
        // Every river node lies below the lowest ridge node of its triangle, and some rise well
        // above the base (the rivers climb towards the ridge instead of lying flat).
        let top = rivers.heights.iter().copied().fold(f64::MIN, f64::max);
        assert!(top <= 300.0 - BELOW_RIDGE_M, "{top}");
        assert!(top > 120.0, "the highest river node is at {top}");
        // Outlets sit on the border at the flank surface's height, `h − 0.4·d` for the ridge
        // point nearest them, never below the base (the east and west ends, 2 km from the ridge,
        // 300 − 800 < 100; the north and south edges at the base too, 5 km away).
        let on_border = |p: DVec2| p.x == 0.0 || p.y == 0.0 || p.x == 10_000.0 || p.y == 10_000.0;
        let outlets: Vec<(DVec2, f64)> =
            rivers.points.iter().zip(&rivers.heights).filter(|(p, _)| on_border(**p)).map(|(&p, &h)| (p, h)).collect();
        assert!(!outlets.is_empty());
        for (p, h) in outlets {
            let (d, top) = ridge_at(p);
            assert_eq!(h, (top - 0.4 * d).max(100.0), "{p}");
        }
    }

    #[test]
    fn rivers_leave_the_map_at_the_flank_surface_not_at_the_base() {
        // A ridge ending 500 m from the west edge at 600 m: the rivers leaving beside it start
        // near 600 − 0.4·500 = 400 m, under their triangles' bounds; far from it, at the base.
        let mut ridges = Network::default();
        let a = ridges.push(DVec2::new(500.0, 5000.0), 600.0);
        let b = ridges.push(DVec2::new(5000.0, 5000.0), 300.0);
        ridges.segments.push([a, b]);
        let ridge_at = |p: DVec2| ridges.project(0, p);
        let graph = dual_graph(&ridges, border_points(extent(), 1000.0), 0.0, |p| {
            let (d, h) = ridge_at(p);
            h - 0.4 * d
        })
        .unwrap();
        let outlet = |x: f64, y: f64| {
            (graph.first_outlet..graph.points.len()).find(|&o| graph.points[o] == DVec2::new(x, y)).unwrap()
        };
        // The west edge's outlets beside the ridge's end, at (0, 4500) and (0, 5500).
        for y in [4500.0, 5500.0] {
            let o = outlet(0.0, y);
            let (d, h) = ridge_at(graph.points[o]);
            let expected = h - 0.4 * d;
            assert!(expected > 300.0);
            assert!(graph.bound[o] <= expected, "{}", graph.bound[o]);
            assert!(graph.bound[o] > 250.0, "{}", graph.bound[o]);
        }
        assert_eq!(graph.bound[outlet(9500.0, 0.0)], 0.0);
        // The flood starts from them.
        let (order, receiver) = drain(&graph, |_| 0.03);
        let height = profile(&graph, &order, &receiver, |_| 0.03);
        assert!((graph.first_outlet..graph.points.len()).all(|o| height[o] == graph.bound[o]));
    }

    #[test]
    fn rivers_descend_along_their_flow_and_steepen_towards_their_heads() {
        let options = TerrainOptions::default();
        let graph = dual_graph(&ridge(), border_points(extent(), 1000.0), 100.0, |_| 0.0).unwrap();
        let (order, receiver) = drain(&graph, |_| options.river_slope);
        assert_eq!(order.len(), graph.points.len(), "every node drains to the border");
        // One link per pair, each through the midpoint of the edge it crosses; outlets on the
        // map's edge.
        let pairs: HashSet<(u32, u32)> = graph.links.iter().map(|&(a, b, _, _)| (a.min(b), a.max(b))).collect();
        assert_eq!(pairs.len(), graph.links.len());
        for &(a, b, mid, len) in &graph.links {
            let (pa, pb) = (graph.points[a as usize], graph.points[b as usize]);
            assert!((pa.distance(mid) + mid.distance(pb) - len).abs() < 1e-9);
        }
        for o in graph.first_outlet..graph.points.len() {
            let p = graph.points[o];
            assert!(p.min_element() == 0.0 || p.max_element() == 10_000.0, "{p}");
        }
        let area = catchments(&graph, &order, &receiver);
        // All the catchments together cover the map.
        let outlets: f64 = (graph.first_outlet..graph.points.len()).map(|o| area[o]).sum();
        assert!((outlets - 1e8).abs() < 1.0, "{outlets}");
        let height = profile(&graph, &order, &receiver, |n| flint_slope(area[n], &options));
        for (n, r) in receiver.iter().enumerate() {
            if let Some((r, _)) = r {
                assert!(height[n] >= height[*r as usize]);
                assert!(height[n] <= graph.bound[n].max(height[*r as usize]));
            }
        }
        // Flint's law: a smaller catchment is steeper, capped by the flank slope.
        assert!(flint_slope(1e5, &options) > flint_slope(1e6, &options));
        assert_eq!(flint_slope(1e6, &options), options.river_slope);
        assert!((flint_slope(1e8, &options) - options.river_slope * 100f64.powf(-0.45)).abs() < 1e-12);
        assert_eq!(flint_slope(1.0, &options), options.flank_slope);
    }

    /// A U-shaped range: two parallel crests 800 m high, 2 km apart, joined only at their east
    /// end through a col of 300 m.
    fn u_range() -> Network {
        let mut net = Network::default();
        let north: Vec<u32> =
            (0..=6).map(|i| net.push(DVec2::new(2000.0 + 1000.0 * f64::from(i), 6000.0), 800.0)).collect();
        let col = net.push(DVec2::new(9000.0, 5000.0), 300.0);
        let south: Vec<u32> =
            (0..=6).map(|i| net.push(DVec2::new(2000.0 + 1000.0 * f64::from(i), 4000.0), 800.0)).collect();
        for line in [&north, &south] {
            net.segments.extend(line.windows(2).map(|w| [w[0], w[1]]));
            net.segments.push([line[6], col]);
        }
        net
    }

    #[test]
    fn a_river_between_two_branches_stays_under_the_col_that_joins_them() {
        // The valley between the crests drains west; its head, 7 km from the edge, would rise
        // well above the col at the river slope. Bounded by the crests' own heights (800 m) it
        // would join them above 300 m; bounded by the tree's path between them it stays under.
        let options = TerrainOptions { jitter: 0.0, river_area_km2: 0.0, ..TerrainOptions::default() };
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        // No open sites (every point on a ridge), outlets at the base.
        let rivers =
            dual_rivers(&u_range(), extent(), 250.0, &options, &mut rng, |_| (0.0, f64::NEG_INFINITY)).unwrap();
        let inside = |p: DVec2| p.x > 2000.0 && p.x < 8000.0 && p.y > 4000.0 && p.y < 6000.0;
        let valley: Vec<f64> =
            rivers.points.iter().zip(&rivers.heights).filter(|(p, _)| inside(**p)).map(|(_, &h)| h).collect();
        assert!(valley.len() > 3);
        let top = valley.iter().copied().fold(f64::MIN, f64::max);
        assert!(top <= 300.0 - BELOW_RIDGE_M, "the valley rises to {top}");
        assert!(top > 290.0, "the valley's head stays at {top}: the bound, not the slope, should stop it");
    }

    #[test]
    fn path_minima_match_a_search_along_the_tree() {
        // A branching tree of 60 nodes (node i hangs from one of the nodes before it), heights
        // scattered: lowest common ancestors away from either end.
        let mut branching = Network::default();
        for i in 0..60u32 {
            branching.push(DVec2::new(f64::from(i), 0.0), f64::from((i * 37) % 101));
            if i > 0 {
                branching.segments.push([(i * 13 + 5) % i, i]);
            }
        }
        for net in [u_range(), branching] {
            check_path_minima(&net);
        }
        let net = u_range();
        let paths = PathMinima::new(&net);
        assert_eq!(paths.lowest_between([0, 8].into_iter()), 300.0);
        assert_eq!(paths.lowest_between([0, 1, 2].into_iter()), 800.0);
        assert_eq!(paths.lowest_between(std::iter::empty()), f64::INFINITY);
        // Two components never join.
        let mut forest = ridge();
        forest.push(DVec2::ZERO, 10.0);
        assert_eq!(PathMinima::new(&forest).between(0, 3), f64::INFINITY);
    }

    fn check_path_minima(net: &Network) {
        let paths = PathMinima::new(net);
        let n = net.points.len();
        let mut adjacent = vec![Vec::new(); n];
        for &[a, b] in &net.segments {
            adjacent[a as usize].push(b as usize);
            adjacent[b as usize].push(a as usize);
        }
        for a in 0..n {
            // The lowest node on the path from `a` to every node, by a search from `a`.
            let mut low = vec![f64::NAN; n];
            low[a] = net.heights[a];
            let mut stack = vec![a];
            while let Some(v) = stack.pop() {
                for &w in &adjacent[v] {
                    if low[w].is_nan() {
                        low[w] = low[v].min(net.heights[w]);
                        stack.push(w);
                    }
                }
            }
            for (b, &lowest) in low.iter().enumerate() {
                assert_eq!(paths.between(a as u32, b as u32), lowest, "{a} → {b}");
            }
        }
    }

    #[test]
    fn voronoi_vertices_are_circumcentres_kept_inside_their_triangles() {
        let (a, b, c) = (DVec2::new(3.0, 1.0), DVec2::new(9.0, 2.0), DVec2::new(5.0, 6.0));
        let v = voronoi_vertex(a, b, c);
        for (p, q) in [(a, b), (b, c), (c, a)] {
            assert!((v.distance(p) - v.distance(q)).abs() < 1e-12, "{v}");
        }
        // Obtuse: the circumcentre (5, −3.5) lies below the long side; the vertex is its
        // nearest point on it, (5, 1), a tenth of the way to the centroid (5, 1.5).
        let (a, b) = (DVec2::new(1.0, 1.0), DVec2::new(9.0, 1.0));
        let v = voronoi_vertex(a, b, DVec2::new(5.0, 2.5));
        assert!(v.distance(DVec2::new(5.0, 1.05)) < 1e-12, "{v}");
        // Obtuse at a corner, the circumcentre beyond a short side.
        let (p, q, r) = (DVec2::new(0.0, 0.0), DVec2::new(10.0, 0.0), DVec2::new(1.0, 1.0));
        let v = voronoi_vertex(p, q, r);
        let inside = |x: DVec2| [(p, q), (q, r), (r, p)].iter().all(|&(s, t)| (t - s).perp_dot(x - s) > 0.0);
        assert!(inside(v), "{v}");
        assert_eq!(voronoi_vertex(a, b, DVec2::new(17.0, 1.0)), DVec2::new(9.0, 1.0));
    }

    #[test]
    fn open_sites_keep_their_spacing_and_their_distance_from_the_ridges() {
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        let ridge_x = 5000.0;
        let sites = open_sites(extent(), 200.0, &mut rng, |p| (p.x - ridge_x).abs()).unwrap();
        let inner: Vec<DVec2> =
            sites.iter().copied().filter(|p| p.min_element() > 0.0 && p.max_element() < 10_000.0).collect();
        assert!(inner.len() >= 4, "{} inner sites", inner.len());
        // Sites come as close as half the spacing, not only a whole spacing away.
        assert!(inner.iter().any(|p| (p.x - ridge_x).abs() < 3000.0));
        for (i, p) in inner.iter().enumerate() {
            assert!((p.x - ridge_x).abs() > 1500.0, "{p} is near the ridge");
            assert!(inner[i + 1..].iter().all(|q| q.distance(*p) >= 3000.0 - 1e-9));
        }
        // The border: every 3 km (15 λ) at most, corners included (2.5 km apart here).
        assert!(border_points(extent(), 3000.0).iter().all(|p| sites.contains(p)));
        assert!(sites.contains(&DVec2::new(2500.0, 0.0)) && sites.contains(&DVec2::splat(10_000.0)));
    }

    #[test]
    fn drainage_follows_the_lowest_river_and_emit_draws_it_through_the_shared_edge() {
        // Triangle nodes A (0) and B (1), an outlet O (2): O–A and A–B 100 m, O–B 150 m. B is
        // steeper than A: through A it reaches 0 + 0.1·100 = 10 m, straight to O 15 m.
        let graph = Graph {
            points: vec![DVec2::new(100.0, 0.0), DVec2::new(100.0, 100.0), DVec2::ZERO],
            bound: vec![f64::INFINITY, f64::INFINITY, 0.0],
            area: vec![1.5e6, 2.5e6, 0.0],
            links: vec![
                (2, 0, DVec2::new(50.0, 0.0), 100.0),
                (0, 1, DVec2::new(100.0, 50.0), 100.0),
                (2, 1, DVec2::new(50.0, 50.0), 150.0),
            ],
            adjacent: vec![vec![0, 1], vec![1, 2], vec![0, 2]],
            first_outlet: 2,
        };
        let slope = |n: usize| [0.0, 0.1, 0.0][n];
        let (order, receiver) = drain(&graph, slope);
        assert_eq!(order, [2, 0, 1]);
        assert_eq!(receiver, [Some((2, 0)), Some((0, 1)), None]);
        let height = profile(&graph, &order, &receiver, |n| [0.02, 0.1, 0.0][n]);
        assert_eq!(height, [2.0, 12.0, 0.0]);
        // Emitted with a 2 km² threshold: B's link only (A drains 1.5 km² of its own but 4 km²
        // with B's; B 2.5 km²), through the midpoint of the edge it crosses, mid-way in height.
        let mut area = graph.area.clone();
        area[0] = 1.9e6;
        let options = TerrainOptions { river_area_km2: 2.0, ..TerrainOptions::default() };
        let mut rng = ChaCha8Rng::seed_from_u64(0);
        let rivers = emit(&graph, &order, &receiver, &height, &area, &options, &mut rng);
        assert_eq!(rivers.points, [DVec2::new(100.0, 100.0), DVec2::new(100.0, 0.0), DVec2::new(100.0, 50.0)]);
        assert_eq!(rivers.heights, [12.0, 2.0, 7.0]);
        assert_eq!(rivers.segments, [[0, 2], [2, 1]]);
        let width = 40.0 * 2.5f64.powf(0.4);
        assert_eq!(rivers.widths, [width, width]);
    }
}
