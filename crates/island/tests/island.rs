//! Issue #10's invariants: sea is exactly 0 and land positive; cuts remove the left side;
//! clockwise supplements add and counter-clockwise ones replace; one stroke can do both; the
//! §3.2 blend keeps heights by unchanged coast; a volcano's crater sits below its rim; incremental
//! updates equal a rebuild; replays are byte-identical for any thread count; bad input is typed.

use glam::DVec2;
use proptest::prelude::*;
use relief_heightfield::{Extent, GridSpec};
use relief_island::{EditKind, Hill, Island, IslandError, IslandSettings, Operation};

fn grid(n: usize) -> GridSpec {
    GridSpec::from_extent(n, n, Extent::new(DVec2::ZERO, DVec2::splat(1000.0))).unwrap()
}

fn island(n: usize) -> Island {
    Island::new(grid(n), IslandSettings::default(), 5).unwrap()
}

fn pts(p: &[[f64; 2]]) -> Vec<DVec2> {
    p.iter().map(|&q| DVec2::from(q)).collect()
}

fn at(island: &Island, p: [f64; 2]) -> (bool, f32) {
    let (i, j) = island.grid().nearest_sample(DVec2::from(p)).unwrap();
    let k = island.grid().index(i, j);
    (island.land()[k], island.terrain()[k])
}

/// The island's own invariants ([`Island::check_invariants`]), then sea exactly +0 and land
/// above 0 (but in the hollows of negative hills: lakes and craters) as this suite states them.
#[track_caller]
fn check_island(island: &Island) {
    if let Err(e) = island.check_invariants() {
        panic!("{e}");
    }
    let g = *island.grid();
    for (k, (&land, &h)) in island.land().iter().zip(island.terrain()).enumerate() {
        if land {
            let p = g.position(k % g.nx(), k / g.nx());
            let hollow: f64 = island.hills().iter().map(|hill| hill.at(p)).sum();
            assert!(h > 0.0 || hollow < 0.0, "land sample {k} at {h}");
        } else {
            assert!(h == 0.0 && h.is_sign_positive(), "sea sample {k} at {h}");
        }
    }
}

#[test]
fn the_start_is_a_conical_island() {
    let i = island(129);
    check_island(&i);
    let (land, top) = at(&i, [500.0, 500.0]);
    assert!(land && (top - 100.0).abs() < 2.0, "{top}");
    let (_, half) = at(&i, [700.0, 500.0]);
    assert!((half - 50.0).abs() < 2.0, "cone: {half}");
    assert!(!at(&i, [50.0, 50.0]).0);
}

#[test]
fn a_cut_removes_the_left_side_of_the_stroke() {
    let mut up = island(129);
    assert_eq!(up.stroke(&pts(&[[400.0, -10.0], [400.0, 1010.0]])).unwrap(), vec![EditKind::Cut]);
    assert!(!at(&up, [300.0, 500.0]).0 && at(&up, [600.0, 500.0]).0);
    let mut down = island(129);
    down.stroke(&pts(&[[400.0, 1010.0], [400.0, -10.0]])).unwrap();
    assert!(at(&down, [300.0, 500.0]).0 && !at(&down, [600.0, 500.0]).0);
    check_island(&up);
    check_island(&down);
}

#[test]
fn clockwise_supplements_add_and_counter_clockwise_ones_replace() {
    // From the top of the circle out around to its right side: clockwise.
    let around = [[500.0, 905.0], [800.0, 960.0], [960.0, 800.0], [905.0, 500.0]];
    let mut add = island(129);
    let area = add.area();
    assert_eq!(add.stroke(&pts(&around)).unwrap(), vec![EditKind::Add]);
    assert!(add.area() > area);
    assert!(at(&add, [850.0, 850.0]).0 && at(&add, [500.0, 500.0]).0);
    let mut replace = island(129);
    let back: Vec<[f64; 2]> = around.iter().rev().copied().collect();
    assert_eq!(replace.stroke(&pts(&back)).unwrap(), vec![EditKind::Replace]);
    assert!(replace.area() < area);
    assert!(at(&replace, [850.0, 850.0]).0 && !at(&replace, [500.0, 500.0]).0);
    check_island(&add);
    check_island(&replace);
}

#[test]
fn one_stroke_can_supplement_then_cut() {
    // Figure 6: out from the west coast, clockwise around to the top, then down through the land.
    let mut i = island(129);
    let stroke = [[96.0, 500.0], [60.0, 700.0], [200.0, 950.0], [500.0, 960.0], [500.0, 40.0]];
    assert_eq!(i.stroke(&pts(&stroke)).unwrap(), vec![EditKind::Add, EditKind::Cut]);
    assert!(at(&i, [250.0, 850.0]).0, "added");
    assert!(at(&i, [300.0, 500.0]).0 && !at(&i, [700.0, 500.0]).0, "east half cut off");
    check_island(&i);
}

#[test]
fn heights_by_unchanged_coast_stay_and_a_cut_keeps_at_most_half() {
    let mut i = island(257);
    let before = i.heights().to_vec();
    i.stroke(&pts(&[[350.0, -10.0], [350.0, 1010.0]])).unwrap();
    check_island(&i);
    let g = *i.grid();
    let mut checked = 0;
    for (k, &h) in i.heights().iter().enumerate() {
        if !i.land()[k] {
            continue;
        }
        let p = g.position(k % g.nx(), k / g.nx());
        let d = i.distance_to_coast(p);
        if d > 25.0 {
            continue;
        }
        if p.x > 700.0 {
            // By the unchanged eastern coast.
            assert!((h - before[k]).abs() <= 0.15 * before[k] + 1.0, "{p}: {h} was {}", before[k]);
            checked += 1;
        } else if (p.x - 350.0).abs() < 8.0 {
            // By the new cut W ≥ ½, so at least half of the old height gives way to the new
            // cone, which starts at sea level there: the cut leaves a cliff at most half as high.
            assert!(h <= 0.5 * before[k] + 3.0, "{p}: {h} was {}", before[k]);
            checked += 1;
        }
    }
    assert!(checked > 50);
}

#[test]
fn a_hollow_below_sea_level_holds_a_lake() {
    // §3.3: paraboloids opening upwards make valleys, lakes and craters. A hollow 60 m deep in
    // ground about 40 m high goes under the sea: a lake, where the land floor used to flatten it
    // to 0.1 m.
    let mut i = island(257);
    let center = DVec2::new(500.0, 500.0);
    let ground = f64::from(at(&i, [500.0, 500.0]).1);
    i.add_hill(Hill::round(center, 120.0, -(ground + 20.0))).unwrap();
    check_island(&i);
    let (land, bottom) = at(&i, [500.0, 500.0]);
    assert!(land && (f64::from(bottom) + 20.0).abs() < 0.5, "the lake bottom at {bottom}, want −20");
    // Its shore, where the hollow has not yet reached the sea, stays on the ground.
    let (_, rim) = at(&i, [500.0 + 119.0, 500.0]);
    assert!(rim > 1.0, "rim {rim}");
}

#[test]
fn a_volcano_has_its_crater_below_its_rim() {
    let mut i = island(257);
    i.add_hill(Hill::round(DVec2::splat(500.0), 300.0, 250.0)).unwrap();
    i.add_hill(Hill::round(DVec2::splat(500.0), 100.0, -200.0)).unwrap();
    let (_, centre) = at(&i, [500.0, 500.0]);
    let (_, rim) = at(&i, [600.0, 500.0]);
    assert!(centre + 50.0 < rim, "crater {centre}, rim {rim}");
    check_island(&i);
}

fn session() -> Vec<Operation> {
    serde_json::from_str(
        r#"[
        {"stroke": {"points": [[300, -10], [320, 500], [300, 1010]]}},
        {"add_hill": {"center": [600, 500], "radii": [220, 140], "rotation": 30, "height": 180}},
        {"add_hill": {"center": [600, 500], "radii": [70, 70], "height": -120}},
        {"add_filters": {"coverage": 2}},
        {"move_hill": {"hill": 0, "center": [620, 520]}},
        {"resize_hill": {"hill": 1, "radii": [90, 80], "height": -150}},
        {"add_filters": {}},
        {"remove_filters": {"count": 30}},
        {"add_hill": {"center": [450, 300], "radii": [100, 60], "height": 60}},
        {"remove_hill": {"hill": 2}}
    ]"#,
    )
    .unwrap()
}

#[test]
fn replays_are_byte_identical_for_any_thread_count() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut i = island(193);
            i.replay(&session()).unwrap();
            i.terrain().iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<u8>>()
        })
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(2));
}

#[test]
fn incremental_updates_equal_a_rebuild_after_a_session() {
    let mut i = island(193);
    for op in &session() {
        i.apply(op).unwrap();
        check_island(&i);
    }
    assert!(!i.filters().is_empty());
    let mut full = i.clone();
    full.rebuild();
    assert_eq!(i.terrain(), full.terrain());
    check_island(&i);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn any_hill_edits_equal_a_rebuild_and_keep_sea_at_zero(
        hills in prop::collection::vec((0.0..1000.0f64, 0.0..1000.0f64, 5.0..300.0f64, 0.3..1.0f64, 0.0..180.0f64, -300.0..300.0f64), 1..8),
        moves in prop::collection::vec((0usize..8, 0.0..1000.0f64, 0.0..1000.0f64), 0..6),
        remove in prop::option::of(0usize..8),
    ) {
        let mut i = island(97);
        for &(x, y, a, ratio, rot, h) in &hills {
            i.add_hill(Hill { center: [x, y], radii: [a, a * ratio], rotation: rot, height: h }).unwrap();
            check_island(&i);
        }
        for &(k, x, y) in &moves {
            if k < i.hills().len() {
                i.move_hill(k, DVec2::new(x, y)).unwrap();
                check_island(&i);
            }
        }
        if let Some(k) = remove && k < i.hills().len() {
            i.remove_hill(k).unwrap();
        }
        let mut full = i.clone();
        full.rebuild();
        prop_assert_eq!(i.terrain(), full.terrain());
        check_island(&i);
    }
}

/// Heights beyond f32's reach are refused by name, never a panic when the grid is made (a scene
/// asking for a 3.5e38 m island used to abort `relief generate`).
#[test]
fn heights_too_large_for_the_grid_are_refused() {
    let settings = |f: fn(&mut IslandSettings)| {
        let mut s = IslandSettings::default();
        f(&mut s);
        Island::new(grid(33), s, 1).map(drop)
    };
    let refused = |result: Result<(), IslandError>, field: &str| match result {
        Err(IslandError::InvalidParameter { name, .. }) => assert_eq!(name, field),
        other => panic!("{field}: {other:?}"),
    };
    refused(settings(|s| s.height = 3.5e38), "height");
    refused(settings(|s| s.height = 1.0e7 * 1.000_001), "height");
    refused(settings(|s| s.land_floor = 2.0e7), "land_floor");
    refused(settings(|s| s.filter_height = [0.1, 11.0]), "filter_height");
    refused(settings(|s| s.filter_radius = [0.1, 11.0]), "filter_radius");
    assert!(settings(|s| s.height = 1.0e7).is_ok(), "MAX_HEIGHT itself is allowed");
    let mut i = island(33);
    for height in [3.5e38, -2.0e7] {
        let hill = Hill::round(DVec2::splat(500.0), 100.0, height);
        assert!(matches!(i.add_hill(hill), Err(IslandError::InvalidHill { .. })), "{height}");
    }
    assert!(i.add_hill(Hill::round(DVec2::splat(500.0), 100.0, -1.0e7)).is_ok());
    let wide = GridSpec::new(33, 33, DVec2::ZERO, DVec2::splat(1.0e8)).unwrap();
    assert!(matches!(Island::new(wide, IslandSettings::default(), 1), Err(IslandError::Grid { .. })));
    // At the bounds every sample stays finite.
    let mut i = Island::new(grid(33), IslandSettings { height: 1.0e7, ..IslandSettings::default() }, 1).unwrap();
    i.add_hill(Hill::round(DVec2::splat(500.0), 400.0, 1.0e7)).unwrap();
    assert!(i.heightfield().samples().iter().all(|v| v.is_finite()));
}

#[test]
fn bad_input_is_a_typed_error() {
    let mut i = island(65);
    assert!(matches!(
        i.set_coastline(&pts(&[[100.0, 100.0], [900.0, 100.0], [900.0, 900.0], [100.0, 700.0]])),
        Err(IslandError::OpenCoastline { .. })
    ));
    assert!(matches!(
        i.set_coastline(&pts(&[[100.0, 100.0], [900.0, 900.0], [900.0, 100.0], [100.0, 900.0], [100.0, 100.0]])),
        Err(IslandError::SelfIntersecting { .. })
    ));
    assert!(matches!(
        i.set_coastline(&pts(&[[100.0, 100.0], [200.0, 200.0], [100.0, 100.0]])),
        Err(IslandError::DegenerateCoastline { .. })
    ));
    assert!(matches!(i.stroke(&pts(&[[480.0, 480.0], [520.0, 520.0]])), Err(IslandError::StrokeMissesCoast { .. })));
    assert!(matches!(i.stroke(&pts(&[[f64::NAN, 0.0], [1.0, 1.0]])), Err(IslandError::NotFinite { .. })));
    assert!(matches!(i.add_hill(Hill::round(DVec2::splat(500.0), 0.0, 10.0)), Err(IslandError::InvalidHill { .. })));
    assert!(matches!(i.move_hill(3, DVec2::ZERO), Err(IslandError::NoSuchHill { index: 3, count: 0 })));
    assert!(matches!(i.add_filters(f64::INFINITY), Err(IslandError::InvalidParameter { .. })));
    // A cut that removes everything: the whole island lies left of this stroke.
    assert!(matches!(
        i.stroke(&pts(&[[960.0, -10.0], [960.0, 1010.0]])),
        Err(IslandError::StrokeMissesCoast { .. } | IslandError::NoLand)
    ));
    // Failed edits leave the island as it was.
    check_island(&i);
    let fresh = island(65);
    assert_eq!(i.terrain(), fresh.terrain());
    // Replays name the failing operation.
    let ops: Vec<Operation> = serde_json::from_str(
        r#"[{"add_hill": {"center": [500, 500], "radii": [100, 100], "height": 50}},
            {"add_hill": {"center": [500, 500], "radii": [0, 0], "height": 50}}]"#,
    )
    .unwrap();
    let err = island(65).replay(&ops).unwrap_err();
    assert!(matches!(err, IslandError::Operation { index: 1, .. }), "{err}");
    assert!(err.to_string().starts_with("operation 1: hill:"), "{err}");
    assert!(Island::new(grid(2), IslandSettings::default(), 0).is_err());
}

/// A coastline reaching past the grid: distances run to its edges off the grid too (they seed the
/// grid's border), so heights stay finite and follow the distance to the whole coast.
#[test]
fn coast_beyond_the_grid_still_shapes_the_heights() {
    // The grid covers [0, 1000]²; the island is a square [-600, 900] × [-600, 900]: its coast
    // runs on the grid only along x = 900 and y = 900.
    let mut i = island(129);
    i.set_coastline(&pts(&[[-600.0, -600.0], [900.0, -600.0], [900.0, 900.0], [-600.0, 900.0], [-600.0, -600.0]]))
        .unwrap();
    check_island(&i);
    // The tallest point of a fresh island is its centre (150, 150), farthest from the coast.
    let g = *i.grid();
    let (k, _) = i.heights().iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).unwrap();
    let top = g.position(k % g.nx(), k / g.nx());
    assert!(top.distance(DVec2::splat(150.0)) < 12.0, "summit at {top}");
    assert!(i.heights().iter().all(|h| h.is_finite()));
    // A grid entirely inland: every sample is land, heights finite and positive.
    let mut inland = island(65);
    inland
        .set_coastline(&pts(&[
            [-3000.0, -3000.0],
            [4000.0, -3000.0],
            [4000.0, 4000.0],
            [-3000.0, 4000.0],
            [-3000.0, -3000.0],
        ]))
        .unwrap();
    assert!(inland.land().iter().all(|&l| l));
    check_island(&inland);
    assert!(inland.terrain().iter().all(|h| h.is_finite() && *h > 0.0), "finite heights inland");
    // All four sides are off the grid, 3 km away on each: the summit is the grid's centre.
    let g = *inland.grid();
    let (k, _) = inland.heights().iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).unwrap();
    let top = g.position(k % g.nx(), k / g.nx());
    assert!(top.distance(DVec2::splat(500.0)) < 20.0, "inland summit at {top}");
}

/// An island far larger than its grid (edges 2·10⁸ long) costs no more than a normal one: the
/// seeding along each edge is capped, and the grid is all land with finite heights.
#[test]
fn a_coast_astronomically_larger_than_the_grid_is_cheap_and_finite() {
    let mut i = island(65);
    let r = 1e8;
    i.set_coastline(&pts(&[[-r, -r], [r, -r], [r, r], [-r, r], [-r, -r]])).unwrap();
    check_island(&i);
    assert!(i.land().iter().all(|&l| l));
    assert!(i.terrain().iter().all(|h| h.is_finite() && *h > 0.0));
}
