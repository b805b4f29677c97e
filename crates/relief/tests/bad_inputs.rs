//! Regression inputs under `fixtures/bad/<target>/`, one directory per fuzz target: each file
//! goes through the same decoding as its target (`relief::harness`) and must come back as a
//! typed error with a message, never a panic or a value.

use std::path::{Path, PathBuf};

use relief::harness;
use relief::io::Format;

fn bad() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/bad")
}

/// The decoding of fuzz target `target` applied to `bytes`: the error's message, or `None` when
/// the input was accepted.
fn replay(target: &str, bytes: &[u8]) -> Option<String> {
    let read = |format| harness::read(bytes, format).err().map(|e| e.to_string());
    match target {
        "read_png8" => read(Format::Png8),
        "read_png16" => read(Format::Png16),
        "read_exr" => read(Format::Exr),
        "read_r16" => read(Format::R16),
        "read_r32" => read(Format::R32),
        "read_asc" => read(Format::Asc),
        "read_hgt" => read(Format::Hgt),
        "read_geotiff" => read(Format::GeoTiff),
        "scene_json" => harness::scene_json(bytes).err().map(|e| e.to_string()),
        "label_image" => harness::label_image(bytes).err().map(|e| e.to_string()),
        "polygon_regions" => harness::polygon_regions(bytes).err().map(|e| e.to_string()),
        other => panic!("fixtures/bad/{other}: no such fuzz target"),
    }
}

#[test]
fn every_bad_input_is_a_typed_error() {
    let mut checked = 0;
    let mut targets: Vec<_> =
        std::fs::read_dir(bad()).unwrap().map(|e| e.unwrap().path()).filter(|p| p.is_dir()).collect();
    targets.sort();
    for dir in &targets {
        let target = dir.file_name().unwrap().to_str().unwrap();
        for file in std::fs::read_dir(dir).unwrap() {
            let file = file.unwrap().path();
            let bytes = std::fs::read(&file).unwrap();
            let message = replay(target, &bytes).unwrap_or_else(|| panic!("{} was accepted", file.display()));
            assert!(!message.trim().is_empty(), "{}: empty error message", file.display());
            checked += 1;
        }
    }
    // Every fuzz target has at least one regression input.
    assert_eq!(targets.len(), 11, "{targets:?}");
    assert!(checked >= 17, "{checked}");
}

/// The first input the label-image fuzzer found: a 9 × 1 image whose levels are one pixel thin,
/// which used to give a growth graph without a node inside Ω.
#[test]
fn a_label_level_thinner_than_the_sampling_radius_is_refused() {
    let bytes = std::fs::read(bad().join("label_image/one-pixel-strip.bin")).unwrap();
    let message = replay("label_image", &bytes).expect("refused");
    assert!(message.contains("holds no graph node"), "{message}");
}
