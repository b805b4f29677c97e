use std::sync::Arc;

use crate::WarpError;

/// A displacement profile δ₀ on [0, 1] (Appendix A/B): zero at both ends, positive at ½. A
/// [`crate::PathWarp`] scales it so the centre of each disc moves by exactly one segment at full
/// strength; its steepest descent `λ = min δ₀′` bounds the segment length ε ≤ 2r·δ₀(½)/(μ·(−λ)).
#[derive(Clone)]
pub struct Profile {
    kind: Kind,
    /// δ₀(½).
    center: f64,
    /// min δ₀′ over [0, 1] (negative).
    min_slope: f64,
}

#[derive(Clone)]
enum Kind {
    /// `(4x(1−x))^k`, the paper's family.
    Power(u32),
    /// A user function.
    Custom(Arc<dyn Fn(f64) -> f64 + Send + Sync>),
}

impl std::fmt::Debug for Profile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.kind {
            Kind::Power(k) => write!(f, "Profile::power({k})"),
            Kind::Custom(_) => write!(f, "Profile::custom(min δ₀′ = {})", self.min_slope),
        }
    }
}

/// Samples used to find a custom profile's steepest descent numerically.
const SLOPE_SAMPLES: usize = 20_000;

impl Profile {
    /// The paper's profile `δ₀(x) = (4x(1−x))^k`, `k ≥ 1`; its bound is the closed form
    /// `ε ≤ 2r·√(2k−1)·(4k−2)^(k−1) / (4^k·k·(k−1)^(k−1))` (0.5r, 0.64r, 0.58r for k = 1, 2, 3).
    ///
    /// # Errors
    /// [`WarpError::InvalidProfile`] for `k = 0`.
    pub fn power(k: u32) -> Result<Self, WarpError> {
        if k == 0 {
            return Err(WarpError::InvalidProfile { reason: "exponent k must be at least 1".into() });
        }
        // The steepest descent of (4x(1−x))^k, from the closed-form bound with δ₀(½) = 1:
        // ε_max = 2r / (−λ)  ⇒  −λ = 2 / (ε_max / r).
        let kf = f64::from(k);
        let ratio = 2.0 * (2.0 * kf - 1.0).sqrt() * (4.0 * kf - 2.0).powf(kf - 1.0)
            / (4f64.powf(kf) * kf * if k == 1 { 1.0 } else { (kf - 1.0).powf(kf - 1.0) });
        Ok(Self { kind: Kind::Power(k), center: 1.0, min_slope: -2.0 / ratio })
    }

    /// Any continuous `δ₀` with `δ₀(0) = δ₀(1) = 0` and `δ₀(½) > 0` (Appendix B); its steepest
    /// descent is found numerically over 20 000 samples.
    ///
    /// # Errors
    /// [`WarpError::InvalidProfile`] when the end values are not zero (within 1e-9), the centre
    /// value is not positive, or the function is not finite on [0, 1].
    pub fn custom(f: impl Fn(f64) -> f64 + Send + Sync + 'static) -> Result<Self, WarpError> {
        let bad = |reason: String| Err(WarpError::InvalidProfile { reason });
        let (f0, f1, c) = (f(0.0), f(1.0), f(0.5));
        if !(f0.abs() <= 1e-9 && f1.abs() <= 1e-9) {
            return bad(format!("δ₀(0) = {f0} and δ₀(1) = {f1} must both be 0"));
        }
        if !(c.is_finite() && c > 0.0) {
            return bad(format!("δ₀(½) = {c} must be positive"));
        }
        let h = 1.0 / SLOPE_SAMPLES as f64;
        let mut min_slope = f64::INFINITY;
        let mut prev = f0;
        for i in 1..=SLOPE_SAMPLES {
            let v = f(i as f64 * h);
            if !v.is_finite() {
                return bad(format!("δ₀({}) is not finite", i as f64 * h));
            }
            min_slope = min_slope.min((v - prev) / h);
            prev = v;
        }
        // A finite difference underestimates the steepest slope between samples: keep a margin.
        Ok(Self { kind: Kind::Custom(Arc::new(f)), center: c, min_slope: 1.01 * min_slope.min(-f64::EPSILON) })
    }

    /// The exponent k of a [`Profile::power`] profile; `None` for a custom one.
    pub fn exponent(&self) -> Option<u32> {
        match self.kind {
            Kind::Power(k) => Some(k),
            Kind::Custom(_) => None,
        }
    }

    /// `δ₀(x)`.
    #[inline]
    pub fn value(&self, x: f64) -> f64 {
        match &self.kind {
            Kind::Power(k) => (4.0 * x * (1.0 - x)).max(0.0).powi(*k as i32),
            Kind::Custom(f) => f(x),
        }
    }

    /// `δ₀′(x)` (analytic for the power family, central difference otherwise).
    #[inline]
    pub fn slope(&self, x: f64) -> f64 {
        match &self.kind {
            Kind::Power(k) => {
                let base = 4.0 * x * (1.0 - x);
                if *k == 1 {
                    4.0 - 8.0 * x
                } else {
                    f64::from(*k) * base.max(0.0).powi(*k as i32 - 1) * (4.0 - 8.0 * x)
                }
            }
            Kind::Custom(f) => {
                let h = 1e-6;
                (f((x + h).min(1.0)) - f((x - h).max(0.0))) / ((x + h).min(1.0) - (x - h).max(0.0))
            }
        }
    }

    /// `δ₀(½)`.
    pub fn center(&self) -> f64 {
        self.center
    }

    /// The steepest descent `min δ₀′` (negative).
    pub fn min_slope(&self) -> f64 {
        self.min_slope
    }

    /// The longest segment `ε` for which the scaled profile keeps every disc warp bijective at
    /// strength `mu` and radius `radius`: `2r·δ₀(½) / (μ·(−min δ₀′))`.
    pub fn max_segment(&self, radius: f64, mu: f64) -> f64 {
        if mu <= 0.0 { f64::INFINITY } else { 2.0 * radius * self.center / (mu * -self.min_slope) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_form_bounds_match_the_paper_and_a_numeric_search() {
        for (k, expected) in [(1, 0.5), (2, 0.6495), (3, 0.5823)] {
            let p = Profile::power(k).unwrap();
            assert!((p.max_segment(1.0, 1.0) - expected).abs() < 1e-4, "k = {k}: {}", p.max_segment(1.0, 1.0));
            // The same bound found by searching δ₀′ numerically.
            let numeric = Profile::custom(move |x| (4.0 * x * (1.0 - x)).powi(k as i32)).unwrap();
            let rel = numeric.max_segment(1.0, 1.0) / p.max_segment(1.0, 1.0);
            assert!((0.98..=1.0).contains(&rel), "k = {k}: numeric/closed = {rel}");
        }
        assert_eq!(
            Profile::power(2).unwrap().max_segment(3.0, 0.5),
            2.0 * Profile::power(2).unwrap().max_segment(3.0, 1.0)
        );
    }

    #[test]
    fn analytic_slope_matches_finite_differences() {
        for k in 1..=4 {
            let p = Profile::power(k).unwrap();
            for i in 1..100 {
                let x = f64::from(i) / 100.0;
                let fd = (p.value(x + 1e-7) - p.value(x - 1e-7)) / 2e-7;
                assert!((p.slope(x) - fd).abs() < 1e-5, "k = {k}, x = {x}");
            }
        }
    }

    #[test]
    fn invalid_profiles_are_rejected() {
        assert!(Profile::power(0).is_err());
        assert!(Profile::custom(|x| x).is_err(), "δ₀(1) ≠ 0");
        assert!(Profile::custom(|x| -x * (1.0 - x)).is_err(), "negative centre");
        assert!(Profile::custom(|x| if x > 0.3 && x < 0.31 { f64::NAN } else { x * (1.0 - x) }).is_err());
        let sine = Profile::custom(|x| (std::f64::consts::PI * x).sin()).unwrap();
        assert!((sine.min_slope() + std::f64::consts::PI).abs() < 0.05);
    }
}
