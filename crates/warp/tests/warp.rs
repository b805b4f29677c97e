//! Exactness, bijectivity and crossing-freedom of the warps.

use glam::DVec2;
use proptest::prelude::*;
use relief_warp::{
    Composition, MAX_DISCS, PathOptions, PathWarp, Profile, SlopeModulation, Warp, WarpError, warp_polyline,
    warp_raster,
};

fn v(points: &[(f64, f64)]) -> Vec<DVec2> {
    points.iter().map(|&(x, y)| DVec2::new(x, y)).collect()
}

fn stroke() -> impl Strategy<Value = Vec<DVec2>> {
    proptest::collection::vec((-100.0f64..100.0, -100.0f64..100.0), 2..6).prop_map(|p| v(&p))
}

#[track_caller]
fn check_inverse(warp: &dyn Warp, p: DVec2) {
    let q = warp.forward(p);
    assert!(q.is_finite());
    let back = warp.inverse(q);
    assert!((back - p).length() < 1e-9, "inverse(forward({p})) = {back}");
    let again = warp.forward(warp.inverse(p));
    assert!((again - p).length() < 1e-9, "forward(inverse({p})) = {again}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn path_warps_invert_exactly(s in stroke(), r in 5.0f64..60.0, mu in 0.0f64..=1.0, k in 1u32..4,
                                 pts in proptest::collection::vec((-170.0f64..170.0, -170.0f64..170.0), 64)) {
        let Ok(warp) = PathWarp::new(&s, &PathOptions { profile: Profile::power(k).unwrap(), ..PathOptions::new(r, mu) }) else {
            return Ok(()); // a random stroke may collapse to one point
        };
        for (x, y) in pts {
            check_inverse(&warp, DVec2::new(x, y));
        }
    }

    #[test]
    fn each_disc_is_monotone_along_its_chords(s in stroke(), r in 5.0f64..60.0, mu in 0.0f64..=1.0, k in 1u32..4, offset in -0.99f64..0.99) {
        let Ok(warp) = PathWarp::new(&s, &PathOptions { profile: Profile::power(k).unwrap(), ..PathOptions::new(r, mu) }) else {
            return Ok(());
        };
        for i in 0..warp.discs() {
            let (c, d) = warp.disc(i);
            let n = d.perp();
            let mut last = f64::NEG_INFINITY;
            for t in -200..=200 {
                let p = c + offset * r * n + (f64::from(t) / 200.0) * r * d;
                let along = (warp.disc_forward(i, p) - c).dot(d);
                prop_assert!(along > last, "disc {} not monotone at t = {}", i, t);
                last = along;
            }
        }
    }

    #[test]
    fn slope_modulations_invert_exactly(cx in -50.0f64..50.0, r in 5.0f64..80.0, mu in -0.99f64..2.99,
                                        pts in proptest::collection::vec((-150.0f64..150.0, -150.0f64..150.0), 64)) {
        let point = SlopeModulation::point(DVec2::new(cx, 0.0), r, mu).unwrap();
        // A gentle arc whose curvature radius (≈ 400) exceeds every tested radius.
        let arc: Vec<DVec2> = (0..=8).map(|k| DVec2::new(-100.0 + 25.0 * f64::from(k), 400.0 - (400.0f64.powi(2) - (-100.0 + 25.0 * f64::from(k)).powi(2)).sqrt())).collect();
        let curve = SlopeModulation::curve(&arc, r, mu).unwrap();
        for (x, y) in pts {
            let p = DVec2::new(x, y);
            check_inverse(&point, p);
            check_inverse(&curve, p);
        }
    }

    #[test]
    fn nested_rings_stay_nested_and_apart_after_random_warps(seed in proptest::collection::vec((0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0), 3),
                                                              mu in 0.1f64..=1.0, sm in -0.9f64..2.9) {
        // Five concentric rings 8 apart, wobbled.
        let rings: Vec<Vec<DVec2>> = (1..=5)
            .map(|k| (0..80).map(|i| {
                let t = std::f64::consts::TAU * f64::from(i) / 80.0;
                (10.0 + 8.0 * f64::from(k) + 1.5 * (5.0 * t + f64::from(k)).sin()) * DVec2::from_angle(t)
            }).collect())
            .collect();
        let (a, b, c) = (seed[0], seed[1], seed[2]);
        let stroke = [DVec2::new(-60.0 + 40.0 * a.0, -30.0 + 60.0 * a.1), DVec2::new(60.0 * b.0, 60.0 * b.1 - 30.0), DVec2::new(40.0 + 20.0 * c.0, 40.0 * c.1)];
        let warp = Composition::new()
            .then(PathWarp::new(&stroke, &PathOptions::new(15.0 + 20.0 * a.2, mu)).unwrap())
            .then(SlopeModulation::point(DVec2::new(30.0 * b.2 - 15.0, 10.0), 40.0, sm).unwrap());
        let warped: Vec<Vec<DVec2>> = rings.iter().map(|r| warp_polyline(&warp, r, true, 0.05).unwrap()).collect();
        prop_assert_eq!(first_crossing(&warped), None);
        // Each ring still encloses the next inner one.
        for k in 1..warped.len() {
            prop_assert!(contains(&warped[k], warped[k - 1][0]), "ring {} no longer inside ring {}", k - 1, k);
        }
    }
}

fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    let k = |p: DVec2| robust::Coord { x: p.x, y: p.y };
    robust::orient2d(k(a), k(b), k(c))
}

/// The first pair of touching or crossing segments among closed polylines (consecutive segments of
/// one ring excepted), brute force with exact predicates.
fn first_crossing(rings: &[Vec<DVec2>]) -> Option<(usize, usize)> {
    let segs: Vec<(usize, usize, DVec2, DVec2)> = rings
        .iter()
        .enumerate()
        .flat_map(|(k, r)| (0..r.len()).map(move |i| (k, i, r[i], r[(i + 1) % r.len()])))
        .collect();
    for x in 0..segs.len() {
        for y in x + 1..segs.len() {
            let ((ka, ia, a, b), (kb, ib, c, d)) = (segs[x], segs[y]);
            let n = rings[ka].len();
            if ka == kb && (ib == ia + 1 || (ia == 0 && ib == n - 1)) {
                continue;
            }
            let (o1, o2, o3, o4) = (orient(a, b, c), orient(a, b, d), orient(c, d, a), orient(c, d, b));
            if o1 * o2 <= 0.0 && o3 * o4 <= 0.0 && (o1, o2, o3, o4) != (0.0, 0.0, 0.0, 0.0) {
                return Some((ka, kb));
            }
        }
    }
    None
}

fn contains(ring: &[DVec2], p: DVec2) -> bool {
    let n = ring.len();
    (0..n)
        .filter(|&i| {
            let (a, b) = (ring[i], ring[(i + 1) % n]);
            (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y)
        })
        .count()
        % 2
        == 1
}

#[test]
fn the_stroke_drags_its_start_to_its_end_at_full_strength() {
    let warp = PathWarp::new(&v(&[(0.0, 0.0), (100.0, 0.0)]), &PathOptions::new(40.0, 1.0)).unwrap();
    // Each disc moves its centre one segment forward: the centre of the first disc ends at the end.
    let moved = warp.forward(DVec2::ZERO);
    assert!((moved - DVec2::new(100.0, 0.0)).length() < 1e-9, "{moved}");
    assert!(warp.segment() <= 0.6495 * 40.0 + 1e-12);
    assert_eq!(warp.forward(DVec2::new(0.0, 45.0)), DVec2::new(0.0, 45.0), "outside every disc");
    assert!(warp.is_locally_bijective(DVec2::new(50.0, 10.0), 1e-4));
}

#[test]
fn forced_segments_above_the_bound_are_rejected_with_the_limit() {
    let stroke = v(&[(0.0, 0.0), (100.0, 0.0)]);
    for (k, limit) in [(1, 0.5), (2, 0.649_519), (3, 0.582_309)] {
        let mut o = PathOptions { profile: Profile::power(k).unwrap(), ..PathOptions::new(10.0, 1.0) };
        o.segment = Some(10.0 * limit * 1.01);
        match PathWarp::new(&stroke, &o) {
            Err(WarpError::SegmentTooLong { limit: l, .. }) => assert!((l - 10.0 * limit).abs() < 1e-4, "k = {k}: {l}"),
            other => panic!("k = {k}: {other:?}"),
        }
        o.segment = Some(10.0 * limit * 0.99);
        assert!(PathWarp::new(&stroke, &o).is_ok());
    }
    // Half strength doubles the admissible segment.
    let mut o = PathOptions::new(10.0, 0.5);
    o.segment = Some(12.0);
    assert!(PathWarp::new(&stroke, &o).is_ok());
    let err = PathWarp::new(&stroke, &PathOptions { segment: Some(14.0), ..PathOptions::new(10.0, 0.5) }).unwrap_err();
    assert!(err.to_string().contains("exceeds the bijectivity limit 12.99"), "{err}");
}

#[test]
fn strokes_needing_too_many_discs_are_refused_not_allocated() {
    // A tiny radius along a long stroke, a forced tiny segment, and a stroke whose length overflows
    // to infinity: each would ask for billions of discs (or saturate a cast) if attempted.
    let long = v(&[(0.0, 0.0), (1.0e9, 0.0)]);
    let huge = v(&[(-1.0e308, 0.0), (1.0e308, 0.0)]);
    let forced = PathOptions { segment: Some(1.0e-9), ..PathOptions::new(10.0, 1.0) };
    for (stroke, options) in
        [(&long, PathOptions::new(1.0e-3, 1.0)), (&long, forced), (&huge, PathOptions::new(1.0, 1.0))]
    {
        match PathWarp::new(stroke, &options) {
            Err(e @ WarpError::TooManyDiscs { max: MAX_DISCS, .. }) => {
                assert!(e.to_string().contains("larger radius"), "{e}");
            }
            other => panic!("{other:?}"),
        }
    }
    // Just under the cap is accepted.
    let radius = 1.0e9 / (0.5 * 0.6495 * (MAX_DISCS - 1000) as f64);
    assert!(PathWarp::new(&long, &PathOptions::new(radius, 1.0)).is_ok_and(|w| w.discs() <= MAX_DISCS));
}

#[test]
fn custom_profiles_get_their_own_bound() {
    let sine = Profile::custom(|x| (std::f64::consts::PI * x).sin()).unwrap();
    let warp = PathWarp::new(
        &v(&[(0.0, 0.0), (50.0, 10.0), (90.0, -20.0)]),
        &PathOptions { profile: sine, ..PathOptions::new(20.0, 1.0) },
    )
    .unwrap();
    assert!(warp.segment() <= 2.0 * 20.0 / std::f64::consts::PI + 1e-9);
    for i in -20..20 {
        check_inverse(&warp, DVec2::new(f64::from(i) * 5.0, 3.0));
    }
}

#[test]
fn bad_input_is_a_typed_error() {
    let o = PathOptions::new(10.0, 0.5);
    assert!(matches!(PathWarp::new(&v(&[(1.0, 1.0)]), &o), Err(WarpError::DegenerateStroke { distinct: 1, .. })));
    assert!(matches!(PathWarp::new(&v(&[(1.0, 1.0), (1.0, 1.0)]), &o), Err(WarpError::DegenerateStroke { .. })));
    assert!(matches!(PathWarp::new(&v(&[(0.0, f64::NAN), (1.0, 1.0)]), &o), Err(WarpError::NonFinite { .. })));
    let s = v(&[(0.0, 0.0), (10.0, 0.0)]);
    assert!(matches!(PathWarp::new(&s, &PathOptions::new(0.0, 0.5)), Err(WarpError::InvalidRadius { .. })));
    assert!(matches!(PathWarp::new(&s, &PathOptions::new(-3.0, 0.5)), Err(WarpError::InvalidRadius { .. })));
    assert!(matches!(PathWarp::new(&s, &PathOptions::new(5.0, 1.5)), Err(WarpError::InvalidStrength { .. })));
    assert!(matches!(PathWarp::new(&s, &PathOptions::new(5.0, f64::NAN)), Err(WarpError::NonFinite { .. })));
    assert!(matches!(SlopeModulation::point(DVec2::ZERO, 5.0, 3.0), Err(WarpError::InvalidStrength { .. })));
    assert!(matches!(SlopeModulation::point(DVec2::ZERO, 5.0, -1.0), Err(WarpError::InvalidStrength { .. })));
    assert!(matches!(SlopeModulation::point(DVec2::ZERO, 0.0, 1.0), Err(WarpError::InvalidRadius { .. })));
    // A sharp corner bends far below the radius.
    let corner = v(&[(0.0, 0.0), (50.0, 0.0), (50.0, 50.0)]);
    assert!(matches!(SlopeModulation::curve(&corner, 20.0, 1.0), Err(WarpError::CurvatureTooHigh { .. })));
    // A hairpin: legs 60 apart joined by a semicircle of radius 30.
    let hairpin = |gap: f64| -> Vec<DVec2> {
        let half = gap / 2.0;
        let mut p: Vec<DVec2> = (0..=10).map(|k| DVec2::new(20.0 * f64::from(k), 0.0)).collect();
        p.extend((1..20).map(|k| {
            let t = -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * f64::from(k) / 20.0;
            DVec2::new(200.0, half) + half * DVec2::from_angle(t)
        }));
        p.extend((0..=10).rev().map(|k| DVec2::new(20.0 * f64::from(k), gap)));
        p
    };
    assert!(SlopeModulation::curve(&hairpin(60.0), 5.0, 1.0).is_ok());
    let err = SlopeModulation::curve(&hairpin(60.0), 40.0, 1.0).unwrap_err();
    assert!(matches!(err, WarpError::CurvatureTooHigh { .. }), "bend radius 30 < 40: {err}");
    // A circle of radius 100 drawn through 340°: gentle everywhere, but its ends are ≈ 35 apart,
    // closer than 2r = 60.
    let almost_closed: Vec<DVec2> =
        (0..=34).map(|k| 100.0 * DVec2::from_angle(f64::from(k).to_radians() * 10.0)).collect();
    let err = SlopeModulation::curve(&almost_closed, 30.0, 1.0).unwrap_err();
    assert!(matches!(err, WarpError::CurveTooClose { .. }), "{err}");
    assert!(SlopeModulation::curve(&almost_closed, 15.0, 1.0).is_ok());
    assert!(warp_polyline(&Composition::new(), &s, false, 0.0).is_err());
}

#[test]
fn rasters_warp_by_backward_mapping() {
    let warp = PathWarp::new(&v(&[(20.0, 32.0), (44.0, 32.0)]), &PathOptions::new(12.0, 1.0)).unwrap();
    let ramp = |p: DVec2| (p.x + 2.0 * p.y) as f32;
    let out = warp_raster(&warp, 64, 64, |i, j| DVec2::new(i as f64, j as f64), ramp);
    for j in 0..64 {
        for i in 0..64 {
            let p = DVec2::new(i as f64, j as f64);
            assert_eq!(out[j * 64 + i], ramp(warp.inverse(p)));
        }
    }
    assert_eq!(out[0], 0.0, "outside the support the raster is unchanged");
    assert_ne!(out[32 * 64 + 40], ramp(DVec2::new(40.0, 32.0)), "inside, content moved");
}

#[test]
fn slope_modulation_steepens_or_flattens_radially() {
    let steep = SlopeModulation::point(DVec2::ZERO, 100.0, 2.0).unwrap();
    let flat = SlopeModulation::point(DVec2::ZERO, 100.0, -0.8).unwrap();
    let p = DVec2::new(40.0, 0.0);
    assert!(steep.forward(p).x < 40.0, "positive μ pulls toward the centre");
    assert!(flat.forward(p).x > 40.0, "negative μ pushes away");
    let arc: Vec<DVec2> = (0..=10).map(|k| DVec2::new(f64::from(k) * 20.0, 0.0)).collect();
    let along = SlopeModulation::curve(&arc, 30.0, 2.0).unwrap();
    let q = along.forward(DVec2::new(100.0, 15.0));
    assert!((q.x - 100.0).abs() < 1e-9 && q.y < 15.0, "moves straight toward the curve: {q}");
    for (w, d) in [(&steep as &dyn Warp, 100.0), (&along, 30.0)] {
        for i in 0..50 {
            let p = DVec2::new(f64::from(i) * 3.7 - 40.0, f64::from(i % 7) * 4.0 - 10.0);
            assert!(w.is_locally_bijective(p, 1e-5 * d), "fold at {p}");
        }
    }
}
