//! Full analysis (peaks, prominence, isolation, divide tree) of fBm DEMs at SRTM tile sizes:
//! 1201² (3″) and 3601² (1″). Target: 3601² under 3 s on a 2-core machine (issue #9).
//!
//! Synthesis (§5–6) at 30 m: divide tree generation alone over the paper's 90 × 90 km, and the
//! whole pipeline at 750² (22.5 km) and 3000² (the paper's 90 × 90 km: 60–190 s in Python + C++;
//! target under 30 s here), targeting the orometry of the 1201² DEM.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec2;
use relief_heightfield::noise::Fbm;
use relief_heightfield::{Extent, GridSpec, Heightfield};
use relief_orometry::{
    AnalysisOptions, ControlMaps, Descriptor, SynthesisOptions, TreeOptions, analyze, generate_tree, synthesize,
};

fn dem(n: usize) -> Heightfield {
    let grid =
        GridSpec::from_extent(n, n, Extent::new(DVec2::ZERO, DVec2::splat(30.0 * (n - 1) as f64))).expect("grid");
    let fbm = Fbm { octaves: 9, frequency: 1.0 / 20_000.0, seed: 3, ..Fbm::default() };
    Heightfield::from_fn(grid, |p| (1500.0 + 1200.0 * fbm.sample(p)) as f32).expect("dem")
}

/// `cargo xtask bench --quick` sets `RELIEF_BENCH_QUICK`: the largest sizes are skipped then.
fn quick() -> bool {
    std::env::var_os("RELIEF_BENCH_QUICK").is_some()
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("orometry");
    group.sample_size(10);
    let largest = if quick() { 1201 } else { 3601 };
    for n in [1201usize, 3601].into_iter().filter(|&n| n <= largest) {
        let dem = dem(n);
        group.bench_with_input(BenchmarkId::new("analyze", n), &dem, |b, dem| {
            b.iter(|| black_box(analyze(dem, &AnalysisOptions::default()).expect("analysis")));
        });
    }
    let options = AnalysisOptions { min_prominence: 30.0, ..AnalysisOptions::default() };
    let target = Descriptor::of(&dem(1201), &options).expect("descriptor").1;
    let extent = Extent::new(DVec2::ZERO, DVec2::splat(90_000.0));
    group.bench_function("generate_tree/90km", |b| {
        b.iter(|| {
            black_box(
                generate_tree(&target, extent, &ControlMaps::default(), &[], &TreeOptions::default()).expect("tree"),
            )
        });
    });
    let largest = if quick() { 750 } else { 3000 };
    for n in [750usize, 3000].into_iter().filter(|&n| n <= largest) {
        let grid =
            GridSpec::from_extent(n, n, Extent::new(DVec2::ZERO, DVec2::splat(30.0 * (n - 1) as f64))).expect("grid");
        group.bench_with_input(BenchmarkId::new("synthesize", n), &grid, |b, grid| {
            b.iter(|| {
                let options = SynthesisOptions::default();
                black_box(
                    synthesize(&target, grid, &ControlMaps::default(), &[], &options, |_, _| {}).expect("synthesis"),
                )
            });
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
