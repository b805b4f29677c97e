//! Determinism and crash safety of `relief generate`, end to end on the real binary.
//!
//! - Determinism: for one fixture scene of every generator kind (run small), the outputs are
//!   byte-identical with `RAYON_NUM_THREADS=1` and `=2`, and across two runs.
//! - Crash safety: `relief generate` killed with SIGKILL at pseudo-random moments never leaves a
//!   file under a final output name that differs from a complete run's.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Copies `from` into `to`, recursively.
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        let target = to.join(path.file_name().unwrap());
        if path.is_dir() {
            copy_dir(&path, &target);
        } else {
            std::fs::copy(&path, &target).unwrap();
        }
    }
}

/// A workspace holding copies of the fixture scenes' inputs (`scenes/inputs`, `dem`), so that
/// scene variants written under `scenes/` resolve their relative paths as the fixtures do.
fn workspace() -> tempfile::TempDir {
    let tmp = tempfile::tempdir().unwrap();
    copy_dir(&root().join("fixtures/scenes/inputs"), &tmp.path().join("scenes/inputs"));
    copy_dir(&root().join("fixtures/dem"), &tmp.path().join("dem"));
    tmp
}

/// The fixture scene `name` at `resolution`², written into `ws/scenes/`.
fn small_scene(ws: &Path, name: &str, resolution: usize) -> PathBuf {
    let text = std::fs::read_to_string(root().join("fixtures/scenes").join(name)).unwrap();
    let mut scene: serde_json::Value = serde_json::from_str(&text).unwrap();
    let reconstruction =
        scene.as_object_mut().unwrap().entry("reconstruction").or_insert_with(|| serde_json::json!({}));
    reconstruction["resolution"] = serde_json::json!([resolution, resolution]);
    let path = ws.join("scenes").join(name);
    std::fs::write(&path, serde_json::to_string_pretty(&scene).unwrap()).unwrap();
    path
}

fn relief(scene: &Path, out: &Path, threads: &str) -> std::process::Command {
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_relief"));
    cmd.args(["--quiet", "generate"]).arg(scene).arg("--out").arg(out).env("RAYON_NUM_THREADS", threads);
    cmd
}

/// Every file under `dir` by name; `summary.json` without its timings, which vary by run.
fn outputs(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut files = BTreeMap::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let mut bytes = std::fs::read(&path).unwrap();
        if name == "summary.json" {
            let mut v: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
            v.as_object_mut().unwrap().remove("timings_ms");
            bytes = serde_json::to_vec(&v).unwrap();
        }
        files.insert(name, bytes);
    }
    files
}

#[test]
fn every_generator_is_byte_identical_across_thread_counts_and_runs() {
    let ws = workspace();
    // Every generator kind: contours (with a warp edit), diffusion (two scenes), island (with
    // seeded perturbation filters), Gaussian (listed primitives with the tools, and a fit from a
    // DEM), orometry.
    let scenes = [
        "editing-session.json",
        "mountain-ridges.json",
        "volcanic-island.json",
        "craggy-island.json",
        "gaussian-massif.json",
        "gaussian-jacksboro.json",
        "orometry-jacksboro.json",
    ];
    for name in scenes {
        let scene = small_scene(ws.path(), name, 160);
        let run = |threads: &str, tag: &str| {
            let out = ws.path().join(format!("out-{name}-{tag}"));
            let status = relief(&scene, &out, threads).status().unwrap();
            assert!(status.success(), "{name} with {threads} threads failed");
            outputs(&out)
        };
        let one = run("1", "a");
        let two = run("2", "b");
        let again = run("2", "c");
        assert!(one.len() >= 5 && one.contains_key("terrain.exr"), "{name}: {:?}", one.keys());
        for (file, bytes) in &one {
            assert!(two.get(file) == Some(bytes), "{name}: {file} differs between 1 and 2 threads");
            assert!(again.get(file) == Some(bytes), "{name}: {file} differs between two runs");
        }
        assert_eq!((one.len(), one.len()), (two.len(), again.len()), "{name}: different sets of files");
    }
}

/// A deterministic stream of fractions in `[0, 1)` (xorshift64*).
struct Fractions(u64);

impl Iterator for Fractions {
    type Item = f64;
    fn next(&mut self) -> Option<f64> {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        Some((self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64)
    }
}

#[test]
fn sigkill_never_leaves_a_truncated_output_under_its_final_name() {
    let ws = workspace();
    let scene = small_scene(ws.path(), "volcanic-island.json", 768);
    let reference_dir = ws.path().join("reference");
    let start = Instant::now();
    assert!(relief(&scene, &reference_dir, "2").status().unwrap().success());
    let full = start.elapsed();
    let reference = outputs(&reference_dir);
    assert!(reference.len() >= 5, "{:?}", reference.keys());

    // Twelve kills anywhere in the run, weighted towards its end where the files are written, and
    // four as soon as the first output appears (then some files are surely still to come).
    let fractions: Vec<Option<f64>> =
        Fractions(0x5eed_cafe).take(12).map(Some).chain(std::iter::repeat_n(None, 4)).collect();
    let (mut complete_files, mut landed) = (0, 0);
    for (round, fraction) in fractions.into_iter().enumerate() {
        let out = ws.path().join(format!("killed-{round}"));
        let mut child = relief(&scene, &out, "2").spawn().unwrap();
        let at = fraction.map(|f| full.mul_f64(0.3 + 0.9 * f));
        let waited = Instant::now();
        let mut running = true;
        loop {
            if child.try_wait().unwrap().is_some() {
                running = false;
                break;
            }
            let due = match at {
                Some(at) => waited.elapsed() >= at,
                None => std::fs::read_dir(&out)
                    .is_ok_and(|d| d.flatten().any(|e| reference.contains_key(&*e.file_name().to_string_lossy()))),
            };
            if due || waited.elapsed() > 4 * full {
                break;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        child.kill().unwrap(); // SIGKILL on Unix; an error only if it already exited and was reaped
        child.wait().unwrap();
        if !out.exists() {
            continue;
        }
        let mut finals = 0;
        for entry in std::fs::read_dir(&out).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            let Some(want) = reference.get(&name) else {
                // Not a final name: a temporary file or the staging folder the kill left behind.
                assert!(
                    name.contains(".tmp") || name.starts_with(".relief-staging."),
                    "round {round}: unexpected file {name}"
                );
                continue;
            };
            let mut got = std::fs::read(&path).unwrap();
            if name == "summary.json" {
                let mut v: serde_json::Value = serde_json::from_slice(&got)
                    .unwrap_or_else(|e| panic!("round {round}: summary.json is not whole JSON: {e}"));
                v.as_object_mut().unwrap().remove("timings_ms");
                got = serde_json::to_vec(&v).unwrap();
            }
            assert!(
                &got == want,
                "round {round}: {name} is not the complete file ({} of {} bytes)",
                got.len(),
                want.len()
            );
            complete_files += 1;
            finals += 1;
        }
        if running && finals > 0 {
            landed += 1;
        }
        // The summary is published last, once every other file is in place.
        if out.join("summary.json").exists() {
            assert_eq!(finals, reference.len(), "round {round}: a summary beside an incomplete set");
        }
    }
    // Some kills must have hit a running process after it had written files, or the test checked
    // nothing.
    assert!(complete_files > 0 && landed > 0, "no kill landed among the writes ({complete_files} files)");
}
