//! Residual against time for both solvers on a ridge scene.
//!
//! `cargo run --release -p relief-diffusion-multigrid --example convergence -- [size] [gradient]`;
//! `MG_ONLY=1` skips the Jacobi pyramid, `ACCURACY=1` also prints how far the solve stops from
//! the converged solution.

use std::time::Instant;

use glam::DVec2;
use relief_diffusion_multigrid::{ConstraintMaps, DiffusionProblem, SolveOptions, Solver};

#[path = "../benches/common/scene.rs"]
mod scene;
use relief_heightfield::GridSpec;
use scene::scene_with;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = std::env::args().nth(1).map_or(Ok(513), |s| s.parse())?;
    let slopes = std::env::args().nth(2).is_none_or(|s| s != "0");
    let cell = 4000.0 / (n - 1) as f64;
    let grid = GridSpec::new(n, n, DVec2::ZERO, DVec2::splat(cell))?;
    let curves = scene_with(if slopes { 600.0 } else { 0.0 });
    let t = Instant::now();
    let maps = ConstraintMaps::rasterize(&curves, &grid)?;
    let problem = DiffusionProblem::elevation(&maps)?;
    println!(
        "{n}²: rasterize + setup {:.0} ms, {} levels, kinds {:?}",
        t.elapsed().as_secs_f64() * 1e3,
        problem.depth(),
        maps.counts()
    );
    let solvers = if std::env::var("MG_ONLY").is_ok() {
        vec![Solver::Multigrid]
    } else {
        vec![Solver::Multigrid, Solver::JacobiPyramid]
    };
    for solver in solvers {
        let opts = SolveOptions {
            solver,
            max_iterations: Some(if solver == Solver::Multigrid { 60 } else { 2000 }),
            ..SolveOptions::default()
        };
        // ACCURACY=1: how far the solve to the tolerance stops from the converged solution.
        if std::env::var_os("ACCURACY").is_some() {
            let (x, _) = problem.solve(&SolveOptions { max_iterations: None, ..opts })?;
            let tight = SolveOptions { tolerance: 1e-7, max_iterations: Some(60), ..SolveOptions::default() };
            let (exact, _) = problem.solve(&tight)?;
            let e: Vec<f64> = x.iter().zip(&exact).map(|(a, b)| f64::from((a - b).abs())).collect();
            println!(
                "  error {:.2} m mean, {:.2} m worst",
                e.iter().sum::<f64>() / e.len() as f64,
                e.iter().copied().fold(0.0, f64::max)
            );
        }
        let t = Instant::now();
        let (_, report) = problem.solve(&opts)?;
        let h: Vec<String> = report.history.iter().take(12).map(|r| format!("{r:.1e}")).collect();
        println!(
            "{solver:?}: {:.0} ms, {} iterations, residual {:.2e} (converged {}), history {}",
            t.elapsed().as_secs_f64() * 1e3,
            report.iterations,
            report.relative_residual,
            report.converged,
            h.join(" ")
        );
    }
    Ok(())
}
