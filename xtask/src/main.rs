//! Project automation, run as `cargo xtask <command>` (alias in `.cargo/config.toml`).
//!
//! - `ci`: the same steps as `.ci/run` (it runs that script, the single source of truth).
//! - `bench [--quick] [-p PACKAGE]...`: runs the criterion benches (all, or those of the named
//!   packages; `--quick`: short measurements, largest sizes skipped) and writes
//!   `docs/benchmarks.md`, our medians beside the figures the papers and the issues report.
//!   `--report-only` rewrites the report from the medians already under `target/criterion` (after
//!   a filtered `cargo bench`, say) without running the criterion benches (the paired TIN and
//!   prominence measurements still run). Rows and sections not measured are carried over from the
//!   previous report (see `bench.rs`).
//! - `fuzz [SECONDS] [TARGET]...`: runs the cargo-fuzz targets under `fuzz/` (nightly), each for
//!   SECONDS (default 600); see `fuzz.rs`.
//! - `gdal-contours`: measures `relief contours` beside `gdal_contour` and `relief convert` to
//!   GeoTIFF beside `gdal_translate` (needs `gdal-bin`) and prints the sections `bench` puts in
//!   the report (see `gdal.rs`).
//! - `gallery`: renders the demo and every fixture scene and writes `docs/gallery.md`.
//! - `artefacts`: generates every fixture scene and prints (and writes to `docs/artefacts.md`)
//!   the artefact measures of its summary beside the real Jacksboro DEM's (see `artefacts.rs`).
//!
//! Dependency-light on purpose (`anyhow`, `serde_json`): it builds in seconds and never needs the
//! crates it measures.

mod artefacts;
mod bench;
mod fuzz;
mod gallery;
mod gdal;
mod prominence;
mod references;

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, bail};

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let root = workspace_root();
    match args.first().map(String::as_str) {
        Some("ci") => run(Command::new("bash").arg(root.join(".ci/run")).current_dir(&root)),
        Some("bench") => {
            let packages: Vec<String> =
                args.windows(2).filter(|w| w[0] == "-p" || w[0] == "--package").map(|w| w[1].clone()).collect();
            let flag = |f: &str| args.iter().any(|a| a == f);
            bench::run(&root, flag("--quick"), &packages, flag("--report-only"))
        }
        Some("gallery") => gallery::run(&root),
        Some("artefacts") => artefacts::run(&root),
        Some("gdal-contours") => {
            print!("{}", gdal::contour_runs(&root, false)?);
            print!("{}", gdal::geotiff_runs(&root, false)?);
            Ok(())
        }
        Some("prominence") => {
            print!("{}", prominence::prominence_runs(&root, false)?);
            Ok(())
        }
        Some("fuzz") => {
            let seconds = args.get(1).and_then(|a| a.parse::<u64>().ok());
            let targets: Vec<String> = args.iter().skip(if seconds.is_some() { 2 } else { 1 }).cloned().collect();
            fuzz::run(&root, seconds.unwrap_or(600), &targets)
        }
        Some("help" | "--help" | "-h") | None => {
            println!(
                "usage: cargo xtask <ci | bench [--quick] [-p PACKAGE]... [--report-only] | gdal-contours | prominence | gallery | artefacts | fuzz [SECONDS] [TARGET]...>"
            );
            Ok(())
        }
        Some(other) => bail!("unknown command `{other}`; try `cargo xtask help`"),
    }
}

/// The workspace root: the parent of this crate's manifest directory.
fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().map_or_else(|| PathBuf::from("."), Path::to_path_buf)
}

/// Runs a command, failing with its status if it does not succeed.
fn run(cmd: &mut Command) -> Result<()> {
    let status = cmd.status().with_context(|| format!("could not start {cmd:?}"))?;
    if !status.success() {
        bail!("{cmd:?} failed with {status}");
    }
    Ok(())
}
