//! Behaviour of `Heightfield`: construction contract, sampling, gradients, resampling, statistics, serde.

use glam::DVec2;
use proptest::prelude::*;
use relief_heightfield::{Extent, GridSpec, Heightfield, HeightfieldError, Units};

fn grid(nx: usize, ny: usize, size: f64) -> GridSpec {
    GridSpec::from_extent(nx, ny, Extent::new(DVec2::ZERO, DVec2::splat(size))).unwrap()
}

#[track_caller]
fn check_close(actual: f64, expected: f64, tol: f64) {
    assert!((actual - expected).abs() <= tol, "got {actual}, expected {expected} ± {tol}");
}

#[test]
fn construction_rejects_infinity_and_wrong_length() {
    let g = grid(3, 3, 2.0);
    let err = Heightfield::from_samples(g, vec![0.0; 8]).unwrap_err();
    assert!(matches!(err, HeightfieldError::SampleCountMismatch { expected: 9, found: 8, .. }));
    let mut s = vec![0.0; 9];
    s[5] = f32::INFINITY;
    let err = Heightfield::from_samples(g, s).unwrap_err();
    assert_eq!(err, HeightfieldError::NonFiniteSample { i: 2, j: 1, value: f32::INFINITY });
    assert!(err.to_string().contains("sample (2, 1)"));
    assert!(Heightfield::filled(g, f32::NEG_INFINITY).is_err());
    let mut h = Heightfield::zeros(g);
    assert!(h.set(0, 0, f32::INFINITY).is_err());
    h.samples_mut()[0] = f32::INFINITY;
    assert!(h.validate().is_err());
}

#[test]
fn no_data_is_nan_and_excluded() {
    let g = grid(3, 2, 2.0);
    let h = Heightfield::from_samples(g, vec![1.0, f32::NAN, 3.0, 4.0, 5.0, -f32::NAN]).unwrap();
    assert_eq!(h.no_data_count(), 2);
    assert!(h.is_no_data(1, 0) && h.is_no_data(2, 1));
    assert_eq!(h.get(1, 0), None);
    assert_eq!(h.get(0, 1), Some(4.0));
    assert_eq!(h.get(3, 0), None);
    assert_eq!(h.no_data_mask(), vec![false, true, false, false, false, true]);
    assert_eq!(h.min_max(), Some((1.0, 5.0)));
    let s = h.statistics().unwrap();
    assert_eq!((s.count, s.no_data), (4, 2));
    check_close(s.mean, 13.0 / 4.0, 1e-12);
    // NaN payloads are canonical, so a field with holes equals its clone bitwise.
    assert_eq!(h, h.clone());
    let all_missing = Heightfield::filled(g, f32::NAN).unwrap();
    assert_eq!(all_missing.min_max(), None);
    assert!(all_missing.statistics().is_none());
    let mut filled = h.clone();
    filled.fill_no_data(-1.0).unwrap();
    assert_eq!(filled.no_data_count(), 0);
    assert_eq!(filled.value(1, 0), -1.0);
}

#[test]
fn bilinear_skips_zero_weight_holes_but_not_weighted_ones() {
    let g = grid(3, 3, 2.0);
    let mut h = Heightfield::from_fn_indexed(g, |i, j| (i + 10 * j) as f32).unwrap();
    h.set(2, 2, f32::NAN).unwrap();
    // On the node (1, 1): the hole at (2, 2) has zero weight.
    assert_eq!(h.sample_bilinear(DVec2::new(1.0, 1.0)), Some(11.0));
    // Inside the cell touching the hole: undefined.
    assert_eq!(h.sample_bilinear(DVec2::new(1.5, 1.5)), None);
    // On the edge between (1, 2) and (2, 1)... the hole's weight is zero along j = 1.
    assert_eq!(h.sample_bilinear(DVec2::new(1.5, 1.0)), Some(11.5));
    assert_eq!(h.sample_bilinear(DVec2::new(-0.1, 1.0)), None);
    assert_eq!(h.sample_bilinear_clamped(DVec2::new(-5.0, 1.0)), Some(10.0));
    assert_eq!(h.sample_bilinear(DVec2::new(f64::NAN, 1.0)), None);
    assert_eq!(h.sample_bilinear_clamped(DVec2::new(f64::NAN, 1.0)), None);
}

#[test]
fn gradient_is_one_sided_at_edges_and_holes() {
    let g = grid(4, 4, 3.0);
    let mut h = Heightfield::from_fn(g, |p| (p.x * p.x) as f32).unwrap();
    // Central difference of x² at x = 1: ((2² − 0²) / 2) = 2.
    check_close(h.gradient(1, 1).unwrap().x, 2.0, 1e-12);
    // One-sided at the west edge: (1 − 0) / 1.
    check_close(h.gradient(0, 1).unwrap().x, 1.0, 1e-12);
    h.set(2, 1, f32::NAN).unwrap();
    // Right neighbour missing: backward difference (1 − 0) / 1.
    check_close(h.gradient(1, 1).unwrap().x, 1.0, 1e-12);
    assert!(h.gradient(2, 1).is_none());
    let lone = Heightfield::filled(GridSpec::new(1, 1, DVec2::ZERO, DVec2::ONE).unwrap(), 3.0).unwrap();
    assert_eq!(lone.gradient(0, 0), Some(DVec2::ZERO));
    assert_eq!(lone.sample_bilinear(DVec2::ZERO), Some(3.0));
}

#[test]
fn slope_and_normal_of_a_45_degree_plane() {
    let h = Heightfield::from_fn(grid(5, 5, 4.0), |p| p.y as f32).unwrap();
    check_close(h.slope(2, 2).unwrap(), std::f64::consts::FRAC_PI_4, 1e-12);
    let n = h.normal(2, 2).unwrap();
    check_close(n.y, -std::f64::consts::FRAC_1_SQRT_2, 1e-12);
    check_close(n.z, std::f64::consts::FRAC_1_SQRT_2, 1e-12);
    let s = h.slope_map();
    assert!(s.samples().iter().all(|&v| (f64::from(v) - std::f64::consts::FRAC_PI_4).abs() < 1e-6));
}

#[test]
fn geographic_gradient_uses_metres() {
    // 1 m of rise per 0.001° of latitude at the equator: ∂h/∂y = 1 / 110.574 m.
    let g = GridSpec::geographic(3, 3, DVec2::new(10.0, -0.001), DVec2::splat(0.001)).unwrap();
    assert_eq!(g.units(), Units::Degrees);
    let h = Heightfield::from_fn_indexed(g, |_, j| j as f32).unwrap();
    let grad = h.gradient(1, 1).unwrap();
    check_close(grad.y, 1.0 / 110.574_27, 1e-7);
    check_close(grad.x, 0.0, 0.0);
}

#[test]
fn zip_requires_identical_grids() {
    let a = Heightfield::filled(grid(3, 3, 2.0), 1.0).unwrap();
    let b = Heightfield::filled(grid(3, 3, 4.0), 2.0).unwrap();
    assert!(matches!(a.zip_with(&b, |x, y| x + y), Err(HeightfieldError::GridMismatch { .. })));
    let mut c = Heightfield::filled(grid(3, 3, 2.0), 2.0).unwrap();
    c.set(1, 1, f32::NAN).unwrap();
    let sum = a.zip_with(&c, |x, y| x + y).unwrap();
    assert_eq!(sum.get(0, 0), Some(3.0));
    assert!(sum.is_no_data(1, 1));
    assert!(a.map(|_| f32::INFINITY).is_err());
    assert_eq!(a.map(|x| 2.0 * x).unwrap().get(2, 2), Some(2.0));
}

#[test]
fn serde_round_trip_keeps_no_data_and_rejects_bad_runs() {
    let mut h = Heightfield::from_fn_indexed(grid(4, 3, 3.0), |i, j| (i * j) as f32 + 0.25).unwrap();
    h.set(1, 0, f32::NAN).unwrap();
    h.set(2, 0, f32::NAN).unwrap();
    h.set(3, 2, f32::NAN).unwrap();
    let json = serde_json::to_string(&h).unwrap();
    assert!(json.contains("\"no_data\":[[1,2],[11,1]]"), "{json}");
    let back: Heightfield = serde_json::from_str(&json).unwrap();
    assert_eq!(back, h);
    let bad = json.replace("[11,1]", "[11,5]");
    let err = serde_json::from_str::<Heightfield>(&bad).unwrap_err().to_string();
    assert!(err.contains("no-data run"), "{err}");
    let short = json.replace("0.25,", "");
    assert!(serde_json::from_str::<Heightfield>(&short).unwrap_err().to_string().contains("samples"));
}

proptest! {
    #[test]
    fn bilinear_reproduces_bilinear_functions(
        a in -10.0f64..10.0, b in -10.0f64..10.0, c in -10.0f64..10.0, d in -1.0f64..1.0,
        px in 0.0f64..1.0, py in 0.0f64..1.0, nx in 2usize..20, ny in 2usize..20,
    ) {
        let g = GridSpec::from_extent(nx, ny, Extent::new(DVec2::new(-5.0, 3.0), DVec2::new(7.0, 11.0))).unwrap();
        let f = |p: DVec2| a + b * p.x + c * p.y + d * p.x * p.y;
        // Exact in f64 on every node; the f32 storage bounds the error.
        let h = Heightfield::from_fn(g, |p| f(p) as f32).unwrap();
        let p = DVec2::new(-5.0 + 12.0 * px, 3.0 + 8.0 * py);
        let got = f64::from(h.sample_bilinear(p).unwrap());
        prop_assert!((got - f(p)).abs() < 1e-4 * (1.0 + f(p).abs()), "{got} vs {}", f(p));
    }

    #[test]
    fn plane_gradient_and_resampling_are_exact(
        a in -100.0f64..100.0, b in -3.0f64..3.0, c in -3.0f64..3.0,
        nx in 2usize..30, ny in 2usize..30, mx in 2usize..40, my in 2usize..40,
    ) {
        let g = GridSpec::from_extent(nx, ny, Extent::new(DVec2::ZERO, DVec2::new(50.0, 20.0))).unwrap();
        let h = Heightfield::from_fn(g, |p| (a + b * p.x + c * p.y) as f32).unwrap();
        let (i, j) = (nx / 2, ny / 2);
        let grad = h.gradient(i, j).unwrap();
        prop_assert!((grad.x - b).abs() < 1e-3 && (grad.y - c).abs() < 1e-3, "{grad} vs ({b}, {c})");
        let r = h.resample(mx, my).unwrap();
        // origin + (n − 1)·cell reproduces the far corner to within rounding, not bit for bit.
        prop_assert!((r.extent().max - h.extent().max).abs().max_element() < 1e-12 * 50.0);
        for (k, &v) in r.samples().iter().enumerate() {
            let (ri, rj) = r.grid().coords(k);
            let p = r.grid().position(ri, rj);
            let exact = a + b * p.x + c * p.y;
            prop_assert!((f64::from(v) - exact).abs() < 1e-3 * (1.0 + exact.abs()));
        }
    }

    #[test]
    fn statistics_agree_with_a_direct_computation(values in proptest::collection::vec(
        prop_oneof![4 => -1e4f32..1e4, 1 => Just(f32::NAN)], 1..200)
    ) {
        let n = values.len();
        let g = GridSpec::new(n, 1, DVec2::ZERO, DVec2::ONE).unwrap();
        let h = Heightfield::from_samples(g, values.clone()).unwrap();
        let valid: Vec<f64> = values.iter().filter(|v| !v.is_nan()).map(|&v| f64::from(v)).collect();
        match h.statistics() {
            None => prop_assert!(valid.is_empty()),
            Some(s) => {
                prop_assert_eq!(s.count, valid.len());
                prop_assert_eq!(s.no_data, n - valid.len());
                let mean = valid.iter().sum::<f64>() / valid.len() as f64;
                prop_assert!((s.mean - mean).abs() < 1e-6 * (1.0 + mean.abs()));
                prop_assert_eq!(f64::from(s.min), valid.iter().copied().fold(f64::INFINITY, f64::min));
                prop_assert_eq!(f64::from(s.max), valid.iter().copied().fold(f64::NEG_INFINITY, f64::max));
            }
        }
        let json = serde_json::to_string(&h).unwrap();
        prop_assert_eq!(serde_json::from_str::<Heightfield>(&json).unwrap(), h);
    }
}
