use glam::DVec2;
use relief_tin::heightfield::{GridSpec, distance_transform};
use relief_tin::poisson_sampling::{Polygon, PolygonSet, Rect};
use serde::{Deserialize, Serialize};

use crate::EdenError;
use crate::masks::{MaskCleaning, MaskOptions, clean_mask};

/// One user-drawn region: a closed contour enclosing higher ground (or, with `depression`, lower
/// ground: a crater or a lake basin).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct Region {
    /// The contour. Holes are allowed only in outermost regions (lagoons, which lie outside Ω).
    pub polygon: Polygon,
    /// Elevation of this contour; applies to every region at the same depth.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    /// Whether the region is a depression: its inside is ordered downward from its rim and is the
    /// only place an endorheic basin may appear.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub depression: bool,
    /// For a depression: how far its floor lies below its rim (default: as deep as the
    /// histogram's slice of the level around it takes it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth: Option<f64>,
}

impl Region {
    /// A raised region without explicit height.
    pub fn new(polygon: Polygon) -> Self {
        Self { polygon, height: None, depression: false, depth: None }
    }

    /// The same region with its contour at `height`.
    #[must_use]
    pub fn with_height(mut self, height: f64) -> Self {
        self.height = Some(height);
        self
    }

    /// The same region marked as a depression.
    #[must_use]
    pub fn as_depression(mut self) -> Self {
        self.depression = true;
        self
    }

    /// The same region as a depression whose floor lies `depth` below its rim.
    #[must_use]
    pub fn with_depth(mut self, depth: f64) -> Self {
        self.depression = true;
        self.depth = Some(depth);
        self
    }
}

/// Where a point falls among the regions: its level (0 outside Ω, otherwise the depth of the
/// innermost raised region containing it; inside a depression, one less than the depression's
/// parent), whether that is inside a depression, and the innermost region (if any).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Class {
    pub(crate) level: u16,
    pub(crate) depression: bool,
    pub(crate) region: Option<u32>,
}

/// Regions organised by containment: the contours paper's nested input contours Γ (§4.5).
///
/// Validated at construction: boundaries never touch or cross, holes only at depth 1, depressions
/// nested in raised regions and childless, explicit heights finite, equal per depth and increasing
/// with depth.
#[derive(Debug, Clone)]
pub struct RegionTree {
    regions: Vec<Region>,
    parent: Vec<Option<usize>>,
    children: Vec<Vec<usize>>,
    depth: Vec<u16>,
    roots: Vec<usize>,
    omega: PolygonSet,
    level_heights: Vec<Option<f64>>,
}

impl RegionTree {
    /// Builds the containment tree of `regions`.
    ///
    /// # Errors
    /// [`EdenError::NoRegions`], [`EdenError::RegionsOverlap`], [`EdenError::HoleInRaisedRegion`],
    /// [`EdenError::DepressionNotNested`], [`EdenError::DepressionWithChildren`],
    /// [`EdenError::DepressionHeight`], [`EdenError::InvalidHeight`], [`EdenError::ConflictingHeights`],
    /// [`EdenError::HeightsNotIncreasing`].
    pub fn new(regions: Vec<Region>) -> Result<Self, EdenError> {
        if regions.is_empty() {
            return Err(EdenError::NoRegions);
        }
        let all = PolygonSet::new(regions.iter().map(|r| r.polygon.clone()).collect());
        if let Some((a, b, at)) = all.first_boundary_contact() {
            return Err(EdenError::RegionsOverlap { a, b, at });
        }
        let n = regions.len();
        // Parent: the smallest region containing one of this region's vertices (boundaries are
        // disjoint, so one vertex decides containment).
        let parent: Vec<Option<usize>> = (0..n)
            .map(|i| {
                let probe = regions[i].polygon.exterior()[0];
                let bi = regions[i].polygon.bounds();
                (0..n)
                    .filter(|&j| j != i && contains_rect(&regions[j].polygon.bounds(), &bi))
                    .filter(|&j| regions[j].polygon.contains(probe))
                    .min_by(|&a, &b| regions[a].polygon.area().total_cmp(&regions[b].polygon.area()))
            })
            .collect();
        let mut depth = vec![0u16; n];
        for i in 0..n {
            let mut d = 1u16;
            let mut p = parent[i];
            while let Some(q) = p {
                d += 1;
                p = parent[q];
            }
            depth[i] = d;
        }
        let mut children = vec![Vec::new(); n];
        for (i, p) in parent.iter().enumerate() {
            if let Some(p) = *p {
                children[p].push(i);
            }
        }
        for i in 0..n {
            let r = &regions[i];
            if depth[i] >= 2 && !r.polygon.holes().is_empty() && !r.depression {
                return Err(EdenError::HoleInRaisedRegion { region: i, depth: depth[i] });
            }
            if r.depression {
                let parent_depth = parent[i].map_or(0, |p| depth[p]);
                if parent_depth < 2 {
                    return Err(EdenError::DepressionNotNested { region: i, parent_depth });
                }
                if let Some(&child) = children[i].first() {
                    return Err(EdenError::DepressionWithChildren { region: i, child });
                }
                if let Some(height) = r.height {
                    return Err(EdenError::DepressionHeight { region: i, height });
                }
            }
            if let Some(h) = r.height
                && !h.is_finite()
            {
                return Err(EdenError::InvalidHeight { region: i, value: h });
            }
            if let Some(d) = r.depth {
                let reason = match (r.depression, d.is_finite() && d > 0.0) {
                    (false, _) => Some("only a depression has a depth (set `depression: true`)"),
                    (true, false) => Some("must be finite and > 0"),
                    (true, true) => None,
                };
                if let Some(reason) = reason {
                    return Err(EdenError::InvalidDepth { region: i, value: d, reason });
                }
            }
        }
        let level_heights = level_heights(&regions, &depth)?;
        let roots: Vec<usize> = (0..n).filter(|&i| parent[i].is_none()).collect();
        let omega = PolygonSet::new(roots.iter().map(|&i| regions[i].polygon.clone()).collect());
        Ok(Self { regions, parent, children, depth, roots, omega, level_heights })
    }

    /// The regions, in input order.
    pub fn regions(&self) -> &[Region] {
        &self.regions
    }

    /// Parent of region `i` (the smallest region containing it).
    pub fn parent(&self, i: usize) -> Option<usize> {
        self.parent[i]
    }

    /// Nesting depth of region `i` (1 for outermost regions).
    pub fn depth(&self, i: usize) -> u16 {
        self.depth[i]
    }

    /// The domain Ω: the union of the outermost regions.
    pub fn omega(&self) -> &PolygonSet {
        &self.omega
    }

    /// Explicit contour height per level (index 0 unused).
    pub fn level_heights(&self) -> &[Option<f64>] {
        &self.level_heights
    }

    /// The deepest level a node can have.
    pub fn max_level(&self) -> u16 {
        self.regions.iter().zip(&self.depth).filter(|(r, _)| !r.depression).map(|(_, &d)| d).max().unwrap_or(0)
    }

    /// Classifies `p` by descending the containment tree.
    pub(crate) fn classify(&self, p: DVec2) -> Class {
        let contains = |i: usize| self.regions[i].polygon.bounds().contains(p) && self.regions[i].polygon.contains(p);
        let Some(mut current) = self.roots.iter().copied().find(|&i| contains(i)) else {
            return Class { level: 0, depression: false, region: None };
        };
        while let Some(&child) = self.children[current].iter().find(|&&c| contains(c)) {
            current = child;
        }
        let region = Some(current as u32);
        if self.regions[current].depression {
            let parent_depth = self.parent[current].map_or(1, |q| self.depth[q]);
            Class { level: parent_depth - 1, depression: true, region }
        } else {
            Class { level: self.depth[current], depression: false, region }
        }
    }
}

fn contains_rect(outer: &Rect, inner: &Rect) -> bool {
    outer.min.x <= inner.min.x && outer.min.y <= inner.min.y && outer.max.x >= inner.max.x && outer.max.y >= inner.max.y
}

/// Heights per depth level from the regions that give one: equal within a level, increasing with
/// depth.
fn level_heights(regions: &[Region], depth: &[u16]) -> Result<Vec<Option<f64>>, EdenError> {
    let max = depth.iter().copied().max().unwrap_or(0) as usize;
    let mut heights: Vec<Option<(usize, f64)>> = vec![None; max + 1];
    for (i, r) in regions.iter().enumerate() {
        let (Some(h), false) = (r.height, r.depression) else { continue };
        let d = depth[i] as usize;
        match heights[d] {
            Some((a, ha)) if ha != h => {
                return Err(EdenError::ConflictingHeights { depth: d as u16, a, height_a: ha, b: i, height_b: h });
            }
            _ => heights[d] = Some((i, h)),
        }
    }
    let mut last: Option<(u16, f64)> = None;
    for (d, h) in heights.iter().enumerate() {
        if let Some((_, h)) = *h {
            if let Some((ld, lh)) = last
                && h <= lh
            {
                return Err(EdenError::HeightsNotIncreasing {
                    depth: d as u16,
                    height: h,
                    lower_depth: ld,
                    lower_height: lh,
                });
            }
            last = Some((d as u16, h));
        }
    }
    Ok(heights.into_iter().map(|h| h.map(|(_, h)| h)).collect())
}

/// A raster of region depths: the contours paper's input maps (0 = outside Ω, each higher value
/// one nested level). Nodes take the depth of their nearest pixel.
#[derive(Debug, Clone)]
pub struct LabelMap {
    grid: GridSpec,
    depth: Vec<u16>,
    allow_depressions: bool,
    /// Per pixel, whether it lies in a depression a colour table marks (empty when none does).
    depression: Vec<bool>,
    /// Contour height per depth, from a colour table (index 0 unused).
    level_heights: Vec<Option<f64>>,
    /// What cleaning a drawn mask changed, for maps built by [`LabelMap::from_mask`].
    cleaning: Option<MaskCleaning>,
    /// Distance from every pixel to the nearest pixel of Ω (depth ≥ 1), world units.
    distance: Vec<f64>,
    max_level: u16,
}

/// The most distinct levels a label map may have; more means it is not a label map.
pub const MAX_LABEL_LEVELS: usize = 255;

impl LabelMap {
    /// A label map of per-pixel depths over `grid` (row 0 = south, as every relief grid).
    ///
    /// # Errors
    /// [`EdenError::InvalidLabelMap`] when the sizes disagree or no pixel has depth ≥ 1.
    pub fn new(grid: GridSpec, depth: Vec<u16>) -> Result<Self, EdenError> {
        if depth.len() != grid.len() {
            return Err(EdenError::InvalidLabelMap {
                reason: format!("{} depths for a {}x{} grid", depth.len(), grid.nx(), grid.ny()),
            });
        }
        let inside: Vec<bool> = depth.iter().map(|&d| d >= 1).collect();
        if !inside.iter().any(|&b| b) {
            return Err(EdenError::InvalidLabelMap { reason: "no pixel is inside a region (all depths are 0)".into() });
        }
        let distance = distance_transform(&grid, &inside);
        let max_level = depth.iter().copied().max().unwrap_or(0);
        let level_heights = vec![None; max_level as usize + 1];
        Ok(Self {
            grid,
            depth,
            allow_depressions: false,
            depression: Vec::new(),
            level_heights,
            cleaning: None,
            distance,
            max_level,
        })
    }

    /// A label map from gray values (e.g. an image read as `[0, 1]`): the distinct values, sorted,
    /// become depths 0, 1, 2, … — the lowest value is outside Ω. NaN counts as outside.
    ///
    /// # Errors
    /// [`EdenError::InvalidLabelMap`] when there are more than [`MAX_LABEL_LEVELS`] distinct values
    /// (a continuous image, not a label map), fewer than two, or the sizes disagree.
    pub fn from_values(grid: GridSpec, values: &[f32]) -> Result<Self, EdenError> {
        let mut distinct: Vec<f32> = values.iter().copied().filter(|v| !v.is_nan()).collect();
        distinct.sort_by(f32::total_cmp);
        distinct.dedup();
        if distinct.len() > MAX_LABEL_LEVELS + 1 {
            return Err(EdenError::InvalidLabelMap {
                reason: format!(
                    "{} distinct values; a label map has at most {} (is this a continuous image?)",
                    distinct.len(),
                    MAX_LABEL_LEVELS + 1
                ),
            });
        }
        if distinct.len() < 2 {
            return Err(EdenError::InvalidLabelMap {
                reason: "fewer than two distinct values: no region to grow".into(),
            });
        }
        let depth =
            values.iter().map(|v| if v.is_nan() { 0 } else { distinct.partition_point(|d| d < v) as u16 }).collect();
        Self::new(grid, depth)
    }

    /// A label map from a mask drawn in a paint program: RGBA pixels in [0, 1] (row 0 south), with
    /// edge blends snapped, specks merged and an optional colour table giving heights and
    /// depressions (see [`MaskOptions`] for the steps). [`LabelMap::cleaning`] tells what
    /// changed.
    ///
    /// # Errors
    /// [`EdenError::InvalidLabelMap`] naming the problem (no region, a colour the table lacks, a
    /// misplaced depression, heights not increasing), or a sampling error.
    pub fn from_mask(grid: GridSpec, rgba: &[[f32; 4]], options: &MaskOptions) -> Result<Self, EdenError> {
        let clean = clean_mask(&grid, rgba, options)?;
        let mut map = Self::new(grid, clean.depth)?;
        if clean.depression.iter().any(|&d| d) {
            map.depression = clean.depression;
        }
        map.level_heights = clean.level_heights;
        map.level_heights.resize(map.max_level as usize + 1, None);
        map.cleaning = Some(clean.cleaning);
        Ok(map)
    }

    /// What cleaning the mask changed (for maps from [`LabelMap::from_mask`]).
    pub fn cleaning(&self) -> Option<&MaskCleaning> {
        self.cleaning.as_ref()
    }

    /// Contour height per depth a colour table gave (index 0 unused).
    pub fn level_heights(&self) -> &[Option<f64>] {
        &self.level_heights
    }

    /// The same map with enclosed areas of lower depth (craters drawn as a lower label inside a
    /// higher one) kept as depressions instead of being filled.
    #[must_use]
    pub fn with_depressions(mut self, allow: bool) -> Self {
        self.allow_depressions = allow;
        self
    }

    /// Whether enclosed lower areas are kept as depressions.
    pub fn allows_depressions(&self) -> bool {
        self.allow_depressions
    }

    /// The raster geometry.
    pub fn grid(&self) -> &GridSpec {
        &self.grid
    }

    /// The deepest level.
    pub fn max_level(&self) -> u16 {
        self.max_level
    }

    /// Per-pixel depths, row-major.
    pub(crate) fn depths(&self) -> &[u16] {
        &self.depth
    }

    /// Area of Ω (pixels of depth ≥ 1 times the cell area).
    pub fn omega_area(&self) -> f64 {
        let c = self.grid.cell_size();
        self.depth.iter().filter(|&&d| d >= 1).count() as f64 * c.x * c.y
    }

    /// Bounding rectangle of Ω's pixels.
    pub fn omega_bounds(&self) -> Rect {
        let mut b = Rect::bounding(&[]);
        for (k, _) in self.depth.iter().enumerate().filter(|(_, d)| **d >= 1) {
            let (i, j) = self.grid.coords(k);
            let p = self.grid.position(i, j);
            b = b.union(&Rect::new(p, p));
        }
        let half = 0.5 * self.grid.cell_size();
        Rect::new(b.min - half, b.max + half)
    }

    /// Nearest pixel of `p`, clamped into the raster, and how far `p` lies outside the raster.
    fn pixel(&self, p: DVec2) -> (usize, f64) {
        let ext = self.grid.extent();
        let q = p.clamp(ext.min, ext.max);
        let g = self.grid.grid_coords(q).round();
        let k = self.grid.index(g.x as usize, g.y as usize);
        (k, p.distance(q))
    }

    /// Depth at `p`: that of its nearest pixel, 0 outside the raster.
    pub fn depth_at(&self, p: DVec2) -> u16 {
        self.depth_beyond(p, 0.0)
    }

    /// Depth at `p` when the map's edge pixels continue `open` beyond the raster: that of its
    /// nearest pixel up to that far out, 0 farther. Land that reaches the image's edge is then
    /// cut by the frame rather than ending there: its coast lies `open` beyond the edge.
    pub(crate) fn depth_beyond(&self, p: DVec2, open: f64) -> u16 {
        let (k, outside) = self.pixel(p);
        if outside > open { 0 } else { self.depth[k] }
    }

    /// Whether `p` falls in a depression a colour table marks, the edge pixels continuing `open`
    /// beyond the raster as in [`LabelMap::depth_beyond`].
    pub(crate) fn depression_at(&self, p: DVec2, open: f64) -> bool {
        let (k, outside) = self.pixel(p);
        outside <= open && self.depression.get(k).copied().unwrap_or(false)
    }

    /// The widest disc inside level `l`'s pixels: the largest distance from one of them to a pixel
    /// of another level (0 when the map has none).
    pub(crate) fn inscribed_radius(&self, l: u16) -> f64 {
        let other: Vec<bool> = self.depth.iter().map(|&d| d != l).collect();
        let distance = distance_transform(&self.grid, &other);
        self.depth.iter().zip(&distance).filter(|(d, _)| **d == l).map(|(_, &r)| r).fold(0.0, f64::max)
    }

    /// Whether `p` lies within `margin` of Ω (by the pixel distance transform, so to within half a
    /// pixel diagonal).
    pub(crate) fn near_omega(&self, p: DVec2, margin: f64) -> bool {
        let (k, outside) = self.pixel(p);
        self.distance[k] + outside <= margin
    }
}
