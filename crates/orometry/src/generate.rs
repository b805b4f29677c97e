//! Divide tree generation from a descriptor (§5): peaks by dart throwing, ridges as a weighted
//! minimum spanning tree of the peaks' Delaunay triangulation, multi-pass placement, and saddle
//! elevations by optimal assignment alternating dominance and prominence targets.
//!
//! Choices where the paper is silent, each documented on its option:
//! - passes are filled from the highest peaks down (elevation stands in for the prominence bin,
//!   since prominence is only known once saddles exist); each pass holds twice the peaks of the
//!   previous one;
//! - ridges of earlier passes keep half their MST weight in later passes, so the primary spine
//!   survives as new peaks arrive;
//! - "diffusing the ridges into `C_P`" multiplies the density by `0.2 + 0.8·exp(−(d/s)²)`, `d`
//!   the distance to the earlier ridges and `s` the pass's mean peak spacing;
//! - a dart that is never accepted falls back to the best of its candidates, so generation always
//!   finishes in `peaks × dart_attempts` draws;
//! - darts are accepted by the distance to the nearest *higher peak* (the descriptor's
//!   `higher_peak_distance`), not by isolation, which is a distance to higher ground and so
//!   shorter on the terrain than between peaks; and each distance bin takes only its share of the
//!   peaks (a quota), since uniform proposals in a filling domain mostly land near a peak;
//! - the assignment works on bins, as the descriptor does: a target in a peak's current bin needs
//!   no move, and a move aims at the point of the target's bin nearest the target that the
//!   saddle's range allows, a tenth of a bin inside its edges;
//! - prominences stay at or above the threshold the target was counted at
//!   ([`crate::DomainStats::min_prominence`]) plus 2 m, and peaks the rounds leave below it are
//!   lifted back over it, so the terrain analysed at that threshold keeps them;
//! - the assignment is a sparse forward auction with ε-scaling (Bertsekas): each peak bids on the
//!   4 targets nearest its current value in every bin plus its rank-matched target, which
//!   guarantees a perfect matching exists.

use glam::DVec2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use relief_heightfield::{Extent, GridSpec, Heightfield, distance_transform_seeded};
use relief_tin::Tin;
use serde::{Deserialize, Serialize};

use crate::descriptor::FractionHistogram;
use crate::point_grid::PointGrid;
use crate::tree::{DivideTree, TreeOrometry, TreePeak, TreeSaddle};
use crate::union_find::find;
use crate::{Descriptor, OrometryError};

/// The most peaks a synthesis places.
pub const MAX_PEAKS: usize = 200_000;

/// User maps that steer peak placement (§5.1, §7.2). Each must span the synthesis domain; its
/// resolution is free (values are sampled bilinearly).
#[derive(Debug, Clone, Default)]
pub struct ControlMaps {
    /// `C_P`: relative peak density, ≥ 0 (0 keeps peaks out, e.g. seas and valley floors).
    pub peak_density: Option<Heightfield>,
    /// `C_H`: coarse elevation, metres; peaks prefer places where it is close to their height.
    pub elevation: Option<Heightfield>,
}

/// How to generate a divide tree.
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TreeOptions {
    /// Peaks to place, pinned ones included (default: the descriptor's density × the domain's area).
    pub peaks: Option<usize>,
    /// Ridge exponent `ρ` of Eq. 1: 0 favours short ridges, 2 high ones (default 1).
    pub rho: f64,
    /// Multi-pass placement passes (default 4; 1 places every peak at once).
    pub passes: usize,
    /// Saddle-elevation rounds, alternating dominance and prominence targets (default 16; the
    /// paper's 3–4 leave Fig. 11's pairing shifts unsettled, about 5 % off in a dominance bin).
    pub saddle_rounds: usize,
    /// Darts thrown per peak before taking the best candidate (default 256: late peaks need
    /// many tries to find the gaps the distance histogram asks for).
    pub dart_attempts: usize,
    /// Peaks keep at least this far apart, metres (default 200, the meshing distance λ).
    pub min_spacing_m: f64,
    /// Seed of every random choice.
    pub seed: u64,
}

impl Default for TreeOptions {
    fn default() -> Self {
        Self { peaks: None, rho: 1.0, passes: 4, saddle_rounds: 16, dart_attempts: 256, min_spacing_m: 200.0, seed: 0 }
    }
}

fn invalid(name: &'static str, value: f64, reason: &'static str) -> OrometryError {
    OrometryError::InvalidOption { name, value, reason }
}

impl TreeOptions {
    /// How many peaks [`generate_tree`] places over `extent` with `pinned` pinned peaks: the
    /// asked-for count, else the descriptor's density × the domain's area, never fewer than the
    /// pinned ones. Callers with their own budget check this before generating.
    #[must_use]
    pub fn peak_count(&self, descriptor: &Descriptor, extent: Extent, pinned: usize) -> usize {
        let size = extent.size();
        let area_km2 = size.x * size.y / 1e6;
        self.peaks.unwrap_or_else(|| (descriptor.density_per_km2 * area_km2).round() as usize).max(pinned)
    }

    fn validate(&self) -> Result<(), OrometryError> {
        if !(self.rho.is_finite() && (0.0..=8.0).contains(&self.rho)) {
            return Err(invalid("rho", self.rho, "must be in [0, 8]"));
        }
        if !(1..=16).contains(&self.passes) {
            return Err(invalid("passes", self.passes as f64, "must be in 1..=16"));
        }
        if self.saddle_rounds > 64 {
            return Err(invalid("saddle_rounds", self.saddle_rounds as f64, "must be at most 64"));
        }
        if !(1..=100_000).contains(&self.dart_attempts) {
            return Err(invalid("dart_attempts", self.dart_attempts as f64, "must be in 1..=100000"));
        }
        if !(self.min_spacing_m.is_finite() && self.min_spacing_m >= 0.0) {
            return Err(invalid("min_spacing_m", self.min_spacing_m, "must be finite and ≥ 0"));
        }
        Ok(())
    }
}

/// A validated control map.
struct Control<'a> {
    map: Option<&'a Heightfield>,
}

impl Control<'_> {
    fn at(&self, p: DVec2) -> Option<f64> {
        self.map.and_then(|m| m.sample_bilinear_clamped(p)).map(f64::from)
    }
}

fn extent_array(e: &Extent) -> [f64; 4] {
    [e.min.x, e.min.y, e.max.x, e.max.y]
}

/// Checks that `map` spans `extent` (within half a cell of the map) and holds only allowed values.
pub(crate) fn check_control(
    name: &'static str,
    map: Option<&Heightfield>,
    extent: &Extent,
    non_negative: bool,
) -> Result<(), OrometryError> {
    let Some(map) = map else { return Ok(()) };
    let e = map.extent();
    let tol = map.grid().cell_size() * 0.5 + DVec2::splat(1e-9 * extent.size().max_element());
    if (e.min - extent.min).abs().cmpgt(tol).any() || (e.max - extent.max).abs().cmpgt(tol).any() {
        return Err(OrometryError::ControlMapExtent { name, expected: extent_array(extent), found: extent_array(&e) });
    }
    if map.has_no_data() {
        return Err(OrometryError::InvalidControlMap { name, reason: "holds no-data samples" });
    }
    if non_negative && map.samples().iter().any(|&v| v < 0.0) {
        return Err(OrometryError::InvalidControlMap { name, reason: "densities must be ≥ 0" });
    }
    if non_negative && map.samples().iter().all(|&v| v == 0.0) {
        return Err(OrometryError::InvalidControlMap { name, reason: "is zero everywhere: no peak can be placed" });
    }
    Ok(())
}

/// `n` stratified samples of a histogram's inverse CDF (one per equal-probability stratum, jittered
/// inside it), in random order.
fn stratified(h: &FractionHistogram, n: usize, rng: &mut ChaCha8Rng) -> Vec<f64> {
    let mut v: Vec<f64> =
        (0..n).map(|k| h.quantile((k as f64 + rng.random::<f64>()) / n as f64).unwrap_or(0.0)).collect();
    for k in (1..v.len()).rev() {
        v.swap(k, rng.random_range(0..=k));
    }
    v
}

/// Generates a divide tree over `extent` whose orometry follows `descriptor` (§5).
///
/// Pinned peaks keep their positions and elevations and count towards the total. Positions are in
/// the extent's units, taken as metres.
///
/// # Errors
/// [`OrometryError::InvalidDescriptor`] for a malformed descriptor or one with an empty
/// elevation histogram, [`OrometryError::InvalidOption`] for bad options or an extent with no area,
/// [`OrometryError::TooManyPeaks`], control-map errors ([`OrometryError::ControlMapExtent`],
/// [`OrometryError::InvalidControlMap`]) and [`OrometryError::InvalidPinnedPeak`].
pub fn generate_tree(
    descriptor: &Descriptor,
    extent: Extent,
    controls: &ControlMaps,
    pinned: &[TreePeak],
    options: &TreeOptions,
) -> Result<DivideTree, OrometryError> {
    let n = check_inputs(descriptor, extent, controls, pinned, options)?;
    // One generator for every step, drawn from in this order: elevations, darts, saddles, targets.
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    let peaks = peak_elevations(descriptor, pinned, n, &mut rng);
    let placement = Placement::new(descriptor, extent, controls, options);
    let (positions, ridges) = placement.place(&peaks, &mut rng);
    let mut tree = DivideTree {
        peaks: positions
            .iter()
            .zip(&peaks)
            .map(|(&position, &(elevation, _))| TreePeak { position, elevation })
            .collect(),
        saddles: Vec::with_capacity(ridges.len()),
    };
    split_ridges(&mut tree, &ridges, placement.base, extent, &mut rng);
    for round in 0..options.saddle_rounds {
        assign_saddles(&mut tree, descriptor, placement.base, round % 2 == 0, &mut rng, &|_| true);
    }
    lift_below_threshold(&mut tree, descriptor, placement.base, &mut rng, &|_| true);
    Ok(tree)
}

/// Checks everything [`generate_tree`] is given (options, descriptor, extent, control maps,
/// pinned peaks) and returns the number of peaks to place.
pub(crate) fn check_inputs(
    descriptor: &Descriptor,
    extent: Extent,
    controls: &ControlMaps,
    pinned: &[TreePeak],
    options: &TreeOptions,
) -> Result<usize, OrometryError> {
    options.validate()?;
    descriptor.validate()?;
    let size = extent.size();
    if !(size.x > 0.0 && size.y > 0.0 && size.is_finite() && extent.min.is_finite()) {
        return Err(invalid("extent", size.x.min(size.y), "must be finite with a positive area"));
    }
    check_control("peak_density", controls.peak_density.as_ref(), &extent, true)?;
    check_control("elevation", controls.elevation.as_ref(), &extent, false)?;
    check_pinned(pinned, &extent, descriptor.domain.min_elevation)?;
    let n = options.peak_count(descriptor, extent, pinned.len());
    if n > MAX_PEAKS {
        return Err(OrometryError::TooManyPeaks { peaks: n, limit: MAX_PEAKS });
    }
    if n == 0 {
        return Err(invalid("peaks", 0.0, "no peaks to place: the descriptor has none and none were asked for"));
    }
    if descriptor.normalized_elevation.is_empty() && n > pinned.len() {
        return Err(OrometryError::InvalidDescriptor {
            feature: "normalized_elevation",
            reason: "is empty, so there are no peak elevations to sample",
        });
    }
    Ok(n)
}

/// Pinned peaks must be finite, inside the domain and above its base.
pub(crate) fn check_pinned(pinned: &[TreePeak], extent: &Extent, base: f64) -> Result<(), OrometryError> {
    for (index, p) in pinned.iter().enumerate() {
        if !(p.position.is_finite() && p.elevation.is_finite()) {
            return Err(OrometryError::InvalidPinnedPeak { index, reason: "position and elevation must be finite" });
        }
        if !extent.contains(p.position) {
            return Err(OrometryError::InvalidPinnedPeak { index, reason: "lies outside the domain" });
        }
        if p.elevation <= base {
            return Err(OrometryError::InvalidPinnedPeak {
                index,
                reason: "is not above the descriptor's lowest elevation (the base)",
            });
        }
    }
    Ok(())
}

/// §5, the peaks' elevations: `n` less the pinned ones drawn from the descriptor's normalized
/// elevation histogram by stratified sampling and scaled to the domain's range, plus the pinned
/// ones (with their positions); highest first, a pinned peak before a free one of equal height.
pub(crate) fn peak_elevations(
    descriptor: &Descriptor,
    pinned: &[TreePeak],
    n: usize,
    rng: &mut ChaCha8Rng,
) -> Vec<(f64, Option<DVec2>)> {
    let d = &descriptor.domain;
    let (base, span) = (d.min_elevation, d.max_elevation - d.min_elevation);
    let mut peaks: Vec<(f64, Option<DVec2>)> = stratified(&descriptor.normalized_elevation, n - pinned.len(), rng)
        .into_iter()
        .map(|u| (base + u * span, None))
        .chain(pinned.iter().map(|p| (p.elevation, Some(p.position))))
        .collect();
    peaks.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.is_none().cmp(&b.1.is_none())));
    peaks
}

/// The end of each placement pass among `n` peaks: sizes 1 : 2 : 4 : … over `passes` passes
/// (fewer when there are fewer peaks), the last ending at `n`.
fn pass_ends(passes: usize, n: usize) -> Vec<usize> {
    let passes = passes.min(n);
    let unit = n as f64 / ((1u64 << passes) - 1) as f64;
    let mut ends: Vec<usize> =
        (1..=passes).map(|p| ((((1u64 << p) - 1) as f64 * unit).round() as usize).min(n)).collect();
    ends[passes - 1] = n;
    ends
}

/// What peak placement (§5.1: dart throwing steered by the descriptor and the control maps;
/// multi-pass with the Eq. 1 ridges between passes) works with, fixed for one generation.
pub(crate) struct Placement<'a> {
    descriptor: &'a Descriptor,
    options: &'a TreeOptions,
    extent: Extent,
    /// The descriptor's lowest elevation: ridges lift and saddles drop relative to it.
    base: f64,
    /// `C_P` and its largest value (1 without a map): densities are relative to it.
    density: Control<'a>,
    density_max: f64,
    /// `C_H` and the spread a peak's height may differ from it by (a twentieth of its range).
    elevation: Control<'a>,
    sigma_h: f64,
}

impl<'a> Placement<'a> {
    pub(crate) fn new(
        descriptor: &'a Descriptor,
        extent: Extent,
        controls: &'a ControlMaps,
        options: &'a TreeOptions,
    ) -> Self {
        let density_max =
            controls.peak_density.as_ref().and_then(Heightfield::min_max).map_or(1.0, |(_, hi)| f64::from(hi));
        let sigma_h = controls
            .elevation
            .as_ref()
            .and_then(Heightfield::min_max)
            .map_or(1.0, |(lo, hi)| (f64::from(hi - lo) / 20.0).max(1e-6));
        Self {
            descriptor,
            options,
            extent,
            base: descriptor.domain.min_elevation,
            density: Control { map: controls.peak_density.as_ref() },
            density_max,
            elevation: Control { map: controls.elevation.as_ref() },
            sigma_h,
        }
    }

    /// Multi-pass placement (§5): each pass places its peaks (pinned ones where they are pinned,
    /// free ones by [`Placement::throw`], biased towards the earlier passes' ridges), then the
    /// ridges are recomputed over every peak placed so far as the Eq. 1 spanning tree. Returns
    /// the positions, in `peaks`' order, and the final ridges.
    pub(crate) fn place(&self, peaks: &[(f64, Option<DVec2>)], rng: &mut ChaCha8Rng) -> (Vec<DVec2>, Vec<[u32; 2]>) {
        let n = peaks.len();
        let size = self.extent.size();
        let mut placed = Placed { positions: Vec::with_capacity(n), grid: PointGrid::new(&self.extent, n) };
        let mut ridges: Vec<[u32; 2]> = Vec::new();
        let mut quota = Quota::new(self.distances(), n);
        let mut start = 0;
        for end in pass_ends(self.options.passes, n) {
            let ridge_field = (start > 0).then(|| RidgeField::new(&self.extent, &placed.positions, &ridges));
            let spacing = (size.x * size.y / end as f64).sqrt();
            for &(h, pin) in &peaks[start..end] {
                let p = match pin {
                    Some(p) => p,
                    None => self.throw(h, &placed, ridge_field.as_ref(), spacing, &quota, rng),
                };
                if let Some((_, d)) = placed.nearest(p) {
                    quota.fill(d / self.descriptor.domain.radius_m);
                }
                placed.push(p);
            }
            let heights: Vec<f64> = peaks[..end].iter().map(|p| p.0).collect();
            ridges = spanning_ridges(&placed.positions, &heights, self.base, self.options.rho, &ridges);
            start = end;
        }
        (placed.positions, ridges)
    }

    /// The histogram of distances to the nearest higher peak that darts are accepted by: the
    /// descriptor's own, or its isolation histogram where it has none.
    fn distances(&self) -> &'a FractionHistogram {
        let d = self.descriptor;
        d.higher_peak_distance.as_ref().unwrap_or(&d.isolation_distance)
    }

    /// Dart throwing for one peak of height `h` (§5.1): a uniform candidate is accepted with the
    /// probability `C_P`/max × the `C_H` Gaussian `exp(−½((C_H − h)/σ)²)` × the relative
    /// densities of the descriptor's nearest-higher-peak distance (see [`Placement::distances`])
    /// and isolation direction (each at least 0.02) towards the nearest placed peak, the former
    /// times the share of its bin's `quota` still open × the earlier-ridge bias
    /// `0.2 + 0.8·exp(−(d/spacing)²)`; candidates closer than the minimum spacing are refused.
    /// Without an accepted dart, the most probable candidate wins, or, when every one was too
    /// close, the one with the most room.
    fn throw(
        &self,
        h: f64,
        placed: &Placed,
        ridge_field: Option<&RidgeField>,
        spacing: f64,
        quota: &Quota<'_>,
        rng: &mut ChaCha8Rng,
    ) -> DVec2 {
        let (extent, size) = (self.extent, self.extent.size());
        let descriptor = self.descriptor;
        let radius = descriptor.domain.radius_m;
        let mut best = (f64::NEG_INFINITY, extent.min + size * 0.5);
        let mut roomiest = (f64::NEG_INFINITY, best.1);
        for _ in 0..self.options.dart_attempts {
            let c = extent.min + DVec2::new(rng.random::<f64>(), rng.random::<f64>()) * size;
            let mut prob = self.density.at(c).map_or(1.0, |v| v / self.density_max);
            if let Some(ch) = self.elevation.at(c) {
                let x = (ch - h) / self.sigma_h;
                prob *= (-0.5 * x * x).exp();
            }
            if let Some((k, dist)) = placed.nearest(c) {
                if dist > roomiest.0 {
                    roomiest = (dist, c);
                }
                if dist < self.options.min_spacing_m {
                    continue;
                }
                let az = crate::descriptor::azimuth(placed.positions[k as usize] - c).to_degrees();
                prob *= self.distances().relative_density(dist / radius).max(0.02) * quota.open(dist / radius);
                prob *= descriptor.isolation_direction.relative_density(az).max(0.02);
            }
            if let Some(f) = ridge_field {
                prob *= 0.2 + 0.8 * (-(f.distance(c) / spacing).powi(2)).exp();
            }
            if prob > best.0 {
                best = (prob, c);
            }
            if rng.random::<f64>() < prob {
                return c;
            }
        }
        if best.0 > f64::NEG_INFINITY { best.1 } else { roomiest.1 }
    }
}

/// How many peaks each bin of the nearest-higher-peak distances may still take: its fraction of
/// all the peaks less those placed in it. Peaks are placed highest first, so a peak's distance to
/// the nearest peak placed before it is final; plain dart throwing accepts by the target's
/// density but proposes uniformly, and as the domain fills, most proposals land near a peak, so
/// the short distances overflow. Scaling the acceptance by the share of the bin still open
/// steers later darts into the gaps instead.
struct Quota<'a> {
    hist: &'a FractionHistogram,
    target: Vec<f64>,
    filled: Vec<f64>,
}

impl<'a> Quota<'a> {
    fn new(hist: &'a FractionHistogram, peaks: usize) -> Self {
        let target: Vec<f64> = hist.fractions.iter().map(|f| f * peaks as f64).collect();
        Self { hist, filled: vec![0.0; target.len()], target }
    }

    /// The share of `v`'s bin (beyond the top, the last, as the histogram counts it) still open,
    /// at least 0.02.
    fn open(&self, v: f64) -> f64 {
        let b = self.hist.bin(v);
        if self.target[b] > 0.0 { ((self.target[b] - self.filled[b]) / self.target[b]).max(0.02) } else { 0.02 }
    }

    fn fill(&mut self, v: f64) {
        self.filled[self.hist.bin(v)] += 1.0;
    }
}

/// The peaks placed so far, bucketed for nearest-neighbour queries.
struct Placed {
    positions: Vec<DVec2>,
    grid: PointGrid,
}

impl Placed {
    fn push(&mut self, p: DVec2) {
        self.grid.insert(self.positions.len() as u32, p);
        self.positions.push(p);
    }

    /// The nearest placed peak to `p` and its distance.
    fn nearest(&self, p: DVec2) -> Option<(u32, f64)> {
        self.grid.nearest(p, &self.positions)
    }
}

/// Distance to earlier ridges on a coarse raster (for the multi-pass density bias).
struct RidgeField {
    grid: GridSpec,
    dist: Vec<f64>,
}

impl RidgeField {
    fn new(extent: &Extent, positions: &[DVec2], ridges: &[[u32; 2]]) -> Self {
        let size = extent.size();
        let cells = 128.0 / size.max_element();
        let (nx, ny) = (((size.x * cells).ceil() as usize).max(2), ((size.y * cells).ceil() as usize).max(2));
        let grid = GridSpec::from_extent(nx, ny, *extent).expect("a validated extent makes a valid grid");
        let mut sq = vec![f64::INFINITY; nx * ny];
        let step = grid.cell_size().min_element() * 0.5;
        for &[a, b] in ridges {
            let (pa, pb) = (positions[a as usize], positions[b as usize]);
            let k = (pa.distance(pb) / step).ceil().max(1.0) as usize;
            for t in 0..=k {
                if let Some((i, j)) = grid.nearest_sample(pa.lerp(pb, t as f64 / k as f64)) {
                    sq[grid.index(i, j)] = 0.0;
                }
            }
        }
        if sq.iter().all(|v| v.is_infinite()) {
            sq.fill(0.0);
        } else {
            distance_transform_seeded(nx, ny, grid.cell_size(), &mut sq, None);
        }
        Self { grid, dist: sq.into_iter().map(f64::sqrt).collect() }
    }

    fn distance(&self, p: DVec2) -> f64 {
        self.grid.nearest_sample(p).map_or(0.0, |(i, j)| self.dist[self.grid.index(i, j)])
    }
}

/// One saddle per ridge of `tree`'s peaks: at a random point between 30 % and 70 % of the
/// way, nudged sideways by up to a tenth of the ridge's length, kept inside the domain, at a
/// random 50–90 % of the lower peak's height above the base. §5.4 then moves them vertically.
pub(crate) fn split_ridges(
    tree: &mut DivideTree,
    ridges: &[[u32; 2]],
    base: f64,
    extent: Extent,
    rng: &mut ChaCha8Rng,
) {
    for &[a, b] in ridges {
        let (pa, pb) = (tree.peaks[a as usize].position, tree.peaks[b as usize].position);
        let t = rng.random_range(0.3..0.7);
        let side = rng.random_range(-0.1..0.1);
        let dir = pb - pa;
        let position = (pa + dir * t + dir.perp() * side).clamp(extent.min, extent.max);
        let top = tree.peaks[a as usize].elevation.min(tree.peaks[b as usize].elevation);
        let elevation = base + (top - base) * rng.random_range(0.5..0.9);
        tree.saddles.push(TreeSaddle { position, elevation, peaks: [a, b] });
    }
}

/// Ridges: the minimum spanning tree of the peaks' Delaunay triangulation under Eq. 1's weights
/// `‖Pᵢ − Pⱼ‖ / min(hᵢ − base, hⱼ − base)^ρ`; edges in `previous` weigh half.
pub(crate) fn spanning_ridges(
    positions: &[DVec2],
    heights: &[f64],
    base: f64,
    rho: f64,
    previous: &[[u32; 2]],
) -> Vec<[u32; 2]> {
    let n = positions.len();
    if n < 2 {
        return Vec::new();
    }
    let mut edges: Vec<(u32, u32)> = match Tin::new(positions.to_vec()) {
        Ok(tin) => tin.edges().collect(),
        // Collinear or duplicated positions: every pair (only happens for tiny or degenerate sets).
        Err(_) => (0..n as u32).flat_map(|a| (a + 1..n as u32).map(move |b| (a, b))).collect(),
    };
    let prev: std::collections::HashSet<(u32, u32)> = previous.iter().map(|&[a, b]| (a.min(b), a.max(b))).collect();
    let weight = |a: u32, b: u32| {
        let lift = (heights[a as usize].min(heights[b as usize]) - base).max(1.0);
        let w = positions[a as usize].distance(positions[b as usize]) / lift.powf(rho);
        if prev.contains(&(a.min(b), a.max(b))) { 0.5 * w } else { w }
    };
    let mut weighted: Vec<(f64, u32, u32)> = edges.drain(..).map(|(a, b)| (weight(a, b), a.min(b), a.max(b))).collect();
    weighted.sort_by(|x, y| x.0.total_cmp(&y.0).then((x.1, x.2).cmp(&(y.1, y.2))));
    let mut parent: Vec<u32> = (0..n as u32).collect();
    let mut out = Vec::with_capacity(n - 1);
    for (_, a, b) in weighted {
        let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
        if ra != rb {
            parent[ra as usize] = rb;
            out.push([a, b]);
        }
    }
    out
}

/// Passes of [`lift_below_threshold`] at most; each only lowers saddles, so it settles in a few.
const LIFT_PASSES: usize = 16;

/// The rounds move saddles up as well as down, and raising one saddle can open a higher route
/// for another peak (Fig. 11), leaving it below the prominence threshold the target was counted
/// at: analysed at that threshold, the terrain would lose it. Each such peak (and any peak of
/// prominence 0) has its key saddle lowered to give it a prominence drawn from the lowest bin
/// above the threshold, never below the base; lowering only raises prominences, so passes repeat
/// until none is left (or its saddle is already at the base).
pub(crate) fn lift_below_threshold(
    tree: &mut DivideTree,
    descriptor: &Descriptor,
    base: f64,
    rng: &mut ChaCha8Rng,
    keep: &dyn Fn(usize) -> bool,
) {
    let floor = descriptor.domain.min_prominence;
    let Some(above) = descriptor.prominence.from_floor(floor) else { return };
    let (lo, hi) = inside(&above, 0);
    for _ in 0..LIFT_PASSES {
        let oro = tree.orometry(base);
        let mut moved = false;
        for (k, peak) in tree.peaks.iter().enumerate() {
            let (Some(s), pi) = (oro.key_saddle[k], oro.prominence[k]) else { continue };
            if (pi >= floor && pi > 0.0) || !keep(k) {
                continue;
            }
            let saddle = &mut tree.saddles[s as usize];
            let target = (peak.elevation - rng.random_range(lo..hi)).max(base);
            if target < saddle.elevation {
                saddle.elevation = target;
                moved = true;
            }
        }
        if !moved {
            return;
        }
    }
}

/// Per person: current value, the saddle shift per unit of target change, bounds, ridge length.
struct Person {
    current: f64,
    scale: f64,
    saddle: usize,
    lo_shift: f64,
    hi_shift: f64,
    length: f64,
}

/// How far above the target's prominence threshold the rounds keep every peak, metres: the
/// terrain moves a prominence by a metre or two, which must not drop a peak below it.
const FLOOR_MARGIN_M: f64 = 2.0;

/// The share of a bin's width at each side that saddle moves keep clear of.
const BIN_MARGIN: f64 = 0.1;

/// Bin `b` of `hist` less [`BIN_MARGIN`] of its width at each side.
fn inside(hist: &FractionHistogram, b: usize) -> (f64, f64) {
    let (lo, hi) = (hist.edges[b], hist.edges[b + 1]);
    let margin = BIN_MARGIN * (hi - lo);
    (lo + margin, hi - margin)
}

/// Targets each peak bids on in each bin, those nearest its current value.
const PER_BIN: usize = 4;

/// One round of §5.4: sample targets (dominance or prominence), assign them to the peaks with key
/// saddles by minimum total cost, and move those saddles.
pub(crate) fn assign_saddles(
    tree: &mut DivideTree,
    descriptor: &Descriptor,
    base: f64,
    dominance: bool,
    rng: &mut ChaCha8Rng,
    keep: &dyn Fn(usize) -> bool,
) {
    let oro = tree.orometry(base);
    let people: Vec<usize> = (0..tree.peaks.len()).filter(|&k| oro.key_saddle[k].is_some() && keep(k)).collect();
    let m = people.len();
    // Prominences are drawn at or above the threshold the target's peaks were counted at, so the
    // terrain analysed at that threshold keeps every peak.
    let above = (!dominance).then(|| descriptor.prominence.from_floor(descriptor.domain.min_prominence)).flatten();
    let hist = if dominance { &descriptor.dominance } else { above.as_ref().unwrap_or(&descriptor.prominence) };
    if m == 0 || hist.is_empty() {
        return;
    }
    let mut targets = stratified(hist, m, rng);
    targets.sort_by(f64::total_cmp);
    let d = &descriptor.domain;
    let persons = persons(tree, &oro, &people, dominance, d.datum, base, d.min_prominence + FLOOR_MARGIN_M);
    let round = Round { hist, persons, targets };
    let assignment = auction(&normalized_costs(&round.candidates()), m);
    for (i, p) in round.persons.iter().enumerate() {
        let t = round.targets[assignment[i] as usize];
        let s = round.shift(p, t).clamp(p.lo_shift, p.hi_shift);
        let saddle = &mut tree.saddles[p.saddle];
        saddle.elevation -= s;
    }
}

/// The persons of a §5.4 round, one per peak in `people` (those with a key saddle): its current
/// dominance (heights above `datum`) or prominence, how far its key saddle moves per unit of
/// target, the moves that keep the saddle between `base` and its lower peak and the peak's
/// prominence at or above `floor` (the target's threshold; where even the base cannot give it
/// that, any move down to the base), its ridge's length.
fn persons(
    tree: &DivideTree,
    oro: &TreeOrometry,
    people: &[usize],
    dominance: bool,
    datum: f64,
    base: f64,
    floor: f64,
) -> Vec<Person> {
    let dom = oro.dominance(tree, datum);
    people
        .iter()
        .map(|&k| {
            let s = oro.key_saddle[k].unwrap_or(0) as usize;
            let saddle = &tree.saddles[s];
            let [a, b] = saddle.peaks;
            let (pa, pb) = (&tree.peaks[a as usize], &tree.peaks[b as usize]);
            let h_max = pa.elevation.min(pb.elevation);
            let lift = tree.peaks[k].elevation - datum;
            let (current, scale) = if dominance { (dom[k], lift) } else { (oro.prominence[k], 1.0) };
            // h' = h(K) − scale·(target − current) must stay in [base, h_max], and the
            // prominence π + shift at or above the floor.
            let hi_shift = saddle.elevation - base;
            let lo_shift = (saddle.elevation - h_max).max(floor - oro.prominence[k]).min(hi_shift);
            Person {
                current,
                scale,
                saddle: s,
                lo_shift,
                hi_shift,
                length: pa.position.distance(pb.position).max(1e-6),
            }
        })
        .collect()
}

/// One §5.4 assignment problem: persons (peaks with key saddles), sorted targets drawn from
/// `hist`, and the cost of giving a target to a person.
struct Round<'a> {
    hist: &'a FractionHistogram,
    persons: Vec<Person>,
    targets: Vec<f64>,
}

impl Round<'_> {
    /// The histogram bin of `v`; `None` below the histogram's range (a prominence under the
    /// threshold), which is never a target's bin.
    fn bin(&self, v: f64) -> Option<usize> {
        (v >= self.hist.edges[0]).then(|| self.hist.bin(v))
    }

    /// The part of bin `b` a move aims for: the bin less [`BIN_MARGIN`] of its width at each
    /// side (the last bin open above, as it counts everything beyond its top), so the small
    /// changes the terrain makes to prominences do not carry a peak across an edge.
    fn window(&self, b: usize) -> (f64, f64) {
        let (lo, hi) = inside(self.hist, b);
        (lo, if b + 1 == self.hist.fractions.len() { f64::INFINITY } else { hi })
    }

    /// How far `p`'s saddle moves down to reach target `t`. The descriptor only knows bins: a
    /// target in the peak's current bin needs no move, so a round never undoes what the other
    /// round matched within a bin, and a peak below the range always moves. Otherwise the move
    /// goes to the point of `t`'s bin (its [`Round::window`]) nearest `t` that the saddle's range
    /// allows: a target uniform within its bin may lie where this peak cannot go while the rest
    /// of the bin is open to it. Where none of the bin is, the move to `t` (clamped into the
    /// window), whose cost then reports the gap.
    fn shift(&self, p: &Person, t: f64) -> f64 {
        let bin = self.bin(t);
        if bin == self.bin(p.current) || p.scale <= 0.0 {
            return 0.0;
        }
        let (a, b) = self.window(bin.unwrap_or(0));
        let (lo, hi) = (a.max(p.current + p.lo_shift / p.scale), b.min(p.current + p.hi_shift / p.scale));
        let v = if lo <= hi { t.clamp(lo, hi) } else { t.clamp(a, b) };
        p.scale * (v - p.current)
    }

    /// The raw cost s²/L of target `t` for `p` and, for an infeasible target, how far (metres)
    /// the saddle would leave its range.
    fn cost(&self, p: &Person, t: f64) -> (f64, f64) {
        let s = self.shift(p, t);
        let gap = if s < p.lo_shift {
            p.lo_shift - s
        } else if s > p.hi_shift {
            s - p.hi_shift
        } else {
            0.0
        };
        (s * s / p.length, gap)
    }

    /// Each person's candidates `(target, raw cost, gap)`: in every bin, the [`PER_BIN`]
    /// targets nearest its current value (so any bin is open to it, however far), plus the
    /// rank-matched target (the one at its rank among the persons' current values), which
    /// guarantees a perfect matching exists.
    fn candidates(&self) -> Vec<Vec<(u32, f64, f64)>> {
        let (persons, targets) = (&self.persons, &self.targets);
        let m = persons.len();
        let mut order: Vec<usize> = (0..m).collect();
        order.sort_by(|&a, &b| persons[a].current.total_cmp(&persons[b].current).then(a.cmp(&b)));
        let mut rank = vec![0; m];
        for (r, &p) in order.iter().enumerate() {
            rank[p] = r;
        }
        // The sorted targets' index range per bin.
        let mut bins: Vec<std::ops::Range<usize>> = Vec::new();
        for (j, &t) in targets.iter().enumerate() {
            match bins.last_mut() {
                Some(r) if self.bin(targets[r.start]) == self.bin(t) => r.end = j + 1,
                _ => bins.push(j..j + 1),
            }
        }
        persons
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let mut c: Vec<usize> = Vec::with_capacity(bins.len() * PER_BIN + 1);
                for r in &bins {
                    let at = r.start + targets[r.clone()].partition_point(|&t| t < p.current);
                    let lo =
                        at.saturating_sub(PER_BIN / 2).max(r.start).min(r.end.saturating_sub(PER_BIN).max(r.start));
                    c.extend(lo..(lo + PER_BIN).min(r.end));
                }
                if !c.contains(&rank[i]) {
                    c.push(rank[i]);
                }
                c.into_iter()
                    .map(|j| {
                        let (v, gap) = self.cost(p, targets[j]);
                        (j as u32, v, gap)
                    })
                    .collect()
            })
            .collect()
    }
}

/// Auction costs from raw ones: feasible costs scale to [0, 1]; infeasible ones cost 2 + a
/// growing share of 1, so any feasible assignment beats any infeasible one and nearer misses beat
/// farther ones.
fn normalized_costs(raw: &[Vec<(u32, f64, f64)>]) -> Vec<Vec<(u32, f64)>> {
    let scale = raw.iter().flatten().filter(|c| c.2 == 0.0).map(|c| c.1).fold(0.0_f64, f64::max).max(1e-300);
    raw.iter()
        .map(|c| {
            c.iter().map(|&(j, v, gap)| (j, if gap > 0.0 { 2.0 + gap / (gap + 1.0) } else { v / scale })).collect()
        })
        .collect()
}

/// Forward auction with ε-scaling for a sparse assignment problem: person `i` may take object `j`
/// for `cost` when `(j, cost)` is in `candidates[i]`; a perfect matching must exist. Returns each
/// person's object; the total cost is within `m·ε_final` of the optimum. Costs should be of order 1.
pub(crate) fn auction(candidates: &[Vec<(u32, f64)>], objects: usize) -> Vec<u32> {
    let m = candidates.len();
    let benefit: Vec<Vec<(u32, f64)>> = candidates.iter().map(|c| c.iter().map(|&(j, v)| (j, -v)).collect()).collect();
    let mut price = vec![0.0_f64; objects];
    let mut owner = vec![u32::MAX; objects];
    let mut assigned = vec![u32::MAX; m];
    let final_eps = 1e-4 / (m as f64 + 1.0);
    let mut eps = 0.25;
    loop {
        owner.fill(u32::MAX);
        assigned.fill(u32::MAX);
        let mut queue: Vec<u32> = (0..m as u32).rev().collect();
        while let Some(i) = queue.pop() {
            let (mut best, mut second, mut pick) = (f64::NEG_INFINITY, f64::NEG_INFINITY, u32::MAX);
            for &(j, b) in &benefit[i as usize] {
                let v = b - price[j as usize];
                if v > best || (v == best && j < pick) {
                    second = best;
                    best = v;
                    pick = j;
                } else if v > second {
                    second = v;
                }
            }
            let increment = if second.is_finite() { best - second } else { 1.0 };
            price[pick as usize] += increment + eps;
            let previous = owner[pick as usize];
            owner[pick as usize] = i;
            assigned[i as usize] = pick;
            if previous != u32::MAX {
                assigned[previous as usize] = u32::MAX;
                queue.push(previous);
            }
        }
        if eps <= final_eps {
            break;
        }
        eps = (eps / 5.0).max(final_eps);
    }
    assigned
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DomainStats;

    /// A descriptor whose peaks were counted at `min_prominence`, all of them in the [0, 100) m
    /// prominence bin; the other histograms empty.
    fn counted_at(min_prominence: f64) -> Descriptor {
        let empty = FractionHistogram::uniform(0.0, 1.0, 20);
        Descriptor {
            domain: DomainStats {
                min_elevation: 0.0,
                max_elevation: 1000.0,
                area_km2: 100.0,
                radius_m: 5000.0,
                datum: 0.0,
                min_prominence,
            },
            peaks: 10,
            density_per_km2: 0.1,
            dominance: empty.clone(),
            dominance_groups: empty.clone(),
            normalized_elevation: empty.clone(),
            isolation_direction: empty.clone(),
            isolation_distance: empty.clone(),
            saddle_direction: empty.clone(),
            saddle_distance: empty.clone(),
            prominence: FractionHistogram::uniform(0.0, 2000.0, 20).filled([50.0]),
            relative_prominence: empty.clone(),
            relevance: empty,
            higher_peak_distance: None,
        }
    }

    /// A 1000 m summit with three neighbours: B (500 m, col 495), C (400 m, col 340) and
    /// D (20 m above the base at 0, col 10).
    fn summit_and_neighbours() -> DivideTree {
        let peak = |x: f64, elevation| TreePeak { position: DVec2::new(x, 0.0), elevation };
        let saddle = |x: f64, elevation, b| TreeSaddle { position: DVec2::new(x, 0.0), elevation, peaks: [0, b] };
        DivideTree {
            peaks: vec![peak(0.0, 1000.0), peak(1000.0, 500.0), peak(-1000.0, 400.0), peak(2000.0, 20.0)],
            saddles: vec![saddle(500.0, 495.0, 1), saddle(-500.0, 340.0, 2), saddle(1500.0, 10.0, 3)],
        }
    }

    #[test]
    fn peaks_below_the_threshold_are_lifted_into_the_lowest_bin_above_it() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let mut tree = summit_and_neighbours();
        lift_below_threshold(&mut tree, &counted_at(30.0), 0.0, &mut rng, &|_| true);
        let oro = tree.orometry(0.0);
        // B, 5 m prominent, gets 37–93 m: the [30, 100) bin less a tenth of it at each side.
        assert!((37.0..=93.0).contains(&oro.prominence[1]), "{}", oro.prominence[1]);
        // C, 60 m prominent, is left alone; D cannot reach 30 m: its col goes to the base.
        assert_eq!(tree.saddles[1].elevation, 340.0);
        assert_eq!(tree.saddles[2].elevation, 0.0);
        // Without a threshold only prominence-0 peaks would move; B stays.
        let mut tree = summit_and_neighbours();
        lift_below_threshold(&mut tree, &counted_at(0.0), 0.0, &mut rng, &|_| true);
        assert_eq!(tree.saddles[0].elevation, 495.0);
    }

    #[test]
    fn saddle_moves_keep_prominence_above_the_floor_and_dominance_scales_with_the_datum() {
        let tree = summit_and_neighbours();
        let oro = tree.orometry(0.0);
        let people = [1, 2];
        // Prominence rounds, floor 32 m: B (5 m prominent) must move its col down 27 m or more;
        // C (60 m) may raise its col by up to 28 m. Neither col goes below the base.
        let p = persons(&tree, &oro, &people, false, 0.0, 0.0, 32.0);
        assert_eq!((p[0].lo_shift, p[0].hi_shift), (27.0, 495.0));
        assert_eq!((p[1].lo_shift, p[1].hi_shift), (-28.0, 340.0));
        assert_eq!((p[0].current, p[0].scale), (5.0, 1.0));
        // Dominance rounds measure heights from the datum: B stands 400 m above a datum at 100.
        let p = persons(&tree, &oro, &people, true, 100.0, 0.0, 32.0);
        assert_eq!(p[0].scale, 400.0);
        assert!((p[0].current - 5.0 / 400.0).abs() < 1e-12);
        // Where even the base cannot give the floor, any move down to the base is allowed.
        let p = persons(&tree, &oro, &[3], false, 0.0, 0.0, 32.0);
        assert_eq!((p[0].lo_shift, p[0].hi_shift), (10.0, 10.0));
    }

    #[test]
    fn a_quota_closes_a_bin_as_it_fills() {
        let hist = FractionHistogram::uniform(0.0, 1.0, 2).filled([0.2, 0.3, 0.4, 0.9]);
        let mut quota = Quota::new(&hist, 8); // 6 peaks for [0, 0.5), 2 for [0.5, 1]
        assert_eq!(quota.open(0.1), 1.0);
        quota.fill(0.1);
        quota.fill(0.2);
        quota.fill(0.3);
        assert_eq!(quota.open(0.4), 0.5);
        quota.fill(0.7);
        assert_eq!(quota.open(0.7), 0.5);
        assert_eq!(quota.open(3.0), 0.5, "beyond the top counts in the last bin");
        quota.fill(0.8);
        quota.fill(0.9);
        assert_eq!(quota.open(0.9), 0.02, "a full (or overfull) bin keeps a small chance");
        let only_low = FractionHistogram::uniform(0.0, 1.0, 2).filled([0.1]);
        let empty = Quota::new(&only_low, 4);
        assert_eq!(empty.open(0.9), 0.02, "a bin the target never holds");
    }
}
