use std::sync::OnceLock;

use glam::{DVec2, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::ploc::{PlocBuilder, PlocSearchDistance, SortPrecision};
use rayon::prelude::*;
use relief_tin::poisson_sampling::{Rect, RingIndex};
use serde::{Deserialize, Serialize};

use crate::ContoursError;
use crate::geometry::{SegmentIndex, segments_touch};
use crate::levels::check_levels;

/// One iso-contour: a polyline at constant height.
///
/// Closed contours run counter-clockwise around higher ground (clockwise around a pit); the
/// closing segment from the last point back to the first is implicit. Open contours end on the
/// mesh boundary or at no-data.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Contour {
    /// Index of this contour's level in [`ContourSet::levels`].
    pub level: u32,
    /// Its height.
    pub height: f64,
    /// Vertices.
    pub points: Vec<DVec2>,
    /// Whether the last point joins the first.
    pub closed: bool,
}

impl Contour {
    /// The signed area (> 0 counter-clockwise); 0 for open contours.
    ///
    /// Computed relative to the first vertex, so a tiny loop far from the origin (a contour around
    /// a single node whose height equals the level) keeps its true sign instead of drowning in
    /// the cancellation of large cross products.
    pub fn signed_area(&self) -> f64 {
        if !self.closed || self.points.is_empty() {
            return 0.0;
        }
        let o = self.points[0];
        let n = self.points.len();
        0.5 * (1..n.saturating_sub(1)).map(|i| (self.points[i] - o).perp_dot(self.points[i + 1] - o)).sum::<f64>()
    }

    /// Whether a closed contour runs counter-clockwise (higher ground inside).
    pub fn is_counter_clockwise(&self) -> bool {
        self.signed_area() > 0.0
    }

    /// The segments, including the closing one of a closed contour.
    pub fn segments(&self) -> impl Iterator<Item = [DVec2; 2]> + '_ {
        let n = self.points.len();
        let count = if self.closed { n } else { n.saturating_sub(1) };
        (0..count).map(move |i| [self.points[i], self.points[(i + 1) % n]])
    }

    /// Total length.
    pub fn length(&self) -> f64 {
        self.segments().map(|[a, b]| a.distance(b)).sum()
    }

    /// Bounding box.
    pub fn bounds(&self) -> Rect {
        Rect::bounding(&self.points)
    }
}

/// A set of contours with the tree of their nesting: each closed contour's parent is the innermost
/// closed contour containing it (open contours have neither parent nor children).
///
/// Serialises as levels plus contours; the tree is rebuilt (and checked) on load.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "ContourSetRepr", into = "ContourSetRepr")]
pub struct ContourSet {
    levels: Vec<f64>,
    contours: Vec<Contour>,
    parent: Vec<Option<u32>>,
    children: Vec<Vec<u32>>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ContourSetRepr {
    levels: Vec<f64>,
    contours: Vec<Contour>,
}

impl TryFrom<ContourSetRepr> for ContourSet {
    type Error = ContoursError;
    fn try_from(r: ContourSetRepr) -> Result<Self, ContoursError> {
        let set = ContourSet::new(r.levels, r.contours)?;
        set.check_invariants()?;
        Ok(set)
    }
}

impl From<ContourSet> for ContourSetRepr {
    fn from(s: ContourSet) -> Self {
        Self { levels: s.levels, contours: s.contours }
    }
}

impl ContourSet {
    /// Builds the nesting tree of `contours` (whose `level` index into `levels`).
    ///
    /// # Errors
    /// [`ContoursError::InvalidLevels`] for unsorted levels, [`ContoursError::Invariant`] for a
    /// contour whose level index or height disagrees with `levels`, or a degenerate closed contour.
    pub fn new(levels: Vec<f64>, contours: Vec<Contour>) -> Result<Self, ContoursError> {
        check_levels(&levels)?;
        for (k, c) in contours.iter().enumerate() {
            if levels.get(c.level as usize) != Some(&c.height) {
                return Err(ContoursError::Invariant(format!(
                    "contour {k} has level {} / height {} not in the level list",
                    c.level, c.height
                )));
            }
            if c.points.iter().any(|p| !p.is_finite()) || c.points.len() < if c.closed { 3 } else { 2 } {
                return Err(ContoursError::Invariant(format!("contour {k} has too few or non-finite points")));
            }
        }
        let parent = nesting(&contours);
        let mut children = vec![Vec::new(); contours.len()];
        for (k, p) in parent.iter().enumerate() {
            if let Some(p) = p {
                children[*p as usize].push(k as u32);
            }
        }
        Ok(Self { levels, contours, parent, children })
    }

    /// The contour levels (heights), ascending.
    pub fn levels(&self) -> &[f64] {
        &self.levels
    }

    /// All contours.
    pub fn contours(&self) -> &[Contour] {
        &self.contours
    }

    /// Number of contours.
    pub fn len(&self) -> usize {
        self.contours.len()
    }

    /// Whether there are no contours.
    pub fn is_empty(&self) -> bool {
        self.contours.is_empty()
    }

    /// The innermost closed contour containing contour `k`.
    pub fn parent(&self, k: usize) -> Option<usize> {
        self.parent[k].map(|p| p as usize)
    }

    /// Contours whose parent is `k`.
    pub fn children(&self, k: usize) -> impl Iterator<Item = usize> + '_ {
        self.children[k].iter().map(|&c| c as usize)
    }

    /// Contours with no parent.
    pub fn roots(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.contours.len()).filter(|&k| self.parent[k].is_none())
    }

    /// Total number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.contours.iter().map(|c| c.points.len()).sum()
    }

    /// Replaces the geometry (same count, levels and closedness) and rebuilds the tree.
    pub(crate) fn with_geometry(&self, points: Vec<Vec<DVec2>>) -> Result<Self, ContoursError> {
        let contours = self.contours.iter().zip(points).map(|(c, p)| Contour { points: p, ..c.clone() }).collect();
        Self::new(self.levels.clone(), contours)
    }

    /// Checks the structure: no two segments anywhere touch or cross (except consecutive segments
    /// of one contour at their shared vertex), closed contours are simple, and each parent is the
    /// innermost closed contour containing its child.
    ///
    /// # Errors
    /// [`ContoursError::Invariant`] describing the first violation.
    pub fn check_invariants(&self) -> Result<(), ContoursError> {
        if let Some((a, b)) = first_contact(&self.contours) {
            return Err(ContoursError::Invariant(format!("contours {a} and {b} touch or cross")));
        }
        let expected = nesting(&self.contours);
        if let Some(k) = (0..self.contours.len()).find(|&k| expected[k] != self.parent[k]) {
            return Err(ContoursError::Invariant(format!(
                "contour {k} has parent {:?}, expected {:?}",
                self.parent[k], expected[k]
            )));
        }
        Ok(())
    }

    /// Whether the set nests strictly by level, as a terrain without depressions must: every
    /// closed contour is counter-clockwise and its parent lies exactly one level below (roots on
    /// the lowest level present).
    ///
    /// # Errors
    /// The index of the first contour that breaks the rule.
    pub fn nests_by_level(&self) -> Result<(), usize> {
        let lowest = self.contours.iter().map(|c| c.level).min().unwrap_or(0);
        for (k, c) in self.contours.iter().enumerate().filter(|(_, c)| c.closed) {
            let ok = c.is_counter_clockwise()
                && match self.parent[k] {
                    Some(p) => self.contours[p as usize].level + 1 == c.level,
                    None => c.level == lowest,
                };
            if !ok {
                return Err(k);
            }
        }
        Ok(())
    }
}

/// Parent of every closed contour: the smallest closed contour containing one of its points.
/// Contours never cross, so one point decides containment.
///
/// O(n log n) in the number of rings: a bounding-volume hierarchy over the closed rings' boxes
/// (obvhs) gives, for each ring's first point, only the rings whose boxes hold it; those larger
/// than the ring are tried smallest first with an exact point-in-ring test, each ring's edge index
/// built the first time it is tried (most rings are never anyone's candidate).
fn nesting(contours: &[Contour]) -> Vec<Option<u32>> {
    let closed: Vec<usize> =
        (0..contours.len()).filter(|&k| contours[k].closed && contours[k].points.len() >= 3).collect();
    let mut parent = vec![None; contours.len()];
    if closed.len() < 2 {
        return parent;
    }
    let area: Vec<f64> = closed.iter().map(|&k| contours[k].signed_area().abs()).collect();
    let bounds: Vec<Rect> = closed.iter().map(|&k| contours[k].bounds()).collect();
    let boxes = RingBoxes::new(&bounds);
    let rings: Vec<OnceLock<RingIndex>> = closed.iter().map(|_| OnceLock::new()).collect();
    let ring = |j: usize| rings[j].get_or_init(|| RingIndex::new(&contours[closed[j]].points));
    let found: Vec<Option<u32>> = (0..closed.len())
        .into_par_iter()
        .map(|k| {
            let probe = contours[closed[k]].points[0];
            let mut candidates = boxes.holding(probe, |j| j != k && area[j] > area[k] && bounds[j].contains(probe));
            candidates.sort_unstable_by(|&a, &b| area[a].total_cmp(&area[b]).then(a.cmp(&b)));
            candidates.into_iter().find(|&j| ring(j).contains(probe)).map(|j| closed[j] as u32)
        })
        .collect();
    for (k, p) in closed.iter().zip(found) {
        parent[*k] = p;
    }
    parent
}

/// The boxes of the closed rings in a bounding-volume hierarchy, for "which boxes hold this
/// point" queries. The hierarchy works in f32 about the boxes' common corner; each box is widened
/// by a few f32 steps so that no box that holds a point in f64 is missed (the caller re-checks
/// in f64).
struct RingBoxes {
    origin: DVec2,
    bvh: obvhs::bvh2::Bvh2,
}

impl RingBoxes {
    fn new(bounds: &[Rect]) -> Self {
        let origin = bounds.iter().fold(DVec2::INFINITY, |o, b| o.min(b.min));
        let aabbs: Vec<Aabb> = bounds
            .iter()
            .map(|b| {
                let (lo, hi) = (b.min - origin, b.max - origin);
                let pad = 4.0 * f64::from(f32::EPSILON) * hi.abs().max_element().max(1.0);
                Aabb::new(
                    Vec3A::new((lo.x - pad) as f32, (lo.y - pad) as f32, 0.0),
                    Vec3A::new((hi.x + pad) as f32, (hi.y + pad) as f32, 0.0),
                )
            })
            .collect();
        let indices = (0..aabbs.len() as u32).collect();
        let bvh = PlocBuilder::with_capacity(aabbs.len()).build(
            PlocSearchDistance::Minimum,
            &aabbs,
            indices,
            SortPrecision::U64,
            0,
        );
        Self { origin, bvh }
    }

    /// The rings whose boxes hold `p` and that pass `keep`.
    fn holding(&self, p: DVec2, keep: impl Fn(usize) -> bool) -> Vec<usize> {
        let q = p - self.origin;
        let mut out = Vec::new();
        self.bvh.point_traverse(Vec3A::new(q.x as f32, q.y as f32, 0.0), |bvh, node| {
            let node = &bvh.nodes[node as usize];
            let first = node.first_index as usize;
            for &j in &bvh.primitive_indices[first..first + node.prim_count as usize] {
                if keep(j as usize) {
                    out.push(j as usize);
                }
            }
            true
        });
        out
    }
}

/// The first pair of contours (possibly the same one twice) with segments that touch or cross,
/// ignoring consecutive segments of one contour at their shared vertex.
pub(crate) fn first_contact(contours: &[Contour]) -> Option<(usize, usize)> {
    let mut segs = Vec::new();
    let mut owner = Vec::new();
    for (k, c) in contours.iter().enumerate() {
        for (i, s) in c.segments().enumerate() {
            segs.push(s);
            owner.push((k as u32, i as u32));
        }
    }
    let index = SegmentIndex::new(&segs);
    let adjacent = |a: usize, b: usize| {
        let ((ka, ia), (kb, ib)) = (owner[a], owner[b]);
        if ka != kb {
            return false;
        }
        let c = &contours[ka as usize];
        let n = c.segments().count() as u32;
        ib == ia + 1 || ia == ib + 1 || (c.closed && ((ia == 0 && ib == n - 1) || (ib == 0 && ia == n - 1)))
    };
    index.pairs().into_par_iter().find_map_first(|(a, b)| {
        let ([p, q], [r, s]) = (segs[a], segs[b]);
        let hit = if adjacent(a, b) { crate::geometry::folds_back(p, q, r, s) } else { segments_touch(p, q, r, s) };
        hit.then(|| (owner[a].0 as usize, owner[b].0 as usize))
    })
}
