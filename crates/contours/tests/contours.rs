//! Properties of heights, extraction, nesting, smoothing and reconstruction.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::DVec2;
use proptest::prelude::*;
use relief_contours::{
    Contour, ContourSet, ContoursError, Histogram, Interpolation, Ranking, Smoothing, Summit, assign_heights,
    evenly_spaced_levels, extract_dem, extract_tin, reconstruct_interpolated, reconstruct_stairs, smooth_heights,
};
use relief_eden_growth::{Graph, GraphOptions, Growth, Region, RegionTree, Uniform, grow};
use relief_fixtures::star;
use relief_heightfield::{Extent, GridSpec, Heightfield};
use relief_tin::poisson_sampling::Polygon;

struct Terrain {
    graph: Graph,
    growth: Growth,
    heights: relief_contours::Heights,
}

fn terrain(regions: Vec<Region>, seed: u64, particles: usize, histogram: &Histogram) -> Terrain {
    let tree = RegionTree::new(regions).unwrap();
    let graph = Graph::from_regions(&tree, &GraphOptions::particles(particles).with_seed(seed)).unwrap();
    let growth = grow(&graph, &Uniform, seed).unwrap();
    let level_ends: Vec<usize> = (1..=growth.levels()).map(|l| growth.level_range(l).end).collect();
    let ranking =
        Ranking { order: growth.order(), level_ends: &level_ends, level_heights: &graph.level_heights()[1..] };
    let heights = assign_heights(graph.tin().num_points(), &ranking, histogram).unwrap();
    Terrain { graph, growth, heights }
}

/// A height ordered by `f32::total_cmp`, for the priority queue.
#[derive(PartialEq)]
struct Height(f32);

impl Eq for Height {}

impl PartialOrd for Height {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Height {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// Cells whose priority-flood fill rises above them by more than `tol`: endorheic basins.
fn endorheic_cells(hf: &Heightfield, tol: f32) -> usize {
    let (nx, ny) = (hf.nx(), hf.ny());
    let s = hf.samples();
    let mut filled = vec![f32::NAN; s.len()];
    let mut heap = BinaryHeap::new();
    let key = |v: f32| Reverse(Height(v));
    for j in 0..ny {
        for i in 0..nx {
            if i == 0 || j == 0 || i + 1 == nx || j + 1 == ny {
                let k = j * nx + i;
                filled[k] = s[k];
                heap.push((key(s[k]), k));
            }
        }
    }
    while let Some((_, k)) = heap.pop() {
        let (i, j) = (k % nx, k / nx);
        for (di, dj) in [(-1i64, 0i64), (1, 0), (0, -1), (0, 1), (-1, -1), (1, 1), (-1, 1), (1, -1)] {
            let (a, b) = (i as i64 + di, j as i64 + dj);
            if a < 0 || b < 0 || a >= nx as i64 || b >= ny as i64 {
                continue;
            }
            let w = b as usize * nx + a as usize;
            if filled[w].is_nan() {
                filled[w] = s[w].max(filled[k]);
                heap.push((key(filled[w]), w));
            }
        }
    }
    filled.iter().zip(s).filter(|(f, h)| **f > **h + tol).count()
}

fn regions() -> impl Strategy<Value = Vec<Region>> {
    (
        proptest::collection::vec(0.0f64..1.0, 5..20),
        proptest::collection::vec(proptest::collection::vec(0.0f64..1.0, 4..9), 0..3),
    )
        .prop_map(|(coast, inner)| {
            let mut out = vec![Region::new(star(DVec2::ZERO, 1000.0, &coast))];
            for (k, shape) in inner.iter().enumerate() {
                let t = std::f64::consts::TAU * k as f64 / 3.0;
                out.push(Region::new(star(330.0 * DVec2::new(t.cos(), t.sin()), 150.0, shape)));
            }
            out
        })
}

fn histogram() -> impl Strategy<Value = Histogram> {
    proptest::collection::vec(0.0f64..1.0, 2..8).prop_map(|w| {
        let edges = (0..=w.len()).map(|k| 100.0 * k as f64).collect();
        let weights = w.iter().map(|x| x + 0.05).collect();
        Histogram::from_bins(edges, weights).unwrap()
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    #[test]
    fn generated_contours_nest_never_cross_and_match_the_histogram(regs in regions(), seed in any::<u64>(), hist in histogram(), count in 3usize..20) {
        let t = terrain(regs, seed, 2_500, &hist);
        let inside: Vec<f64> = t.growth.order().iter().map(|&v| t.heights.heights[v as usize]).collect();
        // Exact histogram match: quantiles at (i + ½)/N are within ½N of the target CDF.
        prop_assert!(hist.ks_distance(&inside) <= 0.5 / inside.len() as f64 + 1e-9);
        // Heights increase with rank.
        prop_assert!(inside.windows(2).all(|w| w[0] <= w[1]));
        let mut levels = evenly_spaced_levels(hist.min(), hist.max(), count).unwrap();
        levels.push(t.heights.level_boundaries[0]);
        levels.sort_by(f64::total_cmp);
        levels.dedup();
        let set = extract_tin(t.graph.tin(), &t.heights.heights, &levels).unwrap();
        prop_assert!(set.contours().iter().all(|c| c.closed), "every contour of a generated terrain is closed");
        set.check_invariants().map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(set.nests_by_level(), Ok(()));
        // Smoothing keeps every invariant.
        let smooth = set.smoothed(&Smoothing { alpha: 0.8, k: 3, iterations: 5, ..Smoothing::default() }).unwrap();
        smooth.check_invariants().map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(smooth.nests_by_level(), Ok(()));
        // The interpolated reconstruction drains: no endorheic cell. Draining only fixes the
        // cell-scale pits of valleys narrower than a cell, so it touches few cells.
        let grid = GridSpec::from_extent(128, 128, Extent::new(DVec2::splat(-1100.0), DVec2::splat(1100.0))).unwrap();
        let raw = reconstruct_interpolated(&set, &grid, t.heights.outside, &Interpolation { drain: false, ..Interpolation::default() }).unwrap();
        let dem = reconstruct_interpolated(&set, &grid, t.heights.outside, &Interpolation::default()).unwrap();
        prop_assert_eq!(endorheic_cells(&dem, 0.0), 0);
        let changed = dem.samples().iter().zip(raw.samples()).filter(|(a, b)| a != b).count();
        prop_assert!(changed * 50 < grid.len(), "draining changed {} of {} cells", changed, grid.len());
    }
}

#[test]
fn explicit_level_heights_make_input_contours_iso_contours() {
    let coast = Region::new(Polygon::circle(DVec2::ZERO, 1000.0, 64).unwrap()).with_height(0.0);
    let range = Region::new(Polygon::circle(DVec2::new(150.0, 0.0), 500.0, 48).unwrap()).with_height(800.0);
    let hist = Histogram::from_bins(vec![0.0, 500.0, 1000.0, 2000.0], vec![5.0, 3.0, 1.0]).unwrap();
    let t = terrain(vec![coast, range], 3, 5_000, &hist);
    let levels = t.graph.levels();
    for (v, &h) in t.heights.heights.iter().enumerate() {
        match levels[v] {
            0 => assert!(h < 0.0),
            1 => assert!((0.0..800.0).contains(&h), "level-1 node at {h}"),
            _ => assert!(h >= 800.0, "level-2 node at {h}"),
        }
    }
    assert_eq!(t.heights.level_boundaries, vec![0.0, 800.0]);
    let set = extract_tin(t.graph.tin(), &t.heights.heights, &[800.0]).unwrap();
    // The 800 m contour is the discretised range outline: a single closed loop around it.
    assert_eq!(set.len(), 1);
    assert!(set.contours()[0].points.iter().all(|p| (p.distance(DVec2::new(150.0, 0.0)) - 500.0).abs() < 60.0));
}

#[test]
fn heights_reject_bad_rankings_and_levels() {
    let hist = Histogram::uniform(0.0, 10.0).unwrap();
    let r = |order: &'static [u32], ends: &'static [usize], hs: &'static [Option<f64>]| Ranking {
        order,
        level_ends: ends,
        level_heights: hs,
    };
    assert!(assign_heights(3, &r(&[0, 1], &[2], &[None]), &hist).is_ok());
    assert!(matches!(assign_heights(3, &r(&[0, 0], &[2], &[None]), &hist), Err(ContoursError::InvalidRanking { .. })));
    assert!(matches!(assign_heights(3, &r(&[0, 5], &[2], &[None]), &hist), Err(ContoursError::InvalidRanking { .. })));
    assert!(matches!(assign_heights(3, &r(&[0, 1], &[1], &[None]), &hist), Err(ContoursError::InvalidRanking { .. })));
    assert!(matches!(assign_heights(3, &r(&[], &[0], &[None]), &hist), Err(ContoursError::InvalidRanking { .. })));
    assert!(matches!(
        assign_heights(3, &r(&[0, 1], &[1, 2], &[None, Some(20.0)]), &hist),
        Err(ContoursError::InvalidLevelRequest { .. })
    ));
    assert!(matches!(
        assign_heights(3, &r(&[0, 1], &[1, 2], &[Some(5.0), Some(4.0)]), &hist),
        Err(ContoursError::InvalidLevelRequest { .. })
    ));
}

/// A pyramid over a 4 × 4 lattice: apex 3 at the centre node.
fn pyramid() -> (relief_tin::Tin, Vec<f64>) {
    let points: Vec<DVec2> =
        (0..=4).flat_map(|j| (0..=4).map(move |i| DVec2::new(f64::from(i), f64::from(j)))).collect();
    let heights = points.iter().map(|p| 2.0 - (p.x - 2.0).abs().max((p.y - 2.0).abs())).collect();
    (relief_tin::Tin::new(points).unwrap(), heights)
}

#[test]
fn pyramid_contours_are_squares_counter_clockwise_around_the_summit() {
    let (tin, heights) = pyramid();
    let set = extract_tin(&tin, &heights, &[0.5, 1.5]).unwrap();
    set.check_invariants().unwrap();
    assert_eq!(set.len(), 2);
    for c in set.contours() {
        assert!(c.closed && c.is_counter_clockwise());
        let half = 2.0 - c.height;
        // Every vertex lies on the square of half-side `half` around (2, 2).
        assert!(c.points.iter().all(|p| ((p.x - 2.0).abs().max((p.y - 2.0).abs()) - half).abs() < 1e-12));
    }
    let inner = set.contours().iter().position(|c| c.height == 1.5).unwrap();
    let outer = set.contours().iter().position(|c| c.height == 0.5).unwrap();
    assert_eq!(set.parent(inner), Some(outer));
    assert_eq!(set.children(outer).collect::<Vec<_>>(), vec![inner]);
    // A level exactly at a node height (1.0 at eight nodes): still simple, nudged off the nodes.
    let tied = extract_tin(&tin, &heights, &[1.0]).unwrap();
    tied.check_invariants().unwrap();
    assert_eq!(tied.len(), 1);
}

/// A summit node exactly at a level, far from the origin (as with integer DEM histograms): the
/// level wraps it in a loop of sub-millimetre size, which must still run counter-clockwise.
#[test]
fn tiny_loops_around_a_node_at_a_level_keep_their_orientation_far_from_the_origin() {
    let (tin, heights) = pyramid();
    let far: Vec<DVec2> = tin.points().iter().map(|p| *p * 30.0 + DVec2::new(6_000_000.0, 4_000_000.0)).collect();
    let tin = relief_tin::Tin::new(far).unwrap();
    let set = extract_tin(&tin, &heights, &[2.0]).unwrap();
    assert_eq!(set.len(), 1);
    let c = &set.contours()[0];
    assert!(c.closed && c.signed_area() > 0.0 && c.signed_area() < 1e-6, "area {}", c.signed_area());
    assert_eq!(set.nests_by_level(), Ok(()));
}

#[test]
fn pits_run_clockwise_and_stairs_step_down_inside_them() {
    // An inverted pyramid: a pit in the middle of a plateau at 2.
    let (tin, heights) = pyramid();
    let inverted: Vec<f64> = heights.iter().map(|h| 2.0 - h).collect();
    let set = extract_tin(&tin, &inverted, &[0.5, 1.5]).unwrap();
    set.check_invariants().unwrap();
    // The pyramid's border is at 2: the contours close inside, clockwise around the lower ground.
    assert!(set.contours().iter().all(|c| c.closed && !c.is_counter_clockwise()));
    assert!(set.nests_by_level().is_err());
    let grid = GridSpec::from_extent(9, 9, Extent::new(DVec2::ZERO, DVec2::splat(4.0))).unwrap();
    let stairs = reconstruct_stairs(&set, &grid, 2.0).unwrap();
    assert_eq!(stairs.get(4, 4), Some(-0.5), "pit floor below every level: one level step under 0.5");
    assert_eq!(stairs.get(2, 4), Some(0.5), "between the contours (ground at 1.0)");
    assert_eq!(stairs.get(0, 0), Some(2.0));
}

#[test]
fn dem_contours_reach_the_outer_edge_and_end_half_way_to_holes() {
    // A ramp h = x over 20 × 10 with a no-data hole in the middle.
    let grid = GridSpec::new(20, 10, DVec2::ZERO, DVec2::ONE).unwrap();
    let mut dem = Heightfield::from_fn(grid, |p| p.x as f32).unwrap();
    for j in 4..6 {
        for i in 9..11 {
            dem.set(i, j, f32::NAN).unwrap();
        }
    }
    let set = extract_dem(&dem, &[5.25, 9.5]).unwrap();
    set.check_invariants().unwrap();
    let at = |h: f64| set.contours().iter().filter(|c| c.height == h).collect::<Vec<_>>();
    assert_eq!(at(5.25).len(), 1, "a full-height line from edge to edge");
    let c = &at(5.25)[0];
    assert!(!c.closed);
    // Higher ground on the left of the direction of travel: the ramp rises to the east, so lines
    // run south, from the raster's outer edge to the outer edge, half a cell beyond the samples.
    assert_eq!((c.points[0], *c.points.last().unwrap()), (DVec2::new(5.25, 9.5), DVec2::new(5.25, -0.5)));
    // The hole (samples 9 and 10 of rows 4 and 5) cuts the 9.5 line in two, each half ending half
    // a cell short of the missing samples: at y = 3.5 and 5.5. The level lies half-way between
    // samples, at the means the split cells take, which count as above it: the ends sit a hair
    // west of x = 9.5, as GDAL's do.
    let mut ends: Vec<f64> = at(9.5)
        .iter()
        .inspect(|c| assert!(!c.closed && c.points.iter().all(|p| (p.x - 9.5).abs() < 1e-5), "{:?}", c.points))
        .flat_map(|c| [c.points[0].y, c.points.last().unwrap().y])
        .collect();
    ends.sort_by(f64::total_cmp);
    assert_eq!(ends, [-0.5, 3.5, 5.5, 9.5]);
}

#[test]
fn saddles_cut_off_the_south_west_and_north_east_corners_as_gdal_does() {
    // One square whose diagonal corners are high (and then low), all levels alike: GDAL keeps
    // the north-west and south-east corners joined whichever way the saddle goes.
    for (sw_ne, se_nw) in [(1.0, 0.0), (0.0, 1.0)] {
        let grid = GridSpec::new(2, 2, DVec2::ZERO, DVec2::ONE).unwrap();
        let dem = Heightfield::from_samples(grid, vec![sw_ne, se_nw, se_nw, sw_ne]).unwrap();
        let set = extract_dem(&dem, &[0.25, 0.5]).unwrap();
        set.check_invariants().unwrap();
        assert_eq!(set.len(), 4, "two corner cuts per level");
        // Each line stays on one side of the north-west–south-east diagonal x + y = 1.
        for c in set.contours() {
            let south_west = c.points.iter().all(|p| p.x + p.y < 1.0);
            let north_east = c.points.iter().all(|p| p.x + p.y > 1.0);
            assert!(south_west || north_east, "{sw_ne}: {:?}", c.points);
        }
    }
}

#[test]
fn dem_to_contours_to_stairs_reproduces_the_level_sets() {
    // A hill whose border lies below every level, so every contour closes.
    let grid = GridSpec::from_extent(61, 47, Extent::new(DVec2::ZERO, DVec2::new(60.0, 46.0))).unwrap();
    let dem = Heightfield::from_fn(grid, |p| {
        let q = p - DVec2::new(30.0, 23.0);
        (100.0 * (-q.length_squared() / 150.0).exp()
            + 15.0 * (p.x * 0.3).sin() * (p.y * 0.25).cos() * (-q.length_squared() / 300.0).exp()) as f32
    })
    .unwrap();
    let levels = evenly_spaced_levels(5.0, 95.0, 8).unwrap();
    let set = extract_dem(&dem, &levels).unwrap();
    set.check_invariants().unwrap();
    assert!(set.contours().iter().all(|c| c.closed));
    let stairs = reconstruct_stairs(&set, &grid, -1.0).unwrap();
    for (k, (&h, &s)) in dem.samples().iter().zip(stairs.samples()).enumerate() {
        let below = levels.iter().filter(|&&l| f64::from(h) >= l).count();
        let expected = if below == 0 { -1.0 } else { levels[below - 1] as f32 };
        assert_eq!(s, expected, "sample {:?}: height {h}", grid.coords(k));
    }
}

#[test]
fn smoothing_never_lets_close_contours_cross() {
    // Two zig-zag rings 0.05 apart: unconstrained smoothing would pull the jagged outer ring across
    // the inner one.
    let ring = |r: f64, amp: f64| -> Vec<DVec2> {
        (0..200)
            .map(|k| {
                let t = std::f64::consts::TAU * f64::from(k) / 200.0;
                let rr = r + if k % 2 == 0 { amp } else { -amp };
                DVec2::new(rr * t.cos(), rr * t.sin())
            })
            .collect()
    };
    let contours = vec![
        Contour { level: 0, height: 1.0, points: ring(10.0, 0.3), closed: true },
        Contour { level: 1, height: 2.0, points: ring(9.5, 0.0), closed: true },
    ];
    let set = ContourSet::new(vec![1.0, 2.0], contours).unwrap();
    set.check_invariants().unwrap();
    let smooth = set.smoothed(&Smoothing { alpha: 1.0, k: 5, iterations: 20, ..Smoothing::default() }).unwrap();
    smooth.check_invariants().unwrap();
    assert_eq!(smooth.nests_by_level(), Ok(()));
    assert_ne!(smooth.contours()[0].points, set.contours()[0].points, "smoothing moved the vertices");
    assert!(matches!(
        set.smoothed(&Smoothing { alpha: 0.0, k: 1, iterations: 1, ..Smoothing::default() }),
        Err(ContoursError::InvalidSmoothing { .. })
    ));
    assert!(matches!(
        set.smoothed(&Smoothing { alpha: 0.5, k: 0, iterations: 1, ..Smoothing::default() }),
        Err(ContoursError::InvalidSmoothing { .. })
    ));
}

#[test]
fn contour_sets_round_trip_through_serde_and_reject_bad_input() {
    let (tin, heights) = pyramid();
    let set = extract_tin(&tin, &heights, &[0.5, 1.5]).unwrap();
    let json = serde_json::to_string(&set).unwrap();
    let back: ContourSet = serde_json::from_str(&json).unwrap();
    assert_eq!(back, set);
    assert!(matches!(extract_tin(&tin, &heights[1..], &[1.0]), Err(ContoursError::HeightCountMismatch { .. })));
    assert!(matches!(extract_tin(&tin, &heights, &[1.0, 1.0]), Err(ContoursError::InvalidLevels { index: 1 })));
    assert!(matches!(extract_tin(&tin, &heights, &[f64::NAN]), Err(ContoursError::InvalidLevels { index: 0 })));
    let crossing = vec![
        Contour {
            level: 0,
            height: 1.0,
            points: vec![DVec2::ZERO, DVec2::new(2.0, 0.0), DVec2::new(2.0, 2.0), DVec2::new(0.0, 2.0)],
            closed: true,
        },
        Contour {
            level: 1,
            height: 2.0,
            points: vec![DVec2::splat(1.0), DVec2::new(3.0, 1.0), DVec2::new(3.0, 3.0), DVec2::new(1.0, 3.0)],
            closed: true,
        },
    ];
    assert!(ContourSet::new(vec![1.0, 2.0], crossing).unwrap().check_invariants().is_err());
    assert!(matches!(
        reconstruct_stairs(&set, &GridSpec::new(2, 2, DVec2::ZERO, DVec2::ONE).unwrap(), f64::NAN),
        Err(ContoursError::NonFinite { .. })
    ));
}

#[test]
fn interpolated_reconstruction_is_bounded_and_continuous_on_a_cone() {
    // Concentric circles of a cone h = 10 − r: interpolation reproduces the cone closely.
    let circle = |r: f64| {
        (0..400).map(|k| r * DVec2::from_angle(std::f64::consts::TAU * f64::from(k) / 400.0)).collect::<Vec<_>>()
    };
    let contours = (1..=9)
        .map(|k| Contour { level: k - 1, height: f64::from(k), points: circle(10.0 - f64::from(k)), closed: true })
        .collect();
    let set = ContourSet::new((1..=9).map(f64::from).collect(), contours).unwrap();
    let grid = GridSpec::from_extent(201, 201, Extent::new(DVec2::splat(-10.0), DVec2::splat(10.0))).unwrap();
    let dem = reconstruct_interpolated(&set, &grid, 0.0, &Interpolation::default()).unwrap();
    for j in 0..201 {
        for i in 0..201 {
            let p = grid.position(i, j);
            let r = p.length();
            // Between the outermost and innermost circles; inside r = 1 the summit rule applies.
            if (1.0..9.0).contains(&r) {
                let got = f64::from(dem.get(i, j).unwrap());
                assert!((got - (10.0 - r)).abs() < 0.06, "at {p}: {got} vs {}", 10.0 - r);
            }
        }
    }
    let flat =
        reconstruct_interpolated(&set, &grid, 0.0, &Interpolation { summit: Summit::Flat, drain: false }).unwrap();
    assert_eq!(flat.get(100, 100), Some(9.0));
    let dome = dem.get(100, 100).unwrap();
    assert!(dome > 9.0 && dome <= 9.5 + 1e-6, "summit dome at {dome}");
    let surface = |_: DVec2| 100.0;
    let clamped =
        reconstruct_interpolated(&set, &grid, 0.0, &Interpolation { summit: Summit::Surface(&surface), drain: false })
            .unwrap();
    assert_eq!(clamped.get(100, 100), Some(10.0), "surface values are clamped to one level step");
}

/// Even-odd point-in-ring, the plain way.
fn inside_ring(p: DVec2, ring: &[DVec2]) -> bool {
    let mut inside = false;
    for (i, &a) in ring.iter().enumerate() {
        let b = ring[(i + 1) % ring.len()];
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            inside = !inside;
        }
    }
    inside
}

/// A DEM of small integers (ties with the levels, saddles everywhere) with a few no-data samples.
fn rough_dem() -> impl Strategy<Value = Heightfield> {
    (4usize..20, 4usize..20).prop_flat_map(|(nx, ny)| {
        proptest::collection::vec(prop_oneof![9 => (0u8..6).prop_map(f32::from), 1 => Just(f32::NAN)], nx * ny)
            .prop_map(move |v| {
                let grid = GridSpec::new(nx, ny, DVec2::ZERO, DVec2::ONE).unwrap();
                Heightfield::from_samples(grid, v).unwrap()
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Raster contours are marching squares' lines: vertices on the edges between samples, except
    /// in squares with a missing corner (no-data, or outside the raster), which are split into
    /// quarters; never crossing, with the nesting tree a brute-force search finds.
    #[test]
    fn dem_contours_have_vertices_on_cell_edges_never_cross_and_nest(dem in rough_dem()) {
        let set = extract_dem(&dem, &[0.5, 1.5, 2.0, 2.5, 3.5, 4.5]).unwrap();
        set.check_invariants().map_err(|e| TestCaseError::fail(e.to_string()))?;
        let on_grid_line = |x: f64| (x - x.round()).abs() < 1e-9;
        let missing = |i: f64, j: f64| dem.get(i as usize, j as usize).is_none_or(f32::is_nan) || i < 0.0 || j < 0.0;
        // Whether a square holding p has a corner without data.
        let split = |p: DVec2| {
            let (i0, j0) = ((p.x - 1e-6).floor(), (p.y - 1e-6).floor());
            let (i1, j1) = ((p.x + 1e-6).floor(), (p.y + 1e-6).floor());
            [(i0, j0), (i1, j1), (i0, j1), (i1, j0)]
                .iter()
                .any(|&(i, j)| [(i, j), (i + 1.0, j), (i, j + 1.0), (i + 1.0, j + 1.0)].iter().any(|&(a, b)| missing(a, b)))
        };
        let (w, h) = (dem.nx() as f64 - 0.5, dem.ny() as f64 - 0.5);
        for c in set.contours() {
            for &p in &c.points {
                let inside = |x: f64, max: f64| x >= -0.5 - 1e-9 && x <= max + 1e-9;
                prop_assert!(inside(p.x, w) && inside(p.y, h), "outside the outer edge: {:?}", p);
                prop_assert!(on_grid_line(p.x) || on_grid_line(p.y) || split(p), "inside a whole square: {:?}", p);
            }
        }
        let contours = set.contours();
        for (k, c) in contours.iter().enumerate() {
            let expected = c.closed.then(|| {
                (0..contours.len())
                    .filter(|&j| j != k && contours[j].closed && inside_ring(c.points[0], &contours[j].points))
                    .min_by(|&a, &b| contours[a].signed_area().abs().total_cmp(&contours[b].signed_area().abs()))
            }).flatten();
            prop_assert_eq!(set.parent(k), expected, "contour {}", k);
        }
    }
}

#[test]
fn lines_cut_open_by_no_data_have_no_parent_even_inside_a_closed_ring() {
    // A cone over 21 × 21 with a 3 × 3 no-data block on its summit: the 2 m contour closes around
    // everything, the 7.9 m one (radius 2.1) is cut open where it meets the hole, whose edge lies
    // half-way to the missing samples.
    let grid = GridSpec::new(21, 21, DVec2::ZERO, DVec2::ONE).unwrap();
    let mut dem = Heightfield::from_fn(grid, |p| (10.0 - p.distance(DVec2::splat(10.0))) as f32).unwrap();
    for j in 9..12 {
        for i in 9..12 {
            dem.set(i, j, f32::NAN).unwrap();
        }
    }
    let set = extract_dem(&dem, &[2.0, 7.9]).unwrap();
    set.check_invariants().unwrap();
    let open: Vec<usize> = (0..set.len()).filter(|&k| !set.contours()[k].closed).collect();
    assert!(!open.is_empty(), "the hole cuts the upper contour open");
    let ring = (0..set.len()).find(|&k| set.contours()[k].closed && set.contours()[k].height == 2.0).unwrap();
    for k in open {
        assert_eq!(set.parent(k), None, "open contour {k}");
    }
    assert_eq!(set.children(ring).count(), 0, "open lines are nobody's children");
}

#[test]
fn the_smallest_dems_have_their_contours_and_thinner_ones_none() {
    let ramp = |nx, ny| {
        let grid = GridSpec::new(nx, ny, DVec2::ZERO, DVec2::ONE).unwrap();
        Heightfield::from_fn(grid, |p| (p.x + p.y) as f32).unwrap()
    };
    // One square: the 0.25 line cuts its south-west corner, carried on to the outer edges.
    let set = extract_dem(&ramp(2, 2), &[0.25]).unwrap();
    assert_eq!(set.len(), 1);
    let points = [DVec2::new(-0.5, 0.25), DVec2::new(0.0, 0.25), DVec2::new(0.25, 0.0), DVec2::new(0.25, -0.5)];
    assert_eq!(set.contours()[0].points, points);
    assert_eq!(extract_dem(&ramp(2, 5), &[2.5]).unwrap().len(), 1);
    assert_eq!(extract_dem(&ramp(5, 2), &[2.5]).unwrap().len(), 1);
    // A single row or column has no square of four samples, but its half squares carry lines
    // across it, as GDAL draws them; a single sample has none.
    for (nx, ny) in [(1, 5), (5, 1)] {
        let set = extract_dem(&ramp(nx, ny), &[2.5]).unwrap();
        set.check_invariants().unwrap();
        assert_eq!(set.len(), 1);
        assert_eq!(set.contours()[0].length(), 1.0, "across the row, from outer edge to outer edge");
    }
    assert!(extract_dem(&ramp(1, 1), &[-1.0, 0.0, 1.0]).unwrap().is_empty());
}

#[test]
fn tall_dems_give_the_same_closed_rings_for_any_thread_count() {
    // 700 rows: rows are traced in bands, in parallel batches, then joined. A hill spanning them
    // all must still give whole closed rings, and the same bytes with 1 thread as with 3.
    let grid = GridSpec::new(40, 700, DVec2::ZERO, DVec2::new(1.0, 0.1)).unwrap();
    let dem = Heightfield::from_fn(grid, |p| {
        let q = (p - DVec2::new(20.0, 35.0)) / DVec2::new(18.0, 33.0);
        (100.0 * (1.0 - q.length_squared()) + 3.0 * (p.x * 1.3).sin() * (p.y * 0.7).cos()) as f32
    })
    .unwrap();
    let levels = evenly_spaced_levels(5.0, 95.0, 10).unwrap();
    let run = || extract_dem(&dem, &levels).unwrap();
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap().install(run);
    let three = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap().install(run);
    assert_eq!(one, three);
    one.check_invariants().unwrap();
    let lowest: Vec<_> = one.contours().iter().filter(|c| c.level == 0).collect();
    assert_eq!(lowest.len(), 1, "one ring at the lowest level");
    assert!(lowest[0].closed && lowest[0].is_counter_clockwise());
    let bounds = lowest[0].bounds();
    assert!(bounds.min.y < 5.0 && bounds.max.y > 65.0, "the ring spans the bands: {bounds:?}");
}

#[test]
fn a_smoothing_brush_moves_only_what_lies_under_it() {
    // A jagged ring of radius 10; the brush covers its east side only.
    let ring: Vec<DVec2> = (0..200)
        .map(|k| {
            let t = std::f64::consts::TAU * f64::from(k) / 200.0;
            let r = 10.0 + if k % 2 == 0 { 0.3 } else { -0.3 };
            DVec2::new(r * t.cos(), r * t.sin())
        })
        .collect();
    let set = ContourSet::new(vec![1.0], vec![Contour { level: 0, height: 1.0, points: ring.clone(), closed: true }])
        .unwrap();
    let brush = Smoothing { centre: Some(DVec2::new(10.0, 0.0)), radius: Some(6.0), ..Smoothing::default() };
    let smooth = set.smoothed(&brush).unwrap();
    smooth.check_invariants().unwrap();
    let moved =
        |p: DVec2| smooth.contours()[0].points.iter().zip(&ring).find(|(_, r)| **r == p).map(|(q, r)| q.distance(*r));
    let (mut inside, mut outside) = (0, 0);
    for &p in &ring {
        let d = p.distance(DVec2::new(10.0, 0.0));
        let m = moved(p).unwrap();
        if d > 6.5 {
            // Beyond the brush (plus the neighbours' reach) nothing moves.
            assert_eq!(m, 0.0, "{p} moved by {m}");
            outside += 1;
        } else if d < 3.0 {
            assert!(m > 0.1, "{p} under the brush moved only {m}");
            inside += 1;
        }
    }
    assert!(inside > 10 && outside > 100, "{inside} {outside}");
    // The brush's weight: 1 at the centre, (1 − ¼)² half-way, 0 at the rim.
    assert_eq!(brush.weight(DVec2::new(10.0, 0.0)), 1.0);
    assert!((brush.weight(DVec2::new(13.0, 0.0)) - 0.5625).abs() < 1e-12);
    assert_eq!(brush.weight(DVec2::new(16.0, 0.0)), 0.0);
    // A centre without a radius, or a radius ≤ 0, is refused.
    for bad in [
        Smoothing { centre: Some(DVec2::ZERO), ..Smoothing::default() },
        Smoothing { radius: Some(3.0), ..Smoothing::default() },
        Smoothing { centre: Some(DVec2::ZERO), radius: Some(0.0), ..Smoothing::default() },
    ] {
        assert!(matches!(set.smoothed(&bad), Err(ContoursError::InvalidSmoothing { .. })), "{bad:?}");
    }
}

#[test]
fn node_heights_smooth_within_their_bounds() {
    // A spiky TIN surface: heights alternate 0 / 10 on a grid of nodes.
    let points: Vec<DVec2> =
        (0..400).map(|k| DVec2::new(f64::from(k % 20) + 0.01 * f64::from(k / 20 % 3), f64::from(k / 20))).collect();
    let tin = relief_tin::Tin::new(points).unwrap();
    let spiky: Vec<f64> = (0..400).map(|k| if (k % 20 + k / 20) % 2 == 0 { 10.0 } else { 0.0 }).collect();
    let roughness = |h: &[f64]| -> f64 {
        (0..h.len() as u32)
            .map(|v| tin.neighbors(v).iter().map(|&w| (h[v as usize] - h[w as usize]).abs()).sum::<f64>())
            .sum()
    };
    let mut h = spiky.clone();
    smooth_heights(&tin, &mut h, &Smoothing::default(), |_| (2.0, 9.0)).unwrap();
    assert!(roughness(&h) < 0.2 * roughness(&spiky), "{} vs {}", roughness(&h), roughness(&spiky));
    assert!(h.iter().all(|&v| (2.0..=9.0).contains(&v)), "bounds hold");
    // With a brush, nodes beyond it keep their heights exactly.
    let mut h = spiky.clone();
    let brush = Smoothing { centre: Some(DVec2::new(5.0, 5.0)), radius: Some(4.0), ..Smoothing::default() };
    smooth_heights(&tin, &mut h, &brush, |_| (f64::NEG_INFINITY, f64::INFINITY)).unwrap();
    for (k, p) in tin.points().iter().enumerate() {
        if p.distance(DVec2::new(5.0, 5.0)) >= 4.0 {
            assert_eq!(h[k], spiky[k]);
        }
    }
    assert_ne!(h, spiky);
}

/// A DEM of small integers (ties with the levels, saddles everywhere), no no-data.
fn full_dem() -> impl Strategy<Value = Heightfield> {
    (3usize..20, 3usize..20).prop_flat_map(|(nx, ny)| {
        proptest::collection::vec((0u8..6).prop_map(f32::from), nx * ny).prop_map(move |v| {
            let grid = GridSpec::new(nx, ny, DVec2::ZERO, DVec2::ONE).unwrap();
            Heightfield::from_samples(grid, v).unwrap()
        })
    })
}

/// The rectangle a DEM's contours reach: its samples' extent and half a cell.
fn outer_edge(dem: &Heightfield) -> relief_tin::poisson_sampling::Rect {
    let e = dem.grid().extent();
    let half = 0.5 * dem.grid().cell_size();
    relief_tin::poisson_sampling::Rect::new(e.min - half, e.max + half)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Closing a DEM's contours along its border gives closed, counter-clockwise rings around
    /// higher ground (clockwise around pits) that never touch: each sample above a level lies in
    /// an odd number of that level's rings... exactly: inside one more raised ring than pit ring.
    #[test]
    fn contours_closed_at_the_border_nest_and_enclose_the_higher_ground(dem in full_dem()) {
        let levels = [0.5, 1.5, 2.0, 2.5, 3.5, 4.5];
        let set = extract_dem(&dem, &levels).unwrap();
        let border_min = (0..dem.nx() * dem.ny())
            .filter(|k| { let (i, j) = (k % dem.nx(), k / dem.nx()); i == 0 || j == 0 || i + 1 == dem.nx() || j + 1 == dem.ny() })
            .map(|k| f64::from(dem.samples()[k]))
            .fold(f64::INFINITY, f64::min);
        let closed = set.closed_at_border(outer_edge(&dem), Some(border_min)).unwrap();
        closed.check_invariants().map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert!(closed.contours().iter().all(|c| c.closed));
        for (l, &h) in levels.iter().enumerate() {
            for j in 0..dem.ny() {
                for i in 0..dem.nx() {
                    let p = dem.grid().position(i, j);
                    let z = f64::from(dem.get(i, j).unwrap());
                    // Winding: raised rings count +1, pits −1; a sample on the level counts above.
                    let winding: i32 = closed
                        .contours()
                        .iter()
                        .filter(|c| c.level as usize == l && inside_ring(p, &c.points))
                        .map(|c| if c.is_counter_clockwise() { 1 } else { -1 })
                        .sum();
                    prop_assert_eq!(winding, i32::from(z >= h), "sample ({}, {}) at {} against level {}", i, j, z, h);
                }
            }
        }
    }
}

#[test]
fn closing_a_tilted_plane_along_its_border() {
    // h = x over 0..=9: every level's contour is a vertical line cut at the bottom and top edges.
    let grid = GridSpec::new(10, 6, DVec2::ZERO, DVec2::ONE).unwrap();
    let dem = Heightfield::from_fn(grid, |p| p.x as f32).unwrap();
    let set = extract_dem(&dem, &[-1.0, 2.5, 6.5]).unwrap();
    assert!(set.contours().iter().all(|c| !c.closed));
    let closed = set.closed_at_border(outer_edge(&dem), Some(0.0)).unwrap();
    closed.check_invariants().unwrap();
    assert_eq!(closed.len(), 3);
    for c in closed.contours() {
        assert!(c.is_counter_clockwise(), "{} m: higher ground inside", c.height);
        // The ring spans from its level eastward to just beyond the east edge.
        let b = c.bounds();
        if c.height > 0.0 {
            assert!((b.min.x - c.height).abs() < 1e-5, "{} m ring starts at x = {}", c.height, b.min.x);
        }
        assert!(b.max.x > 9.5 && b.max.x < 9.6, "{}", b.max.x);
    }
    // The level under the whole border is the rectangle itself, farthest out.
    let outer = closed.contours().iter().find(|c| c.height == -1.0).unwrap();
    assert_eq!(outer.points.len(), 4);
    assert!(outer.bounds().min.x < closed.contours()[1].bounds().min.x.min(-0.5));
    // An open line that ends inside the map cannot be closed along the border.
    let cut = ContourSet::new(
        vec![1.0],
        vec![Contour {
            level: 0,
            height: 1.0,
            points: vec![DVec2::new(1.0, -0.5), DVec2::new(1.0, 3.0)],
            closed: false,
        }],
    )
    .unwrap();
    let err = cut.closed_at_border(outer_edge(&dem), None).unwrap_err();
    assert!(err.to_string().contains("inside the map"), "{err}");
}
