use crate::ContoursError;

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
    let n = (last - first) as usize + 1;
    if n > max_levels {
        return Err(ContoursError::InvalidLevelRequest {
            reason: format!("interval {interval} gives {n} levels over [{min}, {max}], more than {max_levels}"),
        });
    }
    Ok((0..n).map(|k| base + (first + k as f64) * interval).collect())
}

/// Checks that `levels` are finite and strictly increasing.
pub(crate) fn check_levels(levels: &[f64]) -> Result<(), ContoursError> {
    match (0..levels.len()).find(|&k| !levels[k].is_finite() || (k > 0 && levels[k] <= levels[k - 1])) {
        Some(index) => Err(ContoursError::InvalidLevels { index }),
        None => Ok(()),
    }
}
