//! Error-bounded TIN approximation of a heightfield by greedy insertion (Garland & Heckbert 1995,
//! "Fast Polygonal Approximation of Terrains and Height Fields", algorithm III).
//!
//! Start from the grid's four corners; repeatedly insert the sample the current Delaunay mesh
//! misses by most, until every sample lies within the error bound or the triangle budget is
//! spent. Each triangle keeps its worst sample as a candidate in a max-heap; an insertion only
//! changes triangles around the new vertex (Lawson flips stay in its star), so only those are
//! rescanned. Work is done in grid-index space, where every orientation is an exact integer.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::DVec2;
use relief_heightfield::Heightfield;
use spade::handles::{FixedFaceHandle, InnerTag};
use spade::{DelaunayTriangulation, Point2, Triangulation};

use crate::{Tin, TinError};

/// How closely [`approximate`] follows the heightfield.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Approximation {
    /// Stop once no sample is farther than this from the mesh, vertically, in height units
    /// (0: until the mesh is exact).
    pub max_error: f64,
    /// Stop before the mesh would exceed this many triangles (at least 2).
    pub max_triangles: usize,
}

impl Default for Approximation {
    /// Exact, within one million triangles.
    fn default() -> Self {
        Self { max_error: 0.0, max_triangles: 1 << 20 }
    }
}

/// A heightfield's TIN approximation: the mesh over the grid's own coordinates, its nodes'
/// heights (grid samples, unchanged) and how far the farthest sample is from it.
#[derive(Debug, Clone)]
pub struct Approximated {
    /// The Delaunay mesh; nodes sit on grid samples.
    pub tin: Tin,
    /// Each node's height.
    pub heights: Vec<f64>,
    /// The largest vertical distance between a sample and the mesh.
    pub max_error: f64,
}

/// Greedy insertion of `hf`'s samples until every sample is within `options.max_error` of the
/// mesh or the next insertion would pass `options.max_triangles`. No-data samples count as the
/// lowest elevation. Ties go to the first sample in row order, so the mesh is the same on every
/// run.
///
/// # Errors
/// [`TinError::TooFewPoints`] for a grid under 2 × 2 samples, [`TinError::Invariant`] if spade
/// refuses a grid point (it cannot: coordinates are small integers).
///
/// ```
/// use glam::DVec2;
/// use relief_tin::{Approximation, approximate};
/// use relief_tin::heightfield::{GridSpec, Heightfield};
///
/// // A plane is two triangles, exactly.
/// let grid = GridSpec::new(65, 65, DVec2::ZERO, DVec2::ONE)?;
/// let plane = Heightfield::from_fn(grid, |p| (0.5 * p.x - p.y) as f32)?;
/// let mesh = approximate(&plane, &Approximation::default())?;
/// assert_eq!(mesh.tin.num_triangles(), 2);
/// assert!(mesh.max_error < 1e-3);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn approximate(hf: &Heightfield, options: &Approximation) -> Result<Approximated, TinError> {
    let (nx, ny) = (hf.nx(), hf.ny());
    if nx < 2 || ny < 2 {
        return Err(TinError::TooFewPoints { count: nx * ny });
    }
    let floor = hf.min_max().map_or(0.0, |(lo, _)| lo);
    let z: Vec<f64> = hf.samples().iter().map(|&v| f64::from(if v.is_nan() { floor } else { v })).collect();
    let mut state = Greedy::new(nx, ny, z, options.max_error);
    let corners = [0, nx - 1, nx * (ny - 1), nx * ny - 1];
    for k in corners {
        state.insert(k, None)?;
    }
    state.rescan_all();
    let budget = options.max_triangles.max(2);
    // An insertion adds at most two triangles (one on the hull's edge, two inside).
    while let Some(candidate) = state.best()
        && state.dt.num_inner_faces() + 2 <= budget
    {
        let v = state.insert(candidate.sample, Some(candidate.hint))?;
        state.rescan_star(v);
    }
    let max_error = state.max_error();
    // Cell sizes are positive: counter-clockwise in index space is counter-clockwise on the ground.
    let grid = hf.grid();
    let points: Vec<DVec2> = state.samples.iter().map(|&k| grid.position(k % nx, k / nx)).collect();
    let heights = state.samples.iter().map(|&k| state.z[k]).collect();
    let triangles = state.dt.inner_faces().map(|f| f.vertices().map(|v| v.fix().index() as u32)).collect();
    let tin = Tin::from_parts(points, triangles)?;
    Ok(Approximated { tin, heights, max_error })
}

/// A triangle's worst sample.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Candidate {
    error: f64,
    sample: usize,
    /// A vertex of its triangle: where spade's point location starts.
    hint: usize,
}

struct Greedy {
    nx: usize,
    z: Vec<f64>,
    dt: DelaunayTriangulation<Point2<f64>>,
    /// The grid sample of each spade vertex, in insertion order.
    samples: Vec<usize>,
    is_vertex: Vec<bool>,
    /// Per face: its current candidate and a stamp that invalidates older heap entries.
    candidates: Vec<(Option<Candidate>, u32)>,
    /// (error bits, first sample first, face, stamp) of candidates beyond the bound.
    heap: BinaryHeap<(u64, Reverse<usize>, usize, u32)>,
    bound: f64,
}

impl Greedy {
    fn new(nx: usize, ny: usize, z: Vec<f64>, bound: f64) -> Self {
        Self {
            nx,
            z,
            dt: DelaunayTriangulation::new(),
            samples: Vec::new(),
            is_vertex: vec![false; nx * ny],
            candidates: Vec::new(),
            heap: BinaryHeap::new(),
            bound,
        }
    }

    /// The largest distance of a sample from the mesh as it stands.
    fn max_error(&self) -> f64 {
        self.dt
            .fixed_inner_faces()
            .filter_map(|f| self.candidates.get(f.index()).and_then(|c| c.0))
            .fold(0.0, |m, c| m.max(c.error))
    }

    /// Inserts grid sample `k`, locating it from vertex `hint` (a vertex of the triangle it falls
    /// in: greedy insertion jumps around the grid, and a walk from the last insertion is long);
    /// returns its vertex.
    fn insert(&mut self, k: usize, hint: Option<usize>) -> Result<spade::handles::FixedVertexHandle, TinError> {
        let p = Point2::new((k % self.nx) as f64, (k / self.nx) as f64);
        let inserted = match hint {
            Some(h) => self.dt.insert_with_hint(p, spade::handles::FixedVertexHandle::from_index(h)),
            None => self.dt.insert(p),
        };
        let v = inserted.map_err(|e| TinError::Invariant(format!("spade refused grid point {k}: {e:?}")))?;
        debug_assert_eq!(v.index(), self.samples.len(), "a sample inserted twice");
        self.samples.push(k);
        self.is_vertex[k] = true;
        Ok(v)
    }

    fn rescan_all(&mut self) {
        let faces: Vec<_> = self.dt.fixed_inner_faces().collect();
        for f in faces {
            self.rescan(f);
        }
    }

    /// Rescans the triangles around vertex `v`: the only ones its insertion changed.
    fn rescan_star(&mut self, v: spade::handles::FixedVertexHandle) {
        let faces: Vec<_> =
            self.dt.vertex(v).out_edges().filter_map(|e| e.face().as_inner()).map(|f| f.fix()).collect();
        for f in faces {
            self.rescan(f);
        }
    }

    fn rescan(&mut self, f: FixedFaceHandle<InnerTag>) {
        let candidate = self.scan(f);
        let i = f.index();
        if self.candidates.len() <= i {
            self.candidates.resize(i + 1, (None, 0));
        }
        let entry = &mut self.candidates[i];
        entry.0 = candidate;
        entry.1 = entry.1.wrapping_add(1);
        if let Some(c) = candidate
            && c.error > self.bound
        {
            self.heap.push((c.error.to_bits(), Reverse(c.sample), i, entry.1));
        }
    }

    /// The current worst sample beyond the bound over all triangles, dropping stale heap entries.
    fn best(&mut self) -> Option<Candidate> {
        while let Some(&(_, _, face, stamp)) = self.heap.peek() {
            let (candidate, current) = self.candidates[face];
            if stamp == current {
                return candidate;
            }
            self.heap.pop();
        }
        None
    }

    /// The sample inside triangle `f` (edges included, vertices excluded) farthest from its
    /// plane.
    fn scan(&self, f: FixedFaceHandle<InnerTag>) -> Option<Candidate> {
        let face = self.dt.face(f);
        let hint = face.vertices()[0].fix().index();
        let [a, b, c] = face.vertices().map(|v| {
            let k = self.samples[v.fix().index()];
            (((k % self.nx) as i64, (k / self.nx) as i64), self.z[k])
        });
        let area = orient(a.0, b.0, c.0);
        if area <= 0 {
            return None;
        }
        let (xs, ys) = ([a.0.0, b.0.0, c.0.0], [a.0.1, b.0.1, c.0.1]);
        let (x0, x1) = (xs.iter().min()?, xs.iter().max()?);
        let (y0, y1) = (ys.iter().min()?, ys.iter().max()?);
        let inv = 1.0 / area as f64;
        let mut best: Option<Candidate> = None;
        for y in *y0..=*y1 {
            let row = y as usize * self.nx;
            for x in *x0..=*x1 {
                let p = (x, y);
                let (wa, wb, wc) = (orient(b.0, c.0, p), orient(c.0, a.0, p), orient(a.0, b.0, p));
                if wa < 0 || wb < 0 || wc < 0 {
                    continue;
                }
                let k = row + x as usize;
                if self.is_vertex[k] {
                    continue;
                }
                let plane = (wa as f64 * a.1 + wb as f64 * b.1 + wc as f64 * c.1) * inv;
                let error = (self.z[k] - plane).abs();
                if best.is_none_or(|c| error > c.error) {
                    best = Some(Candidate { error, sample: k, hint });
                }
            }
        }
        best
    }
}

/// Twice the signed area of (a, b, c), exact on grid indices.
fn orient(a: (i64, i64), b: (i64, i64), c: (i64, i64)) -> i64 {
    (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_heightfield::GridSpec;

    fn field(n: usize, f: impl Fn(f64, f64) -> f64) -> Heightfield {
        let grid = GridSpec::new(n, n, DVec2::ZERO, DVec2::splat(2.0)).unwrap();
        Heightfield::from_fn(grid, |p| f(p.x, p.y) as f32).unwrap()
    }

    /// The largest vertical gap between the samples and the mesh, measured independently by
    /// rasterizing the TIN.
    fn measured_error(hf: &Heightfield, mesh: &Approximated) -> f64 {
        let raster = mesh.tin.rasterize(&mesh.heights, hf.grid()).unwrap();
        assert_eq!(raster.no_data_count(), 0, "the mesh covers the whole grid");
        hf.samples().iter().zip(raster.samples()).map(|(a, b)| f64::from((a - b).abs())).fold(0.0, f64::max)
    }

    #[test]
    fn the_bound_holds_and_is_reported() {
        let hf = field(97, |x, y| 40.0 * (x / 30.0).sin() * (y / 45.0).cos() + 0.01 * x * y);
        for bound in [4.0, 1.0, 0.25] {
            let mesh = approximate(&hf, &Approximation { max_error: bound, ..Approximation::default() }).unwrap();
            let measured = measured_error(&hf, &mesh);
            assert!(mesh.max_error <= bound, "{} > {bound}", mesh.max_error);
            // f32 rasterization rounds: a little slack.
            assert!(measured <= bound + 1e-3, "bound {bound}: measured {measured}");
            assert!(measured >= mesh.max_error - 1e-3, "reported {} but measured {measured}", mesh.max_error);
            mesh.tin.check_invariants().unwrap();
        }
    }

    #[test]
    fn finer_bounds_take_more_triangles_and_the_budget_caps_them() {
        let hf = field(65, |x, y| 10.0 * ((x * x + y * y).sqrt() / 20.0).sin());
        let count = |max_error, max_triangles| {
            let m = approximate(&hf, &Approximation { max_error, max_triangles }).unwrap();
            (m.tin.num_triangles(), m.max_error)
        };
        let (coarse, _) = count(1.0, usize::MAX);
        let (fine, _) = count(0.05, usize::MAX);
        assert!(coarse < fine, "{coarse} !< {fine}");
        let (capped, error) = count(0.0, 100);
        assert!((97..=100).contains(&capped), "{capped}");
        assert!(error > 0.05, "a 100-triangle cone cannot be that close: {error}");
    }

    #[test]
    fn greedy_insertion_beats_a_uniform_mesh_of_the_same_size() {
        // A sharp ridge: greedy insertion puts vertices on it, a regular grid straddles it.
        let hf = field(129, |x, y| if (x - y).abs() < 3.0 { 50.0 - 10.0 * (x - y).abs() } else { 20.0 });
        let greedy = approximate(&hf, &Approximation { max_error: 0.0, max_triangles: 512 }).unwrap();
        let coarse = hf.resample(17, 17).unwrap().resample(129, 129).unwrap();
        let uniform = hf.samples().iter().zip(coarse.samples()).map(|(a, b)| (a - b).abs()).fold(0.0, f32::max);
        assert!(greedy.max_error < 0.5 * f64::from(uniform), "{} vs {uniform}", greedy.max_error);
    }

    #[test]
    fn exact_meshes_and_tiny_grids() {
        let plane = field(33, |x, y| 3.0 * x - y);
        let m = approximate(&plane, &Approximation::default()).unwrap();
        assert_eq!((m.tin.num_points(), m.tin.num_triangles()), (4, 2));
        let two = field(2, |x, _| x);
        assert_eq!(approximate(&two, &Approximation::default()).unwrap().tin.num_triangles(), 2);
        let one = Heightfield::from_fn(GridSpec::new(1, 5, DVec2::ZERO, DVec2::ONE).unwrap(), |_| 0.0).unwrap();
        assert_eq!(approximate(&one, &Approximation::default()).unwrap_err(), TinError::TooFewPoints { count: 5 });
        // Exact on a bumpy field: every sample on the mesh.
        let bumpy = field(17, |x, y| ((x * 7.0 + y * 13.0) % 5.0).floor());
        let m = approximate(&bumpy, &Approximation::default()).unwrap();
        assert!(measured_error(&bumpy, &m) < 1e-4 && m.max_error == 0.0);
    }
}
