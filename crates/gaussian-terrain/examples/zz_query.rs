use glam::DVec2;
use relief_fixtures::random_terrain;
use relief_gaussian_terrain::{RasterOptions, rasterize};
use relief_heightfield::{Extent, GridSpec};
use std::time::Instant;
fn main() {
    let n = 1024usize;
    let count: usize = std::env::var("COUNT").ok().and_then(|s| s.parse().ok()).unwrap_or(60_000);
    let n: usize = std::env::var("N").ok().and_then(|s| s.parse().ok()).unwrap_or(n);
    let terrain = random_terrain(count, 1000.0, 16.0, 1);
    let grid = GridSpec::from_extent(n, n, Extent::new(DVec2::ZERO, DVec2::splat(1000.0))).unwrap();
    let query = terrain.query().unwrap();
    let mut points: Vec<DVec2> = (0..grid.len()).map(|k| grid.position(k % n, k / n)).collect();
    if std::env::var_os("SCATTER").is_some() {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        points = points.iter().map(|_| DVec2::new(next() * 1000.0, next() * 1000.0)).collect();
    }
    let which = std::env::args().nth(1).unwrap_or_default();
    let reps: usize = std::env::args().nth(2).and_then(|s| s.parse().ok()).unwrap_or(10);
    let (mut r, mut q) = (f64::MAX, f64::MAX);
    let mut hash = 0u64;
    let mut rhash = 0u64;
    for _ in 0..reps {
        if which != "q" {
            let t = Instant::now();
            let h = rasterize(&terrain, &grid, &RasterOptions::default()).unwrap();
            r = r.min(t.elapsed().as_secs_f64());
            rhash = h.samples().iter().fold(0xcbf2_9ce4_8422_2325u64, |a, v| {
                (a ^ u64::from(v.to_bits())).wrapping_mul(0x100_0000_01b3).rotate_left(17)
            });
        }
        if which != "r" {
            let t = Instant::now();
            let e: Vec<f64> = if std::env::var_os("SINGLE").is_some() {
                points.iter().step_by(10).map(|&p| query.elevation(p)).collect()
            } else if std::env::var_os("SAMPLES").is_some() {
                query.samples(&points).iter().map(|s| s.elevation + s.gradient.x).collect()
            } else {
                query.elevations(&points)
            };
            q = q.min(t.elapsed().as_secs_f64());
            hash = e
                .iter()
                .fold(0xcbf2_9ce4_8422_2325u64, |h, v| (h ^ v.to_bits()).wrapping_mul(0x100_0000_01b3).rotate_left(17));
        }
    }
    println!("raster {:.1} ms  query {:.1} ms  ratio {:.2}  hash {hash:x} rhash {rhash:x}", r * 1e3, q * 1e3, q / r);
}
