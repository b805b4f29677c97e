//! The facade's benchmarks: the contours paper's Table 1 protocol on the authors' own input (the
//! `reunion.png` coastline over a 15 km box, uniform probability, growth timed without graph
//! building, extraction of 10/20/30 evenly spaced levels), the demo scene end to end, and preview
//! rendering at 4096².
//!
//! Paper (Ryzen 5 5600X, ms): growth 10k 86, 20k 297, 50k 1 880, 100k 5 827, 500k 91 790;
//! extraction at 100k 71/142/212, at 500k 386/766/1 140. The authors' code on this machine class:
//! growth 10k ~180, 50k ~3 500, 100k ~6 900; graph 100k ~1 900; 30 levels at 100k ~340.
//! Targets: `relief demo` (generation and every output) under 5 s; a 4096² preview under 1 s.

use std::hint::black_box;
use std::path::Path;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec2;
use relief::Scene;
use relief::contours::{Histogram, Ranking, assign_heights, evenly_spaced_levels, extract_tin};
use relief::eden_growth::{Graph, GraphOptions, LabelMap, MaskOptions, Sampling, Uniform, grow};
use relief::heightfield::noise::Fbm;
use relief::heightfield::{Extent, GridSpec, Heightfield};
use relief::io::ReadOptions;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

/// The authors' Table 1 input: the Réunion coastline mask over a 15 km box.
fn reunion() -> LabelMap {
    let image = relief::io::read_gray_image(root().join("fixtures/scenes/inputs/reunion.png"), &ReadOptions::default())
        .expect("reunion.png");
    let grid =
        GridSpec::from_extent(image.nx(), image.ny(), Extent::new(DVec2::ZERO, DVec2::splat(15_000.0))).expect("grid");
    LabelMap::from_values(grid, image.samples()).expect("label map")
}

/// `cargo xtask bench --quick` sets `RELIEF_BENCH_QUICK`: the largest sizes are skipped then.
fn quick() -> bool {
    std::env::var_os("RELIEF_BENCH_QUICK").is_some()
}

fn table1(c: &mut Criterion) {
    let labels = reunion();
    let mut group = c.benchmark_group("relief_table1");
    group.sample_size(10);
    for n in [10_000usize, 20_000, 50_000, 100_000, 500_000] {
        let graph = Graph::from_labels(&labels, &GraphOptions::particles(n).with_seed(1)).expect("graph");
        group
            .bench_with_input(BenchmarkId::new("growth", n), &graph, |b, g| b.iter(|| black_box(grow(g, &Uniform, 1))));
        if n == 100_000 || n == 500_000 {
            let growth = grow(&graph, &Uniform, 1).expect("growth");
            let ends = [growth.order().len()];
            let ranking = Ranking { order: growth.order(), level_ends: &ends, level_heights: &[None] };
            let histogram = Histogram::uniform(0.0, 3000.0).expect("histogram");
            let heights = assign_heights(graph.tin().num_points(), &ranking, &histogram).expect("heights").heights;
            for k in [10usize, 20, 30] {
                let levels = evenly_spaced_levels(0.0, 3000.0, k).expect("levels");
                group.bench_with_input(BenchmarkId::new(format!("extract_{k}_levels"), n), &levels, |b, l| {
                    b.iter(|| black_box(extract_tin(graph.tin(), &heights, l)));
                });
            }
        }
    }
    group.bench_function(BenchmarkId::new("graph", 100_000), |b| {
        b.iter(|| black_box(Graph::from_labels(&labels, &GraphOptions::particles(100_000).with_seed(1))));
    });
    group.finish();
}

fn demo(c: &mut Criterion) {
    let scene = Scene::demo();
    let mut group = c.benchmark_group("relief_demo");
    group.sample_size(10);
    group.bench_function("generate", |b| b.iter(|| black_box(relief::pipeline::generate(&scene, root(), &mut ()))));
    if !quick() {
        let dir = tempfile::tempdir().expect("temporary directory");
        group.bench_function("generate_and_write", |b| {
            b.iter(|| black_box(relief::pipeline::run(&scene, root(), dir.path(), &mut ())));
        });
    }
    group.finish();

    let grid = GridSpec::from_extent(4096, 4096, Extent::new(DVec2::ZERO, DVec2::splat(40_960.0))).expect("grid");
    let fbm = Fbm { octaves: 8, frequency: 1.0 / 8000.0, lacunarity: 2.0, gain: 0.5, seed: 1 };
    let dem = Heightfield::from_fn(grid, |p| (1500.0 * fbm.sample(p)) as f32).expect("dem");
    let mut group = c.benchmark_group("relief_preview");
    group.sample_size(10);
    group.bench_function("shade_4096", |b| b.iter(|| black_box(relief::export::preview_image(&dem, None, Some(0.0)))));
    group.finish();
}

/// The contours issue's additions: multi-level generation against one pass, cleaning a drawn
/// 2048² mask, regrowing the Jacksboro DEM from its contours with the §6.5 comparison.
fn contours(c: &mut Criterion) {
    let scenes = root().join("fixtures/scenes");
    let mut group = c.benchmark_group("relief_contours");
    group.sample_size(10);
    let mut scene = relief::pipeline::load_scene(scenes.join("coastline-island.json")).expect("scene");
    scene.reconstruction.resolution = [256, 192];
    for passes in [1u32, 3] {
        if let relief::scene::Generator::Contours(g) = &mut scene.generator {
            g.particles = Some(100_000);
            g.multilevel = (passes > 1).then_some(relief::scene::Multilevel { passes, factor: 4.0, contrast: 6.0 });
        }
        group.bench_with_input(BenchmarkId::new("multilevel", passes), &scene, |b, s| {
            b.iter(|| black_box(relief::pipeline::generate(s, &scenes, &mut ())));
        });
    }
    let image = relief::io::read_color_image(scenes.join("inputs/teaser-2-a.png"), &ReadOptions::default())
        .expect("teaser mask");
    let options = MaskOptions { levels: None, sampling: Sampling::Particles(50_000) };
    group.bench_function("mask_clean/2048", |b| {
        b.iter(|| black_box(LabelMap::from_mask(image.grid, &image.pixels, &options)));
    });
    let regrown = relief::pipeline::load_scene(scenes.join("jacksboro-regrown.json")).expect("scene");
    group.bench_function("regrow_jacksboro", |b| {
        b.iter(|| black_box(relief::pipeline::generate(&regrown, &scenes, &mut ())));
    });
    group.finish();
}

criterion_group!(benches, table1, demo, contours);
criterion_main!(benches);
