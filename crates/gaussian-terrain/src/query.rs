//! Continuous queries (§3.2: a vector terrain is a function of the plane, not a grid): the
//! elevation, gradient and normal at any point, with no raster. The supports of the primitives
//! and of the detail falloffs go into a bounding volume hierarchy (`obvhs`, a maintained BVH
//! library: PLOC construction and stack traversal, which a hand-written grid would only
//! approximate for primitives whose sizes span three orders of magnitude).
//!
//! Queries go by cells of a fixed lattice about a typical support wide: a cell walks the
//! hierarchy once for the supports that may reach it and cuts its points into groups of 16
//! neighbours (along a Z-order curve). Each support is added to each group it may reach with
//! the rasterizer's branch-free f32 arithmetic (module `fastmath`), the loop over the group's
//! points vectorized (AVX2 through `pulp` where the CPU has it); the test of whether it reaches
//! a group is conservative, so a group skips only supports that add nothing to any of its
//! points. A single query is a cell with one point, and each point sums the supports over it in
//! index order whatever the other points of its cell, so a batch returns exactly the single
//! queries' values, for any thread count.

use glam::{DVec2, DVec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::bvh2::builder::build_bvh2;
use rayon::prelude::*;

use crate::fastmath::{exp_neg, exp2_signed, log2};
use crate::{DetailLayer, Gaussian, GaussianError, Ground, VectorTerrain};

/// Side of the query lattice's cells, in typical support widths (measured best among 0.5–2 on
/// the rasterizer benchmark's terrain).
const CELL_PER_SUPPORT: f64 = 1.0;

/// Cells per parallel task in the batched queries.
const CELLS_PER_TASK: usize = 16;

/// The elevation and its gradient at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// `h(p)`, world units of elevation.
    pub elevation: f64,
    /// `∇h(p) = (∂h/∂x, ∂h/∂y)`, elevation per world unit.
    pub gradient: DVec2,
}

impl Sample {
    /// The upward unit normal of the surface `z = h(x, y)`: `(−∂h/∂x, −∂h/∂y, 1)` normalized.
    pub fn normal(&self) -> DVec3 {
        DVec3::new(-self.gradient.x, -self.gradient.y, 1.0).normalize()
    }
}

/// One support in the hierarchy: a primitive (or a detail falloff, amplitude 1) ready to
/// evaluate.
struct Item {
    center: DVec2,
    /// Rows of `A⁻¹`: local coordinates are `(d·u, d·v)`.
    u: DVec2,
    v: DVec2,
    /// Squared support radius in `d` units.
    r2: f64,
    amplitude: f64,
    half_beta: f64,
    /// The support's bounding box.
    lo: DVec2,
    hi: DVec2,
}

impl Item {
    fn new(g: &Gaussian, tolerance: f64) -> Self {
        let (u, v) = g.inverse_axes();
        let r = g.support_radius(tolerance);
        let (lo, hi) = g.bounds(tolerance);
        Self { center: DVec2::from(g.center), u, v, r2: r * r, amplitude: g.amplitude, half_beta: 0.5 * g.beta, lo, hi }
    }

    /// The value at `p` in f64, 0 outside the support (a detail falloff's weight).
    fn value(&self, p: DVec2) -> f64 {
        let d = p - self.center;
        let (x, y) = (d.dot(self.u), d.dot(self.v));
        let s = x * x + y * y;
        if s > self.r2 { 0.0 } else { self.amplitude * (-0.5 * s.powf(self.half_beta)).exp() }
    }

    /// Whether the support may reach the box `[lo, hi]` grown by `slack` ([`reaches`]). A cull
    /// for the whole cell: the groups of its points test again, so a support let through that
    /// reaches none of them only costs time.
    fn meets(&self, lo: DVec2, hi: DVec2, slack: f64) -> bool {
        let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo) + slack);
        reaches(mid - self.center, self.u, self.v, self.r2.sqrt(), half)
    }
}

/// Whether a support (centre at `−d` from `mid`, inverse axes `u`, `v`, radius `r` in `d`
/// units) may reach a point of the box `mid ± half`: in the support's `d` coordinates the box
/// is a parallelogram inside the rectangle `m ± e`, `e = (|u|·half, |v|·half)`, so none of it is
/// inside when that rectangle keeps further than `r` from the centre (conservative, and tight
/// for thin boxes and elongated supports alike). `r` gets a relative 10⁻⁴ on top, far above the
/// f32 rounding of the kernel's own inside test.
fn reaches(d: DVec2, u: DVec2, v: DVec2, r: f64, half: DVec2) -> bool {
    let gap = |m: f64, axis: DVec2| (m.abs() - axis.abs().dot(half)).max(0.0);
    let (x, y) = (gap(d.dot(u), u), gap(d.dot(v), v));
    let limit = r * (1.0 + 1e-4);
    x * x + y * y <= limit * limit
}

/// A vector terrain prepared for point queries: [`VectorTerrain::query`] builds it.
///
/// Values agree with [`crate::rasterize`] at its samples (the same truncated supports, f32
/// arithmetic and f32 sums, so to f32 rounding except where a sample lies on the very edge of a
/// support) and with [`VectorTerrain::height_at`] to within the
/// truncation tolerance. Gradients are the analytic derivative of each support,
/// `∇g = −g·(β/2)·d^(β−2)·A⁻ᵀA⁻¹(p − c)`; a detail layer's noise or error map has no
/// closed-form gradient, so its part is a central difference over 10⁻³ of the layer's σ.
/// A non-finite point gives NaN.
///
/// # Example
/// ```
/// use glam::DVec2;
/// use relief_gaussian_terrain::{Gaussian, VectorTerrain};
///
/// let terrain = VectorTerrain::new(vec![Gaussian::round(DVec2::new(0.0, 0.0), 10.0, 100.0)]);
/// let query = terrain.query()?;
/// let top = query.sample(DVec2::ZERO);
/// assert!((top.elevation - 100.0).abs() < 1e-9 && top.gradient.length() < 1e-9);
/// // East of the top the ground falls to the east: the normal leans east.
/// assert!(query.sample(DVec2::new(10.0, 0.0)).normal().x > 0.0);
/// let heights = query.elevations(&[DVec2::ZERO, DVec2::new(1e6, 0.0)]);
/// assert_eq!(heights[1], 0.0);
/// # Ok::<(), relief_gaussian_terrain::GaussianError>(())
/// ```
pub struct TerrainQuery {
    /// Boxes are stored relative to this point, so f32 keeps them tight far from the origin.
    origin: DVec2,
    bvh: Bvh2,
    /// The Gaussians, then each detail layer's falloffs, in order.
    items: Vec<Item>,
    /// `items[gaussians..]` are detail falloffs.
    gaussians: usize,
    /// Each detail layer and the end of its falloffs in `items`.
    layers: Vec<(DetailLayer, usize)>,
    base: f64,
    /// [`VectorTerrain::floor`].
    floor: Option<f64>,
    /// Side of the lattice of query cells, anchored at `origin`.
    cell: f64,
}

impl std::fmt::Debug for TerrainQuery {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TerrainQuery")
            .field("gaussians", &self.gaussians)
            .field("detail_layers", &self.layers.len())
            .field("nodes", &self.bvh.nodes.len())
            .finish_non_exhaustive()
    }
}

impl VectorTerrain {
    /// Prepares continuous queries at the default tolerance ([`crate::DEFAULT_TOLERANCE`]).
    ///
    /// # Errors
    /// The terrain's [`VectorTerrain::validate`] errors.
    pub fn query(&self) -> Result<TerrainQuery, GaussianError> {
        self.query_with(crate::DEFAULT_TOLERANCE)
    }

    /// Prepares continuous queries, each primitive cut off below `tolerance·|a|` as in
    /// [`crate::RasterOptions::tolerance`].
    ///
    /// # Errors
    /// The terrain's [`VectorTerrain::validate`] errors; [`GaussianError::InvalidOption`] for a
    /// tolerance outside `(0, 1)`.
    pub fn query_with(&self, tolerance: f64) -> Result<TerrainQuery, GaussianError> {
        if !(tolerance > 0.0 && tolerance < 1.0) {
            return Err(GaussianError::InvalidOption {
                name: "tolerance",
                value: tolerance,
                reason: "must be in (0, 1)",
            });
        }
        self.validate()?;
        let mut supports: Vec<Gaussian> = self.primitives.clone();
        let mut layers = Vec::with_capacity(self.details.len());
        for layer in &self.details {
            supports.extend(layer.falloffs());
            layers.push((layer.clone(), supports.len()));
        }
        let bounds: Vec<(DVec2, DVec2)> = supports.iter().map(|g| g.bounds(tolerance)).collect();
        let origin = bounds.iter().map(|&(lo, hi)| 0.5 * (lo + hi)).sum::<DVec2>() / bounds.len().max(1) as f64;
        let boxes: Vec<Aabb> = bounds.iter().map(|&(lo, hi)| outward_box(lo - origin, hi - origin)).collect();
        let bvh = if boxes.is_empty() {
            Bvh2::default()
        } else {
            let mut build_time = std::time::Duration::ZERO;
            build_bvh2(&boxes, BvhBuildParams::fast_build(), &mut build_time)
        };
        let items: Vec<Item> = supports.iter().map(|g| Item::new(g, tolerance)).collect();
        let cell = CELL_PER_SUPPORT
            * typical_width(&items[..if self.primitives.is_empty() { items.len() } else { self.primitives.len() }]);
        let (gaussians, base, floor) = (self.primitives.len(), self.base, self.floor);
        Ok(TerrainQuery { origin, bvh, items, gaussians, layers, base, floor, cell })
    }
}

/// A traversal's visit of the leaf `node`: appends its supports' indices to `into` and goes on.
fn collect_leaf(bvh: &Bvh2, node: u32, into: &mut Vec<u32>) -> bool {
    let node = &bvh.nodes[node as usize];
    let first = node.first_index as usize;
    into.extend_from_slice(&bvh.primitive_indices[first..first + node.prim_count as usize]);
    true
}

/// An f32 box that holds the f64 box `[lo, hi]`: widened by a relative 10⁻⁶, well above f32
/// rounding, so a point inside the f64 box is never culled.
fn outward_box(lo: DVec2, hi: DVec2) -> Aabb {
    let pad = |v: DVec2| v.abs() * 1e-6 + DVec2::splat(1e-9);
    let (a, b) = (lo - pad(lo), hi + pad(hi));
    Aabb::new(Vec3A::new(a.x as f32, a.y as f32, -1.0), Vec3A::new(b.x as f32, b.y as f32, 1.0))
}

/// The median of the supports' narrowest box widths (1 when there is none).
fn typical_width(items: &[Item]) -> f64 {
    let mut widths: Vec<f64> = items.iter().map(|i| (i.hi - i.lo).min_element()).filter(|w| *w > 0.0).collect();
    if widths.is_empty() {
        return 1.0;
    }
    let mid = widths.len() / 2;
    *widths.select_nth_unstable_by(mid, f64::total_cmp).1
}

impl TerrainQuery {
    /// Number of supports (primitives and detail falloffs) in the hierarchy.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// Whether the terrain has no primitive and no detail (a flat terrain at its base).
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// The elevation at `p`.
    pub fn elevation(&self, p: DVec2) -> f64 {
        self.single(p, false).elevation
    }

    /// The elevation and gradient at `p`.
    pub fn sample(&self, p: DVec2) -> Sample {
        self.single(p, true)
    }

    /// [`Self::sample`], the gradient left at zero unless `gradients`.
    fn single(&self, p: DVec2, gradients: bool) -> Sample {
        let Some(key) = self.cell_of(p) else { return self.beyond(p) };
        let mut out = Vec::with_capacity(1);
        self.cell_samples(key, &[p], &[0], gradients, &mut Block::default(), &mut out);
        out[0].1
    }

    /// The upward unit normal at `p`.
    pub fn normal(&self, p: DVec2) -> DVec3 {
        self.sample(p).normal()
    }

    /// The elevations at `points`, in parallel: the same values as [`Self::elevation`] one by
    /// one (and as the elevations of [`Self::samples`]), for any thread count. The gradients
    /// are not computed (unless a detail layer's amplitude follows the slope), which matters
    /// most with detail layers: their gradient is a central difference.
    pub fn elevations(&self, points: &[DVec2]) -> Vec<f64> {
        self.batch(points, false).into_iter().map(|s| s.elevation).collect()
    }

    /// The elevations and gradients at `points`, in parallel: the same values as
    /// [`Self::sample`] one by one, for any thread count. Points close together share one walk
    /// of the hierarchy, so a batch in the order of a grid or a track is the fast case.
    pub fn samples(&self, points: &[DVec2]) -> Vec<Sample> {
        self.batch(points, true)
    }

    /// [`Self::samples`], the gradients left at zero unless `gradients`.
    fn batch(&self, points: &[DVec2], gradients: bool) -> Vec<Sample> {
        let mut out: Vec<Sample> = points.iter().map(|&p| self.beyond(p)).collect();
        let cells = self.bucket(points);
        let parts: Vec<Vec<(u32, Sample)>> = cells
            .par_chunks(CELLS_PER_TASK)
            .map(|cells| {
                let mut block = Block::default();
                let mut part = Vec::new();
                for (key, members) in cells {
                    self.cell_samples(*key, points, members, gradients, &mut block, &mut part);
                }
                part
            })
            .collect();
        for (k, s) in parts.into_iter().flatten() {
            out[k as usize] = s;
        }
        out
    }

    /// A point no cell holds: NaN when it is not finite, else so far out (beyond the lattice's
    /// i32 range) that no support reaches it: the base.
    fn beyond(&self, p: DVec2) -> Sample {
        let elevation = self.floor.map_or(self.base, |f| self.base.max(f));
        if p.is_finite() { Sample { elevation, gradient: DVec2::ZERO } } else { Sample::NAN }
    }

    /// The lattice cell of `p`, `None` when it is not finite or beyond the lattice's i32 range.
    fn cell_of(&self, p: DVec2) -> Option<(i32, i32)> {
        let c = ((p - self.origin) / self.cell).floor();
        let fits = |v: f64| v.is_finite() && v.abs() < f64::from(i32::MAX);
        (fits(c.x) && fits(c.y)).then_some((c.x as i32, c.y as i32))
    }

    /// The finite points grouped by lattice cell, cells in (y, x) order.
    fn bucket(&self, points: &[DVec2]) -> Vec<((i32, i32), Vec<u32>)> {
        let keys: Vec<Option<(i32, i32)>> = points.iter().map(|&p| self.cell_of(p)).collect();
        let (lo, hi) = keys.iter().flatten().fold(((i32::MAX, i32::MAX), (i32::MIN, i32::MIN)), |(a, b), &(x, y)| {
            ((a.0.min(x), a.1.min(y)), (b.0.max(x), b.1.max(y)))
        });
        if lo.0 > hi.0 {
            return Vec::new();
        }
        let (w, h) = (i64::from(hi.0) - i64::from(lo.0) + 1, i64::from(hi.1) - i64::from(lo.1) + 1);
        if w.saturating_mul(h) > points.len() as i64 + 64 {
            return Self::bucket_sparse(&keys);
        }
        // Dense (no more cells in the window than points, so the buckets cost at most one empty
        // list per point): a counting sort over the lattice window.
        let slot =
            |(x, y): (i32, i32)| ((i64::from(y) - i64::from(lo.1)) * w + i64::from(x) - i64::from(lo.0)) as usize;
        let mut cells: Vec<Vec<u32>> = vec![Vec::new(); (w * h) as usize];
        for (k, key) in keys.iter().enumerate() {
            if let Some(key) = key {
                cells[slot(*key)].push(k as u32);
            }
        }
        let at = |s: usize| (lo.0 + (s as i64 % w) as i32, lo.1 + (s as i64 / w) as i32);
        cells.into_iter().enumerate().filter(|(_, m)| !m.is_empty()).map(|(s, m)| (at(s), m)).collect()
    }

    /// [`Self::bucket`] for points spread thin over a wide window: a sort by cell.
    fn bucket_sparse(keys: &[Option<(i32, i32)>]) -> Vec<((i32, i32), Vec<u32>)> {
        let mut keyed: Vec<((i32, i32), u32)> =
            keys.iter().enumerate().filter_map(|(k, key)| key.map(|(x, y)| ((y, x), k as u32))).collect();
        keyed.sort_unstable();
        let mut cells: Vec<((i32, i32), Vec<u32>)> = Vec::new();
        for ((y, x), k) in keyed {
            match cells.last_mut() {
                Some((key, members)) if *key == (x, y) => members.push(k),
                _ => cells.push(((x, y), vec![k])),
            }
        }
        cells
    }

    /// The samples at `points[members]`, all in the lattice cell `key`: the supports over the
    /// cell once, then every point against all of them.
    fn cell_samples(
        &self,
        key: (i32, i32),
        points: &[DVec2],
        members: &[u32],
        gradients: bool,
        block: &mut Block,
        out: &mut Vec<(u32, Sample)>,
    ) {
        let corner = self.origin + DVec2::new(f64::from(key.0), f64::from(key.1)) * self.cell;
        let (lo, hi) = (corner, corner + DVec2::splat(self.cell));
        let mut candidates = std::mem::take(&mut block.candidates);
        candidates.clear();
        // The supports over the cell, and over the detail gradient's steps out of it.
        let step = if gradients { self.detail_step() } else { 0.0 };
        self.bvh.aabb_traverse(outward_box(lo - step - self.origin, hi + step - self.origin), |bvh, node| {
            collect_leaf(bvh, node, &mut candidates)
        });
        // What the points' f32 coordinates relative to the corner may be off by, and more.
        let slack = 1e-5 * self.cell;
        candidates.retain(|&k| self.items[k as usize].meets(lo, hi, slack + step));
        candidates.sort_unstable();
        let split = candidates.partition_point(|&k| (k as usize) < self.gaussians);
        block.load(&self.items, &candidates[..split], points, members, corner, slack);
        // A detail layer modulated by the slope needs the Gaussians' gradient for its value.
        let by_slope = |layer: &DetailLayer| matches!(&layer.source, crate::DetailSource::Noise { modulation, .. } if modulation.slope.is_some());
        block.gradients = gradients || self.layers.iter().any(|(layer, _)| by_slope(layer));
        block.run();
        for (n, &k) in block.order.iter().enumerate() {
            let p = points[k as usize];
            let sums = &block.sums[3 * LANES * (n / LANES)..];
            let lane = n % LANES;
            let (h, gx, gy) = (sums[lane], sums[LANES + lane], sums[2 * LANES + lane]);
            let (h, gx, gy) = (f64::from(h), f64::from(gx), f64::from(gy));
            let mut s = Sample { elevation: self.base + h, gradient: DVec2::new(gx, gy) };
            if let Some(floor) = self.floor
                && s.elevation < floor
            {
                s = Sample { elevation: floor, gradient: DVec2::ZERO };
            }
            if split < candidates.len() {
                let ground = s;
                s.elevation += self.details_at(p, &candidates[split..], ground.ground());
                if gradients {
                    s.gradient += self.details_gradient(p, ground, &candidates[split..]);
                }
            }
            out.push((k, s));
        }
        block.candidates = candidates;
    }

    /// The detail layers at `p`, given a superset of the falloffs over it (ascending): each
    /// layer's amplitude times its summed falloff, capped at 1, as [`DetailLayer::value`].
    fn details_at(&self, p: DVec2, falloffs: &[u32], ground: Ground) -> f64 {
        let mut total = 0.0;
        let mut rest = falloffs;
        for (layer, end) in &self.layers {
            let here = rest.partition_point(|&k| (k as usize) < *end);
            let w: f64 = rest[..here].iter().map(|&k| self.items[k as usize].value(p)).sum();
            if w > 0.0 {
                total += layer.amplitude_at(p, ground) * w.min(1.0);
            }
            rest = &rest[here..];
        }
        total
    }

    /// The step of the detail layers' central differences: 10⁻³ of the narrowest layer's σ (0
    /// without layers).
    fn detail_step(&self) -> f64 {
        self.layers.iter().map(|(l, _)| l.sigma * 1e-3).reduce(f64::min).unwrap_or(0.0)
    }

    /// The detail layers' gradient at `p`: a central difference, over the Gaussians' `ground`
    /// at `p` carried to the nearby points by its gradient (a modulation's change of slope over
    /// the step is left out).
    /// `falloffs` (ascending) holds every falloff within [`Self::detail_step`] of `p`.
    fn details_gradient(&self, p: DVec2, ground: Sample, falloffs: &[u32]) -> DVec2 {
        let step = self.detail_step();
        let at = |q: DVec2| {
            let under =
                Ground { elevation: ground.elevation + ground.gradient.dot(q - p), slope: ground.gradient.length() };
            self.details_at(q, falloffs, under)
        };
        let (dx, dy) = (DVec2::new(step, 0.0), DVec2::new(0.0, step));
        DVec2::new(at(p + dx) - at(p - dx), at(p + dy) - at(p - dy)) / (2.0 * step)
    }
}

impl Sample {
    const NAN: Sample = Sample { elevation: f64::NAN, gradient: DVec2::NAN };

    /// The ground a detail layer sees here.
    fn ground(&self) -> Ground {
        Ground { elevation: self.elevation, slope: self.gradient.length() }
    }
}

/// Points per group: two AVX2 registers of f32 (measured best among 8, 16 and 32 on the
/// rasterizer benchmark's terrain).
const LANES: usize = 16;

/// A cell's work: its Gaussians (centres relative to the cell's corner, f32) and its points in
/// groups of [`LANES`] nearby points, each group with the sums being accumulated. A Gaussian is
/// added to a group only when it may reach one of the group's points; the points it skips lie
/// outside its support, where the kernel adds nothing anyway, so a point's sum is the same
/// whatever group it is in.
#[derive(Default)]
struct Block {
    supports: Vec<Support>,
    groups: Vec<Group>,
    /// Each group's points relative to the cell's corner: [`LANES`] x, then [`LANES`] y (the
    /// last point repeated to fill the lanes).
    q: Vec<f32>,
    /// Each group's sums: [`LANES`] elevations, then x and y derivatives (f32 like the
    /// rasterizer's sums).
    sums: Vec<f32>,
    /// The cell's points (indices into the caller's points) in group order.
    order: Vec<u32>,
    /// Whether to sum the gradients too (else only the elevations).
    gradients: bool,
    /// Scratch: the supports over the cell, and the points' Z-order keys.
    candidates: Vec<u32>,
    keys: Vec<(u32, u32)>,
}

/// One Gaussian of a [`Block`]: f32 for the kernel, f64 for the test of whether it reaches a
/// group.
#[derive(Clone, Copy)]
struct Support {
    cx: f32,
    cy: f32,
    ux: f32,
    uy: f32,
    vx: f32,
    vy: f32,
    r2: f32,
    amplitude: f32,
    half_beta: f32,
    center: DVec2,
    u: DVec2,
    v: DVec2,
    r: f64,
    /// What its f32 centre and the points may be off by (10⁻⁵ of the cell and of its offset
    /// from the corner: f32 keeps 2⁻²³ of a magnitude), added to the groups' half-sizes.
    slack: f64,
}

/// Up to [`LANES`] nearby points of a cell: the box that holds them, relative to the cell's
/// corner.
#[derive(Clone, Copy)]
struct Group {
    /// The centre of the points' box and its half-size.
    mid: DVec2,
    half: DVec2,
}

impl Block {
    /// Loads the Gaussians `indices` and the points `members` of the cell at `corner`, sums
    /// cleared: the points sorted along a Z-order curve over the cell, cut into groups.
    fn load(&mut self, items: &[Item], indices: &[u32], points: &[DVec2], members: &[u32], corner: DVec2, slack: f64) {
        self.supports.clear();
        self.supports.extend(indices.iter().map(|&k| {
            let i = &items[k as usize];
            let c = i.center - corner;
            Support {
                cx: c.x as f32,
                cy: c.y as f32,
                ux: i.u.x as f32,
                uy: i.u.y as f32,
                vx: i.v.x as f32,
                vy: i.v.y as f32,
                r2: i.r2 as f32,
                amplitude: i.amplitude as f32,
                half_beta: i.half_beta as f32,
                center: c,
                u: i.u,
                v: i.v,
                r: i.r2.sqrt(),
                slack: slack + 1e-5 * c.abs().max_element(),
            }
        }));
        self.order.clear();
        if members.len() > LANES {
            let (lo, hi) = members.iter().fold((DVec2::MAX, DVec2::MIN), |(lo, hi), &k| {
                let p = points[k as usize];
                (lo.min(p), hi.max(p))
            });
            let extent = (hi - lo).max_element();
            let scale = if extent > 0.0 { 65_535.0 / extent } else { 0.0 };
            self.keys.clear();
            self.keys.extend(members.iter().map(|&k| {
                let q = ((points[k as usize] - lo) * scale).min(DVec2::splat(65_535.0));
                (z_order(q.x as u32, q.y as u32), k)
            }));
            self.keys.sort_unstable();
            self.order.extend(self.keys.iter().map(|&(_, k)| k));
        } else {
            self.order.extend_from_slice(members);
        }
        self.groups.clear();
        self.q.clear();
        for chunk in self.order.chunks(LANES) {
            let lane = |l: usize| points[chunk[l.min(chunk.len() - 1)] as usize] - corner;
            self.q.extend((0..LANES).map(|l| lane(l).x as f32));
            self.q.extend((0..LANES).map(|l| lane(l).y as f32));
            let (lo, hi) = chunk.iter().fold((DVec2::MAX, DVec2::MIN), |(lo, hi), &k| {
                let p = points[k as usize] - corner;
                (lo.min(p), hi.max(p))
            });
            self.groups.push(Group { mid: 0.5 * (lo + hi), half: 0.5 * (hi - lo) });
        }
        self.sums.clear();
        self.sums.resize(3 * LANES * self.groups.len(), 0.0);
    }

    /// Adds every Gaussian, in order, to every group it may reach: the loop over a group's
    /// lanes is the one the compiler vectorizes, dispatched by `pulp` to the widest vector
    /// instructions the CPU has (AVX2 where present). The vector build gives the bits of the
    /// plain one (no implicit fusing, explicit `mul_add`s fused on both).
    fn run(&mut self) {
        pulp::Arch::new().dispatch(&mut *self);
    }
}

/// Interleaves the bits of `x` and `y` (16 each): the Z-order key of a point.
fn z_order(x: u32, y: u32) -> u32 {
    let spread = |v: u32| {
        let v = (v | (v << 8)) & 0x00ff_00ff;
        let v = (v | (v << 4)) & 0x0f0f_0f0f;
        let v = (v | (v << 2)) & 0x3333_3333;
        (v | (v << 1)) & 0x5555_5555
    };
    spread(x & 0xffff) | (spread(y & 0xffff) << 1)
}

impl pulp::WithSimd for &mut Block {
    type Output = ();

    #[allow(
        clippy::inline_always,
        reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
    )]
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let groups = self.groups.iter().zip(self.q.chunks_exact(2 * LANES)).zip(self.sums.chunks_exact_mut(3 * LANES));
        for ((group, q), sums) in groups {
            for c in &self.supports {
                if !reaches(group.mid - c.center, c.u, c.v, c.r, group.half + c.slack) {
                    continue;
                }
                // By value: a support behind a reference keeps the loops from vectorizing.
                let (c, exponent) = (*c, c.half_beta - 1.0);
                let lower = move |s: f32| exp2_signed(exponent * log2(s));
                match (self.gradients, c.half_beta == 1.0) {
                    (true, true) => add_terms(c, q, sums, |_| 1.0),
                    (true, false) => add_terms(c, q, sums, lower),
                    (false, true) => add_values(c, q, sums, |_| 1.0),
                    (false, false) => add_values(c, q, sums, lower),
                }
            }
        }
    }
}

/// Adds the Gaussian `c` to the sums of the group's points inside its support, given
/// `lower(s) = s^(β/2 − 1)`: the gradient's factor, and `s^(β/2)` is `s·lower(s)` (β = 2 skips
/// the logarithm: `lower` is 1).
#[allow(
    clippy::inline_always,
    reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
)]
#[inline(always)]
fn add_terms(c: Support, q: &[f32], sums: &mut [f32], lower: impl Fn(f32) -> f32) {
    let n = q.len() / 2;
    let (qx, qy) = q.split_at(n);
    let (h, rest) = sums.split_at_mut(n);
    let (gx, gy) = rest.split_at_mut(n);
    let (qy, h, gx, gy) = (&qy[..n], &mut h[..n], &mut gx[..n], &mut gy[..n]);
    for j in 0..n {
        let (dx, dy) = (qx[j] - c.cx, qy[j] - c.cy);
        let (x, y) = (dx * c.ux + dy * c.uy, dx * c.vx + dy * c.vy);
        let s = x * x + y * y;
        let lower = lower(s);
        let g = c.amplitude * exp_neg(-0.5 * (s * lower));
        let slope = -g * c.half_beta * lower;
        let inside = s <= c.r2;
        let (nh, ngx, ngy) = (h[j] + g, gx[j] + slope * (x * c.ux + y * c.vx), gy[j] + slope * (x * c.uy + y * c.vy));
        h[j] = if inside { nh } else { h[j] };
        gx[j] = if inside { ngx } else { gx[j] };
        gy[j] = if inside { ngy } else { gy[j] };
    }
}

/// [`add_terms`] without the gradient: the elevations only, the same bits.
#[allow(
    clippy::inline_always,
    reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
)]
#[inline(always)]
fn add_values(c: Support, q: &[f32], sums: &mut [f32], lower: impl Fn(f32) -> f32) {
    let n = q.len() / 2;
    let (qx, qy) = q.split_at(n);
    let (qy, h) = (&qy[..n], &mut sums[..n]);
    for j in 0..n {
        let (dx, dy) = (qx[j] - c.cx, qy[j] - c.cy);
        let (x, y) = (dx * c.ux + dy * c.uy, dx * c.vx + dy * c.vy);
        let s = x * x + y * y;
        let g = c.amplitude * exp_neg(-0.5 * (s * lower(s)));
        h[j] = if s <= c.r2 { h[j] + g } else { h[j] };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn z_order_interleaves_x_then_y() {
        assert_eq!(z_order(1, 0), 1);
        assert_eq!(z_order(0, 1), 2);
        assert_eq!(z_order(3, 3), 15);
        assert_eq!(z_order(0b1010, 0b0110), 0b0110_1100);
        assert_eq!(z_order(0xffff, 0), 0x5555_5555);
        assert_eq!(z_order(0, 0xffff), 0xaaaa_aaaa);
        assert_eq!(z_order(0x1_0001, 0), 1, "only 16 bits of each");
    }

    /// The box test is exact on the axes of a round support and never refuses a box holding a
    /// point of the support.
    #[test]
    fn reaches_is_tight_and_conservative() {
        let (u, v) = (DVec2::X, DVec2::Y);
        // A unit box centred 4.5 from a support of radius 4 (in d units): its near edge is 4.0.
        assert!(reaches(DVec2::new(4.5, 0.0), u, v, 4.0, DVec2::splat(0.5)));
        assert!(!reaches(DVec2::new(4.502, 0.0), u, v, 4.0, DVec2::splat(0.5)));
        assert!(!reaches(DVec2::new(0.0, -4.502), u, v, 4.0, DVec2::splat(0.5)));
        // The box's corner: (3, 3) − (0.5, 0.5) is 3.54 from the centre.
        assert!(reaches(DVec2::new(3.0, 3.0), u, v, 3.54, DVec2::splat(0.5)));
        assert!(!reaches(DVec2::new(3.0, 3.0), u, v, 3.53, DVec2::splat(0.5)));
        // A long support (σ = 10, 1) turned 30°: a box holding a point just inside it is kept.
        let g = Gaussian {
            center: [0.0, 0.0],
            sigma: [10.0, 1.0],
            theta: std::f64::consts::FRAC_PI_6,
            amplitude: 1.0,
            beta: 2.0,
        };
        let (u, v) = g.inverse_axes();
        for k in 0..360 {
            let dir = DVec2::from_angle(f64::from(k).to_radians());
            let inside = DVec2::new(dir.x * 10.0, dir.y) * 0.999;
            let p = DVec2::from_angle(std::f64::consts::FRAC_PI_6).rotate(inside) * 3.0;
            let (mid, half) = (p + DVec2::new(0.7, -0.4), DVec2::new(0.8, 0.5));
            assert!(reaches(mid, u, v, 3.0, half), "angle {k}");
            // And one at 1.5 r is refused: the box adds at most 0.83 to its distance in d units.
            let far =
                DVec2::from_angle(std::f64::consts::FRAC_PI_6).rotate(DVec2::new(dir.x * 10.0, dir.y)) * 3.0 * 1.5;
            assert!(!reaches(far, u, v, 3.0, half), "angle {k}");
        }
    }
}
