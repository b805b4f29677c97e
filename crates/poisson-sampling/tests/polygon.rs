//! Polygon validation and the indexed point-in-polygon test.

mod common;

use common::polygon_with_holes;
use glam::DVec2;
use proptest::prelude::*;
use relief_poisson_sampling::{Polygon, PolygonError, PolygonSet, Rect, RingIndex};

fn v(points: &[(f64, f64)]) -> Vec<DVec2> {
    points.iter().map(|&(x, y)| DVec2::new(x, y)).collect()
}

#[test]
fn rings_are_normalised() {
    // Clockwise exterior with a closing vertex and a repeated vertex; counter-clockwise hole.
    let poly = Polygon::new(
        v(&[(0.0, 0.0), (0.0, 10.0), (0.0, 10.0), (10.0, 10.0), (10.0, 0.0), (0.0, 0.0)]),
        vec![v(&[(2.0, 2.0), (4.0, 2.0), (3.0, 4.0)])],
    )
    .unwrap();
    assert_eq!(poly.exterior().len(), 4);
    assert_eq!(poly.area(), 100.0 - 2.0);
    assert!(poly.contains(DVec2::new(5.0, 5.0)));
    assert!(!poly.contains(DVec2::new(3.0, 2.5)));
    assert!(!poly.contains(DVec2::new(11.0, 5.0)));
    assert_eq!(poly.bounds(), Rect::new(DVec2::ZERO, DVec2::splat(10.0)));
}

#[test]
fn invalid_polygons_name_the_defect() {
    let err = Polygon::from_exterior(v(&[(0.0, 0.0), (1.0, 1.0), (0.0, 0.0)])).unwrap_err();
    assert_eq!(err, PolygonError::TooFewVertices { ring: 0, count: 2 });
    let err = Polygon::from_exterior(v(&[(0.0, 0.0), (1.0, f64::NAN), (2.0, 0.0)])).unwrap_err();
    assert!(matches!(err, PolygonError::NonFiniteVertex { ring: 0, vertex: 1, .. }));
    let err = Polygon::from_exterior(v(&[(0.0, 0.0), (1.0, 1.0), (2.0, 2.0)])).unwrap_err();
    assert_eq!(err, PolygonError::ZeroArea { ring: 0 });
    // A bow tie crosses itself.
    let err = Polygon::from_exterior(v(&[(0.0, 0.0), (2.0, 2.0), (2.0, 0.0), (0.0, 2.0)])).unwrap_err();
    assert!(matches!(err, PolygonError::SelfIntersection { ring_a: 0, ring_b: 0, .. }), "{err}");
    assert!(err.to_string().contains("near (1, 1)"), "{err}");
    // A spike folds an edge back onto the previous one.
    let err = Polygon::from_exterior(v(&[(0.0, 0.0), (4.0, 0.0), (2.0, 0.0), (2.0, 3.0)])).unwrap_err();
    assert!(matches!(err, PolygonError::SelfIntersection { .. }), "{err}");
    // A vertex touching another edge (pinch).
    let err = Polygon::from_exterior(v(&[(0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (2.0, 0.0), (0.0, 4.0)])).unwrap_err();
    assert!(matches!(err, PolygonError::SelfIntersection { .. }), "{err}");
    let square = v(&[(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)]);
    let err = Polygon::new(square.clone(), vec![v(&[(20.0, 20.0), (21.0, 20.0), (20.0, 21.0)])]).unwrap_err();
    assert_eq!(err, PolygonError::HoleOutside { ring: 1 });
    let err = Polygon::new(square.clone(), vec![v(&[(8.0, 8.0), (12.0, 8.0), (8.0, 9.0)])]).unwrap_err();
    assert!(matches!(err, PolygonError::SelfIntersection { ring_a: 0, ring_b: 1, .. }), "{err}");
    let nested = Polygon::new(
        square,
        vec![v(&[(1.0, 1.0), (9.0, 1.0), (9.0, 9.0), (1.0, 9.0)]), v(&[(4.0, 4.0), (5.0, 4.0), (4.0, 5.0)])],
    )
    .unwrap_err();
    assert_eq!(nested, PolygonError::HoleOutside { ring: 2 });
}

#[test]
fn serde_round_trip_revalidates() {
    let set = PolygonSet::new(vec![
        Polygon::circle(DVec2::new(1.0, 2.0), 3.0, 12).unwrap(),
        Polygon::new(
            v(&[(10.0, 0.0), (20.0, 0.0), (20.0, 10.0), (10.0, 10.0)]),
            vec![v(&[(12.0, 2.0), (14.0, 2.0), (13.0, 4.0)])],
        )
        .unwrap(),
    ]);
    let json = serde_json::to_string(&set).unwrap();
    let back: PolygonSet = serde_json::from_str(&json).unwrap();
    assert_eq!(back, set);
    assert_eq!(back.bounds(), set.bounds());
    let bow_tie = r#"[{"exterior": [[0, 0], [2, 2], [2, 0], [0, 2]]}]"#;
    let err = serde_json::from_str::<PolygonSet>(bow_tie).unwrap_err().to_string();
    assert!(err.contains("touches or crosses"), "{err}");
}

#[test]
fn vertex_on_the_ray_is_counted_once() {
    // The ray from (1, 1) toward +x passes exactly through the vertex (3, 1).
    let diamond = Polygon::from_exterior(v(&[(2.0, 0.0), (3.0, 1.0), (2.0, 2.0), (0.0, 1.0)])).unwrap();
    assert!(diamond.contains(DVec2::new(1.0, 1.0)));
    assert!(!diamond.contains(DVec2::new(3.5, 1.0)));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn indexed_containment_equals_brute_force(poly in polygon_with_holes(), probes in proptest::collection::vec((-60.0f64..60.0, -60.0f64..60.0), 200)) {
        for (x, y) in probes {
            let p = DVec2::new(x, y);
            prop_assert_eq!(poly.contains(p), poly.contains_brute_force(p), "at {}", p);
        }
        // A ring index over the exterior alone agrees with a polygon of that exterior alone.
        let outer = Polygon::from_exterior(poly.exterior().to_vec()).unwrap();
        let index = RingIndex::new(poly.exterior());
        for &q in poly.exterior() {
            for p in [q, q - DVec2::X * 0.5, q + DVec2::X * 1e-9, q * 0.5] {
                prop_assert_eq!(index.contains(p), outer.contains_brute_force(p), "ring index at {}", p);
            }
        }
        // Vertices themselves and their y-levels are the hard cases for a banded index.
        for ring in poly.rings() {
            for &q in ring {
                for p in [q, q - DVec2::X * 0.5, q + DVec2::X * 1e-9] {
                    prop_assert_eq!(poly.contains(p), poly.contains_brute_force(p), "at {}", p);
                }
            }
        }
    }
}
