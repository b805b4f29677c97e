//! Full analysis (peaks, prominence, isolation, divide tree) of fBm DEMs at SRTM tile sizes:
//! 1201² (3″) and 3601² (1″). Target: 3601² under 3 s on a 2-core machine (issue #9).

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec2;
use relief_heightfield::noise::Fbm;
use relief_heightfield::{Extent, GridSpec, Heightfield};
use relief_orometry::{AnalysisOptions, analyze};

fn dem(n: usize) -> Heightfield {
    let grid =
        GridSpec::from_extent(n, n, Extent::new(DVec2::ZERO, DVec2::splat(30.0 * (n - 1) as f64))).expect("grid");
    let fbm = Fbm { octaves: 9, frequency: 1.0 / 20_000.0, seed: 3, ..Fbm::default() };
    Heightfield::from_fn(grid, |p| (1500.0 + 1200.0 * fbm.sample(p)) as f32).expect("dem")
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("orometry");
    group.sample_size(10);
    for n in [1201usize, 3601] {
        let dem = dem(n);
        group.bench_with_input(BenchmarkId::new("analyze", n), &dem, |b, dem| {
            b.iter(|| black_box(analyze(dem, &AnalysisOptions::default()).expect("analysis")));
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
