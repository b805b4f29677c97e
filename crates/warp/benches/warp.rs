//! Warping 100k contour vertices by a 50-segment stroke, and a 2048² raster by backward mapping.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::DVec2;
use relief_warp::{PathOptions, PathWarp, warp_points, warp_polylines, warp_raster};

fn bench(c: &mut Criterion) {
    // A 1500 m wavy stroke cut into exactly 50 segments of 30 m, discs of 100 m.
    let stroke: Vec<DVec2> =
        (0..=30).map(|k| DVec2::new(50.0 * f64::from(k) - 750.0, 120.0 * (f64::from(k) * 0.4).sin())).collect();
    let length: f64 = stroke.windows(2).map(|w| w[0].distance(w[1])).sum();
    let warp = PathWarp::new(&stroke, &PathOptions { segment: Some(length / 50.0), ..PathOptions::new(100.0, 1.0) })
        .expect("warp");
    assert_eq!(warp.discs(), 50);
    // 100 concentric contours of 1 000 vertices each around the stroke: 100 000 vertices.
    let contours: Vec<(Vec<DVec2>, bool)> = (1..=100)
        .map(|k| {
            let r = 10.0 * f64::from(k);
            (
                (0..1000)
                    .map(|i| {
                        DVec2::new(r * 0.9, r * 0.4)
                            .mul_add(DVec2::from_angle(f64::from(i) * std::f64::consts::TAU / 1000.0), DVec2::ZERO)
                    })
                    .collect(),
                true,
            )
        })
        .collect();
    let points: Vec<DVec2> = contours.iter().flat_map(|(p, _)| p.iter().copied()).collect();
    let mut group = c.benchmark_group("warp");
    group.sample_size(10);
    group.bench_function("points_100k_50_segments", |b| {
        b.iter(|| {
            let mut p = points.clone();
            warp_points(&warp, &mut p);
            black_box(p)
        });
    });
    group.bench_function("polylines_100k_50_segments", |b| b.iter(|| black_box(warp_polylines(&warp, &contours, 0.1))));
    let field = |p: DVec2| ((p.x * 0.01).sin() * 100.0 + p.y * 0.05) as f32;
    group.bench_function("raster_2048", |b| {
        b.iter(|| {
            black_box(warp_raster(&warp, 2048, 2048, |i, j| DVec2::new(i as f64 - 1024.0, j as f64 - 1024.0), field))
        });
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
