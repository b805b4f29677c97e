use serde::{Deserialize, Serialize};

use crate::ContoursError;

/// A target distribution of elevations H (the contours paper, §3.3): the proportion of terrain at
/// each height. Stored as a piecewise-linear cumulative distribution through knots `(height, F)`,
/// so heights within a bin are spread uniformly and a list of sample elevations interpolates
/// between consecutive samples.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "HistogramSpec", into = "HistogramSpec")]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct Histogram {
    knots: Vec<(f64, f64)>,
    spec: HistogramSpec,
}

/// How a histogram is written in a scene file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub enum HistogramSpec {
    /// Bins: `edges` (n + 1, increasing) and non-negative `weights` (n), not necessarily normalised.
    Bins {
        /// Bin edges, strictly increasing.
        edges: Vec<f64>,
        /// Relative weight of each bin.
        weights: Vec<f64>,
    },
    /// Sample elevations (e.g. every cell of a real DEM); their empirical distribution is the target.
    Samples(Vec<f64>),
    /// Uniform between two heights.
    Uniform {
        /// Lowest height.
        min: f64,
        /// Highest height.
        max: f64,
    },
}

impl TryFrom<HistogramSpec> for Histogram {
    type Error = ContoursError;
    fn try_from(spec: HistogramSpec) -> Result<Self, ContoursError> {
        match &spec {
            HistogramSpec::Bins { edges, weights } => Self::build_bins(edges, weights, spec.clone()),
            HistogramSpec::Samples(s) => Self::build_samples(s, spec.clone()),
            HistogramSpec::Uniform { min, max } => Self::build_bins(&[*min, *max], &[1.0], spec.clone()),
        }
    }
}

impl From<Histogram> for HistogramSpec {
    fn from(h: Histogram) -> Self {
        h.spec
    }
}

impl Histogram {
    /// From bin edges and weights.
    ///
    /// # Errors
    /// [`ContoursError::EmptyHistogram`] when every weight is zero or there are no bins,
    /// [`ContoursError::InvalidHistogram`] for non-increasing edges, negative or non-finite
    /// weights, or mismatched lengths.
    pub fn from_bins(edges: Vec<f64>, weights: Vec<f64>) -> Result<Self, ContoursError> {
        Self::try_from(HistogramSpec::Bins { edges, weights })
    }

    /// From sample elevations.
    ///
    /// # Errors
    /// [`ContoursError::EmptyHistogram`] for no samples, [`ContoursError::NonFinite`] for NaN/∞.
    pub fn from_samples(samples: Vec<f64>) -> Result<Self, ContoursError> {
        Self::try_from(HistogramSpec::Samples(samples))
    }

    /// Uniform on `[min, max]`.
    ///
    /// # Errors
    /// [`ContoursError::InvalidHistogram`] unless `min < max`, both finite.
    pub fn uniform(min: f64, max: f64) -> Result<Self, ContoursError> {
        Self::try_from(HistogramSpec::Uniform { min, max })
    }

    fn build_bins(edges: &[f64], weights: &[f64], spec: HistogramSpec) -> Result<Self, ContoursError> {
        let bad = |reason: String| Err(ContoursError::InvalidHistogram { reason });
        if weights.is_empty() {
            return Err(ContoursError::EmptyHistogram);
        }
        if edges.len() != weights.len() + 1 {
            return bad(format!("{} edges for {} bins: need one more edge than bins", edges.len(), weights.len()));
        }
        if let Some(k) = (0..edges.len()).find(|&k| !edges[k].is_finite() || (k > 0 && edges[k] <= edges[k - 1])) {
            return bad(format!("edge {k} ({}) is not finite or not above the previous edge", edges[k]));
        }
        if let Some(k) = weights.iter().position(|w| !(w.is_finite() && *w >= 0.0)) {
            return bad(format!("weight {k} is {}; weights must be finite and >= 0", weights[k]));
        }
        let total: f64 = weights.iter().sum();
        if total <= 0.0 {
            return Err(ContoursError::EmptyHistogram);
        }
        let mut knots = Vec::with_capacity(edges.len());
        let mut acc = 0.0;
        knots.push((edges[0], 0.0));
        for (k, w) in weights.iter().enumerate() {
            acc += w / total;
            knots.push((edges[k + 1], if k + 1 == weights.len() { 1.0 } else { acc.min(1.0) }));
        }
        Ok(Self { knots, spec })
    }

    fn build_samples(samples: &[f64], spec: HistogramSpec) -> Result<Self, ContoursError> {
        if samples.is_empty() {
            return Err(ContoursError::EmptyHistogram);
        }
        if let Some(&v) = samples.iter().find(|v| !v.is_finite()) {
            return Err(ContoursError::NonFinite { what: "histogram sample", value: v });
        }
        let mut sorted = samples.to_vec();
        sorted.sort_by(f64::total_cmp);
        let n = sorted.len();
        let knots = if n == 1 {
            vec![(sorted[0], 0.0), (sorted[0], 1.0)]
        } else {
            sorted.iter().enumerate().map(|(k, &x)| (x, k as f64 / (n - 1) as f64)).collect()
        };
        Ok(Self { knots, spec })
    }

    /// Lowest height with non-zero density.
    pub fn min(&self) -> f64 {
        self.quantile(0.0)
    }

    /// Highest height with non-zero density.
    pub fn max(&self) -> f64 {
        self.quantile(1.0)
    }

    /// The specification this histogram was built from.
    pub fn spec(&self) -> &HistogramSpec {
        &self.spec
    }

    /// The height below which a fraction `u` of the terrain lies (`u` clamped to [0, 1]).
    pub fn quantile(&self, u: f64) -> f64 {
        let u = u.clamp(0.0, 1.0);
        // First knot whose F reaches u; interpolate inside the segment leading to it.
        let k = self.knots.partition_point(|&(_, f)| f < u);
        if k == 0 {
            // Skip leading zero-weight bins: the lowest height with density.
            let first = self.knots.iter().rposition(|&(_, f)| f <= 0.0).unwrap_or(0);
            return self.knots[first].0;
        }
        let (x0, f0) = self.knots[k - 1];
        let (x1, f1) = self.knots[k.min(self.knots.len() - 1)];
        if f1 <= f0 { x1 } else { x0 + (u - f0) / (f1 - f0) * (x1 - x0) }
    }

    /// Fraction of the terrain below height `h`.
    pub fn cdf(&self, h: f64) -> f64 {
        let k = self.knots.partition_point(|&(x, _)| x <= h);
        if k == 0 {
            return 0.0;
        }
        if k == self.knots.len() {
            return 1.0;
        }
        let (x0, f0) = self.knots[k - 1];
        let (x1, f1) = self.knots[k];
        if x1 <= x0 { f1 } else { f0 + (h - x0) / (x1 - x0) * (f1 - f0) }
    }

    /// Kolmogorov–Smirnov distance between this distribution and the empirical distribution of
    /// `heights`: the largest gap between the two cumulative distributions, in [0, 1].
    pub fn ks_distance(&self, heights: &[f64]) -> f64 {
        let mut sorted: Vec<f64> = heights.iter().copied().filter(|h| h.is_finite()).collect();
        if sorted.is_empty() {
            return 1.0;
        }
        sorted.sort_by(f64::total_cmp);
        let n = sorted.len() as f64;
        sorted
            .iter()
            .enumerate()
            .map(|(k, &h)| {
                let f = self.cdf(h);
                (f - k as f64 / n).abs().max((f - (k + 1) as f64 / n).abs())
            })
            .fold(0.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_quantiles_and_cdf_invert_each_other() {
        let h = Histogram::from_bins(vec![0.0, 100.0, 200.0, 1000.0], vec![2.0, 0.0, 2.0]).unwrap();
        assert_eq!(h.min(), 0.0);
        assert_eq!(h.max(), 1000.0);
        assert_eq!(h.quantile(0.25), 50.0);
        // The empty middle bin is skipped: just above half, heights jump to 200.
        assert!((h.quantile(0.500_000_1) - 200.0).abs() < 1e-3);
        assert_eq!(h.quantile(0.75), 600.0);
        for u in [0.1, 0.3, 0.6, 0.9] {
            assert!((h.cdf(h.quantile(u)) - u).abs() < 1e-12);
        }
        assert_eq!(h.cdf(-5.0), 0.0);
        assert_eq!(h.cdf(5000.0), 1.0);
    }

    #[test]
    fn samples_interpolate_and_ks_detects_mismatch() {
        let h = Histogram::from_samples(vec![3.0, 1.0, 2.0]).unwrap();
        assert_eq!((h.min(), h.max(), h.quantile(0.25)), (1.0, 3.0, 1.5));
        let matched: Vec<f64> = (0..1000).map(|i| h.quantile((f64::from(i) + 0.5) / 1000.0)).collect();
        assert!(h.ks_distance(&matched) < 0.002);
        assert!(h.ks_distance(&[1.0; 10]) > 0.9);
        let single = Histogram::from_samples(vec![7.0]).unwrap();
        assert_eq!(single.quantile(0.3), 7.0);
    }

    #[test]
    fn invalid_histograms_are_typed_errors() {
        assert_eq!(Histogram::from_bins(vec![0.0], vec![]).unwrap_err(), ContoursError::EmptyHistogram);
        assert_eq!(Histogram::from_bins(vec![0.0, 1.0], vec![0.0]).unwrap_err(), ContoursError::EmptyHistogram);
        assert!(matches!(Histogram::from_bins(vec![0.0, 0.0], vec![1.0]), Err(ContoursError::InvalidHistogram { .. })));
        assert!(matches!(
            Histogram::from_bins(vec![0.0, 1.0, 2.0], vec![1.0]),
            Err(ContoursError::InvalidHistogram { .. })
        ));
        assert!(matches!(
            Histogram::from_bins(vec![0.0, 1.0], vec![-1.0]),
            Err(ContoursError::InvalidHistogram { .. })
        ));
        assert_eq!(Histogram::from_samples(vec![]).unwrap_err(), ContoursError::EmptyHistogram);
        assert!(matches!(Histogram::from_samples(vec![f64::NAN]), Err(ContoursError::NonFinite { .. })));
        assert!(matches!(Histogram::uniform(5.0, 5.0), Err(ContoursError::InvalidHistogram { .. })));
    }
}
