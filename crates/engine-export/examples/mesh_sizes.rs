//! Triangles and time of a `.glb` at several error bounds:
//! `cargo run --release -p relief-engine-export --example mesh_sizes -- DEM|fbm:N [ERROR_M…]`
//! (`GLB_OUT=STEM` also writes each mesh to `STEM-ERROR.glb`).
use std::time::Instant;

use relief_engine_export::{MeshOptions, TerrainMesh};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args.next().ok_or("usage: mesh_sizes DEM [ERROR_M…]")?;
    // `fbm:N`: the benches' synthetic N × N terrain.
    let dem = match path.strip_prefix("fbm:") {
        Some(n) => relief_fixtures::fbm_dem(n.parse()?, 7)?,
        None => relief_heightfield_io::read(&path)?,
    };
    let (lo, hi) = dem.min_max().ok_or("no data")?;
    println!("{path}: {} × {}, {lo} … {hi} m", dem.nx(), dem.ny());
    for e in args {
        let options = MeshOptions { max_error_m: Some(e.parse()?), max_triangles: 1 << 24, colours: true };
        let t = Instant::now();
        let mesh = TerrainMesh::from_heightfield(&dem, &options)?;
        let decimate = t.elapsed();
        let glb = mesh.to_glb(true)?;
        if let Ok(out) = std::env::var("GLB_OUT") {
            std::fs::write(format!("{out}-{e}.glb"), &glb)?;
        }
        println!(
            "error {e} m: {} triangles ({:.1} % of the grid's), max error {:.2} m, decimation {:.0} ms, glb {:.0} ms, {} kB",
            mesh.triangles.len(),
            100.0 * mesh.triangles.len() as f64 / (2 * (dem.nx() - 1) * (dem.ny() - 1)) as f64,
            mesh.max_error_m,
            decimate.as_secs_f64() * 1e3,
            t.elapsed().saturating_sub(decimate).as_secs_f64() * 1e3,
            glb.len() / 1024
        );
    }
    Ok(())
}
