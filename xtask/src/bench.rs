//! `cargo xtask bench`: run the criterion benches, collect medians, write `docs/benchmarks.md`.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::fs;
use std::path::Path;
use std::process::Command;

use anyhow::{Context, Result};

use crate::references::{GROUP_NOTES, REFERENCES, Reference, SECTION_NOTES};

/// Runs the benches (shorter warm-up and measurement with `quick`; only `packages` when given) and
/// writes the report from every median under `target/criterion`, so a partial run refreshes its
/// rows and keeps the others from earlier runs. Rows of the previous report with no median on
/// disk (a fresh clone has none) are carried over and marked, rather than dropped.
pub(crate) fn run(root: &Path, quick: bool, packages: &[String], report_only: bool) -> Result<()> {
    if !report_only {
        run_benches(root, quick, packages)?;
    }
    let out = root.join("docs/benchmarks.md");
    let mut medians = collect(&root.join("target/criterion"))?;
    let previous_text = fs::read_to_string(&out).unwrap_or_default();
    let previous = previous_medians(&previous_text);
    let measured = medians.len();
    let carried = carry_over(&mut medians, previous);
    let mut report = render(&medians, &carried, quick);
    report.push_str(&paired_tin(root, quick)?);
    report.push_str(&crate::gdal::contour_runs(root, quick)?);
    report.push_str(&crate::gdal::geotiff_runs(root, quick)?);
    report.push_str(&crate::prominence::prominence_runs(root, quick)?);
    let fit_again = !report_only && (packages.is_empty() || packages.iter().any(|p| p == "relief-gaussian-terrain"));
    report.push_str(&vectorize_runs(root, quick, !fit_again)?);
    let studio_again = !report_only && (packages.is_empty() || packages.iter().any(|p| p == "relief-studio"));
    report.push_str(&studio_runs(root, !studio_again)?);
    let report = keep_previous_sections(&report, &previous_text);
    let tmp = out.with_extension("md.tmp");
    fs::write(&tmp, report).with_context(|| format!("writing {}", tmp.display()))?;
    fs::rename(&tmp, &out).with_context(|| format!("renaming into {}", out.display()))?;
    println!("wrote {} ({measured} benchmarks measured, {} carried over)", out.display(), carried.len());
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
/// does not suit criterion's repeated sampling. The section's notes go between the timings and the
/// fidelity tables; both are kept in `target/vectorize-timing.md` and `target/vectorize-fidelity.md`
/// so that a report-only run or another package's run reprints them.
fn vectorize_runs(root: &Path, quick: bool, reprint: bool) -> Result<String> {
    let (cache, fidelity_cache) = (root.join("target/vectorize-timing.md"), root.join("target/vectorize-fidelity.md"));
    let mut md = String::from(
        "## gaussian-terrain, vectorize\n\nOne fit of the synthetic `fbm_dem` with 10 000 primitives, 200 Adam steps, \
         working grid 512² by default, 1024² in the paper's protocol (the paper: 1024², ≈ 10 000 primitives, \
         ≈ 60 s on an RTX 3090; the issue's target: 60 s at 1024² on 2 cores). ℓ₁ is of the relief's half-range (the relief mapped to [−1, 1], as \
         the paper's §4 words it; Table 3's unit, as the authors' code measures it, is the whole relief, so Table 3 \
         compares with half these figures), measured at the DEM's resolution. Run: `cargo run --release -p relief-gaussian-terrain --example vectorize_timing -- <size>`.\n\n",
    );
    let (lines, fidelity) = if reprint {
        (
            fs::read_to_string(&cache).unwrap_or_else(|_| "(not run yet)\n".into()),
            fs::read_to_string(&fidelity_cache).unwrap_or_default(),
        )
    } else {
        let (lines, fidelity) = (vectorize_timings(root, quick)?, fidelity_runs(root, quick)?);
        fs::write(&cache, &lines).with_context(|| format!("writing {}", cache.display()))?;
        fs::write(&fidelity_cache, &fidelity).with_context(|| format!("writing {}", fidelity_cache.display()))?;
        (lines, fidelity)
    };
    md.push_str(&lines);
    md.push('\n');
    md.push_str(&section_notes("gaussian-terrain, vectorize"));
    end_paragraph(&mut md);
    md.push_str(&fidelity_section(&fidelity));
    md.push('\n');
    Ok(md)
}

/// One `- …` line per run of the vectorize timing example (the 512² run alone with `quick`).
fn vectorize_timings(root: &Path, quick: bool) -> Result<String> {
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
    Ok(lines)
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
    md.push_str(&section_notes("studio"));
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

/// Trims `md` to end with one newline, so that a heading that starts with a blank line follows
/// its paragraph after exactly one.
fn end_paragraph(md: &mut String) {
    while md.ends_with("\n\n") {
        md.pop();
    }
}

/// The vectorization of real DEMs against the paper's choices
/// (`crates/relief/examples/vectorize_fidelity.rs`), at the paper's density of primitives (10 per
/// 1000 samples) and at 4× that: one table each (the section's text is [`fidelity_section`]'s).
fn fidelity_runs(root: &Path, quick: bool) -> Result<String> {
    let mut md = String::new();
    let variants = ["ours", "paper", "plain-range", "positional-densify", "uniform-steps", "paper-exponents"];
    let densities: &[&str] = if quick { &["10"] } else { &["10", "40"] };
    for density in densities {
        let out = Command::new(env!("CARGO"))
            .current_dir(root)
            .args(["run", "--quiet", "--release", "-p", "relief", "--example", "vectorize_fidelity", "--", density])
            .args(variants)
            .output()
            .context("could not start the vectorization fidelity runs")?;
        anyhow::ensure!(out.status.success(), "vectorize_fidelity failed: {}", String::from_utf8_lossy(&out.stderr));
        let paper = if *density == "10" { " (the paper's 10 000 at 1024²)" } else { "" };
        let _ = write!(
            md,
            "\n{density} primitives per 1000 DEM samples{paper}:\n\n{}",
            String::from_utf8_lossy(&out.stdout)
        );
    }
    Ok(md)
}

/// The fidelity section: its heading, what the columns and variants are, its notes, then the
/// `tables` of [`fidelity_runs`].
fn fidelity_section(tables: &str) -> String {
    let mut md = String::from(
        "\n### Real DEMs: fidelity, and our choices against the paper's\n\nEach row one fit (260 steps, the library's default) of a real DEM \
         in `fixtures/dem/` rasterized back at its grid: ℓ₁ of the relief's half-range, as above (twice Table 3's unit); *beyond range* the furthest \
         sample outside the DEM's elevation range, % of the relief; *flat* the error over samples whose 3 × 3 \
         (mean) or 5 × 5 (max, the open flat away from the steps at its edge) neighbourhood is flat in the DEM \
         (sea, a lake, filled no-data). `paper` is the paper's choices together, as its authors' code makes them \
         (3DGS densification by positional gradients; their Adam, one constant step size for every parameter of \
         their parametrisation with PyTorch's moment decays; their kernel's exponents, β in [2, 4] in ours; the plain \
         sum); the other variants are ours with one of them. Run: `cargo run --release -p relief --example vectorize_fidelity -- DENSITY VARIANT…`.\n",
    );
    let notes = section_notes("Real DEMs: fidelity, and our choices against the paper's");
    if !notes.is_empty() {
        let _ = write!(md, "\n{}", notes.trim_end());
        md.push('\n');
    }
    md.push_str(tables);
    md
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

/// The paragraphs of [`SECTION_NOTES`] for the section `heading`, each followed by a blank line.
fn section_notes(heading: &str) -> String {
    SECTION_NOTES.iter().filter(|(h, _)| *h == heading).map(|(_, note)| [*note, "\n\n"].concat()).collect()
}

/// What a section holds when its measurement has never run here (no cache under `target/`).
const NOT_RUN: &str = "(not run yet";

/// `report` with each `## ` section that holds [`NOT_RUN`] replaced by the `previous` report's
/// section of the same heading, when that one was measured: a fresh clone, or a machine without
/// the tool a section needs, keeps the last figures instead of losing them.
fn keep_previous_sections(report: &str, previous: &str) -> String {
    let earlier = sections(previous);
    sections(report)
        .into_iter()
        .map(|(heading, text)| {
            let kept = earlier.iter().find(|(h, t)| *h == heading && !heading.is_empty() && !t.contains(NOT_RUN));
            match kept {
                Some((_, t)) if text.contains(NOT_RUN) => t.clone(),
                _ => text,
            }
        })
        .collect()
}

/// `text` cut before each `## ` heading: (the heading, the section with it), the text before
/// the first heading under an empty one.
fn sections(text: &str) -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = vec![(String::new(), String::new())];
    for line in text.split_inclusive('\n') {
        if let Some(heading) = line.strip_prefix("## ") {
            out.push((heading.trim_end().to_string(), String::new()));
        }
        out.last_mut().expect("never empty").1.push_str(line);
    }
    out
}

/// The header of every criterion table in the report.
const TABLE_HEADER: &str = "| benchmark | ours | reference | reference time | ratio |";

/// Marks a row carried over from the previous report.
const CARRIED: &str = "†";

/// The medians in a report written by [`render`]: each table row's id and its `ours` time (the
/// first row of an id with several references). Only the criterion tables are read, not the
/// tables of the groups' prose.
fn previous_medians(report: &str) -> BTreeMap<String, f64> {
    let mut out = BTreeMap::new();
    let mut in_table = false;
    for line in report.lines() {
        if line == TABLE_HEADER {
            in_table = true;
            continue;
        }
        if !line.starts_with('|') {
            in_table = false;
        }
        if !in_table {
            continue;
        }
        let mut cells = line.split('|').skip(1);
        let (Some(id), Some(ours)) = (cells.next(), cells.next()) else { continue };
        let id = id.trim().trim_end_matches(CARRIED).trim_matches('`');
        if let (false, Some(s)) = (id.is_empty(), parse_time(ours.trim())) {
            out.entry(id.to_string()).or_insert(s);
        }
    }
    out
}

/// Seconds from a time as [`fmt_time`] writes it.
fn parse_time(text: &str) -> Option<f64> {
    let (value, unit) = text.split_once(' ')?;
    let value: f64 = value.parse().ok()?;
    let scale = match unit {
        "s" => 1.0,
        "ms" => 1e-3,
        "µs" => 1e-6,
        _ => return None,
    };
    Some(value * scale)
}

/// Adds to `medians` the `previous` ones it lacks, returning their ids.
fn carry_over(medians: &mut BTreeMap<String, f64>, previous: BTreeMap<String, f64>) -> BTreeSet<String> {
    let mut carried = BTreeSet::new();
    for (id, s) in previous {
        if !medians.contains_key(&id) {
            medians.insert(id.clone(), s);
            carried.insert(id);
        }
    }
    carried
}

/// The markdown report; the ids in `carried` are marked as not measured in this run.
fn render(medians: &BTreeMap<String, f64>, carried: &BTreeSet<String>, quick: bool) -> String {
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
    if !carried.is_empty() {
        let _ = writeln!(
            md,
            "Rows marked {CARRIED} were not measured in this run (a partial run, or no criterion data on \
             disk): they are carried over from the previous report. Delete a row here to drop a bench \
             that no longer exists.\n"
        );
    }
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
        let _ = writeln!(md, "{TABLE_HEADER}");
        let _ = writeln!(md, "|---|---:|---|---:|---:|");
        for (id, s) in rows {
            let mark = if carried.contains(id) { CARRIED } else { "" };
            let refs: Vec<(&str, Option<f64>)> = REFERENCES
                .iter()
                .filter(|(b, _)| b == id)
                .map(|(_, r)| match r {
                    Reference::Fixed { label, seconds } => (*label, Some(*seconds)),
                    Reference::SideBySide { label, bench } => (*label, medians.get(*bench).copied()),
                })
                .collect();
            if refs.is_empty() {
                let _ = writeln!(md, "| `{id}`{mark} | {} | — | — | — |", fmt_time(s));
            }
            for (label, reference) in refs {
                let (time, ratio) = reference.map_or(("not measured".to_string(), "—".to_string()), |r| {
                    (fmt_time(r), format!("{:.2}", s / r))
                });
                let _ = writeln!(md, "| `{id}`{mark} | {} | {label} | {time} | {ratio} |", fmt_time(s));
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A report's rows read back give the same figures when written again, marked as carried;
    /// the groups' own prose tables are not read as medians.
    #[test]
    fn carried_rows_keep_their_figures() {
        let measured: BTreeMap<String, f64> = [
            ("contours/extract_10_levels/100000", 0.008_43),
            ("gaussian_terrain/rasterize/1024/60k", 0.056_5),
            ("island/generate/2048", 1.234),
            ("tin/insert/1000", 0.000_123_4),
        ]
        .into_iter()
        .map(|(id, s)| (id.to_string(), s))
        .collect();
        let mut report = render(&measured, &BTreeSet::new(), false);
        // A group's note and a bench's references come from references.rs, only their own.
        let note = GROUP_NOTES.iter().find(|(g, _)| *g == "gaussian_terrain").expect("a note").1;
        assert!(report.contains(note));
        assert_eq!(GROUP_NOTES.iter().filter(|(_, n)| report.contains(n)).count(), 1);
        assert!(
            report
                .contains("| `gaussian_terrain/rasterize/1024/60k` | 56.5 ms | target (issue #25) | 50.0 ms | 1.13 |")
        );
        assert!(!report.contains("| `gaussian_terrain/rasterize/1024/60k` | 56.5 ms | — |"));
        assert!(!report.contains("Rows marked"));
        report.push_str("\n| scene | before |\n|---|---:|\n| `mountain` | 4.85 s |\n");
        let previous = previous_medians(&report);
        assert_eq!(previous.keys().collect::<Vec<_>>(), measured.keys().collect::<Vec<_>>());

        // A later run measured only one group: the others come from the report.
        let mut medians: BTreeMap<String, f64> =
            [("gaussian_terrain/rasterize/1024/60k".to_string(), 0.050_1)].into_iter().collect();
        let carried = carry_over(&mut medians, previous);
        assert_eq!(carried.len(), 3);
        assert!(!carried.contains("gaussian_terrain/rasterize/1024/60k"));
        let again = render(&medians, &carried, false);
        assert!(again.contains(&format!("Rows marked {CARRIED} were not measured")));
        assert!(again.contains("| `gaussian_terrain/rasterize/1024/60k` | 50.1 ms |"));
        for (id, &s) in measured.iter().filter(|(id, _)| carried.contains(*id)) {
            let row = format!("| `{id}`{CARRIED} | {} |", fmt_time(s));
            assert!(again.contains(&row), "missing {row}");
        }
        // Read back once more, the marks do not leak into the ids, and the figures stay put.
        let rounded = |s: f64| parse_time(&fmt_time(s)).unwrap();
        let expected: BTreeMap<String, f64> = medians.iter().map(|(id, &s)| (id.clone(), rounded(s))).collect();
        assert_eq!(previous_medians(&again), expected);
    }

    /// A section never measured here takes the previous report's; measured ones, and a previous
    /// section that was never measured either, do not.
    #[test]
    fn unmeasured_sections_keep_the_previous_ones() {
        let previous = "# Benchmarks\n\nold header\n\n## a\n\nold a\n\n## gdal\n\n| old | table |\n\n\
                        ## studio\n\n(not run yet)\n\n";
        let report = "# Benchmarks\n\nnew header\n\n## a\n\nnew a\n\n## gdal\n\n(not run yet: install gdal-bin)\n\n\
                      ## studio\n\n(not run yet)\n\n## new\n\n(not run yet)\n";
        let kept = keep_previous_sections(report, previous);
        assert_eq!(
            kept,
            "# Benchmarks\n\nnew header\n\n## a\n\nnew a\n\n## gdal\n\n| old | table |\n\n\
             ## studio\n\n(not run yet)\n\n## new\n\n(not run yet)\n"
        );
        assert_eq!(keep_previous_sections(report, ""), report);
    }

    /// A section's notes are its own, each closed by a blank line.
    #[test]
    fn section_notes_are_found_by_heading() {
        let studio = section_notes("studio");
        let own: Vec<&str> = SECTION_NOTES.iter().filter(|(h, _)| *h == "studio").map(|(_, n)| *n).collect();
        assert!(!own.is_empty());
        assert_eq!(studio, own.iter().map(|n| format!("{n}\n\n")).collect::<Vec<_>>().concat());
        assert_eq!(section_notes("no such section"), "");
    }

    #[test]
    fn times_parse_in_every_unit() {
        assert_eq!(parse_time("1.50 s"), Some(1.5));
        assert!((parse_time("57.6 ms").unwrap() - 0.0576).abs() < 1e-12);
        assert!((parse_time("12.3 µs").unwrap() - 12.3e-6).abs() < 1e-15);
        assert_eq!(parse_time("not measured"), None);
        assert_eq!(parse_time("—"), None);
    }
}
