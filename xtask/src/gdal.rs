//! `relief contours` beside `gdal_contour` (Debian's `gdal-bin`) on the same DEM in the same run:
//! wall time and peak memory of each tool, and the size of what each writes. The project never
//! depends on GDAL: without `gdal_contour` on the PATH the section keeps the last run's lines.

use std::fmt::Write as _;
use std::fs;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

use anyhow::{Context, Result};

/// The contour intervals compared, metres.
const INTERVALS: [&str; 3] = ["10", "5", "2"];

/// The report section: measured now when `gdal_contour` and `/usr/bin/time` are there, else the
/// lines of the last run (kept in `target/gdal-contour.md`).
pub(crate) fn contour_runs(root: &Path, quick: bool) -> Result<String> {
    let cache = root.join("target/gdal-contour.md");
    let mut md = String::from(
        "## contours, beside gdal_contour\n\n`relief contours DEM --interval M --geojson OUT` and `gdal_contour -q -i M \
         -a elev -f GeoJSON DEM OUT` on the same DEMs, one after the other: the shared Jacksboro SRTM DEM (403 × 344) \
         and the same resampled to 1209 × 1032 (1.25 M cells, `relief convert --size`). Best wall time of 3 runs, \
         peak resident memory (`/usr/bin/time`), output size. Run: `cargo xtask gdal-contours` (or any \
         `cargo xtask bench`) with `gdal-bin` installed.\n\n",
    );
    // gdal_contour --version prints the version and exits 1: being able to start it is enough.
    let available = |tool: &str| Command::new(tool).arg("--version").output().is_ok();
    if quick || !available("gdal_contour") || !Path::new("/usr/bin/time").exists() {
        md.push_str(&fs::read_to_string(&cache).unwrap_or_else(|_| "(not run yet: install gdal-bin)\n".into()));
        md.push('\n');
        return Ok(md);
    }
    crate::run(Command::new(env!("CARGO")).current_dir(root).args([
        "build",
        "--quiet",
        "--release",
        "-p",
        "relief-cli",
    ]))?;
    let relief = root.join("target/release/relief");
    let work = root.join("target/gdal-contour");
    fs::create_dir_all(&work)?;
    let small = root.join("fixtures/dem/jacksboro.asc");
    let large = work.join("jacksboro-1209.asc");
    let source = small.to_str().context("DEM path")?;
    let resample = [source, large.to_str().context("path")?, "--size", "1209x1032", "--force", "-q"];
    crate::run(Command::new(&relief).arg("convert").args(resample))?;
    let mut lines = String::from(
        "| DEM | interval | relief | relief memory | relief output | gdal_contour | gdal memory | gdal output | time ratio |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for (name, dem) in [("Jacksboro 403 × 344", small), ("Jacksboro 1209 × 1032", large)] {
        for interval in INTERVALS {
            let ours = work.join(format!("relief-{interval}.geojson"));
            let theirs = work.join(format!("gdal-{interval}.geojson"));
            let r = measure(&ours, |out| {
                let mut cmd = Command::new(&relief);
                cmd.arg("contours")
                    .arg(&dem)
                    .args(["--interval", interval, "--geojson"])
                    .arg(out)
                    .args(["--force", "-q"]);
                cmd
            })?;
            let g = measure(&theirs, |out| {
                let mut cmd = Command::new("gdal_contour");
                cmd.args(["-q", "-i", interval, "-a", "elev", "-f", "GeoJSON"]).arg(&dem).arg(out);
                cmd
            })?;
            let _ = writeln!(
                lines,
                "| {name} | {interval} m | {:.2} s | {} MB | {} MB | {:.2} s | {} MB | {} MB | {:.2} |",
                r.seconds,
                r.peak_kb / 1024,
                r.bytes >> 20,
                g.seconds,
                g.peak_kb / 1024,
                g.bytes >> 20,
                r.seconds / g.seconds
            );
        }
    }
    fs::write(&cache, &lines).with_context(|| format!("writing {}", cache.display()))?;
    md.push_str(&lines);
    md.push('\n');
    Ok(md)
}

/// One tool's best of three runs.
struct Run {
    seconds: f64,
    peak_kb: u64,
    bytes: u64,
}

/// Runs the command `make(out)` three times under `/usr/bin/time` (removing `out` first: GDAL
/// refuses to overwrite), keeping the best time and the largest peak memory.
fn measure(out: &Path, make: impl Fn(&Path) -> Command) -> Result<Run> {
    let mut best = Run { seconds: f64::INFINITY, peak_kb: 0, bytes: 0 };
    for _ in 0..3 {
        let _ = fs::remove_file(out);
        let inner = make(out);
        let mut timed = Command::new("/usr/bin/time");
        timed.args(["-f", "%M"]).arg(inner.get_program()).args(inner.get_args());
        let start = Instant::now();
        let output = timed.output().context("running /usr/bin/time")?;
        let seconds = start.elapsed().as_secs_f64();
        anyhow::ensure!(output.status.success(), "{:?} failed: {}", inner, String::from_utf8_lossy(&output.stderr));
        let stderr = String::from_utf8_lossy(&output.stderr);
        let peak_kb = stderr.lines().last().and_then(|l| l.trim().parse().ok()).unwrap_or(0);
        best = Run { seconds: best.seconds.min(seconds), peak_kb: best.peak_kb.max(peak_kb), bytes: file_size(out) };
    }
    Ok(best)
}

fn file_size(path: &Path) -> u64 {
    fs::metadata(path).map_or(0, |m| m.len())
}
