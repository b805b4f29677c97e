//! The rasterizer against the untruncated f64 sum, windows and resolutions, thread-count
//! independence, the atlas, and typed errors for bad input.

use glam::DVec2;
use proptest::prelude::*;
use relief_fixtures::random_terrain;
use relief_gaussian_terrain::{
    Atlas, Gaussian, GaussianError, Landform, RasterOptions, VectorTerrain, rasterize, rasterize_exact,
};
use relief_heightfield::{Extent, GridSpec};

fn square(n: usize, size: f64) -> GridSpec {
    GridSpec::from_extent(n, n, Extent::new(DVec2::ZERO, DVec2::splat(size))).unwrap()
}

fn primitive() -> impl Strategy<Value = Gaussian> {
    (-20.0..120.0f64, -20.0..120.0f64, 0.5..30.0f64, 0.5..30.0f64, -4.0..4.0f64, -100.0..100.0f64, 0.8..6.0f64)
        .prop_map(|(x, y, sx, sy, theta, amplitude, beta)| Gaussian {
            center: [x, y],
            sigma: [sx, sy],
            theta,
            amplitude,
            beta,
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Truncation costs at most `tolerance·|a|` per primitive; the f32 sums and fast `exp`/`log2`
    /// add a few 1e-6 relative.
    #[test]
    fn raster_matches_the_exact_sum(
        prims in proptest::collection::vec(primitive(), 0..30),
        nx in 2usize..40, ny in 2usize..40,
        ox in -30.0..30.0f64, oy in -30.0..30.0f64, cell in 0.3..6.0f64,
        tolerance in prop::sample::select(vec![1e-2, 1e-3, 1e-5]),
    ) {
        let terrain = VectorTerrain::new(prims);
        let grid = GridSpec::new(nx, ny, DVec2::new(ox, oy), DVec2::splat(cell)).unwrap();
        let fast = rasterize(&terrain, &grid, &RasterOptions { tolerance }).unwrap();
        let exact = rasterize_exact(&terrain, &grid).unwrap();
        let total: f64 = terrain.primitives.iter().map(|g| g.amplitude.abs()).sum();
        let bound = tolerance * total + 2e-5 * total + 1e-4;
        for (k, (a, b)) in fast.samples().iter().zip(exact.samples()).enumerate() {
            prop_assert!(f64::from((a - b).abs()) <= bound, "sample {}: {} vs {} (bound {})", k, a, b, bound);
        }
    }
}

#[test]
fn a_window_agrees_with_the_whole_and_resolutions_agree_where_samples_meet() {
    let terrain = random_terrain(400, 1000.0, 12.0, 9);
    let whole = rasterize(&terrain, &square(201, 1000.0), &RasterOptions::default()).unwrap();
    // The window [300, 500] × [600, 800] at the same spacing, and the whole at half spacing.
    let window = GridSpec::new(41, 41, DVec2::new(300.0, 600.0), DVec2::splat(5.0)).unwrap();
    let part = rasterize(&terrain, &window, &RasterOptions::default()).unwrap();
    let fine = rasterize(&terrain, &square(401, 1000.0), &RasterOptions::default()).unwrap();
    let scale = terrain.primitives.iter().map(|g| g.amplitude.abs()).fold(0.0, f64::max) as f32;
    for j in 0..41 {
        for i in 0..41 {
            let (a, b) = (part.value(i, j), whole.value(60 + i, 120 + j));
            assert!((a - b).abs() <= 1e-5 * scale, "window ({i}, {j}): {a} vs {b}");
        }
    }
    for j in (0..201).step_by(7) {
        for i in (0..201).step_by(5) {
            let (a, b) = (whole.value(i, j), fine.value(2 * i, 2 * j));
            assert!((a - b).abs() <= 1e-5 * scale, "({i}, {j}): {a} vs {b}");
        }
    }
}

#[test]
fn same_bytes_for_one_and_two_threads() {
    let terrain = random_terrain(3000, 1000.0, 16.0, 4);
    let grid = square(300, 1000.0);
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| rasterize(&terrain, &grid, &RasterOptions::default()).unwrap())
    };
    let (one, two) = (run(1), run(2));
    assert!(one.samples().iter().zip(two.samples()).all(|(a, b)| a.to_bits() == b.to_bits()));
    assert!(one.samples().iter().any(|&v| v != 0.0));
}

#[test]
fn an_empty_terrain_is_flat_and_primitives_off_the_window_add_nothing() {
    let grid = square(17, 100.0);
    let flat = rasterize(&VectorTerrain::default(), &grid, &RasterOptions::default()).unwrap();
    assert!(flat.samples().iter().all(|&v| v == 0.0));
    let far = VectorTerrain::new(vec![Gaussian::round(DVec2::new(5000.0, 50.0), 10.0, 1e6)]);
    let h = rasterize(&far, &grid, &RasterOptions::default()).unwrap();
    assert!(h.samples().iter().all(|&v| v == 0.0));
}

#[test]
fn a_placed_landform_is_the_original_moved_turned_and_scaled() {
    let source = random_terrain(60, 200.0, 6.0, 2);
    let landform = Landform::new("crater field", &source.primitives, DVec2::splat(100.0));
    let atlas = Atlas { landforms: vec![landform], ..Atlas::default() };
    let json = serde_json::to_string(&atlas).unwrap();
    let back: Atlas = serde_json::from_str(&json).unwrap();
    assert_eq!(back, atlas);
    back.validate().unwrap();
    let (at, turn, scale) = (DVec2::new(700.0, 400.0), 0.8, 1.5);
    let placed = VectorTerrain::new(back.get("crater field").unwrap().placed(at, turn, scale));
    for k in 0..50 {
        let q = DVec2::new(f64::from(k) * 4.0, 200.0 - f64::from(k) * 3.0);
        let moved = at + DVec2::from_angle(turn).rotate((q - DVec2::splat(100.0)) * scale);
        let (a, b) = (source.height_at(q), placed.height_at(moved));
        assert!((a - b).abs() <= 1e-9 * a.abs().max(1.0), "{q}: {a} vs {b}");
    }
    assert!(matches!(back.get("dune"), Err(GaussianError::NoSuchLandform { .. })));
}

#[test]
fn bad_input_gets_typed_errors() {
    let grid = square(9, 10.0);
    // Loading from JSON checks every primitive, naming the parameter at fault.
    let json = r#"{"primitives": [{"center": [1, 2], "sigma": [1, 0], "amplitude": 3}]}"#;
    let e = serde_json::from_str::<VectorTerrain>(json).unwrap_err().to_string();
    assert!(e.contains("sigma.y = 0"), "{e}");
    let mut t: VectorTerrain = serde_json::from_str(&json.replace("[1, 0]", "[1, 2]")).unwrap();
    assert_eq!(t.primitives[0].beta, 2.0, "β defaults to 2");
    // σ ≤ 0 and NaN set in code are caught by the rasterizer and `validate`.
    t.primitives[0].sigma[1] = 0.0;
    assert!(matches!(
        rasterize(&t, &grid, &RasterOptions::default()),
        Err(GaussianError::InvalidPrimitive { index: 0, what: "sigma.y", .. })
    ));
    let mut t = random_terrain(5, 10.0, 4.0, 1);
    t.primitives[3].amplitude = f64::NAN;
    assert!(matches!(t.validate(), Err(GaussianError::NotFinite { index: 3, what: "amplitude" })));
    t.primitives[3].amplitude = 1.0;
    t.primitives[1].beta = -1.0;
    assert!(matches!(t.validate(), Err(GaussianError::InvalidPrimitive { index: 1, what: "beta", .. })));
    // The count cap, checked before any work.
    let many = random_terrain(11, 10.0, 4.0, 1);
    assert!(matches!(many.validate_with_limit(10), Err(GaussianError::TooManyPrimitives { count: 11, limit: 10 })));
    assert!(many.validate_with_limit(11).is_ok(), "the cap itself is allowed");
    // A base f64 holds but f32 does not, and empty or unbounded domains.
    let at = |base: f64, domain: [[f64; 2]; 2]| VectorTerrain { base, domain: Some(domain), ..many.clone() }.validate();
    assert!(at(1e6, [[0.0, 0.0], [1.0, 1.0]]).is_ok());
    assert!(matches!(at(1e300, [[0.0, 0.0], [1.0, 1.0]]), Err(GaussianError::NotFinite { what: "base", .. })));
    for domain in [
        [[0.0, 0.0], [0.0, 1.0]],
        [[0.0, 0.0], [1.0, 0.0]],
        [[0.0, 0.0], [1.0, -1.0]],
        [[0.0, 0.0], [f64::INFINITY, 1.0]],
    ] {
        assert!(
            matches!(at(0.0, domain), Err(GaussianError::NotFinite { what, .. }) if what.starts_with("domain")),
            "{domain:?}"
        );
    }
    // Options and output size.
    assert!(matches!(
        rasterize(&many, &grid, &RasterOptions { tolerance: 0.0 }),
        Err(GaussianError::InvalidOption { name: "tolerance", .. })
    ));
    // Amplitudes beyond f32, and f32 sums that overflow.
    let loud = VectorTerrain::new(vec![Gaussian::round(DVec2::splat(5.0), 2.0, 1e39)]);
    assert!(matches!(loud.validate(), Err(GaussianError::InvalidPrimitive { what: "amplitude", .. })));
    let pair = VectorTerrain::new(vec![Gaussian::round(DVec2::splat(5.0), 2.0, 3e38); 2]);
    assert!(matches!(rasterize(&pair, &grid, &RasterOptions::default()), Err(GaussianError::Raster(_))));
    let huge = GridSpec::new(20_000, 20_000, DVec2::ZERO, DVec2::ONE).unwrap();
    assert!(matches!(rasterize(&many, &huge, &RasterOptions::default()), Err(GaussianError::GridTooLarge { .. })));
}

/// A terrain records what its coordinates are (units and CRS, as vectorization takes them from
/// the DEM) and keeps them through JSON; its own units win over its CRS's.
#[test]
fn the_frame_is_recorded_read_back_and_checked() {
    use relief_heightfield::{Crs, Heightfield, Units};
    let plain = VectorTerrain::new(vec![Gaussian::round(DVec2::ZERO, 1.0, 1.0)]);
    assert_eq!((plain.units(), plain.crs.as_ref()), (Units::Metres, None));
    assert!(!serde_json::to_string(&plain).unwrap().contains("units"), "nothing written when unknown");
    let wgs84 = Crs::from_wkt(r#"GEOGCS["WGS 84",DATUM["WGS_1984"],UNIT["degree",0.0174532925199433]]"#).unwrap();
    let grid = GridSpec::from_extent(3, 3, Extent::new(DVec2::ZERO, DVec2::ONE)).unwrap().with_units(Units::Degrees);
    let dem = Heightfield::zeros(grid.unwrap()).with_crs(Some(wgs84.clone()));
    let framed = plain.clone().in_frame_of(&dem);
    assert_eq!((framed.units, framed.crs.as_ref()), (Some(Units::Degrees), Some(&wgs84)));
    let back: VectorTerrain = serde_json::from_str(&serde_json::to_string(&framed).unwrap()).unwrap();
    assert_eq!(back, framed);
    // Without units, the CRS's.
    let crs_only = VectorTerrain { units: None, ..framed.clone() };
    assert_eq!(crs_only.units(), Units::Degrees);
    // Given units win over the CRS's, as a grid's do (a DEM read with `--units feet` keeps its
    // file's CRS label): such a terrain is valid and reads back as it was.
    let overridden = VectorTerrain { units: Some(Units::Feet), ..framed };
    assert_eq!(overridden.units(), Units::Feet);
    assert!(overridden.validate().is_ok());
    let back: VectorTerrain = serde_json::from_str(&serde_json::to_string(&overridden).unwrap()).unwrap();
    assert_eq!(back, overridden);
}
