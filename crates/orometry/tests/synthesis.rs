//! Descriptor, divide tree and synthesis (§4.2, §5, §6): histogram distances, classification,
//! tree prominence against the grid analysis, edits, generation fidelity, pinned peaks, drainage,
//! determinism and bad input.

use glam::DVec2;
use proptest::prelude::*;
use relief_heightfield::noise::Fbm;
use relief_heightfield::{Extent, GridSpec, Heightfield};
use relief_hydrology::{NoData, has_endorheic_basins};
use relief_orometry::{
    AnalysisOptions, ControlMaps, Descriptor, DivideTree, FractionHistogram, OrometryError, SynthesisOptions,
    TreeOptions, TreePeak, TreeSaddle, analyze, classify, generate_tree, synthesize, terrain_from_tree,
};

/// An fBm DEM at 30 m: `frequency` cycles per metre, `relief` metres of amplitude.
fn fbm_dem(n: usize, seed: u64, frequency: f64, relief: f64) -> Heightfield {
    let grid = GridSpec::from_extent(n, n, Extent::new(DVec2::ZERO, DVec2::splat(30.0 * (n - 1) as f64))).unwrap();
    let fbm = Fbm { octaves: 7, frequency, seed, gain: 0.55, ..Fbm::default() };
    Heightfield::from_fn(grid, |p| (1000.0 + relief * fbm.sample(p)) as f32).unwrap()
}

fn analysis() -> AnalysisOptions {
    AnalysisOptions { min_prominence: 20.0, ..AnalysisOptions::default() }
}

/// The descriptor every synthesis test targets: rugged fBm, 9 × 9 km.
fn target() -> Descriptor {
    Descriptor::of(&fbm_dem(301, 11, 1.0 / 4000.0, 600.0), &analysis()).unwrap().1
}

#[test]
fn histogram_fractions_quantiles_and_emd() {
    let h = FractionHistogram::uniform(0.0, 10.0, 10).filled([0.5, 1.5, 1.7, 9.9, 25.0, f64::NAN]);
    assert_eq!(h.fractions.iter().sum::<f64>(), 1.0);
    assert_eq!(h.fractions[1], 0.4, "1.5 and 1.7 share bin 1 of five finite values");
    assert_eq!(h.fractions[9], 0.4, "9.9 and the clamped 25 share the last bin");
    assert_eq!(h.emd(&h), Some(0.0));
    assert!((h.quantile(0.0).unwrap() - 0.0).abs() < 1e-12);
    assert!((h.quantile(1.0).unwrap() - 10.0).abs() < 1e-12);

    // All mass in the first bin against all in the last: 11/12 apart on a line, 1/12 on a circle.
    let first = FractionHistogram::uniform(0.0, 360.0, 12).filled([10.0]);
    let last = FractionHistogram::uniform(0.0, 360.0, 12).filled([350.0]);
    assert!((first.emd(&last).unwrap() - 11.0 / 12.0).abs() < 1e-12);
    let mut cf = first.clone();
    let mut cl = last.clone();
    cf.circular = true;
    cl.circular = true;
    assert!((cf.emd(&cl).unwrap() - 1.0 / 12.0).abs() < 1e-12);
    assert_eq!(first.max_bin_error(&last), Some(1.0));
    // Empty histograms: 0 from each other, 1 from anything else; different bins do not compare.
    let empty = FractionHistogram::uniform(0.0, 360.0, 12);
    assert_eq!(empty.emd(&empty), Some(0.0));
    assert_eq!(empty.emd(&first), Some(1.0));
    assert_eq!(FractionHistogram::uniform(0.0, 1.0, 5).emd(&first), None);
}

#[test]
fn a_histogram_from_a_floor_keeps_what_lies_above_it() {
    // Prominences counted at 30 m in [0, 100) bins: the first bin holds only values ≥ 30.
    let h = FractionHistogram::uniform(0.0, 400.0, 4).filled([30.0, 50.0, 150.0, 350.0]);
    let above = h.from_floor(30.0).unwrap();
    assert_eq!(above.edges, [30.0, 100.0, 200.0, 300.0, 400.0]);
    assert_eq!(above.fractions, h.fractions);
    assert!(above.quantile(0.0).unwrap() >= 30.0);
    // A floor in a later bin drops the bins under it and renormalizes.
    let high = h.from_floor(120.0).unwrap();
    assert_eq!(high.edges, [120.0, 200.0, 300.0, 400.0]);
    assert_eq!(high.fractions, [0.5, 0.0, 0.5]);
    assert_eq!(h.from_floor(-5.0).unwrap(), h);
    assert_eq!(h.from_floor(f64::NAN), None);
    assert_eq!(FractionHistogram::uniform(0.0, 400.0, 4).filled([10.0]).from_floor(150.0), None);
}

#[test]
fn the_descriptor_counts_distances_to_the_nearest_higher_peak() {
    // Three cones on a 1 km grid: 300 m at (200, 500), 200 m at (800, 500), 100 m at (800, 200).
    let grid = GridSpec::from_extent(101, 101, Extent::new(DVec2::ZERO, DVec2::splat(1000.0))).unwrap();
    let cones =
        [(DVec2::new(200.0, 500.0), 300.0), (DVec2::new(800.0, 500.0), 200.0), (DVec2::new(800.0, 200.0), 100.0)];
    let dem =
        Heightfield::from_fn(grid, |p| cones.iter().map(|&(c, h)| h - 0.5 * p.distance(c)).fold(0.0, f64::max) as f32)
            .unwrap();
    let (oro, d) =
        Descriptor::of(&dem, &AnalysisOptions { min_prominence: 10.0, ..AnalysisOptions::default() }).unwrap();
    assert_eq!(oro.peaks.len(), 3);
    assert_eq!(d.domain.min_prominence, 10.0);
    // 600 m from the 200 m cone to the 300 m one, 300 m from the 100 m cone to the 200 m one
    // (not to higher ground, which is nearer); the highest has none.
    let r = d.domain.radius_m;
    let expected = FractionHistogram::uniform(0.0, 1.0, 20).filled([600.0 / r, 300.0 / r]);
    assert_eq!(d.higher_peak_distance.as_ref(), Some(&expected));
    assert_ne!(d.isolation_distance, expected, "isolation is to higher ground, shorter");
}

#[test]
fn descriptor_of_a_dem_is_at_distance_zero_from_itself_and_validates() {
    let (oro, d) = Descriptor::of(&fbm_dem(201, 2, 1.0 / 3000.0, 500.0), &analysis()).unwrap();
    assert_eq!(d.peaks, oro.peaks.len());
    assert!(d.peaks > 10, "{} peaks", d.peaks);
    d.validate().unwrap();
    let dist = d.distance(&d).unwrap();
    assert_eq!(dist.mean_emd, 0.0);
    assert_eq!(dist.features.len(), 10);
    // Everything but the top peak has a key saddle and an isolation.
    let counted = |h: &FractionHistogram| h.fractions.iter().sum::<f64>();
    assert!((counted(&d.isolation_distance) - 1.0).abs() < 1e-9);
    // A corrupted histogram is a typed error naming the feature.
    let mut bad = d.clone();
    bad.prominence.fractions[0] += 0.5;
    assert!(matches!(bad.validate(), Err(OrometryError::InvalidDescriptor { feature: "prominence", .. })));
    let mut bins = d.clone();
    bins.relevance = FractionHistogram::uniform(0.0, 1.0, 7);
    assert!(matches!(d.distance(&bins), Err(OrometryError::InvalidDescriptor { feature: "relevance", .. })));
    // A JSON round trip keeps it.
    let back: Descriptor = serde_json::from_str(&serde_json::to_string(&d).unwrap()).unwrap();
    assert_eq!(back, d);
}

#[test]
fn nearest_neighbour_classification_tells_rolling_from_rugged_terrain() {
    let rolling = |seed| fbm_dem(201, seed, 1.0 / 4000.0, 300.0);
    let rugged = |seed| fbm_dem(201, seed, 1.0 / 1000.0, 800.0);
    let describe = |dem: &Heightfield| Descriptor::of(dem, &analysis()).unwrap().1;
    let references = [describe(&rolling(1)), describe(&rugged(1))];
    for seed in 2..5 {
        assert_eq!(classify(&describe(&rolling(seed)), &references).unwrap().map(|c| c.0), Some(0), "seed {seed}");
        assert_eq!(classify(&describe(&rugged(seed)), &references).unwrap().map(|c| c.0), Some(1), "seed {seed}");
    }
    assert_eq!(classify(&references[0], &[]).unwrap(), None);
}

/// Two cones and a third peak: a hand-built tree with known prominences.
fn small_tree() -> DivideTree {
    let peak = |x: f64, h: f64| TreePeak { position: DVec2::new(x, 0.0), elevation: h };
    let saddle =
        |x: f64, h: f64, a: u32, b: u32| TreeSaddle { position: DVec2::new(x, 0.0), elevation: h, peaks: [a, b] };
    DivideTree {
        peaks: vec![peak(0.0, 100.0), peak(100.0, 80.0), peak(200.0, 60.0)],
        saddles: vec![saddle(50.0, 50.0, 0, 1), saddle(150.0, 40.0, 1, 2)],
    }
}

#[test]
fn tree_prominence_and_edits() {
    let tree = small_tree();
    let oro = tree.orometry(0.0);
    assert_eq!(oro.prominence, vec![100.0, 30.0, 20.0]);
    assert_eq!(oro.key_saddle, vec![None, Some(0), Some(1)]);
    assert_eq!(oro.dominance(&tree, 0.0), vec![1.0, 30.0 / 80.0, 20.0 / 60.0]);

    // Pruning at 25 m drops the 60 m peak; the 80 m keeps its prominence.
    let pruned = tree.pruned(25.0, 0.0);
    assert_eq!(pruned.peaks.len(), 2);
    assert_eq!(pruned.orometry(0.0).prominence, vec![100.0, 30.0]);

    // Deleting the middle peak keeps its neighbours joined through the lower saddle.
    let mut t = tree.clone();
    t.delete_peak(1).unwrap();
    assert_eq!(t.peaks.len(), 2);
    assert_eq!(t.saddles.len(), 1);
    assert_eq!(t.saddles[0].elevation, 40.0);
    assert_eq!(t.orometry(0.0).prominence, vec![100.0, 20.0]);

    // Inserting, moving and deleting ridges.
    let mut t = tree.clone();
    let k = t
        .insert_peak(TreePeak { position: DVec2::new(0.0, 100.0), elevation: 70.0 }, 0, (DVec2::new(0.0, 50.0), 65.0))
        .unwrap();
    assert_eq!(t.orometry(0.0).prominence[k as usize], 5.0);
    t.move_saddle(2, DVec2::new(0.0, 40.0), Some(30.0)).unwrap();
    assert_eq!(t.orometry(0.0).prominence[k as usize], 40.0);
    t.delete_ridge(0).unwrap();
    assert_eq!(t.orometry(0.0).prominence[1], 80.0, "the 80 m peak tops its own tree now");

    // Edits that would break the tree are refused and leave it unchanged.
    let mut t = tree.clone();
    assert!(matches!(t.move_peak(2, DVec2::ZERO, Some(30.0)), Err(OrometryError::InvalidTree(_))));
    assert!(t.insert_ridge(0, 0, (DVec2::ZERO, 10.0)).is_err());
    assert!(t.insert_ridge(0, 9, (DVec2::ZERO, 10.0)).is_err());
    assert!(t.delete_peak(7).is_err());
    assert_eq!(t, tree);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// The divide tree exported from a grid analysis reproduces every non-top peak's prominence,
    /// and pruning it keeps the survivors' prominences.
    #[test]
    fn tree_of_an_analysis_reproduces_its_prominence(
        heights in proptest::collection::vec(0u8..12, 12 * 10),
        threshold in 0.0f64..6.0,
    ) {
        let grid = GridSpec::new(12, 10, DVec2::ZERO, DVec2::ONE).unwrap();
        let dem = Heightfield::from_samples(grid, heights.iter().map(|&h| f32::from(h)).collect()).unwrap();
        let oro = analyze(&dem, &AnalysisOptions::default()).unwrap();
        let tree = DivideTree::from_orometry(&oro);
        tree.validate().unwrap();
        let t = tree.orometry(0.0);
        for (k, p) in oro.peaks.iter().enumerate() {
            if p.key_saddle.is_some() {
                prop_assert_eq!(t.prominence[k], p.prominence, "peak {}", k);
                prop_assert_eq!(t.key_saddle[k].map(|s| s as usize), p.key_saddle);
            }
        }
        let kept: Vec<f64> = t.prominence.iter().copied().filter(|&p| p >= threshold).collect();
        let mut pruned = tree.pruned(threshold, 0.0).orometry(0.0).prominence;
        let mut kept_sorted = kept.clone();
        pruned.sort_by(f64::total_cmp);
        kept_sorted.sort_by(f64::total_cmp);
        prop_assert_eq!(pruned, kept_sorted);
    }
}

#[test]
fn generated_trees_match_the_target_prominence_and_dominance() {
    let target = target();
    let extent = Extent::new(DVec2::ZERO, DVec2::splat(18_000.0));
    let tree = generate_tree(&target, extent, &ControlMaps::default(), &[], &TreeOptions::default()).unwrap();
    tree.validate().unwrap();
    let expected = (target.density_per_km2 * 18.0 * 18.0).round() as usize;
    assert_eq!(tree.peaks.len(), expected);
    assert_eq!(tree.saddles.len(), expected - 1, "one spanning tree");
    let base = target.domain.min_elevation;
    let oro = tree.orometry(base);
    let prominence = FractionHistogram::uniform(0.0, 2000.0, 20).filled(oro.prominence.iter().copied());
    let dominance = FractionHistogram::uniform(0.0, 1.0, 20).filled(oro.dominance(&tree, target.domain.datum));
    let (pe, pm) = (prominence.emd(&target.prominence).unwrap(), prominence.max_bin_error(&target.prominence).unwrap());
    let (de, dm) = (dominance.emd(&target.dominance).unwrap(), dominance.max_bin_error(&target.dominance).unwrap());
    println!("tree: prominence EMD {pe:.4} max {pm:.4}; dominance EMD {de:.4} max {dm:.4}");
    assert!(pe < 0.01 && pm < 0.03, "prominence EMD {pe}, max bin error {pm}");
    assert!(de < 0.01 && dm < 0.03, "dominance EMD {de}, max bin error {dm}");
    // Ridges come from a Delaunay MST: no two ridges of peak-to-peak segments cross.
    for (i, a) in tree.saddles.iter().enumerate() {
        for b in &tree.saddles[i + 1..] {
            let [p, q] = a.peaks.map(|k| tree.peaks[k as usize].position);
            let [r, s] = b.peaks.map(|k| tree.peaks[k as usize].position);
            if a.peaks.iter().any(|k| b.peaks.contains(k)) {
                continue;
            }
            let o = |a: DVec2, b: DVec2, c: DVec2| (b - a).perp_dot(c - a);
            assert!(!(o(p, q, r) * o(p, q, s) < 0.0 && o(r, s, p) * o(r, s, q) < 0.0), "ridges cross");
        }
    }
    // Same seed ⇒ the same tree; another seed ⇒ another tree.
    assert_eq!(generate_tree(&target, extent, &ControlMaps::default(), &[], &TreeOptions::default()).unwrap(), tree);
    let other = TreeOptions { seed: 1, ..TreeOptions::default() };
    assert_ne!(generate_tree(&target, extent, &ControlMaps::default(), &[], &other).unwrap(), tree);
}

/// Each peak's distance to the nearest strictly higher peak (none for the highest).
fn nearest_higher(peaks: &[TreePeak]) -> Vec<f64> {
    peaks
        .iter()
        .filter_map(|p| {
            let higher = peaks.iter().filter(|q| q.elevation > p.elevation);
            higher.map(|q| q.position.distance(p.position)).min_by(f64::total_cmp)
        })
        .collect()
}

#[test]
fn a_generated_tree_keeps_every_peak_above_the_targets_threshold() {
    let target = target();
    assert_eq!(target.domain.min_prominence, 20.0);
    let extent = Extent::new(DVec2::ZERO, DVec2::splat(18_000.0));
    let tree = generate_tree(&target, extent, &ControlMaps::default(), &[], &TreeOptions::default()).unwrap();
    let base = target.domain.min_elevation;
    let oro = tree.orometry(base);
    // The target's peaks were counted at 20 m; the rounds keep 2 m above that, so the terrain
    // analysed at 20 m keeps every peak (a peak too low above the base to be that prominent
    // cannot, and there is none here).
    let least = (0..tree.peaks.len()).filter(|&k| oro.key_saddle[k].is_some()).map(|k| oro.prominence[k]);
    let least = least.fold(f64::INFINITY, f64::min);
    assert!(least >= 22.0 - 1e-9, "least prominence {least}");
    // The lowest bin is spread above the floor as the target's is, not piled on it.
    let low: Vec<f64> =
        (0..tree.peaks.len()).filter(|&k| oro.key_saddle[k].is_some()).map(|k| oro.prominence[k]).collect();
    let piled = low.iter().filter(|&&p| p < 23.0).count();
    let under_40 = low.iter().filter(|&&p| p < 40.0).count();
    println!("{piled} of {} peaks within 1 m of the floor, {under_40} under 40 m", low.len());
    assert!(piled * 4 < low.len() && under_40 * 10 > low.len());
}

#[test]
fn a_generated_tree_spaces_its_peaks_as_the_target_does() {
    // Darts are accepted by the distance to the nearest higher peak, each distance bin taking
    // only its share of the peaks: the tree's distances follow the target's histogram of them.
    let target = target();
    let wanted = target.higher_peak_distance.clone().unwrap();
    let extent = Extent::new(DVec2::ZERO, DVec2::splat(18_000.0));
    let tree = generate_tree(&target, extent, &ControlMaps::default(), &[], &TreeOptions::default()).unwrap();
    let r = target.domain.radius_m;
    let got = FractionHistogram::uniform(0.0, 1.0, 20).filled(nearest_higher(&tree.peaks).iter().map(|d| d / r));
    let error = got.max_bin_error(&wanted).unwrap();
    println!("nearest higher peak: max bin error {error:.4} over {} peaks", tree.peaks.len());
    assert!(error < 0.1, "max bin error {error}");
}

#[test]
fn density_control_keeps_peaks_out_of_zeroed_areas() {
    let target = target();
    let extent = Extent::new(DVec2::ZERO, DVec2::splat(9000.0));
    let grid = GridSpec::from_extent(31, 31, extent).unwrap();
    // Peaks only in the western half.
    let density = Heightfield::from_fn(grid, |p| if p.x < 4000.0 { 1.0 } else { 0.0 }).unwrap();
    let controls = ControlMaps { peak_density: Some(density), elevation: None };
    let options = TreeOptions { dart_attempts: 400, ..TreeOptions::default() };
    let tree = generate_tree(&target, extent, &controls, &[], &options).unwrap();
    let west = tree.peaks.iter().filter(|p| p.position.x < 4500.0).count();
    assert!(west as f64 >= 0.9 * tree.peaks.len() as f64, "{west} of {} peaks in the west", tree.peaks.len());
}

#[test]
fn synthesized_terrain_keeps_its_orometry_pins_and_drainage() {
    let target = target();
    let n = 241;
    let grid = GridSpec::from_extent(n, n, Extent::new(DVec2::ZERO, DVec2::splat(30.0 * (n - 1) as f64))).unwrap();
    let pinned = [TreePeak { position: grid.position(60, 170), elevation: target.domain.max_elevation + 50.0 }];
    let options = SynthesisOptions::default();
    let (tree, hf) = synthesize(&target, &grid, &ControlMaps::default(), &pinned, &options, |_, _| {}).unwrap();
    assert!(!hf.has_no_data());
    assert!(!has_endorheic_basins(&hf, NoData::Outlet), "synthesized terrain has a closed basin");
    // The pinned peak is there, at its height, and it is the summit.
    assert!(tree.peaks.iter().any(|p| p.position == pinned[0].position && p.elevation == pinned[0].elevation));
    assert_eq!(hf.value(60, 170), pinned[0].elevation as f32);
    let (oro, got) = Descriptor::with_radius(&hf, &analysis(), Some(target.domain.radius_m)).unwrap();
    assert_eq!(oro.peaks[0].cell, [60, 170]);
    // Tree peaks prominent in the tree are found by the analysis within two cells and 1 m (the
    // last sweep cuts the bridges that flanks of other branches build over their cols).
    let tree_oro = tree.orometry(target.domain.min_elevation);
    let prominent: Vec<&TreePeak> =
        tree.peaks.iter().enumerate().filter(|(k, _)| tree_oro.prominence[*k] >= 40.0).map(|(_, p)| p).collect();
    let found = prominent
        .iter()
        .filter(|p| {
            oro.peaks.iter().any(|q| {
                DVec2::from(q.position).distance(p.position) <= 61.0 && (q.elevation - p.elevation).abs() <= 1.0
            })
        })
        .count();
    println!("{found} of {} prominent tree peaks found", prominent.len());
    assert!(found as f64 >= 0.95 * prominent.len() as f64, "{found} of {} prominent tree peaks found", prominent.len());
    let distance = got.distance(&target).unwrap();
    println!("terrain: mean EMD {:.4}", distance.mean_emd);
    for (name, emd, max) in &distance.features {
        println!("  {name:<22} EMD {emd:.4} max {max:.4}");
    }
    assert!(distance.mean_emd < 0.06, "mean EMD {}", distance.mean_emd);
    let (pe, _) = distance.feature("prominence").unwrap();
    assert!(pe < 0.03, "prominence EMD {pe}");
}

#[test]
fn erodibility_and_noise_wavelength_shape_the_terrain() {
    // A generated tree over 6 km at 30 m: each option, changed alone, changes the terrain.
    let target = target();
    let extent = Extent::new(DVec2::ZERO, DVec2::splat(6000.0));
    let tree = generate_tree(&target, extent, &ControlMaps::default(), &[], &TreeOptions::default()).unwrap();
    let grid = GridSpec::from_extent(201, 201, extent).unwrap();
    let base = target.domain.min_elevation;
    let run = |o: &relief_orometry::TerrainOptions| terrain_from_tree(&tree, base, &grid, o, |_, _| {}).unwrap();
    let default = relief_orometry::TerrainOptions::default();
    let reference = run(&default);
    let changed = |o: relief_orometry::TerrainOptions| {
        let hf = run(&o);
        hf.samples().iter().zip(reference.samples()).filter(|(a, b)| a != b).count()
    };
    // The stream-power law's own default erodibility (2e-5) would not do: ours is the option's.
    for erodibility in [2e-5, 4e-5] {
        assert!(changed(relief_orometry::TerrainOptions { erodibility, ..default.clone() }) > 100);
    }
    assert!(changed(relief_orometry::TerrainOptions { noise_wavelength_m: 700.0, ..default.clone() }) > 100);
}

#[test]
fn synthesis_is_identical_for_any_thread_count() {
    let target = target();
    let grid = GridSpec::from_extent(121, 121, Extent::new(DVec2::ZERO, DVec2::splat(3600.0))).unwrap();
    let options = SynthesisOptions::default();
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| synthesize(&target, &grid, &ControlMaps::default(), &[], &options, |_, _| {}).unwrap())
    };
    let (t1, h1) = run(1);
    let (t2, h2) = run(2);
    assert_eq!(t1, t2);
    let bits = |h: &Heightfield| h.samples().iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&h1), bits(&h2));
}

#[test]
fn bad_synthesis_input_is_a_typed_error() {
    let target = target();
    let extent = Extent::new(DVec2::ZERO, DVec2::splat(9000.0));
    let none = ControlMaps::default();
    let opts = TreeOptions::default();
    // A control map over another extent.
    let wrong =
        Heightfield::zeros(GridSpec::from_extent(10, 10, Extent::new(DVec2::ZERO, DVec2::splat(5000.0))).unwrap());
    let controls = ControlMaps { peak_density: None, elevation: Some(wrong) };
    assert!(matches!(
        generate_tree(&target, extent, &controls, &[], &opts),
        Err(OrometryError::ControlMapExtent { name: "elevation", .. })
    ));
    // A density map that is zero everywhere, or negative.
    let grid = GridSpec::from_extent(10, 10, extent).unwrap();
    for v in [0.0, -1.0] {
        let controls = ControlMaps { peak_density: Some(Heightfield::filled(grid, v).unwrap()), elevation: None };
        assert!(matches!(
            generate_tree(&target, extent, &controls, &[], &opts),
            Err(OrometryError::InvalidControlMap { name: "peak_density", .. })
        ));
    }
    // A NaN control sample.
    let mut nan = Heightfield::filled(grid, 1.0).unwrap();
    nan.samples_mut()[3] = f32::NAN;
    let controls = ControlMaps { peak_density: Some(nan), elevation: None };
    assert!(matches!(
        generate_tree(&target, extent, &controls, &[], &opts),
        Err(OrometryError::InvalidControlMap { .. })
    ));
    // Empty histograms: nothing to sample elevations from.
    let mut empty = target.clone();
    empty.normalized_elevation = FractionHistogram::uniform(0.0, 1.0, 20);
    assert!(matches!(
        generate_tree(&empty, extent, &none, &[], &opts),
        Err(OrometryError::InvalidDescriptor { feature: "normalized_elevation", .. })
    ));
    // No peaks at all.
    let zero = TreeOptions { peaks: Some(0), ..TreeOptions::default() };
    assert!(matches!(
        generate_tree(&target, extent, &none, &[], &zero),
        Err(OrometryError::InvalidOption { name: "peaks", .. })
    ));
    let many = TreeOptions { peaks: Some(10_000_000), ..TreeOptions::default() };
    assert!(matches!(generate_tree(&target, extent, &none, &[], &many), Err(OrometryError::TooManyPeaks { .. })));
    // Pinned peaks outside the domain or below the base.
    let outside = [TreePeak { position: DVec2::new(-5.0, 10.0), elevation: 2000.0 }];
    assert!(matches!(
        generate_tree(&target, extent, &none, &outside, &opts),
        Err(OrometryError::InvalidPinnedPeak { index: 0, .. })
    ));
    let low = [TreePeak { position: DVec2::splat(100.0), elevation: target.domain.min_elevation - 1.0 }];
    assert!(matches!(generate_tree(&target, extent, &none, &low, &opts), Err(OrometryError::InvalidPinnedPeak { .. })));
    let bad_rho = TreeOptions { rho: f64::NAN, ..TreeOptions::default() };
    assert!(matches!(
        generate_tree(&target, extent, &none, &[], &bad_rho),
        Err(OrometryError::InvalidOption { name: "rho", .. })
    ));
    // A tree with a peak off the grid, or a saddle above its peaks.
    let grid = GridSpec::from_extent(11, 11, Extent::new(DVec2::ZERO, DVec2::splat(100.0))).unwrap();
    let mut tree = small_tree();
    assert!(matches!(
        terrain_from_tree(&tree, 0.0, &grid, &relief_orometry::TerrainOptions::default(), |_, _| {}),
        Err(OrometryError::InvalidTree(_))
    ));
    tree.saddles[0].elevation = 1000.0;
    assert!(matches!(tree.validate(), Err(OrometryError::InvalidTree(_))));
    // A one-peak tree makes a cone-like hill.
    let single =
        DivideTree { peaks: vec![TreePeak { position: DVec2::splat(50.0), elevation: 30.0 }], saddles: vec![] };
    let hf = terrain_from_tree(&single, 0.0, &grid, &relief_orometry::TerrainOptions::default(), |_, _| {}).unwrap();
    assert_eq!(hf.value(5, 5), 30.0);
    assert!(hf.samples().iter().all(|&v| (0.0..=30.0).contains(&v)));
    // Erosion scales must be positive cells, at most eight of them.
    for scales in [vec![0.0], vec![f64::NAN], vec![30.0; 9]] {
        let bad = relief_orometry::TerrainOptions { erosion_scales_m: scales, ..Default::default() };
        match terrain_from_tree(&single, 0.0, &grid, &bad, |_, _| {}) {
            Err(OrometryError::InvalidOption { name: "erosion_scales_m", .. }) => {}
            other => panic!("{other:?}"),
        }
    }
    // A meshing distance far too fine for the domain (10^10 routing cells) fails before allocating.
    let fine = relief_orometry::TerrainOptions { lambda_m: 0.002, ..relief_orometry::TerrainOptions::default() };
    assert!(fine.mesh_samples(&single, grid.extent()) > 1e10);
    match terrain_from_tree(&single, 0.0, &grid, &fine, |_, _| {}) {
        Err(e @ OrometryError::MeshTooFine { limit: relief_orometry::MAX_MESH_SAMPLES, .. }) => {
            assert!(e.to_string().contains("raise lambda_m"), "{e}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn an_overcrowded_domain_still_gets_distinct_peaks_and_a_spanning_tree() {
    // 400 peaks in 2 × 2 km cannot keep 200 m apart: darts that all land too close fall back to the
    // roomiest candidate, never to a duplicate position.
    let target = target();
    let extent = Extent::new(DVec2::ZERO, DVec2::splat(2000.0));
    let options = TreeOptions { peaks: Some(400), dart_attempts: 8, ..TreeOptions::default() };
    let tree = generate_tree(&target, extent, &ControlMaps::default(), &[], &options).unwrap();
    let mut seen = std::collections::HashSet::new();
    assert!(tree.peaks.iter().all(|p| seen.insert((p.position.x.to_bits(), p.position.y.to_bits()))));
    assert_eq!(tree.saddles.len(), 399);
    tree.validate().unwrap();
}
