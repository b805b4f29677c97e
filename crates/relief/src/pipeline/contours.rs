//! The contours paper's generator (Huftier et al. 2025): nested regions or a label image → a
//! Poisson-sampled TIN → inward Open Eden Growth → node heights by histogram quantiles → nested
//! iso-contours → the scene's edits → a reconstructed heightfield.

use glam::DVec2;

use super::contour_input::{self, ContourInputSummary, Regrowth};
use super::contour_tools::{apply_tools, set_crater_depths};
use super::edits::{Edits, apply_edits};
use super::inputs::{Env, default_domain, raster_grid};
use super::labels::{label_map, merge_warning};
use super::progress::Timer;
use super::summary::GraphSummary;
use super::{Generated, Report};
use crate::contours::{
    ContourSet, Heights, Histogram, HistogramSpec, Interpolation, Ranking, Summit, assign_heights, extract_tin,
    reconstruct_interpolated, reconstruct_stairs, smooth_heights,
};
use crate::eden_growth::{
    CoarseOrder, EdenError, Fronts, Graph, GraphOptions, Growth, LabelMap, MaskCleaning, ProbabilityMap,
    RasterProbability, Region, RegionTree, Sampling, Uniform, grow_with,
};
use crate::error::SceneError;
use crate::heightfield::{Extent, GridSpec, Heightfield, fill_depressions};
use crate::poisson_sampling::Polygon;
use crate::scene::{ContoursGenerator, HistogramSource, Multilevel, Probability, ReconstructionMode, Scene};
use crate::tin::PointLocator;
use crate::warp::{Warp, warp_raster};
use crate::{ReliefError, ReliefError as E};

/// Default node count when a scene gives neither `particles` nor `radius`.
pub const DEFAULT_PARTICLES: usize = 50_000;

pub(super) const GENERATOR: &str = "generator.contours";

/// Everything a contour scene asks for, read and checked before the heavy work.
struct Inputs {
    source: Source,
    sampling: Sampling,
    target: Target,
    probability: Box<dyn ProbabilityMap>,
    levels: Vec<f64>,
    edits: Edits,
    grid: GridSpec,
    /// The budget's particle cap, which a radius's estimated count is checked against.
    max_particles: u64,
}

enum Source {
    Regions(RegionTree),
    Labels(LabelMap),
    /// Regions made from contour input, with what the input reported.
    Contours(RegionTree, Box<Regrowth>),
}

/// A label image's cleaning, contour input's reading, and the DEM contours came from.
type InputReport = (Option<MaskCleaning>, Option<ContourInputSummary>, Option<Box<(String, Heightfield)>>);

impl Source {
    /// What the summary reports of the inputs: a label image's cleaning, contour input's reading
    /// and the DEM it came from.
    fn into_report(self) -> InputReport {
        match self {
            Self::Labels(labels) => (labels.cleaning().cloned(), None, None),
            Self::Contours(_, regrowth) => (None, Some(regrowth.summary), regrowth.reference.map(Box::new)),
            Self::Regions(_) => (None, None, None),
        }
    }
}

/// The histogram the heights follow: the scene's, or one derived from the regions' heights once
/// the growth has measured how many nodes each level holds.
enum Target {
    Given(Histogram),
    /// The given heights as `(level, height)` from the coastline up, and the top of the last bin.
    FromHeights {
        anchors: Vec<(usize, f64)>,
        top: f64,
    },
}

/// The contour generator's run.
pub(super) fn generate(
    scene: &Scene,
    g: &ContoursGenerator,
    env: &Env<'_>,
    timer: &mut Timer<'_>,
) -> Result<Generated, ReliefError> {
    let mut inputs = timer.step("inputs", || Inputs::prepare(scene, g, env))?;
    let coarse = match &g.multilevel {
        Some(m) => Some(timer.step("coarse passes", || inputs.coarse_passes(scene.seed, m, g.fronts))?),
        None => None,
    };
    let graph = timer.step("graph", || inputs.graph(scene.seed))?;
    let growth = timer.step("growth", || inputs.grow(&graph, coarse.as_ref(), g, scene.seed))?;
    let level_ends: Vec<usize> = (1..=growth.levels()).map(|l| growth.level_range(l).end).collect();
    let histogram = inputs.target.histogram(&level_ends)?;
    let ranking =
        Ranking { order: growth.order(), level_ends: &level_ends, level_heights: &graph.level_heights()[1..] };
    let mut heights = timer.step("heights", || {
        assign_heights(graph.tin().num_points(), &ranking, &histogram)
            .map_err(|e| E::located(&format!("{GENERATOR}.histogram"), e))
    })?;
    if let Source::Regions(tree) | Source::Contours(tree, _) = &inputs.source {
        set_crater_depths(tree, &graph, &mut heights);
    }
    let sea_level = heights.level_boundaries[0];
    let mut levels = inputs.levels.clone();
    levels.extend_from_slice(&heights.level_boundaries);
    let levels = merge_levels(levels);
    let extract = |heights: &[f64]| extract_tin(graph.tin(), heights, &levels).map_err(|e| E::step("contours", e));
    if !inputs.edits.tools.is_empty() {
        let tools = inputs.edits.tools.len() as u64;
        timer.counted("tools", tools, |tick| {
            let probability = inputs.probability.as_ref();
            apply_tools(&graph, &mut heights.heights, &inputs.edits.tools, &extract, probability, scene.seed, tick)
        })?;
    }
    let contours = timer.step("contours", || extract(&heights.heights))?;
    let tolerance = graph.radius() / 20.0;
    let edit_count = inputs.edits.len() as u64;
    let contours = timer.counted("edits", edit_count, |tick| apply_edits(contours, &inputs.edits, tolerance, tick))?;
    let surface = Surface { graph: &graph, heights: &heights };
    let heightfield = timer.step("reconstruction", || inputs.reconstruct(scene, &surface, &contours, sea_level))?;
    let inside: Vec<f64> = growth.order().iter().map(|&v| heights.heights[v as usize]).collect();
    let nodes_ks = histogram.ks_distance(&inside);
    let (mask, contour_input, reference) = inputs.source.into_report();
    let warnings =
        mask.as_ref().and_then(merge_warning).into_iter().chain(fit_warning(&histogram, &ranking, nodes_ks)).collect();
    let report = Report::Contours {
        graph: GraphSummary {
            nodes: graph.tin().num_points(),
            inside: graph.inside_count(),
            radius: graph.radius(),
            filled_nodes: graph.filled_nodes(),
            levels: graph.max_level(),
        },
        nodes_ks,
        histogram,
        mask,
        contour_input,
        reference,
    };
    Ok(Generated {
        heightfield,
        sea_level: Some(sea_level),
        contours: Some(contours),
        report,
        warnings,
        vector: None,
        layers: None,
    })
}

/// Seed of the growth, decorrelated from the sampling's.
pub(super) fn growth_seed(seed: u64) -> u64 {
    seed ^ 0x9E37_79B9_7F4A_7C15
}

/// Sorted, with levels closer than a billionth of the range merged (the input contours' heights
/// win over a requested level that coincides with one).
fn merge_levels(mut levels: Vec<f64>) -> Vec<f64> {
    levels.sort_by(f64::total_cmp);
    let range = levels.last().copied().unwrap_or(0.0) - levels.first().copied().unwrap_or(0.0);
    let eps = 1e-9 * range.max(1.0);
    levels.dedup_by(|a, b| (*a - *b).abs() <= eps);
    levels
}

/// The generated TIN with its node heights: the surface the reconstruction interpolates.
struct Surface<'a> {
    graph: &'a Graph,
    heights: &'a Heights,
}

impl Inputs {
    fn prepare(scene: &Scene, g: &ContoursGenerator, env: &Env<'_>) -> Result<Self, ReliefError> {
        let sampling = sampling(g)?;
        let source = match (&g.label_image, g.regions.is_empty(), &g.contours) {
            (Some(_), false, _) => return Err(E::at(GENERATOR, SceneError::Conflict("regions", "label_image"))),
            (_, false, Some(_)) => return Err(E::at(GENERATOR, SceneError::Conflict("regions", "contours"))),
            (Some(_), _, Some(_)) => return Err(E::at(GENERATOR, SceneError::Conflict("label_image", "contours"))),
            (None, true, None) => {
                let missing = SceneError::Missing("at least one region (or `label_image`, or `contours`)");
                return Err(E::at(format!("{GENERATOR}.regions"), missing));
            }
            (None, false, None) => {
                Source::Regions(RegionTree::new(g.regions.clone()).map_err(|e| E::located(GENERATOR, e))?)
            }
            (Some(label), true, None) => Source::Labels(label_map(label, env, sampling)?),
            (None, true, Some(spec)) => {
                let regrowth = contour_input::read(spec, env, sampling)?;
                Source::Contours(contour_input::tree(&regrowth.regions)?, Box::new(regrowth))
            }
        };
        let target = match &g.histogram {
            Some(source) => Target::Given(histogram(source, env)?),
            None => Target::from_heights(&source)?,
        };
        let (min, max) = target.range();
        let levels = g.levels.resolve(min, max).map_err(|e| E::located(&format!("{GENERATOR}.levels"), e))?;
        let extent = scene.domain.unwrap_or_else(|| match &source {
            Source::Labels(l) => l.grid().extent(),
            Source::Regions(t) => default_domain(t.omega().bounds(), scene.reconstruction.resolution),
            Source::Contours(_, regrowth) => regrowth.extent,
        });
        let grid = raster_grid(scene, extent)?;
        let probability = probability(&g.probability, env, &extent, scene.seed)?;
        let edits = Edits::prepare(&scene.edits)?;
        Ok(Self { source, sampling, target, probability, levels, edits, grid, max_particles: env.budget.max_particles })
    }

    /// The growth over `graph`, steered by the last coarse pass of multi-level generation.
    fn grow(
        &self,
        graph: &Graph,
        coarse: Option<&(Graph, Growth)>,
        g: &ContoursGenerator,
        seed: u64,
    ) -> Result<Growth, ReliefError> {
        let (seed, base) = (growth_seed(seed), self.probability.as_ref());
        let grown = match (coarse, &g.multilevel) {
            (Some((cg, cgrowth)), Some(m)) => {
                let order = CoarseOrder::new(cg, cgrowth, m.contrast).map_err(|e| E::located(GENERATOR, e))?;
                grow_with(graph, &|p: DVec2| base.probability(p) * order.probability(p), seed, g.fronts)
            }
            _ => grow_with(graph, base, seed, g.fronts),
        };
        grown.map_err(|e| E::located(GENERATOR, e))
    }

    /// The coarse passes of multi-level generation, coarsest first, each steered by the one
    /// before; returns the last (finest coarse) graph and growth.
    fn coarse_passes(&self, seed: u64, m: &Multilevel, fronts: Fronts) -> Result<(Graph, Growth), ReliefError> {
        let at = format!("{GENERATOR}.multilevel");
        let fail = |e: EdenError| E::at(&at, e);
        let mut previous: Option<(Graph, Growth)> = None;
        for k in (1..m.passes).rev() {
            let scale = m.factor.powi(k as i32);
            let sampling = match self.sampling {
                Sampling::Particles(n) => Sampling::Particles(((n as f64 / scale).round() as usize).max(16)),
                Sampling::Radius(r) => Sampling::Radius(r * scale.sqrt()),
            };
            let options = self.graph_options(sampling, seed ^ u64::from(k));
            let graph = match &self.source {
                Source::Regions(tree) | Source::Contours(tree, _) => Graph::from_regions(tree, &options),
                Source::Labels(labels) => Graph::from_labels(labels, &options),
            }
            .map_err(fail)?;
            let seed = growth_seed(seed) ^ u64::from(k).wrapping_mul(0x9E37_79B9);
            let base = self.probability.as_ref();
            let growth = match &previous {
                None => grow_with(&graph, base, seed, fronts),
                Some((pg, pgrowth)) => {
                    let order = CoarseOrder::new(pg, pgrowth, m.contrast).map_err(fail)?;
                    grow_with(&graph, &|p: DVec2| base.probability(p) * order.probability(p), seed, fronts)
                }
            }
            .map_err(fail)?;
            previous = Some((graph, growth));
        }
        previous.ok_or_else(|| E::at(format!("{at}.passes"), "at least 2 passes (one coarse, then the final)"))
    }

    /// Graph options for `sampling` and `seed` under the budget's particle cap.
    fn graph_options(&self, sampling: Sampling, seed: u64) -> GraphOptions {
        GraphOptions { sampling, max_particles: self.max_particles, ..GraphOptions::particles(1).with_seed(seed) }
    }

    fn graph(&mut self, seed: u64) -> Result<Graph, ReliefError> {
        let options = self.graph_options(self.sampling, seed);
        let graph = match &mut self.source {
            Source::Regions(tree) => Graph::from_regions(tree, &options),
            Source::Labels(labels) => Graph::from_labels(labels, &options),
            Source::Contours(tree, regrowth) => return contour_graph(tree, regrowth, &options),
        };
        // The two errors whose place depends on how the scene gave its inputs.
        graph.map_err(|e| match (&e, self.sampling) {
            (EdenError::RegionTooSmall { .. } | EdenError::LevelTooSmall { .. }, _)
                if matches!(self.source, Source::Labels(_)) =>
            {
                E::at(format!("{GENERATOR}.label_image.path"), e)
            }
            (EdenError::TooManyParticles { .. } | EdenError::SparseDomain { .. }, Sampling::Radius(_)) => {
                E::at(format!("{GENERATOR}.radius"), e)
            }
            (EdenError::TooManyParticles { .. } | EdenError::SparseDomain { .. }, Sampling::Particles(_)) => {
                E::at(format!("{GENERATOR}.particles"), e)
            }
            _ => E::located(GENERATOR, e),
        })
    }

    /// The node heights of the TIN reconstruction, smoothed by the scene's smoothing edits (the
    /// other modes smooth the contours): each node kept inside its level's slice, so the input
    /// contours stay put.
    fn smoothed_nodes(&self, surface: &Surface<'_>) -> Result<Vec<f64>, ReliefError> {
        let (levels, heights) = (surface.graph.levels(), surface.heights);
        let mut out = heights.heights.clone();
        let bounds = |i: usize| {
            let h = heights.heights[i];
            match usize::from(levels[i]) {
                0 => (h, h),
                l => {
                    let lo = heights.level_boundaries[l - 1];
                    let hi = heights.level_boundaries.get(l).copied().unwrap_or(f64::INFINITY);
                    (lo.min(h), hi.max(h))
                }
            }
        };
        for s in self.edits.smoothings() {
            smooth_heights(surface.graph.tin(), &mut out, s, bounds).map_err(|e| E::step("reconstruction", e))?;
        }
        Ok(out)
    }

    /// The heightfield: terraces, Hormann's interpolation with the TIN as summit surface, or the
    /// TIN itself; warps reach the raster through the contours or by backward mapping.
    fn reconstruct(
        &self,
        scene: &Scene,
        surface: &Surface<'_>,
        contours: &ContourSet,
        sea_level: f64,
    ) -> Result<Heightfield, ReliefError> {
        let (grid, drain, outside) = (&self.grid, scene.reconstruction.drain, surface.heights.outside);
        let hf = match scene.reconstruction.mode {
            ReconstructionMode::Stairs => reconstruct_stairs(contours, grid, outside),
            ReconstructionMode::Interpolated => {
                let locator = PointLocator::new(surface.graph.tin());
                let warps = &self.edits.warps;
                let at = |p: DVec2| {
                    let q = if warps.is_empty() { p } else { warps.inverse(p) };
                    locator.interpolate(q, &surface.heights.heights).ok().flatten().unwrap_or(outside)
                };
                let options = Interpolation { summit: Summit::Surface(&at), drain };
                reconstruct_interpolated(contours, grid, outside, &options)
            }
            ReconstructionMode::Tin => return self.tin_raster(surface, contours, drain, sea_level),
        };
        hf.map_err(|e| E::step("reconstruction", e))
    }

    /// The TIN itself as the terrain: rasterized (no-data beyond its hull reads as `outside`),
    /// warped by backward mapping, and optionally drained with the sea, the border and every pit
    /// contour's inside as outlets.
    fn tin_raster(
        &self,
        surface: &Surface<'_>,
        contours: &ContourSet,
        drain: bool,
        sea_level: f64,
    ) -> Result<Heightfield, ReliefError> {
        let (grid, outside) = (&self.grid, surface.heights.outside);
        let fail = |e| E::step("reconstruction", e);
        let heights = self.smoothed_nodes(surface)?;
        let mut hf = surface.graph.tin().rasterize(&heights, grid).map_err(|e| E::step("reconstruction", e))?;
        hf.fill_no_data(outside as f32).map_err(fail)?;
        if !self.edits.warps.is_empty() {
            let source = hf;
            let samples = warp_raster(
                &self.edits.warps,
                grid.nx(),
                grid.ny(),
                |i, j| grid.position(i, j),
                |p| source.sample_bilinear_clamped(p).unwrap_or(outside as f32),
            );
            hf = Heightfield::from_samples(*grid, samples).map_err(fail)?;
        }
        if drain {
            let pits = pit_mask(contours, grid);
            let nx = grid.nx();
            let sea = sea_level as f32;
            let values = hf.samples().to_vec();
            fill_depressions(&mut hf, |i, j| {
                let k = j * nx + i;
                i == 0 || j == 0 || i + 1 == nx || j + 1 == grid.ny() || values[k] < sea || pits[k]
            });
        }
        Ok(hf)
    }
}

/// The graph over regions made from contour input: a region the sampling misses (a ring just
/// over the size cut, but thin) is dropped with what it encloses, and the graph built again.
fn contour_graph(tree: &mut RegionTree, regrowth: &mut Regrowth, options: &GraphOptions) -> Result<Graph, ReliefError> {
    const RETRIES: usize = 8;
    for _ in 0..RETRIES {
        match Graph::from_regions(tree, options) {
            Err(EdenError::RegionTooSmall { region, .. }) => {
                let inside = |mut i: usize| loop {
                    if i == region {
                        return true;
                    }
                    match tree.parent(i) {
                        Some(p) => i = p,
                        None => return false,
                    }
                };
                let kept: Vec<Region> =
                    tree.regions().iter().enumerate().filter(|&(i, _)| !inside(i)).map(|(_, r)| r.clone()).collect();
                regrowth.summary.dropped_small += tree.regions().len() - kept.len();
                regrowth.summary.regions = kept.len();
                regrowth.summary.depressions = kept.iter().filter(|r| r.depression).count();
                *tree = contour_input::tree(&kept)?;
            }
            other => return other.map_err(|e| E::at("generator.contours.contours", e)),
        }
    }
    Err(E::at("generator.contours.contours", "too many contour rings hold no graph node: raise the particle count"))
}

/// How densely the graph samples Ω: `particles` or `radius`.
fn sampling(g: &ContoursGenerator) -> Result<Sampling, ReliefError> {
    let out_of_range = |field: &str, value: String, rule| {
        E::at(format!("{GENERATOR}.{field}"), SceneError::OutOfRange { value, rule })
    };
    match (g.particles, g.radius) {
        (Some(_), Some(_)) => Err(E::at(GENERATOR, SceneError::Conflict("particles", "radius"))),
        (Some(0), None) => Err(out_of_range("particles", "0".into(), "must be at least 1")),
        (Some(n), None) => Ok(Sampling::Particles(n)),
        (None, Some(r)) if !(r.is_finite() && r > 0.0) => {
            Err(out_of_range("radius", r.to_string(), "must be finite and > 0"))
        }
        (None, Some(r)) => Ok(Sampling::Radius(r)),
        (None, None) => Ok(Sampling::Particles(DEFAULT_PARTICLES)),
    }
}

impl Target {
    /// The plan for a scene without a histogram: heights on the coastline and at least one level
    /// inside it are needed.
    fn from_heights(source: &Source) -> Result<Self, ReliefError> {
        let heights = match source {
            Source::Regions(tree) | Source::Contours(tree, _) => tree.level_heights(),
            Source::Labels(labels) => labels.level_heights(),
        };
        let anchors: Vec<(usize, f64)> =
            heights.iter().enumerate().skip(1).filter_map(|(l, h)| h.map(|h| (l, h))).collect();
        match anchors.as_slice() {
            [(1, _), .., (_, below), (_, last)] | [(1, below), (_, last)] => {
                Ok(Self::FromHeights { top: last + (last - below), anchors })
            }
            _ => Err(E::at(
                format!("{GENERATOR}.histogram"),
                SceneError::Missing(
                    "a histogram, or heights on the coastline and on a region inside it to derive one from \
                     (e.g. \"histogram\": { \"uniform\": { \"min\": 0, \"max\": 1000 } })",
                ),
            )),
        }
    }

    /// The elevations the histogram will span.
    fn range(&self) -> (f64, f64) {
        match self {
            Self::Given(h) => (h.min(), h.max()),
            Self::FromHeights { anchors, top } => (anchors[0].1, *top),
        }
    }

    /// The histogram, given the growth's level ends (`level_ends[l − 1]`: the end of level `l`'s
    /// ranks): a derived one gives each slice between given heights the share of the nodes its
    /// levels hold, so each level gets exactly its area's share.
    fn histogram(&self, level_ends: &[usize]) -> Result<Histogram, ReliefError> {
        let (anchors, top) = match self {
            Self::Given(h) => return Ok(h.clone()),
            Self::FromHeights { anchors, top } => (anchors, *top),
        };
        let total = level_ends.last().copied().unwrap_or(0);
        let start = |l: usize| if l <= 1 { 0 } else { level_ends.get(l - 2).copied().unwrap_or(total) };
        let mut edges: Vec<f64> = anchors.iter().map(|&(_, h)| h).collect();
        edges.push(top);
        let weights = (0..anchors.len())
            .map(|k| {
                let end = anchors.get(k + 1).map_or(total, |&(l, _)| start(l));
                (end - start(anchors[k].0)) as f64
            })
            .collect();
        Histogram::from_bins(edges, weights).map_err(|e| E::located(&format!("{GENERATOR}.histogram"), e))
    }
}

/// The warning for node heights far from the histogram, which happens when the given region
/// heights fix each level's share of the histogram unlike its share of the area; it names the
/// worst share and a histogram of the same shape, rescaled slice by slice, that fits.
fn fit_warning(histogram: &Histogram, ranking: &Ranking<'_>, ks: f64) -> Option<String> {
    if ks <= FIT_WARNING_KS {
        return None;
    }
    let total = ranking.order.len() as f64;
    // Each given height inside the histogram's range, with the share of the nodes below it.
    let given: Vec<(f64, f64)> = ranking
        .level_heights
        .iter()
        .enumerate()
        .filter_map(|(l, h)| h.map(|h| (h, if l == 0 { 0.0 } else { ranking.level_ends[l - 1] as f64 / total })))
        .filter(|&(h, _)| h > histogram.min() && h < histogram.max())
        .collect();
    let (worst_h, worst_below) = given
        .iter()
        .copied()
        .max_by(|a, b| (histogram.cdf(a.0) - a.1).abs().total_cmp(&(histogram.cdf(b.0) - b.1).abs()))?;
    let (edges, weights) = fitting_bins(histogram, &given);
    let list = |v: &[f64]| v.iter().map(|x| format!("{x}")).collect::<Vec<_>>().join(", ");
    Some(format!(
        "elevations deviate from the histogram (KS {ks:.3}): region heights fix each level's share of it, and the \
         {worst_h} m contour encloses {:.0} % of the land where the histogram puts {:.0} % above {worst_h} m; the same \
         shape with the regions' shares: {{ \"bins\": {{ \"edges\": [{}], \"weights\": [{}] }} }}, or leave \
         `histogram` out to derive one",
        100.0 * (1.0 - worst_below),
        100.0 * (1.0 - histogram.cdf(worst_h)),
        list(&edges),
        list(&weights)
    ))
}

/// Bins with the shape of `histogram` (its own bins, or 16 even ones) split at the `given`
/// heights, each slice between two given heights rescaled to the share of the nodes it holds;
/// weights in percent, to 0.01.
fn fitting_bins(histogram: &Histogram, given: &[(f64, f64)]) -> (Vec<f64>, Vec<f64>) {
    let (min, max) = (histogram.min(), histogram.max());
    let mut edges = match histogram.spec() {
        HistogramSpec::Bins { edges, .. } => edges.clone(),
        HistogramSpec::Uniform { .. } => vec![min, max],
        HistogramSpec::Samples(_) => (0..=16).map(|k| min + (max - min) * f64::from(k) / 16.0).collect(),
    };
    edges.extend(given.iter().map(|g| g.0));
    edges.sort_by(f64::total_cmp);
    edges.dedup();
    // Slice k spans [bounds[k], bounds[k + 1]] and should hold targets[k + 1] − targets[k].
    let mut bounds = vec![min];
    bounds.extend(given.iter().map(|g| g.0));
    bounds.push(max);
    let mut targets = vec![0.0];
    targets.extend(given.iter().map(|g| g.1));
    targets.push(1.0);
    let weights = edges
        .windows(2)
        .map(|w| {
            let k = bounds.partition_point(|&b| b <= w[0]).saturating_sub(1).min(bounds.len() - 2);
            let (lo, hi) = (bounds[k], bounds[k + 1]);
            let want = targets[k + 1] - targets[k];
            let have = histogram.cdf(hi) - histogram.cdf(lo);
            let share =
                if have > 0.0 { (histogram.cdf(w[1]) - histogram.cdf(w[0])) / have } else { (w[1] - w[0]) / (hi - lo) };
            (100.0 * want * share * 100.0).round() / 100.0
        })
        .collect();
    (edges, weights)
}

/// KS distance of the node heights above which [`fit_warning`] speaks: without explicit heights
/// they match the histogram to 1/(2N).
const FIT_WARNING_KS: f64 = 0.02;

/// The target histogram: written in the scene, or the elevations of a DEM's land (its flat sea
/// left out, as the growth makes land only: `contour_input::flat_sea`).
fn histogram(source: &HistogramSource, env: &Env<'_>) -> Result<Histogram, ReliefError> {
    match source {
        HistogramSource::Histogram(h) => Ok(h.clone()),
        HistogramSource::Dem(path) => {
            let at = format!("{GENERATOR}.histogram.dem");
            let dem = env.read(path).map_err(|e| E::at(&at, e))?;
            let sea = contour_input::flat_sea(&dem);
            let land = |v: &&f32| v.is_finite() && sea.is_none_or(|s| **v > s);
            let samples: Vec<f64> = dem.samples().iter().filter(land).map(|&v| f64::from(v)).collect();
            Histogram::from_samples(samples).map_err(|e| E::at(&at, e))
        }
    }
}

/// The probability map, seeded by the scene.
fn probability(
    p: &Probability,
    env: &Env<'_>,
    domain: &Extent,
    seed: u64,
) -> Result<Box<dyn ProbabilityMap>, ReliefError> {
    const AT: &str = "generator.contours.probability";
    Ok(match p {
        Probability::Uniform => Box::new(Uniform),
        Probability::Fbm(fbm) => Box::new(fbm.with_seed(seed)),
        Probability::Image { path, extent, exponent } => {
            let image = env.read_gray(path).map_err(|e| E::at(format!("{AT}.image.path"), e))?;
            let grid = GridSpec::from_extent(image.nx(), image.ny(), extent.unwrap_or(*domain))
                .map_err(|e| E::at(format!("{AT}.image.path"), e))?;
            let mut samples = image.into_samples();
            // Transparent pixels read as no-data; they are places the growth should not prefer.
            samples.iter_mut().filter(|v| v.is_nan()).for_each(|v| *v = 0.0);
            let field = Heightfield::from_samples(grid, samples).map_err(|e| E::step("inputs", e))?;
            Box::new(RasterProbability::new(field, *exponent).map_err(|e| E::located("generator.contours", e))?)
        }
    })
}

/// The samples inside a closed clockwise contour (around a pit).
fn pit_mask(set: &ContourSet, grid: &GridSpec) -> Vec<bool> {
    let mut mask = vec![false; grid.len()];
    for c in set.contours().iter().filter(|c| c.closed && !c.is_counter_clockwise()) {
        let Ok(polygon) = Polygon::from_exterior(c.points.clone()) else { continue };
        let b = c.bounds();
        let (lo, hi) = (grid.grid_coords(b.min).ceil(), grid.grid_coords(b.max).floor());
        let (i0, j0) = (lo.x.max(0.0) as usize, lo.y.max(0.0) as usize);
        let (i1, j1) = (hi.x.min((grid.nx() - 1) as f64), hi.y.min((grid.ny() - 1) as f64));
        if i1 < 0.0 || j1 < 0.0 {
            continue;
        }
        for j in j0..=j1 as usize {
            for i in i0..=i1 as usize {
                if polygon.contains(grid.position(i, j)) {
                    mask[grid.index(i, j)] = true;
                }
            }
        }
    }
    mask
}
