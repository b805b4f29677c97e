//! Regression inputs under `fixtures/bad/<target>/`, one directory per fuzz target: each file
//! goes through the same decoding as its target (`relief::harness`) and must come back as a
//! typed error naming its problem (`EXPECTED`), never a panic or a value.

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

/// Every regression input and a fragment of the error it must give: the error that names its
/// problem, not merely some error.
const EXPECTED: &[(&str, &str)] = &[
    ("label_image/one-pixel-strip.bin", "no region to grow"),
    ("polygon_regions/bowtie.bin", "regions[0].polygon: ring 0 edge 0 touches or crosses ring 0 edge 2"),
    ("polygon_regions/overlap.bin", "regions 0 and 1 overlap without nesting"),
    ("read_asc/lying_header.asc", "900000000 cells exceed the limit"),
    ("read_asc/over_limit.asc", "10000000000 cells exceed the limit"),
    ("read_exr/truncated.exr", "file is truncated"),
    ("read_geotiff/truncated.tif", "file is truncated"),
    ("read_hgt/seven-bytes.hgt", "file holds 7 bytes, but this format needs 2884802 or 25934402 bytes"),
    ("read_png16/huge-header.png", "4294836225 cells exceed the limit"),
    ("read_png16/truncated.png", "file is truncated"),
    ("read_png8/not-a-png.png", "cannot decode"),
    ("read_r16/odd-length.r16", "not a square number of samples"),
    ("read_r32/not-square.r32", "not a square number of samples"),
    ("scene_json/deep-nesting.json", "generator: expected value"),
    ("scene_json/nan-resolution.json", "reconstruction.resolution[0]: number out of range"),
    ("scene_json/not-utf8.json", "invalid utf-8"),
    ("scene_json/version-2.json", "version 2 is not supported"),
];

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
            let name = format!("{target}/{}", file.file_name().unwrap().to_string_lossy());
            let Some((_, want)) = EXPECTED.iter().find(|(n, _)| *n == name) else {
                panic!("{name}: add the error it must give to EXPECTED (it gives: {message})");
            };
            assert!(message.contains(want), "{name}: expected an error containing {want:?}, got: {message}");
            checked += 1;
        }
    }
    // Every fuzz target has at least one regression input.
    assert_eq!(targets.len(), 11, "{targets:?}");
    assert!(checked >= 17, "{checked}");
}

/// The first input the label-image fuzzer found: a 9 × 1 image whose levels are one pixel thin,
/// which used to give a growth graph without a node inside Ω. As a drawn mask its lone pixel is a
/// speck, not a region; `tests/masks.rs` of eden-growth covers levels the sampling misses.
#[test]
fn a_label_image_of_one_pixel_specks_is_refused() {
    let bytes = std::fs::read(bad().join("label_image/one-pixel-strip.bin")).unwrap();
    let message = replay("label_image", &bytes).expect("refused");
    assert!(message.contains("no region to grow") && message.contains("specks"), "{message}");
}
