//! Vectorizes the synthetic `fbm_dem` (relief-fixtures) once and prints the time and the ℓ₁
//! reached, the way the paper reports its vectorization (§6: 1024², about 10 000 primitives,
//! ≈ 60 s on an RTX 3090).
//! `cargo xtask bench` runs it; one run of a minute-long fit does not suit criterion's sampling.
//!
//! Usage: `cargo run --release -p relief-gaussian-terrain --example vectorize_timing -- [size]
//! [primitives] [iterations] [resolution]` (defaults 512 10000 200 512; the paper's protocol is
//! `1024 10000 200 1024`).

use std::ops::ControlFlow;

use relief_fixtures::fbm_dem;
use relief_gaussian_terrain::{VectorizeOptions, vectorize};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<usize> = std::env::args().skip(1).map(|a| a.parse()).collect::<Result<_, _>>()?;
    let size = args.first().copied().unwrap_or(512);
    let primitives = args.get(1).copied().unwrap_or(10_000);
    let iterations = args.get(2).copied().unwrap_or(200);
    let resolution = args.get(3).copied().unwrap_or(512);
    let verbose = std::env::var_os("VERBOSE").is_some();
    let dem = fbm_dem(size, 7)?;
    let options = VectorizeOptions { primitives, iterations, resolution, ..VectorizeOptions::default() };
    let fit = vectorize(&dem, &options, |p| {
        if verbose && p.iteration % 25 == 0 {
            eprintln!(
                "step {:4} primitives {:6} ℓ {:.5} ℓ1 {:.5} grad {:.5} ssim {:.5} {:.1} s",
                p.iteration,
                p.primitives,
                p.loss.total,
                p.loss.l1,
                p.loss.gradient,
                p.loss.ssim,
                p.elapsed.as_secs_f64()
            );
        }
        ControlFlow::Continue(())
    })?;
    let r = &fit.report;
    println!(
        "vectorize {size}² (working grid {}²) with {primitives} primitives, {} steps: {:.1} s, {} primitives kept, ℓ1 {:.2e} (of the relief's half-range, [-1, 1]; twice Table 3's unit), loss {:.2e}",
        resolution.min(size),
        r.iterations,
        r.seconds,
        r.primitives,
        r.l1_normalized,
        r.loss.total
    );
    Ok(())
}
