//! Closing contours cut open by a map's border along that border, so that the contours of a real
//! DEM (or of any map) become nested regions a regrowth can start from (the contours paper's
//! Fig. 24, regrowing the Alps from their own contours).

use glam::DVec2;
use relief_tin::poisson_sampling::Rect;

use crate::{Contour, ContourSet, ContoursError};

/// Open contours may end this far from the rectangle (as a share of its smaller side).
const END_TOLERANCE: f64 = 0.01;

/// The closing paths of all levels lie within this share of the rectangle's smaller side
/// outside it, the lowest level outermost.
const BAND: f64 = 0.005;

impl ContourSet {
    /// The set with every open contour closed along `rect`'s border.
    ///
    /// Open contours run with higher ground on their left and end on the border (as
    /// [`crate::extract_dem`] gives them), so from each end the higher ground continues
    /// counter-clockwise along the border, up to the start of the next open contour of the same
    /// level: joined that way, the pieces make counter-clockwise rings around higher ground. Each
    /// level's closing path runs just outside the rectangle, lower levels farther out, so rings of
    /// different levels never touch. Levels below `border_min` (the lowest height on the border,
    /// when known; a border sample at a level counts as above it, as in extraction) whose region
    /// covers the whole border get the rectangle itself as a ring.
    ///
    /// # Errors
    /// [`ContoursError::Invariant`] for a degenerate rectangle, an open contour that ends away from
    /// the border, or a level whose ends do not pair up.
    pub fn closed_at_border(&self, rect: Rect, border_min: Option<f64>) -> Result<ContourSet, ContoursError> {
        let size = rect.max - rect.min;
        if !(size.x > 0.0 && size.y > 0.0 && size.is_finite()) {
            return Err(ContoursError::Invariant(format!("cannot close contours along a {size} rectangle")));
        }
        let border = Border { rect, perimeter: 2.0 * (size.x + size.y) };
        let n = self.levels().len();
        let step = BAND * size.x.min(size.y) / n.max(1) as f64;
        let mut contours: Vec<Contour> = self.contours().iter().filter(|c| c.closed).cloned().collect();
        for (level, &height) in self.levels().iter().enumerate() {
            let offset = (n - level) as f64 * step;
            let open: Vec<&Contour> =
                self.contours().iter().filter(|c| !c.closed && c.level as usize == level).collect();
            let ring = |points: Vec<DVec2>| Contour { level: level as u32, height, points, closed: true };
            if open.is_empty() {
                if border_min.is_some_and(|m| height <= m) {
                    contours.push(ring(border.corners(offset).to_vec()));
                }
                continue;
            }
            for points in border.join(&open, offset)? {
                contours.push(ring(points));
            }
        }
        ContourSet::new(self.levels().to_vec(), contours)
    }
}

/// A rectangle's border, walked counter-clockwise from its lower-left corner.
struct Border {
    rect: Rect,
    perimeter: f64,
}

impl Border {
    /// Where `p` projects on the border, as the distance walked from the lower-left corner, and
    /// how far `p` lies from it.
    fn param(&self, p: DVec2) -> (f64, f64) {
        let (lo, hi) = (self.rect.min, self.rect.max);
        let (w, h) = (hi.x - lo.x, hi.y - lo.y);
        let q = p.clamp(lo, hi);
        let to_side = [q.y - lo.y, hi.x - q.x, hi.y - q.y, q.x - lo.x];
        let side = (0..4).min_by(|&a, &b| to_side[a].total_cmp(&to_side[b])).unwrap_or(0);
        let s = match side {
            0 => q.x - lo.x,
            1 => w + (q.y - lo.y),
            2 => w + h + (hi.x - q.x),
            _ => 2.0 * w + h + (hi.y - q.y),
        };
        (s % self.perimeter, p.distance(q) + to_side[side])
    }

    /// The border point at parameter `s`, pushed `offset` outward.
    fn point(&self, s: f64, offset: f64) -> DVec2 {
        let (lo, hi) = (self.rect.min - DVec2::splat(offset), self.rect.max + DVec2::splat(offset));
        let (w, h) = (self.rect.max.x - self.rect.min.x, self.rect.max.y - self.rect.min.y);
        match s {
            s if s <= w => DVec2::new(self.rect.min.x + s, lo.y),
            s if s <= w + h => DVec2::new(hi.x, self.rect.min.y + (s - w)),
            s if s <= 2.0 * w + h => DVec2::new(self.rect.max.x - (s - w - h), hi.y),
            s => DVec2::new(lo.x, self.rect.max.y - (s - 2.0 * w - h)),
        }
    }

    /// The rectangle grown by `offset`, counter-clockwise from its lower-left corner, with the
    /// parameter of each corner.
    fn corners(&self, offset: f64) -> [DVec2; 4] {
        let (lo, hi) = (self.rect.min - DVec2::splat(offset), self.rect.max + DVec2::splat(offset));
        [lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)]
    }

    /// The path just outside the border from parameter `from` counter-clockwise to `to`.
    fn path(&self, from: f64, to: f64, offset: f64) -> Vec<DVec2> {
        let (w, h) = (self.rect.max.x - self.rect.min.x, self.rect.max.y - self.rect.min.y);
        let corner_at = [w, w + h, 2.0 * w + h, self.perimeter];
        let corners = self.corners(offset);
        let span = (to - from).rem_euclid(self.perimeter);
        let mut out = vec![self.point(from, offset)];
        // Corners passed, in walking order (corner k sits at corner_at[k], the last at 0 ≡ P).
        let mut passed: Vec<(f64, DVec2)> = (0..4)
            .map(|k| ((corner_at[k] - from).rem_euclid(self.perimeter), corners[(k + 1) % 4]))
            .filter(|&(d, _)| d > 0.0 && d < span)
            .collect();
        passed.sort_by(|a, b| a.0.total_cmp(&b.0));
        out.extend(passed.into_iter().map(|(_, c)| c));
        out.push(self.point(to, offset));
        out
    }

    /// Joins one level's open contours into rings along the border.
    fn join(&self, open: &[&Contour], offset: f64) -> Result<Vec<Vec<DVec2>>, ContoursError> {
        let limit = END_TOLERANCE * (self.rect.max - self.rect.min).min_element();
        let mut starts = Vec::with_capacity(open.len());
        let mut ends = Vec::with_capacity(open.len());
        for c in open {
            let (first, last) = (c.points[0], c.points[c.points.len() - 1]);
            for (p, list) in [(first, &mut starts), (last, &mut ends)] {
                let (s, d) = self.param(p);
                if d > limit {
                    return Err(ContoursError::Invariant(format!(
                        "the {} m contour ends at ({}, {}), inside the map: only contours cut by its border can be \
                         closed along it",
                        c.height, p.x, p.y
                    )));
                }
                list.push(s);
            }
        }
        let mut used = vec![false; open.len()];
        let mut rings = Vec::new();
        for first in 0..open.len() {
            if used[first] {
                continue;
            }
            let mut ring = Vec::new();
            let mut k = first;
            loop {
                used[k] = true;
                ring.extend_from_slice(&open[k].points);
                // The next start counter-clockwise from this end.
                let next = (0..open.len())
                    .min_by(|&a, &b| {
                        let da = (starts[a] - ends[k]).rem_euclid(self.perimeter);
                        let db = (starts[b] - ends[k]).rem_euclid(self.perimeter);
                        da.total_cmp(&db).then(a.cmp(&b))
                    })
                    .unwrap_or(k);
                ring.extend(self.path(ends[k], starts[next], offset));
                if next == first {
                    break;
                }
                if used[next] {
                    return Err(ContoursError::Invariant(format!(
                        "the {} m contours cut by the border do not pair up along it (is higher ground on their \
                         left?)",
                        open[k].height
                    )));
                }
                k = next;
            }
            ring.dedup();
            rings.push(ring);
        }
        Ok(rings)
    }
}
