//! Vector terrains through the facade: Table 3's trend on the real Jacksboro DEM, the crest
//! skeleton from hydrology, and the `gaussian` scene kind.

use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

use glam::DVec2;
use relief::gaussian_terrain::{VectorizeOptions, vectorize};
use relief::pipeline::{Progress, generate};
use relief::scene::Scene;
use relief::vector::crest_skeleton;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

struct Quiet;
impl Progress for Quiet {
    fn start(&mut self, _: &'static str) {}
    fn finish(&mut self, _: &'static str, _: std::time::Duration) {}
}

/// Table 3 of the paper: the loss falls as the primitive count grows, here on a real DEM.
#[test]
fn loss_falls_with_the_primitive_count_on_a_real_dem() {
    let dem = relief::io::read(root().join("fixtures/dem/jacksboro.asc")).unwrap();
    let mut last = (f64::INFINITY, f64::INFINITY);
    for count in [50, 200, 800] {
        let options = VectorizeOptions { primitives: count, iterations: 60, resolution: 128, ..Default::default() };
        let fit = vectorize(&dem, &options, |_| ControlFlow::Continue(())).unwrap();
        let r = &fit.report;
        assert!(r.l1_normalized < last.0, "{count}: ℓ1 {} not below {}", r.l1_normalized, last.0);
        assert!(r.loss.total < last.1, "{count}: loss {} not below {}", r.loss.total, last.1);
        last = (r.l1_normalized, r.loss.total);
    }
    // 800 primitives on a 403 × 344 ridge-and-valley DEM: within 3 % of the relief on average.
    assert!(last.0 < 0.06, "ℓ1 {}", last.0);
}

/// The Salish Sea DEM with its sea set to 0, as land-only DEMs store it
/// (fixtures/dem/salish-land.tif): the sea is 44 % of the samples.
fn salish_land() -> relief::heightfield::Heightfield {
    relief::io::read(root().join("fixtures/dem/salish-land.tif")).unwrap()
}

/// Mean |error| over the samples whose 5 × 5 neighbourhood is all sea (0) in the DEM.
fn open_sea_error(dem: &relief::heightfield::Heightfield, back: &relief::heightfield::Heightfield) -> (f64, usize) {
    let (nx, ny) = (dem.nx(), dem.ny());
    let (mut sum, mut count) = (0.0, 0);
    for j in 2..ny - 2 {
        for i in 2..nx - 2 {
            if (j - 2..=j + 2).all(|jj| (i - 2..=i + 2).all(|ii| dem.value(ii, jj) == 0.0)) {
                sum += f64::from(back.value(i, j).abs());
                count += 1;
            }
        }
    }
    (sum / count.max(1) as f64, count)
}

/// A real coast vectorized: the sea stays exactly at sea level and nothing dips below it,
/// because the fit gets a floor at the DEM's minimum; without the floor the same fit digs
/// below the sea by more than 0.5 % of the relief and ripples over it.
#[test]
fn a_vectorized_coast_keeps_its_sea_flat() {
    use relief::gaussian_terrain::{RasterOptions, rasterize};
    let dem = salish_land();
    let relief = f64::from(dem.min_max().unwrap().1);
    let options = VectorizeOptions { primitives: 250, iterations: 100, ..Default::default() };
    let run = |options: &VectorizeOptions| {
        let fit = vectorize(&dem, options, |_| ControlFlow::Continue(())).unwrap();
        let back = rasterize(&fit.terrain, dem.grid(), &RasterOptions::default()).unwrap();
        (fit, back)
    };
    let (fit, back) = run(&options);
    assert_eq!(fit.terrain.floor, Some(0.0));
    let (lowest, highest) = back.min_max().unwrap();
    assert_eq!(lowest, 0.0, "nothing below the sea");
    assert!(f64::from(highest) <= 1.005 * relief, "{highest} above the DEM's top {relief} by more than 0.5 %");
    let (sea, count) = open_sea_error(&dem, &back);
    assert!(count > 2000, "{count} open-sea samples");
    assert!(sea < 1e-3 * relief, "open sea {sea} m off on average");
    assert!(fit.report.l1_normalized < 0.1, "ℓ1 {}", fit.report.l1_normalized);

    let (_, unfloored) = run(&VectorizeOptions { keep_range: false, ..options });
    let (lowest, _) = unfloored.min_max().unwrap();
    assert!(f64::from(lowest) < -0.005 * relief, "without the floor the sea dips to {lowest} only");
    let (rippled, _) = open_sea_error(&dem, &unfloored);
    assert!(rippled > 3.0 * sea, "open sea {rippled} m off without the floor, {sea} m with it");
}

/// The Salish coast (sea at the floor, 0) with a flat lake on its land: flat ground above the
/// floor weighs more from the first step, as on a DEM without a floor, so the lake stays far
/// flatter than the plain sum leaves it: 0.60 of its error, summed over two budgets; 0.71 when
/// the lake is weighed only in the last fifth, as the floor's own flat ground is.
#[test]
fn a_lake_on_a_floored_coast_stays_flat() {
    use relief::gaussian_terrain::{RasterOptions, rasterize};
    const SIDE: usize = 12;
    let mut dem = salish_land();
    let (nx, ny) = (dem.nx(), dem.ny());
    let land = |i0: usize, j0: usize, dem: &relief::heightfield::Heightfield| {
        (j0..j0 + SIDE).all(|j| (i0..i0 + SIDE).all(|i| dem.value(i, j) > 0.0))
    };
    let (i0, j0) = (3..ny - SIDE - 3)
        .step_by(SIDE)
        .flat_map(|j| (3..nx - SIDE - 3).step_by(SIDE).map(move |i| (i, j)))
        .find(|&(i, j)| land(i, j, &dem))
        .expect("a block of land");
    let lake: Vec<(usize, usize)> = (j0..j0 + SIDE).flat_map(|j| (i0..i0 + SIDE).map(move |i| (i, j))).collect();
    let level = lake.iter().map(|&(i, j)| dem.value(i, j)).sum::<f32>() / lake.len() as f32;
    for &(i, j) in &lake {
        dem.set(i, j, level).unwrap();
    }
    let relief = f64::from(dem.min_max().unwrap().1);
    let lake_error = |options: &VectorizeOptions| {
        let fit = vectorize(&dem, options, |_| ControlFlow::Continue(())).unwrap();
        assert_eq!(fit.terrain.floor, options.keep_range.then_some(0.0), "the sea is the floor");
        let back = rasterize(&fit.terrain, dem.grid(), &RasterOptions::default()).unwrap();
        let sum: f64 = lake.iter().map(|&(i, j)| f64::from((back.value(i, j) - level).abs())).sum();
        sum / lake.len() as f64 / relief
    };
    let (mut kept, mut plain) = (0.0, 0.0);
    for primitives in [100, 200] {
        let options = VectorizeOptions { primitives, iterations: 200, ..Default::default() };
        kept += lake_error(&options);
        plain += lake_error(&VectorizeOptions { keep_range: false, ..options });
    }
    assert!(kept < 0.65 * plain, "mean error over the lake: {kept} kept, {plain} plain (of the relief, summed)");
}

/// Luxembourg's SRTM elevations with the no-data beyond its border filled at the lowest
/// elevation, as a user fills it: a 100 m step all around. The plain fit digs below the DEM's
/// range along the step (and, with only the floor, a peak overshoots the top by 3 %); the kept
/// range stays within 0.5 % of the relief. Over the open flat beyond the border (5 × 5 samples
/// at the floor), the land's primitives leaked bumps of 1.5–23 % of the relief at this budget
/// (seeds 0–5) until the last fifth of the fit weighed the floor's flat ground too; weighed
/// earlier, it reshapes the land (ℓ₁ 0.080 from the tenth step, 0.0753 in the last fifth).
/// With the flat weight of the rest of the fit there (4), seeds 4 and 5 at 86 primitives still
/// left bumps of 26 % and 12 %; the settling weight (32) holds them under 0.5 %. Seed 31 kept one
/// of 2.8 % until the fit held its primitives within the pruning's elongation: a thin negative
/// primitive along the border (23:1) cancelled land primitives there and was pruned after the fit.
#[test]
fn a_filled_border_stays_within_the_dem_range() {
    use relief::gaussian_terrain::{RasterOptions, rasterize};
    let mut dem = relief::io::read(root().join("fixtures/dem/luxembourg.tif")).unwrap();
    let (lo, hi) = dem.min_max().unwrap();
    dem.fill_no_data(lo).unwrap();
    let relief = f64::from(hi - lo);
    let (nx, ny) = (dem.nx(), dem.ny());
    let open_flat: Vec<usize> = (0..nx * ny)
        .filter(|&k| {
            let (i, j) = (k % nx, k / nx);
            (j.saturating_sub(2)..(j + 3).min(ny))
                .all(|jj| (i.saturating_sub(2)..(i + 3).min(nx)).all(|ii| dem.value(ii, jj) == lo))
        })
        .collect();
    assert!(open_flat.len() > 500, "{} open-flat samples", open_flat.len());
    let fit = |options: &VectorizeOptions| {
        let fit = vectorize(&dem, options, |_| ControlFlow::Continue(())).unwrap();
        let back = rasterize(&fit.terrain, dem.grid(), &RasterOptions::default()).unwrap();
        let (a, b) = back.min_max().unwrap();
        let bump = open_flat.iter().map(|&k| f64::from(back.samples()[k] - lo).abs()).fold(0.0, f64::max);
        let l1 = fit.report.l1_normalized;
        (f64::from(lo - a).max(0.0) / relief, f64::from(b - hi).max(0.0) / relief, bump / relief, l1)
    };
    let options = VectorizeOptions { primitives: 90, iterations: 200, ..Default::default() };
    let (below, above, bump, l1) = fit(&options);
    assert!(below == 0.0 && above <= 0.005, "beyond the range by {below} below, {above} above");
    assert!(bump <= 0.005, "a bump of {bump} of the relief over the open flat");
    assert!(l1 < 0.078, "ℓ₁ {l1}");
    for seed in [4, 5, 31] {
        let (_, _, bump, _) = fit(&VectorizeOptions { primitives: 86, seed, ..options });
        assert!(bump <= 0.005, "seed {seed}: a bump of {bump} of the relief over the open flat");
    }
    let (below, above, _, _) = fit(&VectorizeOptions { keep_range: false, ..options });
    assert!(below > 0.02, "the plain sum only {below} below ({above} above)");
}

/// The Salish topobathy's flat ground above its minimum (shores and flats at 0 m, between the
/// sea floor and the mountains): the kept range weighs errors there more, so the fit strays from
/// it far less than the plain sum does.
#[test]
fn flat_ground_above_the_minimum_stays_nearly_flat() {
    use relief::gaussian_terrain::{RasterOptions, rasterize};
    let dem = relief::io::read(root().join("fixtures/dem/salish.tif")).unwrap();
    let (lo, hi) = dem.min_max().unwrap();
    let relief = f64::from(hi - lo);
    let (nx, ny) = (dem.nx(), dem.ny());
    let flat: Vec<usize> = (0..nx * ny)
        .filter(|&k| {
            let (i, j, h) = (k % nx, k / nx, dem.samples()[k]);
            i >= 1 && j >= 1 && i + 1 < nx && j + 1 < ny && h > lo && {
                (j - 1..=j + 1).all(|jj| (i - 1..=i + 1).all(|ii| dem.value(ii, jj) == h))
            }
        })
        .collect();
    assert!(flat.len() > 50, "{} flat samples", flat.len());
    let mean_error = |options: &VectorizeOptions| {
        let fit = vectorize(&dem, options, |_| ControlFlow::Continue(())).unwrap();
        let back = rasterize(&fit.terrain, dem.grid(), &RasterOptions::default()).unwrap();
        let sum: f64 = flat.iter().map(|&k| f64::from((back.samples()[k] - dem.samples()[k]).abs())).sum();
        sum / flat.len() as f64 / relief
    };
    // Three budgets, so that one fit's luck does not decide.
    let (mut kept, mut plain) = (0.0, 0.0);
    for primitives in [100, 200, 400] {
        let options = VectorizeOptions { primitives, iterations: 200, ..Default::default() };
        kept += mean_error(&options);
        plain += mean_error(&VectorizeOptions { keep_range: false, ..options });
    }
    assert!(kept < 0.75 * plain, "mean error over the flat: {kept} kept, {plain} plain (of the relief, summed)");
}

/// The paper's choices (densification by positional gradients, its Adam as the authors' code
/// runs it: one constant step size in their parametrisation and PyTorch's moment decays; its
/// kernel's exponents) against ours on a real DEM at the same budget:
/// each changes the fit, and ours reaches the lower error (the full table is in
/// docs/benchmarks.md; at the paper's density the two densifications tie on this DEM, so the
/// test runs at 4× it, where they differ by 5 %).
#[test]
fn our_fitting_choices_beat_the_papers_on_a_real_dem() {
    use relief::gaussian_terrain::Densify;
    let dem = relief::io::read(root().join("fixtures/dem/salish.tif")).unwrap();
    let ours = VectorizeOptions { primitives: 437, iterations: 200, ..Default::default() };
    let l1 = |options: &VectorizeOptions| {
        vectorize(&dem, options, |_| ControlFlow::Continue(())).unwrap().report.l1_normalized
    };
    let mine = l1(&ours);
    let densify = l1(&VectorizeOptions { densify: Densify::PositionalGradient, ..ours.clone() });
    let steps = l1(&VectorizeOptions { uniform_steps: true, ..ours.clone() });
    let exponents = l1(&VectorizeOptions { beta_range: [2.0, 4.0], ..ours.clone() });
    assert!(
        mine < densify && mine < steps && mine < exponents,
        "ours {mine}, positional-gradient densify {densify}, the paper's steps {steps}, its exponents {exponents}"
    );
}

/// Crests of a ridge made of two Gaussians run along its top.
#[test]
fn crest_skeleton_follows_the_ridge() {
    use relief::gaussian_terrain::{Gaussian, RasterOptions, VectorTerrain, rasterize};
    use relief::heightfield::{Extent, GridSpec};
    let ridge = VectorTerrain::new(vec![
        Gaussian { center: [500.0, 500.0], sigma: [300.0, 60.0], theta: 0.0, amplitude: 500.0, beta: 2.0 },
        Gaussian { center: [500.0, 800.0], sigma: [60.0, 200.0], theta: 0.0, amplitude: 300.0, beta: 2.0 },
    ]);
    let grid = GridSpec::from_extent(129, 129, Extent::new(DVec2::ZERO, DVec2::splat(1000.0))).unwrap();
    let hf = rasterize(&ridge, &grid, &RasterOptions::default()).unwrap();
    let skeleton = crest_skeleton(&hf, 20, 40.0).unwrap();
    assert!(skeleton.nodes.len() >= 5, "{} nodes", skeleton.nodes.len());
    // Nodes along the main ridge sit on its axis y = 500 (where x is within its extent).
    let on_axis =
        skeleton.nodes.iter().filter(|p| (250.0..750.0).contains(&p[0]) && (p[1] - 500.0).abs() < 30.0).count();
    assert!(on_axis >= 3, "{:?}", skeleton.nodes);
    for &[a, b] in &skeleton.edges {
        assert!(DVec2::from(skeleton.nodes[a]).distance(DVec2::from(skeleton.nodes[b])) >= 40.0);
    }
}

/// A scene's DEM source takes `details` (error-map detail primitives, so the vector terrain
/// restores the DEM), `keep_range` (false: the paper's plain sum, no floor) and `beta_range`
/// (the primitives' exponents; `[2, 4]` the paper's).
#[test]
fn a_scene_vectorizes_a_dem_with_details_and_the_range_choice() {
    let dem = root().join("fixtures/dem/salish-land.tif");
    let truth = relief::io::read(&dem).unwrap();
    let e = truth.extent();
    let scene = |source: serde_json::Value| {
        let json = serde_json::json!({
            "version": 1,
            "generator": { "gaussian": { "source": source } },
            "domain": { "min": e.min.to_array(), "max": e.max.to_array() },
            "reconstruction": { "resolution": [120, 91] },
        });
        let scene = Scene::from_json(&json.to_string()).unwrap();
        generate(&scene, root().as_path(), &mut Quiet).unwrap()
    };
    let source = |extra: serde_json::Value| {
        let mut s = serde_json::json!({ "kind": "dem", "path": dem, "primitives": 120, "iterations": 40 });
        s.as_object_mut().unwrap().extend(extra.as_object().unwrap().clone());
        s
    };
    let mean_error = |t: &relief::Terrain| {
        let sum: f64 = truth.samples().iter().zip(t.heightfield.samples()).map(|(a, b)| f64::from((a - b).abs())).sum();
        sum / truth.samples().len() as f64
    };
    let plain = scene(source(serde_json::json!({})));
    let detailed = scene(source(serde_json::json!({ "details": 2.0 })));
    let unkept = scene(source(serde_json::json!({ "keep_range": false })));
    let floor = |t: &relief::Terrain| t.vector.as_ref().unwrap().terrain.floor;
    assert_eq!(floor(&plain), Some(0.0));
    assert_eq!(floor(&unkept), None);
    assert!(unkept.heightfield.min_max().unwrap().0 < 0.0, "the plain sum dips below the sea");
    assert!(!detailed.vector.as_ref().unwrap().terrain.details.is_empty());
    let (coarse, fine) = (mean_error(&plain), mean_error(&detailed));
    assert!(fine < 0.01 * coarse && fine < 1.0, "details: {fine} m against {coarse} m without");
    let betas = |t: &relief::Terrain| -> Vec<f64> {
        t.vector.as_ref().unwrap().terrain.primitives.iter().map(|g| g.beta).collect()
    };
    let paper = betas(&scene(source(serde_json::json!({ "beta_range": [2.0, 4.0] }))));
    assert!(paper.iter().all(|b| (2.0..=4.0).contains(b)), "{paper:?}");
    assert!(betas(&plain).iter().any(|b| !(2.0..=4.0).contains(b)));
}

/// A DEM with no-data (Luxembourg, masked beyond its border as SRTM extracts are) is refused
/// by a scene unless `fill_no_data` says how to fill it; `"min"` fills at the lowest elevation,
/// which becomes the terrain's floor, so the border rasterizes flat; an elevation fills
/// at that elevation; anything else is refused with what the field takes.
#[test]
fn a_scene_fills_a_dems_no_data_when_asked() {
    let dem = root().join("fixtures/dem/luxembourg.tif");
    let truth = relief::io::read(&dem).unwrap();
    let (lo, hi) = truth.min_max().unwrap();
    let (nx, ny) = (truth.nx(), truth.ny());
    let scene = |fill: Option<serde_json::Value>| {
        let mut source = serde_json::json!({ "kind": "dem", "path": dem, "primitives": 86, "iterations": 200 });
        if let Some(fill) = fill {
            source["fill_no_data"] = fill;
        }
        let json = serde_json::json!({
            "version": 1,
            "generator": { "gaussian": { "source": source } },
            "reconstruction": { "resolution": [nx, ny] },
        });
        let scene = Scene::from_json(&json.to_string()).map_err(|e| e.to_string())?;
        generate(&scene, root().as_path(), &mut Quiet).map_err(|e| e.to_string())
    };
    let err = scene(None).err().unwrap();
    assert!(err.contains("generator.gaussian.source.fill_no_data") && err.contains("3942 no-data"), "{err}");
    let err = scene(Some(serde_json::json!("max"))).err().unwrap();
    assert!(err.contains("max: give `min`"), "{err}");
    let err = scene(Some(serde_json::json!(true))).err().unwrap();
    assert!(err.contains("true: give \"min\""), "{err}");
    let filled = scene(Some(serde_json::json!("min"))).unwrap();
    assert_eq!(filled.vector.as_ref().unwrap().terrain.floor, Some(f64::from(lo)));
    // The samples that were no-data, away from the border (5 × 5 of them), stay at the floor.
    let no_data = |i: usize, j: usize| truth.value(i, j).is_nan();
    let open: Vec<(usize, usize)> = (2..ny - 2)
        .flat_map(|j| (2..nx - 2).map(move |i| (i, j)))
        .filter(|&(i, j)| (j - 2..=j + 2).all(|jj| (i - 2..=i + 2).all(|ii| no_data(ii, jj))))
        .collect();
    assert!(open.len() > 1000, "{} open no-data samples", open.len());
    let relief = f64::from(hi - lo);
    let worst = open.iter().map(|&(i, j)| f64::from(filled.heightfield.value(i, j) - lo)).fold(0.0, f64::max);
    assert!(worst <= 0.005 * relief, "{worst} m above the floor");
    // At an elevation above the lowest there is no floor: the fill is the terrain's there.
    let high = scene(Some(serde_json::json!(300.0))).unwrap();
    assert_eq!(high.vector.as_ref().unwrap().terrain.floor, None);
    let mean: f64 = open.iter().map(|&(i, j)| f64::from(high.heightfield.value(i, j))).sum::<f64>() / open.len() as f64;
    assert!((mean - 300.0).abs() < 10.0, "the open fill at {mean} m, filled at 300 m");
}

/// The fixture scene applies every tool and is deterministic.
#[test]
fn gaussian_scenes_generate_deterministically() {
    let path = root().join("fixtures/scenes/gaussian-massif.json");
    let scene = Scene::from_json(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let base = path.parent().unwrap();
    let a = generate(&scene, base, &mut Quiet).unwrap();
    let b = generate(&scene, base, &mut Quiet).unwrap();
    assert_eq!(a.heightfield.samples(), b.heightfield.samples());
    // The pasted volcano and the copied peak add primitives; the deletion removed one.
    assert_eq!(a.summary.gaussian.as_ref().unwrap().primitives, 12 + 3 + 1 - 1);
    // Errors name the operation.
    let mut bad = scene.clone();
    let relief::scene::Generator::Gaussian(g) = &mut bad.generator else { panic!("a gaussian scene") };
    g.operations[1] = serde_json::from_value(serde_json::json!({
        "op": "twist", "region": { "shape": "circle", "center": [0, 0], "radius": -1 }, "angle": 1, "falloff": 1
    }))
    .unwrap();
    let err = generate(&bad, base, &mut Quiet).err().unwrap().to_string();
    assert!(err.contains("generator.gaussian.operations[1]"), "{err}");
}

/// A round trip: a gaussian scene writes its edited vector terrain and crest skeleton; a scene
/// that reloads the terrain rasterizes the same bytes, and its crest tools take the exported
/// node ids (the same node as `near` at the node's position, and a real move).
#[test]
fn edited_vector_terrains_and_skeletons_round_trip() {
    let path = root().join("fixtures/scenes/gaussian-massif.json");
    let mut scene = Scene::from_json(&std::fs::read_to_string(&path).unwrap()).unwrap();
    scene.outputs.vector_terrain = Some("edited.json".into());
    scene.outputs.skeleton = Some("skeleton.geojson".into());
    let out = tempfile::tempdir().unwrap();
    let (first, written) = relief::pipeline::run(&scene, path.parent().unwrap(), out.path(), &mut Quiet).unwrap();
    assert!(
        written.contains(&out.path().join("edited.json")) && written.contains(&out.path().join("skeleton.geojson"))
    );
    assert_eq!(
        scene.output_files().iter().filter(|f| f.ends_with("edited.json") || f.ends_with("skeleton.geojson")).count(),
        2
    );

    // Reload: no domain in the scene, no tools; the terrain's recorded domain gives the grid.
    let reload = |operations: serde_json::Value| {
        let json = serde_json::json!({
            "version": 1,
            "reconstruction": { "resolution": scene.reconstruction.resolution },
            "generator": { "gaussian": {
                "source": { "kind": "terrain", "path": "edited.json" },
                "skeleton": { "spacing": 40 },
                "operations": operations,
            } },
        });
        let reloaded = Scene::from_json(&json.to_string()).unwrap();
        generate(&reloaded, out.path(), &mut Quiet).unwrap()
    };
    let again = reload(serde_json::json!([]));
    assert_eq!(again.heightfield.grid(), first.heightfield.grid());
    assert_eq!(again.heightfield.samples(), first.heightfield.samples());

    // The skeleton: node ids 0..n with their elevations, edges between them.
    let text = std::fs::read_to_string(out.path().join("skeleton.geojson")).unwrap();
    let geojson: serde_json::Value = serde_json::from_str(&text).unwrap();
    let features = geojson["features"].as_array().unwrap();
    let nodes: Vec<&serde_json::Value> = features.iter().filter(|f| f["properties"]["kind"] == "node").collect();
    assert!(nodes.len() >= 3, "{} crest nodes", nodes.len());
    let edited: relief::gaussian_terrain::VectorTerrain =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("edited.json")).unwrap()).unwrap();
    let query = edited.query().unwrap();
    for (k, node) in nodes.iter().enumerate() {
        assert_eq!(node["properties"]["id"], k);
        let c = &node["geometry"]["coordinates"];
        let p = DVec2::new(c[0].as_f64().unwrap(), c[1].as_f64().unwrap());
        assert_eq!(node["properties"]["elevation"].as_f64().unwrap(), query.elevation(p));
    }
    let edges = features.iter().filter(|f| f["properties"]["kind"] == "edge");
    assert!(edges.clone().all(|e| e["properties"]["from"].as_u64().unwrap() < nodes.len() as u64));
    assert!(edges.count() >= nodes.len() - 1 - 2, "a crest graph is mostly connected");

    // The highest node, moved by id and by a point on it: the same terrain, and a changed one.
    let (top, position) = nodes
        .iter()
        .map(|n| (n["properties"]["id"].as_u64().unwrap(), n["geometry"]["coordinates"].clone()))
        .max_by(|a, b| {
            let h = |id: u64| nodes[id as usize]["properties"]["elevation"].as_f64().unwrap();
            h(a.0).total_cmp(&h(b.0))
        })
        .unwrap();
    let by_id = reload(serde_json::json!([{ "op": "move_crest", "node": top, "by": [60, 0], "reach": 300 }]));
    let by_point = reload(serde_json::json!([{ "op": "move_crest", "near": position, "by": [60, 0], "reach": 300 }]));
    assert_eq!(by_id.heightfield.samples(), by_point.heightfield.samples());
    assert_ne!(by_id.heightfield.samples(), again.heightfield.samples());
    // A node that does not exist is named, with the count.
    let json = serde_json::json!({
        "version": 1,
        "reconstruction": { "resolution": scene.reconstruction.resolution },
        "generator": { "gaussian": {
            "source": { "kind": "terrain", "path": "edited.json" },
            "operations": [{ "op": "raise_crest", "node": 100_000, "factor": 1 }],
        } },
    });
    let err = generate(&Scene::from_json(&json.to_string()).unwrap(), out.path(), &mut Quiet).err().unwrap();
    assert!(err.to_string().contains("crest node 100000 does not exist"), "{err}");
    let json = serde_json::json!({
        "version": 1,
        "generator": { "gaussian": {
            "source": { "kind": "terrain", "path": "edited.json" },
            "operations": [{ "op": "raise_crest", "node": 0, "near": [0, 0], "factor": 1 }],
        } },
    });
    let err = generate(&Scene::from_json(&json.to_string()).unwrap(), out.path(), &mut Quiet).err().unwrap();
    assert!(err.to_string().contains("exactly one of near and node"), "{err}");
}

/// An atlas built from a vectorized real DEM: the fixture scene copies and cuts landforms into
/// its session atlas and pastes them elsewhere; the written atlas then serves a later scene's
/// `paste` from the file, and the cut left a hole where the knob was.
#[test]
fn atlases_from_a_real_dem_round_trip() {
    let path = root().join("fixtures/scenes/gaussian-atlas.json");
    let scene = Scene::from_json(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let out = tempfile::tempdir().unwrap();
    let (first, _) = relief::pipeline::run(&scene, path.parent().unwrap(), out.path(), &mut Quiet).unwrap();
    let atlas: relief::gaussian_terrain::Atlas =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("atlas.json")).unwrap()).unwrap();
    let names: Vec<&str> = atlas.landforms.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["hill", "knob"]);
    let (hill, knob) = (atlas.get("hill").unwrap(), atlas.get("knob").unwrap());
    assert!(hill.primitives.len() >= 5 && knob.primitives.len() >= 3);
    // The knob's primitives left its region: none of the edited terrain's centres is there.
    let edited: relief::gaussian_terrain::VectorTerrain =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("edited.json")).unwrap()).unwrap();
    let knob_region = relief::gaussian_terrain::Region::Circle { center: [-84.15, 36.62], radius: 0.03 };
    assert!(knob_region.select(&edited).is_empty());
    // Both pasted landforms are in the terrain exactly where their placements put them.
    for (landform, to, rotation, scale) in [(knob, [-84.35, 36.68], 1.2, 1.0), (hill, [-84.13, 36.50], -0.5, 0.8)] {
        for g in landform.placed(DVec2::from(to), rotation, scale) {
            assert!(edited.primitives.contains(&g), "{} not pasted", landform.name);
        }
    }
    // A later scene pastes the hill from the written atlas file.
    let json = serde_json::json!({
        "version": 1,
        "reconstruction": { "resolution": scene.reconstruction.resolution },
        "generator": { "gaussian": {
            "source": { "kind": "terrain", "path": "edited.json" },
            "operations": [{ "op": "paste", "atlas": "atlas.json", "landform": "hill", "footprint": 0.035,
                             "placement": { "to": [-84.35, 36.50] }, "damping": 0.015 }],
        } },
    });
    let later = generate(&Scene::from_json(&json.to_string()).unwrap(), out.path(), &mut Quiet).unwrap();
    // In the DEM's frame, which the written terrain records: degrees, in its CRS (the later
    // scene's raster once came out as planar metres with no CRS).
    assert!(first.heightfield.crs().is_some());
    assert_eq!(later.heightfield.crs(), first.heightfield.crs());
    assert_eq!(later.heightfield.grid().units(), relief::heightfield::Units::Degrees);
    let vector = later.vector.unwrap().terrain;
    assert_eq!(vector.units, Some(relief::heightfield::Units::Degrees));
    for g in hill.placed(DVec2::new(-84.35, 36.50), 0.0, 1.0) {
        assert!(vector.primitives.contains(&g));
    }
    assert_ne!(later.heightfield.samples(), first.heightfield.samples());
    // The atlas records its landforms' units (degrees): pasted into a planar terrain in metres
    // they would come out 100 000 times too small, so that is refused.
    assert_eq!(atlas.units, Some(relief::heightfield::Units::Degrees));
    let json = serde_json::json!({
        "version": 1,
        "reconstruction": { "resolution": [64, 64] },
        "generator": { "gaussian": {
            "source": { "kind": "primitives", "primitives": [{ "center": [500, 500], "sigma": [100, 100], "amplitude": 50 }] },
            "operations": [{ "op": "paste", "atlas": "atlas.json", "landform": "hill", "footprint": 100,
                             "placement": { "to": [300, 300] }, "damping": 20 }],
        } },
    });
    let err =
        generate(&Scene::from_json(&json.to_string()).unwrap(), out.path(), &mut Quiet).err().unwrap().to_string();
    assert!(err.contains("operations[0].atlas") && err.contains("degrees") && err.contains("metres"), "{err}");
}

/// Fig. 15's loop as a post step: erosion on the raster, then `details` turns the change into
/// detail primitives, so the written vector terrain reproduces the eroded raster on its grid
/// and carries the erosion to a finer one; a scene without a vector terrain is told so.
#[test]
fn erosion_becomes_detail_primitives() {
    let path = root().join("fixtures/scenes/gaussian-massif.json");
    let mut scene = Scene::from_json(&std::fs::read_to_string(&path).unwrap()).unwrap();
    scene.post = serde_json::from_value(serde_json::json!([
        { "thermal": { "talus_deg": 20, "iterations": 40 } },
        { "details": {} }
    ]))
    .unwrap();
    scene.outputs.vector_terrain = Some("eroded.json".into());
    let out = tempfile::tempdir().unwrap();
    let (eroded, _) = relief::pipeline::run(&scene, path.parent().unwrap(), out.path(), &mut Quiet).unwrap();
    assert!(eroded.summary.warnings.is_empty(), "{:?}", eroded.summary.warnings);
    let plain = generate(&Scene { post: Vec::new(), ..scene.clone() }, path.parent().unwrap(), &mut Quiet).unwrap();
    let changed = |a: &[f32], b: &[f32]| a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0f32, f32::max);
    let erosion = changed(eroded.heightfield.samples(), plain.heightfield.samples());
    assert!(erosion > 1.0, "thermal erosion changed the raster by only {erosion}");

    let terrain: relief::gaussian_terrain::VectorTerrain =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("eroded.json")).unwrap()).unwrap();
    assert_eq!(terrain.details.len(), 1);
    let grid = eroded.heightfield.grid();
    let options = relief::gaussian_terrain::RasterOptions::default();
    let again = relief::gaussian_terrain::rasterize(&terrain, grid, &options).unwrap();
    let residual = changed(again.samples(), eroded.heightfield.samples());
    assert!(residual < 0.01 * erosion, "the detailed terrain misses the eroded raster by {residual}");
    // At twice the resolution the erosion is still there (the plain terrain lacks it).
    let fine = relief::heightfield::GridSpec::from_extent(2 * grid.nx() - 1, 2 * grid.ny() - 1, grid.extent()).unwrap();
    let mut bare = terrain.clone();
    bare.details.clear();
    let (with, without) = (
        relief::gaussian_terrain::rasterize(&terrain, &fine, &options).unwrap(),
        relief::gaussian_terrain::rasterize(&bare, &fine, &options).unwrap(),
    );
    assert!(changed(with.samples(), without.samples()) > 0.5 * erosion);

    // No vector terrain, no details.
    let island = root().join("fixtures/scenes/volcanic-island.json");
    let mut other = Scene::from_json(&std::fs::read_to_string(&island).unwrap()).unwrap();
    other.post = serde_json::from_value(serde_json::json!([{ "details": {} }])).unwrap();
    let err = generate(&other, island.parent().unwrap(), &mut Quiet).err().unwrap().to_string();
    assert!(err.contains("post[0].details") && err.contains("gaussian"), "{err}");
}
