//! The invariants of issue #6: filling is idempotent, never lowers a cell and leaves no basin;
//! drainage is conserved; Strahler orders of known trees; erosion creates nothing it should not;
//! results do not depend on the thread count; bad input gets defined results or typed errors.

use glam::DVec2;
use proptest::prelude::*;
use relief_heightfield::noise::Fbm;
use relief_heightfield::{GridSpec, Heightfield, metres_per_degree};
use relief_hydrology::{
    CountHistogram, D8, DescriptorOptions, Descriptors, Field, HydrologyError, Mfd, NO_RECEIVER, NoData, Outlets,
    StreamPower, Thermal, depressions, fill, has_endorheic_basins, mfd_drainage_area, strahler,
};

fn grid(nx: usize, ny: usize) -> GridSpec {
    GridSpec::new(nx, ny, DVec2::ZERO, DVec2::splat(10.0)).unwrap()
}

/// A bumpy fBm terrain with many pits, optionally with a no-data hole.
fn bumpy(n: usize, seed: u64, hole: bool) -> Heightfield {
    let fbm = Fbm { seed, octaves: 5, frequency: 6.0 / (10.0 * n as f64), ..Fbm::default() };
    let c = DVec2::splat(5.0 * n as f64);
    Heightfield::from_fn(grid(n, n), |p| {
        if hole && (p - c).length() < 1.5 * n as f64 { f32::NAN } else { (300.0 * fbm.sample(p)) as f32 }
    })
    .unwrap()
}

fn arb_dem() -> impl Strategy<Value = Heightfield> {
    (2usize..14, 1usize..14).prop_flat_map(|(nx, ny)| {
        prop::collection::vec(prop_oneof![9 => (0u8..6).prop_map(f32::from), 1 => Just(f32::NAN)], nx * ny)
            .prop_map(move |s| Heightfield::from_samples(grid(nx, ny), s).unwrap())
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn filling_is_idempotent_monotone_and_drains(dem in arb_dem(), wall in any::<bool>()) {
        prop_assume!(dem.no_data_count() < dem.grid().len());
        let no_data = if wall { NoData::Wall } else { NoData::Outlet };
        let outlets = Outlets::new().with_no_data(no_data);
        let once = fill(&dem, outlets).unwrap();
        for (a, b) in once.samples().iter().zip(dem.samples()) {
            prop_assert!(a >= b || (a.is_nan() && b.is_nan()), "{a} < {b}");
        }
        prop_assert_eq!(&fill(&once, outlets).unwrap(), &once);
        prop_assert!(!has_endorheic_basins(&once, no_data));
        // The plain fill agrees about which cells lie in basins.
        let d = depressions(&dem, outlets).unwrap();
        prop_assert_eq!(d.basins.is_empty(), !has_endorheic_basins(&dem, no_data));
        prop_assert!(!has_endorheic_basins(&d.filled, no_data));
        let labelled = d.labels.iter().filter(|&&l| l > 0).count();
        prop_assert_eq!(labelled, d.basins.iter().map(|b| b.cells).sum::<usize>());
        for b in &d.basins {
            prop_assert!(b.fill_level > b.pit_elevation && b.volume_m3 > 0.0);
        }
    }

    #[test]
    fn drainage_reaches_the_outlets_whole(dem in arb_dem()) {
        prop_assume!(dem.no_data_count() < dem.grid().len());
        let filled = fill(&dem, Outlets::new()).unwrap();
        let valid = filled.samples().iter().filter(|v| !v.is_nan()).count() as f64 * 100.0;
        let d8 = D8::new(&filled).unwrap();
        let at_sinks: f64 = d8.sinks().map(|(i, j)| d8.drainage_area()[j * dem.nx() + i]).sum();
        prop_assert!((at_sinks - valid).abs() < 1e-6 * valid, "{at_sinks} vs {valid}");
        // Every sink of a filled DEM is an outlet: the border or next to no-data.
        for (i, j) in d8.sinks() {
            let border = i == 0 || j == 0 || i + 1 == dem.nx() || j + 1 == dem.ny();
            let by_hole = (-1i64..=1).any(|a| (-1i64..=1).any(|b| {
                let (x, y) = (i as i64 + a, j as i64 + b);
                x >= 0 && y >= 0 && (x as usize) < dem.nx() && (y as usize) < dem.ny() && filled.is_no_data(x as usize, y as usize)
            }));
            prop_assert!(border || by_hole, "interior sink at ({i}, {j})");
        }
        let mfd = mfd_drainage_area(&filled, Mfd::default()).unwrap();
        let mfd_sinks: f64 = d8.sinks().map(|(i, j)| mfd[j * dem.nx() + i]).sum();
        prop_assert!((mfd_sinks - valid).abs() < 1e-6 * valid, "MFD {mfd_sinks} vs {valid}");
    }

    #[test]
    fn stream_power_creates_nothing(dem in arb_dem(), uplift in 0.0f64..0.01, n in prop_oneof![Just(1.0), 0.5f64..2.0]) {
        prop_assume!(dem.no_data_count() < dem.grid().len());
        let sp = StreamPower { uplift: Field::Uniform(uplift), n, dt: 500.0, erodibility: Field::Uniform(1e-3), ..StreamPower::default() };
        let mut out = dem.clone();
        StreamPower { iterations: 3, ..sp }.run(&mut out, |_| {}).unwrap();
        let rise = (3.0 * uplift * 500.0) as f32 * (1.0 + 1e-5) + 1e-4;
        for (k, (a, b)) in out.samples().iter().zip(dem.samples()).enumerate() {
            prop_assert_eq!(a.is_nan(), b.is_nan(), "no-data changed at {}", k);
            if !b.is_nan() {
                prop_assert!(a.is_finite() && *a <= *b + rise, "cell {k}: {b} -> {a}");
            }
        }
    }
}

#[test]
fn tilted_plane_drains_to_its_upstream_count() {
    let (nx, ny) = (17, 9);
    let plane = Heightfield::from_fn(grid(nx, ny), |p| (0.2 * p.x) as f32).unwrap();
    let d8 = D8::new(&plane).unwrap();
    let acc = d8.accumulation();
    for j in 0..ny {
        for i in 0..nx {
            assert_eq!(acc[j * nx + i] as usize, nx - i, "({i}, {j})");
            assert!((d8.drainage_area()[j * nx + i] - 100.0 * (nx - i) as f64).abs() < 1e-9);
        }
    }
    // Outlets are the west column; each takes its whole row.
    let sinks: Vec<_> = d8.sinks().collect();
    assert_eq!(sinks, (0..ny).map(|j| (0, j)).collect::<Vec<_>>());
    // Streams from 10 cells up are the 8 westmost columns, all order 1 (no confluences).
    let streams = d8.streams(1000.0).unwrap();
    assert_eq!(streams.iter().filter(|&&s| s).count(), 8 * ny);
    assert_eq!(d8.strahler(&streams).unwrap().iter().max(), Some(&1));
}

#[test]
fn strahler_of_binary_trees() {
    // A complete binary tree of depth 3 (15 nodes, root 0, children 2k+1 and 2k+2): root order 4.
    let n = 15u32;
    let receivers: Vec<u32> = (0..n).map(|k| if k == 0 { NO_RECEIVER } else { (k - 1) / 2 }).collect();
    let order: Vec<u32> = (0..n).collect();
    let s = strahler(&receivers, &order, &vec![true; n as usize]).unwrap();
    assert_eq!(s[0], 4);
    assert_eq!(&s[7..15], &[1; 8]);
    assert_eq!(&s[1..3], &[3, 3]);
    // Prune one side to a single leaf: the root joins orders 3 and 1 and stays 3.
    let keep: Vec<bool> = (0..n).map(|k| ![5, 6, 11, 12, 13, 14].contains(&k)).collect();
    let s = strahler(&receivers, &order, &keep).unwrap();
    assert_eq!((s[0], s[1], s[2]), (3, 3, 1));
    assert!(matches!(strahler(&receivers, &order, &[true]), Err(HydrologyError::LengthMismatch { .. })));
}

#[test]
fn strahler_of_two_valleys_joining() {
    // A V-shaped valley system on a grid: two tributaries running down x meet a trunk along y = 0.
    let (nx, ny) = (41, 41);
    let dem = Heightfield::from_fn_indexed(grid(nx, ny), |i, j| {
        let (x, y) = (i as f32, j as f32);
        // Trunk along row 0 falling west; two side valleys at x = 12 and x = 30 falling south.
        let side = ((x - 12.0).abs()).min((x - 30.0).abs());
        0.5 * x + 3.0 * side.min(y) + 0.1 * y
    })
    .unwrap();
    let filled = fill(&dem, Outlets::new()).unwrap();
    let d8 = D8::new(&filled).unwrap();
    let streams = d8.streams(100.0 * 30.0).unwrap();
    let orders = d8.strahler(&streams).unwrap();
    let max = *orders.iter().max().unwrap();
    assert!(max >= 2, "two valleys joining make at least order 2, got {max}");
}

#[test]
fn results_do_not_depend_on_thread_count() {
    let dem = bumpy(96, 3, true);
    let run = || {
        let filled = fill(&dem, Outlets::new()).unwrap();
        let d8 = D8::new(&filled).unwrap();
        let mfd = mfd_drainage_area(&filled, Mfd::Quinn).unwrap();
        let mut thermal = dem.clone();
        Thermal { iterations: 5, ..Thermal::default() }.run(&mut thermal, |_| {}).unwrap();
        let mut eroded = dem.clone();
        StreamPower::default().step(&mut eroded).unwrap();
        (filled, d8, mfd.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), thermal, eroded)
    };
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap().install(run);
    let many = rayon::ThreadPoolBuilder::new().num_threads(4).build().unwrap().install(run);
    assert!(one == many);
}

#[test]
fn thermal_erosion_conserves_volume_and_relaxes_steep_slopes() {
    // A 40 m spike on a plain: far steeper than 33°.
    let mut dem =
        Heightfield::from_fn_indexed(grid(21, 21), |i, j| if (i, j) == (10, 10) { 40.0 } else { 0.0 }).unwrap();
    let before: f64 = dem.samples().iter().map(|&v| f64::from(v)).sum();
    let mut steps = 0;
    Thermal { iterations: 200, ..Thermal::default() }.run(&mut dem, |d| steps = d).unwrap();
    assert_eq!(steps, 200);
    let after: f64 = dem.samples().iter().map(|&v| f64::from(v)).sum();
    assert!((before - after).abs() < 1e-3, "{before} -> {after}");
    let peak = dem.get(10, 10).unwrap();
    assert!(peak < 15.0, "spike still {peak} m");
    let tan = 33f64.to_radians().tan();
    // Within a whisker of the talus angle everywhere.
    for j in 0..21 {
        for i in 0..20 {
            let d = f64::from((dem.get(i, j).unwrap() - dem.get(i + 1, j).unwrap()).abs());
            assert!(d <= tan * 10.0 * 1.1 + 0.05, "slope {d} at ({i}, {j})");
        }
    }
    assert!(matches!(
        Thermal { rate: 0.9, ..Thermal::default() }.run(&mut dem, |_| {}),
        Err(HydrologyError::InvalidParameter { name: "rate", .. })
    ));
}

#[test]
fn stream_power_incises_valleys_and_keeps_outlets() {
    let dem = bumpy(64, 11, false);
    let mut eroded = dem.clone();
    let sp = StreamPower { erodibility: Field::Uniform(5e-4), n: 1.0, dt: 1000.0, ..StreamPower::default() };
    // The sinks of the routing (border outlets) are the base level: one step leaves them be.
    let sinks: Vec<_> = D8::new(&fill(&dem, Outlets::new()).unwrap()).unwrap().sinks().collect();
    sp.step(&mut eroded).unwrap();
    assert!(sinks.iter().all(|&(i, j)| eroded.get(i, j) == dem.get(i, j)));
    StreamPower { iterations: 9, ..sp.clone() }.run(&mut eroded, |_| {}).unwrap();
    let lowered = eroded.samples().iter().zip(dem.samples()).filter(|(a, b)| a < b).count();
    assert!(lowered > 64 * 64 / 4, "only {lowered} cells eroded");
    // With a sea, every cell at or below its level is base level too, however the floor slopes.
    let mut coast = dem.clone();
    let sea = StreamPower { iterations: 10, outlets: Outlets::new().with_sea_level(0.0), ..sp.clone() };
    sea.run(&mut coast, |_| {}).unwrap();
    let under: Vec<(f32, f32)> =
        dem.samples().iter().zip(coast.samples()).filter(|(a, _)| **a <= 0.0).map(|(a, b)| (*a, *b)).collect();
    assert!(under.len() > 64 * 64 / 4 && under.iter().any(|(a, _)| *a < -50.0), "{} sea cells", under.len());
    assert!(under.iter().all(|(a, b)| a == b), "the sea floor was carved");
    assert!(coast.samples().iter().zip(dem.samples()).any(|(a, b)| a < b), "the land erodes");
    let bad = StreamPower { uplift: Field::Map(vec![0.0; 3]), ..StreamPower::default() };
    assert!(matches!(bad.step(&mut eroded), Err(HydrologyError::LengthMismatch { what: "uplift", .. })));
    let bad = StreamPower { m: f64::NAN, ..StreamPower::default() };
    assert!(matches!(bad.step(&mut eroded), Err(HydrologyError::InvalidParameter { name: "m", .. })));
}

#[test]
fn descriptors_compare_terrains() {
    let a = bumpy(64, 1, false);
    let da = Descriptors::of(&a, &DescriptorOptions::default()).unwrap();
    assert_eq!(da.cells, 64 * 64);
    assert!(da.max_strahler >= 2);
    let same = da.distance(&da);
    assert_eq!((same.elevation, same.slope_deg, same.log10_drainage_area, same.strahler), (0.0, 0.0, 0.0, 0));
    // Raising a terrain by 100 m moves its elevation histogram by exactly that much.
    let raised = a.map(|v| v + 100.0).unwrap();
    let dr = Descriptors::of(&raised, &DescriptorOptions::default()).unwrap();
    let d = da.distance(&dr);
    assert!((d.elevation - 100.0).abs() < 1e-6, "{}", d.elevation);
    // Slopes move only by the f32 rounding of the raised samples.
    assert!(d.slope_deg < 0.05, "{}", d.slope_deg);
    // A different terrain is further away in slope and drainage than the same one.
    let b = bumpy(64, 2, false).map(|v| v * 2.0).unwrap();
    let db = Descriptors::of(&b, &DescriptorOptions::default()).unwrap();
    assert!(da.distance(&db).slope_deg > 1.0);
    let json = serde_json::to_string(&da).unwrap();
    assert_eq!(serde_json::from_str::<Descriptors>(&json).unwrap(), da);
}

#[test]
fn wasserstein_of_histograms() {
    let a = CountHistogram { lo: 0.0, hi: 1.0, counts: vec![1] };
    let b = CountHistogram { lo: 2.0, hi: 3.0, counts: vec![5] };
    assert!((a.wasserstein(&b) - 2.0).abs() < 1e-12);
    // Two bins against one covering both: uniform on [0, 2] either way.
    let c = CountHistogram { lo: 0.0, hi: 2.0, counts: vec![3, 3] };
    let d = CountHistogram { lo: 0.0, hi: 2.0, counts: vec![1] };
    assert!(c.wasserstein(&d).abs() < 1e-12);
    // Half the mass moved by 1: distance 0.5, crossing CDFs handled.
    let e = CountHistogram { lo: 0.0, hi: 2.0, counts: vec![1, 1] };
    let f = CountHistogram { lo: 0.0, hi: 2.0, counts: vec![0, 2] };
    assert!((e.wasserstein(&f) - 0.5).abs() < 1e-12);
    assert!((f.wasserstein(&e) - 0.5).abs() < 1e-12);
}

#[test]
fn bad_input_gets_defined_results_or_typed_errors() {
    // All no-data.
    let none = Heightfield::filled(grid(5, 5), f32::NAN).unwrap();
    assert!(matches!(fill(&none, Outlets::new()), Err(HydrologyError::AllNoData { cells: 25 })));
    assert!(matches!(D8::new(&none), Err(HydrologyError::AllNoData { .. })));
    assert!(matches!(mfd_drainage_area(&none, Mfd::Quinn), Err(HydrologyError::AllNoData { .. })));
    assert!(matches!(Descriptors::of(&none, &DescriptorOptions::default()), Err(HydrologyError::AllNoData { .. })));
    assert!(!has_endorheic_basins(&none, NoData::Outlet));
    // A single row and a single column: every cell is on the border, so nothing is closed.
    for (nx, ny) in [(12, 1), (1, 12)] {
        let line = Heightfield::from_fn_indexed(grid(nx, ny), |i, j| ((i + j) % 3) as f32).unwrap();
        assert!(!has_endorheic_basins(&line, NoData::Wall));
        let d8 = D8::new(&line).unwrap();
        let total: f64 = d8.sinks().map(|(i, j)| d8.drainage_area()[j * nx + i]).sum();
        assert!((total - 1200.0).abs() < 1e-9);
        assert!(Descriptors::of(&line, &DescriptorOptions::default()).is_ok());
    }
    // A flat DEM: no basins; the ε-fill gives it a drainage pattern toward the border.
    let flat = Heightfield::filled(grid(9, 9), 5.0).unwrap();
    assert!(!has_endorheic_basins(&flat, NoData::Outlet));
    assert!(depressions(&flat, Outlets::new()).unwrap().basins.is_empty());
    let routed = D8::new(&fill(&flat, Outlets::new()).unwrap()).unwrap();
    assert!(routed.sinks().all(|(i, j)| i == 0 || j == 0 || i == 8 || j == 8));
    // NaN inside data is no-data: routing goes around it.
    let holed = bumpy(32, 5, true);
    let d8 = D8::new(&fill(&holed, Outlets::new()).unwrap()).unwrap();
    assert!(d8.drainage_area().iter().zip(holed.samples()).all(|(a, z)| z.is_nan() == (*a == 0.0)));
    assert!(matches!(
        Descriptors::of(&holed, &DescriptorOptions { bins: 0, ..DescriptorOptions::default() }),
        Err(HydrologyError::InvalidParameter { name: "bins", .. })
    ));
    assert!(matches!(
        Descriptors::of(&holed, &DescriptorOptions { bins: usize::MAX, ..DescriptorOptions::default() }),
        Err(HydrologyError::InvalidParameter { name: "bins", .. })
    ));
    assert!(matches!(
        mfd_drainage_area(&holed, Mfd::Freeman { p: -1.0 }),
        Err(HydrologyError::InvalidParameter { name: "p", .. })
    ));
}

#[test]
fn geographic_grids_measure_area_in_square_metres() {
    // A 1/120° tile at 60° N: cells are about 463 m × 927 m.
    let grid = GridSpec::geographic(8, 8, DVec2::new(10.0, 60.0), DVec2::splat(1.0 / 120.0)).unwrap();
    let plane = Heightfield::from_fn(grid, |p| (1000.0 * (p.x - 10.0)) as f32).unwrap();
    let d8 = D8::new(&plane).unwrap();
    let a = d8.drainage_area()[0];
    let expected: f64 = (0..8).map(|_| grid.cell_area_m2(0)).sum();
    assert!((a - expected).abs() < 1e-6 * expected);
    assert!(grid.cell_area_m2(0) > 4.0e5 && grid.cell_area_m2(0) < 4.6e5, "{}", grid.cell_area_m2(0));
}

#[test]
fn descriptor_slopes_are_angles_in_metres_even_on_geographic_grids() {
    // A plane rising 1 m per metre eastward: every slope is 45°.
    let grid = GridSpec::new(32, 32, DVec2::ZERO, DVec2::splat(10.0)).unwrap();
    let plane = Heightfield::from_fn(grid, |p| p.x as f32).unwrap();
    let d = Descriptors::of(&plane, &DescriptorOptions::default()).unwrap();
    let below = |h: &relief_hydrology::CountHistogram, x: f64| h.cdf(x);
    assert!(below(&d.slope_deg, 44.0) < 0.01 && below(&d.slope_deg, 46.0) > 0.99, "{:?}", d.slope_deg);
    // The same plane on a geographic grid at 60° N: 0.001° cells are 55.8 m east, 111.4 m north,
    // and the ground rises 55.8 m per cell eastward, so the slope is 45° again.
    let east = metres_per_degree(60.0).x * 0.001;
    let geo = GridSpec::geographic(32, 32, DVec2::new(10.0, 60.0), DVec2::splat(0.001)).unwrap();
    let tilted = Heightfield::from_fn(geo, |p| ((p.x - 10.0) / 0.001 * east) as f32).unwrap();
    let g = Descriptors::of(&tilted, &DescriptorOptions::default()).unwrap();
    assert!(below(&g.slope_deg, 44.0) < 0.01 && below(&g.slope_deg, 46.0) > 0.99, "{:?}", g.slope_deg);
}
