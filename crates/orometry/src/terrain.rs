//! Terrain from a divide tree (§6): rivers as the dual of the ridges, a refined ridge and river
//! network, Poisson-disc fill with the valley-width interpolation, a constrained Delaunay TIN
//! rasterized to the grid, multi-fractal noise below the prominence threshold, and stream-power
//! erosion with the uplift compensation that keeps peaks and saddles at their heights.
//!
//! How each step is realized (the paper leaves these open):
//! - **River network (§6.1).** The Voronoi dual of the refined ridges, pruned where it would
//!   cross them (module `rivers`): river nodes at the circumcentres of a constrained Delaunay
//!   triangulation of the ridge nodes and of sites in open country, each bounded under the tree's
//!   col between the ridges around it; a priority flood from the map's edge orients it into a
//!   drainage tree, and Flint's law on its catchments sets the river profiles. Channels draining
//!   at least [`TerrainOptions::river_area_km2`] are rivers.
//! - **Refinement (§6.2).** Ridge and river segments are split to lengths below λ with sideways
//!   jitter, heights linear along the original segment.
//! - **Fill.** Poisson-disc samples at radius λ get `h = (1 − α)h(q) + α·h(r)`,
//!   `α = d_T / (d_R + d_T − w)`, and the river's height within the valley width
//!   `w = c·(A / 1 km²)^0.4`.
//! - **Noise (§6.3).** fBm whose amplitude grows with height (a multi-fractal), at most
//!   [`TerrainOptions::noise_m`], faded to zero at peaks and saddles so they keep their heights.
//! - **Erosion (§6.3).** [`relief_hydrology::StreamPower`] steps at each of
//!   [`TerrainOptions::erosion_scales_m`] (100, 50 and 30 m cells, as the paper's), on grids of at
//!   most [`TerrainOptions::erosion_resolution`] samples a side, each followed by the uplift
//!   `H ← E − U·(E − H)` with `U = g(d/R)`, `g(r) = (1 − r²)³`: where `U = 1` the step is undone.
//!   (The paper prints `E + U·ΔH` with `ΔH = E − H`, which would double erosion at the peaks; the
//!   sign here is the one that keeps them fixed.) The eroded change is added back at full
//!   resolution under the same mask.
//! - **Crest lines.** The ridges are burnt into the grid after rasterizing (each sample on a ridge
//!   at least the ridge's height, up to 10 m above its saddle), since the TIN sampled off its
//!   lines would dip below the saddle and lower the col.
//! - Peaks and saddles are snapped to grid samples so the grid holds their exact heights, and the
//!   result is filled (Priority-Flood+ε) so it has no endorheic basins.
//! - **The tree kept.** Flanks of two branches can still meet above the col between them where
//!   no river runs between them (channels draining less than the river area), raising the col.
//!   A last descending sweep (`carve`) lowers every sample that would join land the tree only
//!   joins lower down to just under the next saddle, then fills again.

use std::collections::HashSet;

use glam::DVec2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use relief_heightfield::noise::Fbm;
use relief_heightfield::{Extent, GridSpec, Heightfield, distance_transform_seeded};
use relief_hydrology::{Field, Outlets, StreamPower, fill};
use relief_tin::Tin;
use serde::{Deserialize, Serialize};

use crate::OrometryError;
use crate::network::{Network, border_points, dedup, jittered_leg, poisson_samples};
use crate::tree::DivideTree;

/// How to turn a divide tree into a heightfield.
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TerrainOptions {
    /// Meshing distance λ, metres (default 200, the paper's).
    pub lambda_m: f64,
    /// Sideways jitter of refined ridge and river nodes, as a fraction of λ (default 0.3).
    pub jitter: f64,
    /// Slope `s` of the flanks where there are no rivers, `max(base, h − s·d)` at distance `d`
    /// from a ridge at height `h`, and the steepest a river may be (default 0.4, about 22°).
    pub flank_slope: f64,
    /// Catchment from which a channel of the dual network is a river (a valley floor the terrain
    /// is built on), km² (default 1). Smaller ones are left to the fill: every channel kept is a
    /// valley between ridges, and the many small ones beside the crests would cut spurs off them
    /// (peaks the tree does not have).
    pub river_area_km2: f64,
    /// River slope `s₁` at a catchment of 1 km² in Flint's law `s = s₁·(A / 1 km²)^(−θ)`
    /// (default 0.03): how fast valley floors rise from the map's edge towards the ridges.
    pub river_slope: f64,
    /// The concavity θ of Flint's law (default 0.45): steep heads, gentle main stems.
    pub river_concavity: f64,
    /// Valley width `c` at 1 km² of drainage, metres: `w = c·(A / 1 km²)^exponent` (default 40).
    pub valley_width_m: f64,
    /// The exponent of the valley-width law (default 0.4, May et al. 2013).
    pub valley_exponent: f64,
    /// Largest noise amplitude, metres; keep it below the prominence threshold you analyse at
    /// (default 12, for a 30 m threshold).
    pub noise_m: f64,
    /// Wavelength of the noise's first octave, metres (default 2000).
    pub noise_wavelength_m: f64,
    /// Stream-power erosion steps (default 6; 0 skips erosion).
    pub erosion_steps: usize,
    /// Erosion steps run on a grid of at most this many samples a side (default 1024).
    pub erosion_resolution: usize,
    /// Cell sizes of the erosion scales, metres, coarse to fine (default 100, 50 and 30, §6.3's
    /// three scales): [`TerrainOptions::erosion_steps`] steps at each, never finer than the
    /// output grid. Empty: one scale, the output grid's.
    pub erosion_scales_m: Vec<f64>,
    /// Erodibility K of the stream-power law (default 1e-5 per year, time step 1000 years).
    pub erodibility: f64,
    /// Radius R of the uplift compensation around peaks and saddles, metres (default 500).
    pub uplift_radius_m: f64,
    /// Seed of the jitter, samples and noise.
    pub seed: u64,
}

impl Default for TerrainOptions {
    fn default() -> Self {
        Self {
            lambda_m: 200.0,
            jitter: 0.3,
            flank_slope: 0.4,
            river_area_km2: 1.0,
            river_slope: 0.03,
            river_concavity: 0.45,
            valley_width_m: 40.0,
            valley_exponent: 0.4,
            noise_m: 12.0,
            noise_wavelength_m: 2000.0,
            erosion_steps: 6,
            erosion_resolution: 1024,
            erosion_scales_m: vec![100.0, 50.0, 30.0],
            erodibility: 1e-5,
            uplift_radius_m: 500.0,
            seed: 0,
        }
    }
}

fn check(name: &'static str, v: f64, ok: bool, reason: &'static str) -> Result<(), OrometryError> {
    if ok && v.is_finite() { Ok(()) } else { Err(OrometryError::InvalidOption { name, value: v, reason }) }
}

/// Most samples [`terrain_from_tree`] meshes and labels at λ: 2^25, the label raster of a domain
/// about 570 km across at the default λ = 200 m. Finer meshes fail with
/// [`OrometryError::MeshTooFine`] before anything is allocated.
pub const MAX_MESH_SAMPLES: u64 = 1 << 25;

impl TerrainOptions {
    /// About how many samples [`terrain_from_tree`] works with over `extent` for `tree`: the
    /// label raster at λ/2 plus the ridge nodes refined every λ (the Poisson fill at λ is a
    /// quarter of the raster). In f64, so absurd domains cannot overflow it.
    pub fn mesh_samples(&self, tree: &DivideTree, extent: Extent) -> f64 {
        let size = extent.size();
        let cell = 0.5 * self.lambda_m;
        let raster = ((size.x / cell).ceil() + 1.0) * ((size.y / cell).ceil() + 1.0);
        let ridges: f64 = tree
            .saddles
            .iter()
            .flat_map(|s| s.peaks.iter().map(move |&p| (s.position, p)))
            .filter_map(|(at, p)| {
                tree.peaks.get(p as usize).map(|peak| (at.distance(peak.position) / self.lambda_m).ceil())
            })
            .sum();
        raster + ridges
    }

    fn validate(&self) -> Result<(), OrometryError> {
        check("lambda_m", self.lambda_m, self.lambda_m > 0.0, "must be finite and > 0")?;
        check("jitter", self.jitter, (0.0..=0.45).contains(&self.jitter), "must be in [0, 0.45]")?;
        check("flank_slope", self.flank_slope, self.flank_slope > 0.0, "must be finite and > 0")?;
        check("river_area_km2", self.river_area_km2, self.river_area_km2 >= 0.0, "must be finite and ≥ 0")?;
        check("river_slope", self.river_slope, self.river_slope >= 0.0, "must be finite and ≥ 0")?;
        check(
            "river_concavity",
            self.river_concavity,
            (0.0..=1.0).contains(&self.river_concavity),
            "must be in [0, 1]",
        )?;
        check("valley_width_m", self.valley_width_m, self.valley_width_m >= 0.0, "must be finite and ≥ 0")?;
        check(
            "valley_exponent",
            self.valley_exponent,
            (0.0..=1.0).contains(&self.valley_exponent),
            "must be in [0, 1]",
        )?;
        check("noise_m", self.noise_m, self.noise_m >= 0.0, "must be finite and ≥ 0")?;
        check("noise_wavelength_m", self.noise_wavelength_m, self.noise_wavelength_m > 0.0, "must be finite and > 0")?;
        check("erosion_steps", self.erosion_steps as f64, self.erosion_steps <= 1000, "must be at most 1000")?;
        check(
            "erosion_resolution",
            self.erosion_resolution as f64,
            (16..=8192).contains(&self.erosion_resolution),
            "must be in 16..=8192",
        )?;
        check(
            "erosion_scales_m",
            self.erosion_scales_m.len() as f64,
            self.erosion_scales_m.len() <= 8,
            "holds at most 8 scales",
        )?;
        for &cell in &self.erosion_scales_m {
            check("erosion_scales_m", cell, cell > 0.0, "cells must be finite and > 0")?;
        }
        check("erodibility", self.erodibility, self.erodibility >= 0.0, "must be finite and ≥ 0")?;
        check("uplift_radius_m", self.uplift_radius_m, self.uplift_radius_m > 0.0, "must be finite and > 0")?;
        Ok(())
    }
}

/// `g(r) = (1 − r²)³` for `r < 1`, else 0.
fn falloff(r: f64) -> f64 {
    if r < 1.0 { (1.0 - r * r).powi(3) } else { 0.0 }
}

/// Builds a heightfield on `grid` from `tree` (§6). `base` is the lowest elevation (valley floors
/// and the map's edge never go below it). `progress(stage, fraction)` reports the stages.
///
/// # Errors
/// [`OrometryError::InvalidTree`] for a malformed tree or a peak or saddle outside the grid,
/// [`OrometryError::InvalidOption`] for bad options or a non-finite base, and wrapped
/// triangulation or hydrology errors (which validated input does not produce).
pub fn terrain_from_tree(
    tree: &DivideTree,
    base: f64,
    grid: &GridSpec,
    options: &TerrainOptions,
    mut progress: impl FnMut(&str, f64),
) -> Result<Heightfield, OrometryError> {
    check_inputs(tree, base, grid, options)?;
    // One generator for every stage, drawn from in this order: ridge jitter, river jitter, the
    // Poisson fill's seed, the noise's seed.
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    let (mut ridges, first_saddle) = snap_anchors(tree, grid);
    let anchors: Vec<DVec2> = ridges.points.clone();
    refine_ridges(&mut ridges, tree, first_saddle, options, &mut rng);
    progress("ridges", 1.0);
    let mut networks = Networks::new(ridges, grid.extent(), base, options)?;
    networks.rivers = match &networks.ridge_label {
        Some(label) => crate::rivers::dual_rivers(&networks.ridges, networks.extent, base, options, &mut rng, |p| {
            networks.ridge_at(p, label)
        })?,
        None => Network::default(),
    };
    networks.river_label = networks.rivers.nearest_segments(&networks.coarse);
    progress("rivers", 1.0);
    let samples = networks.fill_samples(&mut rng)?;
    let mut hf = networks.triangulate(&samples, grid)?;
    networks.ridges.burn(&mut hf);
    progress("triangulation", 1.0);
    let uplift = uplift_mask(&anchors, grid, options.uplift_radius_m);
    if options.noise_m > 0.0 {
        add_noise(&mut hf, &uplift, options, &mut rng);
    }
    progress("noise", 1.0);
    if options.erosion_steps > 0 && options.erodibility > 0.0 {
        erode(&mut hf, &uplift, options, &mut progress)?;
    }
    let hf = settle(hf, tree, base, &anchors, &networks.ridges.heights)?;
    progress("done", 1.0);
    Ok(hf)
}

/// Checks what [`terrain_from_tree`] is given: options, the tree, a finite base, every peak and
/// saddle inside the grid and no peak below the base, and a mesh at λ within
/// [`MAX_MESH_SAMPLES`] (before anything is allocated).
fn check_inputs(tree: &DivideTree, base: f64, grid: &GridSpec, options: &TerrainOptions) -> Result<(), OrometryError> {
    options.validate()?;
    tree.validate()?;
    check("base", base, true, "must be finite")?;
    let extent = grid.extent();
    for (k, p) in tree.peaks.iter().enumerate() {
        if !extent.contains(p.position) {
            return Err(OrometryError::InvalidTree(format!("peak {k} lies outside the grid's extent")));
        }
        if p.elevation < base {
            return Err(OrometryError::InvalidTree(format!("peak {k} is below the base elevation {base}")));
        }
    }
    if let Some(k) = tree.saddles.iter().position(|s| !extent.contains(s.position)) {
        return Err(OrometryError::InvalidTree(format!("saddle {k} lies outside the grid's extent")));
    }
    let samples = options.mesh_samples(tree, extent);
    if samples.is_nan() || samples > MAX_MESH_SAMPLES as f64 {
        return Err(OrometryError::MeshTooFine { lambda: options.lambda_m, samples, limit: MAX_MESH_SAMPLES });
    }
    Ok(())
}

/// The anchors of the ridge network: peaks, then saddles, each snapped to a free sample of `grid`
/// (a sample already taken keeps the first) so the grid can hold its exact height. Returns the
/// network (points only) and the index of the first saddle.
fn snap_anchors(tree: &DivideTree, grid: &GridSpec) -> (Network, u32) {
    let mut taken = HashSet::new();
    let mut snap = |p: DVec2| match grid.nearest_sample(p) {
        Some((i, j)) if taken.insert((i, j)) => grid.position(i, j),
        _ => p,
    };
    let mut ridges = Network::default();
    for p in &tree.peaks {
        let q = snap(p.position);
        ridges.push(q, p.elevation);
    }
    let first_saddle = ridges.points.len() as u32;
    for s in &tree.saddles {
        let q = snap(s.position);
        ridges.push(q, s.elevation);
    }
    (ridges, first_saddle)
}

/// §6.2, ridge refinement: every ridge (peak → saddle) is split into segments shorter than λ,
/// heights linear along it, nodes jittered sideways by up to `jitter·λ` tapered to zero at both
/// ends by `sin(πt)`.
fn refine_ridges(
    ridges: &mut Network,
    tree: &DivideTree,
    first_saddle: u32,
    options: &TerrainOptions,
    rng: &mut ChaCha8Rng,
) {
    for (s, saddle) in tree.saddles.iter().enumerate() {
        let sv = first_saddle + s as u32;
        for &peak in &saddle.peaks {
            let added = jittered_leg(ridges, peak, sv, options.lambda_m, options.jitter, rng);
            let hb = ridges.heights[sv as usize];
            ridges.saddles.extend(std::iter::repeat_n(hb, added));
        }
    }
}

/// The refined ridge and river networks with their nearest-segment labels on the label raster
/// (spacing λ/2): what the open river sites, the fill and the valley-width interpolation consult.
struct Networks<'a> {
    options: &'a TerrainOptions,
    /// The lowest elevation.
    base: f64,
    /// The output grid's extent.
    extent: Extent,
    /// The label raster, at λ/2 over `extent`.
    coarse: GridSpec,
    ridges: Network,
    /// The nearest ridge segment per `coarse` sample; `None` without ridges.
    ridge_label: Option<Vec<u32>>,
    rivers: Network,
    /// The nearest river segment per `coarse` sample; `None` without rivers.
    river_label: Option<Vec<u32>>,
}

impl<'a> Networks<'a> {
    /// The refined `ridges` on the label raster over `extent`, without rivers yet.
    fn new(ridges: Network, extent: Extent, base: f64, options: &'a TerrainOptions) -> Result<Self, OrometryError> {
        let size = extent.size();
        let cell = options.lambda_m * 0.5;
        let (cx, cy) = (((size.x / cell).ceil() as usize + 1).max(2), ((size.y / cell).ceil() as usize + 1).max(2));
        let coarse = GridSpec::from_extent(cx, cy, extent)?;
        let ridge_label = ridges.nearest_segments(&coarse);
        Ok(Self { options, base, extent, coarse, ridges, ridge_label, rivers: Network::default(), river_label: None })
    }

    /// The distance from `p` to its nearest ridge segment (by `label`, the ridge labels) and the
    /// height of the closest point on it.
    fn ridge_at(&self, p: DVec2, label: &[u32]) -> (f64, f64) {
        let (i, j) = self.coarse.nearest_sample(p).unwrap_or((0, 0));
        self.ridges.project(label[self.coarse.index(i, j)], p)
    }

    /// The flank surface `max(base, h − s·d)` at distance `d` from a ridge point at height `h`.
    fn flank(&self, d: f64, h: f64) -> f64 {
        (h - self.options.flank_slope * d).max(self.base)
    }

    /// §6.2, the fill: Poisson-disc samples at radius λ plus the border every λ or less, less
    /// those within λ/2 of a ridge or river (the corners always stay).
    fn fill_samples(&self, rng: &mut ChaCha8Rng) -> Result<Vec<DVec2>, OrometryError> {
        let (extent, lambda) = (self.extent, self.options.lambda_m);
        let mut samples = poisson_samples(extent, lambda, rng.random())?;
        samples.extend(border_points(extent, lambda));
        let corners =
            [extent.min, extent.max, DVec2::new(extent.min.x, extent.max.y), DVec2::new(extent.max.x, extent.min.y)];
        samples.retain(|&p| corners.contains(&p) || !self.near_network(p));
        Ok(samples)
    }

    /// Whether `p` lies within λ/2 of a ridge or a river.
    fn near_network(&self, p: DVec2) -> bool {
        let near = |net: &Network, label: &Option<Vec<u32>>| {
            label.as_ref().is_some_and(|l| {
                let (i, j) = self.coarse.nearest_sample(p).unwrap_or((0, 0));
                net.project(l[self.coarse.index(i, j)], p).0 < 0.5 * self.options.lambda_m
            })
        };
        near(&self.ridges, &self.ridge_label) || near(&self.rivers, &self.river_label)
    }

    /// §6.2, the valley-width interpolation at `p`, and `p`'s distance to the ridges: with `d_T`,
    /// `h(q)` the nearest ridge point's distance and height and `d_R`, `h(r)` the nearest river
    /// point's, `h = (1 − α)h(q) + α·h(r)`, `α = d_T / (d_R + d_T − w)`, and the river's height
    /// within its valley width `w`; the flank surface where there are no rivers, the base where
    /// there are no ridges. Kept between the base and `h(q)`.
    fn elevation(&self, p: DVec2) -> (f64, f64) {
        let Some(label) = &self.ridge_label else { return (self.base, f64::INFINITY) };
        let (d_t, h_t) = self.ridge_at(p, label);
        let h = match &self.river_label {
            None => self.flank(d_t, h_t),
            Some(rl) => {
                let (i, j) = self.coarse.nearest_sample(p).unwrap_or((0, 0));
                let s = rl[self.coarse.index(i, j)];
                let (d_r, h_r) = self.rivers.project(s, p);
                let w = self.rivers.widths[s as usize];
                let h = if d_r < w {
                    h_r
                } else {
                    let alpha = d_t / (d_r + d_t - w).max(f64::MIN_POSITIVE);
                    (1.0 - alpha) * h_t + alpha * h_r
                };
                h.clamp(self.base, h_t.max(self.base))
            }
        };
        (h, d_t)
    }

    /// The constrained TIN of ridges, rivers (both kept as edges) and the fill `samples` valued
    /// by [`Networks::elevation`], exact duplicates (rare coincidences) dropped, rasterized on
    /// `grid`.
    fn triangulate(&self, samples: &[DVec2], grid: &GridSpec) -> Result<Heightfield, OrometryError> {
        let (ridges, rivers) = (&self.ridges, &self.rivers);
        let mut points = ridges.points.clone();
        let mut values = ridges.heights.clone();
        let mut constraints = ridges.segments.clone();
        let offset = points.len() as u32;
        points.extend_from_slice(&rivers.points);
        values.extend_from_slice(&rivers.heights);
        constraints.extend(rivers.segments.iter().map(|&[a, b]| [a + offset, b + offset]));
        let sample_values: Vec<f64> = samples.par_iter().map(|&p| self.elevation(p).0).collect();
        points.extend_from_slice(samples);
        values.extend_from_slice(&sample_values);
        let (points, values, constraints) = dedup(points, values, constraints);
        let (tin, _skipped) = Tin::constrained(points, &constraints)?;
        Ok(tin.rasterize(&values, grid)?)
    }
}

/// The uplift compensation `U = g(d/R)` on `grid`, `d` the distance to the nearest peak or saddle
/// (`anchors`), `R` = `radius_m`: 1 on them, fading to 0 at `R`. It also fades the noise.
fn uplift_mask(anchors: &[DVec2], grid: &GridSpec, radius_m: f64) -> Vec<f64> {
    let mut sq = vec![f64::INFINITY; grid.len()];
    for &p in anchors {
        if let Some((i, j)) = grid.nearest_sample(p) {
            sq[grid.index(i, j)] = 0.0;
        }
    }
    distance_transform_seeded(grid.nx(), grid.ny(), grid.cell_size(), &mut sq, None);
    sq.par_iter().map(|&d2| falloff(d2.sqrt() / radius_m)).collect()
}

/// §6.3, noise: fBm of six octaves whose amplitude grows from a quarter to all of
/// [`TerrainOptions::noise_m`] with the height, faded by `1 − U` so peaks and saddles keep their
/// heights. Rows in parallel.
fn add_noise(hf: &mut Heightfield, uplift: &[f64], options: &TerrainOptions, rng: &mut ChaCha8Rng) {
    let grid = *hf.grid();
    let nx = grid.nx();
    let (lo, hi) = hf.min_max().map_or((0.0, 1.0), |(a, b)| (f64::from(a), f64::from(b)));
    let span = (hi - lo).max(1e-9);
    let noise = Fbm { octaves: 6, frequency: 1.0 / options.noise_wavelength_m, seed: rng.random(), ..Fbm::default() };
    hf.samples_mut().par_chunks_mut(nx).enumerate().for_each(|(j, row)| {
        for (i, v) in row.iter_mut().enumerate() {
            let k = j * nx + i;
            let rise = (f64::from(*v) - lo) / span;
            let amp = options.noise_m * (0.25 + 0.75 * rise) * (1.0 - uplift[k]);
            *v += (amp * noise.sample(grid.position(i, j)).clamp(-1.0, 1.0)) as f32;
        }
    });
}

/// The last touches: every sample clamped between the base and the highest peak (noise never
/// lifts ground above it nor sinks it below the base), peaks and saddles pinned to their exact
/// `heights` where they were snapped to a sample, then every basin drained (Priority-Flood+ε).
fn settle(
    mut hf: Heightfield,
    tree: &DivideTree,
    base: f64,
    anchors: &[DVec2],
    heights: &[f64],
) -> Result<Heightfield, OrometryError> {
    let grid = *hf.grid();
    let top = tree.peaks.iter().map(|p| p.elevation).fold(base, f64::max);
    hf.samples_mut().iter_mut().for_each(|v| *v = v.clamp(base as f32, top as f32));
    // The samples the anchors were snapped to (`None` for one that kept its own position).
    let snapped: Vec<Option<usize>> = anchors
        .iter()
        .map(|p| grid.nearest_sample(*p).filter(|&(i, j)| grid.position(i, j) == *p).map(|(i, j)| grid.index(i, j)))
        .collect();
    let samples_mut = hf.samples_mut();
    for (at, &h) in snapped.iter().zip(heights) {
        if let Some(at) = *at {
            samples_mut[at] = h as f32;
        }
    }
    let mut hf = fill(&hf, Outlets::default())?;
    crate::carve::separate(&mut hf, tree, &snapped[..tree.peaks.len()], base);
    Ok(fill(&hf, Outlets::default())?)
}

/// The erosion grids, coarse to fine: one per [`TerrainOptions::erosion_scales_m`] (the output
/// grid's own cell when there are none), each never finer than the output grid and at most
/// `erosion_resolution` samples a side; scales that come out the same size run once.
fn erosion_grids(grid: &GridSpec, options: &TerrainOptions) -> Result<Vec<GridSpec>, OrometryError> {
    let (nx, ny) = (grid.nx(), grid.ny());
    let size = grid.extent().size();
    let cap = (nx.max(ny) as f64 / options.erosion_resolution as f64).max(1.0);
    let finest = (nx, ny);
    let own = [grid.cell_size().max_element()];
    let scales = if options.erosion_scales_m.is_empty() { &own[..] } else { &options.erosion_scales_m[..] };
    let mut grids: Vec<GridSpec> = Vec::new();
    for &cell in scales {
        let fit = |n: usize, span: f64| ((span / cell).round() as usize + 1).clamp(2, n);
        let (ex, ey) = (fit(finest.0, size.x), fit(finest.1, size.y));
        let (ex, ey) = (
            ((ex as f64).min(nx as f64 / cap).round() as usize).max(2),
            ((ey as f64).min(ny as f64 / cap).round() as usize).max(2),
        );
        if grids.last().is_none_or(|g| (g.nx(), g.ny()) != (ex, ey)) {
            grids.push(grid.resized(ex, ey)?);
        }
    }
    Ok(grids)
}

/// §6.3, constrained multi-scale erosion: at each of [`erosion_grids`], coarse to fine,
/// [`TerrainOptions::erosion_steps`] stream-power steps each followed by the uplift
/// compensation; each scale's change is added back at full resolution, faded by the same uplift.
fn erode(
    hf: &mut Heightfield,
    uplift: &[f64],
    options: &TerrainOptions,
    progress: &mut impl FnMut(&str, f64),
) -> Result<(), OrometryError> {
    let grids = erosion_grids(hf.grid(), options)?;
    let uplift_hf = Heightfield::from_samples(*hf.grid(), uplift.iter().map(|&u| u as f32).collect())?;
    let law = StreamPower { erodibility: Field::Uniform(options.erodibility), ..StreamPower::default() };
    let total = (grids.len() * options.erosion_steps) as f64;
    let mut done = 0.0;
    for coarse_grid in &grids {
        let before = hf.resample_to(coarse_grid);
        let coarse_uplift = uplift_hf.resample_to(coarse_grid);
        let mut h = before.clone();
        for _ in 0..options.erosion_steps {
            let prev = h.clone();
            law.step(&mut h)?;
            for ((e, &p), &u) in h.samples_mut().iter_mut().zip(prev.samples()).zip(coarse_uplift.samples()) {
                *e -= u * (*e - p);
            }
            done += 1.0;
            progress("erosion", done / total);
        }
        let delta = h.zip_with(&before, |a, b| a - b)?.resample_to(hf.grid());
        for ((v, &d), &u) in hf.samples_mut().iter_mut().zip(delta.samples()).zip(uplift) {
            *v += d * (1.0 - u as f32);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erosion_runs_coarse_to_fine_at_the_papers_scales_within_the_grid() {
        // 48 km at 50 m: the 100 m scale, then the grid's own (50 m and 30 m are the same).
        let grid = GridSpec::from_extent(961, 961, Extent::new(DVec2::ZERO, DVec2::splat(48_000.0))).unwrap();
        let sizes =
            |o: &TerrainOptions| erosion_grids(&grid, o).unwrap().iter().map(|g| (g.nx(), g.ny())).collect::<Vec<_>>();
        let options = TerrainOptions::default();
        assert_eq!(sizes(&options), [(481, 481), (961, 961)]);
        // Capped at `erosion_resolution` a side; no scales: the grid's own.
        assert_eq!(sizes(&TerrainOptions { erosion_resolution: 300, ..options.clone() }), [(300, 300)]);
        assert_eq!(sizes(&TerrainOptions { erosion_scales_m: vec![], ..options.clone() }), [(961, 961)]);
        assert_eq!(sizes(&TerrainOptions { erosion_scales_m: vec![400.0], ..options }), [(121, 121)]);
    }
}
