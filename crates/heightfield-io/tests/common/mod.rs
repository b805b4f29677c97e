//! Helpers shared by the integration tests.
#![allow(dead_code, unreachable_pub, reason = "each test binary uses a different subset")]

use std::path::{Path, PathBuf};

use glam::DVec2;
use relief_heightfield::{GridSpec, Heightfield};

/// `fixtures/dem/<name>` at the workspace root.
pub fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/dem").join(name)
}

/// A small deterministic field with a hole, on a metric grid.
pub fn small_field(nx: usize, ny: usize) -> Heightfield {
    let grid = GridSpec::new(nx, ny, DVec2::new(1000.5, -250.25), DVec2::new(2.5, 5.0)).unwrap();
    let mut hf = Heightfield::from_fn_indexed(grid, |i, j| (i * 7 + j * 13) as f32 * 0.75 - 10.0).unwrap();
    hf.set(nx / 2, ny / 2, f32::NAN).unwrap();
    hf
}

/// Asserts two fields share a grid and agree within `tol` (no-data where the other has it).
#[track_caller]
pub fn assert_close(back: &Heightfield, orig: &Heightfield, tol: f32) {
    assert_eq!(back.grid(), orig.grid(), "grids differ");
    for (k, (a, b)) in back.samples().iter().zip(orig.samples()).enumerate() {
        if b.is_nan() {
            assert!(a.is_nan(), "sample {k}: expected no-data, got {a}");
        } else {
            assert!((a - b).abs() <= tol, "sample {k}: {a} vs {b}, tolerance {tol}");
        }
    }
}

/// One quantisation step of a `bits`-bit encoding of `hf`, plus f32 rounding of the result.
pub fn quantisation_step(hf: &Heightfield, bits: u32) -> f32 {
    let (lo, hi) = hf.min_max().unwrap_or((0.0, 0.0));
    let max_code = ((1u64 << bits) - 1) as f64;
    let step = (f64::from(hi) - f64::from(lo)) / max_code;
    let ulp = f32::EPSILON * lo.abs().max(hi.abs());
    (step as f32) + ulp
}

/// Names of the entries of a directory, sorted.
pub fn dir_entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}
