//! The orometric descriptor of a domain (§4.2, Table 1): ten histograms over its peaks, a
//! distance between descriptors and nearest-neighbour classification against labelled references.
//!
//! | feature | metric | range | bins |
//! |---|---|---|---|
//! | dominance | `δ` | [0, 1] | 20 |
//! | dominance groups | `δ` | [0, 1] | 15 (Jurgalski's elevation-unit thresholds) |
//! | normalized elevation | `ĥ = (h − min)/(max − min)` over the domain | [0, 1] | 20 |
//! | isolation direction | azimuth of the nearest higher ground | [0, 360) | 12 |
//! | isolation distance | `i / R` | [0, 1] | 20 |
//! | key saddle direction | azimuth from the key saddle to the peak | [0, 360) | 12 |
//! | key saddle distance | `‖P − K‖ / R` | [0, 1] | 20 |
//! | prominence | `π`, metres | [0, 2000] | 20 |
//! | relative prominence | `π̃` | [0, 1] | 20 |
//! | relevance | `ρ` | [0, 1] | 20 |
//!
//! Values beyond a range's top (a prominence of 3000 m, an isolation longer than `R`) count in
//! the last bin, as the paper's fixed ranges imply. The highest peak has no isolation and no key
//! saddle, so it is left out of those four histograms. Histograms hold fractions that sum to 1
//! (or are all zero when nothing was counted).
//!
//! The distance between two histograms is the earth mover's distance of their bins, normalized to
//! [0, 1] (the mean absolute difference of the cumulative fractions); for the two direction
//! histograms it is the circular EMD (the cumulative differences less their median, which
//! minimizes the sum: Rabin, Delon & Gousseau 2008). A histogram compared with an empty one is at
//! distance 1, two empty ones at 0. It is the workspace's one EMD,
//! [`relief_hydrology::earth_movers_distance`], measured in bins rather than in the values' unit:
//! bin `k`'s fraction sits at `x = k`, so the CDFs are steps ([`CdfShape::Step`]) whose difference
//! on `[k, k + 1)` is the cumulative difference through bin `k`; the integral over `[0, bins]`,
//! divided by `bins`, is the mean above. Counting in bins makes features with different units
//! (metres, degrees, ratios) comparable, so [`Descriptor::distance`] can average them.

use std::f64::consts::TAU;

use glam::DVec2;
use relief_heightfield::{Extent, Heightfield};
use relief_hydrology::{CdfShape, earth_movers_distance};
use serde::{Deserialize, Serialize};

use crate::point_grid::PointGrid;
use crate::{AnalysisOptions, Orometry, OrometryError, analyze};

/// Jurgalski's dominance thresholds (the "D" column of his elevation-unit chart, in percent),
/// the bin edges of the dominance-groups histogram.
pub const DOMINANCE_GROUP_EDGES: [f64; 16] =
    [0.0, 0.35, 0.70, 1.40, 2.10, 4.20, 7.00, 10.50, 14.00, 19.25, 24.50, 36.75, 49.00, 68.60, 88.20, 100.0];

/// The ten features of Table 1, in the descriptor's order.
pub const FEATURES: [&str; 10] = [
    "dominance",
    "dominance_groups",
    "normalized_elevation",
    "isolation_direction",
    "isolation_distance",
    "saddle_direction",
    "saddle_distance",
    "prominence",
    "relative_prominence",
    "relevance",
];

/// A normalized histogram: the fraction of the values in each bin over explicit bin edges,
/// compared with others of the same bins by [`FractionHistogram::emd`] (in bins, so in [0, 1]).
/// (Not to be confused with [`relief_hydrology::CountHistogram`], counts in equal-width bins
/// compared in the values' unit.)
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FractionHistogram {
    /// `bins + 1` increasing edges.
    pub edges: Vec<f64>,
    /// Fraction of the values in each bin; sums to 1, or all zero for an empty histogram.
    pub fractions: Vec<f64>,
    /// The values wrap around (directions): the distance is circular.
    #[serde(default)]
    pub circular: bool,
}

impl FractionHistogram {
    /// `bins` equal bins over `[lo, hi]`.
    pub fn uniform(lo: f64, hi: f64, bins: usize) -> Self {
        let edges = (0..=bins).map(|k| lo + (hi - lo) * k as f64 / bins as f64).collect();
        Self { edges, fractions: vec![0.0; bins], circular: false }
    }

    fn with_edges(edges: Vec<f64>) -> Self {
        let bins = edges.len() - 1;
        Self { edges, fractions: vec![0.0; bins], circular: false }
    }

    fn circular(mut self) -> Self {
        self.circular = true;
        self
    }

    /// The bin of `v`: below the first edge the first bin, beyond the last the last (for a
    /// circular histogram, wrap `v` first).
    pub(crate) fn bin(&self, v: f64) -> usize {
        self.edges[1..self.fractions.len()].partition_point(|&e| e <= v)
    }

    /// The histogram of `values` (non-finite ones skipped; out-of-range ones clamped into the
    /// first or last bin, or wrapped for a circular histogram).
    #[must_use]
    pub fn filled(mut self, values: impl IntoIterator<Item = f64>) -> Self {
        let bins = self.fractions.len();
        let (lo, hi) = (self.edges[0], self.edges[bins]);
        let mut counts = vec![0u64; bins];
        for v in values.into_iter().filter(|v| v.is_finite()) {
            let v = if self.circular { lo + (v - lo).rem_euclid(hi - lo) } else { v };
            counts[self.bin(v)] += 1;
        }
        let total: u64 = counts.iter().sum();
        if total > 0 {
            self.fractions = counts.iter().map(|&c| c as f64 / total as f64).collect();
        }
        self
    }

    /// Whether nothing was counted.
    pub fn is_empty(&self) -> bool {
        self.fractions.iter().all(|&f| f == 0.0)
    }

    /// Checks the shape: at least one bin, increasing finite edges, finite non-negative fractions
    /// that sum to 1 (or are all zero).
    ///
    /// # Errors
    /// [`OrometryError::InvalidDescriptor`] naming the problem.
    pub fn validate(&self, name: &'static str) -> Result<(), OrometryError> {
        let bad = |reason: &'static str| Err(OrometryError::InvalidDescriptor { feature: name, reason });
        if self.fractions.is_empty() || self.edges.len() != self.fractions.len() + 1 {
            return bad("needs at least one bin and one more edge than bins");
        }
        if !self.edges.iter().all(|e| e.is_finite()) || self.edges.windows(2).any(|w| w[1] <= w[0]) {
            return bad("edges must be finite and increasing");
        }
        if !self.fractions.iter().all(|f| f.is_finite() && *f >= 0.0) {
            return bad("fractions must be finite and ≥ 0");
        }
        let sum: f64 = self.fractions.iter().sum();
        if sum != 0.0 && (sum - 1.0).abs() > 1e-6 {
            return bad("fractions must sum to 1 (or all be 0)");
        }
        Ok(())
    }

    /// Earth mover's distance to `other` in [0, 1] (see the module docs): with `D_k` the
    /// cumulative difference of the fractions through bin `k`, `Σ_k |D_k − c| / bins`, where `c`
    /// is 0, or for a circular histogram (either one) the median of the `D_k`. `None` when the
    /// bins differ.
    pub fn emd(&self, other: &Self) -> Option<f64> {
        if self.fractions.len() != other.fractions.len() {
            return None;
        }
        match (self.is_empty(), other.is_empty()) {
            (true, true) => return Some(0.0),
            (true, false) | (false, true) => return Some(1.0),
            _ => {}
        }
        let bins = self.fractions.len();
        let mut cum = 0.0;
        let diffs: Vec<f64> = self
            .fractions
            .iter()
            .zip(&other.fractions)
            .map(|(a, b)| {
                cum += a - b;
                cum
            })
            .collect();
        let shift = if self.circular || other.circular {
            let mut sorted = diffs.clone();
            sorted.sort_by(f64::total_cmp);
            sorted[bins / 2]
        } else {
            0.0
        };
        // Step CDFs over bin indices: the difference is `diffs[k]` on `[k, k + 1)`, and the last
        // breakpoint, `bins`, only closes the last interval.
        let steps = diffs.iter().enumerate().map(|(k, &d)| (k as f64, d - shift)).chain([(bins as f64, 0.0)]);
        Some(earth_movers_distance(steps, CdfShape::Step) / bins as f64)
    }

    /// The largest difference between matching bins (the paper's "maximum histogram error").
    pub fn max_bin_error(&self, other: &Self) -> Option<f64> {
        (self.fractions.len() == other.fractions.len())
            .then(|| self.fractions.iter().zip(&other.fractions).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max))
    }

    /// The histogram of values known to be at least `floor` (a linear histogram counted above a
    /// threshold that falls inside a bin, such as prominences at or above 30 m in the [0, 100)
    /// bin): the bins wholly below `floor` dropped, the one holding it starting at `floor`, the
    /// fractions renormalized. `None` when nothing lies at or above `floor`, or for a circular
    /// histogram. At or below the lowest edge it is the histogram itself.
    #[must_use]
    pub fn from_floor(&self, floor: f64) -> Option<Self> {
        if self.circular || floor.is_nan() {
            return None;
        }
        if floor <= self.edges[0] {
            return Some(self.clone());
        }
        let first = self.edges[1..].partition_point(|&e| e <= floor);
        let kept = self.fractions.get(first..)?;
        let sum: f64 = kept.iter().sum();
        if sum <= 0.0 {
            return None;
        }
        let mut edges = self.edges[first..].to_vec();
        edges[0] = floor;
        Some(Self { edges, fractions: kept.iter().map(|f| f / sum).collect(), circular: false })
    }

    /// The value at cumulative fraction `u ∈ [0, 1]`, linear within a bin (the inverse CDF).
    /// `None` for an empty histogram.
    pub fn quantile(&self, u: f64) -> Option<f64> {
        if self.is_empty() {
            return None;
        }
        let u = u.clamp(0.0, 1.0);
        let mut cum = 0.0;
        let last = self.fractions.iter().rposition(|&f| f > 0.0).unwrap_or(0);
        for (b, &f) in self.fractions.iter().enumerate() {
            if f > 0.0 && (u <= cum + f || b == last) {
                let t = ((u - cum) / f).clamp(0.0, 1.0);
                return Some(self.edges[b] + t * (self.edges[b + 1] - self.edges[b]));
            }
            cum += f;
        }
        None
    }

    /// The fraction density at `v` relative to the fullest bin, in [0, 1] (0 outside the range
    /// of a linear histogram, wrapped for a circular one). Dart throwing uses it as an acceptance
    /// probability.
    pub fn relative_density(&self, v: f64) -> f64 {
        let bins = self.fractions.len();
        let (lo, hi) = (self.edges[0], self.edges[bins]);
        let v = if self.circular { lo + (v - lo).rem_euclid(hi - lo) } else { v.min(hi) };
        if v.is_nan() || v < lo {
            return 0.0;
        }
        let peak = self.fractions.iter().zip(self.edges.windows(2)).map(|(f, w)| f / (w[1] - w[0])).fold(0.0, f64::max);
        if peak == 0.0 {
            return 1.0;
        }
        let b = self.bin(v);
        self.fractions[b] / (self.edges[b + 1] - self.edges[b]) / peak
    }
}

/// Domain facts the descriptor normalizes by.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DomainStats {
    /// Lowest valid elevation.
    pub min_elevation: f64,
    /// Highest valid elevation.
    pub max_elevation: f64,
    /// Area, km².
    pub area_km2: f64,
    /// The radius `R` that isolation and key-saddle distances are divided by, metres.
    pub radius_m: f64,
    /// The level dominance measures heights from: the sea level of the analysis, or 0.
    #[serde(default)]
    pub datum: f64,
    /// The prominence threshold the peaks were counted at (0 when unknown): synthesis draws
    /// prominences at or above it, so the terrain analysed at the same threshold keeps its peaks.
    #[serde(default)]
    pub min_prominence: f64,
}

impl DomainStats {
    /// The stats of a DEM: its valid range, ground area, and `R` = the radius of the disc of the
    /// same area (the paper analyses discs of radius R).
    pub fn of(dem: &Heightfield) -> Self {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &v in dem.samples().iter().filter(|v| !v.is_nan()) {
            lo = lo.min(f64::from(v));
            hi = hi.max(f64::from(v));
        }
        let grid = dem.grid();
        let area_m2: f64 = (0..grid.ny()).map(|j| grid.cell_area_m2(j) * grid.nx() as f64).sum();
        Self {
            min_elevation: lo,
            max_elevation: hi,
            area_km2: area_m2 / 1e6,
            radius_m: (area_m2 / std::f64::consts::PI).sqrt(),
            datum: 0.0,
            min_prominence: 0.0,
        }
    }
}

/// The orometric descriptor of a domain: Table 1's ten histograms plus the peak density and the
/// elevation range they were measured over (which synthesis needs to turn them back into metres).
/// Deserializing validates it ([`Descriptor::validate`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(remote = "Self")]
pub struct Descriptor {
    /// The domain the peaks came from.
    pub domain: DomainStats,
    /// Peaks counted.
    pub peaks: usize,
    /// Peaks per km².
    pub density_per_km2: f64,
    /// `δ`, 20 bins over [0, 1].
    pub dominance: FractionHistogram,
    /// `δ` in percent over Jurgalski's groups ([`DOMINANCE_GROUP_EDGES`]).
    pub dominance_groups: FractionHistogram,
    /// `ĥ`, 20 bins over [0, 1].
    pub normalized_elevation: FractionHistogram,
    /// Isolation azimuth, degrees clockwise from north, 12 bins.
    pub isolation_direction: FractionHistogram,
    /// Isolation distance / R, 20 bins over [0, 1].
    pub isolation_distance: FractionHistogram,
    /// Azimuth from the key saddle to the peak, 12 bins.
    pub saddle_direction: FractionHistogram,
    /// Key-saddle distance / R, 20 bins over [0, 1].
    pub saddle_distance: FractionHistogram,
    /// Prominence, metres, 20 bins over [0, 2000].
    pub prominence: FractionHistogram,
    /// `π̃`, 20 bins over [0, 1].
    pub relative_prominence: FractionHistogram,
    /// `ρ`, 20 bins over [0, 1].
    pub relevance: FractionHistogram,
    /// Distance from each peak to the nearest higher peak / R, 20 bins over [0, 1]: not a
    /// Table 1 feature (distances and classification leave it out) but what synthesis places
    /// peaks by. A dart's distance to the peaks already placed (all higher) is a nearest-higher-
    /// peak distance; isolation, the distance to higher *ground*, is shorter on a terrain, so
    /// darts accepted by the isolation histogram crowd the peaks. `None` in descriptors written
    /// before it existed: synthesis then falls back to the isolation histogram.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub higher_peak_distance: Option<FractionHistogram>,
}

impl Serialize for Descriptor {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        Descriptor::serialize(self, s)
    }
}

impl<'de> Deserialize<'de> for Descriptor {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let descriptor = Descriptor::deserialize(d)?;
        descriptor.validate().map_err(serde::de::Error::custom)?;
        Ok(descriptor)
    }
}

/// How two descriptors differ, feature by feature.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DescriptorDistance {
    /// `(feature, EMD, max bin error)` in [`FEATURES`] order.
    pub features: Vec<(String, f64, f64)>,
    /// The mean EMD over the features: the distance classification ranks by.
    pub mean_emd: f64,
}

impl DescriptorDistance {
    /// The EMD and max bin error of one feature.
    pub fn feature(&self, name: &str) -> Option<(f64, f64)> {
        self.features.iter().find(|(n, ..)| n == name).map(|&(_, e, m)| (e, m))
    }
}

/// Each peak's ground distance, metres, to the nearest strictly higher peak (`None` for those
/// with none), peaks given as `(position, elevation)`: inserted highest first into a bucket grid,
/// each equal-height group queried before it is inserted. Positions are scaled by
/// `metres_per_unit` first.
fn nearest_higher_peaks(peaks: &[(DVec2, f64)], metres_per_unit: DVec2) -> Vec<Option<f64>> {
    let at: Vec<DVec2> = peaks.iter().map(|&(p, _)| p * metres_per_unit).collect();
    let mut out = vec![None; peaks.len()];
    let Some(extent) =
        at.iter().fold(None, |e: Option<(DVec2, DVec2)>, &p| Some(e.map_or((p, p), |(lo, hi)| (lo.min(p), hi.max(p)))))
    else {
        return out;
    };
    let mut grid = PointGrid::new(&Extent::new(extent.0, extent.1), peaks.len());
    let mut order: Vec<usize> = (0..peaks.len()).collect();
    order.sort_by(|&a, &b| peaks[b].1.total_cmp(&peaks[a].1));
    for group in order.chunk_by(|&a, &b| peaks[a].1 == peaks[b].1) {
        for &k in group {
            out[k] = grid.nearest(at[k], &at).map(|(_, d)| d);
        }
        for &k in group {
            grid.insert(k as u32, at[k]);
        }
    }
    out
}

/// Ground distance in metres between two world positions of `dem`'s grid, and the azimuth of
/// `to` seen from `from` (degrees clockwise from north).
fn ground_vector(dem_units_m: DVec2, from: DVec2, to: DVec2) -> (f64, f64) {
    let d = (to - from) * dem_units_m;
    (d.length(), d.x.atan2(d.y).to_degrees().rem_euclid(360.0))
}

impl Descriptor {
    /// The descriptor of analysed peaks over a domain. Metres per grid unit are taken from
    /// `metres_per_unit` (1 for projected grids; [`relief_heightfield::metres_per_degree`] at the
    /// domain's latitude for geographic ones).
    pub fn from_orometry(oro: &Orometry, domain: DomainStats, metres_per_unit: DVec2) -> Self {
        let peaks = &oro.peaks;
        let summits: Vec<(DVec2, f64)> = peaks.iter().map(|p| (DVec2::from(p.position), p.elevation)).collect();
        let r = domain.radius_m.max(f64::MIN_POSITIVE);
        let span = (domain.max_elevation - domain.min_elevation).max(f64::MIN_POSITIVE);
        let unit = |lo: f64, hi: f64| FractionHistogram::uniform(lo, hi, 20);
        let saddle = |p: &crate::Peak| {
            p.key_saddle.map(|s| {
                let s = &oro.saddles[s];
                ground_vector(metres_per_unit, DVec2::from(s.position), DVec2::from(p.position))
            })
        };
        Self {
            domain,
            peaks: peaks.len(),
            density_per_km2: if domain.area_km2 > 0.0 { peaks.len() as f64 / domain.area_km2 } else { 0.0 },
            dominance: unit(0.0, 1.0).filled(peaks.iter().map(|p| p.dominance)),
            dominance_groups: FractionHistogram::with_edges(DOMINANCE_GROUP_EDGES.to_vec())
                .filled(peaks.iter().map(|p| 100.0 * p.dominance)),
            normalized_elevation: unit(0.0, 1.0)
                .filled(peaks.iter().map(|p| (p.elevation - domain.min_elevation) / span)),
            isolation_direction: FractionHistogram::uniform(0.0, 360.0, 12)
                .circular()
                .filled(peaks.iter().filter_map(|p| p.isolation.map(|i| i.azimuth))),
            isolation_distance: unit(0.0, 1.0).filled(peaks.iter().filter_map(|p| p.isolation.map(|i| i.distance / r))),
            saddle_direction: FractionHistogram::uniform(0.0, 360.0, 12)
                .circular()
                .filled(peaks.iter().filter_map(|p| saddle(p).map(|(_, az)| az))),
            saddle_distance: unit(0.0, 1.0).filled(peaks.iter().filter_map(|p| saddle(p).map(|(d, _)| d / r))),
            prominence: unit(0.0, 2000.0).filled(peaks.iter().map(|p| p.prominence)),
            relative_prominence: unit(0.0, 1.0).filled(peaks.iter().map(|p| p.relative_prominence)),
            relevance: unit(0.0, 1.0).filled(peaks.iter().map(|p| p.relevance)),
            higher_peak_distance: Some(
                unit(0.0, 1.0)
                    .filled(nearest_higher_peaks(&summits, metres_per_unit).into_iter().flatten().map(|d| d / r)),
            ),
        }
    }

    /// Analyses `dem` and describes its peaks: the analysis and the descriptor.
    ///
    /// # Errors
    /// Those of [`analyze`].
    pub fn of(dem: &Heightfield, options: &AnalysisOptions) -> Result<(Orometry, Self), OrometryError> {
        Self::with_radius(dem, options, None)
    }

    /// [`Descriptor::of`] with distances divided by `radius_m` instead of the DEM's equal-area
    /// radius: descriptors compare only at the same `R`, so describe a synthesized terrain with
    /// its target's `R`.
    ///
    /// # Errors
    /// Those of [`analyze`], or [`OrometryError::InvalidOption`] for a radius that is not finite
    /// and positive.
    pub fn with_radius(
        dem: &Heightfield,
        options: &AnalysisOptions,
        radius_m: Option<f64>,
    ) -> Result<(Orometry, Self), OrometryError> {
        if let Some(r) = radius_m.filter(|r| !(r.is_finite() && *r > 0.0)) {
            return Err(OrometryError::InvalidOption { name: "radius_m", value: r, reason: "must be finite and > 0" });
        }
        let oro = analyze(dem, options)?;
        let grid = dem.grid();
        let mut stats = DomainStats::of(dem);
        if let Some(r) = radius_m {
            stats.radius_m = r;
        }
        stats.datum = options.sea_level.map_or(0.0, f64::from);
        stats.min_prominence = options.min_prominence;
        let d = Self::from_orometry(&oro, stats, grid.metres_per_unit(grid.ny() / 2));
        Ok((oro, d))
    }

    /// The histograms in [`FEATURES`] order.
    pub fn histograms(&self) -> [&FractionHistogram; 10] {
        [
            &self.dominance,
            &self.dominance_groups,
            &self.normalized_elevation,
            &self.isolation_direction,
            &self.isolation_distance,
            &self.saddle_direction,
            &self.saddle_distance,
            &self.prominence,
            &self.relative_prominence,
            &self.relevance,
        ]
    }

    /// Checks every histogram and the domain facts (for descriptors read from files).
    ///
    /// # Errors
    /// [`OrometryError::InvalidDescriptor`] naming the first bad feature.
    pub fn validate(&self) -> Result<(), OrometryError> {
        for (name, h) in FEATURES.iter().zip(self.histograms()) {
            h.validate(name)?;
        }
        if let Some(h) = &self.higher_peak_distance {
            h.validate("higher_peak_distance")?;
        }
        let d = &self.domain;
        let bad = |feature, reason| Err(OrometryError::InvalidDescriptor { feature, reason });
        if !(d.min_elevation.is_finite()
            && d.max_elevation.is_finite()
            && d.max_elevation >= d.min_elevation
            && d.datum.is_finite())
        {
            return bad("domain", "min/max elevation and datum must be finite with min ≤ max");
        }
        if !(d.radius_m > 0.0 && d.radius_m.is_finite() && d.area_km2 >= 0.0 && d.area_km2.is_finite()) {
            return bad("domain", "radius and area must be finite and positive");
        }
        if !(self.density_per_km2 >= 0.0 && self.density_per_km2.is_finite()) {
            return bad("density_per_km2", "must be finite and ≥ 0");
        }
        if !(d.min_prominence >= 0.0 && d.min_prominence.is_finite()) {
            return bad("domain", "min_prominence must be finite and ≥ 0");
        }
        Ok(())
    }

    /// Feature-by-feature distance to `other`.
    ///
    /// # Errors
    /// [`OrometryError::InvalidDescriptor`] when a feature's bins differ between the two.
    pub fn distance(&self, other: &Self) -> Result<DescriptorDistance, OrometryError> {
        let mut features = Vec::with_capacity(FEATURES.len());
        for ((name, a), b) in FEATURES.iter().zip(self.histograms()).zip(other.histograms()) {
            let (Some(emd), Some(max)) = (a.emd(b), a.max_bin_error(b)) else {
                return Err(OrometryError::InvalidDescriptor {
                    feature: name,
                    reason: "the two descriptors bin this feature differently",
                });
            };
            features.push(((*name).to_owned(), emd, max));
        }
        let mean_emd = features.iter().map(|f| f.1).sum::<f64>() / features.len() as f64;
        Ok(DescriptorDistance { features, mean_emd })
    }
}

/// Nearest-neighbour classification: the index of the reference descriptor closest to `query`
/// (by mean EMD) and that distance; `None` when there are no references.
///
/// # Errors
/// As [`Descriptor::distance`].
pub fn classify<'a>(
    query: &Descriptor,
    references: impl IntoIterator<Item = &'a Descriptor>,
) -> Result<Option<(usize, f64)>, OrometryError> {
    let mut best: Option<(usize, f64)> = None;
    for (k, r) in references.into_iter().enumerate() {
        let d = query.distance(r)?.mean_emd;
        if best.is_none_or(|(_, b)| d < b) {
            best = Some((k, d));
        }
    }
    Ok(best)
}

/// Azimuth of `v` in radians clockwise from north, in [0, 2π).
pub(crate) fn azimuth(v: DVec2) -> f64 {
    v.x.atan2(v.y).rem_euclid(TAU)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_higher_peaks_measure_ground_distance_to_strictly_higher_peaks() {
        let peaks = [
            (DVec2::new(0.0, 0.0), 100.0),
            (DVec2::new(4.0, 0.0), 80.0),
            (DVec2::new(4.0, 1.0), 80.0), // as high as its neighbour: measured to the first
            (DVec2::new(1.0, 1.0), 50.0),
        ];
        // Units of 2 m east and 3 m north.
        let d = nearest_higher_peaks(&peaks, DVec2::new(2.0, 3.0));
        assert_eq!(d[0], None);
        assert_eq!(d[1], Some(8.0));
        assert_eq!(d[2], Some(DVec2::new(8.0, 3.0).length()));
        assert_eq!(d[3], Some(DVec2::new(2.0, 3.0).length()));
        assert_eq!(nearest_higher_peaks(&[], DVec2::ONE), Vec::<Option<f64>>::new());
    }
}
