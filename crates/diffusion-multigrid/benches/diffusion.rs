//! Time to a 1e-4 relative residual for the elevation solve of a mountain scene (three ridges
//! sharing a peak, a riverbed) at 512², 1024², 2048² and 4096²: our multigrid against the paper's
//! Jacobi pyramid (the pyramid only up to 2048², where it already needs ~1 650 finest sweeps).
//! Paper (GPU, 8800 GTS, Table 2): 0.168–0.216 s at 512², 0.253–0.339 s at 1024², 0.611–0.811 s at 2048².
//! Rasterization is benched apart.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec2;
use relief_diffusion_multigrid::{ConstraintMaps, DiffusionProblem, SolveOptions, Solver};

#[path = "common/scene.rs"]
mod scene;
use relief_heightfield::GridSpec;
use scene::scene_with;

/// `cargo xtask bench --quick` sets `RELIEF_BENCH_QUICK`: the largest sizes are skipped then.
fn quick() -> bool {
    std::env::var_os("RELIEF_BENCH_QUICK").is_some()
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("diffusion");
    group.sample_size(10);
    let curves = scene_with(600.0);
    // Quick runs leave out the Jacobi baseline (seconds per solve even at 512²).
    let (largest, largest_jacobi) = if quick() { (1024, 0) } else { (4096, 2048) };
    for n in [512usize, 1024, 2048, 4096].into_iter().filter(|&n| n <= largest) {
        let grid = GridSpec::new(n, n, DVec2::ZERO, DVec2::splat(4000.0 / (n - 1) as f64)).expect("grid");
        group.bench_with_input(BenchmarkId::new("rasterize", n), &grid, |b, grid| {
            b.iter(|| black_box(ConstraintMaps::rasterize(&curves, grid).expect("maps")));
        });
        let maps = ConstraintMaps::rasterize(&curves, &grid).expect("maps");
        let problem = DiffusionProblem::elevation(&maps).expect("problem");
        group.bench_with_input(BenchmarkId::new("multigrid", n), &problem, |b, p| {
            b.iter(|| {
                let (x, report) = p.solve(&SolveOptions::default()).expect("solve");
                assert!(report.converged);
                black_box(x)
            });
        });
        if n <= largest_jacobi {
            let jacobi =
                SolveOptions { solver: Solver::JacobiPyramid, max_iterations: Some(5000), ..SolveOptions::default() };
            group.bench_with_input(BenchmarkId::new("jacobi_pyramid", n), &problem, |b, p| {
                b.iter(|| black_box(p.solve(&jacobi).expect("solve").0));
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
