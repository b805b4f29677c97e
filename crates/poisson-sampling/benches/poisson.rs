//! Poisson-disc sampling at the sizes the foundation issue reports (10k / 100k / 1M points).
//!
//! Reference figures measured on the same 2-core machine class: a plain grid-based Bridson takes
//! ≈0.37 s for 100k and ≈4.0 s for 1M points; the `fast_poisson` crate 1.6 s and 65 s.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec2;
use relief_poisson_sampling::{PoissonDisc, Polygon, PolygonSet, Rect, radius_for_count};

/// A wiggly 2 000-vertex coastline of radius ≈ 1 km.
fn coastline() -> Polygon {
    let ring = (0..2000)
        .map(|k| {
            let t = std::f64::consts::TAU * f64::from(k) / 2000.0;
            let r = 1000.0 * (1.0 + 0.15 * (7.0 * t).sin() + 0.05 * (31.0 * t).cos());
            DVec2::new(r * t.cos(), r * t.sin())
        })
        .collect();
    Polygon::from_exterior(ring).expect("valid coastline")
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("poisson");
    group.sample_size(10);
    let square = Rect::new(DVec2::ZERO, DVec2::splat(1000.0));
    for n in [10_000usize, 100_000, 1_000_000] {
        let r = radius_for_count(square.area(), n).expect("radius");
        let sampler = PoissonDisc::new(r).expect("radius").with_seed(1);
        group.bench_with_input(BenchmarkId::new("rect", n), &n, |b, _| b.iter(|| black_box(sampler.sample(&square))));
    }
    let island = coastline();
    let r = radius_for_count(island.area(), 100_000).expect("radius");
    let sampler = PoissonDisc::new(r).expect("radius").with_seed(1);
    group.bench_with_input(BenchmarkId::new("polygon", 100_000), &island, |b, poly| {
        b.iter(|| black_box(sampler.sample(poly)));
    });
    let omega = PolygonSet::from(island);
    group.bench_with_input(BenchmarkId::new("extended_4r", 100_000), &omega, |b, omega| {
        b.iter(|| black_box(sampler.sample_extended(omega, 4.0 * r)));
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
