use glam::DVec2;
use std::sync::atomic::{AtomicU32, Ordering};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use spade::{ConstrainedDelaunayTriangulation, DelaunayTriangulation, HasPosition, Point2, Triangulation};

use crate::TinError;
use crate::predicates::{incircle, orient};

/// Marks a missing triangle neighbour (an edge on the convex hull / mesh boundary).
pub const NO_TRIANGLE: u32 = u32::MAX;

/// The most points a TIN may hold: indices are `u32` and `u32::MAX` is reserved.
pub const MAX_POINTS: usize = (u32::MAX - 1) as usize;

/// A triangulated irregular network stored as flat arrays.
///
/// - `points[v]`: node positions, in the order they were given;
/// - `triangles[t]`: three node indices, counter-clockwise;
/// - `triangle_neighbors(t)[k]`: the triangle across the edge *opposite* corner `k`
///   (edge `t[k+1] → t[k+2]`), or [`NO_TRIANGLE`] on the boundary;
/// - CSR vertex adjacency: `neighbors(v)` lists the nodes joined to `v` counter-clockwise; for a
///   boundary node the list starts and ends with its two boundary neighbours (the fan is open);
/// - `is_boundary(v)`: node on the mesh boundary (the convex hull for a Delaunay TIN).
///
/// Built from points by Delaunay triangulation ([`Tin::new`], read straight out of spade's
/// half-edge structure) or from explicit triangles ([`Tin::from_parts`], validated and assembled
/// here). Both apply the same fan-rotation rule, so `Tin::from_parts(tin.points(), tin.triangles())`
/// rebuilds an identical TIN, and every `Tin` satisfies [`Tin::check_invariants`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "TinRepr", into = "TinRepr")]
pub struct Tin {
    points: Vec<DVec2>,
    triangles: Vec<[u32; 3]>,
    triangle_neighbors: Vec<[u32; 3]>,
    adjacency_offsets: Vec<u32>,
    adjacency: Vec<u32>,
    boundary: Vec<bool>,
    convex: bool,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct TinRepr {
    points: Vec<DVec2>,
    triangles: Vec<[u32; 3]>,
}

impl TryFrom<TinRepr> for Tin {
    type Error = TinError;
    fn try_from(r: TinRepr) -> Result<Self, TinError> {
        Tin::from_parts(r.points, r.triangles)
    }
}

impl From<Tin> for TinRepr {
    fn from(t: Tin) -> Self {
        Self { points: t.points, triangles: t.triangles }
    }
}

/// Checks what spade's exact predicates need: finite coordinates of magnitude 0 or 2^-142 ..= 2^201.
fn validate_points(points: &[DVec2]) -> Result<(), TinError> {
    if points.len() < 3 {
        return Err(TinError::TooFewPoints { count: points.len() });
    }
    if points.len() > MAX_POINTS {
        return Err(TinError::TooManyPoints { count: points.len(), max: MAX_POINTS });
    }
    let ok = |c: f64| c == 0.0 || (c.abs() >= spade::MIN_ALLOWED_VALUE && c.abs() <= spade::MAX_ALLOWED_VALUE);
    for (index, p) in points.iter().enumerate() {
        if !p.is_finite() {
            return Err(TinError::NonFinitePoint { index, x: p.x, y: p.y });
        }
        if !(ok(p.x) && ok(p.y)) {
            return Err(TinError::CoordinateOutOfRange { index, x: p.x, y: p.y });
        }
    }
    Ok(())
}

/// The first pair of coinciding points, by index.
fn find_duplicate(points: &[DVec2]) -> Option<(usize, usize)> {
    let mut order: Vec<u32> = (0..points.len() as u32).collect();
    order.par_sort_unstable_by(|&a, &b| {
        let (p, q) = (points[a as usize], points[b as usize]);
        p.x.total_cmp(&q.x).then(p.y.total_cmp(&q.y)).then(a.cmp(&b))
    });
    order
        .windows(2)
        .filter(|w| points[w[0] as usize] == points[w[1] as usize])
        .map(|w| (w[0] as usize, w[1] as usize))
        .min()
}

impl Tin {
    /// The Delaunay triangulation of `points` (spade's bulk loader; node `v` is `points[v]`).
    ///
    /// Triangles come in spade's order (deterministic for given points); fans start at a
    /// canonical neighbour, so [`Tin::from_parts`] of the result's points and triangles rebuilds
    /// an identical `Tin`.
    ///
    /// # Errors
    /// [`TinError::TooFewPoints`], [`TinError::TooManyPoints`], [`TinError::NonFinitePoint`],
    /// [`TinError::CoordinateOutOfRange`], [`TinError::DuplicatePoint`] or [`TinError::Collinear`].
    pub fn new(points: Vec<DVec2>) -> Result<Self, TinError> {
        validate_points(&points)?;
        let nodes: Vec<Node> =
            points.iter().enumerate().map(|(i, p)| Node { position: Point2::new(p.x, p.y), index: i as u32 }).collect();
        let dt = DelaunayTriangulation::<Node>::bulk_load(nodes)
            .map_err(|e| TinError::Invariant(format!("spade rejected validated input: {e:?}")))?;
        Self::from_spade(points, dt)
    }

    /// The constrained Delaunay triangulation of `points` in which each `constraints` edge
    /// `[a, b]` (vertex indices) is kept as a mesh edge, split where it passes through other
    /// vertices (orometry synthesis keeps ridges and rivers this way, §6.2). A constraint that
    /// crosses an earlier one is skipped; the second value counts those. The result is Delaunay
    /// away from the constraints only, so [`Tin::is_delaunay`] may be false.
    ///
    /// # Errors
    /// The errors of [`Tin::new`], or [`TinError::InvalidConstraint`] for a constraint naming a
    /// missing vertex or the same vertex twice.
    pub fn constrained(points: Vec<DVec2>, constraints: &[[u32; 2]]) -> Result<(Self, usize), TinError> {
        validate_points(&points)?;
        for (constraint, &[a, b]) in constraints.iter().enumerate() {
            let reason = if a as usize >= points.len() || b as usize >= points.len() {
                "no such vertex"
            } else if a == b {
                "an edge needs two distinct vertices"
            } else {
                continue;
            };
            return Err(TinError::InvalidConstraint { constraint, a, b, reason });
        }
        let nodes: Vec<Node> =
            points.iter().enumerate().map(|(i, p)| Node { position: Point2::new(p.x, p.y), index: i as u32 }).collect();
        let edges = constraints.iter().map(|&[a, b]| [a as usize, b as usize]).collect();
        let mut skipped = 0;
        let cdt = ConstrainedDelaunayTriangulation::<Node>::try_bulk_load_cdt(nodes, edges, |_| skipped += 1)
            .map_err(|e| TinError::Invariant(format!("spade rejected validated input: {e:?}")))?;
        Ok((Self::from_spade(points, cdt)?, skipped))
    }

    /// Copies a spade triangulation of `points` into flat arrays, after checking that spade kept
    /// every point (no duplicates) and made at least one triangle (not all collinear).
    fn from_spade<T>(points: Vec<DVec2>, dt: T) -> Result<Self, TinError>
    where
        T: Triangulation<Vertex = Node> + Sync,
        T::DirectedEdge: Sync,
        T::UndirectedEdge: Sync,
        T::Face: Sync,
    {
        if dt.num_vertices() < points.len() {
            let (first, second) = find_duplicate(&points).unwrap_or((0, 0));
            let p = points[first];
            return Err(TinError::DuplicatePoint { first, second, x: p.x, y: p.y });
        }
        if dt.num_inner_faces() == 0 {
            return Err(TinError::Collinear { count: points.len() });
        }
        let (triangles, triangle_neighbors) = spade_triangles(&dt);
        // Free spade's half-edges before the fans allocate.
        drop(dt);
        let (adjacency_offsets, adjacency, boundary) = mesh_fans(points.len(), &triangles, &triangle_neighbors);
        Ok(Self { points, triangles, triangle_neighbors, adjacency_offsets, adjacency, boundary, convex: true })
    }

    /// A TIN from explicit counter-clockwise triangles over `points` (e.g. a constrained or
    /// deserialized triangulation). Every node must belong to a triangle and the triangles must
    /// form a manifold, consistently oriented mesh.
    ///
    /// # Errors
    /// The point errors of [`Tin::new`] (except duplicates and collinearity), or
    /// [`TinError::InvalidTriangle`] / [`TinError::NonManifoldVertex`].
    pub fn from_parts(points: Vec<DVec2>, triangles: Vec<[u32; 3]>) -> Result<Self, TinError> {
        validate_points(&points)?;
        let n = points.len() as u32;
        for (t, tri) in triangles.iter().enumerate() {
            let bad = |reason: String| TinError::InvalidTriangle { triangle: t, reason };
            if let Some(v) = tri.iter().find(|&&v| v >= n) {
                return Err(bad(format!("node {v} does not exist ({n} nodes)")));
            }
            let [a, b, c] = tri.map(|v| points[v as usize]);
            if orient(a, b, c) <= 0.0 {
                return Err(bad(format!("nodes {tri:?} are not counter-clockwise (or are collinear)")));
            }
        }
        if triangles.is_empty() {
            return Err(TinError::Collinear { count: points.len() });
        }
        Self::assemble(points, triangles)
    }

    /// Derives adjacency from validated points and counter-clockwise triangles (kept in the given
    /// order).
    fn assemble(points: Vec<DVec2>, triangles: Vec<[u32; 3]>) -> Result<Self, TinError> {
        /// Vertices per parallel work item.
        const CHUNK: usize = 2048;
        let n = points.len();
        // The triangles around each vertex, CSR, as spans `(a, b, (t << 2) | corner)`: triangle `t`
        // has the vertex at `corner` and runs from node `a` to node `b` counter-clockwise around it.
        let mut inc_off = vec![0u32; n + 1];
        for tri in &triangles {
            for &v in tri {
                inc_off[v as usize + 1] += 1;
            }
        }
        for v in 0..n {
            inc_off[v + 1] += inc_off[v];
        }
        let mut fill = inc_off.clone();
        let mut incident = vec![(0u32, 0u32, 0u32); inc_off[n] as usize];
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let v = tri[k] as usize;
                incident[fill[v] as usize] = (tri[(k + 1) % 3], tri[(k + 2) % 3], ((t as u32) << 2) | k as u32);
                fill[v] += 1;
            }
        }
        drop(fill);
        // Each triangle slot is written exactly once (see `fan`), so relaxed atomic stores from
        // parallel vertices give a deterministic result without unsafe code.
        let links: Vec<AtomicU32> = (0..3 * triangles.len()).map(|_| AtomicU32::new(NO_TRIANGLE)).collect();
        let chunks: Vec<Result<FanChunk, TinError>> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let vertices = c * CHUNK..n.min((c + 1) * CHUNK);
                let mut chunk = FanChunk::with_capacity(vertices.len());
                let mut visited = Vec::with_capacity(16);
                for v in vertices {
                    let spans = &incident[inc_off[v] as usize..inc_off[v + 1] as usize];
                    let before = chunk.adjacency.len();
                    let open = fan(v, spans, &mut visited, &mut chunk.adjacency, &links)?;
                    chunk.push_degree(before, open);
                }
                Ok(chunk)
            })
            .collect();
        let (adjacency_offsets, adjacency, boundary) =
            FanChunk::concat(chunks.into_iter().collect::<Result<Vec<_>, _>>()?);
        let triangle_neighbors = links
            .chunks_exact(3)
            .map(|l| [l[0].load(Ordering::Relaxed), l[1].load(Ordering::Relaxed), l[2].load(Ordering::Relaxed)])
            .collect();
        let mut tin =
            Self { points, triangles, triangle_neighbors, adjacency_offsets, adjacency, boundary, convex: false };
        tin.convex = tin.boundary_is_convex();
        Ok(tin)
    }

    /// One component whose single boundary loop never turns right: the mesh covers the convex
    /// hull of its nodes (always true for a Delaunay TIN).
    fn boundary_is_convex(&self) -> bool {
        if self.components() != 1 || self.boundary_loops() != 1 {
            return false;
        }
        (0..self.points.len() as u32).filter(|&v| self.boundary[v as usize]).all(|v| {
            let nb = self.neighbors(v);
            // Boundary neighbours: `prev` before v along the loop, `next` after it.
            let (next, prev) = (nb[0], nb[nb.len() - 1]);
            orient(self.points[prev as usize], self.points[v as usize], self.points[next as usize]) >= 0.0
        })
    }

    /// Whether the mesh covers the convex hull of its nodes (always true for [`Tin::new`]).
    pub fn is_convex(&self) -> bool {
        self.convex
    }

    /// Number of nodes.
    pub fn num_points(&self) -> usize {
        self.points.len()
    }

    /// Number of triangles.
    pub fn num_triangles(&self) -> usize {
        self.triangles.len()
    }

    /// Number of undirected edges.
    pub fn num_edges(&self) -> usize {
        // Each edge is listed from both ends.
        self.adjacency.len() / 2
    }

    /// Node positions.
    pub fn points(&self) -> &[DVec2] {
        &self.points
    }

    /// Triangles as counter-clockwise node triples.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Per triangle, the triangle across the edge opposite each corner ([`NO_TRIANGLE`] if none).
    pub fn triangle_neighbors(&self) -> &[[u32; 3]] {
        &self.triangle_neighbors
    }

    /// CSR offsets: the neighbours of `v` are `adjacency()[offsets[v]..offsets[v + 1]]`.
    pub fn adjacency_offsets(&self) -> &[u32] {
        &self.adjacency_offsets
    }

    /// CSR neighbour lists, concatenated.
    pub fn adjacency(&self) -> &[u32] {
        &self.adjacency
    }

    /// Nodes joined to `v` by an edge, counter-clockwise (open fans start and end on the boundary).
    #[inline]
    pub fn neighbors(&self, v: u32) -> &[u32] {
        let v = v as usize;
        &self.adjacency[self.adjacency_offsets[v] as usize..self.adjacency_offsets[v + 1] as usize]
    }

    /// Whether node `v` lies on the boundary (convex hull of a Delaunay TIN).
    #[inline]
    pub fn is_boundary(&self, v: u32) -> bool {
        self.boundary[v as usize]
    }

    /// Boundary flags of every node.
    pub fn boundary_flags(&self) -> &[bool] {
        &self.boundary
    }

    /// Every undirected edge once, as `(a, b)` with `a < b`.
    pub fn edges(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        (0..self.points.len() as u32)
            .flat_map(move |a| self.neighbors(a).iter().filter(move |&&b| a < b).map(move |&b| (a, b)))
    }

    /// Corner positions of triangle `t`.
    #[inline]
    pub fn triangle_points(&self, t: u32) -> [DVec2; 3] {
        self.triangles[t as usize].map(|v| self.points[v as usize])
    }

    /// Whether every edge is locally Delaunay: the node opposite an edge in one triangle is not
    /// strictly inside the circumcircle of the triangle on the other side (exact predicate). For a
    /// triangulation, locally Delaunay everywhere ⇔ globally Delaunay.
    pub fn is_delaunay(&self) -> bool {
        (0..self.triangles.len()).into_par_iter().all(|t| {
            let [a, b, c] = self.triangle_points(t as u32);
            self.triangle_neighbors[t].iter().all(|&u| {
                u == NO_TRIANGLE
                    || self.triangles[u as usize].iter().all(|&w| incircle(a, b, c, self.points[w as usize]) <= 0.0)
            })
        })
    }

    /// Verifies every structural invariant; unit tests, property tests and fuzz targets call this.
    ///
    /// Checked: triangles counter-clockwise and non-degenerate; neighbour links symmetric and
    /// sharing the right edge; adjacency symmetric, free of self-loops and duplicates, consistent
    /// with the triangles; boundary flags consistent with boundary edges; Euler's formula
    /// `V − E + T = 1` for a connected mesh without holes (a Delaunay TIN), or `V − E + T = 1 − holes`
    /// in general, where holes are counted from boundary loops.
    ///
    /// # Errors
    /// [`TinError::Invariant`] describing the first violation found.
    pub fn check_invariants(&self) -> Result<(), TinError> {
        let fail = |m: String| Err(TinError::Invariant(m));
        let n = self.points.len();
        if self.adjacency_offsets.len() != n + 1 || self.boundary.len() != n {
            return fail("per-node arrays have the wrong length".into());
        }
        if self.triangle_neighbors.len() != self.triangles.len() {
            return fail("per-triangle arrays have the wrong length".into());
        }
        let mut boundary_edges = 0usize;
        for (t, tri) in self.triangles.iter().enumerate() {
            let [a, b, c] = self.triangle_points(t as u32);
            if orient(a, b, c) <= 0.0 {
                return fail(format!("triangle {t} {tri:?} is not counter-clockwise"));
            }
            for k in 0..3 {
                let (p, q) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
                if !self.neighbors(p).contains(&q) || !self.neighbors(q).contains(&p) {
                    return fail(format!("edge {p}-{q} of triangle {t} missing from the adjacency"));
                }
                let u = self.triangle_neighbors[t][k];
                if u == NO_TRIANGLE {
                    boundary_edges += 1;
                    if !(self.boundary[p as usize] && self.boundary[q as usize]) {
                        return fail(format!("boundary edge {p}-{q} has a node not flagged as boundary"));
                    }
                    continue;
                }
                let other = self
                    .triangles
                    .get(u as usize)
                    .ok_or_else(|| TinError::Invariant(format!("triangle {t} links to missing {u}")))?;
                let back = other.iter().position(|&w| w != p && w != q);
                let Some(m) = back else {
                    return fail(format!("triangles {t} and {u} are linked but share all corners"));
                };
                if self.triangle_neighbors[u as usize][m] != t as u32 || !(other.contains(&p) && other.contains(&q)) {
                    return fail(format!("neighbour link {t} -> {u} is not symmetric across edge {p}-{q}"));
                }
            }
        }
        for v in 0..n as u32 {
            let nb = self.neighbors(v);
            if nb.len() < 2 {
                return fail(format!("node {v} has {} neighbours", nb.len()));
            }
            let mut sorted = nb.to_vec();
            sorted.sort_unstable();
            if sorted.windows(2).any(|w| w[0] == w[1]) || sorted.contains(&v) {
                return fail(format!("node {v} lists a duplicate neighbour or itself"));
            }
            if let Some(&w) = nb.iter().find(|&&w| w as usize >= n || !self.neighbors(w).contains(&v)) {
                return fail(format!("adjacency {v} -> {w} is not symmetric"));
            }
        }
        let boundary_nodes = self.boundary.iter().filter(|&&b| b).count();
        if boundary_nodes != boundary_edges {
            return fail(format!("{boundary_nodes} boundary nodes but {boundary_edges} boundary edges"));
        }
        // Euler: a triangulated surface of genus 0 with c components and b boundary loops has
        // V − E + T = 2c − b (a Delaunay TIN: one component, one loop, so 1).
        let (v, e, t) = (n as i64, self.num_edges() as i64, self.triangles.len() as i64);
        let (c, b) = (self.components() as i64, self.boundary_loops() as i64);
        if v - e + t != 2 * c - b {
            return fail(format!("Euler characteristic V − E + T = {v} − {e} + {t} ≠ 2·{c} − {b}"));
        }
        Ok(())
    }

    /// Number of closed loops formed by boundary edges.
    fn boundary_loops(&self) -> usize {
        let mut seen = vec![false; self.points.len()];
        let mut loops = 0;
        for start in 0..self.points.len() as u32 {
            if !self.boundary[start as usize] || seen[start as usize] {
                continue;
            }
            loops += 1;
            // An open fan starts at the boundary neighbour reached along the boundary with the
            // mesh on the left, so following first neighbours walks the loop.
            let mut v = start;
            while !seen[v as usize] {
                seen[v as usize] = true;
                v = self.neighbors(v)[0];
            }
        }
        loops
    }

    /// Number of connected components of the node graph.
    fn components(&self) -> usize {
        let mut seen = vec![false; self.points.len()];
        let mut stack = Vec::new();
        let mut count = 0;
        for start in 0..self.points.len() as u32 {
            if seen[start as usize] {
                continue;
            }
            count += 1;
            seen[start as usize] = true;
            stack.push(start);
            while let Some(v) = stack.pop() {
                for &w in self.neighbors(v) {
                    if !std::mem::replace(&mut seen[w as usize], true) {
                        stack.push(w);
                    }
                }
            }
        }
        count
    }
}

/// A spade vertex that remembers its input index (cheaper than `bulk_load_stable`, which costs
/// 15–25 % more than `bulk_load` on 10⁶ points here).
#[derive(Clone, Copy)]
struct Node {
    position: Point2<f64>,
    index: u32,
}

impl HasPosition for Node {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.position
    }
}

/// Triangles (spade's inner-face order, corners as input indices) and their neighbours, read
/// straight from spade's half-edge structure in parallel.
fn spade_triangles<T>(dt: &T) -> (Vec<[u32; 3]>, Vec<[u32; 3]>)
where
    T: Triangulation<Vertex = Node> + Sync,
    T::DirectedEdge: Sync,
    T::UndirectedEdge: Sync,
    T::Face: Sync,
{
    let faces: Vec<_> = dt.inner_faces().collect();
    // Spade numbers faces with the outer face first; after a bulk load the inner faces are
    // 1..=T, so triangle t is face t + 1. Map explicitly if that ever changes.
    let contiguous = faces.len() + 1 == dt.num_all_faces();
    let face_to_tri = if contiguous {
        Vec::new()
    } else {
        let mut map = vec![NO_TRIANGLE; dt.num_all_faces()];
        for (t, f) in faces.iter().enumerate() {
            map[f.fix().index()] = t as u32;
        }
        map
    };
    let tri_of = |face: usize| if contiguous { (face - 1) as u32 } else { face_to_tri[face] };
    faces
        .par_iter()
        .map(|f| {
            // Edge i runs from corner i to corner i + 1, so it lies opposite corner i + 2.
            let edges = f.adjacent_edges();
            let tri = edges.map(|e| e.from().data().index);
            let beyond = edges.map(|e| e.rev().face().as_inner().map_or(NO_TRIANGLE, |h| tri_of(h.index())));
            (tri, [beyond[1], beyond[2], beyond[0]])
        })
        .unzip()
}

/// CSR adjacency (input order) and boundary flags of a Delaunay mesh, walked on its own flat
/// `triangles` and `neighbors` (compact, unlike spade's half-edges), with the rotation rule of
/// [`fan`]: an open fan starts at the neighbour whose edge has no triangle on its right, a closed
/// fan at its smallest neighbour.
///
/// Fans are walked in triangle order — each vertex from the last triangle that lists it — so the
/// triangles a walk visits were stored near each other (spade creates them together) and stay in
/// cache; the finished fans are then scattered to their vertices' places. Against reading spade's
/// out-edges vertex by vertex in input order this halves the cost (`examples/wrapper_overhead.rs`).
fn mesh_fans(n: usize, triangles: &[[u32; 3]], neighbors: &[[u32; 3]]) -> (Vec<u32>, Vec<u32>, Vec<bool>) {
    const CHUNK: usize = 8192;
    // Each vertex is walked from one designated corner (the last listing it), flagged in
    // triangle order so the walks read the flags sequentially.
    let mut corner = vec![u32::MAX; n];
    for (t, tri) in triangles.iter().enumerate() {
        for (k, &v) in tri.iter().enumerate() {
            corner[v as usize] = (t as u32) << 2 | k as u32;
        }
    }
    let mut head = vec![false; 3 * triangles.len()];
    for &c in corner.iter().filter(|&&c| c != u32::MAX) {
        head[3 * (c >> 2) as usize + (c & 3) as usize] = true;
    }
    drop(corner);
    let runs: Vec<FanRun> = (0..triangles.len().div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let mut run = FanRun::with_capacity(CHUNK);
            let mut ring = Vec::with_capacity(16);
            for t in c * CHUNK..triangles.len().min((c + 1) * CHUNK) {
                for k in (0..3).filter(|&k| head[3 * t + k]) {
                    let before = run.fans.len();
                    let open = walk_fan(triangles, neighbors, t as u32, k, &mut ring, &mut run.fans);
                    run.heads.push((triangles[t][k], open, (run.fans.len() - before) as u32));
                }
            }
            run
        })
        .collect();
    let mut degree = vec![0u32; n];
    let mut boundary = vec![false; n];
    for &(v, open, len) in runs.iter().flat_map(|r| &r.heads) {
        degree[v as usize] = len;
        boundary[v as usize] = open;
    }
    let mut offsets = Vec::with_capacity(n + 1);
    offsets.push(0u32);
    for d in &degree {
        offsets.push(offsets[offsets.len() - 1] + d);
    }
    let mut adjacency = vec![0u32; offsets[n] as usize];
    for run in &runs {
        let mut from = 0usize;
        for &(v, _, len) in &run.heads {
            let (to, len) = (offsets[v as usize] as usize, len as usize);
            adjacency[to..to + len].copy_from_slice(&run.fans[from..from + len]);
            from += len;
        }
    }
    (offsets, adjacency, boundary)
}

/// Fans walked from one chunk of triangles: `(vertex, open, fan length)` and the fans, back to back.
struct FanRun {
    heads: Vec<(u32, bool, u32)>,
    fans: Vec<u32>,
}

impl FanRun {
    /// Room for the fans of `triangles` triangles: about one vertex per two, six neighbours each.
    fn with_capacity(triangles: usize) -> Self {
        Self { heads: Vec::with_capacity(triangles / 2 + 64), fans: Vec::with_capacity(3 * triangles + 256) }
    }
}

/// Appends the fan of the vertex at corner `k0` of triangle `t0` to `out` (canonical rotation) and
/// returns whether it is open. `ring` is scratch space.
fn walk_fan(
    triangles: &[[u32; 3]],
    neighbors: &[[u32; 3]],
    t0: u32,
    k0: usize,
    ring: &mut Vec<u32>,
    out: &mut Vec<u32>,
) -> bool {
    let v = triangles[t0 as usize][k0];
    let corner_of = |t: u32| triangles[t as usize].iter().position(|&w| w == v).unwrap_or(0);
    // Counter-clockwise: in (v, a, b) the next triangle shares v–b, the edge opposite corner k + 1.
    ring.clear();
    let (mut t, mut k) = (t0, k0);
    let open = loop {
        let tri = triangles[t as usize];
        ring.push(tri[(k + 1) % 3]);
        let next = neighbors[t as usize][(k + 1) % 3];
        if next == NO_TRIANGLE {
            ring.push(tri[(k + 2) % 3]);
            break true;
        }
        if next == t0 {
            break false;
        }
        t = next;
        k = corner_of(t);
    };
    if open {
        // The fan starts further clockwise, where the edge v–a has nothing beyond: collect the
        // neighbours there backwards, then the ring.
        let mark = out.len();
        let (mut t, mut k) = (t0, k0);
        loop {
            let prev = neighbors[t as usize][(k + 2) % 3];
            if prev == NO_TRIANGLE {
                break;
            }
            t = prev;
            k = corner_of(t);
            out.push(triangles[t as usize][(k + 1) % 3]);
        }
        out[mark..].reverse();
        out.extend_from_slice(ring);
    } else {
        let start = (0..ring.len()).min_by_key(|&k| ring[k]).unwrap_or(0);
        out.extend_from_slice(&ring[start..]);
        out.extend_from_slice(&ring[..start]);
    }
    open
}

/// Fans of a run of consecutive vertices, built in parallel and concatenated in order.
struct FanChunk {
    adjacency: Vec<u32>,
    degrees: Vec<u32>,
    boundary: Vec<bool>,
}

impl FanChunk {
    fn with_capacity(vertices: usize) -> Self {
        Self {
            adjacency: Vec::with_capacity(7 * vertices),
            degrees: Vec::with_capacity(vertices),
            boundary: Vec::with_capacity(vertices),
        }
    }

    /// Records the vertex whose fan was appended after `adjacency[..before]`.
    fn push_degree(&mut self, before: usize, open: bool) {
        self.degrees.push((self.adjacency.len() - before) as u32);
        self.boundary.push(open);
    }

    /// CSR offsets, concatenated adjacency and boundary flags.
    fn concat(chunks: Vec<FanChunk>) -> (Vec<u32>, Vec<u32>, Vec<bool>) {
        let n = chunks.iter().map(|c| c.degrees.len()).sum::<usize>();
        let mut offsets = Vec::with_capacity(n + 1);
        offsets.push(0u32);
        let mut adjacency = Vec::with_capacity(chunks.iter().map(|c| c.adjacency.len()).sum());
        let mut boundary = Vec::with_capacity(n);
        for chunk in chunks {
            adjacency.extend_from_slice(&chunk.adjacency);
            for d in chunk.degrees {
                offsets.push(offsets[offsets.len() - 1] + d);
            }
            boundary.extend_from_slice(&chunk.boundary);
        }
        (offsets, adjacency, boundary)
    }
}

/// Orders the triangles around `v` into its counter-clockwise fan, appending the neighbour nodes to
/// `adjacency` and linking consecutive triangles in `links`. Returns whether the fan is open (`v`
/// on the boundary); fails unless the triangles form exactly one fan (`visited` is scratch space).
///
/// `spans[i] = (a, b, e)`: triangle `e >> 2` has `v` at corner `k = e & 3` and spans the nodes
/// `a = t[k+1] → b = t[k+2]` counter-clockwise around `v`. The triangle after it in the fan starts
/// at `b`; they share edge `v–b`, which is opposite corner `k + 1` of the first triangle, so slot
/// `k + 1` of every triangle is set here, by its corner `k`: each slot exactly once over the mesh.
fn fan(
    v: usize,
    spans: &[(u32, u32, u32)],
    visited: &mut Vec<bool>,
    adjacency: &mut Vec<u32>,
    links: &[AtomicU32],
) -> Result<bool, TinError> {
    let bad = || TinError::NonManifoldVertex { vertex: v };
    if spans.is_empty() {
        return Err(bad());
    }
    // In a closed fan the start nodes and end nodes are the same multiset, so their sums agree;
    // only then may the walk start anywhere. Otherwise (a boundary vertex, or a broken mesh that
    // the walk below rejects) it starts at the span whose first node no span ends at.
    let (sa, sb) = spans.iter().fold((0u64, 0u64), |(sa, sb), &(a, b, _)| (sa + u64::from(a), sb + u64::from(b)));
    let start =
        if sa == sb { None } else { spans.iter().position(|&(a, _, _)| !spans.iter().any(|&(_, b, _)| b == a)) };
    let open = start.is_some();
    // Closed fans start at their smallest neighbour, so the adjacency does not depend on how the
    // triangles were listed (`Tin::new` applies the same rule).
    let start = start.unwrap_or_else(|| (0..spans.len()).min_by_key(|&k| spans[k].0).unwrap_or(0));
    visited.clear();
    visited.resize(spans.len(), false);
    visited[start] = true;
    adjacency.push(spans[start].0);
    let mut i = start;
    for step in 0..spans.len() {
        let last = step + 1 == spans.len();
        let (_, b, e) = spans[i];
        // Every span must be visited exactly once: a duplicate start node leaves one unvisited,
        // which forces a revisit or an early end below.
        match spans.iter().position(|&(a, _, _)| a == b) {
            Some(j) if !visited[j] || (j == start && last && !open) => {
                visited[j] = true;
                let slot = 3 * (e >> 2) as usize + ((e & 3) as usize + 1) % 3;
                links[slot].store(spans[j].2 >> 2, Ordering::Relaxed);
                i = j;
            }
            None if open && last => {}
            _ => return Err(bad()),
        }
        if open || !last {
            adjacency.push(b);
        }
    }
    // A closed fan must come back to its start.
    if !open && i != start {
        return Err(bad());
    }
    Ok(open)
}
