//! The README's "Writing your first scene" works when copied verbatim: every JSON block, saved at
//! the repository root under the name the text gives it, generates without an error or a warning,
//! its inputs draw over the result, and the peak-finding command writes what it says.

use std::path::{Path, PathBuf};

use assert_cmd::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The section's text, from its heading to the next one of the same level.
fn section() -> String {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let start = readme.find("## Writing your first scene").expect("the README has a first-scene section");
    let rest = &readme[start + 3..];
    rest[..rest.find("\n## ").unwrap_or(rest.len())].to_owned()
}

/// Every JSON block of the section, with the `first-*.json` name mentioned last before it.
fn scenes(text: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(open) = rest.find("```json\n") {
        let before = &rest[..open];
        let name = before.rfind("`first-").map(|k| {
            let tail = &before[k + 1..];
            tail[..tail.find('`').unwrap()].to_owned()
        });
        let body = &rest[open + 8..];
        let close = body.find("```").unwrap();
        out.push((name.expect("a block follows the name to save it as"), body[..close].to_owned()));
        rest = &body[close + 3..];
    }
    out
}

/// Runs `relief args…` from the repository root with `stdin`, as a user at the root would.
fn relief(args: &[&str], stdin: &str) -> std::process::Output {
    Command::cargo_bin("relief").unwrap().current_dir(root()).args(args).write_stdin(stdin).output().unwrap()
}

#[test]
fn the_first_scenes_generate_as_written() {
    let text = section();
    let scenes = scenes(&text);
    let names: Vec<&str> = scenes.iter().map(|(name, _)| name.as_str()).collect();
    let expected = ["first-contours.json", "first-island.json", "first-diffusion.json"];
    assert_eq!(names[..3], expected);
    assert_eq!(names[3..], ["first-gaussian.json", "first-orometry.json"], "one scene per generator");
    let tmp = tempfile::tempdir().unwrap();
    for (name, json) in &scenes {
        // Saved at the root, the scene's relative paths resolve there: the same as reading it from
        // standard input with the root as the current folder.
        let out = tmp.path().join(name.trim_end_matches(".json"));
        let run = relief(&["generate", "-", "--out", out.to_str().unwrap()], json);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success(), "{name}: {stderr}");
        assert!(!stderr.contains("warning"), "{name} should run without a warning: {stderr}");
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
        assert!(summary.get("warnings").is_none(), "{name}: {}", summary["warnings"]);
        assert!(out.join("terrain.exr").exists() && out.join("preview.png").exists(), "{name}");
        // Its inputs draw over the result.
        let png = out.join("inputs.png");
        let exr = out.join("terrain.exr");
        let run = relief(&["preview", exr.to_str().unwrap(), "-o", png.to_str().unwrap(), "--inputs", "-"], json);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success() && !stderr.contains("warning"), "{name}: {stderr}");
    }
    let orometry = tmp.path().join("first-orometry");
    assert!(orometry.join("divide_tree.geojson").exists(), "the orometry scene writes its divide tree");
}

#[test]
fn the_peak_finding_command_writes_peaks_and_a_divide_tree() {
    let text = section();
    let line = text.lines().find(|l| l.contains("-- prominence ")).expect("the section shows how to find peaks");
    let args: Vec<&str> = line.split_once("-- ").unwrap().1.split_whitespace().collect();
    let tmp = tempfile::tempdir().unwrap();
    // The command as written, with its two outputs sent to a temporary folder.
    let moved: Vec<String> = args
        .iter()
        .map(|a| {
            if matches!(Path::new(a).extension().and_then(|e| e.to_str()), Some("csv" | "geojson")) {
                tmp.path().join(a).display().to_string()
            } else {
                (*a).to_owned()
            }
        })
        .collect();
    let run = Command::cargo_bin("relief").unwrap().current_dir(root()).args(&moved).output().unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let csv = std::fs::read_to_string(tmp.path().join("peaks.csv")).unwrap();
    assert!(csv.starts_with("id,lon,lat,elevation,prominence,"), "{csv}");
    assert!(csv.lines().count() > 100, "every peak at least 30 m prominent: {}", csv.lines().count());
    assert!(tmp.path().join("tree.geojson").exists());
}
