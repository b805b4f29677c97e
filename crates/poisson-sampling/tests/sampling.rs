//! Properties of the Poisson-disc sampler: spacing, containment, coverage (maximality), determinism.

mod common;

use common::{PointIndex, closest_pair, polygon_with_holes, probe_points};
use glam::DVec2;
use proptest::prelude::*;
use relief_poisson_sampling::{
    DENSITY, Domain, ExtendedDomain, FnDomain, PoissonDisc, Polygon, PolygonSet, Rect, SamplingError, radius_for_count,
};

/// Asserts the three guarantees of a fixed-radius set over `domain`.
#[track_caller]
fn check_blue_noise(domain: &impl Domain, points: &[DVec2], r: f64, is_inside: impl Fn(DVec2) -> bool) {
    if let Some((d, a, b)) = closest_pair(points, r) {
        assert!(d >= r, "points {a} and {b} are {d} apart, closer than r = {r}");
    }
    for &p in points {
        assert!(domain.contains(p) && is_inside(p), "sample {p} outside its domain");
    }
    // Maximality: every probe whose 2r-disc fits in the domain has a sample within 1.5r (the
    // documented bound), hence no empty disc of radius 2r lies inside the domain.
    let index = PointIndex::new(points, r);
    for q in probe_points(domain, r / 3.0, &is_inside) {
        let disc_inside = (0..16).all(|k| {
            let t = std::f64::consts::TAU * f64::from(k) / 16.0;
            is_inside(q + 2.0 * r * DVec2::new(t.cos(), t.sin()))
        });
        if disc_inside {
            assert!(index.any_within(q, 1.5 * r), "no sample within 1.5r of {q}: the set is not maximal");
        }
    }
}

#[test]
fn rectangle_sample_is_blue_noise_and_matches_the_density() {
    let rect = Rect::new(DVec2::new(-20.0, 5.0), DVec2::new(80.0, 65.0));
    let r = 1.0;
    let points = PoissonDisc::new(r).unwrap().with_seed(3).sample(&rect).unwrap();
    check_blue_noise(&rect, &points, r, |p| rect.contains(p));
    let expected = DENSITY * rect.area() / (r * r);
    let ratio = points.len() as f64 / expected;
    assert!((0.95..1.05).contains(&ratio), "{} points, expected about {expected}", points.len());
}

#[test]
fn radius_for_count_hits_the_target_count() {
    let rect = Rect::new(DVec2::ZERO, DVec2::new(300.0, 200.0));
    for target in [1_000, 10_000, 50_000] {
        let r = radius_for_count(rect.area(), target).unwrap();
        let n = PoissonDisc::new(r).unwrap().with_seed(11).sample(&rect).unwrap().len();
        let ratio = n as f64 / target as f64;
        // The boundary strip is sampled slightly sparser than the interior: allow a few percent.
        assert!((0.93..1.05).contains(&ratio), "{n} points for a target of {target}");
    }
    assert!(matches!(radius_for_count(10.0, 0), Err(SamplingError::InvalidCount { .. })));
    assert!(matches!(radius_for_count(f64::NAN, 10), Err(SamplingError::InvalidCount { .. })));
}

#[test]
fn disconnected_domains_are_all_sampled() {
    let squares = PolygonSet::new(vec![
        Polygon::rectangle(Rect::new(DVec2::ZERO, DVec2::splat(5.0))).unwrap(),
        Polygon::rectangle(Rect::new(DVec2::splat(95.0), DVec2::splat(100.0))).unwrap(),
        Polygon::circle(DVec2::new(90.0, 10.0), 2.0, 32).unwrap(),
    ]);
    let r = 0.5;
    let points = PoissonDisc::new(r).unwrap().with_seed(5).sample(&squares).unwrap();
    for poly in squares.polygons() {
        let n = points.iter().filter(|&&p| poly.contains(p)).count();
        assert!(n as f64 > 0.6 * DENSITY * poly.area() / (r * r), "component with {n} samples");
    }
    check_blue_noise(&squares, &points, r, |p| squares.contains(p));
}

#[test]
fn a_domain_too_thin_to_hold_two_samples_still_gets_one() {
    let sliver = Rect::new(DVec2::ZERO, DVec2::new(10.0, 0.0));
    let points = PoissonDisc::new(1.0).unwrap().sample(&sliver).unwrap();
    assert!(points.len() >= 5, "{points:?}");
    assert!(points.iter().all(|p| p.y == 0.0));
}

#[test]
fn an_empty_predicate_domain_yields_no_points() {
    let nothing = FnDomain::new(Rect::new(DVec2::ZERO, DVec2::ONE), |_| false);
    assert!(PoissonDisc::new(0.1).unwrap().sample(&nothing).unwrap().is_empty());
}

#[test]
fn bad_parameters_are_typed_errors() {
    assert!(matches!(PoissonDisc::new(0.0), Err(SamplingError::InvalidRadius { .. })));
    assert!(matches!(PoissonDisc::new(f64::NAN), Err(SamplingError::InvalidRadius { .. })));
    assert!(matches!(PoissonDisc::new(f64::INFINITY), Err(SamplingError::InvalidRadius { .. })));
    assert!(matches!(PoissonDisc::new(1.0).unwrap().with_attempts(0), Err(SamplingError::InvalidAttempts { .. })));
    let nan_bounds = FnDomain::new(Rect::new(DVec2::ZERO, DVec2::new(f64::NAN, 1.0)), |_| true);
    assert!(matches!(PoissonDisc::new(1.0).unwrap().sample(&nan_bounds), Err(SamplingError::InvalidBounds { .. })));
    let set = PolygonSet::from(Polygon::circle(DVec2::ZERO, 1.0, 8).unwrap());
    let sampler = PoissonDisc::new(0.1).unwrap();
    assert!(matches!(sampler.sample_extended(&set, -1.0), Err(SamplingError::InvalidMargin { .. })));
    assert!(matches!(sampler.sample_extended(&PolygonSet::new(vec![]), 1.0), Err(SamplingError::InvalidBounds { .. })));
}

#[test]
fn point_budget_is_enforced_before_allocating() {
    // 10^12 cells would be needed: refused up front, no allocation.
    let huge = Rect::new(DVec2::ZERO, DVec2::splat(1e6));
    let err = PoissonDisc::new(1e-3).unwrap().sample(&huge).unwrap_err();
    assert!(matches!(err, SamplingError::TooManyPoints { .. }), "{err}");
    assert!(err.to_string().contains("with_max_points"));
    // A small explicit budget stops a run that would produce more points.
    let rect = Rect::new(DVec2::ZERO, DVec2::splat(100.0));
    let err = PoissonDisc::new(1.0).unwrap().with_max_points(100).sample(&rect).unwrap_err();
    assert!(matches!(err, SamplingError::TooManyPoints { limit: 100, .. }), "{err}");
}

#[test]
fn extended_domain_tags_and_bounds_every_point() {
    let island = Polygon::new(
        common::star(DVec2::ZERO, 40.0, &[0.3, 0.9, 0.1, 0.8, 0.5, 0.0, 0.7, 0.2, 1.0, 0.4]),
        vec![common::star(DVec2::ZERO, 8.0, &[0.5, 0.2, 0.9, 0.1, 0.6])],
    )
    .unwrap();
    let omega = PolygonSet::from(island.clone());
    let r = 0.8;
    let margin = 4.0 * r;
    let s = PoissonDisc::new(r).unwrap().with_seed(1).sample_extended(&omega, margin).unwrap();
    assert_eq!(s.points.len(), s.inside.len());
    for (&p, &inside) in s.points.iter().zip(&s.inside) {
        assert_eq!(inside, island.contains_brute_force(p), "tag of {p}");
        if !inside {
            let d = island.boundary_distance(p);
            assert!(d <= margin + 1e-9, "outside point {p} is {d} from Ω, beyond the margin {margin}");
        }
    }
    let outside = s.len() - s.inside_count();
    assert!(outside > 0 && s.inside_count() > 0);
    let ext = ExtendedDomain::new(&omega, margin).unwrap();
    check_blue_noise(&ext, &s.points, r, |p| island.contains_brute_force(p) || island.boundary_distance(p) <= margin);
    // The hole is not sampled except within the margin of its rim: it has radius ≥ 4, margin 3.2.
    assert!(!s.points.iter().any(|p| p.length() < 0.5));
}

#[test]
fn same_seed_same_points_different_seed_different_points() {
    let poly = Polygon::circle(DVec2::new(3.0, -2.0), 20.0, 64).unwrap();
    let sampler = PoissonDisc::new(0.7).unwrap();
    let a = sampler.with_seed(123).sample(&poly).unwrap();
    let b = sampler.with_seed(123).sample(&poly).unwrap();
    let c = sampler.with_seed(124).sample(&poly).unwrap();
    assert_eq!(a, b);
    assert_ne!(a, c);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn polygon_samples_are_spaced_contained_and_maximal(poly in polygon_with_holes(), seed in any::<u64>(), r in 0.8f64..3.0) {
        let points = PoissonDisc::new(r).unwrap().with_seed(seed).sample(&poly).unwrap();
        check_blue_noise(&poly, &points, r, |p| poly.contains_brute_force(p));
    }

    #[test]
    fn seeds_are_reproducible(seed in any::<u64>(), r in 0.5f64..2.0) {
        let rect = Rect::new(DVec2::ZERO, DVec2::new(30.0, 17.0));
        let s = PoissonDisc::new(r).unwrap().with_seed(seed);
        prop_assert_eq!(s.sample(&rect).unwrap(), s.sample(&rect).unwrap());
    }
}
