//! The three edits of the paper's Table 4 at its grid sizes 32² … 1024² (Pentium D, seconds):
//! silhouette update (0.007 … 8.13, worst case: the whole grid recomputed), 50 hills updated
//! (0.001 … 0.047) and 1 000 perturbations added (0.001 … 0.036).

use std::hint::black_box;

use criterion::{BatchSize, BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec2;
use relief_heightfield::{Extent, GridSpec};
use relief_island::{Hill, Island, IslandSettings};

fn island(n: usize) -> Island {
    let grid = GridSpec::from_extent(n, n, Extent::new(DVec2::ZERO, DVec2::splat(1000.0))).expect("grid");
    Island::new(grid, IslandSettings::default(), 1).expect("island")
}

/// 50 hills spread over the island, deterministic.
fn hills() -> Vec<Hill> {
    (0..50)
        .map(|k| {
            let a = f64::from(k) * 2.399;
            let r = 300.0 * (f64::from(k) / 50.0).sqrt();
            Hill {
                center: [500.0 + r * a.cos(), 500.0 + r * a.sin()],
                radii: [90.0, 60.0],
                rotation: f64::from(k) * 7.0,
                height: if k % 5 == 0 { -30.0 } else { 40.0 },
            }
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("island");
    for n in [32usize, 64, 128, 256, 512, 1024] {
        let base = island(n);
        // A clockwise supplement around the north-east: the whole height grid is recomputed.
        let stroke =
            [DVec2::new(500.0, 905.0), DVec2::new(800.0, 960.0), DVec2::new(960.0, 800.0), DVec2::new(905.0, 500.0)];
        group.bench_with_input(BenchmarkId::new("silhouette_update", n), &base, |b, base| {
            b.iter_batched(
                || base.clone(),
                |mut i| black_box(i.stroke(&stroke).expect("stroke")),
                BatchSize::LargeInput,
            );
        });
        let mut with_hills = base.clone();
        for h in hills() {
            with_hills.add_hill(h).expect("hill");
        }
        group.bench_with_input(BenchmarkId::new("hills_updated_50", n), &with_hills, |b, island| {
            b.iter_batched(
                || island.clone(),
                |mut i| {
                    for k in 0..50 {
                        let mut h = i.hills()[k];
                        h.center[0] += 15.0;
                        i.set_hill(k, h).expect("move");
                    }
                    black_box(i)
                },
                BatchSize::LargeInput,
            );
        });
        // Coverage 4.225 gives 1 000 perturbations with the default radii (mean area 0.4225 % of
        // the island's).
        group.bench_with_input(BenchmarkId::new("perturbations_1000", n), &base, |b, base| {
            b.iter_batched(
                || base.clone(),
                |mut i| black_box(i.add_filters(4.225).expect("filters")),
                BatchSize::LargeInput,
            );
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
