//! Structure, Delaunay property, location, interpolation and rasterization of `Tin`.

use glam::DVec2;
use proptest::prelude::*;
use relief_tin::heightfield::{Extent, GridSpec};
use relief_tin::poisson_sampling::{PoissonDisc, Rect};
use relief_tin::{Location, NO_TRIANGLE, PointLocator, Tin, TinError};

fn pts(v: &[(f64, f64)]) -> Vec<DVec2> {
    v.iter().map(|&(x, y)| DVec2::new(x, y)).collect()
}

/// Random points, or points snapped to a coarse lattice (many cocircular and collinear quadruples).
fn point_set() -> impl Strategy<Value = Vec<DVec2>> {
    let free = proptest::collection::vec((-100.0f64..100.0, -100.0f64..100.0), 3..150);
    let lattice = proptest::collection::vec((0i32..12, 0i32..12), 3..150)
        .prop_map(|v| v.into_iter().map(|(x, y)| (f64::from(x) * 2.5, f64::from(y) * 2.5)).collect());
    prop_oneof![free, lattice].prop_map(|v: Vec<(f64, f64)>| {
        let mut p = pts(&v);
        p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
        p.dedup();
        p
    })
}

fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

/// Exact-enough brute force: is `d` strictly inside the circumcircle of `a, b, c` (CCW)?
fn in_circumcircle(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let k = |p: DVec2| robust::Coord { x: p.x, y: p.y };
    robust::incircle(k(a), k(b), k(c), k(d)) > 0.0
}

fn all_collinear(p: &[DVec2]) -> bool {
    p.len() < 3
        || p[2..].iter().all(|&c| {
            robust::orient2d(
                robust::Coord { x: p[0].x, y: p[0].y },
                robust::Coord { x: p[1].x, y: p[1].y },
                robust::Coord { x: c.x, y: c.y },
            ) == 0.0
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn delaunay_structure_holds_on_random_sets(points in point_set()) {
        let tin = match Tin::new(points.clone()) {
            Ok(t) => t,
            Err(TinError::Collinear { .. }) => {
                prop_assert!(all_collinear(&points));
                return Ok(());
            }
            Err(e) => return Err(TestCaseError::fail(e.to_string())),
        };
        tin.check_invariants().map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(tin.points(), &points[..]);
        // Euler: V − E + T = 1 for a triangulated convex region.
        let (v, e, t) = (tin.num_points() as i64, tin.num_edges() as i64, tin.num_triangles() as i64);
        prop_assert_eq!(v - e + t, 1);
        // Empty circumcircle, brute force over all nodes.
        for tri in tin.triangles() {
            let [a, b, c] = tri.map(|k| points[k as usize]);
            for (w, &d) in points.iter().enumerate() {
                prop_assert!(!in_circumcircle(a, b, c, d), "node {} inside circumcircle of {:?}", w, tri);
            }
        }
        prop_assert!(tin.is_delaunay());
        // Adjacency symmetric and equal to the triangles' edges.
        let mut from_triangles: Vec<(u32, u32)> = tin.triangles().iter()
            .flat_map(|t| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]))))
            .collect();
        from_triangles.sort_unstable();
        from_triangles.dedup();
        let edges: Vec<(u32, u32)> = { let mut e: Vec<_> = tin.edges().collect(); e.sort_unstable(); e };
        prop_assert_eq!(edges, from_triangles);
        // Boundary flags are exactly the nodes on hull edges.
        for (node, &flag) in tin.boundary_flags().iter().enumerate() {
            let on_hull_edge = tin.triangles().iter().zip(tin.triangle_neighbors()).any(|(t, n)| {
                (0..3).any(|k| n[k] == NO_TRIANGLE && (t[(k + 1) % 3] as usize == node || t[(k + 2) % 3] as usize == node))
            });
            prop_assert_eq!(flag, on_hull_edge);
        }
        // Rebuilding from the parts reproduces the same TIN.
        let rebuilt = Tin::from_parts(tin.points().to_vec(), tin.triangles().to_vec()).unwrap();
        prop_assert_eq!(&rebuilt, &tin);
    }

    #[test]
    fn interpolation_reproduces_linear_functions(points in point_set(), a in -5.0f64..5.0, b in -5.0f64..5.0, c in -100.0f64..100.0, probes in proptest::collection::vec((-100.0f64..100.0, -100.0f64..100.0), 50)) {
        let Ok(tin) = Tin::new(points.clone()) else { return Ok(()) };
        let f = |p: DVec2| a * p.x + b * p.y + c;
        let values: Vec<f64> = points.iter().map(|&p| f(p)).collect();
        let locator = PointLocator::new(&tin);
        for (x, y) in probes {
            let p = DVec2::new(x, y);
            let got = tin.interpolate(p, &values).unwrap();
            prop_assert_eq!(got.is_some(), matches!(locator.locate(p), Location::Inside { .. }));
            if let Some(v) = got {
                prop_assert!((v - f(p)).abs() <= 1e-9 * (1.0 + f(p).abs() + 100.0 * (a.abs() + b.abs())), "{} vs {}", v, f(p));
                prop_assert_eq!(locator.interpolate(p, &values).unwrap().is_some(), true);
            }
        }
        for (k, &p) in points.iter().enumerate() {
            let v = tin.interpolate(p, &values).unwrap().expect("every node is inside its own TIN");
            prop_assert!((v - values[k]).abs() <= 1e-9 * (1.0 + values[k].abs() + 1000.0));
        }
    }

    #[test]
    fn parallel_raster_equals_serial_and_fills_the_hull(points in point_set(), nx in 2usize..60, ny in 2usize..60, a in -3.0f64..3.0, b in -3.0f64..3.0) {
        let Ok(tin) = Tin::new(points.clone()) else { return Ok(()) };
        let values: Vec<f64> = points.iter().map(|p| a * p.x + b * p.y).collect();
        let grid = GridSpec::from_extent(nx, ny, Extent::new(DVec2::splat(-105.0), DVec2::splat(105.0))).unwrap();
        let par = tin.rasterize(&values, &grid).unwrap();
        let ser = tin.rasterize_serial(&values, &grid).unwrap();
        prop_assert_eq!(&par, &ser);
        for j in 0..ny {
            for i in 0..nx {
                let p = grid.position(i, j);
                match tin.locate(p) {
                    Location::Inside { .. } => {
                        let v = par.get(i, j);
                        prop_assert!(v.is_some(), "sample {} inside the hull was not rasterized", p);
                        let exact = a * p.x + b * p.y;
                        prop_assert!((f64::from(v.unwrap()) - exact).abs() < 1e-3 * (1.0 + exact.abs()));
                    }
                    Location::Outside => prop_assert!(par.get(i, j).is_none(), "sample {} outside the hull has a value", p),
                }
            }
        }
    }
}

#[test]
fn lattice_raster_has_no_gaps_on_shared_edges() {
    // Grid samples exactly on triangle edges and corners: every one must get a value.
    let points: Vec<DVec2> =
        (0..=10).flat_map(|j| (0..=10).map(move |i| DVec2::new(f64::from(i), f64::from(j)))).collect();
    let tin = Tin::new(points.clone()).unwrap();
    let values: Vec<f64> = points.iter().map(|p| p.x + 2.0 * p.y).collect();
    let grid = GridSpec::from_extent(41, 41, Extent::new(DVec2::ZERO, DVec2::splat(10.0))).unwrap();
    let dem = tin.rasterize(&values, &grid).unwrap();
    assert_eq!(dem.no_data_count(), 0);
    assert_eq!(dem.get(40, 40), Some(30.0));
    assert_eq!(dem.get(20, 4), Some(7.0));
}

/// A hull on the grid's last column and row covers them at every size, though `x / dx` there
/// may round below the column's index (24 000 m over 256 samples: 254.99…); samples beyond the
/// hull stay empty.
#[test]
fn a_hull_on_the_grid_edge_covers_the_last_column_and_row() {
    let side = 24_000.0;
    let points = pts(&[(0.0, 0.0), (side, 0.0), (side, side), (0.0, side), (9_000.0, 13_000.0)]);
    let tin = Tin::new(points.clone()).unwrap();
    let values: Vec<f64> = points.iter().map(|p| 1.0 + p.x * 1e-3 + p.y * 2e-3).collect();
    for n in (2..=64).chain([255, 256, 257, 600, 1000]) {
        let grid = GridSpec::from_extent(n, n, Extent::new(DVec2::ZERO, DVec2::splat(side))).unwrap();
        let dem = tin.rasterize(&values, &grid).unwrap();
        assert_eq!(dem.no_data_count(), 0, "{n} samples a side");
        assert_eq!(dem.samples(), tin.rasterize_serial(&values, &grid).unwrap().samples());
        let corner = dem.get(n - 1, 0).unwrap();
        assert!((corner - 25.0).abs() < 1e-3, "{n}: {corner}");
    }
    // A grid wider than the hull: the columns beyond it stay empty, the one on it does not.
    let grid = GridSpec::new(5, 1, DVec2::new(side - 2.0, 0.0), DVec2::ONE).unwrap();
    let dem = tin.rasterize(&values, &grid).unwrap();
    let filled: Vec<bool> = dem.samples().iter().map(|v| v.is_finite()).collect();
    assert_eq!(filled, [true, true, true, false, false]);
}

#[test]
fn bad_input_is_rejected_with_the_culprit_named() {
    assert_eq!(Tin::new(pts(&[(0.0, 0.0), (1.0, 0.0)])), Err(TinError::TooFewPoints { count: 2 }));
    let err = Tin::new(pts(&[(0.0, 0.0), (1.0, 0.0), (f64::NAN, 1.0)])).unwrap_err();
    assert!(matches!(err, TinError::NonFinitePoint { index: 2, .. }));
    let err = Tin::new(pts(&[(0.0, 0.0), (1.0, 0.0), (1e300, 1.0)])).unwrap_err();
    assert!(matches!(err, TinError::CoordinateOutOfRange { index: 2, .. }));
    let err = Tin::new(pts(&[(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 0.0)])).unwrap_err();
    assert_eq!(err, TinError::DuplicatePoint { first: 1, second: 3, x: 1.0, y: 0.0 });
    let err = Tin::new(pts(&[(0.0, 0.0), (1.0, 1.0), (2.0, 2.0), (3.0, 3.0)])).unwrap_err();
    assert_eq!(err, TinError::Collinear { count: 4 });
    let square = pts(&[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]);
    let err = Tin::from_parts(square.clone(), vec![[0, 1, 2], [0, 2, 7]]).unwrap_err();
    assert!(matches!(err, TinError::InvalidTriangle { triangle: 1, .. }), "{err}");
    let err = Tin::from_parts(square.clone(), vec![[0, 2, 1]]).unwrap_err();
    assert!(err.to_string().contains("not counter-clockwise"), "{err}");
    // Node 3 belongs to no triangle.
    let err = Tin::from_parts(square.clone(), vec![[0, 1, 2]]).unwrap_err();
    assert_eq!(err, TinError::NonManifoldVertex { vertex: 3 });
    // The same triangle twice: its edges are used three... twice in the same direction.
    let err = Tin::from_parts(square, vec![[0, 1, 2], [0, 1, 2], [0, 2, 3]]).unwrap_err();
    assert!(matches!(err, TinError::NonManifoldVertex { .. }), "{err}");
}

#[test]
fn rasterize_validates_values() {
    let tin = Tin::new(pts(&[(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)])).unwrap();
    let grid = GridSpec::from_extent(3, 3, Extent::new(DVec2::ZERO, DVec2::ONE)).unwrap();
    assert_eq!(tin.rasterize(&[1.0, 2.0], &grid), Err(TinError::ValueCountMismatch { expected: 3, found: 2 }));
    assert_eq!(
        tin.rasterize(&[1.0, f64::INFINITY, 0.0], &grid),
        Err(TinError::NonFiniteValue { node: 1, value: f64::INFINITY })
    );
    let with_hole = tin.rasterize(&[1.0, f64::NAN, 0.0], &grid).unwrap();
    assert_eq!(with_hole.no_data_count(), 9);
    assert_eq!(tin.interpolate(DVec2::ZERO, &[1.0]), Err(TinError::ValueCountMismatch { expected: 3, found: 1 }));
}

#[test]
fn non_convex_meshes_locate_by_scan_when_the_walk_leaves() {
    // An L-shaped mesh: the walk from the far arm exits through the notch.
    let points = pts(&[(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0), (0.0, 1.0)]);
    let tris = vec![[0, 1, 2], [0, 2, 3], [0, 3, 6], [6, 3, 4], [6, 4, 5]];
    let tin = Tin::from_parts(points, tris).unwrap();
    tin.check_invariants().unwrap();
    assert!(!tin.is_convex());
    assert!(matches!(tin.locate_from(DVec2::new(1.5, 0.5), 4), Location::Inside { triangle: 0 | 1, .. }));
    assert_eq!(tin.locate_from(DVec2::new(1.5, 1.5), 4), Location::Outside);
    assert!(matches!(tin.locate_from(DVec2::new(0.5, 1.7), 0), Location::Inside { triangle: 4, .. }));
}

#[test]
fn mesh_with_a_hole_satisfies_euler() {
    // A square annulus: 8 nodes, 8 triangles, two boundary loops: V − E + T = 8 − 16 + 8 = 0.
    let points = pts(&[(0.0, 0.0), (3.0, 0.0), (3.0, 3.0), (0.0, 3.0), (1.0, 1.0), (2.0, 1.0), (2.0, 2.0), (1.0, 2.0)]);
    let tris = vec![[0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]];
    let tin = Tin::from_parts(points, tris).unwrap();
    tin.check_invariants().unwrap();
    assert_eq!(tin.num_edges(), 16);
    assert!(tin.boundary_flags().iter().all(|&b| b));
    assert_eq!(tin.locate(DVec2::splat(1.5)), Location::Outside);
}

#[test]
fn neighbours_are_counter_clockwise_fans() {
    let points =
        PoissonDisc::new(1.0).unwrap().with_seed(4).sample(&Rect::new(DVec2::ZERO, DVec2::splat(20.0))).unwrap();
    let tin = Tin::new(points).unwrap();
    for v in 0..tin.num_points() as u32 {
        let c = tin.points()[v as usize];
        let nb = tin.neighbors(v);
        let turns = nb.len() - usize::from(tin.is_boundary(v));
        for k in 0..turns {
            let (a, b) = (tin.points()[nb[k] as usize], tin.points()[nb[(k + 1) % nb.len()] as usize]);
            assert!(orient(c, a, b) > 0.0, "neighbours of {v} are not counter-clockwise at {k}");
        }
    }
}

#[test]
fn serde_round_trip_rebuilds_and_validates() {
    let points =
        PoissonDisc::new(1.0).unwrap().with_seed(2).sample(&Rect::new(DVec2::ZERO, DVec2::splat(8.0))).unwrap();
    let tin = Tin::new(points).unwrap();
    let json = serde_json::to_string(&tin).unwrap();
    let back: Tin = serde_json::from_str(&json).unwrap();
    assert_eq!(back, tin);
    let broken = json.replacen("[0,", "[9999,", 1);
    assert!(serde_json::from_str::<Tin>(&broken).is_err());
}

#[test]
fn vertices_joining_several_fans_are_not_manifold() {
    // Bow tie: two triangles touching only at node 0 give it two open fans.
    let points = pts(&[(0.0, 0.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0)]);
    let err = Tin::from_parts(points, vec![[0, 1, 2], [0, 3, 4]]).unwrap_err();
    assert_eq!(err, TinError::NonManifoldVertex { vertex: 0 });
    // Hourglass: two distinct closed fans around node 0 (an inner and an outer diamond).
    let points = pts(&[
        (0.0, 0.0),
        (1.0, 0.0),
        (0.0, 1.0),
        (-1.0, 0.0),
        (0.0, -1.0),
        (2.0, 0.0),
        (0.0, 2.0),
        (-2.0, 0.0),
        (0.0, -2.0),
    ]);
    let inner = [[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]];
    let outer = [[0, 5, 6], [0, 6, 7], [0, 7, 8], [0, 8, 5]];
    let err = Tin::from_parts(points, inner.iter().chain(&outer).copied().collect()).unwrap_err();
    assert_eq!(err, TinError::NonManifoldVertex { vertex: 0 });
    // The same triangle twice: node 0's spans start at the same node twice.
    let points = pts(&[(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)]);
    let err = Tin::from_parts(points, vec![[0, 1, 2], [0, 1, 2]]).unwrap_err();
    assert_eq!(err, TinError::NonManifoldVertex { vertex: 0 });
}

#[test]
fn constrained_triangulation_keeps_its_constraints_and_skips_crossings() {
    use glam::DVec2;
    use relief_tin::{Tin, TinError};
    // A square of points with a long diagonal constraint that plain Delaunay would not contain,
    // and a second constraint crossing it.
    let mut points = Vec::new();
    for j in 0..5 {
        for i in 0..5 {
            points.push(DVec2::new(f64::from(i), f64::from(j) + 0.01 * f64::from(i)));
        }
    }
    let (tin, skipped) = Tin::constrained(points.clone(), &[[0, 24], [4, 20]]).unwrap();
    tin.check_invariants().unwrap();
    assert_eq!(skipped, 1, "the crossing constraint is skipped");
    // Exactly one of the two diagonals survives as a mesh edge (which one spade keeps is unspecified).
    let edges: std::collections::HashSet<(u32, u32)> = tin.edges().map(|(a, b)| (a.min(b), a.max(b))).collect();
    assert!(edges.contains(&(0, 24)) ^ edges.contains(&(4, 20)), "neither or both diagonals are in the mesh");
    // Without constraints neither long diagonal is a Delaunay edge.
    let plain = Tin::new(points.clone()).unwrap();
    assert!(!plain.edges().any(|(a, b)| (a.min(b), a.max(b)) == (0, 24) || (a.min(b), a.max(b)) == (4, 20)));
    assert!(matches!(
        Tin::constrained(points.clone(), &[[0, 99]]),
        Err(TinError::InvalidConstraint { constraint: 0, .. })
    ));
    assert!(matches!(Tin::constrained(points, &[[3, 3]]), Err(TinError::InvalidConstraint { .. })));
}
