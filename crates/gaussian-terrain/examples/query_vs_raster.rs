//! Batched continuous queries against rasterization of the same samples, alternated call by call
//! in one process so that both see the same machine state (criterion's separate benchmarks run
//! minutes apart, and a shared VM drifts by more than the difference between the two).
//!
//! The terrain is the benchmarks' 1024² / 60k one (`relief_fixtures::random_terrain`, 16 supports
//! over each point on average); the query's hierarchy is built once, outside the timing, as an
//! editor keeps it. Each round times one rasterization and one `TerrainQuery::elevations` of the
//! grid's sample positions, in an order that alternates between rounds, and prints the medians
//! and the median of the per-round ratios.
//!
//! Run: `cargo run --release -p relief-gaussian-terrain --example query_vs_raster -- [ROUNDS]`
//! (31 rounds by default).

use std::hint::black_box;
use std::time::{Duration, Instant};

use glam::DVec2;
use relief_fixtures::random_terrain;
use relief_gaussian_terrain::{RasterOptions, rasterize};
use relief_heightfield::{Extent, GridSpec};

fn main() {
    let rounds = match std::env::args().nth(1).map(|a| a.parse::<usize>()) {
        None => 31,
        Some(Ok(r)) if r > 0 => r,
        Some(_) => {
            eprintln!("usage: query_vs_raster [ROUNDS ≥ 1]");
            std::process::exit(2);
        }
    };
    let n = 1024;
    let terrain = random_terrain(60_000, 1000.0, 16.0, 1);
    let grid = GridSpec::from_extent(n, n, Extent::new(DVec2::ZERO, DVec2::splat(1000.0))).expect("grid");
    let query = terrain.query().expect("query");
    let points: Vec<DVec2> = (0..grid.len()).map(|k| grid.position(k % n, k / n)).collect();
    let raster = || {
        let start = Instant::now();
        black_box(rasterize(&terrain, &grid, &RasterOptions::default()).expect("raster"));
        start.elapsed()
    };
    let batch = || {
        let start = Instant::now();
        black_box(query.elevations(&points));
        start.elapsed()
    };
    // One call of each first: page faults and the thread pool's start are not what is measured.
    raster();
    batch();
    let (mut r, mut q, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
    for round in 0..rounds {
        let (a, b) = if round % 2 == 0 {
            let a = raster();
            (a, batch())
        } else {
            let b = batch();
            (raster(), b)
        };
        ratios.push(b.as_secs_f64() / a.as_secs_f64());
        r.push(a);
        q.push(b);
    }
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    let (r, q) = (median(&mut r), median(&mut q));
    let ratio = median(&mut ratios);
    println!(
        "1024² / 60k, {rounds} rounds on {} threads: rasterize {:.1} ms, query elevations {:.1} ms (medians); \
         query / raster per round: median {ratio:.3}",
        rayon::current_num_threads(),
        ms(r),
        ms(q)
    );
}

/// The middle value (the upper one of an even count).
fn median<T: PartialOrd + Copy>(values: &mut [T]) -> T {
    values.sort_by(|a, b| a.partial_cmp(b).expect("no NaN"));
    values[values.len() / 2]
}
