//! Priority-flood, D8 routing with accumulation, and one stream-power step at 1024², 2048² and
//! 4096² on an fBm terrain full of pits. Target (issue #6): 4096² flood + accumulation under 3 s.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec2;
use relief_heightfield::noise::Fbm;
use relief_heightfield::{GridSpec, Heightfield};
use relief_hydrology::{D8, Outlets, StreamPower, fill};

fn terrain(n: usize) -> Heightfield {
    let grid = GridSpec::new(n, n, DVec2::ZERO, DVec2::splat(30.0)).expect("grid");
    let fbm = Fbm { seed: 7, octaves: 8, frequency: 4.0 / (30.0 * n as f64), ..Fbm::default() };
    Heightfield::from_fn(grid, |p| (1000.0 * fbm.sample(p)) as f32).expect("terrain")
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("hydrology");
    group.sample_size(10);
    for n in [1024usize, 2048, 4096] {
        let dem = terrain(n);
        group.bench_with_input(BenchmarkId::new("priority_flood", n), &dem, |b, dem| {
            b.iter(|| black_box(fill(dem, Outlets::new()).expect("fill")));
        });
        let filled = fill(&dem, Outlets::new()).expect("fill");
        group.bench_with_input(BenchmarkId::new("d8_accumulation", n), &filled, |b, filled| {
            b.iter(|| black_box(D8::new(filled).expect("d8").drainage_area()[0]));
        });
        group.bench_with_input(BenchmarkId::new("flood_and_accumulation", n), &dem, |b, dem| {
            b.iter(|| black_box(D8::new(&fill(dem, Outlets::new()).expect("fill")).expect("d8").drainage_area()[0]));
        });
        let sp = StreamPower::default();
        group.bench_with_input(BenchmarkId::new("stream_power_step", n), &dem, |b, dem| {
            b.iter_batched(
                || dem.clone(),
                |mut h| {
                    sp.step(&mut h).expect("step");
                    black_box(h)
                },
                criterion::BatchSize::LargeInput,
            );
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
