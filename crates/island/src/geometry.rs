//! Polygon geometry of the coastline: crossings, validation, and the stroke operations of §3.1
//! (cut and supplement). Containment and signed area are relief-poisson-sampling's
//! ([`ring_contains`], [`signed_area`]), the exact tests every crate shares.

use glam::DVec2;
use relief_poisson_sampling::{ring_contains, signed_area};

use crate::IslandError;

/// Closest point to `q` on segment `ab` and its parameter along it.
pub(crate) fn project(a: DVec2, b: DVec2, q: DVec2) -> (DVec2, f64) {
    let d = b - a;
    let len2 = d.length_squared();
    let t = if len2 > 0.0 { ((q - a).dot(d) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (a + d * t, t)
}

/// Distance from `q` to the closed polygon's boundary, with the edge index and point reached.
pub(crate) fn nearest_on_boundary(p: &[DVec2], q: DVec2) -> (f64, usize, DVec2) {
    let n = p.len();
    let mut best = (f64::INFINITY, 0, p[0]);
    for i in 0..n {
        let (c, _) = project(p[i], p[(i + 1) % n], q);
        let d = c.distance(q);
        if d < best.0 {
            best = (d, i, c);
        }
    }
    best
}

/// Parameters `(t, u)` where segments `a0a1` and `b0b1` cross, if they do (`t` along a, `u`
/// along b, both in [0, 1]). Parallel segments never cross here.
pub(crate) fn crossing(a0: DVec2, a1: DVec2, b0: DVec2, b1: DVec2) -> Option<(f64, f64)> {
    let (da, db) = (a1 - a0, b1 - b0);
    let den = da.perp_dot(db);
    if den == 0.0 {
        return None;
    }
    let w = b0 - a0;
    let t = w.perp_dot(db) / den;
    let u = w.perp_dot(da) / den;
    ((0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u)).then_some((t, u))
}

/// Checks a closed polygon: finite points, at least three distinct, nonzero area, no two
/// non-adjacent edges touching. Returns it counter-clockwise with repeated points removed.
pub(crate) fn simple_polygon(points: &[DVec2]) -> Result<Vec<DVec2>, IslandError> {
    if points.iter().any(|p| !p.is_finite()) {
        return Err(IslandError::NotFinite { what: "a coastline point" });
    }
    let mut p: Vec<DVec2> = Vec::with_capacity(points.len());
    for &q in points {
        if p.last().is_none_or(|&l: &DVec2| l.distance_squared(q) > 1e-18) {
            p.push(q);
        }
    }
    while p.len() > 1 && p[0].distance_squared(p[p.len() - 1]) <= 1e-18 {
        p.pop();
    }
    if p.len() >= 4
        && let Some(at) = self_crossing(&p)
    {
        return Err(IslandError::SelfIntersecting { x: at.x, y: at.y });
    }
    let area = signed_area(&p);
    if p.len() < 3 || area.abs() < 1e-12 {
        return Err(IslandError::DegenerateCoastline { points: points.len() });
    }
    if area < 0.0 {
        p.reverse();
    }
    Ok(p)
}

/// Where two non-adjacent edges of a closed polygon meet, if any. Edges are sorted by their
/// lowest x so only overlapping x-ranges are compared.
fn self_crossing(p: &[DVec2]) -> Option<DVec2> {
    let n = p.len();
    let mut order: Vec<usize> = (0..n).collect();
    let lo = |i: usize| p[i].x.min(p[(i + 1) % n].x);
    let hi = |i: usize| p[i].x.max(p[(i + 1) % n].x);
    order.sort_by(|&a, &b| lo(a).total_cmp(&lo(b)));
    for (k, &e) in order.iter().enumerate() {
        let (a0, a1) = (p[e], p[(e + 1) % n]);
        let (ylo, yhi) = (a0.y.min(a1.y), a0.y.max(a1.y));
        for &f in &order[k + 1..] {
            if lo(f) > hi(e) {
                break;
            }
            if f == (e + 1) % n || e == (f + 1) % n {
                continue;
            }
            let (b0, b1) = (p[f], p[(f + 1) % n]);
            if b0.y.max(b1.y) < ylo || b0.y.min(b1.y) > yhi {
                continue;
            }
            if let Some((t, _)) = crossing(a0, a1, b0, b1) {
                return Some(a0 + (a1 - a0) * t);
            }
        }
    }
    None
}

/// What one piece of a stroke did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EditKind {
    /// A piece through the land: the part left of the stroke direction was removed.
    Cut,
    /// A clockwise piece outside the land: the area it encloses was added.
    Add,
    /// A counter-clockwise piece outside the land: the area it encloses replaced the island.
    Replace,
}

/// A coastline: a simple counter-clockwise polygon, each edge flagged when it comes from the
/// latest stroke (the "new coastline" of §3.2's height update).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Coast {
    pub(crate) points: Vec<DVec2>,
    /// `fresh[i]`: edge `points[i] → points[i + 1]` was drawn by the latest edit.
    pub(crate) fresh: Vec<bool>,
}

impl Coast {
    pub(crate) fn new(points: Vec<DVec2>) -> Self {
        let fresh = vec![true; points.len()];
        Self { points, fresh }
    }

    /// Axis-aligned bounds `(min, max)` of the coastline.
    pub(crate) fn bounds(&self) -> (DVec2, DVec2) {
        self.points.iter().fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(a, b), &p| (a.min(p), b.max(p)))
    }

    /// Inserts `q` (a point on edge `e`) as a vertex unless it is one already.
    fn insert(&mut self, e: usize, q: DVec2) {
        let n = self.points.len();
        let tol = 1e-9 * (1.0 + q.abs().max_element());
        if self.points[e].distance(q) <= tol || self.points[(e + 1) % n].distance(q) <= tol {
            return;
        }
        self.points.insert(e + 1, q);
        let flag = self.fresh[e];
        self.fresh.insert(e + 1, flag);
    }

    /// The stroke split at its contacts with the coast, each piece running from contact to
    /// contact. Contacts are crossings, plus an end of the stroke lying within `snap` of the coast
    /// (projected onto it) when no crossing is that close along the stroke and the stroke leaves
    /// the `snap` band around the coast before its first (or after its last) crossing.
    pub(crate) fn pieces(&self, stroke: &[DVec2], snap: f64) -> Result<Vec<Vec<DVec2>>, IslandError> {
        if stroke.len() < 2 {
            return Err(IslandError::ShortStroke);
        }
        if stroke.iter().any(|p| !p.is_finite()) {
            return Err(IslandError::NotFinite { what: "a stroke point" });
        }
        let p = &self.points;
        let n = p.len();
        // Contacts as (stroke segment + parameter, point).
        let mut contacts: Vec<(f64, DVec2)> = Vec::new();
        for s in 0..stroke.len() - 1 {
            let (a, b) = (stroke[s], stroke[s + 1]);
            for e in 0..n {
                if let Some((t, _)) = crossing(a, b, p[e], p[(e + 1) % n]) {
                    contacts.push((s as f64 + t, a + (b - a) * t));
                }
            }
        }
        contacts.sort_by(|x, y| x.0.total_cmp(&y.0));
        contacts.dedup_by(|x, y| x.1.distance(y.1) <= 1e-9 * (1.0 + x.1.abs().max_element()));
        // Arc length of the stroke up to parameter s.
        let mut cum = vec![0.0];
        for w in stroke.windows(2) {
            cum.push(cum[cum.len() - 1] + w[0].distance(w[1]));
        }
        let along = |s: f64| {
            let k = (s.floor() as usize).min(stroke.len() - 2);
            cum[k] + (s - k as f64) * (cum[k + 1] - cum[k])
        };
        let last = (stroke.len() - 1) as f64;
        // Whether the stroke between parameters s0 and s1 goes farther than `snap` from the
        // coast: a stub that never does is a hesitation at the stroke's end before it crosses,
        // not a piece of its own.
        let leaves = |s0: f64, s1: f64| {
            s0 < s1 && stroke_between(stroke, s0, s1, 0.5 * snap).any(|q| nearest_on_boundary(p, q).0 > snap)
        };
        let (d0, _, q0) = nearest_on_boundary(p, stroke[0]);
        if d0 <= snap && contacts.first().is_none_or(|c| along(c.0) > snap && leaves(0.0, c.0)) {
            contacts.insert(0, (0.0, q0));
        }
        let (d1, _, q1) = nearest_on_boundary(p, stroke[stroke.len() - 1]);
        if d1 <= snap && contacts.last().is_none_or(|c| along(last) - along(c.0) > snap && leaves(c.0, last)) {
            contacts.push((last, q1));
        }
        if contacts.len() < 2 {
            return Err(IslandError::StrokeMissesCoast { snap });
        }
        let mut pieces = Vec::new();
        for w in contacts.windows(2) {
            let (s0, s1) = (w[0].0, w[1].0);
            let mut piece = vec![w[0].1];
            for (k, &q) in stroke.iter().enumerate() {
                let k = k as f64;
                if k > s0 && k < s1 {
                    piece.push(q);
                }
            }
            piece.push(w[1].1);
            let length: f64 = piece.windows(2).map(|w| w[0].distance(w[1])).sum();
            if length > 1e-9 * (1.0 + w[0].1.abs().max_element()) {
                pieces.push(piece);
            }
        }
        if pieces.is_empty() {
            return Err(IslandError::StrokeMissesCoast { snap });
        }
        Ok(pieces)
    }

    /// Applies one piece (its ends on the coast, the rest strictly inside or outside the land):
    /// its ends become coast vertices, the piece and the coast between them form two loops, and
    /// the one the edit keeps becomes the coast. What the edit was; `None` (the coast unchanged
    /// but for two vertices on it) when the piece's ends land on one coast vertex.
    pub(crate) fn apply(&mut self, piece: &[DVec2]) -> Result<Option<EditKind>, IslandError> {
        let inside = ring_contains(&self.points, arc_midpoint(piece));
        let Some((ia, ib)) = self.attach(piece[0], piece[piece.len() - 1]) else { return Ok(None) };
        let inner = &piece[1..piece.len() - 1];
        let forward = self.loop_through(ia, ib, inner, true);
        let backward = self.loop_through(ia, ib, inner, false);
        let (kind, (points, fresh)) = choose_loop(inside, forward, backward);
        (self.points, self.fresh) = counter_clockwise(points, fresh)?;
        Ok(Some(kind))
    }

    /// Inserts the piece's ends `a` and `b`, projected onto the coast, as vertices; returns their
    /// vertex indices, or `None` when both land on one vertex: the piece runs from one coast
    /// point back to it (a closed sketch, or a stub between a stroke's end snapped to the coast
    /// and a crossing beside it) and is not an edit.
    fn attach(&mut self, a: DVec2, b: DVec2) -> Option<(usize, usize)> {
        let (_, ea, qa) = nearest_on_boundary(&self.points, a);
        self.insert(ea, qa);
        let (_, eb, qb) = nearest_on_boundary(&self.points, b);
        self.insert(eb, qb);
        let vertex = |q: DVec2| {
            (0..self.points.len()).min_by(|&i, &j| self.points[i].distance(q).total_cmp(&self.points[j].distance(q)))
        };
        let (ia, ib) = (vertex(qa).unwrap_or(0), vertex(qb).unwrap_or(0));
        (ia != ib).then_some((ia, ib))
    }

    /// The loop through vertex `ia`, the piece's `inner` points, vertex `ib`, then the coast from
    /// `ib` back to `ia` forwards or backwards, with its edge flags: the piece's edges are fresh,
    /// coast edges keep theirs.
    fn loop_through(&self, ia: usize, ib: usize, inner: &[DVec2], forward: bool) -> (Vec<DVec2>, Vec<bool>) {
        let n = self.points.len();
        let mut pts: Vec<DVec2> = Vec::with_capacity(n + inner.len() + 1);
        let mut fresh = Vec::with_capacity(n + inner.len() + 1);
        pts.push(self.points[ia]);
        fresh.push(true);
        for &q in inner {
            pts.push(q);
            fresh.push(true);
        }
        let mut k = ib;
        loop {
            pts.push(self.points[k]);
            let next = if forward { (k + 1) % n } else { (k + n - 1) % n };
            // The coast edge k → next keeps its flag (edge k forwards, edge next backwards).
            fresh.push(if forward { self.fresh[k] } else { self.fresh[next] });
            if next == ia {
                break;
            }
            k = next;
        }
        (pts, fresh)
    }
}

/// Points of `stroke` from parameter `s0` to `s1` (segment index plus fraction), at most `step`
/// apart along each segment (and at most 1024 a segment), both ends included.
fn stroke_between(stroke: &[DVec2], s0: f64, s1: f64, step: f64) -> impl Iterator<Item = DVec2> + '_ {
    let at = move |s: f64| {
        let k = (s.floor() as usize).min(stroke.len() - 2);
        stroke[k].lerp(stroke[k + 1], s - k as f64)
    };
    let mut knots = vec![s0];
    knots.extend((s0.floor() as usize + 1..stroke.len()).map(|k| k as f64).filter(|&k| k < s1));
    knots.push(s1);
    let spans: Vec<(f64, f64)> = knots.windows(2).map(|w| (w[0], w[1])).collect();
    spans.into_iter().flat_map(move |(a, b)| {
        let n = ((at(a).distance(at(b)) / step.max(f64::MIN_POSITIVE)).ceil() as usize).clamp(1, 1024);
        (0..=n).map(move |i| at(a + (b - a) * i as f64 / n as f64))
    })
}

/// The point halfway along `piece` by arc length: where a piece that runs strictly inside or
/// outside the land tells which it does.
fn arc_midpoint(piece: &[DVec2]) -> DVec2 {
    let total: f64 = piece.windows(2).map(|w| w[0].distance(w[1])).sum();
    let mut walked = 0.0;
    for w in piece.windows(2) {
        let l = w[0].distance(w[1]);
        if walked + l >= 0.5 * total {
            return w[0] + (w[1] - w[0]) * ((0.5 * total - walked) / l.max(f64::MIN_POSITIVE));
        }
        walked += l;
    }
    piece[0]
}

/// Which of a piece's two loops (with their edge flags) the edit keeps, and what the edit is.
/// A piece through the land cuts: the loop left of the stroke is counter-clockwise, the other
/// one stays. A piece outside supplements: the smaller loop is the area the piece encloses with
/// the coast, oriented as the stroke; clockwise adds it (the larger loop stays), counter-
/// clockwise keeps only it.
fn choose_loop(
    inside: bool,
    forward: (Vec<DVec2>, Vec<bool>),
    backward: (Vec<DVec2>, Vec<bool>),
) -> (EditKind, (Vec<DVec2>, Vec<bool>)) {
    let (af, ab) = (signed_area(&forward.0), signed_area(&backward.0));
    if inside {
        (EditKind::Cut, if af > 0.0 { backward } else { forward })
    } else {
        let (region, region_area, union) =
            if af.abs() < ab.abs() { (forward, af, backward) } else { (backward, ab, forward) };
        if region_area < 0.0 { (EditKind::Add, union) } else { (EditKind::Replace, region) }
    }
}

/// The ring `pts` with edge flags `fresh`, turned counter-clockwise and validated as a coast
/// ([`simple_polygon`]), the flags following their edges.
fn counter_clockwise(mut pts: Vec<DVec2>, mut fresh: Vec<bool>) -> Result<(Vec<DVec2>, Vec<bool>), IslandError> {
    if signed_area(&pts) < 0.0 {
        // Reverse the ring and its edge flags (edge i of the reversed ring is old edge n−2−i).
        pts.reverse();
        let m = fresh.len();
        let old = fresh.clone();
        for (i, f) in fresh.iter_mut().enumerate() {
            *f = old[(2 * m - 2 - i) % m];
        }
    }
    let pts_checked = simple_polygon(&pts)?;
    if pts_checked.len() != pts.len() {
        // Repeated points were dropped: rebuild the flags by matching edges.
        fresh = rebuild_flags(&pts, &fresh, &pts_checked);
        pts = pts_checked;
    }
    Ok((pts, fresh))
}

/// Edge flags of `clean` (a copy of `ring` with repeated points removed), taken from the edge of
/// `ring` that starts at the same point.
fn rebuild_flags(ring: &[DVec2], flags: &[bool], clean: &[DVec2]) -> Vec<bool> {
    clean.iter().map(|q| ring.iter().position(|p| p == q).is_none_or(|i| flags[i])).collect()
}

#[cfg(test)]
mod tests {
    use relief_poisson_sampling::{ring_contains as contains, signed_area};

    use super::*;

    /// The stroke between two parameters, sampled at most `step` apart along each segment, from
    /// the first parameter's point to the second's, through the vertices between.
    #[test]
    fn stroke_between_samples_the_stroke_from_one_parameter_to_another() {
        let stroke =
            [DVec2::ZERO, DVec2::new(9.0, 0.0), DVec2::new(9.0, 9.0), DVec2::new(0.0, 9.0), DVec2::new(0.0, 18.0)];
        let points: Vec<[f64; 2]> = stroke_between(&stroke, 1.0 / 3.0, 4.0 / 3.0, 2.0).map(|p| p.to_array()).collect();
        let expected = [[3.0, 0.0], [5.0, 0.0], [7.0, 0.0], [9.0, 0.0], [9.0, 0.0], [9.0, 1.5], [9.0, 3.0]];
        assert_eq!(points.len(), expected.len(), "{points:?}");
        for (p, q) in points.iter().zip(expected) {
            assert!((p[0] - q[0]).abs() < 1e-9 && (p[1] - q[1]).abs() < 1e-9, "{points:?}");
        }
        // Within one segment; and the last segment up to the stroke's end.
        assert_eq!(stroke_between(&stroke, 0.0, 0.5, 10.0).count(), 2);
        let tail: Vec<[f64; 2]> = stroke_between(&stroke, 3.5, 4.0, 4.5).map(|p| p.to_array()).collect();
        assert_eq!(tail, [[0.0, 13.5], [0.0, 18.0]]);
    }

    fn square() -> Coast {
        Coast::new(vec![DVec2::new(0.0, 0.0), DVec2::new(10.0, 0.0), DVec2::new(10.0, 10.0), DVec2::new(0.0, 10.0)])
    }

    #[test]
    fn a_cut_removes_the_left_side() {
        // Upwards through x = 4: the left side (x < 4) goes.
        let mut c = square();
        let stroke = [DVec2::new(4.0, -1.0), DVec2::new(4.0, 11.0)];
        let pieces = c.pieces(&stroke, 0.5).unwrap();
        assert_eq!(pieces.len(), 1);
        assert_eq!(c.apply(&pieces[0]).unwrap(), Some(EditKind::Cut));
        assert!((signed_area(&c.points) - 60.0).abs() < 1e-9);
        assert!(contains(&c.points, DVec2::new(7.0, 5.0)) && !contains(&c.points, DVec2::new(2.0, 5.0)));
    }

    #[test]
    fn reversing_the_cut_removes_the_other_side() {
        let mut c = square();
        let stroke = [DVec2::new(4.0, 11.0), DVec2::new(4.0, -1.0)];
        for piece in c.clone().pieces(&stroke, 0.5).unwrap() {
            c.apply(&piece).unwrap();
        }
        assert!((signed_area(&c.points) - 40.0).abs() < 1e-9);
        assert!(contains(&c.points, DVec2::new(2.0, 5.0)));
    }

    #[test]
    fn flags_mark_the_new_edges() {
        let mut c = square();
        for f in &mut c.fresh {
            *f = false;
        }
        let stroke = [DVec2::new(4.0, -1.0), DVec2::new(4.0, 11.0)];
        for piece in c.clone().pieces(&stroke, 0.5).unwrap() {
            c.apply(&piece).unwrap();
        }
        let n = c.points.len();
        let fresh: Vec<(DVec2, DVec2)> =
            (0..n).filter(|&i| c.fresh[i]).map(|i| (c.points[i], c.points[(i + 1) % n])).collect();
        assert_eq!(fresh.len(), 1);
        assert!(fresh[0].0.x == 4.0 && fresh[0].1.x == 4.0);
    }
}
