use glam::DVec2;
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
fn nesting(contours: &[Contour]) -> Vec<Option<u32>> {
    let closed: Vec<usize> = (0..contours.len()).filter(|&k| contours[k].closed).collect();
    // Extracted and smoothed contours are simple by construction: index them for point-in-ring
    // queries without re-validating them as polygons.
    let rings: Vec<Option<RingIndex>> =
        contours.par_iter().map(|c| (c.closed && c.points.len() >= 3).then(|| RingIndex::new(&c.points))).collect();
    let area: Vec<f64> = contours.iter().map(|c| c.signed_area().abs()).collect();
    let bounds: Vec<Rect> = contours.iter().map(Contour::bounds).collect();
    (0..contours.len())
        .into_par_iter()
        .map(|k| {
            if !contours[k].closed {
                return None;
            }
            let probe = contours[k].points[0];
            closed
                .iter()
                .copied()
                .filter(|&j| j != k && area[j] > area[k] && bounds[j].contains(probe))
                .filter(|&j| rings[j].as_ref().is_some_and(|r| r.contains(probe)))
                .min_by(|&a, &b| area[a].total_cmp(&area[b]).then(a.cmp(&b)))
                .map(|j| j as u32)
        })
        .collect()
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
