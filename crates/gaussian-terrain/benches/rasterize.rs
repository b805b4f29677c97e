//! Rasterization at the paper's sizes (Table 1 and §6.1, RTX 3090): 1024² with 10k / 30k / 60k
//! primitives (15–21 ms) and 4096² with 60k (388 ms). The terrains are synthetic
//! (`relief_fixtures::random_terrain`): on average 16 supports cover each point, β mixed in
//! [1.2, 4].

use std::hint::black_box;
use std::ops::ControlFlow;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec2;
use relief_fixtures::{fbm_dem, random_terrain};
use relief_gaussian_terrain::{RasterOptions, VectorizeOptions, rasterize, vectorize};
use relief_heightfield::{Extent, GridSpec};

/// `cargo xtask bench --quick` sets `RELIEF_BENCH_QUICK`: the largest sizes are skipped then.
fn quick() -> bool {
    std::env::var_os("RELIEF_BENCH_QUICK").is_some()
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("gaussian_terrain");
    group.sample_size(10);
    let largest = if quick() { 1024 } else { 4096 };
    for (n, count) in [(1024usize, 10_000usize), (1024, 30_000), (1024, 60_000), (4096, 60_000)] {
        if n > largest {
            continue;
        }
        let terrain = random_terrain(count, 1000.0, 16.0, 1);
        let grid = GridSpec::from_extent(n, n, Extent::new(DVec2::ZERO, DVec2::splat(1000.0))).expect("grid");
        let id = BenchmarkId::new("rasterize", format!("{n}/{}k", count / 1000));
        group.bench_with_input(id, &terrain, |b, t| {
            b.iter(|| black_box(rasterize(t, &grid, &RasterOptions::default()).expect("raster")));
        });
        // The same samples as continuous queries, batched (the hierarchy built outside the
        // timing, as an editor keeps it between queries; its build has its own row).
        if n == 1024 && count == 60_000 {
            let query = terrain.query().expect("query");
            let points: Vec<DVec2> = (0..grid.len()).map(|k| grid.position(k % n, k / n)).collect();
            group.bench_function(format!("query/elevations/{n}/{}k", count / 1000), |b| {
                b.iter(|| black_box(query.elevations(&points)));
            });
            group.bench_function(format!("query/samples/{n}/{}k", count / 1000), |b| {
                b.iter(|| black_box(query.samples(&points)));
            });
            group.bench_function(format!("query/build/{}k", count / 1000), |b| {
                b.iter(|| black_box(terrain.query().expect("query")));
            });
        }
    }
    // A short fit: initialisation and 20 Adam steps on 256² with 2 000 primitives (the full
    // 512² / 1024² fits are single timed runs: `cargo xtask bench` runs `vectorize_timing`).
    if !quick() {
        let dem = fbm_dem(256, 7).expect("dem");
        let options = VectorizeOptions { primitives: 2000, iterations: 20, ..VectorizeOptions::default() };
        group.bench_function("vectorize/256/2k-20-steps", |b| {
            b.iter(|| black_box(vectorize(&dem, &options, |_| ControlFlow::Continue(())).expect("fit")));
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
