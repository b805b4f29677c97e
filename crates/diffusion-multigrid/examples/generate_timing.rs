//! Where a whole feature-curve generation spends its time (rasterization, the elevation solve's
//! set-up and solve, the amplitude and roughness solves at full resolution, which `generate` runs at
//! half resolution from 256 samples a side), the whole `generate` over several runs,
//! and how far the default solve stops from the converged solution, for the curves of a `relief`
//! scene file.
//!
//! `cargo run --release -p relief-diffusion-multigrid --example generate_timing -- SCENE.json [size] [runs]`
//!
//! With `WHOLE_ONLY=1` it runs the whole `generate` alone (for a profiler).

use std::time::Instant;

use relief_diffusion_multigrid::{
    ConstraintMaps, DiffusionProblem, FeatureCurve, SolveOptions, TerrainOptions, generate,
};
use relief_heightfield::GridSpec;

#[path = "../benches/common/fixture.rs"]
mod fixture;

type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let path = args.next().ok_or("usage: generate_timing SCENE.json [size] [runs]")?;
    let n: usize = args.next().map_or(Ok(2048), |s| s.parse())?;
    let runs: usize = args.next().map_or(Ok(5), |s| s.parse())?;
    let (curves, [lo, hi], options) = fixture::load(std::path::Path::new(&path))?;
    let grid = GridSpec::new(n, n, lo, (hi - lo) / (n - 1) as f64)?;
    let ms = |t: Instant| t.elapsed().as_secs_f64() * 1e3;
    let whole_only = std::env::var_os("WHOLE_ONLY").is_some();
    if whole_only {
        return whole(&curves, &grid, &options, runs);
    }

    let t = Instant::now();
    let maps = ConstraintMaps::rasterize(&curves, &grid)?;
    let raster = ms(t);
    let t = Instant::now();
    let problem = DiffusionProblem::elevation(&maps)?;
    let setup = ms(t);
    let t = Instant::now();
    let (_, report) = problem.solve(&SolveOptions::default())?;
    let solve = ms(t);
    let t = Instant::now();
    if let Some(amplitude) = DiffusionProblem::laplace(n, n, &maps.amplitude) {
        amplitude.solve(&SolveOptions::default())?;
        if let Some(roughness) = amplitude.laplace_like(&maps.roughness) {
            roughness.solve(&SolveOptions::default())?;
        }
    }
    let noise = ms(t);
    println!(
        "{n}², {} curves: rasterize {raster:.0} ms, set-up {setup:.0} ms, solve {solve:.0} ms ({} iterations, {:.1e}; relative residual after the start and each: {}), amplitude and roughness at full resolution {noise:.0} ms",
        curves.len(),
        report.iterations,
        report.relative_residual,
        report.history.iter().map(|h| format!("{h:.1e}")).collect::<Vec<_>>().join(", ")
    );

    whole(&curves, &grid, &options, runs)?;

    let tight = SolveOptions { tolerance: 1e-7, max_iterations: Some(60), ..SolveOptions::default() };
    let (converged, _) = problem.solve(&tight)?;
    for tolerance in [1e-4, 1e-5] {
        let (x, r) = problem.solve(&SolveOptions { tolerance, ..SolveOptions::default() })?;
        let error: Vec<f64> = x.iter().zip(&converged).map(|(a, b)| f64::from((a - b).abs())).collect();
        let mean = error.iter().sum::<f64>() / error.len() as f64;
        let worst = error.iter().copied().fold(0.0, f64::max);
        println!(
            "tolerance {tolerance:.0e}: {} iterations, {mean:.2} m mean and {worst:.2} m worst from the converged solution",
            r.iterations
        );
    }
    Ok(())
}

/// Times `runs` whole generations.
fn whole(curves: &[FeatureCurve], grid: &GridSpec, options: &TerrainOptions, runs: usize) -> Result<()> {
    let mut times: Vec<f64> = (0..runs.max(1))
        .map(|_| {
            let t = Instant::now();
            std::hint::black_box(generate(curves, grid, options)).map(|_| t.elapsed().as_secs_f64() * 1e3)
        })
        .collect::<std::result::Result<_, _>>()?;
    times.sort_by(f64::total_cmp);
    println!("whole generate: best {:.0} ms, median {:.0} ms of {}", times[0], times[times.len() / 2], times.len());
    Ok(())
}
