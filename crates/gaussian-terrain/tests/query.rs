//! Continuous queries: the elevations of the rasterizer and of the exact evaluation (to f32
//! rounding and the tail tolerance), analytic gradients and normals, batched = one by one for
//! any thread count, and far from the origin.

use glam::DVec2;
use relief_fixtures::random_terrain;
use relief_gaussian_terrain::{
    DetailLayer, DetailSource, Gaussian, RasterOptions, Sample, VectorTerrain, rasterize, rasterize_exact,
};
use relief_heightfield::{Extent, GridSpec};

fn grid(n: usize, lo: DVec2, size: f64) -> GridSpec {
    GridSpec::from_extent(n, n, Extent::new(lo, lo + DVec2::splat(size))).unwrap()
}

fn grid_points(g: &GridSpec) -> Vec<DVec2> {
    (0..g.len()).map(|k| g.position(g.coords(k).0, g.coords(k).1)).collect()
}

/// A seeded stream of uniform numbers in [0, 1) (a 64-bit LCG's top 53 bits).
fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn relief(terrain: &VectorTerrain) -> f64 {
    terrain.primitives.iter().map(|g| g.amplitude.abs()).sum::<f64>()
}

#[test]
fn elevations_match_the_rasterizer_at_its_samples() {
    let terrain = random_terrain(2_000, 1000.0, 12.0, 3);
    let g = grid(97, DVec2::ZERO, 1000.0);
    let raster = rasterize(&terrain, &g, &RasterOptions::default()).unwrap();
    let query = terrain.query().unwrap();
    let heights = query.elevations(&grid_points(&g));
    let scale = f64::from(raster.min_max().map_or(1.0, |(a, b)| b - a));
    let biggest = terrain.primitives.iter().map(|g| g.amplitude.abs()).fold(0.0, f64::max);
    let diffs: Vec<f64> = heights.iter().zip(raster.samples()).map(|(h, r)| (h - f64::from(*r)).abs()).collect();
    // A sample on the edge of a support may be in one truncation and not the other (a step of
    // at most tolerance·|a|); elsewhere they agree to f32 rounding.
    let worst = diffs.iter().copied().fold(0.0, f64::max);
    assert!(worst < 1e-3 * biggest + 1e-5 * scale, "worst difference {worst} over a relief of {scale}");
    let close = diffs.iter().filter(|d| **d < 1e-5 * scale).count();
    assert!(close as f64 > 0.99 * diffs.len() as f64, "only {close} of {} samples agree to f32 rounding", diffs.len());
    // And with the untruncated reference, to within the tail tolerance of the primitives there.
    let exact = rasterize_exact(&terrain, &grid(17, DVec2::ZERO, 1000.0)).unwrap();
    for (k, p) in grid_points(&grid(17, DVec2::ZERO, 1000.0)).into_iter().enumerate() {
        let bound = 1e-3 * relief(&terrain) + 1e-3;
        assert!((query.elevation(p) - f64::from(exact.samples()[k])).abs() < bound);
    }
}

#[test]
fn gradients_are_exact() {
    // One primitive of each kind; at p = c + σx·e (its own x axis) d = 1 and
    // ∇g = −g·(β/2)·(x·u) with u = e/σx, x = 1: a closed form to check against.
    for beta in [2.0, 1.3, 3.5] {
        let theta: f64 = 0.6;
        let g = Gaussian { center: [10.0, -20.0], sigma: [40.0, 15.0], theta, amplitude: 250.0, beta };
        let query = VectorTerrain::new(vec![g]).query().unwrap();
        let e = DVec2::from_angle(theta);
        let p = DVec2::from(g.center) + e * 40.0;
        let value = 250.0 * (-0.5f64).exp();
        let want = -value * (beta / 2.0) * e / 40.0;
        let s = query.sample(p);
        // f32 arithmetic per support, like the rasterizer: a relative 10⁻⁶.
        assert!((s.elevation - value).abs() < 1e-6 * value, "β {beta}: {} vs {value}", s.elevation);
        assert!((s.gradient - want).length() < 1e-6 * want.length(), "β {beta}: {:?} vs {want:?}", s.gradient);
        let n = s.normal();
        let expect = glam::DVec3::new(-want.x, -want.y, 1.0).normalize();
        assert!((n - expect).length() < 1e-6 && (n.length() - 1.0).abs() < 1e-12);
        assert_eq!(query.normal(p), n);
    }
    // A sum of many: the gradient is the derivative of the elevation (central differences).
    let terrain = random_terrain(500, 1000.0, 10.0, 9);
    let query = terrain.query().unwrap();
    for k in 0..200 {
        let p = DVec2::new(f64::from(k * 37 % 1000), f64::from(k * 91 % 1000)) + DVec2::splat(0.37);
        let s = query.sample(p);
        // Central differences of each primitive inside its support, in f64.
        let h = 1e-4;
        let fd: DVec2 = terrain
            .primitives
            .iter()
            .filter(|g| g.distance_squared(p) <= g.support_radius(1e-3).powi(2))
            .map(|g| {
                let (dx, dy) = (DVec2::X * h, DVec2::Y * h);
                DVec2::new(g.value(p + dx) - g.value(p - dx), g.value(p + dy) - g.value(p - dy)) / (2.0 * h)
            })
            .sum();
        assert!((s.gradient - fd).length() < 1e-5 * (1.0 + fd.length()), "at {p}: {:?} vs {fd:?}", s.gradient);
        assert_eq!(s.elevation, query.elevation(p));
    }
}

#[test]
fn batched_queries_are_the_single_ones_for_any_thread_count() {
    let terrain = random_terrain(3_000, 1000.0, 16.0, 5);
    let query = terrain.query().unwrap();
    let points = grid_points(&grid(71, DVec2::splat(-50.0), 1100.0));
    let single: Vec<f64> = points.iter().map(|&p| query.elevation(p)).collect();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| (query.elevations(&points), query.samples(&points)))
    };
    let (one, one_samples) = run(1);
    let (four, four_samples) = run(4);
    assert_eq!(one, single);
    assert_eq!(four, single);
    assert_eq!(one_samples, four_samples);
    assert!(one_samples.iter().zip(&single).all(|(s, h)| s.elevation == *h));
    assert!(single.iter().any(|h| *h != 0.0));
    // Grid rows with a point that is not finite: the others as before.
    let mut holed = points.clone();
    holed[100] = DVec2::NAN;
    let elevations = query.elevations(&holed);
    assert!(elevations[100].is_nan());
    assert!(elevations.iter().zip(&single).enumerate().all(|(k, (a, b))| k == 100 || a == b));
}

/// Points in another order than rows of growing y: a grid from its top row down (image order),
/// a profile along a path that runs east and south, and two blocks each in row order, the second
/// lower, meeting where the parallel order check splits its work (at point 8 192).
#[test]
fn batches_out_of_row_order_are_the_single_queries() {
    let terrain = random_terrain(3_000, 1000.0, 16.0, 5);
    let query = terrain.query().unwrap();
    let rows = |ys: std::ops::Range<i32>, width: usize| -> Vec<DVec2> {
        ys.flat_map(|j| (0..width).map(move |i| DVec2::new(i as f64 * 990.0 / width as f64, f64::from(j)))).collect()
    };
    let mut top_down = rows(0..80, 100);
    top_down.reverse();
    top_down.chunks_mut(100).for_each(<[DVec2]>::reverse);
    let mut blocks = rows(600..682, 100);
    blocks.truncate(8_192);
    blocks.extend(rows(100..150, 100));
    let profile: Vec<DVec2> =
        (0..5_000).map(|k| DVec2::new(f64::from(k) * 0.19, 990.0 - f64::from(k) * 0.17)).collect();
    for points in [top_down, profile, blocks] {
        let single: Vec<f64> = points.iter().map(|&p| query.elevation(p)).collect();
        assert_eq!(query.elevations(&points), single);
        assert!(single.iter().any(|h| *h != 0.0));
    }
}

#[test]
fn far_from_the_origin_and_outside_every_support() {
    // A terrain in UTM-like coordinates: f32 boxes relative to the terrain, so nothing is culled.
    let offset = DVec2::new(652_000.0, 4_983_000.0);
    let mut terrain = random_terrain(800, 1000.0, 10.0, 11);
    for g in &mut terrain.primitives {
        g.center = (DVec2::from(g.center) + offset).to_array();
    }
    terrain.base = 120.0;
    let query = terrain.query().unwrap();
    let g = grid(23, offset, 1000.0);
    let exact = rasterize_exact(&terrain, &g).unwrap();
    for (k, p) in grid_points(&g).into_iter().enumerate() {
        let bound = 1e-3 * relief(&terrain) + 1e-3;
        assert!((query.elevation(p) - f64::from(exact.samples()[k])).abs() < bound, "at {p}");
    }
    assert_eq!(query.elevation(offset + DVec2::splat(1e5)), 120.0);
    // Beyond the query lattice's range, still the base; a NaN point gives NaN.
    let far = [DVec2::splat(1e15), DVec2::new(f64::NAN, 0.0), offset + DVec2::splat(500.0)];
    let batch = query.elevations(&far);
    assert_eq!(batch[0], 120.0);
    assert!(batch[1].is_nan() && query.elevation(far[1]).is_nan());
    assert_eq!(query.elevation(far[0]), 120.0);
    assert_eq!(batch[2], query.elevation(far[2]));
    // A row in row order that ends beyond the lattice: the points in range are still a batch.
    let mut row: Vec<DVec2> = (0..50).map(|i| offset + DVec2::new(f64::from(i) * 20.0, 500.0)).collect();
    row.push(DVec2::new(1e15, offset.y + 500.0));
    let single: Vec<f64> = row.iter().map(|&p| query.elevation(p)).collect();
    assert_eq!(query.elevations(&row), single);
    assert!(single[50] == 120.0 && single.iter().any(|h| *h != 120.0));
    let empty = VectorTerrain { base: -3.0, ..VectorTerrain::default() }.query().unwrap();
    assert!(empty.is_empty());
    assert_eq!(empty.sample(DVec2::new(1.0, 2.0)).elevation, -3.0);
    assert_eq!(empty.normal(DVec2::ZERO), glam::DVec3::Z);
}

#[test]
fn detail_layers_are_queried_too() {
    let mut terrain = VectorTerrain::new(vec![Gaussian::round(DVec2::splat(500.0), 200.0, 300.0)]);
    let fbm = relief_heightfield::noise::Fbm { octaves: 3, frequency: 0.02, seed: 4, ..Default::default() };
    let source =
        DetailSource::Noise { amplitude: 10.0, fbm, modulation: relief_gaussian_terrain::Modulation::default() };
    terrain.details.push(DetailLayer::poisson((DVec2::ZERO, DVec2::splat(1000.0)), 20.0, 1, 100_000, source).unwrap());
    let query = terrain.query().unwrap();
    assert_eq!(query.len(), 1 + terrain.details[0].centers.len());
    let mut moved = 0;
    for k in 0..100 {
        let p = DVec2::new(f64::from(k * 53 % 1000), f64::from(k * 29 % 1000)) + DVec2::splat(0.5);
        let want = terrain.height_at(p);
        let got = query.elevation(p);
        // Within the truncation of the falloffs (each at most 10⁻³ of the 10 m detail amplitude).
        assert!((got - want).abs() < 0.05, "at {p}: {got} vs {want}");
        let plain = Gaussian::round(DVec2::splat(500.0), 200.0, 300.0).value(p);
        moved += usize::from((got - plain).abs() > 0.5);
        let s = query.sample(p);
        let h = 1e-2;
        let fd = DVec2::new(
            terrain.height_at(p + DVec2::X * h) - terrain.height_at(p - DVec2::X * h),
            terrain.height_at(p + DVec2::Y * h) - terrain.height_at(p - DVec2::Y * h),
        ) / (2.0 * h);
        assert!((s.gradient - fd).length() < 2e-2 * (1.0 + fd.length()), "at {p}: {:?} vs {fd:?}", s.gradient);
    }
    assert!(moved > 30, "the detail layer changed only {moved} of 100 points");
    // Modulated by the ground's elevation: the query sees the same ground as the exact sum.
    if let DetailSource::Noise { modulation, .. } = &mut terrain.details[0].source {
        modulation.elevation = Some([50.0, 250.0]);
    }
    let query = terrain.query().unwrap();
    for k in 0..100 {
        let p = DVec2::new(f64::from(k * 53 % 1000), f64::from(k * 29 % 1000)) + DVec2::splat(0.5);
        assert!((query.elevation(p) - terrain.height_at(p)).abs() < 0.05, "at {p}");
    }
}

#[test]
fn bad_tolerances_and_terrains_are_refused() {
    let terrain = VectorTerrain::new(vec![Gaussian::round(DVec2::ZERO, 1.0, 1.0)]);
    assert!(terrain.query_with(0.0).is_err());
    assert!(terrain.query_with(1.0).is_err());
    let mut bad = terrain.clone();
    bad.primitives[0].sigma[0] = -1.0;
    assert!(bad.query().is_err());
}

/// A floor raises the base plus the primitives to it, before the details, in the rasterizer,
/// the exact evaluation and the queries alike, with a flat gradient where it holds; JSON keeps it.
#[test]
fn the_floor_flattens_what_falls_below_it() {
    let terrain = VectorTerrain {
        primitives: vec![
            Gaussian::round(DVec2::new(300.0, 500.0), 120.0, 80.0),
            Gaussian::round(DVec2::new(700.0, 500.0), 120.0, -60.0),
        ],
        base: 10.0,
        floor: Some(-20.0),
        ..VectorTerrain::default()
    };
    let unfloored = VectorTerrain { floor: None, ..terrain.clone() };
    let g = grid(65, DVec2::ZERO, 1000.0);
    let raster = rasterize(&terrain, &g, &RasterOptions::default()).unwrap();
    let plain = rasterize(&unfloored, &g, &RasterOptions::default()).unwrap();
    let exact = rasterize_exact(&terrain, &g).unwrap();
    let query = terrain.query().unwrap();
    let points = grid_points(&g);
    let samples = query.samples(&points);
    let mut raised = 0;
    for (k, p) in points.iter().enumerate() {
        let (h, below) = (raster.samples()[k], plain.samples()[k]);
        assert_eq!(h, below.max(-20.0), "raster at {p}");
        assert!((f64::from(exact.samples()[k]) - f64::from(h)).abs() < 0.1, "exact at {p}");
        assert!((samples[k].elevation - f64::from(h)).abs() < 0.1, "query at {p}");
        if below < -20.0 {
            raised += 1;
            assert_eq!(samples[k].elevation, -20.0);
            assert_eq!(samples[k].gradient, DVec2::ZERO, "the floor is flat at {p}");
        } else if below > -19.0
            && p.distance(DVec2::new(300.0, 500.0)).min(p.distance(DVec2::new(700.0, 500.0))) < 250.0
        {
            assert_ne!(samples[k].gradient, DVec2::ZERO, "slope kept above the floor at {p}");
        }
    }
    // The hollow reaches 10 − 60 = −50 at its centre: well below the floor over a wide disc.
    assert!(raised > 40, "{raised} samples raised");
    assert_eq!(terrain.height_at(DVec2::new(700.0, 500.0)), -20.0);
    assert!((terrain.height_at(DVec2::new(300.0, 500.0)) - 90.0).abs() < 0.5);
    // Far away the base is above the floor: the base; a floor above the base wins.
    assert_eq!(query.elevation(DVec2::splat(1e12)), 10.0);
    let high = VectorTerrain { floor: Some(15.0), ..terrain.clone() };
    assert_eq!(high.query().unwrap().elevation(DVec2::splat(1e12)), 15.0);
    let json = serde_json::to_string(&terrain).unwrap();
    assert!(json.contains("\"floor\":-20.0"), "{json}");
    let back: VectorTerrain = serde_json::from_str(&json).unwrap();
    assert_eq!(back, terrain);
    assert!(!serde_json::to_string(&unfloored).unwrap().contains("floor"));
    let nan = VectorTerrain { floor: Some(f64::NAN), ..terrain };
    assert!(nan.validate().is_err());
}

/// Long thin supports at an angle to the lattice are summed wherever they reach. Growing the
/// support ellipse by a cell's half-diagonal, the test this crate first used, misses slivers of
/// them (up to 0.8 % of the amplitude off here); the box-in-the-support's-frame test does not.
#[test]
fn elongated_supports_are_never_cut() {
    for (sx, sy, theta) in [(30.0, 1.0, 0.785), (20.0, 2.0, 0.3), (40.0, 0.5, 2.0)] {
        let mut primitives = vec![Gaussian { center: [0.0, 0.0], sigma: [sx, sy], theta, amplitude: 100.0, beta: 2.0 }];
        // Small round neighbours set the lattice's cell size.
        primitives.extend((0..20).map(|k| Gaussian::round(DVec2::new(-150.0 + 15.0 * f64::from(k), 140.0), 2.0, 1.0)));
        let terrain = VectorTerrain::new(primitives);
        let g = grid(301, DVec2::splat(-150.0), 300.0);
        let raster = rasterize(&terrain, &g, &RasterOptions::default()).unwrap();
        let heights = terrain.query().unwrap().elevations(&grid_points(&g));
        let worst = heights.iter().zip(raster.samples()).map(|(h, r)| (h - f64::from(*r)).abs()).fold(0.0, f64::max);
        assert!(worst < 0.01, "σ ({sx}, {sy}), θ {theta}: {worst} off the rasterizer");
    }
}

/// `elevations` skips the gradients, except the Gaussians' when a detail layer follows the
/// slope: its values are still the exact sum's and those of `samples`, bit for bit.
#[test]
fn elevations_without_gradients_still_see_the_slope() {
    let mut terrain = VectorTerrain::new(vec![Gaussian::round(DVec2::splat(500.0), 200.0, 300.0)]);
    let fbm = relief_heightfield::noise::Fbm { octaves: 3, frequency: 0.02, seed: 4, ..Default::default() };
    let modulation = relief_gaussian_terrain::Modulation { elevation: None, slope: Some([0.5, 1.0]) };
    let source = DetailSource::Noise { amplitude: 10.0, fbm, modulation };
    terrain.details.push(DetailLayer::poisson((DVec2::ZERO, DVec2::splat(1000.0)), 20.0, 1, 100_000, source).unwrap());
    let query = terrain.query().unwrap();
    let points: Vec<DVec2> =
        (0..200).map(|k| DVec2::new(f64::from(k * 53 % 1000), f64::from(k * 29 % 1000)) + 0.5).collect();
    let (heights, samples) = (query.elevations(&points), query.samples(&points));
    let mut steep = 0;
    for ((&p, h), s) in points.iter().zip(&heights).zip(&samples) {
        assert_eq!(h.to_bits(), s.elevation.to_bits(), "at {p}");
        assert_eq!(h.to_bits(), query.elevation(p).to_bits(), "at {p}");
        assert!((h - terrain.height_at(p)).abs() < 0.05, "at {p}: {h} vs {}", terrain.height_at(p));
        steep += usize::from(s.gradient.length() > 0.75);
    }
    assert!(steep > 10, "only {steep} points where the slope ramp is above half");
}

/// Scattered points in no order (strips of several y values, sorted inside by x, cut where a
/// stretch crosses into another anchor square), with repeats, NaN and a far point: every batch
/// gives the single queries' bits, and the values are the terrain's.
#[test]
fn scattered_points_in_any_order_are_the_single_queries() {
    let terrain = random_terrain(3_000, 1000.0, 16.0, 9);
    let query = terrain.query().unwrap();
    let mut next = uniform(0x9e37_79b9_7f4a_7c15);
    let mut points: Vec<DVec2> =
        (0..20_000).map(|_| DVec2::new(next() * 1100.0 - 50.0, next() * 1100.0 - 50.0)).collect();
    points.extend_from_within(..50);
    points.push(DVec2::NAN);
    points.push(DVec2::new(1e12, -3.0));
    let single: Vec<Sample> = points.iter().map(|&p| query.sample(p)).collect();
    let batch = query.samples(&points);
    let elevations = query.elevations(&points);
    for (k, (s, b)) in single.iter().zip(&batch).enumerate() {
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits();
        assert!(same(s.elevation, b.elevation) && same(s.gradient.x, b.gradient.x), "point {k}: {s:?} {b:?}");
        assert!(same(s.gradient.y, b.gradient.y) && same(elevations[k], s.elevation), "point {k}");
    }
    assert!(batch[batch.len() - 2].elevation.is_nan() && batch[batch.len() - 1].elevation == 0.0);
    // Against the terrain itself: to the truncation tolerance (and f32 rounding).
    let bound = 1e-3 * terrain.primitives.iter().map(|g| g.amplitude.abs()).fold(0.0, f64::max) * 16.0;
    let worst =
        points[..2_000].iter().zip(&elevations).map(|(&p, h)| (h - terrain.height_at(p)).abs()).fold(0.0, f64::max);
    assert!(worst < bound, "worst {worst}, bound {bound}");
    assert!(elevations.iter().filter(|h| **h != 0.0).count() > 15_000);
    // Sorted by y, then x: in the order strips are cut, yet a strip of several y values holds
    // its points by x, not in the order given.
    let mut sorted = points[..20_000].to_vec();
    sorted.sort_by(|a, b| a.y.total_cmp(&b.y).then(a.x.total_cmp(&b.x)));
    let single: Vec<f64> = sorted.iter().map(|&p| query.elevation(p)).collect();
    assert_eq!(query.elevations(&sorted), single);
    // Two grid rows amid them, still by y: strips in place (the rows) among sorted ones.
    let row = |y: f64| (0..100).map(move |i| DVec2::new(f64::from(i) * 9.9, y));
    let mut mixed: Vec<DVec2> = sorted.iter().copied().filter(|p| p.y < 480.0).collect();
    mixed.extend(row(495.0).chain(row(505.0)));
    mixed.extend(sorted.iter().copied().filter(|p| p.y > 520.0));
    let single: Vec<f64> = mixed.iter().map(|&p| query.elevation(p)).collect();
    assert_eq!(query.elevations(&mixed), single);
    // Few points far apart in y (sorted whole, not by slabs), and y = ±0 with x out of order.
    let sparse = [
        DVec2::new(500.0, 4e7),
        DVec2::new(300.0, 0.0),
        DVec2::new(200.0, -0.0),
        DVec2::new(100.0, 0.0),
        DVec2::new(400.0, -3e7),
        DVec2::new(250.0, -0.0),
        DVec2::new(500.0, 500.0),
    ];
    let single: Vec<f64> = sparse.iter().map(|&p| query.elevation(p)).collect();
    assert_eq!(query.elevations(&sparse), single);
    assert!(single[1..4].iter().chain(&single[5..]).any(|h| *h != 0.0));
}

/// A support far narrower than the typical one, far from its anchor corner: the points' f32
/// coordinates are off by more than its relative margin, so the kernel's inside test counts
/// points just beyond the support. A single query lets that test decide; only the slack keeps
/// the batch's stretches (the exact chord of a grid row, the x range over a strip of several y)
/// wide enough to reach the same points.
#[test]
fn a_tiny_support_far_from_its_corner_gives_the_same_bits() {
    let mut terrain = random_terrain(500, 1000.0, 16.0, 4);
    let centre = DVec2::new(611.3, 377.9);
    terrain.primitives.push(Gaussian::round(centre, 0.002, 1000.0));
    let query = terrain.query().unwrap();
    let mut uniform = uniform(0x2545_f491_4f6c_dd1d);
    let mut next = move || uniform() - 0.5;
    let points: Vec<DVec2> = (0..20_000).map(|_| centre + DVec2::new(next(), next()) * 0.02).collect();
    let single: Vec<f64> = points.iter().map(|&p| query.elevation(p)).collect();
    assert_eq!(query.elevations(&points), single);
    let base = query.elevation(centre + DVec2::new(0.5, 0.0));
    assert!(single.iter().filter(|h| (**h - base).abs() > 1.0).count() > 1000);
    // Grid rows over it: strips of one y, each support's stretch the exact chord.
    let rows: Vec<DVec2> = (0..200)
        .flat_map(|j| (0..200).map(move |i| centre + (DVec2::new(f64::from(i), f64::from(j)) - 99.5) * 1e-4))
        .collect();
    let single: Vec<f64> = rows.iter().map(|&p| query.elevation(p)).collect();
    assert_eq!(query.elevations(&rows), single);
}

/// A support wider than several anchor squares: a stretch of it crosses squares, and the lanes
/// that pad a stretch to whole vectors hold points of the next square, measured from another
/// corner. Only the stretch's own points may take it: the grid's batch, and a scattered one's
/// (strips of several y, cut where they cross a third square), are the single queries.
#[test]
fn a_support_wider_than_the_anchor_squares() {
    let mut terrain = random_terrain(20_000, 1000.0, 16.0, 6);
    terrain.primitives.push(Gaussian::round(DVec2::new(480.0, 510.0), 400.0, 50.0));
    let query = terrain.query().unwrap();
    let g = grid(151, DVec2::ZERO, 1000.0);
    let points = grid_points(&g);
    let single: Vec<f64> = points.iter().map(|&p| query.elevation(p)).collect();
    assert_eq!(query.elevations(&points), single);
    let samples = query.samples(&points);
    assert!(samples.iter().zip(&points).all(|(s, &p)| *s == query.sample(p)));
    let mut uniform = uniform(0x9e37_79b9_7f4a_7c15);
    let scattered: Vec<DVec2> = (0..20_000).map(|_| DVec2::new(uniform(), uniform()) * 1000.0).collect();
    let alone: Vec<f64> = scattered.iter().map(|&p| query.elevation(p)).collect();
    assert_eq!(query.elevations(&scattered), alone);
    let together = query.samples(&scattered);
    assert!(together.iter().zip(&scattered).all(|(s, &p)| *s == query.sample(p)));
    // And the rasterizer's values, to a support's truncation at a sample on its edge.
    let raster = rasterize(&terrain, &g, &RasterOptions::default()).unwrap();
    let worst = single.iter().zip(raster.samples()).map(|(h, r)| (h - f64::from(*r)).abs()).fold(0.0, f64::max);
    let biggest = terrain.primitives.iter().map(|g| g.amplitude.abs()).fold(0.0, f64::max);
    assert!(worst < 1e-3 * biggest + 1e-3, "worst {worst}");
}

/// Supports of extreme shape (stretched a hundred million times, σ near the f64 limits, a
/// segment with no y extent): no NaN reaches the hierarchy, and batches of scattered points
/// around each are the single queries.
#[test]
fn supports_of_extreme_shape() {
    let shapes = [([100.0, 1e-6], 0.7), ([1e90, 1e90], 0.3), ([1.0, 1e-200], 0.0), ([3e-150, 1e-160], 1.1)];
    for (sigma, theta) in shapes {
        let g = Gaussian { center: [10.0, 20.0], sigma, theta, amplitude: 5.0, beta: 2.0 };
        let mut terrain = random_terrain(200, 100.0, 8.0, 1);
        terrain.primitives.push(g);
        let query = terrain.query().unwrap();
        let reach = sigma[0].max(sigma[1]).min(50.0) * 3.0;
        let mut uniform = uniform(99);
        let mut next = move || uniform() - 0.5;
        let points: Vec<DVec2> =
            (0..3_000).map(|_| DVec2::new(10.0, 20.0) + DVec2::new(next(), next()) * reach).collect();
        let single: Vec<f64> = points.iter().map(|&p| query.elevation(p)).collect();
        assert_eq!(query.elevations(&points), single, "σ {sigma:?}");
        assert!(single.iter().all(|h| h.is_finite()), "σ {sigma:?}");
    }
}
