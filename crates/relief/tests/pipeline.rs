//! The pipeline end to end, as a library: generated terrains nest, drain and follow their
//! histogram; the same seed gives the same bytes with any number of threads; every output is
//! written, parses and leaves no temporary file behind.

use std::path::{Path, PathBuf};

use glam::DVec2;
use proptest::prelude::*;
use relief::contours::{Contour, ContourSet, Histogram, Levels, Smoothing};
use relief::eden_growth::{FbmProbability, Fronts, Region};
use relief::heightfield::Heightfield;
use relief::heightfield::noise::Fbm;
use relief::hydrology::{Field, Outlets, StreamPower, Thermal, depressions};
use relief::pipeline::{Progress, generate, load_scene, run};
use relief::poisson_sampling::Polygon;
use relief::scene::{
    ContoursGenerator, Edit, Generator, HistogramSource, Outputs, PostProcess, Probability, Reconstruction,
    ReconstructionMode, Scene,
};
use relief::warp::{PathOptions, PathWarp, SlopeModulation};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A star-shaped ring: `n` vertices at radii `r·(0.7 + 0.3·wᵢ)` around `c`.
fn star(c: [f64; 2], r: f64, wobble: &[f64]) -> Vec<[f64; 2]> {
    relief_fixtures::star_ring(DVec2::from(c), r, 0.7, 0.3, wobble).into_iter().map(Into::into).collect()
}

fn region(exterior: Vec<[f64; 2]>, height: Option<f64>, depression: bool) -> Region {
    let polygon = Polygon::from_exterior(exterior.into_iter().map(DVec2::from).collect()).unwrap();
    Region { polygon, height, depression, depth: None }
}

fn smooth(alpha: f64, k: usize, iterations: u32) -> Edit {
    Edit::Smooth(Smoothing { alpha, k, iterations, ..Smoothing::default() })
}

fn warp(stroke: &[[f64; 2]], radius: f64, strength: f64) -> Edit {
    let stroke: Vec<DVec2> = stroke.iter().map(|&p| DVec2::from(p)).collect();
    Edit::Warp(PathWarp::new(&stroke, &PathOptions::new(radius, strength)).unwrap())
}

fn slope_at(point: [f64; 2], radius: f64, strength: f64) -> Edit {
    Edit::Slope(SlopeModulation::point(DVec2::from(point), radius, strength).unwrap())
}

fn slope_along(curve: &[[f64; 2]], radius: f64, strength: f64) -> Edit {
    let curve: Vec<DVec2> = curve.iter().map(|&p| DVec2::from(p)).collect();
    Edit::Slope(SlopeModulation::curve(&curve, radius, strength).unwrap())
}

fn stream_power(iterations: usize, n: f64, dt: f64) -> PostProcess {
    let erodibility = Field::Uniform(1e-4);
    PostProcess::StreamPower(StreamPower { iterations, erodibility, n, dt, ..StreamPower::default() })
}

fn scene(seed: u64, regions: Vec<Region>, edits: Vec<Edit>, mode: ReconstructionMode, size: usize) -> Scene {
    Scene {
        version: 1,
        description: None,
        seed,
        domain: None,
        inputs: relief::scene::InputOptions::default(),
        generator: Generator::Contours(ContoursGenerator {
            regions,
            label_image: None,
            contours: None,
            particles: Some(3_000),
            radius: None,
            histogram: Some(HistogramSource::Histogram(
                Histogram::from_bins(vec![0.0, 100.0, 400.0, 900.0], vec![3.0, 2.0, 1.0]).unwrap(),
            )),
            probability: Probability::Fbm(
                FbmProbability::new(Fbm { octaves: 4, frequency: 0.002, lacunarity: 2.0, gain: 0.5, seed: 0 }, 2.0)
                    .unwrap(),
            ),
            levels: Levels::Count(12),
            fronts: Fronts::Double,
            multilevel: None,
        }),
        edits,
        reconstruction: Reconstruction { mode, resolution: [size, size], drain: true },
        post: Vec::new(),
        outputs: Outputs::default(),
    }
}

/// Closed basins of `dem` (water cannot reach the sea below `sea_level` or the border) whose
/// pit is not `excluded`: the endorheic check of `relief-hydrology`, not just one-cell pits.
fn closed_basins(dem: &Heightfield, sea_level: f32, excluded: impl Fn(DVec2) -> bool) -> usize {
    let found = depressions(dem, Outlets::new().with_sea_level(sea_level)).unwrap();
    found.basins.iter().filter(|b| !excluded(dem.grid().position(b.pit.0, b.pit.1))).count()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// The main invariants of a generated terrain, on random islands with a random range and
    /// random edits: contours never cross and nest level by level (warps and smoothing keep the
    /// tree), node heights follow the histogram exactly, and the raster has no endorheic basin
    /// (none was asked for).
    #[test]
    fn generated_terrains_nest_drain_and_follow_the_histogram(
        seed in any::<u64>(),
        coast in prop::collection::vec(0.0f64..1.0, 12..24),
        range in prop::collection::vec(0.0f64..1.0, 8..16),
        smooth in any::<bool>(),
        warp in prop::option::of(((-1500.0f64..1500.0, -1500.0f64..1500.0), (0.0f64..std::f64::consts::TAU, 50.0f64..600.0), 100.0f64..600.0, 0.1f64..1.0)),
        slope in prop::option::of(((-1500.0f64..1500.0, -1500.0f64..1500.0), 200.0f64..1000.0, -0.9f64..2.5)),
    ) {
        let regions = vec![
            region(star([0.0, 0.0], 3000.0, &coast), Some(0.0), false),
            region(star([300.0, -200.0], 900.0, &range), None, false),
        ];
        // Random edits: smoothing, a warp stroke anywhere, a slope modulation anywhere.
        let mut edits = if smooth { vec![self::smooth(0.5, 2, 3)] } else { Vec::new() };
        if let Some(((x, y), (angle, length), radius, strength)) = warp {
            let end = [x + length * angle.cos(), y + length * angle.sin()];
            edits.push(self::warp(&[[x, y], end], radius, strength));
        }
        if let Some(((x, y), radius, strength)) = slope {
            edits.push(slope_at([x, y], radius, strength));
        }
        let terrain = generate(&scene(seed, regions, edits, ReconstructionMode::Interpolated, 96), &root(), &mut ()).unwrap();
        terrain.contours.check_invariants().map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(terrain.contours.nests_by_level(), Ok(()));
        prop_assert!(terrain.contours.contours().iter().all(|c| c.closed));
        let (fit, graph) = (terrain.summary.histogram_match.as_ref().unwrap(), terrain.summary.graph.as_ref().unwrap());
        prop_assert!(fit.nodes <= 0.5 / graph.inside as f64 + 1e-9);
        prop_assert!(fit.raster < 0.1, "raster KS {}", fit.raster);
        prop_assert_eq!(closed_basins(&terrain.heightfield, terrain.sea_level.unwrap() as f32, |_| false), 0);
        prop_assert_eq!(terrain.summary.drainage.closed_basins, 0);
    }
}

/// An island with two ranges, a crater and every kind of edit.
fn full_scene(mode: ReconstructionMode) -> Scene {
    let wobble: Vec<f64> = (0..30).map(|k| (f64::from(k) * 1.7).sin().abs()).collect();
    let regions = vec![
        region(star([0.0, 0.0], 4000.0, &wobble), Some(0.0), false),
        region(star([-1500.0, 0.0], 1200.0, &wobble[..12]), None, false),
        region(star([1600.0, 300.0], 1000.0, &wobble[3..15]), None, false),
        region(star([-1500.0, 0.0], 300.0, &wobble[5..13]), None, true),
    ];
    let edits = vec![
        smooth(0.5, 2, 2),
        warp(&[[1600.0, -300.0], [1700.0, -900.0]], 400.0, 1.0),
        slope_at([1600.0, 300.0], 800.0, 1.0),
        slope_along(&[[-2500.0, -1500.0], [-1500.0, -1800.0], [-500.0, -1500.0]], 300.0, -0.5),
    ];
    scene(9, regions, edits, mode, 128)
}

#[test]
fn every_reconstruction_mode_keeps_the_crater_and_drains_elsewhere() {
    for mode in [ReconstructionMode::Interpolated, ReconstructionMode::Stairs, ReconstructionMode::Tin] {
        let terrain = generate(&full_scene(mode), &root(), &mut ()).unwrap();
        terrain.contours.check_invariants().unwrap();
        let dem = &terrain.heightfield;
        // The crater's floor is lower than its rim: a pit contour (clockwise) encloses it.
        let pit = terrain.contours.contours().iter().find(|c| c.closed && !c.is_counter_clockwise());
        assert!(pit.is_some(), "{mode:?}: the crater has a pit contour");
        let floor = dem.sample_bilinear(DVec2::new(-1500.0, 0.0)).unwrap();
        let rim = dem.sample_bilinear(DVec2::new(-1500.0, 600.0)).unwrap();
        assert!(floor < rim, "{mode:?}: crater floor {floor} not below its rim {rim}");
        assert_eq!(dem.no_data_count(), 0, "{mode:?}");
        if mode != ReconstructionMode::Stairs {
            // Away from the crater, every land cell drains.
            let crater = |p: DVec2| p.distance(DVec2::new(-1500.0, 0.0)) < 500.0;
            assert_eq!(closed_basins(dem, terrain.sea_level.unwrap() as f32, crater), 0, "{mode:?}");
            assert!(terrain.summary.drainage.closed_basins >= 1, "{mode:?}: the crater is a closed basin");
        }
    }
}

#[test]
fn a_hundred_thousand_node_scene_keeps_its_invariants_with_either_front() {
    for fronts in [Fronts::Double, Fronts::PerRegion] {
        let mut scene = full_scene(ReconstructionMode::Interpolated);
        let Generator::Contours(g) = &mut scene.generator else { unreachable!() };
        g.particles = Some(100_000);
        g.fronts = fronts;
        let terrain = generate(&scene, &root(), &mut ()).unwrap();
        assert!(terrain.summary.graph.as_ref().unwrap().inside > 95_000);
        // Nesting and no crossings of the extracted and edited contours.
        terrain.contours.check_invariants().unwrap();
        // No endorheic basin but the marked crater.
        let crater = |p: DVec2| p.distance(DVec2::new(-1500.0, 0.0)) < 500.0;
        assert_eq!(closed_basins(&terrain.heightfield, terrain.sea_level.unwrap() as f32, crater), 0, "{fronts:?}");
    }
}

#[test]
fn the_tin_reconstruction_applies_smoothing() {
    let wobble: Vec<f64> = (0..30).map(|k| (f64::from(k) * 1.7).sin().abs()).collect();
    let regions = vec![
        region(star([0.0, 0.0], 4000.0, &wobble), Some(0.0), false),
        region(star([-1500.0, 0.0], 1200.0, &wobble[..12]), Some(400.0), false),
    ];
    // Mean absolute discrete Laplacian of the land: what smoothing lowers.
    let roughness = |hf: &Heightfield| {
        let (nx, ny, v) = (hf.nx(), hf.ny(), hf.samples());
        let mut sum = 0.0;
        for j in 1..ny - 1 {
            for i in 1..nx - 1 {
                let k = j * nx + i;
                sum += f64::from((4.0 * v[k] - v[k - 1] - v[k + 1] - v[k - nx] - v[k + nx]).abs());
            }
        }
        sum / ((nx - 2) * (ny - 2)) as f64
    };
    let plain =
        generate(&scene(9, regions.clone(), Vec::new(), ReconstructionMode::Tin, 128), &root(), &mut ()).unwrap();
    let smoothed =
        generate(&scene(9, regions, vec![smooth(1.0, 2, 6)], ReconstructionMode::Tin, 128), &root(), &mut ()).unwrap();
    let (a, b) = (roughness(&plain.heightfield), roughness(&smoothed.heightfield));
    assert!(b < 0.8 * a, "smoothing left the TIN terrain as rough: {b} vs {a}");
    // The range's 400 m contour stays where it was drawn: its inside stays above it.
    let summit = smoothed.heightfield.sample_bilinear(DVec2::new(-1500.0, 0.0)).unwrap();
    assert!(summit > 400.0, "{summit}");
}

/// Runs `f` on a pool of `threads` threads.
fn with_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(f)
}

fn contour_bits(set: &ContourSet) -> Vec<(u32, u64, bool, Vec<[u64; 2]>)> {
    set.contours()
        .iter()
        .map(|c: &Contour| {
            (c.level, c.height.to_bits(), c.closed, c.points.iter().map(|p| [p.x.to_bits(), p.y.to_bits()]).collect())
        })
        .collect()
}

#[test]
fn same_seed_gives_identical_bytes_with_one_or_two_threads() {
    for mode in [ReconstructionMode::Interpolated, ReconstructionMode::Tin] {
        let scene = full_scene(mode);
        let one = with_threads(1, || generate(&scene, &root(), &mut ()).unwrap());
        let two = with_threads(2, || generate(&scene, &root(), &mut ()).unwrap());
        assert_eq!(one.heightfield, two.heightfield, "{mode:?}: heightfields differ");
        assert_eq!(contour_bits(&one.contours), contour_bits(&two.contours), "{mode:?}: contours differ");
        let mut other = scene.clone();
        other.seed += 1;
        let three = generate(&other, &root(), &mut ()).unwrap();
        assert_ne!(one.heightfield, three.heightfield, "{mode:?}: the seed matters");
    }
}

#[derive(Default)]
struct Steps(Vec<(&'static str, bool)>);

impl Progress for Steps {
    fn start(&mut self, step: &'static str) {
        self.0.push((step, false));
    }
    fn finish(&mut self, step: &'static str, _: std::time::Duration) {
        self.0.push((step, true));
    }
}

/// A preview is the same heightfield as a full run, post steps included, without the analyses.
#[test]
fn a_preview_is_the_generated_heightfield() {
    for name in ["volcano-island-sketch", "lake", "mesa", "orometry-jacksboro-tree"] {
        let mut scene = load_scene(root().join(format!("fixtures/scenes/{name}.json"))).unwrap();
        scene.reconstruction.resolution = [96, 96];
        if name == "volcano-island-sketch" {
            // The crater filled: a post step that changes the heightfield.
            scene.post = vec![serde_json::from_str(r#"{"fill": {}}"#).unwrap()];
        }
        let dir = root().join("fixtures/scenes");
        let full = generate(&scene, &dir, &mut ()).unwrap();
        let mut steps = Steps::default();
        let preview = relief::pipeline::preview_with(&scene, &dir, &relief::Budget::default(), &mut steps).unwrap();
        assert_eq!(preview.heightfield, full.heightfield, "{name}");
        if name == "volcano-island-sketch" {
            assert_eq!(full.summary.drainage.closed_basins, 0, "the post step ran");
        }
        assert_eq!(preview.sea_level, full.sea_level, "{name}");
        assert!(!steps.0.iter().any(|(s, _)| *s == "drainage"), "{name}: {:?}", steps.0);
        assert_eq!(preview.timings.len() * 2, steps.0.len(), "{name}");
        // An orometry scene's tree, the one a full run writes.
        let tree = full.summary.orometry.as_ref().map(|o| &o.tree);
        assert_eq!(preview.divide_tree.as_ref(), tree, "{name}");
        assert_eq!(tree.is_some(), name.starts_with("orometry"), "{name}");
    }
}

/// Records how long each step took, as the pipeline reports it to the caller.
#[derive(Default)]
struct Durations(Vec<(&'static str, std::time::Duration)>);

impl Progress for Durations {
    fn start(&mut self, _: &'static str) {}
    fn finish(&mut self, step: &'static str, elapsed: std::time::Duration) {
        self.0.push((step, elapsed));
    }
}

/// The summary's timings are the durations the caller was told, in milliseconds.
#[test]
fn the_summary_times_each_step_in_milliseconds() {
    let mut scene = load_scene(root().join("fixtures/scenes/volcano-island-sketch.json")).unwrap();
    scene.reconstruction.resolution = [64, 64];
    let mut durations = Durations::default();
    let terrain = generate(&scene, &root().join("fixtures/scenes"), &mut durations).unwrap();
    let told: Vec<(&str, f64)> = durations.0.iter().map(|(s, d)| (*s, d.as_secs_f64() * 1000.0)).collect();
    let reported: Vec<(&str, f64)> = terrain.summary.timings_ms.iter().map(|t| (t.step, t.ms)).collect();
    assert_eq!(reported, told);
}

/// Cancels the run once `after` steps have finished, or once `after_units` units of a counted
/// step are done.
struct CancelAfter {
    steps: Steps,
    after: usize,
    units: u64,
    after_units: u64,
}

impl Progress for CancelAfter {
    fn start(&mut self, step: &'static str) {
        self.steps.start(step);
    }
    fn finish(&mut self, step: &'static str, elapsed: std::time::Duration) {
        self.steps.finish(step, elapsed);
    }
    fn advance(&mut self, _: &'static str, done: u64, _: u64) {
        self.units = done;
    }
    fn cancelled(&self) -> bool {
        self.steps.0.iter().filter(|(_, finished)| *finished).count() >= self.after || self.units >= self.after_units
    }
}

#[test]
fn a_cancelled_run_stops_before_its_next_step_or_unit() {
    let scene = full_scene(ReconstructionMode::Interpolated);
    let mut progress = CancelAfter { steps: Steps::default(), after: 2, units: 0, after_units: u64::MAX };
    let error = generate(&scene, &root(), &mut progress).unwrap_err();
    assert!(matches!(error, relief::ReliefError::Cancelled), "{error}");
    let started: Vec<&str> = progress.steps.0.iter().filter(|(_, f)| !f).map(|(s, _)| *s).collect();
    assert_eq!(started, ["inputs", "graph"], "no step starts after the cancel");
    // Within a counted step: an island's operations stop after the first.
    let mut island = load_scene(root().join("fixtures/scenes/volcano-island-sketch.json")).unwrap();
    island.reconstruction.resolution = [64, 64];
    let mut progress = CancelAfter { steps: Steps::default(), after: usize::MAX, units: 0, after_units: 1 };
    let error = generate(&island, &root(), &mut progress).unwrap_err();
    assert!(matches!(error, relief::ReliefError::Cancelled), "{error}");
    assert_eq!(progress.units, 1);
    assert!(generate(&island, &root(), &mut ()).is_ok());
    // Within a DEM's vectorization: its fit stops at the iteration the cancel came after.
    let vectorize = jacksboro_vectorized(60);
    let mut progress = CancelAfter { steps: Steps::default(), after: usize::MAX, units: 0, after_units: 3 };
    let error = generate(&vectorize, &root(), &mut progress).unwrap_err();
    assert!(matches!(error, relief::ReliefError::Cancelled), "{error}");
    assert_eq!(progress.units, 3, "the fit went on after the cancel");
    let mut fit = FitProgress::default();
    assert!(generate(&vectorize, &root(), &mut fit).is_ok());
    assert_eq!(fit.0, (1..=60).map(|k| (k, 60)).collect::<Vec<_>>(), "each of the fit's iterations is reported");
    // Within a diffusion: it stops once its holes are filled, inside the one `diffusion` step.
    let mut ridges = load_scene(root().join("fixtures/scenes/mountain-ridges.json")).unwrap();
    ridges.reconstruction.resolution = [96, 96];
    let mut progress = CancelAfter { steps: Steps::default(), after: usize::MAX, units: 0, after_units: 1 };
    let error = generate(&ridges, &root(), &mut progress).unwrap_err();
    assert!(matches!(error, relief::ReliefError::Cancelled), "{error}");
    assert_eq!(progress.units, 1, "the solves went on after the cancel");
    let started: Vec<&str> = progress.steps.0.iter().filter(|(_, f)| !f).map(|(s, _)| *s).collect();
    assert_eq!(started, ["inputs", "diffusion"], "no step starts after the cancel");
    let mut units = StepUnits::default();
    assert!(generate(&ridges, &root(), &mut units).is_ok());
    let diffusion: Vec<_> = units.0.iter().filter(|u| u.0 == "diffusion").map(|u| (u.1, u.2)).collect();
    assert_eq!(diffusion, [(0, 3), (1, 3), (2, 3), (3, 3)], "each unit once, as it is reached");
}

/// Every progress report: `(step, done, total)`.
#[derive(Default)]
struct StepUnits(Vec<(&'static str, u64, u64)>);

impl Progress for StepUnits {
    fn start(&mut self, _: &'static str) {}
    fn finish(&mut self, _: &'static str, _: std::time::Duration) {}
    fn advance(&mut self, step: &'static str, done: u64, total: u64) {
        self.0.push((step, done, total));
    }
}

/// The `source` step's progress reports: `(done, total)`, after the first (0 of the total).
#[derive(Default)]
struct FitProgress(Vec<(u64, u64)>);

impl Progress for FitProgress {
    fn start(&mut self, _: &'static str) {}
    fn finish(&mut self, _: &'static str, _: std::time::Duration) {}
    fn advance(&mut self, step: &'static str, done: u64, total: u64) {
        if step == "source" && done > 0 {
            self.0.push((done, total));
        }
    }
}

#[test]
fn run_writes_every_output_atomically_and_reports_progress() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = full_scene(ReconstructionMode::Interpolated);
    scene.outputs.heightfield = ["t.exr", "t.png", "t.r32", "t.asc", "t.tif"].iter().map(PathBuf::from).collect();
    let mut steps = Steps::default();
    let (terrain, written) = run(&scene, &root(), dir.path(), &mut steps).unwrap();
    // Every step starts, then finishes, in order.
    let names = ["inputs", "graph", "growth", "heights", "contours", "edits", "reconstruction", "drainage", "write"];
    let expected: Vec<(&str, bool)> = names.iter().flat_map(|&s| [(s, false), (s, true)]).collect();
    assert_eq!(steps.0, expected);
    let mut files: Vec<String> =
        std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    files.sort();
    // Only the outputs (and the raw format's sidecar): no temporary file is left.
    let expected = vec![
        "contours.geojson",
        "contours.svg",
        "preview.png",
        "summary.json",
        "t.asc",
        "t.exr",
        "t.png",
        "t.prj",
        "t.r32",
        "t.r32.json",
        "t.tif",
    ];
    assert_eq!(files, expected);
    // Every file is reported written, sidecars and summary included.
    let mut reported: Vec<String> =
        written.iter().map(|p| p.file_name().unwrap().to_string_lossy().into_owned()).collect();
    reported.sort();
    assert_eq!(reported, expected);
    // The heightfield files hold the terrain (EXR and r32 exactly).
    for file in ["t.exr", "t.r32"] {
        let back = relief::io::read(dir.path().join(file)).unwrap();
        assert_eq!(back.samples(), terrain.heightfield.samples(), "{file}");
    }
    // GeoJSON: one feature per contour, each with its elevation, closed rings repeating their start.
    let geojson: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("contours.geojson")).unwrap()).unwrap();
    let features = geojson["features"].as_array().unwrap();
    assert_eq!(features.len(), terrain.contours.len());
    for (f, c) in features.iter().zip(terrain.contours.contours()) {
        assert_eq!(f["properties"]["elevation"].as_f64(), Some(c.height));
        let coords = f["geometry"]["coordinates"].as_array().unwrap();
        assert_eq!(coords.len(), c.points.len() + usize::from(c.closed));
        if c.closed {
            assert_eq!(coords.first(), coords.last());
        }
    }
    // The summary parses and carries the counts and the scene.
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["contours"]["contours"].as_u64(), Some(terrain.contours.len() as u64));
    assert_eq!(summary["scene"]["seed"].as_u64(), Some(9));
    assert_eq!(summary["timings_ms"].as_array().unwrap().len(), names.len());
    // The crater is the one closed basin, reported with the water it holds.
    assert_eq!(summary["drainage"]["closed_basins"].as_u64(), Some(terrain.summary.drainage.closed_basins as u64));
    assert!(terrain.summary.drainage.closed_basins >= 1 && terrain.summary.drainage.closed_volume > 0.0);
    assert!(terrain.summary.drainage.max_strahler >= 2);
    // The SVG is a document with one path per contour.
    let svg = std::fs::read_to_string(dir.path().join("contours.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert_eq!(svg.matches("<path ").count(), terrain.contours.len());
}

#[test]
fn erosion_post_processes_carve_the_terrain_and_fill_closes_nothing() {
    let mut scene = full_scene(ReconstructionMode::Interpolated);
    let plain = generate(&scene, &root(), &mut ()).unwrap();
    scene.post = vec![
        stream_power(10, 1.0, 1000.0),
        PostProcess::Thermal(Thermal { talus_deg: 33.0, rate: 0.25, iterations: 10 }),
    ];
    let eroded = generate(&scene, &root(), &mut ()).unwrap();
    let (a, b) = (plain.heightfield.samples(), eroded.heightfield.samples());
    assert!(b.iter().all(|v| v.is_finite()));
    let lowered = a.iter().zip(b).filter(|(x, y)| y < x).count();
    assert!(lowered > a.len() / 10, "erosion lowered only {lowered} cells");
    assert!(eroded.summary.timings_ms.iter().any(|t| t.step == "post-process"));
    // A final fill leaves nothing closed, the crater included.
    scene.post.push(PostProcess::Fill {});
    let filled = generate(&scene, &root(), &mut ()).unwrap();
    assert_eq!(filled.summary.drainage.closed_basins, 0);
    assert_eq!(closed_basins(&filled.heightfield, filled.sea_level.unwrap() as f32, |_| false), 0);
    // Bad parameters are scene errors at their JSON path.
    scene.post = vec![stream_power(1, -1.0, 1.0)];
    let err = generate(&scene, &root(), &mut ()).unwrap_err();
    assert!(matches!(&err, relief::ReliefError::Scene { path, .. } if path == "post[0].stream_power.n"), "{err}");
}

/// Fixture scene `name` at `resolution`, generated with one thread and again with two: the two
/// heightfields must be equal.
fn fixture_on_one_and_two_threads(name: &str, resolution: [usize; 2]) -> (Scene, relief::Terrain) {
    let text = std::fs::read_to_string(root().join("fixtures/scenes").join(name)).unwrap();
    let mut scene = Scene::from_json(&text).unwrap();
    scene.reconstruction.resolution = resolution;
    let one = with_threads(1, || generate(&scene, &root(), &mut ()).unwrap());
    let two = with_threads(2, || generate(&scene, &root(), &mut ()).unwrap());
    assert_eq!(one.heightfield, two.heightfield, "{name}: thread count changed the terrain");
    (scene, one)
}

#[test]
fn diffusion_scenes_run_through_the_same_pipeline() {
    let (mut scene, one) = fixture_on_one_and_two_threads("volcanic-island.json", [128, 128]);
    let report = one.summary.diffusion.as_ref().unwrap();
    assert!(report.converged, "{report:?}");
    assert!(one.summary.graph.is_none() && one.summary.histogram_match.is_none());
    // The crater rim stands high above the sea floor, which lies below sea level.
    let rim = one.heightfield.sample_bilinear(DVec2::new(1250.0, 200.0)).unwrap();
    let sea = one.heightfield.sample_bilinear(DVec2::new(-4700.0, 0.0)).unwrap();
    assert!(rim > 900.0 && sea < 0.0, "rim {rim}, sea {sea}");
    one.contours.check_invariants().unwrap();
    assert!(!one.contours.is_empty());
    // A bad value is a scene error at its JSON path.
    let Generator::Diffusion(g) = &mut scene.generator else { panic!("a diffusion scene") };
    g.curves[2].constraints[0].noise.as_mut().unwrap().roughness = 2.0;
    let err = generate(&scene, &root(), &mut ()).unwrap_err();
    assert!(
        matches!(&err, relief::ReliefError::Scene { path, .. } if path == "generator.diffusion.curves[2].constraints[0].noise.roughness"),
        "{err}"
    );
}

#[test]
fn presets_by_name_are_their_curves() {
    let generator = |curves: serde_json::Value, presets: serde_json::Value| {
        let json = serde_json::json!({
            "version": 1,
            "domain": { "min": [0, 0], "max": [2000, 2000] },
            "generator": { "diffusion": { "curves": curves, "presets": presets } },
            "reconstruction": { "resolution": [96, 96] }
        });
        Scene::from_json(&json.to_string())
    };
    let named = generator(
        serde_json::json!([]),
        serde_json::json!([
            { "ridge": { "points": [[200, 1000], [1800, 1200]], "start_h": 300, "peak_h": 900, "end_h": 400,
                         "angle": 25, "extent": 300, "noise": { "amplitude": 20, "roughness": 0.6 } } },
            { "crack": { "points": [[1000, 200], [1000, 1800]], "angle": 20, "extent": 80 } }
        ]),
    )
    .unwrap();
    let ridge = relief::diffusion::presets::ridge(
        &[DVec2::new(200.0, 1000.0), DVec2::new(1800.0, 1200.0)],
        300.0,
        900.0,
        400.0,
        25.0,
        300.0,
    );
    let crack = relief::diffusion::presets::crack(&[DVec2::new(1000.0, 200.0), DVec2::new(1000.0, 1800.0)], 20.0, 80.0);
    let curves = vec![relief::diffusion::presets::with_noise(ridge, 20.0, 0.6), crack];
    let written = generator(serde_json::to_value(curves).unwrap(), serde_json::json!([])).unwrap();
    let a = generate(&named, &root(), &mut ()).unwrap();
    let b = generate(&written, &root(), &mut ()).unwrap();
    assert_eq!(a.heightfield, b.heightfield);
    // A preset's bad value is an error at the preset.
    let bad = generator(
        serde_json::json!([]),
        serde_json::json!([{ "hill": { "points": [[0, 0], [100, 0]], "h": 10, "extent": -5 } }]),
    )
    .unwrap();
    let err = generate(&bad, &root(), &mut ()).unwrap_err();
    let path = err.scene_path().unwrap_or_default().to_owned();
    assert!(path.starts_with("generator.diffusion.presets[0]"), "{path}: {err}");
    let unknown = generator(serde_json::json!([]), serde_json::json!([{ "volcano": { "points": [[0, 0], [1, 1]] } }]));
    assert!(unknown.is_err(), "an unknown preset name is refused");
}

#[test]
fn scenes_choose_the_papers_fixed_jacobi_budget() {
    let text = std::fs::read_to_string(root().join("fixtures/scenes/mountain-ridges.json")).unwrap();
    let mut scene = Scene::from_json(&text).unwrap();
    scene.reconstruction.resolution = [129, 129];
    let Generator::Diffusion(g) = &mut scene.generator else { panic!("a diffusion scene") };
    g.solver = relief::diffusion::Solver::JacobiPyramid;
    g.max_iterations = Some(0);
    let paper = generate(&scene, &root(), &mut ()).unwrap();
    let report = paper.summary.diffusion.as_ref().unwrap();
    // The pyramid's 5·(l − i) sweeps per level and nothing more: no finest-level sweep after
    // it, whatever residual that leaves.
    assert_eq!((report.iterations, report.history.len()), (0, 1), "{report:?}");
    assert!(!report.converged && report.relative_residual > 1e-4, "{report:?}");
    let Generator::Diffusion(g) = &mut scene.generator else { unreachable!() };
    g.max_iterations = None;
    let converged = generate(&scene, &root(), &mut ()).unwrap();
    let report = converged.summary.diffusion.as_ref().unwrap();
    assert!(report.converged && report.iterations > 0, "{report:?}");
    assert_ne!(paper.heightfield, converged.heightfield);
}

/// The endorheic check on the generation graph itself (the TIN's node heights and CSR adjacency):
/// Open Eden Growth leaves no node without a non-ascending path to Ω's outside, unless a region is
/// a depression.
#[test]
fn grown_node_heights_have_no_endorheic_node_unless_a_depression_asks() {
    use relief::contours::{Histogram, Ranking, assign_heights};
    use relief::eden_growth::{Graph, GraphOptions, Region, RegionTree, Uniform, grow};
    use relief::hydrology::endorheic_nodes;
    use relief::poisson_sampling::Polygon;

    let ring = |c: [f64; 2], r: f64| {
        let wobble: Vec<f64> = (0..16).map(|k| (f64::from(k) * 2.3).sin().abs()).collect();
        Polygon::from_exterior(star(c, r, &wobble).into_iter().map(DVec2::from).collect()).unwrap()
    };
    for crater in [false, true] {
        let mut regions =
            vec![Region::new(ring([0.0, 0.0], 3000.0)).with_height(0.0), Region::new(ring([200.0, 0.0], 1200.0))];
        if crater {
            regions.push(Region::new(ring([200.0, 0.0], 400.0)).as_depression());
        }
        let tree = RegionTree::new(regions).unwrap();
        let graph = Graph::from_regions(&tree, &GraphOptions::particles(4000).with_seed(5)).unwrap();
        let growth = grow(&graph, &Uniform, 5).unwrap();
        let level_ends: Vec<usize> = (1..=growth.levels()).map(|l| growth.level_range(l).end).collect();
        let ranking =
            Ranking { order: growth.order(), level_ends: &level_ends, level_heights: &graph.level_heights()[1..] };
        let histogram = Histogram::uniform(0.0, 1000.0).unwrap();
        let heights = assign_heights(graph.tin().num_points(), &ranking, &histogram).unwrap();
        let tin = graph.tin();
        // Water leaves at the nodes outside Ω (the sea around the island).
        let outlet: Vec<bool> = (0..tin.num_points() as u32).map(|v| !graph.is_inside(v)).collect();
        let closed = endorheic_nodes(&heights.heights, tin.adjacency_offsets(), tin.adjacency(), &outlet).unwrap();
        if crater {
            assert!(!closed.is_empty(), "the crater's floor is a closed basin");
            // Every closed node lies in or near the crater.
            let far =
                closed.iter().filter(|&&v| tin.points()[v as usize].distance(DVec2::new(200.0, 0.0)) > 900.0).count();
            assert_eq!(far, 0, "closed nodes away from the crater");
        } else {
            assert!(closed.is_empty(), "{} closed nodes without a depression", closed.len());
        }
    }
}

#[test]
fn island_scenes_replay_identically_and_name_the_failing_operation() {
    let (mut scene, one) = fixture_on_one_and_two_threads("volcano-island-sketch.json", [160, 160]);
    let summary = one.summary.island.as_ref().unwrap();
    assert!(summary.hills == 4 && summary.perturbations > 0, "{summary:?}");
    // Sea is exactly 0, land above the sea level; the crater sits below its rim.
    let h = |x: f64, y: f64| one.heightfield.sample_bilinear(DVec2::new(x, y)).unwrap();
    assert_eq!(h(20.0, 20.0), 0.0);
    assert!(
        h(1900.0, 2000.0) + 100.0 < h(1900.0 + 700.0, 2000.0),
        "crater {} rim {}",
        h(1900.0, 2000.0),
        h(2600.0, 2000.0)
    );
    assert!(one.heightfield.samples().iter().all(|&v| v == 0.0 || f64::from(v) > one.sea_level.unwrap()));
    one.contours.check_invariants().unwrap();
    // A stroke that never reaches the coast fails at its operation's JSON path.
    let Generator::Island(g) = &mut scene.generator else { panic!("an island scene") };
    g.operations.insert(1, serde_json::from_str(r#"{"stroke": {"points": [[1900, 1900], [2000, 2000]]}}"#).unwrap());
    let err = generate(&scene, &root(), &mut ()).unwrap_err();
    assert!(
        matches!(&err, relief::ReliefError::Scene { path, .. } if path == "generator.island.operations[1]"),
        "{err}"
    );
    assert!(err.to_string().contains("never touches the coastline"), "{err}");
}

/// An island scene on a 1 km square (the start circle has radius 400 m about the centre) with
/// `operations`.
fn island(operations: &serde_json::Value) -> Scene {
    let scene = serde_json::json!({
        "version": 1, "seed": 1, "domain": { "min": [0, 0], "max": [1000, 1000] },
        "generator": { "island": { "operations": operations } },
        "reconstruction": { "resolution": [64, 64] }
    });
    Scene::from_json(&scene.to_string()).unwrap()
}

#[test]
fn strokes_that_keep_the_smaller_piece_and_hills_that_change_nothing_are_warned_about() {
    // Drawn northward at x = 700, a stroke cuts off the land to its left: the larger, western part.
    let north = serde_json::json!([{ "stroke": { "points": [[700, -50], [700, 1050]] } }]);
    let terrain = generate(&island(&north), &root(), &mut ()).unwrap();
    let [warning] = terrain.summary.warnings.as_slice() else { panic!("{:?}", terrain.summary.warnings) };
    assert!(warning.starts_with("generator.island.operations[0]: the stroke removed 8"), "{warning}");
    assert!(warning.contains("draw it the other way"), "{warning}");
    // Drawn southward, it cuts off the eastern sliver: what was meant, no warning.
    let south = serde_json::json!([{ "stroke": { "points": [[700, 1050], [700, -50]] } }]);
    let terrain = generate(&island(&south), &root(), &mut ()).unwrap();
    assert!(terrain.summary.warnings.is_empty(), "{:?}", terrain.summary.warnings);
    assert!(terrain.summary.island.as_ref().unwrap().area > 0.8 * std::f64::consts::PI * 400.0 * 400.0);
    // Hills raise land only: one in the sea and one off the map change nothing, one on land does.
    let hills = serde_json::json!([
        { "add_hill": { "center": [60, 60], "radii": [40, 40], "height": 100 } },
        { "add_hill": { "center": [5000, 500], "radii": [40, 40], "height": 100 } },
        { "add_hill": { "center": [500, 500], "radii": [40, 40], "height": 100 } },
        { "add_hill": { "center": [130, 500], "radii": [40, 40], "height": 100 } }
    ]);
    let terrain = generate(&island(&hills), &root(), &mut ()).unwrap();
    let warnings = &terrain.summary.warnings;
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    assert!(warnings[0].contains("hill 0 (centre 60, 60) lies in the sea"), "{warnings:?}");
    assert!(warnings[1].contains("hill 1 (centre 5000, 500) lies outside the domain"), "{warnings:?}");
}

/// The sea is the base level of erosion: stream power never touches a cell below the sea level,
/// even where the sea floor slopes (a diffusion scene's `sea_level`).
#[test]
fn erosion_leaves_the_sea_floor_alone() {
    let text = std::fs::read_to_string(root().join("fixtures/scenes/volcanic-island.json")).unwrap();
    let mut scene = Scene::from_json(&text).unwrap();
    scene.reconstruction.resolution = [96, 96];
    let plain = generate(&scene, &root().join("fixtures/scenes"), &mut ()).unwrap();
    let sea = plain.sea_level.expect("the volcanic island has a sea") as f32;
    scene.post = vec![stream_power(10, 1.0, 1000.0)];
    let eroded = generate(&scene, &root().join("fixtures/scenes"), &mut ()).unwrap();
    let (a, b) = (plain.heightfield.samples(), eroded.heightfield.samples());
    let under = a.iter().zip(b).filter(|(before, _)| **before < sea);
    let (count, moved) = under.fold((0, 0), |(n, m), (x, y)| (n + 1, m + usize::from(x != y)));
    assert!(count > a.len() / 10, "{count} sea cells");
    assert_eq!(moved, 0, "sea cells eroded");
    assert!(a.iter().zip(b).any(|(x, y)| y < x), "the land erodes");
}

/// Without a `domain`, drawn inputs get their bounds grown by 5 % and widened to the raster's
/// aspect so cells are square; a degenerate bounding box still makes a grid.
#[test]
fn default_domains_fit_the_inputs_with_square_cells() {
    // Wide regions on a square raster: the domain is widened in y.
    let wide = vec![region(vec![[0.0, 0.0], [4000.0, 0.0], [4000.0, 1000.0], [0.0, 1000.0]], Some(0.0), false)];
    let mut s = scene(1, wide, Vec::new(), ReconstructionMode::Stairs, 64);
    let terrain = generate(&s, &root(), &mut ()).unwrap();
    let e = terrain.heightfield.extent();
    assert!((e.min.x + 200.0).abs() < 1e-9 && (e.max.x - 4200.0).abs() < 1e-9, "{e:?}");
    assert!((e.size().y - 4400.0).abs() < 1e-9 && (e.center().y - 500.0).abs() < 1e-9, "{e:?}");
    // Tall regions on a wide raster: widened in x, cells square.
    let tall = vec![region(vec![[0.0, 0.0], [1000.0, 0.0], [1000.0, 3000.0], [0.0, 3000.0]], Some(0.0), false)];
    s = scene(1, tall, Vec::new(), ReconstructionMode::Stairs, 64);
    s.reconstruction.resolution = [97, 49];
    let grid = *generate(&s, &root(), &mut ()).unwrap().heightfield.grid();
    assert!((grid.cell_size().x - grid.cell_size().y).abs() < 1e-9, "{grid:?}");
    assert!((grid.extent().size().y - 3300.0).abs() < 1e-9, "{grid:?}");
    // A single horizontal feature curve: its bounding box has no height, the domain still does.
    let flat: Scene = serde_json::from_value(serde_json::json!({
        "version": 1,
        "generator": { "diffusion": { "curves": [
            { "points": [[0, 0], [1000, 0]], "constraints": [{ "u": 0.5, "elevation": { "h": 100 } }] }
        ] } },
        "reconstruction": { "resolution": [33, 33] }
    }))
    .unwrap();
    let e = generate(&flat, &root(), &mut ()).unwrap().heightfield.extent();
    assert!(e.size().y > 0.0 && (e.size().x - e.size().y).abs() < 1e-6, "{e:?}");
}

/// One arched curve at 800 m with detail noise, on a 64² raster, with `border` (left out when
/// `None`).
fn one_curve(border: Option<serde_json::Value>) -> Scene {
    let mut generator = serde_json::json!({
        "curves": [{
            "points": [[0, 0], [1300, 900], [2700, 900], [4000, 0]],
            "constraints": [{ "u": 0.5, "elevation": { "h": 800, "r": 0 }, "noise": { "amplitude": 40, "roughness": 0.5 } }]
        }]
    });
    if let Some(b) = border {
        generator["border"] = b;
    }
    let scene = serde_json::json!({
        "version": 1, "generator": { "diffusion": generator }, "reconstruction": { "resolution": [64, 64] }
    });
    Scene::from_json(&scene.to_string()).unwrap()
}

#[test]
fn a_first_curve_stands_out_and_noise_that_hides_the_relief_is_warned_about() {
    // Free, as in the paper, one elevation diffuses to itself everywhere: flat, noise on top.
    let free = generate(&one_curve(Some(serde_json::json!("free"))), &root(), &mut ()).unwrap();
    let (lo, hi) = free.heightfield.min_max().unwrap();
    assert!(hi - lo < 200.0 && lo > 650.0, "{lo} .. {hi}");
    let [warning] = free.summary.warnings.as_slice() else { panic!("{:?}", free.summary.warnings) };
    assert!(warning.contains("detail noise (amplitude up to 40) is as tall as the relief"), "{warning}");
    // By default such a scene holds the border at 0 with no noise there: a ridge stands out.
    let ridge = generate(&one_curve(None), &root(), &mut ()).unwrap();
    assert!(ridge.summary.warnings.is_empty(), "{:?}", ridge.summary.warnings);
    let hf = &ridge.heightfield;
    let (nx, ny) = (hf.nx(), hf.ny());
    let border = (0..nx).flat_map(|i| [(i, 0), (i, ny - 1)]).chain((0..ny).flat_map(|j| [(0, j), (nx - 1, j)]));
    assert!(border.into_iter().all(|(i, j)| hf.value(i, j).abs() < 1e-3));
    let top = hf.sample_bilinear(DVec2::new(2000.0, 850.0)).unwrap();
    assert!(top > 700.0, "ridge at {top}");
    // Noise fades away from the curve: the field between the ridge and the border is smooth.
    let smooth_row = (1..nx - 1).map(|i| hf.value(i, 3)).collect::<Vec<_>>();
    let wiggle = smooth_row.windows(3).map(|w| (w[0] - 2.0 * w[1] + w[2]).abs()).fold(0.0_f32, f32::max);
    let near = (1..nx - 1).map(|i| hf.value(i, ny / 2)).collect::<Vec<_>>();
    let rough = near.windows(3).map(|w| (w[0] - 2.0 * w[1] + w[2]).abs()).fold(0.0_f32, f32::max);
    assert!(wiggle < 0.25 * rough, "{wiggle} near the border, {rough} near the curve");
    // An explicit border elevation is held as given; the noise there too when it is held at 0,
    // else the curve's noise reaches the border.
    let held = serde_json::json!({ "held": { "elevation": 100, "noise": 0 } });
    let held = generate(&one_curve(Some(held)), &root(), &mut ()).unwrap();
    assert!((held.heightfield.value(0, 0) - 100.0).abs() < 1e-3);
    let noisy = serde_json::json!({ "held": { "elevation": 100 } });
    let noisy = generate(&one_curve(Some(noisy)), &root(), &mut ()).unwrap();
    assert!((noisy.heightfield.value(0, 0) - 100.0).abs() > 1e-3);
}

/// Every progress report: start, advance (done, total), finish.
#[derive(Default)]
struct Reports(Vec<(&'static str, Option<(u64, u64)>)>);

impl Progress for Reports {
    fn start(&mut self, step: &'static str) {
        self.0.push((step, None));
    }
    fn advance(&mut self, step: &'static str, done: u64, total: u64) {
        self.0.push((step, Some((done, total))));
    }
    fn finish(&mut self, _: &'static str, _: std::time::Duration) {}
}

#[test]
fn countable_steps_report_how_far_they_are() {
    let mut scene = island(&serde_json::json!([
        { "add_hill": { "center": [500, 500], "radii": [100, 100], "height": 50 } },
        { "add_hill": { "center": [400, 500], "radii": [80, 80], "height": 30 } },
        { "add_filters": {} },
    ]));
    let post = serde_json::json!([{ "thermal": { "iterations": 5 } }, { "fill": {} }]);
    scene.post = serde_json::from_value(post).unwrap();
    let mut reports = Reports::default();
    generate(&scene, &root(), &mut reports).unwrap();
    let of = |step: &str| -> Vec<(u64, u64)> {
        reports.0.iter().filter(|(s, _)| *s == step).filter_map(|&(_, a)| a).collect()
    };
    // One unit per operation; one per erosion pass and one per fill, from 0 to the total.
    assert_eq!(of("island"), [(0, 3), (1, 3), (2, 3), (3, 3)]);
    assert_eq!(of("post-process"), (0..=6).map(|k| (k, 6)).collect::<Vec<_>>());
    // Reports come between the step's start and the next step's.
    let start = reports.0.iter().position(|r| *r == ("post-process", None)).unwrap();
    assert_eq!(reports.0[start + 1], ("post-process", Some((0, 6))));
    assert!(of("drainage").is_empty(), "a step that cannot count its work does not report");
}

#[test]
fn a_craters_depth_sets_how_far_its_floor_lies_below_its_rim() {
    let floor = |depth: f64| {
        let mut scene = full_scene(ReconstructionMode::Tin);
        scene.edits.clear();
        let Generator::Contours(g) = &mut scene.generator else { unreachable!() };
        g.regions[3].depth = Some(depth);
        let terrain = generate(&scene, &root(), &mut ()).unwrap();
        let hf = &terrain.heightfield;
        (0..hf.samples().len())
            .filter(|&k| hf.grid().position(k % hf.nx(), k / hf.nx()).distance(DVec2::new(-1500.0, 0.0)) < 250.0)
            .map(|k| hf.samples()[k])
            .fold(f32::INFINITY, f32::min)
    };
    let (shallow, deep) = (floor(100.0), floor(400.0));
    assert!((shallow - deep - 300.0).abs() < 40.0, "floors {shallow} and {deep}");
    // Only a depression has a depth.
    let mut scene = full_scene(ReconstructionMode::Tin);
    let Generator::Contours(g) = &mut scene.generator else { unreachable!() };
    g.regions[1].depth = Some(50.0);
    let err = generate(&scene, &root(), &mut ()).unwrap_err();
    assert!(err.to_string().starts_with("generator.contours.regions[1].depth"), "{err}");
}

/// A DEM in degrees vectorizes into primitives in degrees: the raster keeps the DEM's units and
/// CRS, so its cells are as many metres wide as the DEM's, not taken for metres themselves.
#[test]
fn a_vectorized_geographic_dem_keeps_its_units_and_crs() {
    let dem = relief::io::read(root().join("fixtures/dem/jacksboro.asc")).unwrap();
    assert_eq!(dem.grid().units(), relief::heightfield::Units::Degrees);
    assert!(dem.crs().is_some(), "jacksboro.prj names its CRS");
    let scene = jacksboro_vectorized(5);
    let terrain = generate(&scene, &root(), &mut ()).unwrap();
    let hf = &terrain.heightfield;
    assert_eq!(hf.grid().units(), relief::heightfield::Units::Degrees);
    assert_eq!(hf.crs(), dem.crs());
    let (ours, theirs) = (hf.grid().metres_per_unit(16), dem.grid().metres_per_unit(dem.ny() / 2));
    assert!((ours.x / theirs.x - 1.0).abs() < 0.01, "{ours} m per degree, the DEM's {theirs}");
}

fn operations_len(scene: &relief::Scene) -> u64 {
    let relief::scene::Generator::Island(island) = &scene.generator else { panic!("an island scene") };
    island.operations.len() as u64
}

/// The `island` step's progress reports: the operations done.
#[derive(Default)]
struct IslandStart(Vec<u64>);

impl Progress for IslandStart {
    fn start(&mut self, _: &'static str) {}
    fn finish(&mut self, _: &'static str, _: std::time::Duration) {}
    fn advance(&mut self, step: &'static str, done: u64, _: u64) {
        if step == "island" {
            self.0.push(done);
        }
    }
}

/// An editing session applies only the operations appended since a kept island, keeps the one
/// before for an undo, replays when the history changed, and always gives a fresh replay's bytes
/// (filters included: their random state is part of the island).
#[test]
fn an_edit_session_resumes_its_island_and_matches_a_replay() {
    let mut scene = load_scene(root().join("fixtures/scenes/volcano-island-sketch.json")).unwrap();
    scene.reconstruction.resolution = [96, 96];
    let relief::scene::Generator::Island(island) = &scene.generator else { panic!("an island scene") };
    let all = island.operations.clone();
    let stroke: relief::island::Operation = serde_json::from_value(
        serde_json::json!({ "stroke": { "points": [[3300, 1200], [3900, 2000], [3300, 2800]] } }),
    )
    .unwrap();
    // (the operations, where the session should start applying them)
    let history = [
        (all[..2].to_vec(), 0),
        (all[..4].to_vec(), 2),
        (all.clone(), 4),
        (all[..4].to_vec(), 4),                            // undo: the state kept before
        ([all.clone(), vec![stroke.clone()]].concat(), 5), // redo, then a stroke
        ([&all[..3], &[stroke.clone()][..]].concat(), 0),  // another history: a replay
        ([&all[..3], &[stroke, all[4].clone()][..]].concat(), 4),
    ];
    let mut session = relief::pipeline::EditSession::new();
    for (k, (operations, start)) in history.into_iter().enumerate() {
        let relief::scene::Generator::Island(island) = &mut scene.generator else { unreachable!() };
        island.operations = operations;
        let mut progress = IslandStart::default();
        let resumed =
            relief::pipeline::preview_in(&mut session, &scene, &root(), &relief::Budget::default(), &mut progress)
                .unwrap();
        let replayed = relief::pipeline::preview_with(&scene, &root(), &relief::Budget::default(), &mut ()).unwrap();
        assert_eq!(session.resumed(), start, "step {k}");
        // The step's count starts where the session resumed.
        let n = operations_len(&scene);
        let counted: Vec<u64> = if start > 0 { vec![0, start as u64] } else { vec![0] };
        let expected: Vec<u64> = counted.into_iter().chain(start as u64 + 1..=n).collect();
        assert_eq!(progress.0, expected, "step {k}");
        assert_eq!(resumed.heightfield, replayed.heightfield, "step {k}");
        assert_eq!(resumed.warnings, replayed.warnings, "step {k}");
        // The stroke keeps only the bump it encloses: its warning is carried by the kept island.
        let stroked = island_ops(&scene).iter().any(|op| matches!(op, relief::island::Operation::Stroke { .. }));
        assert_eq!(resumed.warnings.iter().any(|w| w.contains("removed")), stroked, "step {k}: {:?}", resumed.warnings);
        assert_eq!(session.kept(), if k == 0 { 1 } else { 2 }, "step {k}");
    }
    // A scene of another kind resumes nothing.
    let other = load_scene(root().join("fixtures/scenes/mountain-ridges.json")).unwrap();
    let mut small = other.clone();
    small.reconstruction.resolution = [33, 33];
    relief::pipeline::preview_in(&mut session, &small, &root(), &relief::Budget::default(), &mut ()).unwrap();
    assert_eq!(session.resumed(), 0);
    // The same operations under another seed, or at another resolution: a replay.
    for change in [|s: &mut relief::Scene| s.seed += 1, |s: &mut relief::Scene| s.reconstruction.resolution = [80, 80]]
    {
        change(&mut scene);
        let resumed =
            relief::pipeline::preview_in(&mut session, &scene, &root(), &relief::Budget::default(), &mut ()).unwrap();
        assert_eq!(session.resumed(), 0);
        let replayed = relief::pipeline::preview_with(&scene, &root(), &relief::Budget::default(), &mut ()).unwrap();
        assert_eq!(resumed.heightfield, replayed.heightfield);
    }
}

fn island_ops(scene: &relief::Scene) -> &[relief::island::Operation] {
    let relief::scene::Generator::Island(island) = &scene.generator else { panic!("an island scene") };
    &island.operations
}

/// The Jacksboro DEM vectorized into 40 primitives over `iterations` steps, at 32².
fn jacksboro_vectorized(iterations: usize) -> relief::Scene {
    serde_json::from_value(serde_json::json!({
        "version": 1,
        "generator": { "gaussian": { "source": { "kind": "dem", "path": "fixtures/dem/jacksboro.asc",
            "primitives": 40, "iterations": iterations, "resolution": 32 }, "operations": [] } },
        "reconstruction": { "resolution": [32, 32] }
    }))
    .unwrap()
}
