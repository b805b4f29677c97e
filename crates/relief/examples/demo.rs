//! The foundation demo: an island outline → blue-noise nodes over Ω ⊕ B(4r) → Delaunay TIN →
//! heights from the distance to the coast plus fBm → a 1024² heightfield written as EXR and 16-bit
//! PNG, with a shaded-relief preview. Outputs go to `./relief-demo/` (or the first argument).
//!
//! Run with `cargo run --release -p relief --example demo`.

use std::error::Error;
use std::path::PathBuf;
use std::time::Instant;

use glam::DVec2;
use relief::heightfield::noise::Fbm;
use relief::heightfield::{Extent, GridSpec};
use relief::io::{ShadeOptions, write, write_preview_png};
use relief::poisson_sampling::{PoissonDisc, Polygon, PolygonSet, radius_for_count};
use relief::tin::Tin;

fn main() -> Result<(), Box<dyn Error>> {
    let out = std::env::args().nth(1).map_or_else(|| PathBuf::from("relief-demo"), PathBuf::from);
    std::fs::create_dir_all(&out)?;
    let start = Instant::now();

    // A 10 km island with a wavy coast (coordinates in metres).
    let coast: Vec<DVec2> = (0..400)
        .map(|k| {
            let t = std::f64::consts::TAU * f64::from(k) / 400.0;
            let r = 4000.0 * (1.0 + 0.18 * (3.0 * t).sin() + 0.07 * (11.0 * t + 1.0).cos());
            DVec2::new(r * t.cos(), r * t.sin())
        })
        .collect();
    let island = PolygonSet::from(Polygon::from_exterior(coast)?);
    let r = radius_for_count(island.area(), 200_000)?;
    let samples = PoissonDisc::new(r)?.with_seed(7).sample_extended(&island, 4.0 * r)?;
    let tin = Tin::new(samples.points.clone())?;

    // Height: rises with the distance to the coast, roughened by fBm; the sea stays below 0.
    let fbm = Fbm { octaves: 6, frequency: 1.0 / 3000.0, seed: 7, ..Fbm::default() };
    let poly = &island.polygons()[0];
    let heights: Vec<f64> = tin
        .points()
        .iter()
        .zip(&samples.inside)
        .map(|(&p, &inside)| {
            let d = poly.boundary_distance(p);
            if inside { 900.0 * (d / 3000.0).min(1.0).powf(0.8) * (1.0 + 0.35 * fbm.sample(p)) } else { -20.0 - d }
        })
        .collect();

    let extent = Extent::new(DVec2::splat(-5500.0), DVec2::splat(5500.0));
    let dem = tin.rasterize(&heights, &GridSpec::from_extent(1024, 1024, extent)?)?;
    let files = [out.join("heightmap.exr"), out.join("heightmap.png")];
    for f in &files {
        write(f, &dem)?;
    }
    let preview = out.join("preview.png");
    write_preview_png(&preview, &dem, &ShadeOptions::default())?;

    let (lo, hi) = dem.min_max().unwrap_or((0.0, 0.0));
    println!(
        "relief demo: {} nodes, {} triangles, elevations {lo:.0}..{hi:.0} m",
        tin.num_points(),
        tin.num_triangles()
    );
    for f in files.iter().chain([&preview]) {
        println!("  wrote {}", f.display());
    }
    println!("done in {:.2} s", start.elapsed().as_secs_f64());
    Ok(())
}
