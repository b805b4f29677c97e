//! Times Priority-Flood+ε and D8 routing with accumulation on an fBm terrain, stage by stage.
//!
//! `cargo run --release -p relief-hydrology --example flood_timing -- [size]` (default 4096).

use std::time::Instant;

use relief_fixtures::pitted_fbm_dem;
use relief_hydrology::{D8, Outlets, fill};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = std::env::args().nth(1).map_or(Ok(4096), |s| s.parse())?;
    let dem = pitted_fbm_dem(n)?;
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
