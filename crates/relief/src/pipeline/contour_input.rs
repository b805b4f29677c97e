//! Contours as a contour scene's input (the contours paper's Fig. 2 loop and Fig. 24): a DEM's,
//! extracted at an interval or at given heights and closed along its border, or a GeoJSON's (a
//! previous run's `contours.geojson`, `gdal_contour` lines or polygons). Every closed contour
//! becomes a nested region at its height, pits become depressions, and rings too small for the
//! sampling are dropped (and counted).

use std::path::Path;

use glam::DVec2;
use serde::Serialize;

use super::inputs::Env;
use crate::contours::{Contour, ContourSet, extract_dem};
use crate::eden_growth::{Region, RegionTree, Sampling};
use crate::error::SceneError;
use crate::heightfield::{Extent, Heightfield};
use crate::hydrology::{DescriptorDistance, DescriptorOptions, Descriptors};
use crate::orometry::{AnalysisOptions, analyze};
use crate::poisson_sampling::{Polygon, Rect, radius_for_count};
use crate::scene::ContourInput;
use crate::{ReliefError, ReliefError as E};

const AT: &str = "generator.contours.contours";

/// What reading contour input did (`summary.json`'s `contour_input`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContourInputSummary {
    /// The file the contours came from.
    pub source: String,
    /// Their heights, ascending.
    pub heights: Vec<f64>,
    /// Closed contours after closing those the border cut.
    pub contours: usize,
    /// Contours the border cut, closed along it.
    pub closed_at_border: usize,
    /// Regions the growth starts from (raised and depressions).
    pub regions: usize,
    /// Of which depressions (pits).
    pub depressions: usize,
    /// Rings dropped as smaller than the sampling holds (with what they enclosed).
    pub dropped_small: usize,
    /// Pit rings dropped because a depression can only sit in a raised region above the coast,
    /// with what they enclosed.
    pub dropped_pits: usize,
}

/// Contour input made into regions.
pub(super) struct Regrowth {
    /// The regions, validated.
    pub(super) regions: Vec<Region>,
    /// The map the contours cover: the output domain unless the scene sets one.
    pub(super) extent: Extent,
    /// The DEM the contours came from, to compare the result with.
    pub(super) reference: Option<(String, Heightfield)>,
    pub(super) summary: ContourInputSummary,
}

/// Reads and closes a scene's contour input and makes it regions for `sampling`.
pub(super) fn read(spec: &ContourInput, env: &Env<'_>, sampling: Sampling) -> Result<Regrowth, ReliefError> {
    let (set, rect, source, reference, open) = match (&spec.dem, &spec.geojson) {
        (Some(_), Some(_)) => return Err(E::at(AT, SceneError::Conflict("dem", "geojson"))),
        (None, None) => return Err(E::at(AT, SceneError::Missing("`dem` or `geojson`"))),
        (Some(path), None) => {
            let dem = env.read(path).map_err(|e| E::at(format!("{AT}.dem"), e))?;
            let (set, open) = dem_contours(&dem, spec)?;
            let rect = Rect::new(dem.grid().extent().min, dem.grid().extent().max);
            (set, rect, path, Some(dem), open)
        }
        (None, Some(path)) => {
            let (set, rect) = geojson_contours(env, path, spec.property.as_deref())?;
            let open = set.contours().iter().filter(|c| !c.closed).count();
            let set = if open > 0 { close(&set, rect, None)? } else { set };
            (oriented(&set)?, rect, path, None, open)
        }
    };
    let omega: f64 =
        (0..set.len()).filter(|&k| set.parent(k).is_none()).map(|k| set.contours()[k].signed_area().abs()).sum();
    let radius = match sampling {
        // No area (no closed ring): no size cut; the empty region list is refused below.
        Sampling::Particles(n) => radius_for_count(omega, n).unwrap_or(0.0),
        Sampling::Radius(r) => r,
    };
    let (regions, mut summary) = regions(&set, std::f64::consts::PI * radius * radius);
    summary.source = source.display().to_string();
    summary.closed_at_border = open;
    if regions.is_empty() {
        return Err(E::at(AT, SceneError::Missing("a closed contour the sampling can hold (all were too small)")));
    }
    let extent = Extent::new(rect.min, rect.max);
    Ok(Regrowth { regions, extent, reference: reference.map(|d| (summary.source.clone(), d)), summary })
}

/// Share of a DEM's samples at exactly its lowest elevation from which that elevation is sea: a
/// flat minimum is how DEMs store the sea (0, or a fill value), where real ground at its lowest
/// touches a few samples only.
const FLAT_SEA_SHARE: f64 = 0.01;

/// The DEM's lowest elevation when it is flat sea: held by at least [`FLAT_SEA_SHARE`] of its
/// valid samples.
pub(super) fn flat_sea(dem: &Heightfield) -> Option<f32> {
    let (min, _) = dem.min_max()?;
    let valid = dem.samples().iter().filter(|v| v.is_finite()).count();
    let at_min = dem.samples().iter().filter(|&&v| v == min).count();
    (at_min as f64 >= FLAT_SEA_SHARE * valid as f64).then_some(min)
}

/// A DEM's contours at the scene's heights (or interval), closed along its border, and how many
/// the border cut. With an interval, the coast is the lowest elevation (the whole map land), or
/// where that is flat sea ([`flat_sea`]) the lowest land elevation, so the sea stays outside and
/// the coast is the lowest height of the land's histogram.
fn dem_contours(dem: &Heightfield, spec: &ContourInput) -> Result<(ContourSet, usize), ReliefError> {
    let (min, max) = match dem.min_max() {
        Some((lo, hi)) if lo < hi => (f64::from(lo), f64::from(hi)),
        _ => return Err(E::at(format!("{AT}.dem"), SceneError::Missing("a DEM with more than one elevation"))),
    };
    let levels = match (spec.interval, &spec.heights) {
        (Some(_), Some(_)) => return Err(E::at(AT, SceneError::Conflict("interval", "heights"))),
        (None, Some(heights)) => given_heights(heights)?,
        (interval, None) => {
            let step = interval.unwrap_or_else(|| nice_step((max - min) / 10.0));
            if !(step.is_finite() && step > 0.0) {
                let rule = "must be finite and > 0";
                return Err(E::at(format!("{AT}.interval"), SceneError::OutOfRange { value: step.to_string(), rule }));
            }
            // The coast at the lowest elevation (samples at a level count as above it), so the
            // whole map is land; at the lowest land elevation when the lowest is flat sea, so the
            // sea stays outside.
            let coast = match flat_sea(dem) {
                Some(sea) => dem.samples().iter().filter(|&&v| v > sea).fold(f32::INFINITY, |m, &v| m.min(v)),
                None => min as f32,
            };
            let coast = f64::from(coast);
            let mut levels = vec![coast];
            let first = (coast / step).floor() as i64 + 1;
            levels.extend((first..).map(|k| k as f64 * step).take_while(|&h| h < max));
            levels
        }
    };
    let set = extract_dem(dem, &levels).map_err(|e| E::at(format!("{AT}.dem"), e))?;
    let open = set.contours().iter().filter(|c| !c.closed).count();
    let grid = dem.grid();
    let (nx, ny) = (grid.nx(), grid.ny());
    let border_min = (0..nx * ny)
        .filter(|k| k % nx == 0 || k % nx == nx - 1 || k / nx == 0 || k / nx == ny - 1)
        .map(|k| dem.samples()[k])
        .filter(|v| v.is_finite())
        .fold(f64::INFINITY, |m, v| m.min(f64::from(v)));
    // Lines reach the raster's outer edge, half a cell beyond its samples.
    let half = 0.5 * grid.cell_size();
    let rect = Rect::new(grid.extent().min - half, grid.extent().max + half);
    Ok((close(&set, rect, Some(border_min))?, open))
}

fn close(set: &ContourSet, rect: Rect, border_min: Option<f64>) -> Result<ContourSet, ReliefError> {
    set.closed_at_border(rect, border_min).map_err(|e| E::at(AT, e))
}

/// Heights given in the scene: finite, sorted, distinct.
fn given_heights(heights: &[f64]) -> Result<Vec<f64>, ReliefError> {
    if let Some(h) = heights.iter().find(|h| !h.is_finite()) {
        return Err(E::at(format!("{AT}.heights"), SceneError::OutOfRange { value: h.to_string(), rule: "finite" }));
    }
    if heights.is_empty() {
        return Err(E::at(format!("{AT}.heights"), SceneError::Missing("at least one height")));
    }
    let mut out = heights.to_vec();
    out.sort_by(f64::total_cmp);
    out.dedup();
    Ok(out)
}

/// 1, 2 or 5 times a power of ten, the nearest above `raw`.
fn nice_step(raw: f64) -> f64 {
    let power = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * power).find(|&s| s >= raw).unwrap_or(10.0 * power)
}

/// The contours of a GeoJSON file and the rectangle they span.
fn geojson_contours(env: &Env<'_>, path: &Path, property: Option<&str>) -> Result<(ContourSet, Rect), ReliefError> {
    let at = format!("{AT}.geojson");
    let doc: serde_json::Value = env.read_json(path, &at)?;
    let invalid = |what: String| E::at(&at, format!("the file needs {what}"));
    let features =
        doc.get("features").and_then(|f| f.as_array()).ok_or_else(|| invalid("a FeatureCollection".into()))?;
    let mut lines: Vec<(f64, Vec<DVec2>, bool)> = Vec::new();
    for (k, feature) in features.iter().enumerate() {
        let props = feature.get("properties");
        let names: Vec<&str> = match property {
            Some(p) => vec![p],
            None => vec!["elevation", "ELEV", "elev", "height", "z"],
        };
        let height = names
            .iter()
            .find_map(|n| props.and_then(|p| p.get(*n)).and_then(serde_json::Value::as_f64))
            .ok_or_else(|| invalid(format!("an elevation property ({}) on feature {k}", names.join(", "))))?;
        let geometry = feature.get("geometry").ok_or_else(|| invalid(format!("a geometry on feature {k}")))?;
        for (points, polygon) in geometry_lines(geometry) {
            let mut points = points.map_err(|e| invalid(format!("feature {k}: {e}")))?;
            let closed = polygon || (points.len() > 3 && points.first() == points.last());
            if closed && points.first() == points.last() {
                points.pop();
            }
            if points.len() >= if closed { 3 } else { 2 } {
                lines.push((height, points, closed));
            }
        }
    }
    if lines.is_empty() {
        return Err(invalid("at least one contour line or polygon".into()));
    }
    let mut levels: Vec<f64> = lines.iter().map(|l| l.0).collect();
    levels.sort_by(f64::total_cmp);
    levels.dedup();
    let all: Vec<DVec2> = lines.iter().flat_map(|l| l.1.iter().copied()).collect();
    let contours = lines
        .into_iter()
        .map(|(height, points, closed)| {
            let level = levels.partition_point(|&l| l < height) as u32;
            Contour { level, height, points, closed }
        })
        .collect();
    let set = ContourSet::new(levels, contours).map_err(|e| E::at(&at, e))?;
    Ok((set, Rect::bounding(&all)))
}

/// The rings and lines of a GeoJSON geometry (a polygon's exterior rings flagged closed).
fn geometry_lines(geometry: &serde_json::Value) -> Vec<(Result<Vec<DVec2>, String>, bool)> {
    let coords = geometry.get("coordinates");
    let line = |v: Option<&serde_json::Value>| -> Result<Vec<DVec2>, String> {
        let array = v.and_then(|v| v.as_array()).ok_or("coordinates are not an array")?;
        array
            .iter()
            .map(|p| {
                match p.as_array().map(|a| {
                    (a.first().and_then(serde_json::Value::as_f64), a.get(1).and_then(serde_json::Value::as_f64))
                }) {
                    Some((Some(x), Some(y))) if x.is_finite() && y.is_finite() => Ok(DVec2::new(x, y)),
                    _ => Err(format!("{p} is not a position")),
                }
            })
            .collect()
    };
    let items = |v: Option<&serde_json::Value>| v.and_then(|v| v.as_array()).cloned().unwrap_or_default();
    match geometry.get("type").and_then(|t| t.as_str()) {
        Some("LineString") => vec![(line(coords), false)],
        Some("MultiLineString") => items(coords).iter().map(|l| (line(Some(l)), false)).collect(),
        Some("Polygon") => items(coords).first().map(|r| vec![(line(Some(r)), true)]).unwrap_or_default(),
        Some("MultiPolygon") => {
            items(coords).iter().filter_map(|p| p.as_array()?.first().map(|r| (line(Some(r)), true))).collect()
        }
        other => vec![(Err(format!("geometry type {other:?} is not a line or polygon")), false)],
    }
}

/// The set with each closed ring turned counter-clockwise around higher ground: a ring above its
/// parent (or without one) is raised, one below it a pit, one at its parent's height keeps the
/// file's orientation (clockwise for a pit, as relief writes them).
fn oriented(set: &ContourSet) -> Result<ContourSet, ReliefError> {
    let contours = set
        .contours()
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let parent = set.parent(k).map(|p| set.contours()[p].height);
            let raised = match parent {
                None => true,
                Some(h) if c.height != h => c.height > h,
                Some(_) => c.is_counter_clockwise(),
            };
            let mut c = c.clone();
            if c.closed && raised != c.is_counter_clockwise() {
                c.points.reverse();
            }
            c
        })
        .collect();
    ContourSet::new(set.levels().to_vec(), contours).map_err(|e| E::at(AT, e))
}

/// What each closed contour becomes.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    /// A raised region at this depth among raised regions.
    Raised(u16),
    Depression,
    Dropped,
}

/// The regions of a closed, oriented set: counter-clockwise rings raised at their height,
/// clockwise ones depressions inside a raised region of depth ≥ 2; rings under `min_area` and
/// anything inside a dropped ring or a pit are dropped.
fn regions(set: &ContourSet, min_area: f64) -> (Vec<Region>, ContourInputSummary) {
    let n = set.len();
    let depth: Vec<usize> = (0..n).map(|k| std::iter::successors(set.parent(k), |&q| set.parent(q)).count()).collect();
    let mut order: Vec<usize> = (0..n).filter(|&k| set.contours()[k].closed).collect();
    order.sort_by_key(|&k| (depth[k], k));
    let mut kind = vec![Kind::Dropped; n];
    let mut summary = ContourInputSummary {
        source: String::new(),
        heights: set.levels().to_vec(),
        contours: order.len(),
        closed_at_border: 0,
        regions: 0,
        depressions: 0,
        dropped_small: 0,
        dropped_pits: 0,
    };
    let mut regions = Vec::new();
    for k in order {
        let c = &set.contours()[k];
        let parent = set.parent(k).map(|p| kind[p]);
        let parent_depth = match parent {
            None => 0,
            Some(Kind::Raised(d)) => d,
            Some(_) => continue, // inside a pit or a dropped ring: dropped with it
        };
        let polygon = Polygon::from_exterior(c.points.clone()).ok().filter(|_| c.signed_area().abs() >= min_area);
        let Some(polygon) = polygon else {
            summary.dropped_small += 1;
            continue;
        };
        if c.is_counter_clockwise() {
            kind[k] = Kind::Raised(parent_depth + 1);
            regions.push(Region::new(polygon).with_height(c.height));
        } else if parent_depth >= 2 {
            kind[k] = Kind::Depression;
            regions.push(Region::new(polygon).as_depression());
            summary.depressions += 1;
        } else {
            summary.dropped_pits += 1;
        }
    }
    summary.regions = regions.len();
    (regions, summary)
}

/// The region tree of contour input, dropping (and counting) regions the graph finds empty.
pub(super) fn tree(regions: &[Region]) -> Result<RegionTree, ReliefError> {
    RegionTree::new(regions.to_vec()).map_err(|e| E::at(AT, e))
}

/// The §6.5 comparison of a regrown terrain with the DEM its contours came from (the contours
/// paper's Fig. 28): descriptor distances, river network order, slopes and peak counts, the DEM
/// resampled onto the terrain's grid first ("a resolution comparable to ours").
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Comparison {
    /// The DEM compared with.
    pub dem: String,
    /// Earth mover's distances of the elevation (m), slope (°) and log₁₀ drainage-area (MFD)
    /// histograms, and the DEM's maximum Strahler order minus ours.
    pub distance: DescriptorDistance,
    /// Maximum Strahler order of the D8 stream network, ours then the DEM's (same threshold).
    pub max_strahler: [u8; 2],
    /// Mean slope in degrees, ours then the DEM's.
    pub mean_slope_deg: [f64; 2],
    /// Peaks at least this prominent (1, 3 and 10 % of the DEM's relief), ours then the DEM's.
    pub peaks: Vec<PeakCount>,
    /// Root mean square of ours minus the DEM, metres, over every sample both have.
    pub rmse_m: f64,
    /// The same over the DEM's land (above its flat sea, [`flat_sea`]; every sample when it has
    /// none): how far the regrown land is from the land it was drawn from.
    pub land_rmse_m: f64,
    /// Share of the samples that are land (above the DEM's flat sea, or above the lowest
    /// elevation when it has none), ours then the DEM's.
    pub land_share: [f64; 2],
}

/// How many peaks two terrains have above a prominence.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PeakCount {
    /// The prominence threshold, m.
    pub min_prominence: f64,
    /// Ours, then the DEM's.
    pub peaks: [usize; 2],
}

/// Compares `ours` with `dem` (called `name`).
pub(super) fn compare(ours: &Heightfield, name: &str, dem: &Heightfield) -> Result<Comparison, ReliefError> {
    let fail = |e: Box<dyn std::error::Error + Send + Sync>| E::step("comparison", e);
    // Both on our grid, in the DEM's units (a geographic DEM is measured in metres by the
    // descriptors, so ours must say it is geographic too).
    let grid = ours.grid().with_units(dem.grid().units()).map_err(|e| fail(e.into()))?;
    let samples = (0..grid.len())
        .map(|k| dem.sample_bilinear_clamped(grid.position(k % grid.nx(), k / grid.nx())).unwrap_or(f32::NAN))
        .collect();
    let reference = Heightfield::from_samples(grid, samples).map_err(|e| fail(e.into()))?;
    let ours = &Heightfield::from_samples(grid, ours.samples().to_vec()).map_err(|e| fail(e.into()))?;
    let theirs = Descriptors::of(&reference, &DescriptorOptions::default()).map_err(|e| fail(e.into()))?;
    let options = DescriptorOptions { stream_area_m2: Some(theirs.stream_area_m2), ..DescriptorOptions::default() };
    let mine = Descriptors::of(ours, &options).map_err(|e| fail(e.into()))?;
    let relief = theirs.elevation.edges().last().unwrap_or(0.0) - theirs.elevation.edges().next().unwrap_or(0.0);
    let thresholds = [0.01, 0.03, 0.1].map(|f| (f * relief).round().max(1.0));
    let prominences = |hf: &Heightfield| -> Result<Vec<f64>, ReliefError> {
        let options = AnalysisOptions { min_prominence: thresholds[0], ..AnalysisOptions::default() };
        Ok(analyze(hf, &options).map_err(|e| fail(e.into()))?.peaks.iter().map(|p| p.prominence).collect())
    };
    let (p_ours, p_dem) = (prominences(ours)?, prominences(&reference)?);
    let count = |p: &[f64], t: f64| p.iter().filter(|&&x| x >= t).count();
    let (rmse_m, land_rmse_m, land_share) = differences(ours, &reference, flat_sea(dem));
    Ok(Comparison {
        rmse_m,
        land_rmse_m,
        land_share,
        dem: name.to_owned(),
        distance: mine.distance(&theirs),
        max_strahler: [mine.max_strahler, theirs.max_strahler],
        mean_slope_deg: [mean_slope(&mine), mean_slope(&theirs)],
        peaks: thresholds
            .iter()
            .map(|&t| PeakCount { min_prominence: t, peaks: [count(&p_ours, t), count(&p_dem, t)] })
            .collect(),
    })
}

/// RMSE of `ours − dem` over every sample both have and over the DEM's land (above `sea`, or
/// above the DEM's lowest sample without one), and each one's share of land samples.
fn differences(ours: &Heightfield, dem: &Heightfield, sea: Option<f32>) -> (f64, f64, [f64; 2]) {
    let coast = sea.unwrap_or_else(|| dem.min_max().map_or(f32::INFINITY, |(lowest, _)| lowest));
    let (mut all, mut land) = ((0.0, 0usize), (0.0, 0usize));
    let (mut our_land, mut dem_land, mut both) = (0usize, 0usize, 0usize);
    for (&a, &b) in ours.samples().iter().zip(dem.samples()) {
        if !(a.is_finite() && b.is_finite()) {
            continue;
        }
        let d2 = f64::from(a - b).powi(2);
        all = (all.0 + d2, all.1 + 1);
        both += 1;
        our_land += usize::from(a > coast);
        if b > coast {
            land = (land.0 + d2, land.1 + 1);
            dem_land += 1;
        }
    }
    let root = |(sum, n): (f64, usize)| if n == 0 { 0.0 } else { (sum / n as f64).sqrt() };
    let share = |k: usize| if both == 0 { 0.0 } else { k as f64 / both as f64 };
    (root(all), root(land), [share(our_land), share(dem_land)])
}

/// Mean slope in degrees, from a descriptor's slope histogram (bin centres).
fn mean_slope(d: &Descriptors) -> f64 {
    let h = &d.slope_deg;
    let width = (h.hi - h.lo) / h.counts.len() as f64;
    let sum: f64 = h.counts.iter().enumerate().map(|(b, &c)| (h.lo + width * (b as f64 + 0.5)) * c as f64).sum();
    sum / h.total().max(1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heightfield::GridSpec;

    /// 100 samples, `at_min` of them at the lowest elevation 0 m, the rest land from 5 m up.
    fn dem(at_min: usize) -> Heightfield {
        let grid = GridSpec::new(10, 10, DVec2::ZERO, DVec2::ONE).unwrap();
        let samples = (0..100).map(|k| if k < at_min { 0.0 } else { 5.0 + k as f32 }).collect();
        Heightfield::from_samples(grid, samples).unwrap()
    }

    #[test]
    fn a_minimum_on_a_hundredth_of_the_samples_is_flat_sea() {
        assert_eq!(flat_sea(&dem(1)), Some(0.0));
        assert_eq!(flat_sea(&dem(40)), Some(0.0));
        // Real ground: its lowest point is one sample in a thousand, say.
        let grid = GridSpec::new(40, 25, DVec2::ZERO, DVec2::ONE).unwrap();
        let ground = Heightfield::from_samples(grid, (0..1000).map(|k| k as f32).collect()).unwrap();
        assert_eq!(flat_sea(&ground), None);
    }
}
