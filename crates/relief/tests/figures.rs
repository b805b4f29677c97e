//! Papers' figures as scenes behave as the papers describe: the contours paper's Fig. 27 editing
//! session step by step and its teaser's label map; Hnaidi et al.'s Figs. 5–7 (single landforms from
//! presets), Figs. 4/11 (lake, mountain, desert) and 12 (volcanic island) at Table 1's curve counts,
//! Fig. 8 (noise alone) and Fig. 10 (a canyon in three editing steps); Puig-Centelles et al.'s
//! Fig. 10 (a coastline traced from a map).

use std::path::{Path, PathBuf};

use glam::DVec2;
use relief::diffusion::FeatureCurve;
use relief::pipeline::{generate, load_scene};
use relief::scene::{Generator, Multilevel, Scene};

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/scenes")
}

/// A fixture scene at a smaller raster.
fn scene(name: &str) -> Scene {
    let mut scene = load_scene(scenes().join(format!("{name}.json"))).unwrap();
    scene.reconstruction.resolution = [160, 160];
    scene
}

/// Where the highest sample lies.
fn summit(name: &str) -> DVec2 {
    let terrain = generate(&scene(name), &scenes(), &mut ()).unwrap();
    let hf = &terrain.heightfield;
    let (k, _) = hf.samples().iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).unwrap();
    hf.grid().position(k % hf.nx(), k / hf.nx())
}

#[test]
fn fig_27_the_larger_range_rises_higher_until_a_contour_lifts_the_other() {
    // (2): two ranges without heights; the larger, bottom-left one reaches higher ground.
    let top = summit("editing-session-2-ranges");
    assert!(top.x < 0.0 && top.y < 0.0, "the summit should be in the bottom-left range, not at {top}");
    // (3): a 1400 m contour inside the right-hand range lifts it above the left one.
    let top = summit("editing-session-3-summit-and-crater");
    assert!(top.distance(DVec2::new(1950.0, 2050.0)) < 800.0, "the summit should be inside the 1400 m contour: {top}");
}

#[test]
fn fig_27_the_histogram_step_raises_the_coastal_land() {
    // (4) keeps the contours of (3) and takes fewer low elevations: the land near the coast rises.
    let share_low = |name: &str| {
        let terrain = generate(&scene(name), &scenes(), &mut ()).unwrap();
        let land: Vec<f32> = terrain.heightfield.samples().iter().copied().filter(|&v| v > 0.0).collect();
        land.iter().filter(|&&v| v < 250.0).count() as f64 / land.len() as f64
    };
    let (before, after) = (share_low("editing-session-3-summit-and-crater"), share_low("editing-session-4-histogram"));
    assert!(after < 0.75 * before, "land under 250 m: {before:.2} before, {after:.2} after");
}

#[test]
fn the_teaser_mask_gives_its_three_levels_at_their_heights() {
    let terrain = generate(&scene("teaser"), &scenes(), &mut ()).unwrap();
    assert_eq!(terrain.summary.graph.as_ref().unwrap().levels, 3);
    let mask = terrain.summary.label_image.as_ref().unwrap();
    assert_eq!(mask.levels, ["#000000", "#424242", "#9d9d9d", "#ffffff"]);
    for h in [0.0, 300.0, 600.0] {
        assert!(terrain.contours.levels().contains(&h), "the {h} m contour");
    }
}

/// The teaser's mesas and valleys run off the image: the frame cuts them, with no trench along it
/// (issue 75's first artefact: its border samples were 12.7 times the next step in below).
#[test]
fn the_teaser_has_no_trench_along_its_border() {
    for resolution in [160, 512] {
        let mut scene = scene("teaser");
        scene.reconstruction.resolution = [resolution, resolution];
        let terrain = generate(&scene, &scenes(), &mut ()).unwrap();
        let a = terrain.summary.drainage.artefacts;
        let (border, next) = (a.border_step_m.unwrap(), a.next_step_m.unwrap());
        assert!(border <= 1.2 * next + 0.5, "at {resolution}²: border step {border} m, next step in {next} m");
    }
}

#[test]
fn multilevel_generation_runs_its_coarse_passes_first() {
    let mut scene = scene("coastline-island");
    let Generator::Contours(g) = &mut scene.generator else { unreachable!() };
    g.multilevel = Some(Multilevel { passes: 3, factor: 4.0, contrast: 6.0 });
    let terrain = generate(&scene, &scenes(), &mut ()).unwrap();
    let steps: Vec<&str> = terrain.summary.timings_ms.iter().map(|t| t.step).collect();
    assert_eq!(&steps[..3], ["inputs", "coarse passes", "graph"], "{steps:?}");
    terrain.contours.check_invariants().unwrap();
    // A single pass is refused, as is a factor that does not coarsen.
    for bad in [r#"{ "passes": 1 }"#, r#"{ "passes": 3, "factor": 1 }"#] {
        let text = std::fs::read_to_string(scenes().join("coastline-island.json")).unwrap();
        let mut value: serde_json::Value = serde_json::from_str(&text).unwrap();
        value["generator"]["contours"]["multilevel"] = serde_json::from_str(bad).unwrap();
        let err = Scene::from_json(&value.to_string()).unwrap_err();
        assert!(err.to_string().contains("generator.contours.multilevel"), "{err}");
    }
}

#[test]
fn fig_8_noise_alone_follows_its_amplitude_and_roughness() {
    // No elevation anywhere: the border is the 0 m base level and the noise is the terrain.
    let scene = load_scene(scenes().join("noise-control.json")).unwrap();
    let terrain = generate(&scene, &scenes(), &mut ()).unwrap();
    assert!(terrain.summary.diffusion.as_ref().unwrap().converged);
    assert!(
        terrain.summary.warnings.is_empty(),
        "noise alone is no noise hiding relief: {:?}",
        terrain.summary.warnings
    );
    let hf = &terrain.heightfield;
    // The samples of the columns between x0 and x1 (metres), row by row.
    let band = |x0: f64, x1: f64| -> Vec<Vec<f64>> {
        (0..hf.ny())
            .map(|j| {
                (0..hf.nx())
                    .filter(|&i| (x0..x1).contains(&hf.grid().position(i, j).x))
                    .map(|i| f64::from(hf.get(i, j).unwrap()))
                    .collect()
            })
            .collect()
    };
    let rms = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt();
    let all = |rows: &[Vec<f64>]| rows.concat();
    // Amplitude 0 on the west edge, 120 m at x = 2800.
    let (west, east) = (rms(&all(&band(0.0, 300.0))), rms(&all(&band(2500.0, 2800.0))));
    assert!(west < 0.2 * east && east > 20.0, "detail {west:.1} m in the west, {east:.1} m at A = 120");
    // Roughness 0 at x = 3200, 1 at x = 5900, same amplitude: the second differences (fine
    // detail) grow against the detail itself.
    let fine = |rows: Vec<Vec<f64>>| {
        let second: Vec<f64> = rows.iter().flat_map(|r| r.windows(3).map(|w| w[0] - 2.0 * w[1] + w[2])).collect();
        rms(&second) / rms(&rows.concat())
    };
    let (smooth, rough) = (fine(band(3200.0, 3700.0)), fine(band(5400.0, 5900.0)));
    assert!(rough > 1.5 * smooth, "fine detail share {smooth:.3} at R = 0, {rough:.3} at R = 1");
}

#[test]
fn figs_5_6_7_single_landforms_from_presets() {
    let run = |name: &str| {
        let scene = load_scene(scenes().join(format!("{name}.json"))).unwrap();
        let terrain = generate(&scene, &scenes(), &mut ()).unwrap();
        assert!(terrain.summary.diffusion.as_ref().unwrap().converged, "{name}");
        move |x: f64, y: f64| f64::from(terrain.heightfield.sample_bilinear(DVec2::new(x, y)).unwrap())
    };
    // Fig. 5: the ridge's crest halfway along, the shared summit of the multiple ridges.
    let h = run("landforms-ridges");
    assert!((h(2000.0, 2300.0) - 1200.0).abs() < 60.0 && (h(6000.0, 2000.0) - 1400.0).abs() < 60.0);
    assert!(h(2000.0, 3300.0) < 900.0 && h(6000.0, 3000.0) < h(6000.0, 2000.0) - 300.0, "flanks fall away");
    // Fig. 6: the riverbed lies below its banks; the cliff drops on its left (north-east) side.
    let h = run("landforms-riverbed-cliff");
    // Halfway along the course's second leg, and 250 m out on either bank.
    let bed = h(1950.0, 2000.0);
    assert!(h(2133.0, 2170.0) > bed + 8.0 && h(1767.0, 1830.0) > bed + 8.0, "bed {bed:.0} not below its banks");
    let (edge, left, right) = (h(6000.0, 2100.0), h(6200.0, 2300.0), h(5800.0, 1900.0));
    assert!(left < edge - 150.0 && (right - edge).abs() < 60.0, "cliff {left:.0} | {edge:.0} | {right:.0}");
    // Fig. 7: the hill stays level beside its crest; the crack cuts below its walls.
    let h = run("landforms-hill-crack");
    assert!((h(2000.0, 2300.0) - 500.0).abs() < 30.0, "level beside the hill: {}", h(2000.0, 2300.0));
    assert!(h(6000.0, 2100.0) < h(5880.0, 2220.0) - 40.0, "the crack below its wall");
}

/// The island-from-image scene with its `coastline_image` changed by `edit`, run.
fn island_from_image(
    edit: impl FnOnce(&mut relief::scene::CoastlineImage),
) -> Result<relief::Terrain, relief::ReliefError> {
    let mut scene = load_scene(scenes().join("island-from-image.json")).unwrap();
    let Generator::Island(g) = &mut scene.generator else { panic!("an island scene") };
    edit(g.coastline_image.as_mut().unwrap());
    generate(&scene, &scenes(), &mut ())
}

#[test]
fn island_fig_10_a_coastline_traced_from_a_map() {
    // The authors' La Réunion mask: light land on a dark sea, 500 × 500 pixels over 60 km.
    let terrain = island_from_image(|_| {}).unwrap();
    let hf = &terrain.heightfield;
    let land = |p: [f64; 2]| hf.sample_bilinear(DVec2::from(p)).unwrap() > 0.0;
    assert!(land([30000.0, 30000.0]) && !land([1000.0, 1000.0]) && !land([59000.0, 59000.0]));
    // The land covers what the mask's light pixels cover, in the same place: the image's rows
    // run from north to south, the grid's from south to north.
    let mask = image::open(scenes().join("inputs/reunion.png")).unwrap().into_luma16();
    let (w, h) = mask.dimensions();
    let (mut both, mut either) = (0usize, 0usize);
    for j in 0..hf.ny() {
        for i in 0..hf.nx() {
            let p = hf.grid().position(i, j);
            let (px, py) =
                ((p.x / 60000.0 * f64::from(w - 1)).round() as u32, (p.y / 60000.0 * f64::from(h - 1)).round() as u32);
            let light = mask.get_pixel(px, h - 1 - py)[0] > 32767;
            let on_land = hf.get(i, j).unwrap() > 0.0;
            both += usize::from(light && on_land);
            either += usize::from(light || on_land);
        }
    }
    let overlap = both as f64 / either as f64;
    assert!(overlap > 0.97, "land and the mask's light pixels overlap by {overlap:.3}");
    // The crater hollow dips below sea level: a lake, not ground flattened at the land floor.
    let lake = hf.sample_bilinear(DVec2::new(40000.0, 21000.0)).unwrap();
    assert!(lake < 0.0, "crater lake bottom at {lake}");
}

#[test]
fn island_coastline_images_say_what_is_wrong() {
    // A threshold outside the image's gray levels: an error at the scene value, not an empty island.
    let err = island_from_image(|c| c.threshold = Some(2.0)).unwrap_err();
    assert_eq!(err.scene_path(), Some("generator.island.coastline_image"), "{err}");
    // A dark island drawn on white paper, as a paint program leaves it (a soft, anti-aliased
    // edge): a disc of radius 100 pixels in a 400-pixel square over the scene's 60 km.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("disc.png");
    let disc = image::GrayImage::from_fn(400, 400, |x, y| {
        let r = (f64::from(x) - 199.5).hypot(f64::from(y) - 199.5);
        image::Luma([((r - 99.5).clamp(0.0, 1.0) * 255.0) as u8])
    });
    disc.save(&path).unwrap();
    let dark = island_from_image(|c| {
        c.path = path.clone();
        c.land = relief::scene::LandTone::Dark;
    })
    .unwrap();
    let cell = 60000.0 / 255.0;
    // Sea is exactly 0; land is not (a crater lake dips below it).
    let area = dark.heightfield.samples().iter().filter(|&&v| v != 0.0).count() as f64 * cell * cell;
    let want = std::f64::consts::PI * (100.0 * 60000.0 / 399.0f64).powi(2);
    assert!((area / want - 1.0).abs() < 0.03, "a {area:.3e} m² island, the disc is {want:.3e} m²");
    let err = island_from_image(|c| c.path = "inputs/no-such-map.png".into()).unwrap_err();
    assert_eq!(err.scene_path(), Some("generator.island.coastline_image.path"), "{err}");
}

#[test]
fn island_fig_13_the_final_grid_is_the_sum_of_its_layers() {
    let scene = load_scene(scenes().join("island-from-image.json")).unwrap();
    let out = tempfile::tempdir().unwrap();
    let (terrain, written) = relief::pipeline::run(&scene, &scenes(), out.path(), &mut ()).unwrap();
    let layers = terrain.layers.as_ref().unwrap();
    for (name, layer) in [("base", &layers.base), ("hills", &layers.hills), ("filters", &layers.filters)] {
        let path = out.path().join(format!("layers-{name}.exr"));
        assert!(written.contains(&path), "{name} written");
        assert_eq!(&relief::io::read(&path).unwrap().into_samples(), layer.samples(), "{name} reads back");
    }
    // The scene names what it reads and writes: the traced map, and every file written.
    assert_eq!(scene.input_files(), [Path::new("inputs/reunion.png")]);
    let mut named: Vec<PathBuf> = scene.output_files().iter().map(|f| out.path().join(f)).collect();
    let mut written = written;
    named.sort();
    written.sort();
    assert_eq!(named, written);
    // On land, where nothing is held at the land floor, the terrain is base + hills + filters.
    let (mut summed, mut hills, mut filters) = (0, 0, 0);
    for (k, &z) in terrain.heightfield.samples().iter().enumerate() {
        let (b, h, f) = (layers.base.samples()[k], layers.hills.samples()[k], layers.filters.samples()[k]);
        if z == 0.0 || b + f < 1.0 {
            continue;
        }
        assert!((z - (b + h + f)).abs() < 1e-3 * z.abs().max(1.0), "sample {k}: {z} is not {b} + {h} + {f}");
        summed += 1;
        hills += usize::from(h.abs() > 1.0);
        filters += usize::from(f.abs() > 0.1);
    }
    assert!(
        summed > 20_000 && hills > 5_000 && filters > 5_000,
        "{summed} samples, {hills} with hills, {filters} with filters"
    );
}

#[test]
fn fig_12_volcanic_island_at_the_papers_scale() {
    let mut scene = load_scene(scenes().join("volcanic-island-48.json")).unwrap();
    let Generator::Diffusion(g) = &scene.generator else { panic!("a diffusion scene") };
    assert_eq!(g.all_curves().len(), 48, "Table 1: the paper's volcanic island has 48 curves");
    scene.reconstruction.resolution = [256, 256];
    let terrain = generate(&scene, &scenes(), &mut ()).unwrap();
    assert!(terrain.summary.diffusion.as_ref().unwrap().converged);
    let h = |x: f64, y: f64| f64::from(terrain.heightfield.sample_bilinear(DVec2::new(x, y)).unwrap());
    // The crater floor lies below its rim; the flanks fall to the sea; the sea floor is deep.
    let (floor, rim) = (h(300.0, 200.0), h(300.0 + 950.0, 200.0));
    assert!(floor < rim - 150.0 && rim > 1000.0, "crater floor {floor:.0}, rim {rim:.0}");
    assert!(h(300.0 + 2200.0, 200.0) < rim - 500.0 && h(300.0 + 2200.0, 200.0) > 0.0);
    assert!(h(-4800.0, -4800.0) < -150.0);
}

/// A fixture scene's curves (presets expanded) and a sampler of its terrain at `resolution`.
fn diffused(name: &str, resolution: [usize; 2]) -> (Vec<FeatureCurve>, impl Fn(f64, f64) -> f64 + use<>) {
    let mut scene = load_scene(scenes().join(format!("{name}.json"))).unwrap();
    let Generator::Diffusion(g) = &scene.generator else { panic!("{name}: a diffusion scene") };
    let curves = g.all_curves();
    scene.reconstruction.resolution = resolution;
    let terrain = generate(&scene, &scenes(), &mut ()).unwrap();
    assert!(terrain.summary.diffusion.as_ref().unwrap().converged, "{name}");
    let hf = terrain.heightfield;
    (curves, move |x: f64, y: f64| f64::from(hf.sample_bilinear_clamped(DVec2::new(x, y)).unwrap()))
}

#[test]
fn figs_4_11_lake_mountain_and_desert_at_the_papers_scale() {
    // Table 1: 45, 59 and 26 curves.
    let (curves, h) = diffused("lake", [256, 256]);
    assert_eq!(curves.len(), 45);
    // The lake (its level, 200 m, is the scene's water level) is deepest on its centre line, and
    // its outlet carries water below the lake level to the southern edge between dry banks.
    assert!((h(5000.0, 4600.0) - 145.0).abs() < 10.0 && h(5000.0, 5600.0) < 200.0, "the lake bed");
    assert!(h(5150.0, 1500.0) < 200.0 && h(4800.0, 60.0) < 200.0, "the outlet");
    assert!(h(4200.0, 1500.0) > 200.0 && h(6100.0, 1500.0) > 200.0, "the outlet's banks");
    let (curves, h) = diffused("mountain", [240, 200]);
    assert_eq!(curves.len(), 59);
    assert!((h(6000.0, 5600.0) - 2400.0).abs() < 80.0, "the main summit: {}", h(6000.0, 5600.0));
    assert!(h(6000.0, 5600.0) > h(2600.0, 7300.0) && h(2600.0, 7300.0) > 1700.0);
    let (curves, h) = diffused("desert", [512, 512]);
    assert_eq!(curves.len(), 26);
    // Every dune is asymmetric (θ ≠ φ): from a point on its crest the ground drops about twice as
    // fast or more on the lee (north) side as on the windward side (measured 2.0–5.1×; equal
    // angles would give 1×).
    for (k, dune) in curves.iter().take(12).enumerate() {
        for p in dune.points.iter().step_by(3).skip(1).take(4) {
            let top = h(p.x, p.y);
            let (lee, windward) = (top - h(p.x, p.y + 60.0), top - h(p.x, p.y - 60.0));
            assert!(
                lee > 1.8 * windward && windward > 3.0,
                "dune {k} at {p}: lee drop {lee:.1} m, windward {windward:.1} m"
            );
        }
    }
    // The largest mesa: a level top inside its rim, a cliff outside.
    let top: Vec<f64> =
        (0..25).map(|k| h(6600.0 + 40.0 * f64::from(k % 5 * 4), 7400.0 + 40.0 * f64::from(k / 5 * 4))).collect();
    let (lo, hi) = top.iter().fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
    assert!(lo > 440.0 && hi - lo < 50.0, "mesa top from {lo:.0} to {hi:.0}");
    assert!(h(7000.0, 7800.0 - 1500.0) < 300.0, "below the mesa's cliff");
}

/// Where Fig. 10's river runs (the generator's `river_y`).
fn river_y(x: f64) -> f64 {
    use std::f64::consts::TAU;
    4000.0 + 500.0 * (TAU * x / 6000.0).sin() + 200.0 * (TAU * x / 2300.0 + 1.0).sin()
}

#[test]
fn fig_10_a_canyon_edited_in_three_steps() {
    let steps: Vec<_> = (1..=3).map(|k| diffused(&format!("canyon-step-{k}"), [288, 192])).collect();
    assert_eq!(steps.iter().map(|s| s.0.len()).collect::<Vec<_>>(), [15, 30, 74], "the caption's curve counts");
    for (k, (_, h)) in steps.iter().enumerate() {
        // Every step keeps the river falling east in its canyon between the rims.
        let (west, east) = (h(1000.0, river_y(1000.0)), h(11000.0, river_y(11000.0)));
        assert!(west > east + 60.0 && west < 320.0, "step {}: river {west:.0} → {east:.0}", k + 1);
        assert!(h(1000.0, river_y(1000.0) + 2000.0) > 650.0 && h(1000.0, river_y(1000.0) - 2000.0) > 650.0);
    }
    // Step 2 cuts a side canyon into the northern plateau where step 1 had level ground.
    let (x, y) = (3100.0, river_y(3300.0) + 1900.0);
    assert!(steps[1].1(x, y) < steps[0].1(x, y) - 100.0, "{} vs {}", steps[1].1(x, y), steps[0].1(x, y));
    // Step 3's details roughen the walls: more second-difference energy across a wall band.
    let roughness = |h: &dyn Fn(f64, f64) -> f64| {
        (0..400)
            .map(|i| {
                let x = 200.0 + 29.0 * f64::from(i);
                let y = river_y(x) + 1000.0;
                (h(x - 40.0, y) - 2.0 * h(x, y) + h(x + 40.0, y)).powi(2)
            })
            .sum::<f64>()
    };
    let (two, three) = (roughness(&steps[1].1), roughness(&steps[2].1));
    assert!(three > 1.5 * two, "wall detail {two:.0} → {three:.0}");
}
