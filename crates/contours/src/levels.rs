use serde::{Deserialize, Serialize};

use crate::ContoursError;

/// Most contour levels one request may produce.
pub const MAX_LEVELS: usize = 10_000;

/// Which contour levels to draw over a range of elevations: in JSON `{ "count": n }`,
/// `{ "interval": m }` or `{ "heights": [h, …] }`. Deserialization checks the request itself
/// (1 ≤ n ≤ [`MAX_LEVELS`], a finite positive interval, finite heights); [`Levels::resolve`]
/// turns it into heights once the range is known.
///
/// ```
/// use relief_contours::Levels;
///
/// assert_eq!(Levels::Count(3).resolve(0.0, 400.0)?, vec![100.0, 200.0, 300.0]);
/// assert_eq!(Levels::Interval(150.0).resolve(10.0, 400.0)?, vec![150.0, 300.0]);
/// assert!(serde_json::from_str::<Levels>(r#"{ "count": 0 }"#).is_err());
/// # Ok::<(), relief_contours::ContoursError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", try_from = "LevelsRepr")]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub enum Levels {
    /// This many levels evenly spaced strictly inside the range ([`evenly_spaced_levels`]).
    Count(usize),
    /// The multiples of this interval within the range, like `gdal_contour -i` ([`interval_levels`]).
    Interval(f64),
    /// These heights, whatever the range.
    Heights(Vec<f64>),
}

/// The unchecked JSON form of [`Levels`].
#[derive(Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema), schemars(rename = "Levels"))]
enum LevelsRepr {
    /// This many levels evenly spaced strictly inside the elevation range (1 to 10 000).
    Count(usize),
    /// The multiples of this interval (finite, > 0) within the elevation range.
    Interval(f64),
    /// These heights (finite), whatever the range.
    Heights(Vec<f64>),
}

impl TryFrom<LevelsRepr> for Levels {
    type Error = ContoursError;
    fn try_from(r: LevelsRepr) -> Result<Self, ContoursError> {
        let levels = match r {
            LevelsRepr::Count(n) => Levels::Count(n),
            LevelsRepr::Interval(m) => Levels::Interval(m),
            LevelsRepr::Heights(h) => Levels::Heights(h),
        };
        levels.validate()?;
        Ok(levels)
    }
}

impl Levels {
    /// Checks the request on its own: a count in 1..=[`MAX_LEVELS`], a finite interval above 0,
    /// at most [`MAX_LEVELS`] finite heights.
    ///
    /// # Errors
    /// [`ContoursError::InvalidLevelRequest`] naming the problem.
    pub fn validate(&self) -> Result<(), ContoursError> {
        let bad = |reason: String| Err(ContoursError::InvalidLevelRequest { reason });
        match self {
            Self::Count(n) if !(1..=MAX_LEVELS).contains(n) => bad(format!("{n} levels: give 1 to {MAX_LEVELS}")),
            Self::Interval(m) if !(m.is_finite() && *m > 0.0) => bad(format!("interval {m} must be finite and > 0")),
            Self::Heights(h) if h.len() > MAX_LEVELS => bad(format!("{} levels, more than {MAX_LEVELS}", h.len())),
            Self::Heights(h) => match h.iter().position(|v| !v.is_finite()) {
                Some(k) => bad(format!("heights[{k}] = {} is not finite", h[k])),
                None => Ok(()),
            },
            _ => Ok(()),
        }
    }

    /// The heights this request gives over elevations `[min, max]`, in the order requested
    /// (sorted for a count or an interval). A count over a flat range (`min == max`) gives no
    /// level: there is nothing to contour.
    ///
    /// # Errors
    /// [`ContoursError::InvalidLevelRequest`] for an invalid request ([`Levels::validate`]), a
    /// non-finite or inverted range, or an interval giving more than [`MAX_LEVELS`] levels.
    pub fn resolve(&self, min: f64, max: f64) -> Result<Vec<f64>, ContoursError> {
        self.validate()?;
        match self {
            Self::Count(_) if min == max && min.is_finite() => Ok(Vec::new()),
            Self::Count(n) => evenly_spaced_levels(min, max, *n),
            Self::Interval(m) => interval_levels(min, max, *m, 0.0, MAX_LEVELS),
            Self::Heights(h) => Ok(h.clone()),
        }
    }
}

/// `count` levels evenly spaced strictly inside `(min, max)`: `min + (max − min)·k/(count + 1)`.
///
/// # Errors
/// [`ContoursError::InvalidLevelRequest`] unless `min < max` (finite) and `count ≥ 1`.
pub fn evenly_spaced_levels(min: f64, max: f64, count: usize) -> Result<Vec<f64>, ContoursError> {
    if !(min.is_finite() && max.is_finite() && min < max) || count == 0 {
        return Err(ContoursError::InvalidLevelRequest { reason: format!("{count} levels between {min} and {max}") });
    }
    Ok((1..=count).map(|k| min + (max - min) * k as f64 / (count + 1) as f64).collect())
}

/// The multiples of `interval` (offset by `base`) within `[min, max]`, like `gdal_contour -i`.
///
/// # Errors
/// [`ContoursError::InvalidLevelRequest`] for a non-positive interval, non-finite bounds, or more
/// than `max_levels` levels.
pub fn interval_levels(
    min: f64,
    max: f64,
    interval: f64,
    base: f64,
    max_levels: usize,
) -> Result<Vec<f64>, ContoursError> {
    if !(interval.is_finite() && interval > 0.0 && min.is_finite() && max.is_finite() && base.is_finite()) {
        return Err(ContoursError::InvalidLevelRequest { reason: format!("interval {interval} over [{min}, {max}]") });
    }
    let first = ((min - base) / interval).ceil();
    let last = ((max - base) / interval).floor();
    if last < first {
        return Ok(Vec::new());
    }
    // Counted in f64: a tiny interval's count overflows usize (and wrapped to none), a huge
    // ratio's is infinite or NaN.
    let count = last - first + 1.0;
    if count.is_nan() || count > max_levels as f64 {
        return Err(ContoursError::InvalidLevelRequest {
            reason: format!("interval {interval} gives {count:e} levels over [{min}, {max}], more than {max_levels}"),
        });
    }
    Ok((0..count as usize).map(|k| base + (first + k as f64) * interval).collect())
}

/// Checks that `levels` are finite and strictly increasing.
pub(crate) fn check_levels(levels: &[f64]) -> Result<(), ContoursError> {
    match (0..levels.len()).find(|&k| !levels[k].is_finite() || (k > 0 && levels[k] <= levels[k - 1])) {
        Some(index) => Err(ContoursError::InvalidLevels { index }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[track_caller]
    fn refused(levels: &Levels, says: &str) {
        let e = levels.validate().unwrap_err().to_string();
        assert!(e.contains(says), "{levels:?}: {e}");
        assert_eq!(levels.resolve(0.0, 100.0).unwrap_err().to_string(), e, "resolve checks first");
    }

    #[test]
    fn a_request_is_checked_on_its_own_then_resolved_over_a_range() {
        for n in [1, 7, MAX_LEVELS] {
            assert_eq!(Levels::Count(n).validate(), Ok(()));
        }
        refused(&Levels::Count(0), "0 levels");
        refused(&Levels::Count(MAX_LEVELS + 1), "10001 levels");
        assert_eq!(Levels::Interval(0.5).validate(), Ok(()));
        for m in [0.0, -2.0, f64::NAN, f64::INFINITY] {
            refused(&Levels::Interval(m), "must be finite and > 0");
        }
        assert_eq!(Levels::Heights(vec![3.0; MAX_LEVELS]).validate(), Ok(()));
        refused(&Levels::Heights(vec![3.0; MAX_LEVELS + 1]), "more than 10000");
        refused(&Levels::Heights(vec![1.0, f64::NAN]), "heights[1]");
        // Resolved: a count inside the range, an interval's multiples, heights as given.
        assert_eq!(Levels::Count(3).resolve(0.0, 400.0), Ok(vec![100.0, 200.0, 300.0]));
        assert_eq!(Levels::Count(3).resolve(5.0, 5.0), Ok(Vec::new()), "a flat range has nothing to contour");
        assert!(Levels::Count(3).resolve(5.0, 1.0).is_err());
        assert_eq!(Levels::Interval(150.0).resolve(10.0, 400.0), Ok(vec![150.0, 300.0]));
        assert!(Levels::Interval(1e-3).resolve(0.0, 1e6).is_err(), "too many levels");
        // Counts past usize (they used to wrap to no level at all) and past f64.
        assert!(Levels::Interval(1e-20).resolve(0.0, 400.0).is_err(), "1e22 levels");
        assert!(Levels::Interval(1e-20).resolve(-1e300, 1e300).is_err(), "an infinite count");
        assert_eq!(interval_levels(0.0, 10.0, 1.0, 0.0, 11).map(|l| l.len()), Ok(11), "at the cap");
        assert!(interval_levels(0.0, 10.0, 1.0, 0.0, 10).is_err(), "one past it");
        assert_eq!(Levels::Heights(vec![9.0, 2.0]).resolve(0.0, 1.0), Ok(vec![9.0, 2.0]));
        // JSON: the same checks as the request is read.
        assert!(serde_json::from_str::<Levels>(r#"{ "interval": -5 }"#).is_err());
        assert_eq!(
            serde_json::from_str::<Levels>(r#"{ "heights": [1, 2] }"#).unwrap(),
            Levels::Heights(vec![1.0, 2.0])
        );
    }
}
