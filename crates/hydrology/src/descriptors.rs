//! Terrain descriptors (contours paper §6.5): histograms of elevation, slope and drainage area,
//! the maximum Strahler order, and a distance between two descriptor sets.

use relief_heightfield::{GridSpec, Heightfield, Units, metres_per_degree};
use serde::{Deserialize, Serialize};

use crate::emd::{CdfShape, earth_movers_distance};
use crate::error::check_param;
use crate::flow::{D8, Mfd, mfd_drainage_area};
use crate::{HydrologyError, Outlets, fill};

/// A histogram of sample counts in equal-width bins over `[lo, hi]`, in the unit of the values.
/// Its distance, [`CountHistogram::wasserstein`], is in that unit too and compares histograms of
/// any range and bin count. (Not to be confused with `relief_orometry::FractionHistogram`,
/// fractions over explicit edges compared bin by bin, nor with `relief_contours::Histogram`, a
/// target elevation distribution.)
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CountHistogram {
    /// Lower edge of the first bin.
    pub lo: f64,
    /// Upper edge of the last bin.
    pub hi: f64,
    /// Samples per bin.
    pub counts: Vec<u64>,
}

impl CountHistogram {
    /// Bins `values` (finite ones only) into `bins` equal bins (clamped to 1..=[`MAX_BINS`])
    /// spanning their range. A single distinct value gets a unit-wide range around it.
    pub fn of(values: impl Iterator<Item = f64> + Clone, bins: usize) -> Self {
        let bins = bins.clamp(1, MAX_BINS);
        let (mut lo, mut hi) = values
            .clone()
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
        if lo > hi {
            (lo, hi) = (0.0, 1.0);
        } else if lo == hi {
            (lo, hi) = (lo - 0.5, hi + 0.5);
        }
        let mut counts = vec![0u64; bins];
        let width = (hi - lo) / bins as f64;
        for v in values.filter(|v| v.is_finite()) {
            let b = (((v - lo) / width) as usize).min(bins - 1);
            counts[b] += 1;
        }
        Self { lo, hi, counts }
    }

    /// Number of samples.
    pub fn total(&self) -> u64 {
        self.counts.iter().sum()
    }

    /// The cumulative share of samples at or below `x`, samples spread evenly within each bin.
    pub fn cdf(&self, x: f64) -> f64 {
        let total = self.total();
        if total == 0 || x <= self.lo {
            return 0.0;
        }
        if x >= self.hi {
            return 1.0;
        }
        let width = (self.hi - self.lo) / self.counts.len() as f64;
        let pos = (x - self.lo) / width;
        let b = (pos as usize).min(self.counts.len() - 1);
        let below: u64 = self.counts[..b].iter().sum();
        (below as f64 + self.counts[b] as f64 * (pos - b as f64)) / total as f64
    }

    /// Bin edges.
    pub fn edges(&self) -> impl Iterator<Item = f64> + '_ {
        let width = (self.hi - self.lo) / self.counts.len() as f64;
        (0..=self.counts.len()).map(move |b| self.lo + width * b as f64)
    }

    /// Earth mover's (1-Wasserstein) distance between the two distributions, in the unit of the
    /// values: ∫|F₁ − F₂|, exact for histograms ([`earth_movers_distance`] with
    /// [`CdfShape::Linear`] over the edges of both: both CDFs are piecewise linear, so between
    /// consecutive edges of either the integrand is linear but for one possible sign change).
    /// Histograms with different ranges and bin counts compare fine; an empty one is at distance 0
    /// from anything.
    pub fn wasserstein(&self, other: &Self) -> f64 {
        if self.total() == 0 || other.total() == 0 {
            return 0.0;
        }
        let mut xs: Vec<f64> = self.edges().chain(other.edges()).collect();
        xs.sort_by(f64::total_cmp);
        xs.dedup();
        earth_movers_distance(xs.iter().map(|&x| (x, self.cdf(x) - other.cdf(x))), CdfShape::Linear)
    }
}

/// The most bins a descriptor histogram may have.
pub const MAX_BINS: usize = 65_536;

/// Options for [`Descriptors::of`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DescriptorOptions {
    /// Bins per histogram (default 64, at most [`MAX_BINS`]).
    pub bins: usize,
    /// How drainage area is routed for its histogram (default Freeman MFD, as the contours
    /// paper's comparison).
    pub routing: Mfd,
    /// Streams for the Strahler order start at this D8 drainage area, m². Default: 0.5 % of the
    /// terrain's area.
    pub stream_area_m2: Option<f64>,
    /// Where water leaves (default: border and no-data).
    pub outlets: Outlets,
}

impl Default for DescriptorOptions {
    fn default() -> Self {
        Self { bins: 64, routing: Mfd::default(), stream_area_m2: None, outlets: Outlets::default() }
    }
}

/// A compact, serialisable summary of a terrain: what §6.5 of the contours paper compares between
/// a generated terrain and a real one.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Descriptors {
    /// Elevations of valid cells.
    pub elevation: CountHistogram,
    /// Slopes of valid cells, degrees.
    pub slope_deg: CountHistogram,
    /// log₁₀ of the drainage area (m²) of valid cells, on the depression-filled DEM.
    pub log10_drainage_area: CountHistogram,
    /// The largest Strahler order of the D8 stream network.
    pub max_strahler: u8,
    /// The stream threshold used, m².
    pub stream_area_m2: f64,
    /// Valid cells.
    pub cells: usize,
}

/// How far apart two [`Descriptors`] are: the earth mover's distance per histogram (in metres,
/// degrees and decades of m²) and the difference in maximum Strahler order.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DescriptorDistance {
    /// Elevation distance, elevation units.
    pub elevation: f64,
    /// Slope distance, degrees.
    pub slope_deg: f64,
    /// Drainage-area distance, decades (log₁₀ m²).
    pub log10_drainage_area: f64,
    /// `other.max_strahler − self.max_strahler`.
    pub strahler: i32,
}

impl Descriptors {
    /// Computes the descriptors of `hf` (the drainage measures on its Priority-Flood+ε fill).
    ///
    /// # Errors
    /// [`HydrologyError::AllNoData`], or [`HydrologyError::InvalidParameter`] for zero bins or a
    /// negative stream threshold.
    pub fn of(hf: &Heightfield, options: &DescriptorOptions) -> Result<Self, HydrologyError> {
        check_param("bins", options.bins as f64, |b| (1.0..=MAX_BINS as f64).contains(&b), "must lie in 1..=65536")?;
        // Slopes and areas in metres: a geographic grid is measured at its middle latitude.
        let metric;
        let hf = match metric_copy(hf) {
            Some(copy) => {
                metric = copy;
                &metric
            }
            None => hf,
        };
        let filled = fill(hf, options.outlets)?;
        let z = hf.samples();
        let cells = z.iter().filter(|v| !v.is_nan()).count();
        let elevation = CountHistogram::of(z.iter().map(|&v| f64::from(v)), options.bins);
        let (nx, ny) = (hf.nx(), hf.ny());
        let slopes: Vec<f64> = (0..ny)
            .flat_map(|j| (0..nx).map(move |i| (i, j)))
            .filter_map(|(i, j)| hf.slope(i, j))
            .map(f64::to_degrees)
            .collect();
        let slope_deg = CountHistogram::of(slopes.iter().copied(), options.bins);
        let area = mfd_drainage_area(&filled, options.routing)?;
        let log_area =
            CountHistogram::of(area.iter().zip(z).filter(|(_, v)| !v.is_nan()).map(|(a, _)| a.log10()), options.bins);
        let d8 = D8::new(&filled)?;
        // Everything drains to a sink of the filled DEM, so the sinks hold the whole valid area.
        let stream_area_m2 = options
            .stream_area_m2
            .unwrap_or_else(|| 0.005 * d8.sinks().map(|(i, j)| d8.drainage_area()[hf.grid().index(i, j)]).sum::<f64>());
        let streams = d8.streams(stream_area_m2)?;
        let max_strahler = d8.strahler(&streams)?.into_iter().max().unwrap_or(0);
        Ok(Self { elevation, slope_deg, log10_drainage_area: log_area, max_strahler, stream_area_m2, cells })
    }

    /// The distance from `self` to `other`.
    pub fn distance(&self, other: &Self) -> DescriptorDistance {
        DescriptorDistance {
            elevation: self.elevation.wasserstein(&other.elevation),
            slope_deg: self.slope_deg.wasserstein(&other.slope_deg),
            log10_drainage_area: self.log10_drainage_area.wasserstein(&other.log10_drainage_area),
            strahler: i32::from(other.max_strahler) - i32::from(self.max_strahler),
        }
    }
}

/// A geographic heightfield on a metric grid of the same samples (cells measured at the middle
/// latitude); `None` for a planar one.
fn metric_copy(hf: &Heightfield) -> Option<Heightfield> {
    let grid = hf.grid();
    if grid.units() != Units::Degrees {
        return None;
    }
    let extent = grid.extent();
    let scale = metres_per_degree(0.5 * (extent.min.y + extent.max.y));
    let metric = GridSpec::new(grid.nx(), grid.ny(), extent.min, grid.cell_size() * scale).ok()?;
    Heightfield::from_samples(metric, hf.samples().to_vec()).ok()
}
