//! `cargo xtask bench`: run the criterion benches, collect medians, write `docs/benchmarks.md`.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::fs;
use std::path::Path;
use std::process::Command;

use anyhow::{Context, Result};

use crate::references::{GROUP_NOTES, REFERENCES, Reference};

/// Runs the benches (shorter warm-up and measurement with `quick`; only `packages` when given) and
/// writes the report from every median under `target/criterion`, so a partial run refreshes its
/// rows and keeps the others from earlier runs.
pub(crate) fn run(root: &Path, quick: bool, packages: &[String], report_only: bool) -> Result<()> {
    if !report_only {
        run_benches(root, quick, packages)?;
    }
    let medians = collect(&root.join("target/criterion"))?;
    let mut report = render(&medians, quick);
    report.push_str(&paired_tin(root, quick)?);
    report.push_str(&crate::gdal::contour_runs(root, quick)?);
    report.push_str(&crate::gdal::geotiff_runs(root, quick)?);
    report.push_str(&crate::prominence::prominence_runs(root, quick)?);
    let fit_again = !report_only && (packages.is_empty() || packages.iter().any(|p| p == "relief-gaussian-terrain"));
    report.push_str(&vectorize_runs(root, quick, !fit_again)?);
    let studio_again = !report_only && (packages.is_empty() || packages.iter().any(|p| p == "relief-studio"));
    report.push_str(&studio_runs(root, !studio_again)?);
    let out = root.join("docs/benchmarks.md");
    let tmp = out.with_extension("md.tmp");
    fs::write(&tmp, report).with_context(|| format!("writing {}", tmp.display()))?;
    fs::rename(&tmp, &out).with_context(|| format!("renaming into {}", out.display()))?;
    println!("wrote {} ({} benchmarks)", out.display(), medians.len());
    Ok(())
}

/// `cargo bench` over the workspace or the named packages.
fn run_benches(root: &Path, quick: bool, packages: &[String]) -> Result<()> {
    let mut cmd = Command::new(env!("CARGO"));
    cmd.current_dir(root).arg("bench");
    if packages.is_empty() {
        cmd.arg("--workspace");
    }
    for p in packages {
        cmd.args(["-p", p]);
    }
    // Bench targets only: `--benches` would also run the libraries' libtest harnesses, which reject
    // criterion's options.
    cmd.args(["--bench", "*", "--"]);
    if quick {
        // The benches skip their largest sizes (seconds per iteration, ten samples each) when
        // they see RELIEF_BENCH_QUICK; the report keeps those rows from the last full run. About 7
        // minutes on the 2-core VM once the benches are built (12 with 1 s / 2 s and every size).
        cmd.args(["--warm-up-time", "0.5", "--measurement-time", "1"]).env("RELIEF_BENCH_QUICK", "1");
    }
    crate::run(&mut cmd)
}

/// The TIN wrapper's cost over spade measured in pairs (`crates/tin/examples/wrapper_overhead.rs`):
/// separate criterion runs drift apart on a shared machine, pairs on the same points do not.
fn paired_tin(root: &Path, quick: bool) -> Result<String> {
    let sizes: &[&str] = if quick { &["10000", "100000"] } else { &["10000", "100000", "1000000"] };
    let mut md = String::from(
        "## tin, paired\n\n`Tin::new` ÷ spade `bulk_load` alone, timed back to back on the same points each round \
         (median of the per-round ratios; target < 1.3×). Run: \
         `cargo run --release -p relief-tin --example wrapper_overhead -- <points>`.\n\n",
    );
    for n in sizes {
        let out = Command::new(env!("CARGO"))
            .current_dir(root)
            .args(["run", "--quiet", "--release", "-p", "relief-tin", "--example", "wrapper_overhead", "--", n])
            .output()
            .context("could not start the paired TIN measurement")?;
        anyhow::ensure!(out.status.success(), "wrapper_overhead {n} failed: {}", String::from_utf8_lossy(&out.stderr));
        let _ = writeln!(md, "- {}", String::from_utf8_lossy(&out.stdout).trim());
    }
    md.push('\n');
    Ok(md)
}

/// Vectorization at the paper's size (§6: 1024², about 10 000 primitives, ≈ 60 s on an RTX 3090),
/// one timed run each (`crates/gaussian-terrain/examples/vectorize_timing.rs`): a minute-long fit
/// does not suit criterion's repeated sampling. The lines are kept in
/// `target/vectorize-timing.md` so that a report-only run or another package's run reprints them.
fn vectorize_runs(root: &Path, quick: bool, reprint: bool) -> Result<String> {
    let cache = root.join("target/vectorize-timing.md");
    let mut md = String::from(
        "## gaussian-terrain, vectorize\n\nOne fit of the synthetic `fbm_dem` with 10 000 primitives, 200 Adam steps, \
         working grid 512² by default, 1024² in the paper's protocol (the paper: 1024², ≈ 10 000 primitives, \
         ≈ 60 s on an RTX 3090; the issue's target: 60 s at 1024² on 2 cores). ℓ₁ is normalized like Table 3 (relief mapped to [−1, 1]), measured at the DEM's \
         resolution. Run: `cargo run --release -p relief-gaussian-terrain --example vectorize_timing -- <size>`.\n\n",
    );
    if reprint {
        md.push_str(&fs::read_to_string(&cache).unwrap_or_else(|_| "(not run yet)\n".into()));
        md.push('\n');
        return Ok(md);
    }
    let runs: &[&[&str]] = if quick { &[&["512"]] } else { &[&["512"], &["1024"], &["1024", "10000", "200", "1024"]] };
    let mut lines = String::new();
    for args in runs {
        let out = Command::new(env!("CARGO"))
            .current_dir(root)
            .args([
                "run",
                "--quiet",
                "--release",
                "-p",
                "relief-gaussian-terrain",
                "--example",
                "vectorize_timing",
                "--",
            ])
            .args(*args)
            .output()
            .context("could not start the vectorization timing")?;
        anyhow::ensure!(
            out.status.success(),
            "vectorize_timing {args:?} failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let _ = writeln!(lines, "- {}", String::from_utf8_lossy(&out.stdout).trim());
    }
    lines.push_str(&fidelity_runs(root, quick)?);
    fs::write(&cache, &lines).with_context(|| format!("writing {}", cache.display()))?;
    md.push_str(&lines);
    md.push('\n');
    Ok(md)
}

/// The studio's latency as a user sees it: edit → map and 3D view redrawn, measured by the page in
/// headless Chromium (`crates/studio/tests/browser.rs` with `RELIEF_STUDIO_LATENCY`). Needs
/// `chromium` and `chromedriver`; without them, or on a report-only run, the section keeps the
/// last run's lines (`target/studio-latency.md`).
fn studio_runs(root: &Path, reprint: bool) -> Result<String> {
    let cache = root.join("target/studio-latency.md");
    let mut md = String::from(
        "## studio

relief studio in headless Chromium (software WebGL) on the same machine as its server: the \
         page's own time from a gesture's edit to the map and the 3D view redrawn (*end to end*), and the server's \
         generation (*server*). The issue's targets: an island edit under 100 ms end to end at 512², a 50 000-node \
         contour regrowth under 1 s. Run: `RELIEF_E2E=1 RELIEF_STUDIO_LATENCY=1 cargo test --release -p \
         relief-studio --test browser -- --nocapture`.\n\n",
    );
    let on_path = |name: &str| {
        std::env::var_os("PATH").is_some_and(|paths| std::env::split_paths(&paths).any(|d| d.join(name).is_file()))
    };
    if reprint || !on_path("chromedriver") {
        md.push_str(&fs::read_to_string(&cache).unwrap_or_else(|_| "(not run yet)\n".into()));
        md.push('\n');
        return Ok(md);
    }
    let out = Command::new(env!("CARGO"))
        .current_dir(root)
        .env("RELIEF_E2E", "1")
        .env("RELIEF_STUDIO_LATENCY", "1")
        .args(["test", "--quiet", "--release", "-p", "relief-studio", "--test", "browser", "--", "--nocapture"])
        .output()
        .context("could not start the studio's browser test")?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    anyhow::ensure!(out.status.success(), "the studio's browser test failed: {stderr}");
    let mut lines = String::new();
    for line in stderr.lines().filter(|l| l.contains("end to end")) {
        let _ = writeln!(lines, "- {line}");
    }
    fs::write(&cache, &lines).with_context(|| format!("writing {}", cache.display()))?;
    md.push_str(&lines);
    md.push('\n');
    Ok(md)
}

/// The vectorization of real DEMs against the paper's choices
/// (`crates/relief/examples/vectorize_fidelity.rs`), at the paper's density of primitives (10 per
/// 1000 samples) and at 4× that: one table each.
fn fidelity_runs(root: &Path, quick: bool) -> Result<String> {
    let mut md = String::from(
        "\n### Real DEMs: fidelity, and our choices against the paper's\n\nEach row one fit (200 steps) of a real DEM \
         in `fixtures/dem/` rasterized back at its grid: ℓ₁ normalized like Table 3; *beyond range* the furthest \
         sample outside the DEM's elevation range, % of the relief; *flat* the error over samples whose 3 × 3 \
         (mean) or 5 × 5 (max, the open flat away from the steps at its edge) neighbourhood is flat in the DEM \
         (sea, a lake, filled no-data). `paper` is the paper's choices together (3DGS densification by positional \
         gradients, one Adam step size for every parameter, the plain sum); the other variants are ours with one \
         of them. Run: `cargo run --release -p relief --example vectorize_fidelity -- DENSITY VARIANT…`.\n",
    );
    let variants = ["ours", "paper", "plain-range", "positional-densify", "uniform-steps"];
    let densities: &[&str] = if quick { &["10"] } else { &["10", "40"] };
    for density in densities {
        let out = Command::new(env!("CARGO"))
            .current_dir(root)
            .args(["run", "--quiet", "--release", "-p", "relief", "--example", "vectorize_fidelity", "--", density])
            .args(variants)
            .output()
            .context("could not start the vectorization fidelity runs")?;
        anyhow::ensure!(out.status.success(), "vectorize_fidelity failed: {}", String::from_utf8_lossy(&out.stderr));
        let _ = write!(md, "\n{density} primitives per 1000 DEM samples:\n\n{}", String::from_utf8_lossy(&out.stdout));
    }
    Ok(md)
}

/// Median seconds per criterion id (`group/function/parameter`), from `*/new/estimates.json`.
fn collect(dir: &Path) -> Result<BTreeMap<String, f64>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = fs::read_dir(&d) else { continue };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            if path.file_name().is_none_or(|n| n != "estimates.json")
                || path.parent().is_none_or(|p| !p.ends_with("new"))
            {
                continue;
            }
            let new_dir = path.parent().context("estimates.json without a parent")?;
            let meta: serde_json::Value = serde_json::from_str(&fs::read_to_string(new_dir.join("benchmark.json"))?)?;
            let est: serde_json::Value = serde_json::from_str(&fs::read_to_string(&path)?)?;
            let id = meta["full_id"].as_str().context("benchmark.json without full_id")?.to_string();
            let ns = est["median"]["point_estimate"].as_f64().context("estimates.json without a median")?;
            out.insert(id, ns * 1e-9);
        }
    }
    Ok(out)
}

/// The markdown report.
fn render(medians: &BTreeMap<String, f64>, quick: bool) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "# Benchmarks\n");
    let _ = writeln!(
        md,
        "Generated by `cargo xtask bench{}` on {} ({} cores, {}), {}. Medians of criterion runs; the",
        if quick { " --quick" } else { "" },
        hostname(),
        cores(),
        cpu_model(),
        today()
    );
    let _ = writeln!(
        md,
        "ratio is ours ÷ reference, so below 1 means faster. Timings on shared 2-core machines are noisy:"
    );
    let _ = writeln!(md, "compare side-by-side rows of the same run before absolute ones.\n");
    let mut by_crate: BTreeMap<&str, Vec<(&String, f64)>> = BTreeMap::new();
    for (id, &s) in medians {
        let group = id.split('/').next().unwrap_or(id);
        by_crate.entry(group).or_default().push((id, s));
    }
    for (group, rows) in by_crate {
        let _ = writeln!(md, "## {group}\n");
        for (_, note) in GROUP_NOTES.iter().filter(|(g, _)| *g == group) {
            let _ = writeln!(md, "{note}\n");
        }
        let _ = writeln!(md, "| benchmark | ours | reference | reference time | ratio |");
        let _ = writeln!(md, "|---|---:|---|---:|---:|");
        for (id, s) in rows {
            let refs: Vec<(&str, Option<f64>)> = REFERENCES
                .iter()
                .filter(|(b, _)| b == id)
                .map(|(_, r)| match r {
                    Reference::Fixed { label, seconds } => (*label, Some(*seconds)),
                    Reference::SideBySide { label, bench } => (*label, medians.get(*bench).copied()),
                })
                .collect();
            if refs.is_empty() {
                let _ = writeln!(md, "| `{id}` | {} | — | — | — |", fmt_time(s));
            }
            for (label, reference) in refs {
                let (time, ratio) = reference.map_or(("not measured".to_string(), "—".to_string()), |r| {
                    (fmt_time(r), format!("{:.2}", s / r))
                });
                let _ = writeln!(md, "| `{id}` | {} | {label} | {time} | {ratio} |", fmt_time(s));
            }
        }
        md.push('\n');
    }
    md
}

fn fmt_time(s: f64) -> String {
    if s >= 1.0 {
        format!("{s:.2} s")
    } else if s >= 1e-3 {
        format!("{:.1} ms", s * 1e3)
    } else {
        format!("{:.1} µs", s * 1e6)
    }
}

fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
}

fn cpu_model() -> String {
    fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into())
}

fn hostname() -> String {
    fs::read_to_string("/etc/hostname").map_or_else(|_| "this machine".into(), |h| format!("`{}`", h.trim()))
}

fn today() -> String {
    Command::new("date")
        .arg("+%Y-%m-%d")
        .output()
        .ok()
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map_or_else(|| "unknown date".into(), |d| d.trim().to_string())
}
