//! A scene's inputs drawn over its relief (`relief preview --inputs`), so that a user sees which
//! region, stroke or curve did what: [`scene_marks`] turns the scene into [`Mark`]s in world
//! coordinates, [`draw_marks`] draws them on a north-up preview.
//!
//! ```
//! use relief::Scene;
//! use relief::overlay::{Role, draw_marks, scene_marks};
//!
//! let scene = Scene::demo();
//! let marks = scene_marks(&scene);
//! assert!(marks.iter().any(|m| m.role == Role::Coastline));
//! let mut image = relief::io::RgbImage { width: 64, height: 64, pixels: vec![128; 64 * 64 * 3] };
//! let extent = relief::heightfield::Extent::new([-3000.0, -3000.0].into(), [3000.0, 3000.0].into());
//! draw_marks(&mut image, &marks, &extent);
//! assert!(image.pixels.iter().any(|&v| v != 128));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::f64::consts::TAU;

use glam::DVec2;

use crate::eden_growth::Region;
use crate::gaussian_terrain::{Region as Selection, Tool};
use crate::heightfield::Extent;
use crate::io::RgbImage;
use crate::island::{Hill, Operation};
use crate::orometry::TreeEdit;
use crate::scene::{Generator, Scene};

/// What an input is, which sets its colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// The outermost contour: a contour scene's depth-0 regions, an island's coastline.
    Coastline,
    /// A raised region inside the coastline.
    Raised,
    /// A depression (lake, basin).
    Depression,
    /// An island stroke; its first point is drawn as a dot, so that its direction shows.
    Stroke,
    /// An island hill or hollow (its ellipse).
    Hill,
    /// A diffusion feature curve (its centre line).
    Curve,
    /// A Gaussian tool's selection or target.
    Selection,
    /// A peak or saddle placed by hand (orometry).
    Peak,
}

impl Role {
    fn colour(self) -> [u8; 3] {
        match self {
            Role::Coastline => [255, 255, 255],
            Role::Raised => [255, 140, 0],
            Role::Depression => [40, 120, 255],
            Role::Stroke => [255, 0, 200],
            Role::Hill => [255, 230, 0],
            Role::Curve => [230, 20, 20],
            Role::Selection => [0, 230, 230],
            Role::Peak => [255, 120, 160],
        }
    }
}

/// One input as a line, a ring or a point, in world coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct Mark {
    /// What it is.
    pub role: Role,
    /// Its points: one for a point, the vertices of a line or ring otherwise.
    pub points: Vec<DVec2>,
    /// Whether the last point joins the first.
    pub closed: bool,
}

impl Mark {
    fn line(role: Role, points: Vec<DVec2>, closed: bool) -> Self {
        Self { role, points, closed }
    }

    fn point(role: Role, p: DVec2) -> Self {
        Self { role, points: vec![p], closed: false }
    }
}

/// The drawable inputs of `scene`: regions (contours), the coastline, strokes and hills left by
/// the operations (island), curves (diffusion), tool selections and targets (gaussian), pinned
/// and edited peaks (orometry). Inputs given as files (a label image, a DEM) are not marks.
pub fn scene_marks(scene: &Scene) -> Vec<Mark> {
    match &scene.generator {
        Generator::Contours(g) => g
            .regions
            .iter()
            .enumerate()
            .flat_map(|(k, r)| {
                let role = match (r.depression, depth(&g.regions, k)) {
                    (true, _) => Role::Depression,
                    (false, 0) => Role::Coastline,
                    (false, _) => Role::Raised,
                };
                r.polygon.rings().map(move |ring| Mark::line(role, ring.to_vec(), true)).collect::<Vec<_>>()
            })
            .collect(),
        Generator::Island(g) => island_marks(&g.operations),
        Generator::Diffusion(g) => {
            let curves = g.all_curves();
            let (lo, hi) = curves.iter().flat_map(|c| &c.points).fold((DVec2::INFINITY, DVec2::NEG_INFINITY), grow);
            let step = ((hi - lo).max_element() / 1000.0).max(f64::MIN_POSITIVE);
            curves.iter().map(|c| Mark::line(Role::Curve, c.centre_line(step), false)).collect()
        }
        Generator::Gaussian(g) => g.operations.iter().flat_map(tool_marks).collect(),
        Generator::Orometry(g) => {
            let pinned = g.pinned.iter().map(|p| Mark::point(Role::Peak, p.position));
            pinned.chain(g.edits.iter().flat_map(edit_marks)).collect()
        }
    }
}

/// The sea level a preview of `scene`'s terrain should draw, where the scene sets it: an island's
/// (half its land floor), a diffusion scene's `sea_level`, the height given to a contour scene's
/// outermost regions.
pub fn scene_sea_level(scene: &Scene) -> Option<f64> {
    match &scene.generator {
        Generator::Contours(g) => {
            (0..g.regions.len()).filter(|&k| depth(&g.regions, k) == 0).find_map(|k| g.regions[k].height)
        }
        Generator::Island(g) => Some(0.5 * g.settings.land_floor),
        Generator::Diffusion(g) => g.sea_level,
        Generator::Gaussian(_) | Generator::Orometry(_) => None,
    }
}

/// How many other regions hold region `k` (0: the coastline). The scene need not be valid yet, so
/// this does not go through `RegionTree`.
fn depth(regions: &[Region], k: usize) -> usize {
    let inside = |o: &Region| regions[k].polygon.exterior().iter().all(|&p| o.polygon.contains(p));
    regions.iter().enumerate().filter(|&(j, o)| j != k && inside(o)).count()
}

/// The bounds fold used for the curves' drawing step.
fn grow((lo, hi): (DVec2, DVec2), p: &DVec2) -> (DVec2, DVec2) {
    (lo.min(*p), hi.max(*p))
}

/// Island operations: every coastline and stroke, and the hills as they stand after the moves,
/// resizes and removals.
fn island_marks(operations: &[Operation]) -> Vec<Mark> {
    let points = |p: &[[f64; 2]]| p.iter().map(|&q| DVec2::from(q)).collect::<Vec<_>>();
    let mut marks = Vec::new();
    let mut hills: Vec<Hill> = Vec::new();
    for op in operations {
        match op {
            Operation::Coastline { points: p } => marks.push(Mark::line(Role::Coastline, points(p), true)),
            Operation::Stroke { points: p } => {
                let line = points(p);
                if let Some(&start) = line.first() {
                    marks.push(Mark::point(Role::Stroke, start));
                }
                marks.push(Mark::line(Role::Stroke, line, false));
            }
            Operation::AddHill(hill) => hills.push(*hill),
            Operation::MoveHill { hill, center } => {
                if let Some(h) = hills.get_mut(*hill) {
                    h.center = *center;
                }
            }
            Operation::ResizeHill { hill, radii, height, rotation } => {
                if let Some(h) = hills.get_mut(*hill) {
                    h.radii = *radii;
                    h.height = height.unwrap_or(h.height);
                    h.rotation = rotation.unwrap_or(h.rotation);
                }
            }
            Operation::RemoveHill { hill } if *hill < hills.len() => {
                hills.remove(*hill);
            }
            _ => {}
        }
    }
    marks.extend(hills.iter().flat_map(|h| {
        let centre = DVec2::from(h.center);
        [Mark::point(Role::Hill, centre), Mark::line(Role::Hill, ellipse(h), true)]
    }));
    marks
}

/// A hill's footprint: the ellipse of its semi-axes, turned by its rotation.
fn ellipse(h: &Hill) -> Vec<DVec2> {
    ring(DVec2::from(h.center), h.radii, h.rotation.to_radians())
}

/// 64 points round the ellipse of semi-axes `[a, b]` about `centre`, the `a` axis turned by
/// `rotation` radians.
fn ring(centre: DVec2, [a, b]: [f64; 2], rotation: f64) -> Vec<DVec2> {
    let axis = DVec2::from_angle(rotation);
    (0..64)
        .map(|k| {
            let t = TAU * f64::from(k) / 64.0;
            centre + axis.rotate(DVec2::new(a * t.cos(), b * t.sin()))
        })
        .collect()
}

/// A Gaussian tool's selection, and where it sends it (a point) when it moves things.
fn tool_marks(tool: &Tool) -> Vec<Mark> {
    let selection = |region: &Selection| match region {
        Selection::Circle { center, radius } => {
            Mark::line(Role::Selection, ring(DVec2::from(*center), [*radius; 2], 0.0), true)
        }
        Selection::Lasso { points } => {
            Mark::line(Role::Selection, points.iter().map(|&p| DVec2::from(p)).collect(), true)
        }
    };
    match tool {
        Tool::Stamp { region, placement, .. } => {
            vec![selection(region), Mark::point(Role::Selection, DVec2::from(placement.to))]
        }
        Tool::Paste { placement, .. } => vec![Mark::point(Role::Selection, DVec2::from(placement.to))],
        Tool::Delete { region }
        | Tool::Copy { region, .. }
        | Tool::Cut { region, .. }
        | Tool::Twist { region, .. }
        | Tool::Squeeze { region, .. } => vec![selection(region)],
        // A node given by id has no position until the skeleton is extracted: no mark.
        Tool::MoveCrest { near, by, .. } => near
            .map(|near| {
                let from = DVec2::from(near);
                vec![
                    Mark::point(Role::Selection, from),
                    Mark::line(Role::Selection, vec![from, from + DVec2::from(*by)], false),
                ]
            })
            .unwrap_or_default(),
        Tool::RaiseCrest { near, .. } => {
            near.map(|p| vec![Mark::point(Role::Selection, DVec2::from(p))]).unwrap_or_default()
        }
    }
}

/// The positions an orometry edit sets.
fn edit_marks(edit: &TreeEdit) -> Vec<Mark> {
    match *edit {
        TreeEdit::InsertPeak { position, saddle, .. } => {
            vec![Mark::point(Role::Peak, position), Mark::line(Role::Peak, vec![position, saddle], false)]
        }
        TreeEdit::MovePeak { position, .. } | TreeEdit::MoveSaddle { position, .. } => {
            vec![Mark::point(Role::Peak, position)]
        }
        TreeEdit::DeletePeak { .. } | TreeEdit::DeleteRidge { .. } => Vec::new(),
    }
}

/// Draws `marks` on a north-up image of `extent`: lines two pixels wide in their role's colour
/// over a dark halo (visible on any ground), points as dots; whatever falls outside is clipped.
pub fn draw_marks(image: &mut RgbImage, marks: &[Mark], extent: &Extent) {
    if image.width < 2 || image.height < 2 {
        return;
    }
    let mut canvas = Canvas { image, extent: *extent };
    for (radius, halo) in [(4.0, true), (2.0, false)] {
        for mark in marks {
            let colour = if halo { [20, 20, 20] } else { mark.role.colour() };
            canvas.mark(mark, radius, colour);
        }
    }
}

/// An image with the world-to-pixel map of its extent.
struct Canvas<'a> {
    image: &'a mut RgbImage,
    extent: Extent,
}

impl Canvas<'_> {
    fn to_px(&self, p: DVec2) -> DVec2 {
        let (e, size) = (self.extent, self.extent.size());
        let (w, h) = ((self.image.width - 1) as f64, (self.image.height - 1) as f64);
        DVec2::new((p.x - e.min.x) / size.x * w, (e.max.y - p.y) / size.y * h)
    }

    fn mark(&mut self, mark: &Mark, radius: f64, colour: [u8; 3]) {
        let px: Vec<DVec2> = mark.points.iter().map(|&p| self.to_px(p)).collect();
        if let [p] = px[..] {
            self.dot(p, radius, colour);
            return;
        }
        let closing = (mark.closed && px.len() > 2).then(|| [px[px.len() - 1], px[0]]);
        for [a, b] in px.windows(2).map(|w| [w[0], w[1]]).chain(closing) {
            self.segment(a, b, radius, colour);
        }
    }

    fn segment(&mut self, a: DVec2, b: DVec2, radius: f64, colour: [u8; 3]) {
        let margin = radius + 1.0;
        let hi = DVec2::new(self.image.width as f64, self.image.height as f64) + margin;
        let Some((a, b)) = clip(a, b, DVec2::splat(-margin), hi) else { return };
        let steps = (b - a).abs().max_element().ceil().max(1.0) as usize;
        for s in 0..=steps {
            self.dot(a.lerp(b, s as f64 / steps as f64), radius * 0.5, colour);
        }
    }

    /// A filled disc of `radius` pixels (at least the pixel under `c`).
    fn dot(&mut self, c: DVec2, radius: f64, colour: [u8; 3]) {
        let size = DVec2::new(self.image.width as f64, self.image.height as f64);
        if !(c.cmpge(DVec2::splat(-radius - 1.0)).all() && c.cmple(size + radius + 1.0).all()) {
            return;
        }
        let r = radius.ceil() as i64;
        let (cx, cy) = (c.x.round() as i64, c.y.round() as i64);
        for y in cy - r..=cy + r {
            for x in cx - r..=cx + r {
                let inside = ((x - cx).pow(2) + (y - cy).pow(2)) as f64 <= radius * radius + 0.5;
                if inside && x >= 0 && y >= 0 && (x as usize) < self.image.width && (y as usize) < self.image.height {
                    let k = 3 * (y as usize * self.image.width + x as usize);
                    self.image.pixels[k..k + 3].copy_from_slice(&colour);
                }
            }
        }
    }
}

/// The part of segment `a`–`b` inside the box `lo`–`hi` (Liang–Barsky), if any.
fn clip(a: DVec2, b: DVec2, lo: DVec2, hi: DVec2) -> Option<(DVec2, DVec2)> {
    if !(a.is_finite() && b.is_finite()) {
        return None;
    }
    let d = b - a;
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (p, q) in [(-d.x, a.x - lo.x), (d.x, hi.x - a.x), (-d.y, a.y - lo.y), (d.y, hi.y - a.y)] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    (t0 <= t1).then(|| (a + d * t0, a + d * t1))
}
