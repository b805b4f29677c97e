//! Golden outputs: every fixture scene and the demo, generated at their own sizes, must write
//! exactly the bytes recorded in `fixtures/golden/outputs.sha256` (SHA-256 of each heightfield,
//! contour file, divide tree and preview, and of the summary without its timings).
//!
//! A refactoring that changes a single output bit fails here. When an output is meant to change,
//! regenerate the list with `RELIEF_BLESS=1 cargo test -p relief --test golden` and say why in the
//! commit; never edit it by hand.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use relief::Scene;
use relief::pipeline::{load_scene, run};
use sha2::{Digest, Sha256};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

const GOLDEN: &str = "fixtures/golden/outputs.sha256";

/// Every fixture scene (with the directory its paths resolve against), then the demo.
fn scenes() -> Vec<(String, Scene, PathBuf)> {
    let dir = root().join("fixtures/scenes");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    let mut scenes: Vec<(String, Scene, PathBuf)> = files
        .iter()
        .map(|p| {
            let name = p.file_stem().unwrap().to_string_lossy().into_owned();
            (name, load_scene(p).unwrap_or_else(|e| panic!("{}: {e}", p.display())), dir.clone())
        })
        .collect();
    scenes.push(("demo".to_owned(), Scene::demo(), root()));
    scenes
}

/// The SHA-256 of every file `scene` writes, keyed `scene/file`; the summary is hashed without
/// its timings, which vary from run to run.
fn hashes(name: &str, scene: &Scene, base: &Path, out: &mut BTreeMap<String, String>) {
    let dir = tempfile::tempdir().unwrap();
    let (_, written) = run(scene, base, dir.path(), &mut ()).unwrap_or_else(|e| panic!("{name}: {e}"));
    for path in written {
        let file = path.file_name().unwrap().to_string_lossy().into_owned();
        let mut bytes = std::fs::read(&path).unwrap();
        if file == "summary.json" {
            let mut summary: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
            summary.as_object_mut().unwrap().remove("timings_ms");
            bytes = serde_json::to_vec(&summary).unwrap();
        }
        let digest = Sha256::digest(&bytes);
        let hex = digest.iter().fold(String::new(), |mut s, b| {
            let _ = write!(s, "{b:02x}");
            s
        });
        out.insert(format!("{name}/{file}"), hex);
    }
}

#[test]
fn every_fixture_scene_writes_its_golden_bytes() {
    let mut found = BTreeMap::new();
    for (name, scene, base) in scenes() {
        hashes(&name, &scene, &base, &mut found);
    }
    let text = found.iter().fold(String::new(), |mut text, (k, v)| {
        let _ = writeln!(text, "{v}  {k}");
        text
    });
    let path = root().join(GOLDEN);
    if std::env::var_os("RELIEF_BLESS").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, &text).unwrap();
    }
    let expected = std::fs::read_to_string(&path).unwrap_or_default();
    let expected: BTreeMap<&str, &str> =
        expected.lines().filter_map(|l| l.split_once("  ")).map(|(hash, key)| (key, hash)).collect();
    let changed: Vec<String> = found
        .iter()
        .filter(|(k, v)| expected.get(k.as_str()) != Some(&v.as_str()))
        .map(|(k, _)| k.clone())
        .chain(expected.keys().filter(|k| !found.contains_key(**k)).map(|k| format!("{k} (no longer written)")))
        .collect();
    assert!(
        changed.is_empty(),
        "outputs differ from {GOLDEN}: {changed:?}\n(if the change is intended: RELIEF_BLESS=1 cargo test -p relief --test golden)"
    );
}
