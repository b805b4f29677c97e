//! TIN construction next to spade's own bulk load of the same points (the wrapper must cost
//! < 1.3× spade alone), rasterization and point location.
//!
//! Reference: spade `bulk_load` ≈ 90 ms for 100k and ≈ 0.7 s for 1M points on this machine class.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec2;
use relief_tin::heightfield::{Extent, GridSpec};
use relief_tin::poisson_sampling::{PoissonDisc, Rect, radius_for_count};
use relief_tin::{PointLocator, Tin};
use spade::{DelaunayTriangulation, Point2, Triangulation};

fn points(n: usize) -> Vec<DVec2> {
    let square = Rect::new(DVec2::ZERO, DVec2::splat(1000.0));
    let r = radius_for_count(square.area(), n).expect("radius");
    PoissonDisc::new(r).expect("radius").with_seed(1).sample(&square).expect("points")
}

/// `cargo xtask bench --quick` sets `RELIEF_BENCH_QUICK`: the largest sizes are skipped then.
fn quick() -> bool {
    std::env::var_os("RELIEF_BENCH_QUICK").is_some()
}

fn build(c: &mut Criterion) {
    let mut group = c.benchmark_group("tin");
    group.sample_size(10);
    let largest = if quick() { 100_000 } else { 1_000_000 };
    for n in [10_000usize, 100_000, 1_000_000].into_iter().filter(|&n| n <= largest) {
        let pts = points(n);
        group.bench_with_input(BenchmarkId::new("spade_bulk_load", n), &pts, |b, pts| {
            b.iter(|| {
                let v: Vec<Point2<f64>> = pts.iter().map(|p| Point2::new(p.x, p.y)).collect();
                black_box(DelaunayTriangulation::<Point2<f64>>::bulk_load(v).expect("spade").num_inner_faces())
            });
        });
        group.bench_with_input(BenchmarkId::new("build", n), &pts, |b, pts| {
            b.iter(|| black_box(Tin::new(pts.clone()).expect("tin").num_triangles()));
        });
    }
    let pts = points(100_000);
    let tin = Tin::new(pts.clone()).expect("tin");
    let values: Vec<f64> = pts.iter().map(|p| (p.x * 0.01).sin() * 100.0 + p.y * 0.1).collect();
    let grid = GridSpec::from_extent(2048, 2048, Extent::new(DVec2::ZERO, DVec2::splat(1000.0))).expect("grid");
    group.bench_function("rasterize_100k_to_2048", |b| b.iter(|| black_box(tin.rasterize(&values, &grid))));
    group.bench_function("rasterize_serial_100k_to_2048", |b| {
        b.iter(|| black_box(tin.rasterize_serial(&values, &grid)));
    });
    let locator = PointLocator::new(&tin);
    let queries: Vec<DVec2> =
        (0..100_000u64).map(|k| DVec2::new((k * 7919 % 1000) as f64, (k * 104_729 % 1000) as f64)).collect();
    group.bench_function("locate_100k_queries", |b| {
        b.iter(|| {
            black_box(
                queries.iter().filter(|&&q| matches!(locator.locate(q), relief_tin::Location::Inside { .. })).count(),
            )
        });
    });
    group.finish();
}

criterion_group!(benches, build);
criterion_main!(benches);
