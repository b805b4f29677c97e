//! Continuous queries (§3.2: a vector terrain is a function of the plane, not a grid): the
//! elevation, gradient and normal at any point, with no raster. The supports of the primitives
//! and of the detail falloffs go into a bounding volume hierarchy (`obvhs`, a maintained BVH
//! library: PLOC construction and stack traversal, which a hand-written grid would only
//! approximate for primitives whose sizes span three orders of magnitude).
//!
//! A batch goes the rasterizer's way (module `kernel`), with its points in place of a grid's
//! rows: sorted into strips of one y value (a grid row) or of a thin range of y (scattered
//! points), each sorted by x. Bands of strips run in parallel; a band finds its candidate
//! supports once (a wide band, as a grid's, scans the Gaussians stored by the y of their
//! centres between two bisections; a narrow one, as a single query, walks the hierarchy), and
//! each support, in a fixed order, adds itself to the stretch of each strip its ellipse covers
//! (for an evenly spread row, the indices its ends fall at; else a search from where the
//! stretch would start were the points evenly spread), with the rasterizer's branch-free f32
//! arithmetic (module `fastmath`), vectorized (AVX-512 or AVX2 through `pulp` where the CPU
//! has it). A point is held relative to the corner of its square of a coarse lattice, so its
//! arithmetic depends on the point and the support alone, and each point sums the supports
//! over it in that order: a single query is a batch of one (whose supports go straight to the
//! kernel's own inside test, with no stretch to find), and a batch returns exactly the single
//! queries' values, in any order, for any thread count. Detail layers (f64 falloffs and noise)
//! go by the cells of a finer lattice.

use glam::{DVec2, DVec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::bvh2::builder::build_bvh2;
use rayon::prelude::*;

use crate::fastmath::{exp_neg, exp2_signed, log2};
use crate::{DetailLayer, Gaussian, GaussianError, Ground, VectorTerrain};

/// Side of the detail layers' query cells, in typical support widths (measured best among 0.5–2
/// on the rasterizer benchmark's terrain).
const CELL_PER_SUPPORT: f64 = 1.0;

/// Side of the lattice whose corners the kernel measures points from, in query cells: a stretch
/// of a strip takes another square's brackets where it crosses into it, and is cut where it
/// crosses into a third (on the rasterizer benchmark's terrain, 1024² points, when every crossing
/// cut: 4 took 1.34–1.46× the rasterizer's time, 16 1.29–1.32×, 64 1.25–1.31×; on 2026-12-02, 64
/// was within noise of 16). f32 holds a point 16 support widths from its corner to a millionth
/// of a width.
const ANCHOR_CELLS: f64 = 16.0;

/// Detail cells per parallel task in the batched queries.
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
    /// The support grown by a relative 10⁻⁴ (far above the f32 rounding of the kernel's inside
    /// test) reaches `x_reach` and `y_reach` from the centre, its furthest x at `y' = −tip`;
    /// over a row at `y'` from the centre it spans `x' = slope·y' ± width·√(y_reach² − y'²)`.
    /// From the covariance `A·Aᵀ` scaled by the larger σ, so no σ overflows or cancels.
    x_reach: f64,
    y_reach: f64,
    tip: f64,
    slope: f64,
    width: f64,
    /// What the kernel's f32 coordinates of the centre and of a point it reaches may be off by,
    /// world units (10⁻⁵ of the support's width and of two anchor squares: a point is held
    /// relative to its square's corner); set by [`Item::with_slack`].
    slack: f64,
}

impl Item {
    fn new(g: &Gaussian, tolerance: f64) -> Self {
        let (u, v) = g.inverse_axes();
        let r = g.support_radius(tolerance);
        let (lo, hi) = g.bounds(tolerance);
        // Σ = A·Aᵀ / m² (m the larger σ): √Σxx, √Σyy and Σxy, all within [−1, 1].
        let (sin, cos) = g.theta.sin_cos();
        let m = g.sigma[0].max(g.sigma[1]);
        let (sx, sy) = (g.sigma[0] / m, g.sigma[1] / m);
        let (xx, yy, xy) = ((sx * cos).hypot(sy * sin), (sx * sin).hypot(sy * cos), (sx * sx - sy * sy) * sin * cos);
        let grown = r * (1.0 + 1e-4) * m;
        Self {
            center: DVec2::from(g.center),
            u,
            v,
            r2: r * r,
            amplitude: g.amplitude,
            half_beta: 0.5 * g.beta,
            lo,
            hi,
            x_reach: grown * xx,
            y_reach: grown * yy,
            tip: -grown * xy / xx,
            slope: xy / (yy * yy),
            width: sx * sy / (yy * yy),
            slack: 0.0,
        }
    }

    /// The item with its [`Item::slack`] for anchor squares of side `anchor`.
    fn with_slack(self, anchor: f64) -> Self {
        Self { slack: 1e-5 * ((self.hi - self.lo).max_element() + 2.0 * anchor), ..self }
    }

    /// The box that holds every point the kernel may count inside the support: the grown
    /// support and the slack. The hierarchy holds these boxes.
    fn reach(&self) -> (DVec2, DVec2) {
        let half = DVec2::new(self.x_reach, self.y_reach) + self.slack;
        (self.center - half, self.center + half)
    }

    /// The x range over which the grown support meets the band of y from `y0` to `y1`, grown by
    /// the slack; `None` when it misses the band. The support's left and right edges are convex
    /// and concave in y, so their extremes over the band are at the band's y nearest to the
    /// support's leftmost and rightmost points.
    #[allow(clippy::inline_always, reason = "called once per stretch from the kernel's loop")]
    #[inline(always)]
    fn x_range(&self, y0: f64, y1: f64) -> Option<(f64, f64)> {
        let lo = (y0 - self.center.y - self.slack).max(-self.y_reach);
        let hi = (y1 - self.center.y + self.slack).min(self.y_reach);
        if lo > hi {
            return None;
        }
        let edge = |y: f64, side: f64| {
            let room = ((self.y_reach - y) * (self.y_reach + y)).max(0.0);
            self.slope * y + side * self.width * room.sqrt()
        };
        let (left, right) = (edge(self.tip.clamp(lo, hi), -1.0), edge((-self.tip).clamp(lo, hi), 1.0));
        // A support flattened to a segment (no y extent in f64) has no finite slope: its box.
        let (left, right) =
            if left.is_finite() && right.is_finite() { (left, right) } else { (-self.x_reach, self.x_reach) };
        Some((self.center.x + left - self.slack, self.center.x + right + self.slack))
    }

    /// The value at `p` in f64, 0 outside the support (a detail falloff's weight).
    fn value(&self, p: DVec2) -> f64 {
        let d = p - self.center;
        let (x, y) = (d.dot(self.u), d.dot(self.v));
        let s = x * x + y * y;
        if s > self.r2 { 0.0 } else { self.amplitude * (-0.5 * s.powf(self.half_beta)).exp() }
    }

    /// Whether the support may reach the box `[lo, hi]` grown by `slack` ([`reaches`]): a
    /// detail cell's cull of its falloffs (a falloff let through that reaches none of the cell's
    /// points adds 0 to each).
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
    /// The Gaussians by the y of their centres, then each detail layer's falloffs in order.
    items: Vec<Item>,
    /// `items[gaussians..]` are detail falloffs.
    gaussians: usize,
    /// Each item's reach box ([`Item::reach`]), packed for the window scans.
    reach: Vec<(DVec2, DVec2)>,
    /// For each Gaussian `k`, the highest top (y) of the reach boxes of Gaussians `0..=k`, and
    /// the lowest bottom of those of `k..`: both rise with `k`, so the Gaussians that may meet
    /// a band of y lie between two bisections ([`TerrainQuery::window`]).
    tops: Vec<f64>,
    bottoms: Vec<f64>,
    /// The x extent of the Gaussians' reach boxes ([`TerrainQuery::scans`]).
    x_span: f64,
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
        // The Gaussians by the y of their centres (then index): a band's supports lie close
        // together in memory, and every point sums them in this order.
        let mut supports: Vec<Gaussian> = self.primitives.clone();
        supports.sort_by(|a, b| a.center[1].total_cmp(&b.center[1]));
        let mut layers = Vec::with_capacity(self.details.len());
        for layer in &self.details {
            supports.extend(layer.falloffs());
            layers.push((layer.clone(), supports.len()));
        }
        let items: Vec<Item> = supports.iter().map(|g| Item::new(g, tolerance)).collect();
        let cell = CELL_PER_SUPPORT
            * typical_width(&items[..if self.primitives.is_empty() { items.len() } else { self.primitives.len() }]);
        let items: Vec<Item> = items.into_iter().map(|i| i.with_slack(ANCHOR_CELLS * cell)).collect();
        let reach: Vec<(DVec2, DVec2)> = items.iter().map(Item::reach).collect();
        let origin = reach.iter().map(|&(lo, hi)| 0.5 * (lo + hi)).sum::<DVec2>() / reach.len().max(1) as f64;
        let boxes: Vec<Aabb> = reach.iter().map(|&(lo, hi)| outward_box(lo - origin, hi - origin)).collect();
        let bvh = if boxes.is_empty() {
            Bvh2::default()
        } else {
            let mut build_time = std::time::Duration::ZERO;
            build_bvh2(&boxes, BvhBuildParams::fast_build(), &mut build_time)
        };
        let (gaussians, base, floor) = (self.primitives.len(), self.base, self.floor);
        let (tops, bottoms, x_span) = windows(&reach[..gaussians]);
        Ok(TerrainQuery { origin, bvh, items, gaussians, reach, tops, bottoms, x_span, layers, base, floor, cell })
    }
}

/// [`TerrainQuery::tops`], [`TerrainQuery::bottoms`] and [`TerrainQuery::x_span`] of the
/// reach boxes `reach`.
fn windows(reach: &[(DVec2, DVec2)]) -> (Vec<f64>, Vec<f64>, f64) {
    let (mut top, mut bottom) = (f64::NEG_INFINITY, f64::INFINITY);
    let tops = reach
        .iter()
        .map(|(_, hi)| {
            top = top.max(hi.y);
            top
        })
        .collect();
    let mut bottoms: Vec<f64> = reach
        .iter()
        .rev()
        .map(|(lo, _)| {
            bottom = bottom.min(lo.y);
            bottom
        })
        .collect();
    bottoms.reverse();
    let (x0, x1) = reach.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (lo, hi)| (a.min(lo.x), b.max(hi.x)));
    (tops, bottoms, (x1 - x0).max(0.0))
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

    /// A batch of one point, on the calling thread.
    fn single(&self, p: DVec2, gradients: bool) -> Sample {
        if self.anchor_of(p).is_none() {
            return self.beyond(p);
        }
        let points = [p];
        let strip = [self.strip(0..1, None, &points)];
        let mut out = [self.ground(&self.band_sums(&strip, self.slopes(gradients))[0], 0)];
        if !self.layers.is_empty() {
            self.add_details(&points, gradients, &mut out);
        }
        out[0]
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
        if points.len() > MAX_BATCH {
            return points.chunks(MAX_BATCH).flat_map(|chunk| self.elevations(chunk)).collect();
        }
        if !self.layers.is_empty() {
            return self.batch(points, false).into_iter().map(|s| s.elevation).collect();
        }
        self.gather(points, false, 0.0, |s| s.elevation)
    }

    /// The elevations and gradients at `points`, in parallel: the same values as
    /// [`Self::sample`] one by one, for any thread count. Any order of points is fast: they are
    /// sorted into strips first (grid rows in row order need no sorting).
    pub fn samples(&self, points: &[DVec2]) -> Vec<Sample> {
        self.batch(points, true)
    }

    /// [`Self::samples`], the gradients left at zero unless `gradients`.
    fn batch(&self, points: &[DVec2], gradients: bool) -> Vec<Sample> {
        if points.len() > MAX_BATCH {
            return points.chunks(MAX_BATCH).flat_map(|chunk| self.batch(chunk, gradients)).collect();
        }
        let mut out = self.gather(points, gradients, Sample::NAN, |s| s);
        if !self.layers.is_empty() {
            self.add_details(points, gradients, &mut out);
        }
        out
    }

    /// The Gaussians' samples at every point, `f` applied to each: the points beyond the anchor
    /// lattice at the base ([`Self::beyond`]). Each band (a parallel task) builds its own strips
    /// and sums them, so a strip's points are still in cache when its kernels read them. When
    /// the batch is in y order within the lattice (a grid in row order), each band writes its
    /// own stretch of the output as it ends (`fill` holds each slot until then); otherwise the
    /// bands' sums are scattered to their points.
    fn gather<T: Send + Sync + Copy>(
        &self,
        points: &[DVec2],
        gradients: bool,
        fill: T,
        f: impl Fn(Sample) -> T + Sync,
    ) -> Vec<T> {
        let (cuts, order) = self.cuts(points);
        let slopes = self.slopes(gradients);
        let bands = bands(&cuts);
        let sum_band = |band: std::ops::Range<usize>| {
            let strips: Vec<Strip> =
                cuts[band].iter().map(|r| self.strip(r.clone(), order.as_deref(), points)).collect();
            let sums = self.band_sums(&strips, slopes);
            (strips, sums)
        };
        if order.is_none() {
            let mut out = Vec::with_capacity(points.len());
            rayon::iter::repeat_n(fill, points.len()).collect_into_vec(&mut out);
            let mut parts = Vec::with_capacity(bands.len());
            let mut rest = out.as_mut_slice();
            for band in &bands {
                let (part, tail) = rest.split_at_mut(cuts[band.end - 1].end - cuts[band.start].start);
                parts.push(part);
                rest = tail;
            }
            bands.into_par_iter().zip(parts).for_each(|(band, part)| {
                let offset = cuts[band.start].start;
                let (strips, sums) = sum_band(band);
                for (s, sums) in strips.iter().zip(&sums) {
                    if s.members.is_empty() {
                        let start = s.first as usize - offset;
                        let slots = &mut part[start..start + s.x.len()];
                        slots.iter_mut().enumerate().for_each(|(n, slot)| *slot = f(self.ground(sums, n)));
                    } else {
                        // Points of several y sorted by x: their slots are within the strip's.
                        for (n, &k) in s.members.iter().enumerate() {
                            part[k as usize - offset] = f(self.ground(sums, n));
                        }
                    }
                }
            });
            return out;
        }
        let done: Vec<(Vec<Strip>, Vec<Sums>)> = bands.into_par_iter().map(sum_band).collect();
        let mut out: Vec<T> = points.par_iter().map(|&p| f(self.beyond(p))).collect();
        for (strip, sums) in done.iter().flat_map(|(strips, sums)| strips.iter().zip(sums)) {
            for n in 0..strip.x.len() {
                out[strip.member(n) as usize] = f(self.ground(sums, n));
            }
        }
        out
    }

    /// Whether the Gaussians' gradients are needed: when asked for, or when a detail layer's
    /// amplitude follows the slope.
    fn slopes(&self, gradients: bool) -> bool {
        let by_slope = |layer: &DetailLayer| matches!(&layer.source, crate::DetailSource::Noise { modulation, .. } if modulation.slope.is_some());
        gradients || self.layers.iter().any(|(layer, _)| by_slope(layer))
    }

    /// The Gaussians' sample `n` of a band: the base added, the floor applied.
    fn ground(&self, sums: &Sums, n: usize) -> Sample {
        let gradient = if sums.gx.is_empty() { DVec2::ZERO } else { DVec2::new(sums.gx[n].into(), sums.gy[n].into()) };
        let s = Sample { elevation: self.base + f64::from(sums.h[n]), gradient };
        match self.floor {
            Some(floor) if s.elevation < floor => Sample { elevation: floor, gradient: DVec2::ZERO },
            _ => s,
        }
    }

    /// A point beyond the anchor lattice: NaN when it is not finite, else the base (more than
    /// 2³⁰ anchor squares, 2³⁴ typical support widths, from the origin: only a support that
    /// wide could reach it, and queries take it as out of reach).
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

    /// The lower corner of the lattice cell `key`.
    fn corner(&self, key: (i32, i32)) -> DVec2 {
        self.origin + DVec2::new(f64::from(key.0), f64::from(key.1)) * self.cell
    }

    /// The square of the anchor lattice ([`ANCHOR_CELLS`] cells a side) that holds `p`, `None`
    /// when it is not finite or more than 2³⁰ squares from the origin (so far out that no
    /// support reaches it).
    fn anchor_of(&self, p: DVec2) -> Option<(i32, i32)> {
        let c = self.in_squares(p);
        // Truncation, one down for a negative fraction: the floor without a libm call.
        let floor = |v: f64| v as i32 - i32::from(f64::from(v as i32) > v);
        within_lattice(c).then(|| (floor(c.x), floor(c.y)))
    }

    /// `p` in anchor squares from the origin.
    fn in_squares(&self, p: DVec2) -> DVec2 {
        (p - self.origin) / (ANCHOR_CELLS * self.cell)
    }

    /// Whether `p` has an anchor square ([`Self::anchor_of`]).
    fn in_lattice(&self, p: DVec2) -> bool {
        within_lattice(self.in_squares(p))
    }

    /// The lower corner of the anchor square `key`.
    fn anchor(&self, key: (i32, i32)) -> DVec2 {
        self.origin + DVec2::new(f64::from(key.0), f64::from(key.1)) * (ANCHOR_CELLS * self.cell)
    }

    /// The points within the anchor lattice's range (the others are [`Self::beyond`]) sorted
    /// into strips ([`Strip`]), and whether they are every point in the order given.
    #[cfg(test)]
    fn strips(&self, points: &[DVec2]) -> (Vec<Strip>, bool) {
        let (cuts, order) = self.cuts(points);
        let strips = cuts.into_iter().map(|range| self.strip(range, order.as_deref(), points)).collect();
        (strips, order.is_none())
    }

    /// The strips of the points within the anchor lattice's range (see [`Strip`]): each a range
    /// of `order` ([`Self::order`]; of `points` when `None`).
    fn cuts(&self, points: &[DVec2]) -> (Vec<std::ops::Range<usize>>, Option<Vec<u32>>) {
        let order = self.order(points);
        let len = order.as_ref().map_or(points.len(), Vec::len);
        if len == 0 {
            return (Vec::new(), order);
        }
        let index = |k: usize| order.as_ref().map_or(k as u32, |order| order[k]);
        let point = |k: usize| points[index(k) as usize];
        let row = |k: usize| self.anchor_of(point(k)).map_or(0, |c| c.1);
        // A strip ends only where y changes, and there it ends when full or in another anchor row.
        let mut cuts = Vec::new();
        let (mut start, mut start_row) = (0, row(0));
        let mut change = |k: usize| {
            let cut = k == len || {
                let (first, last, p) = (point(start), point(k - 1), point(k));
                let row_of_many = first.y == last.y && k - start >= MIN_ROW;
                row_of_many || p.y - first.y > self.cell * STRIP_THICKNESS || row(k) != start_row
            };
            if cut {
                cuts.push(start..k);
                start = k;
                start_row = if k < len { row(k) } else { 0 };
            }
        };
        if order.is_none() {
            // Points in the order given (so by y), likely grid rows: a search for each change.
            changes_of_y(points).for_each(&mut change);
        } else {
            (1..len).filter(|&k| point(k).y != point(k - 1).y).for_each(&mut change);
        }
        change(len);
        (cuts, order)
    }

    /// The indices of the points within the anchor lattice's range, ordered by y (ties in any
    /// order: a strip sorts its own points by x): `None` when that is every point in the order
    /// given (a grid in row order), which is checked in parallel.
    fn order(&self, points: &[DVec2]) -> Option<Vec<u32>> {
        // The lattice row grows with y, so an order by y is one by row too; −0 and +0 are one y.
        let le = |p: DVec2, q: DVec2| p.y <= q.y;
        // Within this of the origin, a point is within the lattice ([`within_lattice`]): its
        // quotient by the square's side is below 2³⁰ (1 − 10⁻¹²), and rounding it adds 2⁻⁵³.
        let near = f64::from(1u32 << 30) * ANCHOR_CELLS * self.cell * (1.0 - 1e-12);
        let close = |p: DVec2| (p - self.origin).abs().cmplt(DVec2::splat(near)).all();
        // Each chunk without a branch per point, so that it runs in vectors; the test without a
        // division first.
        let given = points.par_chunks(SCAN_CHUNK).enumerate().all(|(c, chunk)| {
            let joined = c == 0 || le(points[c * SCAN_CHUNK - 1], chunk[0]);
            let ordered = chunk.windows(2).fold(true, |ordered, pair| ordered & le(pair[0], pair[1]));
            let close = chunk.iter().fold(true, |inside, &p| inside & close(p));
            joined && ordered && (close || chunk.iter().fold(true, |inside, &p| inside & self.in_lattice(p)))
        });
        if given {
            return None;
        }
        let mut order: Vec<u32> = Vec::with_capacity(points.len());
        let mut sorted = true;
        for (k, p) in points.iter().enumerate() {
            if self.anchor_of(*p).is_some() {
                sorted &= order.last().is_none_or(|&last| le(points[last as usize], *p));
                order.push(k as u32);
            }
        }
        Some(if sorted { order } else { self.sort_by_y(&order, points) })
    }

    /// `order` sorted by y (ties in any order: a strip sorts its own points by x): a counting
    /// sort into slabs a strip thick, then each slab on its own; one sort of the whole when the
    /// points are too far apart for slabs.
    fn sort_by_y(&self, order: &[u32], points: &[DVec2]) -> Vec<u32> {
        let y = |k: u32| points[k as usize].y;
        let (lo, hi) = order.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &k| (lo.min(y(k)), hi.max(y(k))));
        let unit = self.cell * STRIP_THICKNESS;
        let slabs = ((hi - lo) / unit).floor() + 1.0;
        if slabs.is_nan() || slabs > 4.0 * order.len() as f64 {
            let mut keyed: Vec<(u64, u32)> = order.par_iter().map(|&k| (sortable(y(k)), k)).collect();
            keyed.par_sort_unstable();
            return keyed.into_iter().map(|(_, k)| k).collect();
        }
        let slabs = slabs as usize;
        let slab = |k: u32| (((y(k) - lo) / unit) as usize).min(slabs - 1);
        let mut start = vec![0usize; slabs + 1];
        for &k in order {
            start[slab(k) + 1] += 1;
        }
        for s in 0..slabs {
            start[s + 1] += start[s];
        }
        let mut fill = start.clone();
        let mut sorted = vec![0u32; order.len()];
        for &k in order {
            let s = slab(k);
            sorted[fill[s]] = k;
            fill[s] += 1;
        }
        let mut parts = Vec::with_capacity(slabs);
        let mut rest = sorted.as_mut_slice();
        for s in 0..slabs {
            let (part, tail) = rest.split_at_mut(start[s + 1] - start[s]);
            parts.push(part);
            rest = tail;
        }
        parts.into_par_iter().for_each(|part| sort_by_key(part, |k| sortable(y(k))));
        sorted
    }

    /// The strip of the points `range` of `order` (of `points` when `None`), sorted by y and in
    /// one anchor row (see [`Strip`]).
    fn strip(&self, range: std::ops::Range<usize>, order: Option<&[u32]>, points: &[DVec2]) -> Strip {
        let index = |k: usize| order.map_or(k as u32, |order| order[k]);
        let (y0, y1) = (points[index(range.start) as usize].y, points[index(range.end - 1) as usize].y);
        // Points in the order given and by x (a grid row) keep no list of indices. The test has
        // no branch per point, so that it runs in vectors.
        let by_x = order.is_none()
            && points[range.clone()].windows(2).map(|pair| usize::from(pair[0].x > pair[1].x)).sum::<usize>() == 0;
        let members = match order {
            None if by_x => Vec::new(),
            _ => {
                let mut members: Vec<u32> = range.clone().map(index).collect();
                let x = |k: u32| points[k as usize].x;
                if !members.is_sorted_by(|a, b| x(*a) <= x(*b)) {
                    sort_by_key(&mut members, |k| sortable(x(k)));
                }
                members
            }
        };
        let point = |i: usize| if members.is_empty() { points[range.start + i] } else { points[members[i] as usize] };
        let n = range.len();
        let x: Vec<f64> = if members.is_empty() {
            points[range.clone()].iter().map(|p| p.x).collect()
        } else {
            members.iter().map(|&k| points[k as usize].x).collect()
        };
        // The strip is in one anchor row (one corner y) and sorted by x, so each anchor square's
        // points follow each other: a search finds where each square's run ends.
        let square = |i: usize| self.anchor_of(point(i)).expect("points in the lattice only");
        let (mut runs, mut qx, mut i) = (Vec::new(), Vec::with_capacity(n), 0);
        while i < n {
            let cell = square(i);
            // A bisection for the end of the run from `i`: the points before `end` are in it,
            // those from `past` on are not.
            let (mut end, mut past) = (i, n);
            while end < past {
                let mid = end + (past - end) / 2;
                (end, past) = if square(mid) == cell { (mid + 1, past) } else { (end, mid) };
            }
            let corner = self.anchor(cell);
            runs.push(Run { end: end as u32, corner });
            qx.resize(end, 0.0);
            qx[i..end].iter_mut().zip(&x[i..end]).for_each(|(q, &x)| *q = (x - corner.x) as f32);
            i = end;
        }
        let corner_y = runs[0].corner.y;
        let (qy, row) = if y0 == y1 {
            (Vec::new(), Some((y0 - corner_y) as f32))
        } else {
            ((0..n).map(|i| (point(i).y - corner_y) as f32).collect(), None)
        };
        let (x0, last) = (x[0], x[n - 1]);
        let per_x = if last > x0 { (n - 1) as f64 / (last - x0) } else { 0.0 };
        let mut strip =
            Strip { y0, y1, x0, per_x, drift: None, x, qx, qy, row, runs, members, first: range.start as u32 };
        if per_x > 0.0 {
            // Exact: within a quarter of its index, a place of index 1 or more is within a factor
            // of 2 of it, so the subtraction is exact (the place of index 0 is 0). Scattered
            // points stop at the first chunk of [`DRIFT_CHUNK`] with a point a quarter or more
            // from its index.
            strip.drift = strip.x.chunks(DRIFT_CHUNK).enumerate().try_fold(0.0, |drift: f64, (c, xs)| {
                // Eight running maxima, in vectors.
                let mut far = [drift; 8];
                for (g, group) in xs.chunks(8).enumerate() {
                    let base = c * DRIFT_CHUNK + 8 * g;
                    for (l, (f, &x)) in far.iter_mut().zip(group).enumerate() {
                        *f = f.max((strip.place(x) - (base + l) as f64).abs());
                    }
                }
                let drift = far.into_iter().fold(0.0, f64::max);
                (drift < 0.25).then_some(drift)
            });
        }
        strip
    }

    /// The Gaussians' sums at the points of the strips `inside` (a band): the candidates found
    /// once for the band's box, then every support in order over every strip it may reach.
    fn band_sums(&self, inside: &[Strip], gradients: bool) -> Vec<Sums> {
        let x_min = inside.iter().map(|s| s.x[0]).fold(f64::INFINITY, f64::min);
        let x_max = inside.iter().map(|s| s.x[s.x.len() - 1]).fold(f64::NEG_INFINITY, f64::max);
        let candidates =
            self.candidates(DVec2::new(x_min, inside[0].y0), DVec2::new(x_max, inside[inside.len() - 1].y1));
        let mut sums: Vec<Sums> = inside
            .iter()
            .map(|s| {
                let n = s.x.len();
                let gradient = if gradients { vec![0.0; n] } else { Vec::new() };
                Sums { h: vec![0.0; n], gx: gradient.clone(), gy: gradient }
            })
            .collect();
        let work = BandWork { items: &self.items, candidates: &candidates, inside, sums: &mut sums };
        pulp::Arch::new().dispatch(work);
        sums
    }

    /// The Gaussians whose reach boxes meet the box `[lo, hi]`, in index order (the order
    /// every point sums them in): from the y window ([`Self::window`]) when the box is wide
    /// ([`Self::scans`]), else from a walk of the hierarchy (a single query).
    fn candidates(&self, lo: DVec2, hi: DVec2) -> Vec<u32> {
        let meets = |k: usize| {
            let (a, b) = self.reach[k];
            a.x <= hi.x && b.x >= lo.x && a.y <= hi.y && b.y >= lo.y
        };
        if self.scans(lo, hi) {
            return self.window(lo.y, hi.y).filter(|&k| meets(k)).map(|k| k as u32).collect();
        }
        let mut candidates = Vec::new();
        let bounds = outward_box(lo - self.origin, hi - self.origin);
        self.bvh.aabb_traverse(bounds, |bvh, node| collect_leaf(bvh, node, &mut candidates));
        // A leaf comes whole: its supports that miss the box would each cost a kernel call.
        candidates.retain(|&k| (k as usize) < self.gaussians && meets(k as usize));
        candidates.sort_unstable();
        candidates
    }

    /// Whether a box from `lo` to `hi` is wide enough to scan its y window for candidates:
    /// at least the Gaussians' x extent over [`WINDOW_SHARE`] (a grid's or a scattered batch's
    /// band). Either way gives the same candidates, so this changes the speed, never the sums.
    fn scans(&self, lo: DVec2, hi: DVec2) -> bool {
        (hi.x - lo.x) * WINDOW_SHARE >= self.x_span
    }

    /// The indices of the Gaussians that may meet the band of y from `y0` to `y1`: from the
    /// first whose reach box's top is at or above `y0` to the last whose bottom is at or below
    /// `y1` (two bisections of [`Self::tops`] and [`Self::bottoms`]).
    fn window(&self, y0: f64, y1: f64) -> std::ops::Range<usize> {
        let first = self.tops.partition_point(|&top| top < y0);
        first..self.bottoms.partition_point(|&bottom| bottom <= y1).max(first)
    }

    /// Adds the detail layers to `out` (the Gaussians' samples), cell by cell in parallel.
    fn add_details(&self, points: &[DVec2], gradients: bool, out: &mut [Sample]) {
        let cells = self.bucket(points);
        let parts: Vec<Vec<(u32, Sample)>> = cells
            .par_chunks(CELLS_PER_TASK)
            .map(|cells| {
                let (mut candidates, mut part) = (Vec::new(), Vec::new());
                for (key, members) in cells {
                    self.cell_details(*key, points, members, gradients, out, &mut candidates, &mut part);
                }
                part
            })
            .collect();
        for (k, s) in parts.into_iter().flatten() {
            out[k as usize] = s;
        }
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

    /// The detail layers at `points[members]`, all in the lattice cell `key`, over the
    /// Gaussians' samples `ground`: the falloffs over the cell (and over the gradient's steps
    /// out of it) once, then every point against all of them.
    #[allow(clippy::too_many_arguments, reason = "one cell's inputs and the caller's scratch")]
    fn cell_details(
        &self,
        key: (i32, i32),
        points: &[DVec2],
        members: &[u32],
        gradients: bool,
        ground: &[Sample],
        candidates: &mut Vec<u32>,
        out: &mut Vec<(u32, Sample)>,
    ) {
        let corner = self.corner(key);
        let (lo, hi) = (corner, corner + DVec2::splat(self.cell));
        candidates.clear();
        let step = if gradients { self.detail_step() } else { 0.0 };
        self.bvh.aabb_traverse(outward_box(lo - step - self.origin, hi + step - self.origin), |bvh, node| {
            collect_leaf(bvh, node, candidates)
        });
        // What the points' f32 coordinates relative to the corner may be off by, and more.
        let slack = 1e-5 * self.cell;
        candidates.retain(|&k| k as usize >= self.gaussians && self.items[k as usize].meets(lo, hi, slack + step));
        candidates.sort_unstable();
        if candidates.is_empty() {
            return;
        }
        for &k in members {
            let (p, under) = (points[k as usize], ground[k as usize]);
            let mut s = under;
            s.elevation += self.details_at(p, candidates, under.ground());
            if gradients {
                s.gradient += self.details_gradient(p, under, candidates);
            }
            out.push((k, s));
        }
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

/// Sorts the point indices `part` by `key`, computed once per point (ties in any order).
fn sort_by_key(part: &mut [u32], key: impl Fn(u32) -> u64) {
    let mut keyed: Vec<(u64, u32)> = part.iter().map(|&k| (key(k), k)).collect();
    keyed.sort_unstable();
    for (slot, (_, k)) in part.iter_mut().zip(keyed) {
        *slot = k;
    }
}

/// An integer in the order of [`f64::total_cmp`].
fn sortable(v: f64) -> u64 {
    let bits = v.to_bits();
    if bits >> 63 == 1 { !bits } else { bits | 1 << 63 }
}

/// Most points a batch takes at once (point indices are u32, a stretch's lanes i32): larger
/// batches go in chunks, each point's value the same.
const MAX_BATCH: usize = i32::MAX as usize;

/// Points per parallel task of the scans over a whole batch.
const SCAN_CHUNK: usize = 8192;

/// Fewest points of one y value that make a strip of their own (a grid row).
const MIN_ROW: usize = 64;

/// Most y spread of a strip, in query cells (typical support widths): a support crosses about 4
/// strips. On 1024² scattered points over the benchmark's terrain, 1/16 took 185–198 ms, 1/8
/// 150–152, 1/4 130–135, 1/2 136–138 and 1 131–141.
const STRIP_THICKNESS: f64 = 0.25;

/// Points per band (a parallel task), at least one strip.
const BAND_POINTS: usize = 16_384;

/// Most strips per band.
const BAND_STRIPS: usize = 16;

/// A batch's points prepared for the kernel. Sorted by lattice row, then y, then x, they are cut
/// into strips: the points of one y value when there are [`MIN_ROW`] of them (a grid row: its
/// stretch of a support is exact, as the rasterizer's span), else the points within
/// [`STRIP_THICKNESS`] cells of y (scattered points), sorted by x. A support reaches a strip's points in one
/// stretch of x, found from where the points would be were they evenly spread; every point is
/// held relative to its own anchor square's corner, so the stretch takes the next square's
/// brackets where the square changes ([`Next`]), and is cut where it changes again.
struct Strip {
    /// The points' y range, the first x, and points per unit of x (0 for one x).
    y0: f64,
    y1: f64,
    x0: f64,
    per_x: f64,
    /// For evenly spread points (a grid row), how far a point's [`Strip::place`] is from its
    /// index at most (below a quarter); `None` for uneven points.
    drift: Option<f64>,
    /// Each point's x, for the stretches' searches.
    x: Vec<f64>,
    /// Each point relative to its square's corner (f32, as the kernel takes it): y only for a
    /// strip of several y values, else `row` for all.
    qx: Vec<f32>,
    qy: Vec<f32>,
    row: Option<f32>,
    /// Consecutive points in one anchor square, in order.
    runs: Vec<Run>,
    /// Each point's index in the caller's points; empty when they are `first` on, in order.
    members: Vec<u32>,
    first: u32,
}

impl Strip {
    /// Point `n`'s index in the caller's points.
    fn member(&self, n: usize) -> u32 {
        if self.members.is_empty() { self.first + n as u32 } else { self.members[n] }
    }

    /// Where a point at `x` would be, were the points evenly spread: its index, not rounded.
    /// It never decreases with `x`.
    #[allow(
        clippy::inline_always,
        reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
    )]
    #[inline(always)]
    fn place(&self, x: f64) -> f64 {
        (x - self.x0) * self.per_x
    }

    /// [`Strip::place`] rounded to an index, so rounding errors of the points' own x keep their
    /// ranks: the guess a search starts from.
    #[allow(
        clippy::inline_always,
        reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
    )]
    #[inline(always)]
    fn rank(&self, x: f64) -> usize {
        (self.place(x) + 0.5).max(0.0) as usize
    }

    /// The points from `x0` to `x1`. For evenly spread points, with no search: a point in the
    /// range has an index within the drift of the range's places, so the stretch is the indices
    /// there (a point within the drift of an end may come along; the kernel's own inside test
    /// leaves it out, as a support's grown range reaches no point it counts outside). No margin
    /// is needed: a point `k` at or after `x0` has `place(x0) − drift ≤ place(x_k) − drift ≤ k`
    /// (rounding keeps order), and the rounded difference stays at or below the integer `k`; the
    /// same holds at `x1`. Else a search from the ranks.
    #[allow(
        clippy::inline_always,
        reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
    )]
    #[inline(always)]
    fn stretch(&self, x0: f64, x1: f64) -> (usize, usize) {
        let n = self.x.len();
        if let Some(drift) = self.drift {
            // The standard rounding: one instruction within the kernel's target features.
            let i = ((self.place(x0) - drift).ceil().max(0.0) as usize).min(n);
            (i, (((self.place(x1) + drift).floor() + 1.0).max(0.0) as usize).clamp(i, n))
        } else {
            let i = partition_near(&self.x, self.rank(x0), |x| x < x0);
            (i, partition_near(&self.x, self.rank(x1), |x| x <= x1).max(i))
        }
    }

    /// The run that holds point `i` (below the strip's length). A strip mostly has a few runs
    /// (a grid row of 1024 points over the benchmark's terrain, 4 or 5): a scan is quicker than
    /// a bisection's unpredictable branches, which take over beyond [`SCANNED_RUNS`].
    #[allow(
        clippy::inline_always,
        reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
    )]
    #[inline(always)]
    fn run_of(&self, i: usize) -> usize {
        if self.runs.len() > SCANNED_RUNS {
            return self.runs.partition_point(|run| run.end as usize <= i);
        }
        let mut r = 0;
        while self.runs[r].end as usize <= i {
            r += 1;
        }
        r
    }
}

/// A band at least the Gaussians' x extent over this wide scans its y window for candidates
/// ([`TerrainQuery::scans`]).
const WINDOW_SHARE: f64 = 4.0;

/// Points a strip's drift takes at once (a scattered strip stops at the first chunk a quarter
/// or more from its indices).
const DRIFT_CHUNK: usize = 64;

/// Most runs a strip's [`Strip::run_of`] scans.
const SCANNED_RUNS: usize = 8;

/// Consecutive points of a strip in one anchor square: where they end and the square's corner.
#[derive(Clone, Copy)]
struct Run {
    end: u32,
    corner: DVec2,
}

/// The partition point of `xs` for `before` (true on a prefix), looked for from `guess`: a few
/// steps when the guess is close (evenly spread points: a grid row), a bisection otherwise.
#[allow(
    clippy::inline_always,
    reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
)]
#[inline(always)]
fn partition_near(xs: &[f64], guess: usize, before: impl Fn(f64) -> bool) -> usize {
    const STEPS: usize = 4;
    let mut g = guess.min(xs.len());
    for _ in 0..STEPS {
        if g > 0 && !before(xs[g - 1]) {
            g -= 1;
        } else if g < xs.len() && before(xs[g]) {
            g += 1;
        } else {
            return g;
        }
    }
    if g > 0 && !before(xs[g - 1]) {
        xs[..g].partition_point(|&x| before(x))
    } else {
        g + xs[g..].partition_point(|&x| before(x))
    }
}

/// Whether a point `c` anchor squares from the origin has one: finite and within 2³⁰ squares.
fn within_lattice(c: DVec2) -> bool {
    const FAR: f64 = (1u32 << 30) as f64;
    c.x.abs() < FAR && c.y.abs() < FAR
}

/// The indices of `points` (ordered by y) whose y differs from the point before's. The points of
/// one y follow each other, so each run's end is found by doubling steps from its start, then a
/// bisection: a grid's row costs about twice the logarithm of its length, not a look at every
/// point.
fn changes_of_y(points: &[DVec2]) -> impl Iterator<Item = usize> + '_ {
    let mut start = 0;
    std::iter::from_fn(move || {
        let y = points.get(start)?.y;
        // `start + reach` is in the run; the run ends before `start + step` (or the end).
        let (mut reach, mut step) = (0, 1);
        while start + step < points.len() && points[start + step].y == y {
            (reach, step) = (step, 2 * step);
        }
        let tail = &points[start + reach + 1..(start + step).min(points.len())];
        start += reach + 1 + tail.partition_point(|p| p.y == y);
        (start < points.len()).then_some(start)
    })
}

/// The strips (their ranges of points) cut into bands (parallel tasks): consecutive strips up
/// to [`BAND_POINTS`] points (at least one strip) and [`BAND_STRIPS`] strips.
fn bands(strips: &[std::ops::Range<usize>]) -> Vec<std::ops::Range<usize>> {
    let mut bands = Vec::new();
    let (mut first, mut points) = (0, 0);
    for (s, strip) in strips.iter().enumerate() {
        points += strip.len();
        if s + 1 == strips.len() || points >= BAND_POINTS || s + 1 - first >= BAND_STRIPS {
            bands.push(first..s + 1);
            (first, points) = (s + 1, 0);
        }
    }
    bands
}

/// A band's Gaussian sums: elevations, and the x and y derivatives (empty unless asked for);
/// f32 like the rasterizer's.
struct Sums {
    h: Vec<f32>,
    gx: Vec<f32>,
    gy: Vec<f32>,
}

/// One band's work as a `pulp` operation: dispatched to the widest vector instructions the CPU
/// has (AVX-512 or AVX2 where present), so the loops along a stretch use them. The vector build
/// gives the bits of the plain one (no implicit fusing, explicit `mul_add`s fused on both).
struct BandWork<'a> {
    items: &'a [Item],
    /// The Gaussians that may reach the band, ascending.
    candidates: &'a [u32],
    /// The band's strips and their sums.
    inside: &'a [Strip],
    sums: &'a mut [Sums],
}

impl pulp::WithSimd for BandWork<'_> {
    type Output = ();

    #[allow(
        clippy::inline_always,
        reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
    )]
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let BandWork { items, candidates, inside, sums } = self;
        if let ([strip], [sums]) = (inside, &mut *sums)
            && strip.x.len() == 1
        {
            // A point alone (a single query): every candidate straight to the kernel, whose own
            // inside test is what decides; the x ranges and searches would cost more than it.
            let corner = strip.runs[0].corner;
            for &k in candidates {
                add_stretch((Local::new(&items[k as usize], corner), None), strip, sums, (0, 1), S::F32_LANES);
            }
            return;
        }
        for &k in candidates {
            let item = &items[k as usize];
            // The support seen from the last corner: consecutive strips mostly share it.
            let mut seen: Option<(DVec2, Local)> = None;
            let reach = item.y_reach + item.slack;
            let first = inside.partition_point(|s| s.y1 < item.center.y - reach);
            let last = inside.partition_point(|s| s.y0 <= item.center.y + reach).max(first);
            // The strips' stretches first, then the kernel over each: the square roots and
            // roundings run back to back instead of each behind a kernel loop's last branch (the
            // kernel's first load waits on them; this took 5-6 % off a grid's query time). Each
            // is (strip, first point, end); a band has at most [`BAND_STRIPS`] strips ([`bands`]).
            let mut stretches = [(0usize, 0usize, 0usize); BAND_STRIPS];
            let mut count = 0;
            for (s, strip) in inside[first..last].iter().enumerate() {
                let Some((x0, x1)) = item.x_range(strip.y0, strip.y1) else { continue };
                let (i, j) = strip.stretch(x0, x1);
                stretches[count] = (first + s, i, j);
                count += usize::from(i < j);
            }
            for &(s, mut i, j) in &stretches[..count] {
                let (strip, sums) = (&inside[s], &mut sums[s]);
                let mut r = strip.run_of(i);
                while i < j {
                    let run = strip.runs[r];
                    r += 1;
                    let e = (run.end as usize).min(j);
                    let c = match seen {
                        Some((corner, c)) if corner == run.corner => c,
                        _ => seen.insert((run.corner, Local::new(item, run.corner))).1,
                    };
                    // A stretch that ends in the next square goes in one pass (each point from
                    // its own square's corner): no second widening, no second stretch's set-up.
                    if e < j && strip.runs[r].end as usize >= j {
                        let far = Local::new(item, strip.runs[r].corner);
                        let next = Next { at: e, kx: far.kx, ky: far.ky };
                        add_stretch((c, Some(next)), strip, sums, (i, j), S::F32_LANES);
                        break;
                    }
                    add_stretch((c, None), strip, sums, (i, e), S::F32_LANES);
                    i = e;
                }
            }
        }
    }
}

/// Adds the Gaussian `c.0` over the points `i..e` of `strip` (in one anchor square, or in two
/// when `c.1` says where the next starts and gives its brackets) to `sums`: with gradients when
/// `sums` has them, the logarithm skipped for β = 2, in vectors of `lanes` points (the
/// dispatched register's f32 count).
#[allow(
    clippy::inline_always,
    reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
)]
#[inline(always)]
fn add_stretch(c: (Local, Option<Next>), strip: &Strip, sums: &mut Sums, (i, e): (usize, usize), lanes: usize) {
    let exponent = c.0.half_beta - 1.0;
    let lower = move |s: f32| exp2_signed(exponent * log2(s));
    let q = (&strip.qx[..], &strip.qy[..], strip.row);
    match (sums.gx.is_empty(), c.0.half_beta == 1.0, c.1.is_some()) {
        (false, true, _) => add_terms(c, q, sums, (i, e, lanes), |_| 1.0),
        (false, false, _) => add_terms(c, q, sums, (i, e, lanes), lower),
        (true, true, true) => add_values::<true>(c, q, &mut sums.h, (i, e, lanes), |_| 1.0),
        (true, true, false) => add_values::<false>(c, q, &mut sums.h, (i, e, lanes), |_| 1.0),
        (true, false, true) => add_values::<true>(c, q, &mut sums.h, (i, e, lanes), lower),
        (true, false, false) => add_values::<false>(c, q, &mut sums.h, (i, e, lanes), lower),
    }
}

/// A Gaussian seen from an anchor square's corner, in f32 for the kernel: a point `q` from the corner has
/// local coordinates `x = qx·ux + (qy·uy + kx)`, `y = qx·vx + (qy·vy + ky)` (fused, so a row of
/// one y takes the bracket once and a point alone gets the same bits), where `(kx, ky)` is
/// minus the centre's, from the corner, in f64.
#[derive(Clone, Copy)]
struct Local {
    ux: f32,
    uy: f32,
    vx: f32,
    vy: f32,
    kx: f32,
    ky: f32,
    r2: f32,
    amplitude: f32,
    half_beta: f32,
}

impl Local {
    fn new(i: &Item, corner: DVec2) -> Self {
        let c = i.center - corner;
        Local {
            ux: i.u.x as f32,
            uy: i.u.y as f32,
            vx: i.v.x as f32,
            vy: i.v.y as f32,
            kx: -c.dot(i.u) as f32,
            ky: -c.dot(i.v) as f32,
            r2: i.r2 as f32,
            amplitude: i.amplitude as f32,
            half_beta: i.half_beta as f32,
        }
    }
}

/// Where a stretch passes into the next anchor square, and the support's brackets `(kx, ky)`
/// from that square's corner ([`Local`]): the points from there on take them, as they would
/// in a stretch of their own.
#[derive(Clone, Copy)]
struct Next {
    at: usize,
    kx: f32,
    ky: f32,
}

impl Next {
    /// The lane where the next square starts in vectors from point `start`, and its brackets.
    #[allow(
        clippy::inline_always,
        reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
    )]
    #[inline(always)]
    fn brackets(self, start: usize) -> (i32, f32, f32) {
        ((self.at - start) as i32, self.kx, self.ky)
    }
}

/// The whole vectors of `lanes` lanes that cover the stretch `a..e` of `n` points (widened
/// within the band, so short stretches need no scalar remainder), and the stretch within them.
#[allow(
    clippy::inline_always,
    reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
)]
#[inline(always)]
fn widen((a, e, lanes): (usize, usize, usize), n: usize) -> (std::ops::Range<usize>, i32, i32) {
    let width = (e - a).next_multiple_of(lanes).min(n);
    let lo = a.min(n - width);
    (lo..lo + width, (a - lo) as i32, (e - lo) as i32)
}

/// Adds the Gaussian `c` to the sums of the stretch `lanes` of points inside its support, given
/// `lower(s) = s^(β/2 − 1)`: the gradient's factor, and `s^(β/2)` is `s·lower(s)` (β = 2 skips
/// the logarithm: `lower` is 1). Lanes outside the stretch or the support add +0, which keeps
/// their bits: a sum starts at +0 and, rounding to nearest, only −0 + −0 makes −0, so no sum is
/// ever −0, the one value +0 would change. Every lane then takes the same add and a plain store
/// (a choice between old and new sums had cost 3–4 % of a grid's query time).
#[allow(
    clippy::inline_always,
    reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
)]
#[inline(always)]
fn add_terms(
    (c, next): (Local, Option<Next>),
    (qx, qy, row): (&[f32], &[f32], Option<f32>),
    sums: &mut Sums,
    lanes: (usize, usize, usize),
    lower: impl Fn(f32) -> f32,
) {
    let (range, first, last) = widen(lanes, qx.len());
    // Without a next square no lane is past the split, and its brackets are the first's.
    let (split, kx2, ky2) = next.map_or((i32::MAX, c.kx, c.ky), |next| next.brackets(range.start));
    let second = |j: usize| (j as i32) >= split;
    let n = range.len();
    let qx = &qx[range.clone()][..n];
    let (h, gx, gy) =
        (&mut sums.h[range.clone()][..n], &mut sums.gx[range.clone()][..n], &mut sums.gy[range.clone()][..n]);
    // The value and gradient terms at local (x, y), 0 outside the support.
    let term = |x: f32, y: f32| {
        let s = x * x + y * y;
        let lower = lower(s);
        let g = c.amplitude * exp_neg(-0.5 * (s * lower));
        let slope = -g * c.half_beta * lower;
        (s <= c.r2, g, slope * (x * c.ux + y * c.vx), slope * (x * c.uy + y * c.vy))
    };
    let keep = |j: usize| (j as i32) >= first && (j as i32) < last;
    if let Some(row) = row {
        // One y for the whole stretch: the brackets once.
        let (a, b) =
            ((row.mul_add(c.uy, c.kx), row.mul_add(c.vy, c.ky)), (row.mul_add(c.uy, kx2), row.mul_add(c.vy, ky2)));
        for j in 0..n {
            let (ax, ay) = if second(j) { b } else { a };
            let (inside, g, dx, dy) = term(qx[j].mul_add(c.ux, ax), qx[j].mul_add(c.vx, ay));
            let add = inside && keep(j);
            let (g, dx, dy) = if add { (g, dx, dy) } else { (0.0, 0.0, 0.0) };
            (h[j], gx[j], gy[j]) = (h[j] + g, gx[j] + dx, gy[j] + dy);
        }
    } else {
        let qy = &qy[range][..n];
        for j in 0..n {
            let (kx, ky) = if second(j) { (kx2, ky2) } else { (c.kx, c.ky) };
            let (x, y) = (qx[j].mul_add(c.ux, qy[j].mul_add(c.uy, kx)), qx[j].mul_add(c.vx, qy[j].mul_add(c.vy, ky)));
            let (inside, g, dx, dy) = term(x, y);
            let add = inside && keep(j);
            let (g, dx, dy) = if add { (g, dx, dy) } else { (0.0, 0.0, 0.0) };
            (h[j], gx[j], gy[j]) = (h[j] + g, gx[j] + dx, gy[j] + dy);
        }
    }
}

/// [`add_terms`] without the gradient: the elevations only, the same bits. `SPLIT` says whether
/// the stretch passes into a next square (`next` is given): without it the lanes' test for the
/// next square's brackets is compiled out (about 1 % of a grid's query time, alternated in one
/// process with the test kept for every stretch).
#[allow(
    clippy::inline_always,
    reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
)]
#[inline(always)]
fn add_values<const SPLIT: bool>(
    (c, next): (Local, Option<Next>),
    (qx, qy, row): (&[f32], &[f32], Option<f32>),
    h: &mut [f32],
    lanes: (usize, usize, usize),
    lower: impl Fn(f32) -> f32,
) {
    let (range, first, last) = widen(lanes, qx.len());
    // Without a next square no lane is past the split, and its brackets are the first's.
    let (split, kx2, ky2) = next.map_or((i32::MAX, c.kx, c.ky), |next| next.brackets(range.start));
    let second = |k: i32| SPLIT && k >= split;
    let n = range.len();
    let (qx, h) = (&qx[range.clone()][..n], &mut h[range.clone()][..n]);
    // Whether (x, y) is inside the support, and the value there.
    let value = |x: f32, y: f32| {
        let s = x * x + y * y;
        (s <= c.r2, c.amplitude * exp_neg(-0.5 * (s * lower(s))))
    };
    if let Some(row) = row {
        // One y for the whole stretch: the brackets once.
        let (a, b) =
            ((row.mul_add(c.uy, c.kx), row.mul_add(c.vy, c.ky)), (row.mul_add(c.uy, kx2), row.mul_add(c.vy, ky2)));
        for j in 0..n {
            let k = j as i32;
            let (ax, ay) = if second(k) { b } else { a };
            let (inside, g) = value(qx[j].mul_add(c.ux, ax), qx[j].mul_add(c.vx, ay));
            h[j] += if inside && k >= first && k < last { g } else { 0.0 };
        }
    } else {
        let qy = &qy[range][..n];
        for j in 0..n {
            let k = j as i32;
            let (kx, ky) = if second(k) { (kx2, ky2) } else { (c.kx, c.ky) };
            let (inside, g) =
                value(qx[j].mul_add(c.ux, qy[j].mul_add(c.uy, kx)), qx[j].mul_add(c.vx, qy[j].mul_add(c.vy, ky)));
            h[j] += if inside && k >= first && k < last { g } else { 0.0 };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The x range over a band of y holds every point of the grown support in the band, and
    /// its ends are reached (to the outline's spacing): the support's extremes, or the band's edge.
    #[test]
    fn x_range_is_the_support_over_the_band() {
        let g = Gaussian { center: [3.0, -2.0], sigma: [6.0, 1.5], theta: 0.6, amplitude: 1.0, beta: 1.5 };
        let item = Item::new(&g, 1e-3);
        let r = g.support_radius(1e-3) * (1.0 + 1e-4);
        let outline: Vec<DVec2> = (0..20_000)
            .map(|k| {
                let t = f64::from(k) * std::f64::consts::TAU / 20_000.0;
                let local = DVec2::new(r * g.sigma[0] * t.cos(), r * g.sigma[1] * t.sin());
                DVec2::from(g.center) + DVec2::from_angle(g.theta).rotate(local)
            })
            .collect();
        let top = outline.iter().map(|p| p.y).fold(f64::MIN, f64::max);
        assert!((top - (g.center[1] + item.y_reach)).abs() < 1e-6);
        for (y0, y1) in [(-20.0, 20.0), (-2.0, -2.0), (0.5, 1.5), (-9.0, -6.0), (top - 0.01, top + 5.0)] {
            let (x0, x1) = item.x_range(y0, y1).unwrap();
            let inside: Vec<f64> = outline.iter().filter(|p| p.y >= y0 && p.y <= y1).map(|p| p.x).collect();
            // An edge point in the band, or for a thin band the edge at its y.
            let (lo, hi) = if inside.is_empty() {
                (x0, x1)
            } else {
                (inside.iter().copied().fold(f64::MAX, f64::min), inside.iter().copied().fold(f64::MIN, f64::max))
            };
            assert!(x0 <= lo && x1 >= hi, "band {y0}..{y1}: {x0}..{x1} misses {lo}..{hi}");
            if !inside.is_empty() {
                assert!(lo - x0 < 1e-2 && x1 - hi < 1e-2, "band {y0}..{y1}: {x0}..{x1} wider than {lo}..{hi}");
            }
        }
        // One y: the chord of the ellipse there.
        let (x0, x1) = item.x_range(-2.0, -2.0).unwrap();
        let chord = |x: f64| g.distance_squared(DVec2::new(x, -2.0)) - r * r;
        assert!(chord(x0 + item.slack).abs() < 1e-9 && chord(x1 - item.slack).abs() < 1e-9);
        assert!(item.x_range(top + 0.1, top + 1.0).is_none());
        assert!(item.x_range(-100.0, 2.0 * g.center[1] - top - 0.1).is_none());
    }

    /// A grid row is an even strip: every point ranks at its own index, and a stretch is exactly
    /// the points in its range (ends on a point included). A jittered row is even with a larger
    /// drift: its stretches hold every point in range, and only points within the drift of an
    /// end besides. A strip of uneven points is not even, and its stretches are exact.
    #[test]
    fn grid_rows_are_even_strips() {
        let terrain = VectorTerrain::new(vec![Gaussian::round(DVec2::new(50.0, 50.0), 10.0, 1.0)]);
        let query = terrain.query().unwrap();
        let row: Vec<DVec2> = (0..700).map(|i| DVec2::new(-3.7 + f64::from(i) * 0.1437, 20.0)).collect();
        let strips = query.strips(&row).0;
        assert_eq!(strips.len(), 1);
        let strip = &strips[0];
        assert!(strip.drift.is_some_and(|d| d < 1e-9) && strip.y0 == strip.y1);
        assert!(strip.x.iter().enumerate().all(|(k, &x)| strip.rank(x) == k));
        let jitter = |i: i32| 0.03 * f64::from((i * 7919) % 13 - 6) / 6.0;
        let jittered: Vec<DVec2> =
            (0..700).map(|i| DVec2::new(-3.7 + (f64::from(i) + jitter(i)) * 0.1437, 20.0)).collect();
        let shaken = &query.strips(&jittered).0[0];
        let drift = shaken.drift.expect("a jittered row is even");
        assert!(drift > 0.02 && drift < 0.1, "drift {drift}");
        let uneven: Vec<DVec2> = (0..700).map(|i| DVec2::new(f64::from(i * i) * 1e-3, 20.0)).collect();
        let other = &query.strips(&uneven).0[0];
        assert!(other.drift.is_none());
        // A range that ends on a point holds it, on every point of both rows.
        for s in [strip, shaken] {
            assert!((0..s.x.len()).all(|k| {
                let ((i, j), (ii, jj)) = (s.stretch(s.x[k], s.x[k]), s.stretch(s.x[k], s.x[k] + 1.0));
                i <= k && k < j && ii <= k && k < jj
            }));
        }
        let on_points = (strip.x[10], strip.x[20]);
        for (x0, x1) in [(-10.0, -5.0), (0.0, 0.0), (1.0, 7.3), (12.34, 80.0), (99.0, 120.0), (-1.0, 200.0), on_points]
        {
            let exact = |s: &Strip| {
                let p0 = s.x.partition_point(|&x| x < x0);
                (p0, s.x.partition_point(|&x| x <= x1).max(p0))
            };
            assert_eq!(strip.stretch(x0, x1), exact(strip), "{x0}..{x1}");
            assert_eq!(other.stretch(x0, x1), exact(other), "{x0}..{x1}");
            let ((i, j), (p0, p1)) = (shaken.stretch(x0, x1), exact(shaken));
            assert!(i <= p0 && j >= p1, "{x0}..{x1}: {i}..{j} against {p0}..{p1}");
            let near = |k: usize| (shaken.x[k] - x0).abs().min((shaken.x[k] - x1).abs()) <= drift / shaken.per_x;
            assert!((i..p0).chain(p1..j).all(near), "{x0}..{x1}: {i}..{j} against {p0}..{p1}");
        }
    }

    /// Grid rows in row order make one strip each, however close; scattered points make strips
    /// at most [`STRIP_THICKNESS`] cells thick, sorted by x, each within one anchor row, cut
    /// only where they must be; every point is in one strip.
    #[test]
    fn strips_are_rows_or_thin_slabs() {
        // The fixture's primitives, as this crate's own (the fixture links another build of it).
        let fixture = relief_fixtures::random_terrain(400, 1000.0, 16.0, 2);
        let primitives = fixture.primitives.iter().map(|g| Gaussian {
            center: g.center,
            sigma: g.sigma,
            theta: g.theta,
            amplitude: g.amplitude,
            beta: g.beta,
        });
        let query = VectorTerrain::new(primitives.collect()).query().unwrap();
        let (thick, rows) = (query.cell * STRIP_THICKNESS, 60);
        let grid: Vec<DVec2> =
            (0..100 * rows).map(|k| DVec2::new(f64::from(k % 100) * 10.0, f64::from(k / 100) * thick * 0.1)).collect();
        let (strips, in_order) = query.strips(&grid);
        assert!(in_order, "a grid in row order is written strip by strip");
        assert_eq!(strips.len(), rows as usize);
        assert!(strips.iter().all(|s| s.drift.is_some() && s.y0 == s.y1 && s.x.len() == 100 && s.members.is_empty()));
        // A point repeated is still in order.
        let twice = [grid[0], grid[1], grid[1], grid[2]];
        assert!(query.strips(&twice).1 && query.strips(&twice).0[0].members.is_empty());
        let mut state = 7_u64;
        let mut next = move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let scattered: Vec<DVec2> = (0..5_000).map(|_| DVec2::new(next() * 1000.0, next() * 1000.0)).collect();
        let (strips, in_order) = query.strips(&scattered);
        assert!(!in_order);
        let anchor_row = |k: u32| query.anchor_of(scattered[k as usize]).unwrap().1;
        let mut seen = vec![false; scattered.len()];
        for (n, s) in strips.iter().enumerate() {
            assert!(s.y1 - s.y0 <= thick && s.x.is_sorted());
            assert!(s.members.iter().all(|&k| anchor_row(k) == anchor_row(s.members[0])));
            // Each point is held from its own anchor square's corner.
            for (i, &k) in s.members.iter().enumerate() {
                let run = s.runs[s.runs.partition_point(|run| run.end as usize <= i)];
                assert_eq!(run.corner, query.anchor(query.anchor_of(scattered[k as usize]).unwrap()));
                let from = (scattered[k as usize] - run.corner) / (ANCHOR_CELLS * query.cell);
                assert!(
                    from.cmpge(DVec2::ZERO).all() && from.cmplt(DVec2::ONE).all(),
                    "{from} squares from the corner"
                );
                assert!(!std::mem::replace(&mut seen[k as usize], true));
                assert!((scattered[k as usize].y - s.y0) * (scattered[k as usize].y - s.y1) <= 0.0);
            }
            // The next strip could not have taken this one's points: thicker, or another row.
            if let Some(next) = strips.get(n + 1) {
                let same_row = anchor_row(next.members[0]) == anchor_row(s.members[0]);
                assert!(next.y1 - s.y0 > thick || !same_row, "strip {n} could hold the next");
            }
        }
        assert!(seen.iter().all(|s| *s));
        assert!(strips.len() > 20 && strips.len() < 1_000);
    }

    /// A point's run is found by a scan over a few runs and by a bisection over many, alike.
    #[test]
    fn run_of_finds_the_run_of_each_point() {
        let terrain = VectorTerrain::new(vec![Gaussian::round(DVec2::new(50.0, 50.0), 10.0, 1.0)]);
        let query = terrain.query().unwrap();
        let square = ANCHOR_CELLS * query.cell;
        // One run, a few (scanned), and many (bisected).
        for (count, step, runs) in [(700, 0.1437, 1..=2), (7, square / 2.0, 4..=4), (700, square / 25.0, 28..=29)] {
            let row: Vec<DVec2> = (0..count).map(|i| DVec2::new(-3.7 + f64::from(i) * step, 20.0)).collect();
            let strip = &query.strips(&row).0[0];
            assert!(runs.contains(&strip.runs.len()), "{count} points: {} runs", strip.runs.len());
            for i in 0..strip.x.len() {
                assert_eq!(
                    strip.run_of(i),
                    strip.runs.partition_point(|run| run.end as usize <= i),
                    "{count} points, {i}"
                );
            }
        }
    }

    /// A batch in y order that ends just within or just beyond the anchor lattice gives the
    /// single queries: the order check's test without a division lets a point through only
    /// well within the lattice, and the exact test decides the rest.
    #[test]
    fn a_batch_to_the_lattice_edge_is_the_single_queries() {
        // Query cells wider and narrower than a unit, the edge on either side of the origin.
        for sigma in [10.0, 0.02] {
            let terrain = VectorTerrain::new(vec![Gaussian::round(DVec2::new(50.0, 50.0), sigma, 1.0)]);
            let query = terrain.query().unwrap();
            let edge = f64::from(1u32 << 30) * ANCHOR_CELLS * query.cell;
            for (side, scale) in [(1.0, 1.0 - 1e-13), (1.0, 1.0 + 1e-13), (-1.0, 1.0 - 1e-13), (-1.0, 1.0 + 1e-13)] {
                let mut row: Vec<DVec2> = (0..100).map(|i| DVec2::new(f64::from(i) * 0.5 + 25.0, 50.0)).collect();
                row.push(DVec2::new(query.origin.x + side * edge * scale, 50.0));
                assert_eq!(query.in_lattice(row[100]), scale < 1.0);
                let single: Vec<f64> = row.iter().map(|&p| query.elevation(p)).collect();
                assert_eq!(query.elevations(&row), single, "σ {sigma}, {side} × {scale}");
                assert!(single[50] > 0.5);
            }
        }
    }

    /// Every point whose y differs from the point before's is found, in order, whatever the
    /// runs' lengths (−0 and +0 are one y).
    #[test]
    fn changes_of_y_finds_every_change() {
        let check = |points: &[DVec2], what: &str| {
            let want: Vec<usize> = (1..points.len()).filter(|&k| points[k].y != points[k - 1].y).collect();
            assert_eq!(changes_of_y(points).collect::<Vec<_>>(), want, "{what}");
        };
        for len in [0_u32, 1, 2, 63, 64, 65, 129, 300] {
            for every in [1, 2, 3, 7, 64, 65, 1000] {
                let points: Vec<DVec2> = (0..len).map(|k| DVec2::new(0.0, f64::from(k / every))).collect();
                check(&points, &format!("{len} points, rows of {every}"));
            }
        }
        // Runs of every length from 1 to 40, then 1 to 40 again, and a run across −0 and +0.
        let runs = (1..=40).chain(1..=40).enumerate().flat_map(|(r, n)| std::iter::repeat_n(r as f64, n));
        check(&runs.map(|y| DVec2::new(1.0, y)).collect::<Vec<_>>(), "runs of 1 to 40");
        let zeros = [-1.0, -0.0, -0.0, 0.0, 0.0, -0.0, 1.0].map(|y| DVec2::new(0.0, y));
        assert_eq!(changes_of_y(&zeros).collect::<Vec<_>>(), [1, 6]);
    }

    /// The search from a guess finds the partition point whatever the guess.
    #[test]
    fn partition_near_finds_the_partition_point() {
        let xs: Vec<f64> = (0..300).map(|k| f64::from(k * k % 1000) * 0.5).collect::<Vec<_>>();
        let mut xs = xs;
        xs.sort_by(f64::total_cmp);
        for target in [-1.0, 0.0, 3.5, 100.0, 250.0, 499.0, 600.0] {
            let want = xs.partition_point(|&x| x < target);
            for guess in [0, 1, 2, want.saturating_sub(3), want, want + 2, 150, 299, 300, 5000] {
                assert_eq!(partition_near(&xs, guess, |x| x < target), want, "target {target} guess {guess}");
            }
        }
        assert_eq!(partition_near(&[], 3, |x| x < 1.0), 0);
    }

    /// The box test is exact on the axes of a round support and never refuses a box holding a
    /// point of the support.
    /// A box's candidates are exactly the Gaussians whose reach boxes meet it, in index order,
    /// whether the box scans its y window or walks the hierarchy; the window is the tightest run
    /// of indices that holds them, stretched by a wide Gaussian in the middle of the order.
    #[test]
    fn candidates_are_the_supports_that_meet_the_box() {
        let fixture = relief_fixtures::random_terrain(2_000, 1000.0, 16.0, 4);
        let mut primitives: Vec<Gaussian> = fixture
            .primitives
            .iter()
            .map(|g| Gaussian {
                center: g.center,
                sigma: g.sigma,
                theta: g.theta,
                amplitude: g.amplitude,
                beta: g.beta,
            })
            .collect();
        primitives.push(Gaussian::round(DVec2::new(300.0, 480.0), 150.0, 10.0));
        let query = VectorTerrain::new(primitives).query().unwrap();
        let reach: Vec<(DVec2, DVec2)> = query.items[..query.gaussians].iter().map(Item::reach).collect();
        let wide = reach.iter().map(|(lo, hi)| hi.y - lo.y).fold(0.0, f64::max);
        assert!(wide > 800.0, "the wide Gaussian reaches {wide}");
        let row = |y0: f64, y1: f64| (DVec2::new(0.0, y0), DVec2::new(1000.0, y1));
        let point = |x: f64, y: f64| (DVec2::new(x, y), DVec2::new(x, y));
        let x_span = reach.iter().map(|(_, hi)| hi.x).fold(f64::MIN, f64::max)
            - reach.iter().map(|(lo, _)| lo.x).fold(f64::MAX, f64::min);
        assert_eq!(query.x_span, x_span);
        // A band from the first Gaussian's top: it still meets that Gaussian.
        let top = reach[0].1.y;
        let quarter = (DVec2::new(100.0, 300.0), DVec2::new(100.0 + x_span / WINDOW_SHARE, 340.0));
        let boxes = [row(10.0, 25.0), row(500.0, 500.0), row(930.0, 946.0), row(-80.0, -60.0), row(top, top + 5.0)];
        let boxes = [boxes.as_slice(), &[row(1e4, 1e4 + 1.0), quarter]].concat();
        let narrow = (DVec2::new(100.0, 300.0), DVec2::new(99.0 + x_span / WINDOW_SHARE, 340.0));
        let points = [point(310.0, 20.0), point(640.0, 955.0), point(300.0, 480.0), point(5e3, 5e3), narrow];
        for (k, &(lo, hi)) in boxes.iter().chain(&points).enumerate() {
            let meets = |(a, b): &(DVec2, DVec2)| a.x <= hi.x && b.x >= lo.x && a.y <= hi.y && b.y >= lo.y;
            let expected: Vec<u32> = (0..reach.len()).filter(|&i| meets(&reach[i])).map(|i| i as u32).collect();
            assert_eq!(query.candidates(lo, hi), expected, "box {k}");
            assert_eq!(query.scans(lo, hi), k < boxes.len(), "box {k}");
            let first = reach.iter().position(|(_, top)| top.y >= lo.y).unwrap_or(reach.len());
            let last = reach.iter().rposition(|(bottom, _)| bottom.y <= hi.y).map_or(0, |i| i + 1).max(first);
            assert_eq!(query.window(lo.y, hi.y), first..last, "box {k}");
        }
        // The wide Gaussian sits in the middle of the order and keeps the windows around it long.
        assert!(query.window(940.0, 946.0).len() > reach.len() / 3);
    }

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
