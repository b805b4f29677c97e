//! `relief prominence` as a whole process on a 6.85 M-cell DEM (wall time and peak memory under
//! `/usr/bin/time`, one and two threads), beside the akirmse/mountains figure the orometry issue
//! gives for this machine class (its sources cannot be fetched here). Without `/usr/bin/time` the
//! section keeps the last run's lines.

use std::fmt::Write as _;
use std::fs;
use std::path::Path;
use std::process::Command;

use anyhow::{Context, Result};

use crate::gdal::{jacksboro_resampled, measure};

/// The report section: measured now when `/usr/bin/time` is there, else the last run's lines
/// (kept in `target/prominence.md`).
pub(crate) fn prominence_runs(root: &Path, quick: bool) -> Result<String> {
    let cache = root.join("target/prominence.md");
    let mut md = String::from(
        "## prominence, beside akirmse/mountains\n\nWhole processes (`/usr/bin/time`, peak resident memory in MiB), \
         best of 3: `relief --threads N prominence DEM --min-prominence 30 --peaks peaks.csv`. akirmse/mountains \
         cannot be built here (no network for its sources), so its row is the figure the orometry issue gives for \
         this machine class: `prominence` + `merge_divide_trees`, one thread, on a real 6.85 M-cell DEM. Our \
         6.85 M-cell DEM is the shared Jacksboro DEM resampled to 2617 × 2617 (`relief convert --size`, a float \
         GeoTIFF: 26.1 MiB of f32 samples): smoother than a real DEM of that size, so fewer peaks, which matters \
         little to the flood's cost (linear passes over the cells). Not the same DEM: read the rows as orders of \
         magnitude. The flood holds, besides the DEM, an order key and an ascent pointer per cell, the basin \
         labels written over the pointers (12 bytes a cell), then the edges between basins, written into one \
         vector row by row; akirmse reads and floods tiles without holding the whole DEM in floats, hence its \
         far smaller footprint. Run: `cargo xtask prominence` (or any `cargo xtask bench`).\n\n",
    );
    if quick || !Path::new("/usr/bin/time").exists() {
        md.push_str(&fs::read_to_string(&cache).unwrap_or_else(|_| "(not run yet)\n".into()));
        md.push('\n');
        return Ok(md);
    }
    let relief = root.join("target/release/relief");
    let work = root.join("target/prominence");
    let (small, large) = jacksboro_resampled(root, &work.join("jacksboro-2617.tif"), "2617x2617")?;
    let dem_mib = 2617.0 * 2617.0 * 4.0 / 1024.0 / 1024.0;
    let mut lines = String::from(
        "| run | DEM | cells | wall time | peak memory | memory / DEM f32 bytes |\n|---|---|---:|---:|---:|---:|\n",
    );
    let csv = work.join("peaks.csv");
    for (name, dem, cells, threads) in [
        ("relief prominence (1 thread)", &large, "6.85 M", "1"),
        ("relief prominence (2 threads)", &large, "6.85 M", "2"),
        ("relief prominence (1 thread)", &small, "0.14 M", "1"),
    ] {
        let r = measure(&csv, |out| {
            let mut cmd = Command::new(&relief);
            cmd.args(["--threads", threads, "-q", "prominence"])
                .arg(dem)
                .args(["--min-prominence", "30", "--peaks"])
                .arg(out)
                .arg("--force");
            cmd
        })?;
        let mib = r.peak_kb as f64 / 1024.0;
        let kind = if dem == &large { "Jacksboro resampled, GeoTIFF" } else { "Jacksboro, ASCII grid" };
        let ratio = if dem == &large { format!("{:.2}", mib / dem_mib) } else { "—".to_owned() };
        let _ = writeln!(lines, "| {name} | {kind} | {cells} | {:.2} s | {mib:.1} MiB | {ratio} |", r.seconds);
    }
    lines.push_str(
        "| akirmse prominence + merge (1 thread, from the issue) | a real DEM | 6.85 M | 2.0 s | 18 MiB | — |\n",
    );
    fs::write(&cache, &lines).with_context(|| format!("writing {}", cache.display()))?;
    md.push_str(&lines);
    md.push('\n');
    Ok(md)
}
