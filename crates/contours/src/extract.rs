use glam::DVec2;
use rayon::prelude::*;
use relief_tin::{NO_TRIANGLE, Tin};

use crate::levels::check_levels;
use crate::{Contour, ContourSet, ContoursError};

/// A triangle mesh with heights at its nodes (the TIN of a generated terrain). Triangles are counter-clockwise; neighbour `k` lies across the edge
/// opposite corner `k`. A NaN height marks no-data.
pub(crate) trait Mesh: Sync {
    fn num_triangles(&self) -> usize;
    fn corners(&self, t: u32) -> [u32; 3];
    fn neighbor(&self, t: u32, k: usize) -> Option<u32>;
    fn point(&self, v: u32) -> DVec2;
    fn height(&self, v: u32) -> f64;
}

pub(crate) struct TinMesh<'a> {
    pub(crate) tin: &'a Tin,
    pub(crate) heights: &'a [f64],
}

impl Mesh for TinMesh<'_> {
    fn num_triangles(&self) -> usize {
        self.tin.num_triangles()
    }
    fn corners(&self, t: u32) -> [u32; 3] {
        self.tin.triangles()[t as usize]
    }
    fn neighbor(&self, t: u32, k: usize) -> Option<u32> {
        let u = self.tin.triangle_neighbors()[t as usize][k];
        (u != NO_TRIANGLE).then_some(u)
    }
    fn point(&self, v: u32) -> DVec2 {
        self.tin.points()[v as usize]
    }
    fn height(&self, v: u32) -> f64 {
        self.heights[v as usize]
    }
}

/// Triangles per parallel work item.
const CHUNK: usize = 4096;

/// Fraction of an edge by which a crossing exactly at a node is moved off it: the numeric form
/// of the symbolic rule "a node at the level counts as above", which keeps contours apart.
const TIE_NUDGE: f64 = 1e-6;

/// One contour segment inside a triangle, oriented with higher ground on its left: it enters
/// through the edge opposite corner `entry_slot` and leaves through the one opposite `exit_slot`.
/// Its end points are computed again when the polylines are linked ([`edge_crossing`]), which
/// keeps a segment at 8 bytes.
#[derive(Clone, Copy)]
struct Segment {
    level: u32,
    entry_slot: u8,
    exit_slot: u8,
}

/// Where the level `l` crosses the edge between nodes `a` and `b` (one above, one below).
/// Computed from the endpoints in node-index order so both triangles sharing the edge agree.
fn crossing(mesh: &impl Mesh, a: u32, b: u32, l: f64) -> DVec2 {
    let (u, v) = if a < b { (a, b) } else { (b, a) };
    let (hu, hv) = (mesh.height(u), mesh.height(v));
    let t = ((l - hu) / (hv - hu)).clamp(TIE_NUDGE, 1.0 - TIE_NUDGE);
    let (pu, pv) = (mesh.point(u), mesh.point(v));
    pu + t * (pv - pu)
}

/// Where level `l` crosses the edge of triangle `t` opposite corner `slot`.
fn edge_crossing(mesh: &impl Mesh, t: u32, slot: u8, l: f64) -> DVec2 {
    let c = mesh.corners(t);
    let k = usize::from(slot);
    crossing(mesh, c[(k + 1) % 3], c[(k + 2) % 3], l)
}

/// The segments of triangle `t`, one per level strictly inside its height range, in level order.
fn triangle_segments(mesh: &impl Mesh, levels: &[f64], t: u32, out: &mut Vec<Segment>) {
    let c = mesh.corners(t);
    let h = c.map(|v| mesh.height(v));
    if h.iter().any(|x| x.is_nan()) {
        return;
    }
    let lo = h[0].min(h[1]).min(h[2]);
    let hi = h[0].max(h[1]).max(h[2]);
    // Mixed for level L iff lo < L <= hi (a node at exactly L counts as above).
    let first = levels.partition_point(|&l| l <= lo);
    let last = levels.partition_point(|&l| l <= hi);
    for (k, &l) in levels.iter().enumerate().take(last).skip(first) {
        let above = h.map(|x| x >= l);
        let count = above.iter().filter(|&&a| a).count();
        // The lone corner (the only one above, or the only one below).
        let i = (0..3).find(|&i| above[i] == (count == 1)).unwrap_or(0);
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        // The crossing on edge (v_i, v_i+1) is opposite corner i+2, the one on (v_i+2, v_i)
        // opposite corner i+1; higher ground stays on the left.
        let (entry_slot, exit_slot) = if count == 1 { (i2, i1) } else { (i1, i2) };
        out.push(Segment { level: k as u32, entry_slot: entry_slot as u8, exit_slot: exit_slot as u8 });
    }
}

/// Every triangle's segments, parallel over chunks of triangles. Segments stay in their chunks
/// (no second copy of them all): the segments of triangle `t` are in chunk t / CHUNK, from global
/// index `offsets[t]` on, and chunk c starts at `base[c]`.
struct Segments {
    chunks: Vec<Vec<Segment>>,
    base: Vec<usize>,
    offsets: Vec<u32>,
    /// The triangle of each segment, by global index.
    owner: Vec<u32>,
}

impl Segments {
    fn new(mesh: &impl Mesh, levels: &[f64]) -> Self {
        let n = mesh.num_triangles();
        let per_chunk: Vec<(Vec<u32>, Vec<Segment>)> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let mut counts = Vec::with_capacity(CHUNK);
                let mut segs = Vec::new();
                for t in c * CHUNK..n.min((c + 1) * CHUNK) {
                    let before = segs.len();
                    triangle_segments(mesh, levels, t as u32, &mut segs);
                    counts.push((segs.len() - before) as u32);
                }
                segs.shrink_to_fit();
                (counts, segs)
            })
            .collect();
        let mut offsets = Vec::with_capacity(n + 1);
        offsets.push(0u32);
        let mut base = Vec::with_capacity(per_chunk.len());
        let mut chunks = Vec::with_capacity(per_chunk.len());
        for (counts, segs) in per_chunk {
            base.push(offsets[offsets.len() - 1] as usize);
            for c in counts {
                offsets.push(offsets[offsets.len() - 1] + c);
            }
            chunks.push(segs);
        }
        let mut owner: Vec<u32> = Vec::with_capacity(offsets[n] as usize);
        for t in 0..n {
            owner.extend(std::iter::repeat_n(t as u32, (offsets[t + 1] - offsets[t]) as usize));
        }
        Self { chunks, base, offsets, owner }
    }

    fn len(&self) -> usize {
        self.owner.len()
    }

    fn get(&self, s: usize) -> Segment {
        let c = self.owner[s] as usize / CHUNK;
        self.chunks[c][s - self.base[c]]
    }

    /// The segment of `level` in triangle `t`, if any (a triangle's segments are in level order).
    fn find(&self, t: u32, level: u32) -> Option<usize> {
        let c = t as usize / CHUNK;
        let (a, b) = (self.offsets[t as usize] as usize, self.offsets[t as usize + 1] as usize);
        let local = &self.chunks[c][a - self.base[c]..b - self.base[c]];
        let k = local.partition_point(|s| s.level < level);
        (k < local.len() && local[k].level == level).then_some(a + k)
    }

    /// The segment that continues `s` across its exit edge (or, with `back`, its entry edge).
    fn neighbour(&self, mesh: &impl Mesh, s: usize, back: bool) -> Option<usize> {
        let seg = self.get(s);
        let slot = if back { seg.entry_slot } else { seg.exit_slot };
        mesh.neighbor(self.owner[s], usize::from(slot)).and_then(|u| self.find(u, seg.level))
    }
}

/// Marching triangles over `mesh` for all `levels` at once: O(triangles + output), parallel over
/// triangles, then segments are linked through the mesh's neighbour relation into polylines.
pub(crate) fn extract(mesh: &impl Mesh, levels: &[f64]) -> Result<ContourSet, ContoursError> {
    check_levels(levels)?;
    let segments = Segments::new(mesh, levels);
    let mut visited = vec![false; segments.len()];
    let mut contours = Vec::new();
    for s0 in 0..segments.len() {
        if !visited[s0] {
            contours.push(link(mesh, &segments, levels, s0, &mut visited));
        }
    }
    // The segments are not needed for the nesting tree: free them first.
    drop((segments, visited));
    ContourSet::new(levels.to_vec(), contours)
}

/// The polyline through segment `s0`: walked back to the start of an open chain (or all the way
/// round a closed one), then forward, marking its segments visited.
fn link(mesh: &impl Mesh, segments: &Segments, levels: &[f64], s0: usize, visited: &mut [bool]) -> Contour {
    let mut start = s0;
    let mut closed = false;
    while let Some(p) = segments.neighbour(mesh, start, true) {
        if p == s0 {
            closed = true;
            break;
        }
        start = p;
    }
    let level = segments.get(s0).level;
    let height = levels[level as usize];
    let at = |s: usize, slot: u8| edge_crossing(mesh, segments.owner[s], slot, height);
    let mut points = Vec::new();
    let mut s = start;
    loop {
        visited[s] = true;
        let seg = segments.get(s);
        points.push(at(s, seg.entry_slot));
        match segments.neighbour(mesh, s, false) {
            Some(q) if q == start && closed => break,
            Some(q) if !visited[q] => s = q,
            _ => {
                points.push(at(s, seg.exit_slot));
                break;
            }
        }
    }
    points.dedup();
    points.shrink_to_fit();
    Contour { level, height, points, closed }
}

/// Contours of per-node `heights` on `tin` at each of `levels` (sorted ascending).
///
/// Closed contours run counter-clockwise around higher ground; contours reaching the mesh
/// boundary or no-data (NaN heights) are open.
///
/// # Errors
/// [`ContoursError::HeightCountMismatch`], [`ContoursError::InvalidLevels`].
pub fn extract_tin(tin: &Tin, heights: &[f64], levels: &[f64]) -> Result<ContourSet, ContoursError> {
    if heights.len() != tin.num_points() {
        return Err(ContoursError::HeightCountMismatch { expected: tin.num_points(), found: heights.len() });
    }
    extract(&TinMesh { tin, heights }, levels)
}
