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
