//! Times one full analysis of the benchmark's fBm DEM and prints the peak count.
//! Usage: `cargo run --release -p relief-orometry --example analyze_timing -- [size]` (default 3601).

use std::time::Instant;

use glam::DVec2;
use relief_heightfield::noise::Fbm;
use relief_heightfield::{Extent, GridSpec, Heightfield};
use relief_orometry::{AnalysisOptions, analyze};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = std::env::args().nth(1).map(|a| a.parse()).transpose()?.unwrap_or(3601);
    let grid = GridSpec::from_extent(n, n, Extent::new(DVec2::ZERO, DVec2::splat(30.0 * (n - 1) as f64)))?;
    let fbm = Fbm { octaves: 9, frequency: 1.0 / 20_000.0, seed: 3, ..Fbm::default() };
    let dem = Heightfield::from_fn(grid, |p| (1500.0 + 1200.0 * fbm.sample(p)) as f32)?;
    let start = Instant::now();
    let oro = analyze(&dem, &AnalysisOptions::default())?;
    let seconds = start.elapsed().as_secs_f64();
    let prominent = oro.peaks.iter().filter(|p| p.prominence >= 30.0).count();
    println!("analyze {n}²: {seconds:.2} s, {} peaks ({prominent} with prominence ≥ 30 m)", oro.peaks.len());
    Ok(())
}
