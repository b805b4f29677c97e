//! `cargo xtask fuzz [SECONDS] [TARGET]...`: runs every cargo-fuzz target under `fuzz/` (or the
//! named ones) for SECONDS each (default 600), one after another, from the committed seeds in
//! `fuzz/seeds/<target>` and the corpus it grows in `fuzz/corpus/<target>` (not committed).
//!
//! Needs the nightly toolchain (libFuzzer's instrumentation); installs `cargo-fuzz` when it is
//! missing. A target that finds a crash leaves the input in `fuzz/artifacts/<target>/`; the
//! command goes on with the others and fails at the end, naming them. A crash, once fixed,
//! becomes a regression file under `fixtures/bad/` (see `fixtures/bad/README.md`).

use std::fs;
use std::path::Path;
use std::process::{Command, Stdio};

use anyhow::{Context, Result, bail};

/// What `cargo run` (and so `cargo xtask`) sets for the program it runs, naming the toolchain
/// that built it. A nested `cargo +nightly` must not inherit them: with `RUSTC` pointing at the
/// stable compiler, the nightly build of the fuzz targets is rejected (E0554, `#![feature]` on
/// stable).
const TOOLCHAIN_ENV: [&str; 6] =
    ["RUSTC", "RUSTDOC", "RUSTUP_TOOLCHAIN", "CARGO", "RUSTC_WRAPPER", "CARGO_ENCODED_RUSTFLAGS"];

/// A command for the nightly toolchain, with the environment of the stable `cargo run` cleared.
fn nightly(root: &Path, program: &str) -> Command {
    let mut cmd = Command::new(program);
    cmd.current_dir(root).arg("+nightly");
    for var in TOOLCHAIN_ENV {
        cmd.env_remove(var);
    }
    for (var, _) in std::env::vars_os() {
        let var = var.to_string_lossy();
        if var.starts_with("CARGO_PKG_")
            || var.starts_with("CARGO_MANIFEST_")
            || var.starts_with("CARGO_BIN_")
            || var.starts_with("CARGO_CRATE_")
            || var == "CARGO_PRIMARY_PACKAGE"
        {
            cmd.env_remove(var.as_ref());
        }
    }
    cmd
}

pub(crate) fn run(root: &Path, seconds: u64, only: &[String]) -> Result<()> {
    let fuzz = || {
        let mut cmd = nightly(root, "cargo");
        cmd.arg("fuzz");
        cmd
    };
    let has_nightly = nightly(root, "rustc").arg("--version").stdout(Stdio::null()).stderr(Stdio::null()).status();
    if !has_nightly.is_ok_and(|s| s.success()) {
        println!("installing the nightly toolchain (libFuzzer needs it)");
        crate::run(Command::new("rustup").args(["toolchain", "install", "nightly", "--profile", "minimal"]))?;
    }
    let installed = fuzz().arg("--version").stdout(Stdio::null()).stderr(Stdio::null()).status();
    if !installed.is_ok_and(|s| s.success()) {
        println!("installing cargo-fuzz");
        crate::run(Command::new("cargo").args(["install", "cargo-fuzz", "--locked"]))?;
    }
    let listed = fuzz().arg("list").output().context("listing the fuzz targets")?;
    anyhow::ensure!(listed.status.success(), "cargo fuzz list: {}", String::from_utf8_lossy(&listed.stderr));
    let targets: Vec<String> = String::from_utf8_lossy(&listed.stdout)
        .lines()
        .map(str::trim)
        .filter(|t| !t.is_empty() && (only.is_empty() || only.iter().any(|o| o == t)))
        .map(str::to_owned)
        .collect();
    anyhow::ensure!(!targets.is_empty(), "no fuzz target matches {only:?}");
    let logs = root.join("target/fuzz-logs");
    fs::create_dir_all(&logs)?;
    let mut failed = Vec::new();
    for target in &targets {
        let corpus = root.join("fuzz/corpus").join(target);
        fs::create_dir_all(&corpus)?;
        let seeds = root.join("fuzz/seeds").join(target);
        let log = logs.join(format!("{target}.log"));
        println!("fuzzing {target} for {seconds} s (log: {})", log.display());
        let mut cmd = fuzz();
        // `--no-cfg-fuzzing`: spade checks its whole hull after every insertion under
        // `cfg(fuzzing)`, which makes triangulating a few thousand points take minutes; our code
        // has no fuzzing-only paths to enable.
        cmd.args(["run", "-O", "--no-cfg-fuzzing", target]).arg(&corpus);
        if seeds.is_dir() {
            cmd.arg(&seeds);
        }
        cmd.arg("--")
            .arg(format!("-max_total_time={seconds}"))
            .args(["-rss_limit_mb=2048", "-timeout=30", "-print_final_stats=1"])
            .stdout(Stdio::null())
            .stderr(fs::File::create(&log)?);
        let status = cmd.status().with_context(|| format!("could not start cargo fuzz run {target}"))?;
        let text = fs::read_to_string(&log).unwrap_or_default();
        let done =
            text.lines().rev().find(|l| l.starts_with("Done ") || l.starts_with("stat::number_of_executed_units"));
        match (status.success(), done) {
            (true, done) => println!("  clean: {}", done.unwrap_or("(no summary)")),
            (false, Some(done)) => println!("  FAILED: {done}"),
            // It never ran: the build or the start failed; say why from the end of the log.
            (false, None) => {
                let lines: Vec<&str> = text.lines().collect();
                println!("  FAILED before fuzzing; the end of {}:", log.display());
                for line in &lines[lines.len().saturating_sub(15)..] {
                    println!("    {line}");
                }
            }
        }
        if !status.success() {
            failed.push(target.clone());
        }
    }
    if !failed.is_empty() {
        bail!("fuzz targets failed (inputs in fuzz/artifacts/): {}", failed.join(", "));
    }
    println!("{} targets ran clean for {seconds} s each", targets.len());
    Ok(())
}
