//! What `Tin::new` costs over spade's bulk load alone, measured in pairs: each round times spade
//! and then `Tin::new` on the same points, and the median of the per-round ratios is reported.
//! Pairing cancels the slow drifts of a shared machine that separate criterion runs pick up.
//!
//! `cargo run --release -p relief-tin --example wrapper_overhead -- [points]` (default 100 000).

use std::hint::black_box;
use std::time::Instant;

use glam::DVec2;
use relief_tin::Tin;
use relief_tin::poisson_sampling::{PoissonDisc, Rect, radius_for_count};
use spade::{DelaunayTriangulation, Point2, Triangulation};

fn millis(f: impl FnOnce()) -> f64 {
    let start = Instant::now();
    f();
    start.elapsed().as_secs_f64() * 1e3
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = std::env::args().nth(1).map_or(Ok(100_000), |s| s.parse())?;
    let rounds = if n > 500_000 { 8 } else { 40 };
    let square = Rect::new(DVec2::ZERO, DVec2::splat(1000.0));
    let points = PoissonDisc::new(radius_for_count(square.area(), n)?)?.with_seed(1).sample(&square)?;
    let (mut spade, mut ours, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..rounds {
        let a = millis(|| {
            let v: Vec<Point2<f64>> = points.iter().map(|p| Point2::new(p.x, p.y)).collect();
            black_box(DelaunayTriangulation::<Point2<f64>>::bulk_load(v).map(|t| t.num_inner_faces()).ok());
        });
        let b = millis(|| {
            black_box(Tin::new(points.clone()).map(|t| t.num_triangles()).ok());
        });
        spade.push(a);
        ours.push(b);
        ratios.push(b / a);
    }
    println!(
        "{} points, {rounds} rounds: spade bulk_load {:.1} ms, Tin::new {:.1} ms (medians); median paired ratio {:.3}",
        points.len(),
        median(spade),
        median(ours),
        median(ratios)
    );
    Ok(())
}
