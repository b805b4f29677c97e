//! No command loses a user's data, each case from a way it used to: writing over its own input,
//! replacing earlier outputs silently, writing one format under another's extension, leaving an
//! earlier run's files in a reused folder, or failing on a missing folder.

use std::path::{Path, PathBuf};

use assert_cmd::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `relief args…` run in `dir`.
fn relief(dir: &Path, args: &[&str]) -> std::process::Output {
    let mut cmd = Command::cargo_bin("relief").unwrap();
    cmd.current_dir(dir).args(args).output().unwrap()
}

#[track_caller]
fn ok(dir: &Path, args: &[&str]) -> String {
    let out = relief(dir, args);
    assert!(out.status.success(), "relief {args:?} failed: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

/// Runs `relief args…` expecting a refusal (exit 1) whose message contains `says`.
#[track_caller]
fn refused(dir: &Path, args: &[&str], says: &str) {
    let out = relief(dir, args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "relief {args:?}: {stderr}");
    assert!(stderr.contains(says), "relief {args:?}: {stderr}");
    assert_eq!(stderr.lines().count(), 1, "one line: {stderr}");
}

/// A folder holding a copy of the Jacksboro DEM, `dem.asc`.
fn workspace() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(root().join("fixtures/dem/jacksboro.asc"), dir.path().join("dem.asc")).unwrap();
    dir
}

fn bytes(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap()
}

#[test]
fn no_command_writes_over_its_own_input() {
    let ws = workspace();
    let (dir, dem) = (ws.path(), ws.path().join("dem.asc"));
    let before = bytes(&dem);
    // Even with --force, and however the path is spelled.
    std::fs::create_dir(dir.join("sub")).unwrap();
    refused(dir, &["--force", "convert", "dem.asc", "sub/../dem.asc"], "refusing to write over");
    refused(dir, &["--force", "analyze", "dem.asc", "--filled", "./dem.asc"], "refusing to write over");
    refused(
        dir,
        &["--force", "analyze", "dem.asc", "--divide-tree", "t.json", "--descriptor", "t.json"],
        "two outputs",
    );
    assert_eq!(bytes(&dem), before, "the DEM is intact");
    // A scene whose output is one of its inputs.
    std::fs::copy(root().join("fixtures/scenes/inputs/mask_lambda.png"), dir.join("mask.png")).unwrap();
    let scene = serde_json::json!({
        "version": 1,
        "generator": { "contours": {
            "label_image": { "path": "mask.png", "extent": { "min": [0, 0], "max": [1000, 1000] } },
            "particles": 500,
            "histogram": { "uniform": { "min": 0, "max": 100 } }
        } },
        "reconstruction": { "resolution": [32, 32] },
        "outputs": { "preview": "mask.png" }
    });
    std::fs::write(dir.join("scene.json"), scene.to_string()).unwrap();
    let mask = bytes(&dir.join("mask.png"));
    refused(dir, &["--force", "generate", "scene.json", "--out", "."], "refusing to write over");
    assert_eq!(bytes(&dir.join("mask.png")), mask);
}

#[test]
fn outputs_are_written_in_the_format_their_extension_names() {
    let ws = workspace();
    let dir = ws.path();
    refused(dir, &["preview", "dem.asc", "-o", "out.exr"], "give it a .png name");
    refused(dir, &["vectorize", "dem.asc", "-o", "x.asc", "--primitives", "10"], "give it a .json name");
    refused(dir, &["vectorize", "dem.asc", "-o", "dem.asc"], "give it a .json name");
    refused(dir, &["contours", "dem.asc", "--interval", "50", "--svg", "c.png"], "give it a .svg name");
    refused(dir, &["analyze", "dem.asc", "--peaks", "p.json"], "give it a .csv name");
    refused(dir, &["convert", "dem.asc", "dem.txt"], "give it a .exr name");
    assert_eq!(std::fs::read_dir(dir).unwrap().count(), 1, "nothing was written");
}

#[test]
fn existing_files_are_kept_unless_forced_and_folders_are_created() {
    let ws = workspace();
    let dir = ws.path();
    ok(dir, &["-q", "convert", "dem.asc", "deep/er/dem.tif"]);
    let first = bytes(&dir.join("deep/er/dem.tif"));
    refused(dir, &["convert", "dem.asc", "deep/er/dem.tif"], "exists; give --force");
    ok(dir, &["preview", "dem.asc", "-o", "p.png"]);
    refused(dir, &["preview", "dem.asc", "-o", "p.png"], "--force");
    ok(dir, &["-q", "--force", "convert", "dem.asc", "deep/er/dem.tif"]);
    assert_eq!(bytes(&dir.join("deep/er/dem.tif")), first);
}

/// The files directly in `dir`, sorted.
fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

#[test]
fn a_reused_output_folder_ends_with_exactly_the_last_runs_files() {
    let ws = workspace();
    let dir = ws.path();
    let scene = |outputs: serde_json::Value| {
        let mut v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(root().join("fixtures/scenes/mesa.json")).unwrap()).unwrap();
        v["reconstruction"]["resolution"] = serde_json::json!([48, 48]);
        v["generator"]["contours"]["particles"] = serde_json::json!(3000);
        v["outputs"] = outputs;
        std::fs::write(dir.join("scene.json"), v.to_string()).unwrap();
    };
    scene(serde_json::json!({}));
    ok(dir, &["-q", "generate", "scene.json", "--out", "out"]);
    let all = files(&dir.join("out"));
    assert_eq!(all, ["contours.geojson", "contours.svg", "preview.png", "summary.json", "terrain.exr", "terrain.png"]);
    // The same folder again: refused without --force, naming a file it would replace.
    refused(dir, &["generate", "scene.json", "--out", "out"], "exists; give --force");
    // A run writing fewer files removes the ones the last summary listed and this run does not
    // write; a file of the user's stays.
    std::fs::write(dir.join("out/notes.txt"), "mine").unwrap();
    scene(serde_json::json!({ "heightfield": ["terrain.tif"], "contours_svg": null, "preview": null }));
    ok(dir, &["-q", "--force", "generate", "scene.json", "--out", "out"]);
    assert_eq!(files(&dir.join("out")), ["contours.geojson", "notes.txt", "summary.json", "terrain.tif"]);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/summary.json")).unwrap()).unwrap();
    assert_eq!(summary["files"], serde_json::json!(["terrain.tif", "contours.geojson", "summary.json"]));
}

#[test]
fn the_demo_keeps_an_earlier_demo_and_takes_a_seed() {
    let ws = tempfile::tempdir().unwrap();
    let dir = ws.path();
    ok(dir, &["-q", "demo", "--out", "d", "--seed", "3"]);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("d/summary.json")).unwrap()).unwrap();
    assert_eq!(summary["scene"]["seed"], 3);
    refused(dir, &["demo", "--out", "d"], "exists; give --force");
}
