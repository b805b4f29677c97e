//! `relief contours` beside `gdal_contour` (Debian's `gdal-bin`) on the same DEM in the same run:
//! wall time and peak memory of each tool, and the size of what each writes. The project never
//! depends on GDAL: without `gdal_contour` on the PATH the section keeps the last run's lines.

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};
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
    let (relief, work) = (root.join("target/release/relief"), root.join("target/gdal-contour"));
    let (small, large) = jacksboro_resampled(root, &work.join("jacksboro-1209.asc"), "1209x1032")?;
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

/// Builds the release `relief`, then resamples the shared Jacksboro DEM to `size` (`WxH`) into
/// `large` (its folder created): the small and large DEMs the sections measure on.
pub(crate) fn jacksboro_resampled(root: &Path, large: &Path, size: &str) -> Result<(PathBuf, PathBuf)> {
    let cargo = ["build", "--quiet", "--release", "-p", "relief-cli"];
    crate::run(Command::new(env!("CARGO")).current_dir(root).args(cargo))?;
    fs::create_dir_all(large.parent().context("resampled DEM path")?)?;
    let small = root.join("fixtures/dem/jacksboro.asc");
    let resample =
        [small.to_str().context("DEM path")?, large.to_str().context("path")?, "--size", size, "--force", "-q"];
    crate::run(Command::new(root.join("target/release/relief")).arg("convert").args(resample))?;
    Ok((small, large.to_path_buf()))
}

/// One tool's best of three runs.
pub(crate) struct Run {
    pub(crate) seconds: f64,
    pub(crate) peak_kb: u64,
    bytes: u64,
}

/// Runs the command `make(out)` three times under `/usr/bin/time` (removing `out` first: GDAL
/// refuses to overwrite), keeping the best time and the largest peak memory.
pub(crate) fn measure(out: &Path, make: impl Fn(&Path) -> Command) -> Result<Run> {
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

/// `relief convert DEM.asc OUT.tif` beside `gdal_translate` writing the same GeoTIFF: one row per
/// output kind, each tool's best time and the file size. Like [`contour_runs`], the last run's
/// lines are kept for machines without GDAL.
pub(crate) fn geotiff_runs(root: &Path, quick: bool) -> Result<String> {
    let cache = root.join("target/gdal-geotiff.md");
    let mut md = String::from(
        "## GeoTIFF writing, beside gdal_translate\n\n`relief convert DEM.asc OUT.tif [flags]` and `gdal_translate -q \
         [flags] DEM.asc OUT.tif` writing the same kind of file from the same ASCII grid (so both times include \
         parsing it): the shared Jacksboro DEM (whole metres) and its 1209 × 1032 bilinear resampling (fractional \
         elevations). Best wall time of 3 runs and file size. Run: `cargo xtask gdal-contours` (or any `cargo \
         xtask bench`) with `gdal-bin` installed.\n\n",
    );
    let available = |tool: &str| Command::new(tool).arg("--version").output().is_ok();
    if quick || !available("gdal_translate") || !Path::new("/usr/bin/time").exists() {
        md.push_str(&fs::read_to_string(&cache).unwrap_or_else(|_| "(not run yet: install gdal-bin)\n".into()));
        md.push('\n');
        return Ok(md);
    }
    let relief = root.join("target/release/relief");
    let work = root.join("target/gdal-contour");
    let (small, large) = (root.join("fixtures/dem/jacksboro.asc"), work.join("jacksboro-1209.asc"));
    // (output, relief flags, gdal_translate flags)
    let kinds: [(&str, &[&str], &[&str]); 3] = [
        ("f32 uncompressed", &["--no-compress"], &["-ot", "Float32"]),
        (
            "f32 DEFLATE + predictor 3 (relief's default)",
            &[],
            &["-ot", "Float32", "-co", "COMPRESS=DEFLATE", "-co", "PREDICTOR=3"],
        ),
        (
            "i16 DEFLATE + predictor 2",
            &["--tiff-type", "i16"],
            &["-ot", "Int16", "-co", "COMPRESS=DEFLATE", "-co", "PREDICTOR=2"],
        ),
    ];
    let mut lines = String::from(
        "| DEM | output | relief | relief size | gdal_translate | gdal size |\n|---|---|---:|---:|---:|---:|\n",
    );
    for (name, dem) in [("Jacksboro 403 × 344", &small), ("Jacksboro 1209 × 1032", &large)] {
        for (kind, ours, theirs) in kinds {
            let r = measure(&work.join("relief.tif"), |out| {
                let mut cmd = Command::new(&relief);
                cmd.arg("convert").arg(dem).arg(out).args(ours).args(["--force", "-q"]);
                cmd
            })?;
            let g = measure(&work.join("gdal.tif"), |out| {
                let mut cmd = Command::new("gdal_translate");
                cmd.arg("-q").args(theirs).arg(dem).arg(out);
                cmd
            })?;
            let kb = |b: u64| b.div_ceil(1024);
            let _ = writeln!(
                lines,
                "| {name} | {kind} | {:.3} s | {} kB | {:.3} s | {} kB |",
                r.seconds,
                kb(r.bytes),
                g.seconds,
                kb(g.bytes)
            );
        }
    }
    fs::write(&cache, &lines).with_context(|| format!("writing {}", cache.display()))?;
    md.push_str(&lines);
    md.push('\n');
    Ok(md)
}
