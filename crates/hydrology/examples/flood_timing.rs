//! Times Priority-Flood+ε and D8 routing with accumulation on an fBm terrain, stage by stage.
//!
//! `cargo run --release -p relief-hydrology --example flood_timing -- [size]` (default 4096).

use std::time::Instant;

use glam::DVec2;
use relief_heightfield::noise::Fbm;
use relief_heightfield::{GridSpec, Heightfield};
use relief_hydrology::{D8, Outlets, fill};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = std::env::args().nth(1).map_or(Ok(4096), |s| s.parse())?;
    let grid = GridSpec::new(n, n, DVec2::ZERO, DVec2::splat(30.0))?;
    let fbm = Fbm { seed: 7, octaves: 8, frequency: 4.0 / (30.0 * n as f64), ..Fbm::default() };
    let dem = Heightfield::from_fn(grid, |p| (1000.0 * fbm.sample(p)) as f32)?;
    for _ in 0..3 {
        let t = Instant::now();
        let filled = fill(&dem, Outlets::new())?;
        let t_fill = t.elapsed().as_secs_f64();
        let raised = filled.samples().iter().zip(dem.samples()).filter(|(a, b)| a != b).count();
        let t = Instant::now();
        let d8 = D8::new(&filled)?;
        let t_d8 = t.elapsed().as_secs_f64();
        println!(
            "{n}²: fill {:.0} ms ({:.1} % of cells raised), D8 + accumulation {:.0} ms, total {:.0} ms (max area {:.3e} m²)",
            t_fill * 1e3,
            100.0 * raised as f64 / dem.grid().len() as f64,
            t_d8 * 1e3,
            (t_fill + t_d8) * 1e3,
            d8.drainage_area().iter().copied().fold(0.0, f64::max)
        );
    }
    Ok(())
}
