//! Landform tools (§5.2): circle and lasso selections, stamping (move / rotate / scale) with the
//! primitives underneath damped, copy / cut / paste through [`Landform`]s, delete, twist and
//! squeeze.
//!
//! Selections act on primitive centres: `P(Ω) = {Pᵢ : cᵢ ∈ Ω}`. Fall-offs use the smoothstep
//! `s(x) = 3x² − 2x³` on `[0, 1]`. A tool only ever changes the primitives its fall-off reaches;
//! every other primitive keeps its exact bits.

use glam::DVec2;
use relief_poisson_sampling::{ring_contains, segment_distance_sq, signed_area};
use serde::{Deserialize, Serialize};

use crate::primitive::stretch_along;
use crate::{Gaussian, GaussianError, Landform, VectorTerrain};

/// The compactly supported step `s` of §5: smoothstep, 0 below 0 and 1 above 1.
pub fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// A selected region Ω of the plane. (Its JSON Schema is named `SelectionRegion`, apart from a
/// contour scene's `Region`.)
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema), schemars(rename = "SelectionRegion"))]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "snake_case", deny_unknown_fields)]
pub enum Region {
    /// A disc.
    Circle {
        /// Centre `[x, y]`.
        center: [f64; 2],
        /// Radius (> 0).
        radius: f64,
    },
    /// A free-form closed lasso (a simple polygon, at least 3 points, closing edge implied).
    Lasso {
        /// Vertices `[x, y]` in order.
        points: Vec<[f64; 2]>,
    },
}

impl Region {
    /// Checks the shape.
    ///
    /// # Errors
    /// [`GaussianError::InvalidRegion`] for a non-finite or non-positive radius, a lasso of
    /// fewer than 3 points, non-finite points or a lasso of zero area.
    pub fn validate(&self) -> Result<(), GaussianError> {
        let bad = |reason: &'static str| Err(GaussianError::InvalidRegion { reason });
        match self {
            Region::Circle { center, radius } => {
                if !(center.iter().all(|v| v.is_finite()) && radius.is_finite() && *radius > 0.0) {
                    return bad("a circle needs a finite centre and a radius > 0");
                }
            }
            Region::Lasso { points } => {
                if points.len() < 3 {
                    return bad("a lasso needs at least 3 points");
                }
                if points.iter().flatten().any(|v| !v.is_finite()) {
                    return bad("a lasso point is not finite");
                }
                if self.area() <= 0.0 {
                    return bad("the lasso encloses no area");
                }
            }
        }
        Ok(())
    }

    fn area(&self) -> f64 {
        match self {
            Region::Circle { radius, .. } => std::f64::consts::PI * radius * radius,
            Region::Lasso { points } => signed_area(points).abs(),
        }
    }

    /// The convex hull of `points` as a lasso (counter-clockwise), `None` when they span no
    /// area (fewer than three, or all on a line).
    pub fn convex_hull(points: &[DVec2]) -> Option<Region> {
        let mut sorted: Vec<DVec2> = points.iter().copied().filter(|p| p.is_finite()).collect();
        sorted.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
        sorted.dedup();
        if sorted.len() < 3 {
            return None;
        }
        // Andrew's monotone chain.
        let cross = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
        let mut hull: Vec<DVec2> = Vec::with_capacity(2 * sorted.len());
        for pass in 0..2 {
            let start = hull.len();
            let iter: Box<dyn Iterator<Item = &DVec2>> =
                if pass == 0 { Box::new(sorted.iter()) } else { Box::new(sorted.iter().rev()) };
            for &p in iter {
                while hull.len() >= start + 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
                    hull.pop();
                }
                hull.push(p);
            }
            hull.pop();
        }
        let lasso = Region::Lasso { points: hull.iter().map(DVec2::to_array).collect() };
        (hull.len() >= 3 && lasso.area() > 0.0).then_some(lasso)
    }

    /// Whether `p` is inside Ω (even–odd rule for a lasso).
    pub fn contains(&self, p: DVec2) -> bool {
        match self {
            Region::Circle { center, radius } => p.distance_squared(DVec2::from(*center)) <= radius * radius,
            Region::Lasso { points } => ring_contains(points, p),
        }
    }

    /// Distance from `p` to the boundary ∂Ω.
    pub fn boundary_distance(&self, p: DVec2) -> f64 {
        match self {
            Region::Circle { center, radius } => (p.distance(DVec2::from(*center)) - radius).abs(),
            Region::Lasso { points } => {
                let n = points.len();
                (0..n)
                    .map(|k| segment_distance_sq(p, DVec2::from(points[k]), DVec2::from(points[(k + 1) % n])))
                    .fold(f64::INFINITY, f64::min)
                    .sqrt()
            }
        }
    }

    /// A point inside Ω to turn and scale about: the circle's centre or the lasso's centroid.
    pub fn anchor(&self) -> DVec2 {
        match self {
            Region::Circle { center, .. } => DVec2::from(*center),
            Region::Lasso { points } => points.iter().map(|&p| DVec2::from(p)).sum::<DVec2>() / points.len() as f64,
        }
    }

    /// Inner fall-off for warps: `s(d(∂Ω, p) / r)` inside Ω, 0 outside (1 deep inside, 0 on the
    /// boundary, so a warp fades to nothing where Ω ends).
    pub fn inner_falloff(&self, p: DVec2, r: f64) -> f64 {
        if self.contains(p) { smoothstep(self.boundary_distance(p) / r) } else { 0.0 }
    }

    /// Outer fall-off for damping: 0 inside Ω, `s(d(∂Ω, p) / r)` outside (1 beyond `r`); `r = ∞`
    /// vanishes everything outside as well, as in §5.2.
    pub fn outer_falloff(&self, p: DVec2, r: f64) -> f64 {
        if self.contains(p) || r.is_infinite() { 0.0 } else { smoothstep(self.boundary_distance(p) / r) }
    }

    /// The indices of the primitives whose centre is inside Ω: `P(Ω)`.
    pub fn select(&self, terrain: &VectorTerrain) -> Vec<usize> {
        (0..terrain.primitives.len()).filter(|&k| self.contains(DVec2::from(terrain.primitives[k].center))).collect()
    }

    /// Ω under the similarity `p ↦ at + R(rotation)·scale·(p − anchor)`.
    fn placed(&self, anchor: DVec2, at: DVec2, rotation: f64, scale: f64) -> Region {
        let map = |p: [f64; 2]| (at + DVec2::from_angle(rotation).rotate((DVec2::from(p) - anchor) * scale)).to_array();
        match self {
            Region::Circle { center, radius } => Region::Circle { center: map(*center), radius: radius * scale },
            Region::Lasso { points } => Region::Lasso { points: points.iter().map(|&p| map(p)).collect() },
        }
    }
}

/// Where and how a stamp puts the selected landform: turned by `rotation` radians and scaled by
/// `scale` about the region's anchor, which lands at `to`.
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Placement {
    /// Where the anchor goes.
    pub to: [f64; 2],
    /// Rotation, radians counter-clockwise (default 0).
    #[serde(default)]
    pub rotation: f64,
    /// Uniform scale of positions and σ (default 1; > 0).
    #[serde(default = "one")]
    pub scale: f64,
}

fn one() -> f64 {
    1.0
}

impl Placement {
    fn validate(&self) -> Result<(), GaussianError> {
        if !(self.to.iter().all(|v| v.is_finite())
            && self.rotation.is_finite()
            && self.scale.is_finite()
            && self.scale > 0.0)
        {
            return Err(GaussianError::InvalidRegion {
                reason: "a placement needs a finite target, rotation and scale > 0",
            });
        }
        Ok(())
    }
}

/// Whether a stamp moves the selection or pastes a copy of it.
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum StampMode {
    /// The selected primitives move (the source area is left without them).
    #[default]
    Move,
    /// A transformed copy is added; the source stays.
    Copy,
}

fn check_radius(name: &'static str, r: f64) -> Result<(), GaussianError> {
    if r.is_nan() || r <= 0.0 {
        return Err(GaussianError::InvalidOption { name, value: r, reason: "must be > 0 (∞ allowed)" });
    }
    Ok(())
}

/// Stamping (§5.2): the primitives of `P(Ω)` are moved (or copied) by `placement`, and every
/// other primitive is damped by the outer fall-off of the destination region,
/// `hᵢ ← f(cᵢ)·hᵢ` with `f = s(d(∂Ω̃, cᵢ)/r)`: vanished under the stamp (and removed, so no
/// zero-amplitude primitive is left), untouched beyond `r`. Returns the indices of the placed
/// primitives.
///
/// # Errors
/// [`GaussianError::InvalidRegion`] or [`GaussianError::InvalidOption`] for a bad region,
/// placement or radius.
pub fn stamp(
    terrain: &mut VectorTerrain,
    region: &Region,
    placement: &Placement,
    mode: StampMode,
    damping_radius: f64,
) -> Result<Vec<usize>, GaussianError> {
    region.validate()?;
    placement.validate()?;
    let selected = region.select(terrain);
    let landform = Landform::new(
        "selection",
        &selected.iter().map(|&k| terrain.primitives[k]).collect::<Vec<_>>(),
        region.anchor(),
    );
    if mode == StampMode::Move {
        delete_indices(terrain, &selected);
    }
    paste_landform(terrain, &landform, region, region.anchor(), placement, damping_radius)
}

/// Pastes `landform` (anchored at its origin) with `placement`, damping the primitives under
/// it by the outer fall-off of `footprint` (given relative to the landform's anchor) placed the
/// same way. Returns the indices of the pasted primitives.
///
/// # Errors
/// As [`stamp`].
pub fn paste(
    terrain: &mut VectorTerrain,
    landform: &Landform,
    footprint: &Region,
    placement: &Placement,
    damping_radius: f64,
) -> Result<Vec<usize>, GaussianError> {
    footprint.validate()?;
    placement.validate()?;
    paste_landform(terrain, landform, footprint, DVec2::ZERO, placement, damping_radius)
}

fn paste_landform(
    terrain: &mut VectorTerrain,
    landform: &Landform,
    source: &Region,
    anchor: DVec2,
    placement: &Placement,
    damping_radius: f64,
) -> Result<Vec<usize>, GaussianError> {
    check_radius("damping radius", damping_radius)?;
    let destination = source.placed(anchor, DVec2::from(placement.to), placement.rotation, placement.scale);
    for g in &mut terrain.primitives {
        let f = destination.outer_falloff(DVec2::from(g.center), damping_radius);
        if f < 1.0 {
            g.amplitude *= f;
        }
    }
    // Primitives wholly under the stamp vanished: drop them rather than keep zero-amplitude ones.
    terrain.primitives.retain(|g| g.amplitude != 0.0);
    let start = terrain.primitives.len();
    terrain.primitives.extend(landform.placed(DVec2::from(placement.to), placement.rotation, placement.scale));
    Ok((start..terrain.primitives.len()).collect())
}

/// Saves `P(Ω)` as a landform anchored at the region's anchor (copy; add it to an
/// [`crate::Atlas`] to keep it).
///
/// # Errors
/// [`GaussianError::InvalidRegion`] for a bad region.
pub fn copy(terrain: &VectorTerrain, region: &Region, name: &str) -> Result<Landform, GaussianError> {
    region.validate()?;
    let selected: Vec<Gaussian> = region.select(terrain).iter().map(|&k| terrain.primitives[k]).collect();
    Ok(Landform::new(name, &selected, region.anchor()))
}

/// [`copy`], then [`delete`].
///
/// # Errors
/// As [`copy`].
pub fn cut(terrain: &mut VectorTerrain, region: &Region, name: &str) -> Result<Landform, GaussianError> {
    let landform = copy(terrain, region, name)?;
    delete(terrain, region)?;
    Ok(landform)
}

/// Removes `P(Ω)`; returns how many primitives went.
///
/// # Errors
/// [`GaussianError::InvalidRegion`] for a bad region.
pub fn delete(terrain: &mut VectorTerrain, region: &Region) -> Result<usize, GaussianError> {
    region.validate()?;
    let selected = region.select(terrain);
    delete_indices(terrain, &selected);
    Ok(selected.len())
}

fn delete_indices(terrain: &mut VectorTerrain, sorted: &[usize]) {
    let mut next = sorted.iter().peekable();
    let mut k = 0;
    terrain.primitives.retain(|_| {
        let drop = next.peek() == Some(&&k);
        if drop {
            next.next();
        }
        k += 1;
        !drop
    });
}

/// The influence region of combined edits (§5.2: "we propagate modifications in an influence
/// region around the convex hull of modifications"): the primitives `moved` by a crest or
/// region edit span a convex hull Ω; every other primitive is damped by Ω's outer fall-off,
/// `hᵢ ← s(d(∂Ω, cᵢ)/r)·hᵢ` (vanished inside Ω, and then removed; untouched beyond `r`), so
/// the moved landform does not pile onto what it now covers. `moved` are indices into the
/// terrain (ascending or not); fewer than three non-collinear centres span no hull and damp
/// nothing. Returns how many primitives were damped.
///
/// # Errors
/// [`GaussianError::InvalidOption`] for a radius that is not `> 0`.
pub fn damp_around(terrain: &mut VectorTerrain, moved: &[usize], radius: f64) -> Result<usize, GaussianError> {
    check_radius("influence radius", radius)?;
    let centres: Vec<DVec2> =
        moved.iter().filter_map(|&k| terrain.primitives.get(k)).map(|g| DVec2::from(g.center)).collect();
    let Some(hull) = Region::convex_hull(&centres) else { return Ok(0) };
    let n = terrain.primitives.len();
    let mut is_moved = vec![false; n];
    for &k in moved.iter().filter(|&&k| k < n) {
        is_moved[k] = true;
    }
    let mut damped = 0;
    for (g, _) in terrain.primitives.iter_mut().zip(&is_moved).filter(|(_, m)| !**m) {
        let f = hull.outer_falloff(DVec2::from(g.center), radius);
        if f < 1.0 {
            g.amplitude *= f;
            damped += 1;
        }
    }
    terrain.primitives.retain(|g| g.amplitude != 0.0);
    Ok(damped)
}

/// Twist (§5.2, after Génevaux et al. 2015): primitives inside Ω turn about the region's anchor
/// by `φ(c) = angle · |c − anchor| / R · f(c)` (R the farthest boundary point from the anchor,
/// `f` the inner fall-off over `falloff_radius`), centre and orientation alike. Returns how many
/// primitives moved.
///
/// # Errors
/// As [`delete`], and [`GaussianError::InvalidOption`] for a non-finite angle or a bad radius.
pub fn twist(
    terrain: &mut VectorTerrain,
    region: &Region,
    angle: f64,
    falloff_radius: f64,
) -> Result<usize, GaussianError> {
    region.validate()?;
    check_radius("fall-off radius", falloff_radius)?;
    if !angle.is_finite() {
        return Err(GaussianError::InvalidOption { name: "angle", value: angle, reason: "must be finite" });
    }
    let anchor = region.anchor();
    let reach = match region {
        Region::Circle { center, radius } => DVec2::from(*center).distance(anchor) + radius,
        Region::Lasso { points } => points.iter().map(|&p| DVec2::from(p).distance(anchor)).fold(0.0, f64::max),
    };
    let mut moved = 0;
    for g in &mut terrain.primitives {
        let c = DVec2::from(g.center);
        let f = region.inner_falloff(c, falloff_radius);
        if f <= 0.0 {
            continue;
        }
        let phi = angle * (c.distance(anchor) / reach) * f;
        g.center = (anchor + DVec2::from_angle(phi).rotate(c - anchor)).to_array();
        g.theta += phi;
        moved += 1;
    }
    Ok(moved)
}

/// Squeeze (§5.2): primitives inside Ω move by `f(c)·v` (`f` the inner fall-off over
/// `falloff_radius`) and stretch along `v` by `f(c) − f(c') + 1`, so that primitives pushed
/// together narrow and those pulled apart widen. Returns how many primitives moved.
///
/// # Errors
/// As [`twist`].
pub fn squeeze(
    terrain: &mut VectorTerrain,
    region: &Region,
    v: DVec2,
    falloff_radius: f64,
) -> Result<usize, GaussianError> {
    region.validate()?;
    check_radius("fall-off radius", falloff_radius)?;
    if !v.is_finite() {
        return Err(GaussianError::InvalidOption {
            name: "squeeze vector",
            value: v.length(),
            reason: "must be finite",
        });
    }
    let Some(dir) = v.try_normalize() else { return Ok(0) };
    let mut moved = 0;
    for g in &mut terrain.primitives {
        let c = DVec2::from(g.center);
        let f = region.inner_falloff(c, falloff_radius);
        if f <= 0.0 {
            continue;
        }
        let moved_to = c + v * f;
        let f2 = region.inner_falloff(moved_to, falloff_radius);
        let k = (f - f2 + 1.0).max(0.05);
        // Scale by k along `dir` about the new centre.
        let m = stretch_along(dir, k);
        *g = g.transformed(m, moved_to - m * c);
        moved += 1;
    }
    Ok(moved)
}

#[cfg(test)]
mod tests {
    use relief_poisson_sampling::Polygon;

    use super::*;

    /// A lasso contains exactly what the shared polygon test says, points on its edges and
    /// vertices included, and measures the same area.
    #[test]
    fn lasso_containment_and_area_are_the_polygon_ones() {
        let points: Vec<[f64; 2]> = (0..24)
            .map(|k| {
                let t = std::f64::consts::TAU * f64::from(k) / 24.0;
                let r = if k % 2 == 0 { 10.0 } else { 6.0 };
                [(r * t.cos()).round(), (r * t.sin()).round()]
            })
            .collect();
        let lasso = Region::Lasso { points: points.clone() };
        let polygon = Polygon::from_exterior(points.iter().map(|&p| DVec2::from(p)).collect()).unwrap();
        assert_eq!(lasso.area(), polygon.area());
        let mut inside = 0;
        for j in -44..=44 {
            for i in -44..=44 {
                let p = DVec2::new(f64::from(i), f64::from(j)) / 4.0;
                assert_eq!(lasso.contains(p), polygon.contains(p), "at {p}");
                inside += usize::from(lasso.contains(p));
            }
        }
        assert!(inside > 1000, "{inside}");
    }
}
