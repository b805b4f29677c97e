//! Times one full synthesis: analyse a reference fBm DEM (1201², 30 m), generate a divide tree and
//! a terrain of `size`² samples at 30 m (default 3000: the paper's 90 × 90 km), then analyse the
//! result and print the descriptor distances.
//! Usage: `cargo run --release -p relief-orometry --example synthesize_timing -- [size]`.

use std::time::Instant;

use glam::DVec2;
use relief_heightfield::noise::Fbm;
use relief_heightfield::{Extent, GridSpec, Heightfield};
use relief_orometry::{AnalysisOptions, ControlMaps, Descriptor, SynthesisOptions, synthesize};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = std::env::args().nth(1).map(|a| a.parse()).transpose()?.unwrap_or(3000);
    let reference_grid = GridSpec::from_extent(1201, 1201, Extent::new(DVec2::ZERO, DVec2::splat(36_000.0)))?;
    let fbm = Fbm { octaves: 9, frequency: 1.0 / 20_000.0, seed: 3, ..Fbm::default() };
    let reference = Heightfield::from_fn(reference_grid, |p| (1500.0 + 1200.0 * fbm.sample(p)) as f32)?;
    let options = AnalysisOptions { min_prominence: 30.0, ..AnalysisOptions::default() };
    let (_, target) = Descriptor::of(&reference, &options)?;
    println!("reference: {} peaks, {:.3}/km²", target.peaks, target.density_per_km2);

    let grid = GridSpec::from_extent(n, n, Extent::new(DVec2::ZERO, DVec2::splat(30.0 * (n - 1) as f64)))?;
    let start = Instant::now();
    let mut last = start;
    let (tree, terrain) =
        synthesize(&target, &grid, &ControlMaps::default(), &[], &SynthesisOptions::default(), |stage, f| {
            if f >= 1.0 {
                println!("  {stage}: {:.2} s", last.elapsed().as_secs_f64());
                last = Instant::now();
            }
        })?;
    let seconds = start.elapsed().as_secs_f64();
    println!("synthesize {n}²: {seconds:.2} s, {} peaks, {} saddles", tree.peaks.len(), tree.saddles.len());
    let (_, got) = Descriptor::with_radius(&terrain, &options, Some(target.domain.radius_m))?;
    let d = got.distance(&target)?;
    println!("analysed: {} peaks; mean EMD {:.4}", got.peaks, d.mean_emd);
    for (name, emd, max) in &d.features {
        println!("  {name:<22} EMD {emd:.4}  max bin error {max:.4}");
    }
    Ok(())
}
