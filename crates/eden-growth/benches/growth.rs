//! Inward Open Eden Growth at the contours paper's Table 1 sizes (10k … 500k particles) plus 1M,
//! growth time only (graph built beforehand, as in the paper's protocol), and graph creation.
//!
//! Paper (Ryzen 5 5600X, ms): 10k 86, 20k 297, 50k 1 880, 100k 5 827, 500k 91 790. Fig. 26:
//! 2 to 6 regions take at most twice one region's time.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec2;
use relief_eden_growth::{Graph, GraphOptions, Region, RegionTree, Uniform, grow};
use relief_tin::poisson_sampling::Polygon;

/// A 15 km island with a wavy coast, as the paper's single-region timing scene.
fn island() -> RegionTree {
    RegionTree::new(vec![Region::new(relief_fixtures::island_coast())]).expect("regions")
}

/// `cargo xtask bench --quick` sets `RELIEF_BENCH_QUICK`: the largest sizes are skipped then.
fn quick() -> bool {
    std::env::var_os("RELIEF_BENCH_QUICK").is_some()
}

fn bench(c: &mut Criterion) {
    let tree = island();
    let mut group = c.benchmark_group("eden");
    group.sample_size(10);
    let largest = if quick() { 500_000 } else { 1_000_000 };
    for n in [10_000usize, 20_000, 50_000, 100_000, 500_000, 1_000_000].into_iter().filter(|&n| n <= largest) {
        let graph = Graph::from_regions(&tree, &GraphOptions::particles(n).with_seed(1)).expect("graph");
        group
            .bench_with_input(BenchmarkId::new("growth", n), &graph, |b, g| b.iter(|| black_box(grow(g, &Uniform, 1))));
    }
    let ranges = RegionTree::new(vec![
        tree.regions()[0].clone(),
        Region::new(Polygon::circle(DVec2::new(-2000.0, 0.0), 1800.0, 64).expect("range")),
        Region::new(Polygon::circle(DVec2::new(2500.0, 500.0), 1200.0, 64).expect("range")),
    ])
    .expect("regions");
    let graph = Graph::from_regions(&ranges, &GraphOptions::particles(100_000).with_seed(1)).expect("graph");
    group.bench_with_input(BenchmarkId::new("growth_two_levels", 100_000), &graph, |b, g| {
        b.iter(|| black_box(grow(g, &Uniform, 1)));
    });
    // Fig. 26: growth time against the number of nested regions m at 100k particles (the paper
    // measures up to six and finds at most twice the single-region time).
    for m in [1usize, 2, 4, 16, 64] {
        let graph =
            Graph::from_regions(&nested(&tree, m), &GraphOptions::particles(100_000).with_seed(1)).expect("graph");
        group.bench_with_input(BenchmarkId::new("regions", m), &graph, |b, g| {
            b.iter(|| black_box(grow(g, &Uniform, 1)));
        });
    }
    group.bench_function(BenchmarkId::new("graph", 100_000), |b| {
        b.iter(|| black_box(Graph::from_regions(&tree, &GraphOptions::particles(100_000).with_seed(1))));
    });
    group.finish();
}

/// The island with `m − 1` concentric regions nested inside its coast (radii from 4.5 km down).
fn nested(island: &RegionTree, m: usize) -> RegionTree {
    let mut regions = vec![island.regions()[0].clone()];
    for k in 1..m {
        let r = 4500.0 * (1.0 - (k - 1) as f64 / (m - 1) as f64 * 0.95);
        regions.push(Region::new(Polygon::circle(DVec2::ZERO, r, 96).expect("ring")));
    }
    RegionTree::new(regions).expect("nested regions")
}

criterion_group!(benches, bench);
criterion_main!(benches);
