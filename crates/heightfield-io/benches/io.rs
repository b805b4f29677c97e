//! Write and read a 4096² synthetic terrain in every format (`.hgt` at its 3601² tile size).
//!
//! Benchmark ids are `io/<write|read>/<format>/<side>`. Writes are atomic (temporary file, fsync,
//! rename), so they include one fsync of the whole file; reads include detection and decoding.

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::DVec2;
use relief_heightfield::{GridSpec, Heightfield};
use relief_heightfield_io::{Format, WriteOptions, read, write_with};

/// Smooth ridges and valleys plus a little deterministic hash noise, in metres.
fn terrain(grid: GridSpec, whole_metres: bool) -> Heightfield {
    Heightfield::from_fn_indexed(grid, |i, j| {
        let (x, y) = (i as f64, j as f64);
        let smooth = 800.0 + 300.0 * (x / 310.0).sin() * (y / 470.0).cos() + 120.0 * ((x + 2.0 * y) / 90.0).sin();
        let mut h = (i as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ (j as u64).wrapping_mul(0xc2b2_ae3d_27d4_eb4f);
        h ^= h >> 29;
        let noise = (h % 1000) as f64 / 250.0 - 2.0;
        let v = smooth + noise;
        (if whole_metres { v.round() } else { v }) as f32
    })
    .unwrap()
}

fn bench_format(c: &mut Criterion, dir: &Path, hf: &Heightfield, name: &str, file: &str, format: Format) {
    let path = dir.join(file);
    let options = WriteOptions::default().with_format(format);
    let side = hf.nx();
    c.bench_function(&format!("io/write/{name}/{side}"), |b| b.iter(|| write_with(&path, hf, &options).unwrap()));
    // Written once more here so that the read bench also runs when a filter skips the write bench.
    write_with(&path, hf, &options).unwrap();
    c.bench_function(&format!("io/read/{name}/{side}"), |b| b.iter(|| black_box(read(&path).unwrap())));
}

/// `cargo xtask bench --quick` sets `RELIEF_BENCH_QUICK`: ASCII grids (seconds per 4096² iteration) are skipped then.
fn quick() -> bool {
    std::env::var_os("RELIEF_BENCH_QUICK").is_some()
}

fn io(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    let grid = GridSpec::new(4096, 4096, DVec2::new(500_000.0, 4_100_000.0), DVec2::splat(10.0)).unwrap();
    let hf = terrain(grid, false);
    let formats = [
        ("png16", "t16.png", Format::Png16, cfg!(feature = "png")),
        ("png8", "t8.png", Format::Png8, cfg!(feature = "png")),
        ("exr", "t.exr", Format::Exr, cfg!(feature = "exr")),
        ("r16", "t.r16", Format::R16, true),
        ("r32", "t.r32", Format::R32, true),
        ("asc", "t.asc", Format::Asc, !quick()),
        ("geotiff", "t.tif", Format::GeoTiff, cfg!(feature = "geotiff")),
    ];
    for (name, file, format, enabled) in formats {
        if enabled {
            bench_format(c, dir.path(), &hf, name, file, format);
        }
    }
    let tile = GridSpec::geographic(3601, 3601, DVec2::new(-85.0, 36.0), DVec2::splat(1.0 / 3600.0)).unwrap();
    bench_format(c, dir.path(), &terrain(tile, true), "hgt", "N36W085.hgt", Format::Hgt);
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = io
}
criterion_main!(benches);
