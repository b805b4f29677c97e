//! Where a whole feature-curve generation spends its time: rasterization, the elevation solve,
//! the amplitude and roughness solves, and the noise, for the curves of a `relief` scene file.
//!
//! `cargo run --release -p relief-diffusion-multigrid --example generate_timing -- SCENE.json [size] [runs]`

use std::time::Instant;

use glam::DVec2;
use relief_diffusion_multigrid::{
    ConstraintMaps, DiffusionProblem, FeatureCurve, SolveOptions, TerrainOptions, generate,
};
use relief_heightfield::GridSpec;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args.next().ok_or("usage: generate_timing SCENE.json [size] [runs]")?;
    let n: usize = args.next().map_or(Ok(2048), |s| s.parse())?;
    let runs: usize = args.next().map_or(Ok(3), |s| s.parse())?;
    let scene: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path)?)?;
    let generator = &scene["generator"]["diffusion"];
    let curves: Vec<FeatureCurve> = serde_json::from_value(generator["curves"].clone())?;
    let corner = |key: &str| -> Result<DVec2, Box<dyn std::error::Error>> {
        let v: [f64; 2] = serde_json::from_value(scene["domain"][key].clone())?;
        Ok(DVec2::from(v))
    };
    let (lo, hi) = (corner("min")?, corner("max")?);
    let grid = GridSpec::new(n, n, lo, (hi - lo) / (n - 1) as f64)?;
    let options = TerrainOptions {
        noise_wavelength: generator["noise_wavelength"].as_f64().unwrap_or(0.0),
        seed: scene["seed"].as_u64().unwrap_or(0),
        ..TerrainOptions::default()
    };
    let ms = |t: Instant| t.elapsed().as_secs_f64() * 1e3;
    for _ in 0..runs {
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
        for field in [&maps.amplitude, &maps.roughness] {
            if let Some(p) = DiffusionProblem::laplace(n, n, field) {
                p.solve(&SolveOptions::default())?;
            }
        }
        let noise_solves = ms(t);
        let t = Instant::now();
        let terrain = generate(&curves, &grid, &options)?;
        let whole = ms(t);
        let rest = whole - raster - setup - solve - noise_solves;
        println!(
            "{:?}\n{n}² {} curves: whole {whole:.0} ms = rasterize {raster:.0} + setup {setup:.0} + solve {solve:.0} ({} it) + A/R solves {noise_solves:.0} + noise ≈ {rest:.0}",
            report.history,
            curves.len(),
            report.iterations
        );
        std::hint::black_box(terrain);
    }
    Ok(())
}
