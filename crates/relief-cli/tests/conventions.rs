//! The command line as a newcomer meets it: errors that point at the line, scenes from standard
//! input, `-q` everywhere, the global options described once, completions and a man page.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::Stdio;

use assert_cmd::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn run(dir: &Path, args: &[&str]) -> std::process::Output {
    Command::cargo_bin("relief").unwrap().current_dir(dir).args(args).output().unwrap()
}

/// stdout of a successful run.
#[track_caller]
fn ok(dir: &Path, args: &[&str]) -> String {
    let out = run(dir, args);
    assert!(out.status.success(), "relief {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

/// stderr of a run failing with `code`.
#[track_caller]
fn fails(dir: &Path, args: &[&str], code: i32) -> String {
    let out = run(dir, args);
    assert_eq!(out.status.code(), Some(code), "relief {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stderr).unwrap()
}

#[test]
fn json_errors_name_the_file_line_and_column() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("bad.json"), "{\n  \"version\": 1,\n  \"seed\": 4,,\n}\n").unwrap();
    let stderr = fails(dir, &["generate", "bad.json"], 1);
    assert!(stderr.starts_with("error: bad.json:3:13: key must be a string"), "{stderr}");
    assert!(!stderr.contains("?:") && !stderr.contains(" at line "), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "no caret off a terminal: {stderr}");

    // A value error keeps its JSON path after the place.
    let text = std::fs::read_to_string(root().join("fixtures/scenes/mountain-ridges.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["generator"]["diffusion"]["curves"][0]["constraints"][0]["slope"]["theta"] = 95.into();
    let pretty = serde_json::to_string_pretty(&v).unwrap();
    std::fs::write(dir.join("ridges.json"), &pretty).unwrap();
    let stderr = fails(dir, &["generate", "ridges.json"], 1);
    let line = pretty.lines().position(|l| l.contains("95")).unwrap() + 1;
    let at = |l: usize| format!("error: ridges.json:{l}:");
    assert!(stderr.starts_with(&at(line)) || stderr.starts_with(&at(line + 1)), "line {line}: {stderr}");
    assert!(stderr.contains(": generator.diffusion.curves[0].constraints[0].slope.theta: 95 must lie"), "{stderr}");

    // A missing file says so once.
    let stderr = fails(dir, &["generate", "nowhere.json"], 1);
    assert_eq!(stderr.matches("No such file").count(), 1, "{stderr}");
}

#[test]
fn a_scene_can_come_from_standard_input() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(root().join("fixtures/scenes/mesa.json")).unwrap()).unwrap();
    v["reconstruction"]["resolution"] = serde_json::json!([40, 40]);
    v["generator"]["contours"]["particles"] = serde_json::json!(2000);
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("relief"))
        .current_dir(dir)
        .args(["-q", "generate", "-"])
        .stdin(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(v.to_string().as_bytes()).unwrap();
    assert!(child.wait().unwrap().success());
    assert!(dir.join("relief-out/stdin/terrain.exr").is_file());
}

#[test]
fn quiet_silences_every_report() {
    let dem = root().join("fixtures/dem/jacksboro.asc");
    let dem = dem.to_str().unwrap();
    let dir = root();
    assert!(ok(&dir, &["info", dem]).contains("size"));
    assert_eq!(ok(&dir, &["-q", "info", dem]), "");
    assert_eq!(ok(&dir, &["info", dem, "-q", "--json"]), "");
    assert!(ok(&dir, &["analyze", dem, "--min-prominence", "100"]).contains("peaks"));
    assert_eq!(ok(&dir, &["-q", "analyze", dem, "--min-prominence", "100"]), "");
}

#[test]
fn help_describes_global_options_once_and_the_tool_describes_itself() {
    let dir = root();
    let top = ok(&dir, &["--help"]);
    for flag in ["--quiet", "--force", "--threads", "--max-cells", "--max-peaks"] {
        assert_eq!(top.matches(flag).count(), 1, "{flag} once in relief --help:\n{top}");
    }
    let sub = ok(&dir, &["generate", "--help"]);
    assert!(!sub.contains("--max-cells <N>") && sub.contains("relief --help"), "{sub}");
    // The flags still work after the subcommand.
    let stderr = fails(&dir, &["generate", "nowhere.json", "--max-cells", "5", "-q"], 1);
    assert!(stderr.contains("nowhere.json"), "{stderr}");

    let bash = ok(&dir, &["completions", "bash"]);
    assert!(bash.contains("_relief()") && bash.contains("generate") && bash.contains("--max-cells"), "{bash}");
    assert!(ok(&dir, &["completions", "zsh"]).contains("#compdef relief"));
    let man = ok(&dir, &["man"]);
    assert!(man.contains(".TH relief 1") && man.contains("vectorize") && man.contains(r"max\-particles"), "{man}");
}

#[test]
fn bad_sizes_say_what_to_give() {
    let tmp = tempfile::tempdir().unwrap();
    let stderr = fails(tmp.path(), &["rasterize", "t.json", "--size", "2x", "-o", "t.exr"], 2);
    assert!(stderr.contains("give W or WxH") && !stderr.contains("empty string"), "{stderr}");
}
