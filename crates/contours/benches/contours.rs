//! Contour extraction at the contours paper's Table 1 sizes, reconstruction at 2048², smoothing,
//! and the 1M-particle pipeline end to end.
//!
//! Paper (Ryzen 5 5600X, ms): extraction of 10/20/30 levels at 100k: 71/142/212; at 500k:
//! 386/766/1 140. Targets here: 30 levels at 500k under 150 ms; 1M particles end to end (sampling,
//! TIN, growth, 30 levels) under 4 s; interpolated reconstruction at 2048² under 1 s.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec2;
use relief_contours::{
    ContourSet, Histogram, Interpolation, Ranking, Smoothing, assign_heights, evenly_spaced_levels, extract_tin,
    reconstruct_interpolated, reconstruct_stairs,
};
use relief_eden_growth::{Graph, GraphOptions, Region, RegionTree, Uniform, grow};
use relief_fixtures::island_coast;
use relief_heightfield::{Extent, GridSpec};
use relief_tin::Tin;

/// The 15 km wavy island of the paper's single-region timing scene.
fn island() -> RegionTree {
    RegionTree::new(vec![Region::new(island_coast())]).expect("regions")
}

fn histogram() -> Histogram {
    Histogram::from_bins(vec![0.0, 200.0, 600.0, 1200.0, 2000.0], vec![4.0, 3.0, 2.0, 1.0]).expect("histogram")
}

/// Graph, growth and node heights for `n` particles.
fn terrain(tree: &RegionTree, n: usize) -> (Tin, Vec<f64>) {
    let graph = Graph::from_regions(tree, &GraphOptions::particles(n).with_seed(1)).expect("graph");
    let growth = grow(&graph, &Uniform, 1).expect("growth");
    let ends = [growth.order().len()];
    let ranking = Ranking { order: growth.order(), level_ends: &ends, level_heights: &[None] };
    let heights = assign_heights(graph.tin().num_points(), &ranking, &histogram()).expect("heights");
    (graph.tin().clone(), heights.heights)
}

/// `cargo xtask bench --quick` sets `RELIEF_BENCH_QUICK`: the largest sizes are skipped then.
fn quick() -> bool {
    std::env::var_os("RELIEF_BENCH_QUICK").is_some()
}

fn bench(c: &mut Criterion) {
    let tree = island();
    let mut group = c.benchmark_group("contours");
    group.sample_size(10);
    let mut at_100k: Option<ContourSet> = None;
    for n in [100_000usize, 500_000] {
        let (tin, heights) = terrain(&tree, n);
        for k in [10usize, 20, 30] {
            let levels = evenly_spaced_levels(0.0, 2000.0, k).expect("levels");
            group.bench_with_input(BenchmarkId::new(format!("extract_{k}_levels"), n), &levels, |b, levels| {
                b.iter(|| black_box(extract_tin(&tin, &heights, levels)));
            });
            if n == 100_000 && k == 30 {
                at_100k = Some(extract_tin(&tin, &heights, &levels).expect("contours"));
            }
        }
    }
    let set = at_100k.expect("contours at 100k");
    let grid =
        GridSpec::from_extent(2048, 2048, Extent::new(DVec2::splat(-7200.0), DVec2::splat(7200.0))).expect("grid");
    if !quick() {
        group.bench_function("reconstruct_interpolated_2048", |b| {
            b.iter(|| black_box(reconstruct_interpolated(&set, &grid, -1.0, &Interpolation::default())));
        });
    }
    group.bench_function("reconstruct_stairs_2048", |b| b.iter(|| black_box(reconstruct_stairs(&set, &grid, -1.0))));
    group.bench_function("smooth_100k_30_levels", |b| b.iter(|| black_box(set.smoothed(&Smoothing::default()))));
    if !quick() {
        group.bench_function(BenchmarkId::new("pipeline_30_levels", 1_000_000), |b| {
            let levels = evenly_spaced_levels(0.0, 2000.0, 30).expect("levels");
            b.iter(|| {
                let (tin, heights) = terrain(&tree, 1_000_000);
                black_box(extract_tin(&tin, &heights, &levels))
            });
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
