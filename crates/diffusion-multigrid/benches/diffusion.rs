//! Feature-curve terrains at 512², 1024², 2048² and 4096², set against Hnaidi et al.'s Table 2
//! (GPU, 8800 GTS, whole generations: 0.168–0.216 s at 512², 0.253–0.339 s at 1024²,
//! 0.611–0.811 s at 2048²):
//!
//! - `generate`: a whole generation of the 48-curve `volcanic-island-48` fixture scene (rasterize,
//!   diffuse the elevation to the default tolerance, the noise amplitude and roughness, add the
//!   detail), the row to compare with Table 2's Volcanic Island (48 curves, Table 1);
//! - `generate_paper_budget`: the same generation with the paper's own solver at its fixed budget
//!   for all three solves (the Jacobi pyramid's 5·(l − i) sweeps per level; the hole fills keep
//!   their multigrid), like for like with Table 2's timing of that solver;
//! - `rasterize`, `multigrid` (the elevation solve alone, to a 1e-4 relative residual) and
//!   `jacobi_pyramid` (the paper's solver with its own fixed budget of 5·(l − i) sweeps per
//!   level, no tolerance) on a 4-curve mountain (three ridges sharing a peak, a riverbed): the
//!   parts, not comparable with Table 2 on their own.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec2;
use relief_diffusion_multigrid::{ConstraintMaps, DiffusionProblem, SolveOptions, Solver, TerrainOptions, generate};

#[path = "common/fixture.rs"]
mod fixture;
#[path = "common/scene.rs"]
mod scene;
use relief_heightfield::GridSpec;
use scene::scene_with;

/// `cargo xtask bench --quick` sets `RELIEF_BENCH_QUICK`: the largest sizes are skipped then.
fn quick() -> bool {
    std::env::var_os("RELIEF_BENCH_QUICK").is_some()
}

/// The paper's solver at its own fixed budget of sweeps, whatever residual that leaves.
fn paper_budget() -> SolveOptions {
    SolveOptions { solver: Solver::JacobiPyramid, max_iterations: Some(0), ..SolveOptions::default() }
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("diffusion");
    group.sample_size(10);
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/scenes/volcanic-island-48.json");
    let (island, [lo, hi], options) = fixture::load(std::path::Path::new(path)).expect("the fixture scene");
    assert_eq!(island.len(), 48);
    let curves = scene_with(600.0);
    let largest = if quick() { 1024 } else { 4096 };
    for n in [512usize, 1024, 2048, 4096].into_iter().filter(|&n| n <= largest) {
        if n <= 2048 {
            let grid = GridSpec::new(n, n, lo, (hi - lo) / (n - 1) as f64).expect("grid");
            group.bench_with_input(BenchmarkId::new("generate", n), &grid, |b, grid| {
                b.iter(|| black_box(generate(&island, grid, &options).expect("terrain")));
            });
            let paper = TerrainOptions { solve: paper_budget(), ..options };
            group.bench_with_input(BenchmarkId::new("generate_paper_budget", n), &grid, |b, grid| {
                b.iter(|| black_box(generate(&island, grid, &paper).expect("terrain")));
            });
        }
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
        if n <= 2048 {
            let paper = paper_budget();
            group.bench_with_input(BenchmarkId::new("jacobi_pyramid", n), &problem, |b, p| {
                b.iter(|| black_box(p.solve(&paper).expect("solve").0));
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
