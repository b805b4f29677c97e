use glam::DVec2;
use serde::{Deserialize, Serialize};

use crate::PolygonError;

/// An axis-aligned rectangle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rect {
    /// Minimum corner.
    pub min: DVec2,
    /// Maximum corner.
    pub max: DVec2,
}

impl Rect {
    /// The rectangle with corners `min` and `max`.
    pub fn new(min: DVec2, max: DVec2) -> Self {
        Self { min, max }
    }

    /// `max − min`.
    pub fn size(&self) -> DVec2 {
        self.max - self.min
    }

    /// Width times height.
    pub fn area(&self) -> f64 {
        let s = self.size();
        s.x * s.y
    }

    /// Whether `p` lies inside or on the border.
    #[inline]
    pub fn contains(&self, p: DVec2) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }

    /// The rectangle grown by `margin` on every side.
    #[must_use]
    pub fn grow(&self, margin: f64) -> Rect {
        Rect::new(self.min - DVec2::splat(margin), self.max + DVec2::splat(margin))
    }

    /// Smallest rectangle containing both.
    #[must_use]
    pub fn union(&self, other: &Rect) -> Rect {
        Rect::new(self.min.min(other.min), self.max.max(other.max))
    }

    /// Bounding box of a point set (inverted, i.e. empty, when `points` is empty).
    pub fn bounding(points: &[DVec2]) -> Rect {
        points
            .iter()
            .fold(Rect::new(DVec2::INFINITY, DVec2::NEG_INFINITY), |r, &p| Rect::new(r.min.min(p), r.max.max(p)))
    }

    /// Finite with `min < max` on both axes.
    pub fn is_valid(&self) -> bool {
        self.min.is_finite() && self.max.is_finite() && self.min.x < self.max.x && self.min.y < self.max.y
    }

    /// Euclidean distance from `p` to the rectangle (0 inside).
    pub fn distance(&self, p: DVec2) -> f64 {
        (p - p.clamp(self.min, self.max)).length()
    }
}

/// Sign of the turn `a → b → c`: > 0 counter-clockwise, < 0 clockwise, exactly 0 when collinear
/// (Shewchuk's adaptive-precision predicate).
#[inline]
pub fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    let k = |p: DVec2| robust::Coord { x: p.x, y: p.y };
    robust::orient2d(k(a), k(b), k(c))
}

/// One step of the crossing-number test: does the ray from `p` toward +x cross edge `a → b`?
/// Half-open in y so a ray through a vertex counts once. The indexed and brute-force tests both
/// call this, so they agree bit for bit.
#[inline]
fn crosses_ray(p: DVec2, a: DVec2, b: DVec2) -> bool {
    (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y)
}

/// Squared distance from `p` to segment `a–b`.
#[inline]
pub fn segment_distance_sq(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 { ((p - a).dot(ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (a + t * ab - p).length_squared()
}

/// Whether closed segments `a–b` and `c–d` share at least one point (exact predicates).
pub fn segments_touch(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let (o1, o2) = (orient(a, b, c), orient(a, b, d));
    let (o3, o4) = (orient(c, d, a), orient(c, d, b));
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    let on = |p: DVec2, q: DVec2, r: DVec2| {
        // r is collinear with p–q: does it lie within their bounding box?
        r.x >= p.x.min(q.x) && r.x <= p.x.max(q.x) && r.y >= p.y.min(q.y) && r.y <= p.y.max(q.y)
    };
    (o1 == 0.0 && on(a, b, c)) || (o2 == 0.0 && on(a, b, d)) || (o3 == 0.0 && on(c, d, a)) || (o4 == 0.0 && on(c, d, b))
}

/// Twice the signed area of a ring (positive when counter-clockwise): the shoelace sum
/// `Σ pᵢ × pᵢ₊₁` in ring order. The one implementation behind [`signed_area`] and
/// [`Polygon::area`].
fn twice_signed_area<P: Copy + Into<DVec2>>(ring: &[P]) -> f64 {
    let n = ring.len();
    (0..n).map(|i| ring[i].into().perp_dot(ring[(i + 1) % n].into())).sum()
}

/// Signed area of the closed ring `ring` (the closing edge from the last point to the first is
/// implied): `½·Σ pᵢ × pᵢ₊₁`, positive when the ring runs counter-clockwise (y up), negative
/// clockwise. Takes `DVec2` or `[f64; 2]` points, so plain coordinate lists need no copy.
///
/// ```
/// use glam::DVec2;
/// use relief_poisson_sampling::signed_area;
///
/// let square = [DVec2::ZERO, DVec2::new(2.0, 0.0), DVec2::new(2.0, 2.0), DVec2::new(0.0, 2.0)];
/// assert_eq!(signed_area(&square), 4.0);
/// assert_eq!(signed_area(&[[0.0, 0.0], [0.0, 2.0], [2.0, 0.0]]), -2.0);
/// ```
pub fn signed_area<P: Copy + Into<DVec2>>(ring: &[P]) -> f64 {
    0.5 * twice_signed_area(ring)
}

/// Horizontal bands over a set of edges: a point-in-polygon query tests only the edges whose
/// y-range overlaps the query's band, which is exact (the same [`crosses_ray`] on the same edges
/// that could cross) and O(edges per band) instead of O(all edges).
#[derive(Debug, Clone, PartialEq)]
struct EdgeBands {
    y0: f64,
    y1: f64,
    inv_h: f64,
    bands: usize,
    offsets: Vec<u32>,
    /// The rings' vertices, each ring closed by repeating its first: edge `i` runs from
    /// `points[i]` to `points[i + 1]`.
    points: Vec<DVec2>,
    /// Edge indices, band by band (an edge in every band it spans).
    edges: Vec<u32>,
}

impl EdgeBands {
    fn new(rings: &[&[DVec2]], y0: f64, y1: f64) -> Self {
        let mut points = Vec::with_capacity(rings.iter().map(|r| r.len() + 1).sum());
        let mut starts = Vec::new();
        for ring in rings.iter().filter(|r| !r.is_empty()) {
            starts.extend((points.len()..points.len() + ring.len()).map(|i| i as u32));
            points.extend_from_slice(ring);
            points.push(ring[0]);
        }
        let edge = |i: u32| [points[i as usize], points[i as usize + 1]];
        // An edge is stored in every band it spans: one band per edge, unless the rings wind up
        // and down so much (a crinkly contour) that the copies would pass 3 per edge.
        let travel: f64 = starts.iter().map(|&i| (edge(i)[0].y - edge(i)[1].y).abs()).sum();
        let (total, height) = (starts.len(), y1 - y0);
        let by_travel = if travel > 0.0 { 3.0 * total as f64 * height / travel } else { f64::INFINITY };
        let bands = (total as f64).min(by_travel).clamp(1.0, f64::from(1u32 << 16)) as usize;
        let inv_h = bands as f64 / height;
        let band_of = |y: f64| (((y - y0) * inv_h) as usize).min(bands - 1);
        let span = |i: u32| {
            let [a, b] = edge(i);
            band_of(a.y.min(b.y))..=band_of(a.y.max(b.y))
        };
        let mut counts = vec![0u32; bands + 1];
        for &i in &starts {
            for band in span(i) {
                counts[band + 1] += 1;
            }
        }
        for i in 0..bands {
            counts[i + 1] += counts[i];
        }
        let mut fill = counts.clone();
        let mut edges = vec![0u32; counts[bands] as usize];
        for &i in &starts {
            for band in span(i) {
                edges[fill[band] as usize] = i;
                fill[band] += 1;
            }
        }
        Self { y0, y1, inv_h, bands, offsets: counts, points, edges }
    }

    #[inline]
    fn contains(&self, p: DVec2) -> bool {
        if !(p.y >= self.y0 && p.y <= self.y1) {
            return false;
        }
        let band = (((p.y - self.y0) * self.inv_h) as usize).min(self.bands - 1);
        let (lo, hi) = (self.offsets[band] as usize, self.offsets[band + 1] as usize);
        let crosses = |&i: &u32| crosses_ray(p, self.points[i as usize], self.points[i as usize + 1]);
        self.edges[lo..hi].iter().filter(|i| crosses(i)).count() % 2 == 1
    }
}

/// Fast even-odd point-in-ring queries on any closed ring (validated or not): the ring's edges in
/// horizontal bands, so each query tests only the edges near its height — the same exact test
/// [`Polygon::contains`] uses. For rings known to be simple by construction (e.g. extracted
/// contours), where [`Polygon::new`]'s validation would be wasted work.
#[derive(Debug, Clone, PartialEq)]
pub struct RingIndex {
    bounds: Rect,
    bands: EdgeBands,
}

impl RingIndex {
    /// Indexes the closed ring `ring` (the closing edge from the last point to the first is implied).
    pub fn new(ring: &[DVec2]) -> Self {
        let bounds = Rect::bounding(ring);
        Self { bounds, bands: EdgeBands::new(&[ring], bounds.min.y, bounds.max.y) }
    }

    /// The ring's bounding rectangle.
    pub fn bounds(&self) -> Rect {
        self.bounds
    }

    /// Whether `p` is inside the ring by the even-odd rule (points on the boundary may go either
    /// way, consistently with [`Polygon::contains`]).
    pub fn contains(&self, p: DVec2) -> bool {
        !self.bands.edges.is_empty() && self.bands.contains(p)
    }
}

/// A uniform grid binning segments by the cells they pass through (a conservative supercover), for
/// distance and intersection queries that only look at nearby segments.
#[derive(Debug, Clone)]
pub struct SegmentIndex {
    origin: DVec2,
    cell: f64,
    w: usize,
    h: usize,
    offsets: Vec<u32>,
    items: Vec<u32>,
}

impl SegmentIndex {
    /// Bins `segments` over `bounds` with square cells of side `cell` (enlarged so the grid has at
    /// most `max_cells` cells).
    pub fn new(segments: &[[DVec2; 2]], bounds: Rect, cell: f64, max_cells: usize) -> Self {
        let size = bounds.size().max(DVec2::splat(f64::MIN_POSITIVE));
        let mut cell = cell.max(f64::MIN_POSITIVE);
        while (size.x / cell).ceil() * (size.y / cell).ceil() > max_cells as f64 {
            cell *= 1.5;
        }
        let w = ((size.x / cell).ceil() as usize).max(1);
        let h = ((size.y / cell).ceil() as usize).max(1);
        let mut grid = Self { origin: bounds.min, cell, w, h, offsets: Vec::new(), items: Vec::new() };
        let mut offsets = vec![0u32; w * h + 1];
        for s in segments {
            grid.for_cells(s[0], s[1], |c| offsets[c + 1] += 1);
        }
        for i in 0..w * h {
            offsets[i + 1] += offsets[i];
        }
        let mut fill = offsets.clone();
        let mut items = vec![0u32; offsets[w * h] as usize];
        for (k, s) in segments.iter().enumerate() {
            grid.for_cells(s[0], s[1], |c| {
                items[fill[c] as usize] = k as u32;
                fill[c] += 1;
            });
        }
        grid.offsets = offsets;
        grid.items = items;
        grid
    }

    fn col(&self, x: f64) -> usize {
        (((x - self.origin.x) / self.cell).floor().max(0.0) as usize).min(self.w - 1)
    }

    fn row(&self, y: f64) -> usize {
        (((y - self.origin.y) / self.cell).floor().max(0.0) as usize).min(self.h - 1)
    }

    /// Calls `f` for every cell the segment passes through (a conservative supercover: a cell
    /// touched within rounding error is included).
    fn for_cells(&self, a: DVec2, b: DVec2, mut f: impl FnMut(usize)) {
        let eps = 1e-9 * self.cell;
        let (r0, r1) = (self.row(a.y.min(b.y) - eps), self.row(a.y.max(b.y) + eps));
        for r in r0..=r1 {
            // Clip the segment to this row's y-band and take the x-range of the clipped piece.
            let band_lo = self.origin.y + r as f64 * self.cell;
            let band_hi = band_lo + self.cell;
            let (ylo, yhi) = (a.y.min(b.y).max(band_lo), a.y.max(b.y).min(band_hi));
            let x_at = |y: f64| if a.y == b.y { a.x } else { a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y) };
            let (xa, xb) = if a.y == b.y { (a.x, b.x) } else { (x_at(ylo), x_at(yhi)) };
            let (c0, c1) = (self.col(xa.min(xb) - eps), self.col(xa.max(xb) + eps));
            for c in c0..=c1 {
                f(r * self.w + c);
            }
        }
    }

    /// Calls `f` with the ids of segments binned in cells overlapping `[lo, hi]` (a segment may be
    /// seen more than once) until `f` returns true; returns whether it did.
    pub fn for_each_near(&self, lo: DVec2, hi: DVec2, mut f: impl FnMut(u32) -> bool) -> bool {
        let (c0, c1) = (self.col(lo.x), self.col(hi.x));
        let (r0, r1) = (self.row(lo.y), self.row(hi.y));
        for r in r0..=r1 {
            for c in c0..=c1 {
                let k = r * self.w + c;
                for &s in &self.items[self.offsets[k] as usize..self.offsets[k + 1] as usize] {
                    if f(s) {
                        return true;
                    }
                }
            }
        }
        false
    }

    /// Segment ids binned in each cell, one slice per cell.
    pub fn cells(&self) -> impl Iterator<Item = &[u32]> {
        (0..self.w * self.h).map(|k| &self.items[self.offsets[k] as usize..self.offsets[k + 1] as usize])
    }
}

/// A simple polygon with optional holes: the exterior ring is stored counter-clockwise, holes
/// clockwise, without a repeated closing vertex.
///
/// Validated at construction — finite coordinates, at least three distinct vertices per ring,
/// non-zero area, no ring touching or crossing itself or another ring, every hole strictly inside
/// the exterior and outside the other holes — so containment queries cannot be ambiguous.
/// Point-in-polygon runs in O(edges in one horizontal band), not O(all edges).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(try_from = "PolygonRepr", into = "PolygonRepr")]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct Polygon {
    exterior: Vec<DVec2>,
    holes: Vec<Vec<DVec2>>,
    bounds: Rect,
    area: f64,
    bands: EdgeBands,
}

impl PartialEq for Polygon {
    fn eq(&self, other: &Self) -> bool {
        self.exterior == other.exterior && self.holes == other.holes
    }
}

/// The JSON form of a [`Polygon`]: an exterior ring and optional holes, `[x, y]` vertices,
/// closed implicitly.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema), schemars(rename = "Polygon"))]
struct PolygonRepr {
    /// The exterior ring (any orientation; a repeated closing vertex is dropped).
    #[cfg_attr(feature = "schemars", schemars(with = "Vec<[f64; 2]>"))]
    exterior: Vec<DVec2>,
    /// Holes, strictly inside the exterior and outside each other.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    #[cfg_attr(feature = "schemars", schemars(with = "Vec<Vec<[f64; 2]>>"))]
    holes: Vec<Vec<DVec2>>,
}

impl TryFrom<PolygonRepr> for Polygon {
    type Error = PolygonError;
    fn try_from(r: PolygonRepr) -> Result<Self, PolygonError> {
        Polygon::new(r.exterior, r.holes)
    }
}

impl From<Polygon> for PolygonRepr {
    fn from(p: Polygon) -> Self {
        Self { exterior: p.exterior, holes: p.holes }
    }
}

/// Drops repeated consecutive vertices (and a closing copy of the first), checks finiteness and size.
fn clean_ring(ring: Vec<DVec2>, index: usize) -> Result<Vec<DVec2>, PolygonError> {
    if let Some((vertex, p)) = ring.iter().enumerate().find(|(_, p)| !p.is_finite()) {
        return Err(PolygonError::NonFiniteVertex { ring: index, vertex, x: p.x, y: p.y });
    }
    let mut out: Vec<DVec2> = Vec::with_capacity(ring.len());
    for p in ring {
        if out.last() != Some(&p) {
            out.push(p);
        }
    }
    while out.len() > 1 && out.first() == out.last() {
        out.pop();
    }
    if out.len() < 3 {
        return Err(PolygonError::TooFewVertices { ring: index, count: out.len() });
    }
    Ok(out)
}

/// Rejects rings that touch or cross themselves or each other, using a segment grid so typical
/// inputs cost O(edges) rather than O(edges²).
fn check_simple(rings: &[&[DVec2]]) -> Result<(), PolygonError> {
    let mut segments = Vec::new();
    let mut owner = Vec::new();
    for (r, ring) in rings.iter().enumerate() {
        for e in 0..ring.len() {
            segments.push([ring[e], ring[(e + 1) % ring.len()]]);
            owner.push((r, e));
        }
    }
    let bounds = segments.iter().fold(Rect::bounding(&[]), |b, s| b.union(&Rect::bounding(s)));
    let total_len: f64 = segments.iter().map(|[a, b]| (*b - *a).length()).sum();
    let cell = 2.0 * total_len / segments.len() as f64;
    let grid = SegmentIndex::new(&segments, bounds, cell, 4 * segments.len() + 16);
    for cell in grid.cells() {
        for (x, &s) in cell.iter().enumerate() {
            for &t in &cell[x + 1..] {
                let ((ra, ea), (rb, eb)) = (owner[s as usize], owner[t as usize]);
                let [a, b] = segments[s as usize];
                let [c, d] = segments[t as usize];
                let n = rings[ra].len();
                let hit = if ra == rb && (eb == (ea + 1) % n || ea == (eb + 1) % n) {
                    // Consecutive edges share a vertex; they are only bad when they fold back
                    // onto each other.
                    let (shared, p, q) = if b == c { (b, a, d) } else { (a, b, c) };
                    orient(p, shared, q) == 0.0 && (p - shared).dot(q - shared) > 0.0
                } else {
                    segments_touch(a, b, c, d)
                };
                if hit {
                    let at = 0.25 * (a + b + c + d);
                    let (first, second) =
                        if (ra, ea) <= (rb, eb) { ((ra, ea), (rb, eb)) } else { ((rb, eb), (ra, ea)) };
                    return Err(PolygonError::SelfIntersection {
                        ring_a: first.0,
                        edge_a: first.1,
                        ring_b: second.0,
                        edge_b: second.1,
                        at,
                    });
                }
            }
        }
    }
    Ok(())
}

/// Whether `p` is inside the closed ring `ring` by the even-odd rule, scanning every edge: O(edges),
/// no index and no validation, for a ring tested a few times or one known to be simple. The same
/// exact test as [`Polygon::contains`] and [`RingIndex::contains`] (they share one crossing
/// predicate), so all three agree bit for bit, points on the boundary included. Takes `DVec2` or
/// `[f64; 2]` points.
///
/// ```
/// use glam::DVec2;
/// use relief_poisson_sampling::ring_contains;
///
/// let triangle = [[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]];
/// assert!(ring_contains(&triangle, DVec2::new(1.0, 1.0)));
/// assert!(!ring_contains(&triangle, DVec2::new(3.0, 3.0)));
/// ```
pub fn ring_contains<P: Copy + Into<DVec2>>(ring: &[P], p: DVec2) -> bool {
    let n = ring.len();
    (0..n).filter(|&i| crosses_ray(p, ring[i].into(), ring[(i + 1) % n].into())).count() % 2 == 1
}

impl Polygon {
    /// Builds and validates a polygon. Rings may be given in either orientation, closed or open.
    ///
    /// # Errors
    /// A [`PolygonError`] naming the ring (0 = exterior) and vertex or edges at fault.
    pub fn new(exterior: Vec<DVec2>, holes: Vec<Vec<DVec2>>) -> Result<Self, PolygonError> {
        let mut rings = Vec::with_capacity(1 + holes.len());
        rings.push(clean_ring(exterior, 0)?);
        for (k, h) in holes.into_iter().enumerate() {
            rings.push(clean_ring(h, k + 1)?);
        }
        for (r, ring) in rings.iter().enumerate() {
            let (a, b) = (ring[0], ring[1]);
            if ring[2..].iter().all(|&c| orient(a, b, c) == 0.0) {
                return Err(PolygonError::ZeroArea { ring: r });
            }
        }
        check_simple(&rings.iter().map(Vec::as_slice).collect::<Vec<_>>())?;
        for (r, ring) in rings.iter_mut().enumerate() {
            // A simple ring with three non-collinear vertices encloses area; only overflow is left.
            let a2 = twice_signed_area(ring.as_slice());
            if a2 == 0.0 || !a2.is_finite() {
                return Err(PolygonError::ZeroArea { ring: r });
            }
            // Exterior counter-clockwise, holes clockwise.
            if (a2 > 0.0) != (r == 0) {
                ring.reverse();
            }
        }
        let views: Vec<&[DVec2]> = rings.iter().map(Vec::as_slice).collect();
        for h in 1..rings.len() {
            let probe = rings[h][0];
            if !ring_contains(rings[0].as_slice(), probe) {
                return Err(PolygonError::HoleOutside { ring: h });
            }
            if (1..rings.len()).any(|o| o != h && ring_contains(rings[o].as_slice(), probe)) {
                return Err(PolygonError::HoleOutside { ring: h });
            }
        }
        let bounds = Rect::bounding(&rings[0]);
        let area = 0.5 * rings.iter().map(|r| twice_signed_area(r.as_slice())).sum::<f64>();
        let bands = EdgeBands::new(&views, bounds.min.y, bounds.max.y);
        let mut rings = rings.into_iter();
        let exterior = rings.next().unwrap_or_default();
        Ok(Self { exterior, holes: rings.collect(), bounds, area, bands })
    }

    /// A polygon without holes.
    ///
    /// # Errors
    /// As [`Polygon::new`].
    pub fn from_exterior(exterior: Vec<DVec2>) -> Result<Self, PolygonError> {
        Self::new(exterior, Vec::new())
    }

    /// The rectangle as a polygon.
    ///
    /// # Errors
    /// [`PolygonError`] if the rectangle is empty or not finite.
    pub fn rectangle(rect: Rect) -> Result<Self, PolygonError> {
        Self::from_exterior(vec![
            rect.min,
            DVec2::new(rect.max.x, rect.min.y),
            rect.max,
            DVec2::new(rect.min.x, rect.max.y),
        ])
    }

    /// A regular polygon with `sides` vertices approximating a circle.
    ///
    /// # Errors
    /// [`PolygonError`] if `sides < 3`, or `radius` is not positive and finite.
    pub fn circle(center: DVec2, radius: f64, sides: usize) -> Result<Self, PolygonError> {
        let ring = (0..sides)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / sides as f64;
                center + radius * DVec2::new(t.cos(), t.sin())
            })
            .collect();
        Self::from_exterior(ring)
    }

    /// The exterior ring, counter-clockwise.
    pub fn exterior(&self) -> &[DVec2] {
        &self.exterior
    }

    /// The holes, each clockwise.
    pub fn holes(&self) -> &[Vec<DVec2>] {
        &self.holes
    }

    /// All rings: the exterior then the holes.
    pub fn rings(&self) -> impl Iterator<Item = &[DVec2]> {
        std::iter::once(self.exterior.as_slice()).chain(self.holes.iter().map(Vec::as_slice))
    }

    /// Every edge of every ring as `[start, end]`.
    pub fn edges(&self) -> impl Iterator<Item = [DVec2; 2]> + '_ {
        self.rings().flat_map(|r| (0..r.len()).map(move |i| [r[i], r[(i + 1) % r.len()]]))
    }

    /// Bounding box of the exterior.
    pub fn bounds(&self) -> Rect {
        self.bounds
    }

    /// Enclosed area (exterior minus holes).
    pub fn area(&self) -> f64 {
        self.area
    }

    /// Whether `p` is inside (even-odd over all rings; points exactly on an edge may go either way).
    #[inline]
    pub fn contains(&self, p: DVec2) -> bool {
        self.bands.contains(p)
    }

    /// The same test by scanning every edge: O(edges), for verification.
    pub fn contains_brute_force(&self, p: DVec2) -> bool {
        self.rings().filter(|r| ring_contains(r, p)).count() % 2 == 1
    }

    /// Euclidean distance from `p` to the nearest edge, by scanning every edge.
    pub fn boundary_distance(&self, p: DVec2) -> f64 {
        self.edges().map(|[a, b]| segment_distance_sq(p, a, b)).fold(f64::INFINITY, f64::min).sqrt()
    }
}

/// A union of polygons (which may overlap): the shape of a coastline with islands, a set of ranges.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(from = "Vec<Polygon>", into = "Vec<Polygon>")]
pub struct PolygonSet {
    polygons: Vec<Polygon>,
    bounds: Rect,
}

impl From<Vec<Polygon>> for PolygonSet {
    fn from(polygons: Vec<Polygon>) -> Self {
        Self::new(polygons)
    }
}

impl From<PolygonSet> for Vec<Polygon> {
    fn from(s: PolygonSet) -> Self {
        s.polygons
    }
}

impl From<Polygon> for PolygonSet {
    fn from(p: Polygon) -> Self {
        Self::new(vec![p])
    }
}

impl PolygonSet {
    /// The union of `polygons` (an empty set contains nothing and has inverted bounds).
    pub fn new(polygons: Vec<Polygon>) -> Self {
        let bounds = polygons.iter().fold(Rect::bounding(&[]), |b, p| b.union(&p.bounds()));
        Self { polygons, bounds }
    }

    /// The member polygons.
    pub fn polygons(&self) -> &[Polygon] {
        &self.polygons
    }

    /// Bounding box of all polygons.
    pub fn bounds(&self) -> Rect {
        self.bounds
    }

    /// Sum of the polygons' areas (overlaps counted twice).
    pub fn area(&self) -> f64 {
        self.polygons.iter().map(Polygon::area).sum()
    }

    /// Whether any polygon contains `p`.
    #[inline]
    pub fn contains(&self, p: DVec2) -> bool {
        self.bounds.contains(p) && self.polygons.iter().any(|poly| poly.bounds().contains(p) && poly.contains(p))
    }

    /// Every edge of every polygon.
    pub fn edges(&self) -> impl Iterator<Item = [DVec2; 2]> + '_ {
        self.polygons.iter().flat_map(Polygon::edges)
    }

    /// The first pair of member polygons whose boundaries touch or cross, with a point near the
    /// contact, or `None` when every two boundaries are disjoint (so each pair is either nested or
    /// apart). Near-linear in the number of edges.
    pub fn first_boundary_contact(&self) -> Option<(usize, usize, DVec2)> {
        let mut rings: Vec<&[DVec2]> = Vec::new();
        let mut owner = Vec::new();
        for (k, poly) in self.polygons.iter().enumerate() {
            for ring in poly.rings() {
                rings.push(ring);
                owner.push(k);
            }
        }
        // Member polygons are valid, so any contact is between rings of different polygons.
        match check_simple(&rings) {
            Err(PolygonError::SelfIntersection { ring_a, ring_b, at, .. }) => {
                let (a, b) = (owner[ring_a], owner[ring_b]);
                Some((a.min(b), a.max(b), at))
            }
            _ => None,
        }
    }
}
